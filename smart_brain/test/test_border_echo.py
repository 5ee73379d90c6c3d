"""border_echo: distance from a ranger to the table border across its cone, and which pose an echo
is explained from (a tf buffer filled by hand: no ROS master needed)."""
import math
import time
import unittest

from robot_core.table_geometry import TableGeometry

L, W = 3.0, 2.1
TABLE = TableGeometry(L, W)


class BorderDistanceTest(unittest.TestCase):
    def test_the_cone_sees_the_nearer_wall(self):
        # Logion's front_left SRF02 in the start zone: 45 deg to the left, 0.18 m below the wall:
        # the cone's edge ray nearest the wall's normal comes nearest, not the axis.
        axis = TABLE.ray_range(0.37, 1.92, math.pi / 4)
        cone = TABLE.cone_range(0.37, 1.92, math.pi / 4, 1.0)
        self.assertAlmostEqual(axis, 0.18 * math.sqrt(2), places=6)
        self.assertAlmostEqual(cone, 0.18 / math.sin(math.pi / 4 + 0.5), places=9)


def sensor_transform(stamp, x, y, heading, parent='map', child='ranger'):
    import rospy
    from geometry_msgs.msg import TransformStamped
    t = TransformStamped()
    t.header.stamp, t.header.frame_id, t.child_frame_id = rospy.Time.from_sec(stamp), parent, child
    t.transform.translation.x, t.transform.translation.y = x, y
    t.transform.rotation.z, t.transform.rotation.w = math.sin(heading / 2), math.cos(heading / 2)
    return t


class BorderEchoPoseTest(unittest.TestCase):
    """Logion's front_left SRF02 0.18 m below the top wall, looking 45 deg to the left; the robot
    then turns in place so that 0.15 s later the sonar looks along the wall."""

    def setUp(self):
        import tf2_ros
        from smart_brain.triggers.border_echo import BorderEcho
        buf = tf2_ros.Buffer(debug=False)  # debug would advertise a service: needs a master
        for stamp, heading in ((10.0, math.pi / 4), (10.05, math.pi / 4), (10.15, 0.0)):
            buf.set_transform(sensor_transform(stamp, 0.37, 1.92, heading), 'test')
        self.echo = BorderEcho(L, W, 0.08, tf_timeout=0.0, buffer=buf)

    def reading(self, stamp, rng):
        import rospy
        from sensor_msgs.msg import Range
        m = Range(range=rng, field_of_view=0.96, min_range=0.16, max_range=6.0)
        m.header.frame_id, m.header.stamp = 'ranger', rospy.Time.from_sec(stamp)
        return m

    def test_the_wall_echo_is_explained_from_where_the_sonar_pinged(self):
        wall = TABLE.cone_range(0.37, 1.92, math.pi / 4, 0.96)   # ~0.19 m
        now = TABLE.cone_range(0.37, 1.92, 0.0, 0.96)         # ~0.39 m: the pose 0.15 s later
        self.assertGreater(now - 0.08, wall)  # from the latest pose the echo would be "the opponent"
        self.assertTrue(self.echo.explains(self.reading(10.0, wall)))

    def test_an_echo_nearer_than_the_wall_is_not_explained(self):
        self.assertFalse(self.echo.explains(self.reading(10.0, 0.10)))

    def test_a_reading_older_than_tf_uses_the_latest_pose(self):
        self.assertTrue(self.echo.explains(self.reading(1.0, 0.40)))
        self.assertFalse(self.echo.explains(self.reading(1.0, 0.19)))


class BorderEchoOdometryChainTest(unittest.TestCase):
    """map -> odom lags the reading (the localization has not processed it yet): the sensor's
    pose comes from odom -> ranger at the reading's stamp under the newest map -> odom, at once."""

    def setUp(self):
        import tf2_ros
        from smart_brain.triggers.border_echo import BorderEcho
        buf = tf2_ros.Buffer(debug=False)
        # map -> odom: identity, known up to 10.0 s only
        buf.set_transform(sensor_transform(10.0, 0.0, 0.0, 0.0, parent='map', child='odom'), 'test')
        for stamp, heading in ((10.0, 0.0), (10.15, math.pi / 4), (10.3, 0.0)):
            buf.set_transform(sensor_transform(stamp, 0.37, 1.92, heading, parent='odom'), 'test')
        self.echo = BorderEcho(L, W, 0.08, buffer=buf)

    def test_a_reading_newer_than_map_to_odom_is_placed_by_odometry(self):
        from sensor_msgs.msg import Range
        import rospy
        wall = TABLE.cone_range(0.37, 1.92, math.pi / 4, 0.96)
        m = Range(range=wall, field_of_view=0.96, min_range=0.16, max_range=6.0)
        m.header.frame_id, m.header.stamp = 'ranger', rospy.Time.from_sec(10.15)
        # Wall time on purpose: a tf wait blocks the callback's thread in wall time, whatever the clock.
        t0 = time.monotonic()
        self.assertTrue(self.echo.explains(m))   # from the pose at 10.15 s (45 deg), not the newest (0 deg)
        self.assertLess(time.monotonic() - t0, 0.02)


if __name__ == '__main__':
    unittest.main()
