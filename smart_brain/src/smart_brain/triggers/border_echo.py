"""BorderEcho: is a ranger's echo the table border rather than the opponent?

The SHARPs and SRF02s see the table's borders as well as the opponent; a robot in its start
zone or near a wall would otherwise stop for a wall forever. From the sensor's pose in `map`
(tf: map -> the Range message's frame) the distance to the nearest border point in the sensor's
cone is robot_core's exact cone range, the one the driver and the localization use; an echo at
least that far (less `tolerance`) is the border. The pose is
the one at the reading's stamp (when the sensor measured), the latest if tf has none there.
Without a pose (no tf yet) nothing is explained away: an unknown echo still stops the robot.
"""
from robot_core.geometry import yaw_of
from robot_core.table_geometry import TableGeometry


class BorderEcho(object):
    def __init__(self, length, width, tolerance, map_frame='map', odom_frame='odom', tf_timeout=0.0, buffer=None):
        """`buffer`: a tf2_ros.Buffer to read poses from (tests); by default one fed by a listener.
        `tf_timeout` [s]: how long a lookup may wait for a transform. 0: none; the trigger decides
        in the reading's callback, and a wait there adds to the reflex latency of the brain's stop."""
        import tf2_ros
        import rospy
        self.table = TableGeometry(length, width)
        self.tolerance = float(tolerance)
        self.map_frame, self.odom_frame = map_frame, odom_frame
        self._timeout = rospy.Duration(tf_timeout)
        if buffer is None:
            buffer = tf2_ros.Buffer()
            self._listener = tf2_ros.TransformListener(buffer)
        self._buffer = buffer

    def _sensor_pose(self, msg):
        """The sensor's transform in map when it measured (the Range's stamp), else the latest.

        An SRF02 reading reaches the brain ~0.14 s after its ping: a robot turning in place near
        a wall has turned 5-10 deg since, and the border seen from its pose now is a wall the
        ping never saw (the opponent_ahead trigger fired on such echoes in homologation).
        map -> odom lags the readings (the localization publishes it after processing them), so
        without waiting: the whole chain at the stamp if tf has it, else odom -> sensor at the stamp
        (odometry is fresh) under the newest map -> odom, else the newest of all."""
        import rospy
        if not msg.header.stamp.is_zero():
            t = self._lookup(msg.header.frame_id, msg.header.stamp)
            if t is not None:
                return t
            try:
                return self._buffer.lookup_transform_full(self.map_frame, rospy.Time(0), msg.header.frame_id,
                                                          msg.header.stamp, self.odom_frame, self._timeout)
            except Exception:
                pass
        return self._lookup(msg.header.frame_id, rospy.Time(0))

    def _lookup(self, frame, stamp):
        try:
            return self._buffer.lookup_transform(self.map_frame, frame, stamp, self._timeout)
        except Exception:
            return None

    def explains(self, msg):
        """True when the Range message's echo is (about) where the border was when it measured."""
        t = self._sensor_pose(msg)
        if t is None:
            return False
        q = t.transform.rotation
        heading = yaw_of(q)
        d = self.table.cone_range(t.transform.translation.x, t.transform.translation.y, heading,
                                  msg.field_of_view)
        return msg.range >= d - self.tolerance
