#!/usr/bin/python3
"""cell.launch brings up every node with its interfaces, its parameters from config/cell.yaml, the machine's frames
with `part` among them, and a stage node that dies comes back and serves again."""
import time
import unittest

import rosgraph
import rosnode
import rosservice
import rospy
import rostest
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage

from art2part.srv import VerifyToolpaths, VerifyToolpathsRequest

SERVICES = ['/load_part', '/get_part', '/list_parts', '/show_cone', '/plan_setups', '/verify_toolpaths',
            '/run_program', '/list_plans', '/get_plan']
ACTIONS = ['/analyse_visibility', '/plan_roughing', '/plan_finishing', '/follow_joint_trajectory', '/plan_part']
NODES = ['/part_server', '/visibility', '/setup_planner', '/roughing_planner', '/finishing_planner', '/verification',
         '/controller_bridge', '/simulated_controller', '/robot_state_publisher', '/cell_supervisor']


def action_servers():
    """Topics X/goal some node subscribes to: the action servers X."""
    _, subscribers, _ = rosgraph.Master('/test_cell').getSystemState()
    return {topic[:-len('/goal')] for topic, nodes in subscribers if topic.endswith('/goal') and nodes}


class Cell(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_cell')
        for service in SERVICES:
            rospy.wait_for_service(service, 60)

    def test_every_node_and_interface_is_up(self):
        self.assertEqual(set(NODES) - set(rosnode.get_node_names()), set())
        self.assertEqual(set(SERVICES) - set(rosservice.get_service_list()), set())
        deadline = time.time() + 30
        while set(ACTIONS) - action_servers() and time.time() < deadline:
            time.sleep(0.5)
        self.assertEqual(set(ACTIONS) - action_servers(), set())

    def test_parameters_come_from_cell_yaml(self):
        self.assertEqual(rospy.get_param('/part_server/frame_id'), 'part')
        self.assertEqual(rospy.get_param('/verification/marker_cells'), 150)
        self.assertTrue(rospy.get_param('/controller_bridge/machine').endswith('/config/machines/vmc_3axis.yaml'))
        self.assertIn('<robot', rospy.get_param('/robot_description'))

    def test_the_machine_carries_the_part_frame(self):
        static = rospy.wait_for_message('/tf_static', TFMessage, 30)
        self.assertIn('part', {t.child_frame_id for t in static.transforms}, 'rviz fixed frame `part` must exist')
        joints = rospy.wait_for_message('/joint_states', JointState, 30)
        self.assertEqual(joints.name, ['X', 'Y', 'Z'])

    def test_a_stage_node_that_dies_respawns_and_serves(self):
        before = rosservice.get_service_uri('/verify_toolpaths')
        rosnode.kill_nodes(['/verification'])
        deadline, uri = time.time() + 30, None
        while time.time() < deadline:
            uri = rosservice.get_service_uri('/verify_toolpaths')
            if uri and uri != before:
                break
            time.sleep(0.2)
        self.assertTrue(uri and uri != before, 'verification did not respawn (%s, before %s)' % (uri, before))
        rospy.wait_for_service('/verify_toolpaths', 30)
        answer = rospy.ServiceProxy('/verify_toolpaths', VerifyToolpaths)(VerifyToolpathsRequest(folder=''))
        self.assertFalse(answer.success)
        self.assertTrue(answer.message, 'a refusal says why')


if __name__ == '__main__':
    rostest.rosrun('art2part', 'cell', Cell)
