"""border_echo: distance from a ranger to the table border across its cone (no ROS needed)."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src'))
from smart_brain.triggers.border_echo import border_distance, ray_to_border  # noqa: E402

L, W = 3.0, 2.1


class BorderDistanceTest(unittest.TestCase):
    def test_straight_rays(self):
        self.assertAlmostEqual(ray_to_border(0.25, 1.8, 0.0, L, W), 2.75)
        self.assertAlmostEqual(ray_to_border(0.25, 1.8, math.pi / 2, L, W), 0.3)
        self.assertAlmostEqual(ray_to_border(1.0, 0.4, -math.pi / 2, L, W), 0.4)

    def test_the_cone_sees_the_nearer_wall(self):
        # Logion's front_left SRF02 in the start zone: 45 deg to the left, 0.18 m below the wall
        axis = ray_to_border(0.37, 1.92, math.pi / 4, L, W)
        cone = border_distance(0.37, 1.92, math.pi / 4, 1.0, L, W)
        self.assertAlmostEqual(axis, 0.18 * math.sqrt(2), places=6)
        self.assertLess(cone, axis)
        self.assertGreater(cone, 0.18)

    def test_open_table_is_far(self):
        self.assertGreater(border_distance(1.5, 1.0, 0.0, 0.3, L, W), 1.4)

    def test_outside_the_table_is_zero(self):
        self.assertEqual(border_distance(-0.1, 1.0, 0.0, 0.3, L, W), 0.0)


if __name__ == '__main__':
    unittest.main()
