"""Planar geometry every layer shares (REP-103: x forward, y left, angles counter-clockwise, rad):
the twin of include/robot_core/geometry.h, checked against the same test vectors."""
import math


def wrap_angle(a):
    """`a` wrapped into (-pi, pi]."""
    if -math.pi < a <= math.pi:
        return a
    a = math.remainder(a, 2.0 * math.pi)
    return a + 2.0 * math.pi if a <= -math.pi else a


def yaw_from_quaternion(x, y, z, w):
    """The heading [rad] of a unit quaternion: its rotation about z (REP-103 yaw)."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def yaw_of(q):
    """The heading [rad] of a geometry_msgs/Quaternion (anything with x, y, z, w)."""
    return yaw_from_quaternion(q.x, q.y, q.z, q.w)
