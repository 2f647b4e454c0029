#!/usr/bin/python3
"""The part frame robot_state_publisher publishes under machine.launch plan:=DIR setup:=K is plan.json's fixture of
setup K: the table -> part transform on /tf_static has origin_mm (in metres) and the rotation plan.json records."""
import json
import os
import threading
import unittest

import rospy
import rostest
from tf2_msgs.msg import TFMessage


def rotation_of(q):
    """Row-major 3x3 matrix of a unit quaternion (geometry_msgs/Quaternion)."""
    x, y, z, w = q.x, q.y, q.z, q.w
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


class MachineFrame(unittest.TestCase):
    def test_part_frame_is_the_fixture_of_the_setup(self):
        rospy.init_node('test_machine_frame_listener')
        setup = rospy.get_param('~setup')
        with open(os.path.join(rospy.get_param('~plan'), 'plan.json')) as f:
            fixture = json.load(f)['setups'][setup]['fixture']
        found = threading.Event()
        transforms = []

        def on_tf(msg):
            for t in msg.transforms:
                if t.header.frame_id == 'table' and t.child_frame_id == 'part':
                    transforms.append(t.transform)
                    found.set()

        rospy.Subscriber('/tf_static', TFMessage, on_tf)
        self.assertTrue(found.wait(30), 'no table -> part transform on /tf_static')
        t = transforms[-1]
        for got, want_mm in zip([t.translation.x, t.translation.y, t.translation.z], fixture['origin_mm']):
            self.assertAlmostEqual(got, want_mm / 1000.0, places=9)
        for got_row, want_row in zip(rotation_of(t.rotation), fixture['rotation']):
            for got, want in zip(got_row, want_row):
                self.assertAlmostEqual(got, want, places=9)


if __name__ == '__main__':
    rostest.rosrun('art2part', 'machine_frame', MachineFrame)
