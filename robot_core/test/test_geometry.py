"""The Python geometry against the vectors of test_geometry.cpp."""
import math
import unittest

from robot_core.geometry import wrap_angle, yaw_from_quaternion


class GeometryTest(unittest.TestCase):
    def test_wrap_angle_is_in_minus_pi_exclusive_pi_inclusive(self):
        self.assertEqual(wrap_angle(0.5), 0.5)
        self.assertEqual(wrap_angle(math.pi), math.pi)
        self.assertEqual(wrap_angle(-math.pi), math.pi)
        self.assertAlmostEqual(wrap_angle(3 * math.pi / 2), -math.pi / 2, places=12)
        self.assertAlmostEqual(wrap_angle(-3 * math.pi / 2), math.pi / 2, places=12)
        self.assertAlmostEqual(wrap_angle(20 * math.pi + 0.25), 0.25, places=12)
        a = -50.0
        while a < 50.0:
            w = wrap_angle(a)
            self.assertTrue(-math.pi < w <= math.pi)
            self.assertAlmostEqual(math.remainder(w - a, 2 * math.pi), 0.0, places=9)
            a += 0.37

    def test_yaw_from_quaternion(self):
        for yaw in (0.0, 0.3, -1.2, 3.0, -3.1):
            self.assertAlmostEqual(yaw_from_quaternion(0, 0, math.sin(yaw / 2), math.cos(yaw / 2)), yaw, places=12)
        yaw, roll = 0.7, 0.1
        cy, sy, cr, sr = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(roll / 2), math.sin(roll / 2)
        self.assertAlmostEqual(yaw_from_quaternion(cy * sr, sy * sr, cr * sy, cr * cy), yaw, places=12)
