#!/usr/bin/env python3
"""The Driver on a whole simulated robot (launch/<robot>.launch: simulator, firmware emulators,
HCL, HAL with odometry, drive, rangers and localization): goto across the table, a path through
six checkpoints, cancel latency, the opponent on the route. Ground truth (/sim/*) is read by
this test only. Parameters: ~robot, ~motor_topic, ~opponent_sensing, ~collision_distance.
Registered for both robots (test/launch/driver_sim_eurobot2009.test, driver_sim_logion.test),
at real time; the cancel case, whose bounds are wall milliseconds, also holds real time when a
launch runs faster (test_support.real_time)."""
import math
import sys
import time
import unittest

import actionlib
import rospy
from robot_core.geometry import wrap_angle
import rostest
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Pose2D, Twist
from hal_nodes.msg import (Checkpoint, FollowPathAction, FollowPathGoal, GotoAction, GotoGoal, GotoResult,
                           LocalizationQuality)
from hcl_drivers.msg import MotorCommand
from nav_msgs.msg import Odometry, Path
from robot_sim.srv import PlaceOpponent

from test_support import Recorder, real_time, yaw_of

DEG = math.pi / 180.0


class DriverSimTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_driver_sim')
        cls.robot = rospy.get_param('~robot')
        cls.truth = Recorder('/sim/ground_truth', Odometry)
        cls.opponent = Recorder('/sim/opponent', Odometry)
        cls.cmd = Recorder('/hal/drive/cmd_vel', Twist)
        cls.motor = Recorder(rospy.get_param('~motor_topic'), MotorCommand)
        cls.quality = Recorder('/mcl/quality', LocalizationQuality)
        cls.path_msgs = Recorder('/hal/driver/path', Path)
        # The age of /odom on arrival (ROS time, the sim clock, minus its stamp): what the driver's
        # ~max_odom_age is measured against, plus up to one control period.
        cls.odom_ages = []
        rospy.Subscriber('/odom', Odometry, lambda m: cls.odom_ages.append((rospy.get_rostime() - m.header.stamp).to_sec()),
                         queue_size=50, tcp_nodelay=True)
        cls.goto = actionlib.SimpleActionClient('/hal/driver/goto', GotoAction)
        cls.follow = actionlib.SimpleActionClient('/hal/driver/follow_path', FollowPathAction)
        assert cls.goto.wait_for_server(rospy.Duration(60)), 'no /hal/driver/goto'
        assert cls.follow.wait_for_server(rospy.Duration(30)), 'no /hal/driver/follow_path'
        rospy.wait_for_service('/sim/place_opponent', 30)
        cls.place = rospy.ServiceProxy('/sim/place_opponent', PlaceOpponent)
        cls.park_opponent()
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            q = cls.quality.last()
            if q is not None and q.probability > 0.6 and cls.truth.last() is not None:
                break
            time.sleep(0.2)
        rospy.sleep(2.0)

    @classmethod
    def tearDownClass(cls):
        ages = sorted(cls.odom_ages)
        if ages:
            print('%s /odom age on arrival over %d messages: p50 %.1f ms, p99 %.1f ms, max %.1f ms'
                  % (cls.robot, len(ages), 1e3 * ages[len(ages) // 2], 1e3 * ages[int(0.99 * (len(ages) - 1))], 1e3 * ages[-1]))

    @classmethod
    def park_opponent(cls):
        cls.place(pose=Pose2D(x=2.75, y=0.25, theta=0.0), hold=True)

    def truth_pose(self):
        m = self.truth.last()
        return m.pose.pose.position.x, m.pose.pose.position.y, yaw_of(m.pose.pose.orientation)

    def run_goto(self, x, y, angle, timeout=40.0):
        t0 = time.monotonic()
        sx, sy, _ = self.truth_pose()
        self.goto.send_goal(GotoGoal(x=x, y=y, angle=angle, timeout=timeout))
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(timeout + 5)))
        rospy.sleep(0.5)
        ux, uy = x - sx, y - sy
        n = math.hypot(ux, uy)
        overshoot = max([((m.pose.pose.position.x - x) * ux + (m.pose.pose.position.y - y) * uy) / n
                         for _, m in self.truth.since(t0)] + [0.0]) if n > 1e-3 else 0.0
        return self.goto.get_state(), self.goto.get_result(), overshoot, time.monotonic() - t0

    def test_1_goto_across_the_table(self):
        # Across the table above the column field (columns are pushed, not avoided).
        for gx, gy, ga in [(2.5, 1.55, -math.pi / 2), (0.5, 1.5, math.pi)]:
            state, r, overshoot, took = self.run_goto(gx, gy, ga)
            x, y, th = self.truth_pose()
            truth_err = math.hypot(x - gx, y - gy)
            truth_ang = abs(wrap_angle(th - ga))
            print('%s goto (%.2f, %.2f, %.2f) in %.1f s: driver estimate %.1f mm %.2f deg; truth %.1f mm %.2f deg; '
                  'overshoot %.1f mm' % (self.robot, gx, gy, ga, took, 1e3 * r.position_error, abs(r.angle_error) / DEG,
                                         1e3 * truth_err, truth_ang / DEG, 1e3 * overshoot))
            self.assertEqual(state, GoalStatus.SUCCEEDED, r.message)
            self.assertLessEqual(r.position_error, 0.010)
            self.assertLessEqual(abs(r.angle_error), 2 * DEG)
            self.assertLessEqual(overshoot, 0.020)
            # Truth also carries the localization's own error (the MCL tests bound it).
            self.assertLessEqual(truth_err, 0.040)
            self.assertLessEqual(truth_ang, 4 * DEG)

    def test_2_path_through_six_checkpoints(self):
        self.run_goto(0.5, 1.5, 0.0)
        cps = [Checkpoint(x=x, y=y) for x, y in [(0.9, 1.55), (1.3, 1.75), (1.7, 1.45), (2.1, 1.7), (2.5, 1.5), (2.1, 1.3)]]
        t0 = time.monotonic()
        self.follow.send_goal(FollowPathGoal(checkpoints=cps, timeout=60.0))
        self.assertTrue(self.follow.wait_for_result(rospy.Duration(65)))
        r = self.follow.get_result()
        self.assertEqual(self.follow.get_state(), GoalStatus.SUCCEEDED, r.message)
        self.assertEqual(r.checkpoints_passed, 6)
        curve = [(p.pose.position.x, p.pose.position.y) for p in self.path_msgs.last().poses]
        worst, worst_at = 0.0, (0.0, 0.0)
        for _, m in self.truth.since(t0):
            px, py = m.pose.pose.position.x, m.pose.pose.position.y
            best = 1e9
            for (ax, ay), (bx, by) in zip(curve, curve[1:]):
                l2 = (bx - ax) ** 2 + (by - ay) ** 2
                t = max(0.0, min(1.0, ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / l2)) if l2 > 0 else 0.0
                best = min(best, math.hypot(ax + t * (bx - ax) - px, ay + t * (by - ay) - py))
            if best > worst:
                worst, worst_at = best, (px, py)
        print('%s path in %.1f s: driver max cross-track %.1f mm, truth max distance to the curve %.1f mm at (%.2f, %.2f)'
              % (self.robot, time.monotonic() - t0, 1e3 * r.max_cross_track_error, 1e3 * worst, worst_at[0], worst_at[1]))
        self.assertLessEqual(r.max_cross_track_error, 0.030)
        self.assertLessEqual(worst, 0.030)

    def test_3_cancel_stops_the_wheels(self):
        self.run_goto(0.5, 1.5, 0.0)
        with real_time():
            self.goto.send_goal(GotoGoal(x=2.5, y=1.5, angle=0.0))
            time.sleep(2.0)
            t0 = time.monotonic()
            self.goto.cancel_goal()
            self.assertTrue(self.goto.wait_for_result(rospy.Duration(5)))
            time.sleep(1.0)
        zero_cmd = [t for t, m in self.cmd.since(t0) if m.linear.x == 0.0 and m.angular.z == 0.0]
        zero_motor = [t for t, m in self.motor.since(t0) if m.value == 0]
        still = [t for t, m in self.truth.since(t0) if abs(m.twist.twist.linear.x) < 0.005]
        self.assertTrue(zero_cmd and zero_motor and still)
        print('%s cancel: zero cmd_vel after %.1f ms, zero motor command (HCL) after %.1f ms, truth speed < 5 mm/s '
              'after %.0f ms' % (self.robot, 1e3 * (zero_cmd[0] - t0), 1e3 * (zero_motor[0] - t0), 1e3 * (still[0] - t0)))
        self.assertLessEqual(zero_cmd[0] - t0, 0.050)
        self.assertLessEqual(zero_motor[0] - t0, 0.050)

    def test_4_opponent_on_the_route(self):
        if not rospy.get_param('~opponent_sensing'):
            self.skipTest('this robot has no forward opponent sensor in its HAL config')
        self.run_goto(0.5, 1.5, 0.0)
        try:
            self.place(pose=Pose2D(x=1.6, y=1.5, theta=math.pi), hold=True)
            rospy.sleep(0.5)
            t0 = time.monotonic()
            state, r, _, _ = self.run_goto(2.5, 1.5, 0.0, timeout=25.0)
            closest = 1e9
            for (_, a), (_, b) in zip(self.truth.since(t0), self.opponent.since(t0)):
                closest = min(closest, math.hypot(a.pose.pose.position.x - b.pose.pose.position.x,
                                                  a.pose.pose.position.y - b.pose.pose.position.y))
            print('%s opponent on the route: %s, avoidance %s, closest centre distance %.3f m'
                  % (self.robot, r.message, r.avoidance, closest))
            self.assertIn(r.avoidance, ('stopped', 'detour', 'stopped+detour'))
            self.assertTrue(r.code == GotoResult.BLOCKED or (state == GoalStatus.SUCCEEDED and 'detour' in r.avoidance))
            self.assertGreater(closest, rospy.get_param('~collision_distance'))
        finally:
            self.park_opponent()


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'driver_sim', DriverSimTest, sys.argv)
