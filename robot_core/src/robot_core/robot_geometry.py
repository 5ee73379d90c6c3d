"""RobotGeometry: the robot's shape and drive as its description gives them, the `robot:` block of
config/<robot>.yaml (/robot). The twin of the C++ robot_core::RobotGeometry (robot_geometry.h):
the same keys, rules and meanings, so the URDF, the simulated robot's tree and the calibration
read what the devices and the simulator read.

    geometry = RobotGeometry.read(Params(tree.get('robot'), '/robot'))
    if geometry.track_width is not None: ...   # a value the description leaves out is None
"""
import collections

from robot_core.params import REQUIRED, Params

# The meanings robot_geometry.cpp gives them, word for word (test_robot_geometry compares).
MEANINGS = collections.OrderedDict([
    ('radius', "[m] the footprint's circumscribed radius (the URDF's chassis)"),
    ('wheel_radius', "[m] radius of the driven wheels"),
    ('track_width', "[m] between the driven wheels' contact points"),
    ('encoder_ticks_per_rev', "the driven wheels' encoders: ticks per wheel revolution"),
])


def _positive_if_given(robot, key):
    # as the C++ reader: always described, declared (a required number > 0) only where given
    robot.describe(key, MEANINGS[key])
    if not robot.has(key):
        return None
    return robot.value(key, REQUIRED, float, rule='> 0', check=lambda v: '' if v > 0 else 'must be > 0')


class RobotGeometry(collections.namedtuple('RobotGeometry', list(MEANINGS))):
    """Each value a number > 0, or None where the description leaves it out."""
    __slots__ = ()

    @classmethod
    def read(cls, robot):
        """The description's values from the Params of its block; ParameterError for a bad one."""
        return cls(*(_positive_if_given(robot, key) for key in MEANINGS))

    @classmethod
    def of_config(cls, tree):
        """The description of a config tree (its robot: block, named /robot), as the nodes read it."""
        return cls.read(Params(tree.get('robot') if isinstance(tree, dict) else None, '/robot'))
