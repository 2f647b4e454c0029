#!/usr/bin/python3
"""cell_rviz.py frames the view on each part the part server loads: the viewer is started again on a config whose
orbit camera looks at the new part's box centre from a distance that fits its diagonal; a part with (nearly) the same
box does not restart it."""
import json
import math
import os
import tempfile
import time
import unittest

import rospy
import rostest

from art2part.srv import LoadPart

# cell_rviz.py's framing: vertical field of view pi/4, margin 1.3 round the box's sphere.
FIT = 1.3 / math.tan(math.pi / 8) / 2


def box_stl(path, lo, hi):
    """An ASCII STL of the box [lo, hi] (mm), outward normals left to the reader."""
    corner = lambda i: [hi[k] if (i >> k) & 1 else lo[k] for k in range(3)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    with open(path, 'w') as f:
        f.write('solid box\n')
        for a, b, c, d in quads:
            for tri in ((a, b, c), (a, c, d)):
                f.write(' facet normal 0 0 0\n  outer loop\n')
                for i in tri:
                    f.write('   vertex %g %g %g\n' % tuple(corner(i)))
                f.write('  endloop\n endfacet\n')
        f.write('endsolid box\n')


class RvizFraming(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_rviz_framing')
        rospy.wait_for_service('/load_part', 60)
        cls.load = rospy.ServiceProxy('/load_part', LoadPart)
        cls.log = rospy.get_param('~viewer_log')
        cls.folder = tempfile.mkdtemp(prefix='art2part-test-rviz-', dir='/tmp')

    def views(self):
        if not os.path.exists(self.log):
            return []
        with open(self.log) as f:
            return [json.loads(line) for line in f if line.strip()]

    def wait_for_views(self, count, seconds=30):
        deadline = time.time() + seconds
        while len(self.views()) < count and time.time() < deadline:
            time.sleep(0.1)
        return self.views()

    def load_box(self, name, lo, hi):
        path = os.path.join(self.folder, name + '.stl')
        box_stl(path, lo, hi)
        response = self.load(path=path, part_id=name, units='mm', chordal_tolerance=0)
        self.assertTrue(response.success, response.message)

    def assertFramedOn(self, view, lo_mm, hi_mm):
        lo, hi = [v / 1000 for v in lo_mm], [v / 1000 for v in hi_mm]
        centre = [(a + b) / 2 for a, b in zip(lo, hi)]
        focal = view['focal_point']
        for axis, value in zip('XYZ', centre):
            self.assertAlmostEqual(focal[axis], value, places=6)
        self.assertAlmostEqual(view['distance'], FIT * math.dist(lo, hi), places=6)

    def test_each_new_part_reframes_the_view(self):
        started = len(self.wait_for_views(1))  # the viewer on the template, before any part
        self.assertGreaterEqual(started, 1)

        self.load_box('small_cube', [0, 0, 0], [10, 10, 10])
        views = self.wait_for_views(started + 1)
        self.assertEqual(len(views), started + 1, 'no restart on the first part')
        self.assertFramedOn(views[-1], [0, 0, 0], [10, 10, 10])

        self.load_box('long_block', [20, 0, 0], [120, 40, 20])
        views = self.wait_for_views(started + 2)
        self.assertEqual(len(views), started + 2, 'no restart on the second part')
        self.assertFramedOn(views[-1], [20, 0, 0], [120, 40, 20])

        # A box 0.05 mm longer (tessellation, rounding): the same view, no restart.
        self.load_box('long_block_again', [20, 0, 0], [120.05, 40, 20])
        time.sleep(3)
        self.assertEqual(len(self.views()), started + 2)


if __name__ == '__main__':
    rostest.rosrun('art2part', 'rviz_framing', RvizFraming)
