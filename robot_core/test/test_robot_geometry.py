"""robot_core.robot_geometry: the Python twin of robot_core::RobotGeometry reads the same keys with
the same rule and meanings as robot_geometry.cpp (its source is compared), and refuses a bad value
with the C++ reader's line."""
import os
import re
import unittest

from robot_core.params import ParameterError, Params
from robot_core.robot_geometry import MEANINGS, RobotGeometry

CPP = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src', 'robot_geometry.cpp')


def cpp_meanings():
    """[(key, meaning)] of RobotGeometry::read's positiveIfGiven calls, in order."""
    with open(CPP) as f:
        text = f.read()
    return re.findall(r'positiveIfGiven\(\s*robot,\s*"(\w+)",\s*"((?:[^"\\]|\\.)*)"\s*\)', text)


class RobotGeometryTest(unittest.TestCase):
    def test_the_keys_and_meanings_are_the_cpp_readers(self):
        self.assertEqual(cpp_meanings(), list(MEANINGS.items()))
        self.assertEqual(list(RobotGeometry._fields), [key for key, _ in cpp_meanings()])

    def test_given_values_are_numbers_and_the_rest_none(self):
        robot = Params({'radius': 0.16, 'track_width': 0.25, 'encoder_ticks_per_rev': 512}, '/robot')
        g = RobotGeometry.read(robot)
        self.assertEqual(g, (0.16, None, 0.25, 512.0))
        self.assertIsInstance(g.encoder_ticks_per_rev, float)
        d = robot.declarations()
        self.assertEqual(d['radius'], ('number', True, '', '> 0', MEANINGS['radius']))
        self.assertEqual(d['wheel_radius'], ('', False, '', '', MEANINGS['wheel_radius']))  # described, not read
        self.assertEqual(RobotGeometry.of_config({}), (None,) * 4)  # no description at all

    def test_a_bad_value_is_the_cpp_readers_line(self):
        for tree, message in (({'radius': 0}, 'parameter /robot/radius = 0: must be > 0'),
                              ({'track_width': 'wide'}, "parameter /robot/track_width = 'wide': must be a number"),
                              ({'wheel_radius': -0.03}, 'parameter /robot/wheel_radius = -0.03: must be > 0')):
            with self.assertRaises(ParameterError) as caught:
                RobotGeometry.of_config({'robot': tree})
            self.assertEqual(str(caught.exception), message)


if __name__ == '__main__':
    unittest.main()
