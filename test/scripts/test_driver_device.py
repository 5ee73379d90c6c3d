#!/usr/bin/env python3
"""The Driver device (hal_nodes/Driver) in a real hal_node against a kinematic robot played here."""
import math
import sys
import threading
import time
import unittest

import actionlib
import rospy
from robot_core.geometry import wrap_angle
import rostest
from actionlib_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PointStamped, PoseWithCovarianceStamped, Twist
from hal_nodes.msg import (Checkpoint, FollowPathAction, FollowPathGoal, GoStraightAction, GoStraightGoal, GoStraightResult,
                           GotoAction, GotoGoal, GotoResult, LocalizationQuality, PathEdit, RotateByAction,
                           RotateByGoal)
from nav_msgs.msg import Odometry, Path
from std_srvs.srv import Trigger

PERIOD = 0.02  # the driver's rate is 50 Hz


class Robot(object):
    """A differential-drive base: the newest cmd_vel acts one step later; publishes odom and localization."""

    def __init__(self):
        self.lock = threading.Lock()
        self.x, self.y, self.th = 0.5, 0.5, 0.0
        self.v = self.w = 0.0
        self.pending = Twist()
        self.cmds = []            # (wall time, linear.x, angular.z)
        self.localize = True      # publish /mcl/pose and /mcl/quality
        self.odometry = True      # publish /odom (False: the odometry died)
        self.walled = False       # True: a wall holds the robot, its wheels stall (it does not move)
        self.probability = 0.9
        self.odom_pub = rospy.Publisher('/odom', Odometry, queue_size=1)
        self.pose_pub = rospy.Publisher('/mcl/pose', PoseWithCovarianceStamped, queue_size=1)
        self.quality_pub = rospy.Publisher('/mcl/quality', LocalizationQuality, queue_size=1)
        rospy.Subscriber('/hal/drive/cmd_vel', Twist, self._cmd, queue_size=50, tcp_nodelay=True)
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _cmd(self, msg):
        with self.lock:
            self.cmds.append((time.monotonic(), msg.linear.x, msg.angular.z))
            self.pending = msg

    def place(self, x, y, th):
        with self.lock:
            self.x, self.y, self.th, self.v, self.w = x, y, th, 0.0, 0.0

    def pose(self):
        with self.lock:
            return self.x, self.y, self.th

    def commands_since(self, t0):
        with self.lock:
            return [c for c in self.cmds if c[0] >= t0]

    def _run(self):
        dt = 0.01
        k = 0
        while not rospy.is_shutdown():
            try:
                self._step(dt, k)
            except rospy.ROSException:  # shutting down
                return
            k += 1
            time.sleep(dt)

    def _step(self, dt, k):
        with self.lock:
            self.x += self.v * dt * math.cos(self.th)
            self.y += self.v * dt * math.sin(self.th)
            self.th = wrap_angle(self.th + self.w * dt)
            self.v, self.w = self.pending.linear.x, self.pending.angular.z  # applied from the next step
            if self.walled:
                self.v = self.w = 0.0
            x, y, th, v, w = self.x, self.y, self.th, self.v, self.w
        now = rospy.Time.now()
        o = Odometry()
        o.header.stamp = now
        o.header.frame_id = 'odom'
        o.pose.pose.position.x, o.pose.pose.position.y = x, y
        o.pose.pose.orientation.z, o.pose.pose.orientation.w = math.sin(th / 2), math.cos(th / 2)
        o.twist.twist.linear.x, o.twist.twist.angular.z = v, w
        if self.odometry:
            self.odom_pub.publish(o)
        if k % 5 == 0 and self.localize:  # localization at 20 Hz
            p = PoseWithCovarianceStamped()
            p.header = o.header
            p.header.frame_id = 'map'
            p.pose.pose = o.pose.pose
            self.pose_pub.publish(p)
            q = LocalizationQuality()
            q.header = p.header
            q.probability = self.probability
            self.quality_pub.publish(q)


class DriverDeviceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_driver_device')
        cls.robot = Robot()
        cls.goto = actionlib.SimpleActionClient('/hal/driver/goto', GotoAction)
        cls.straight = actionlib.SimpleActionClient('/hal/driver/go_straight', GoStraightAction)
        cls.rotate = actionlib.SimpleActionClient('/hal/driver/rotate_by', RotateByAction)
        cls.path = actionlib.SimpleActionClient('/hal/driver/follow_path', FollowPathAction)
        for c in (cls.goto, cls.straight, cls.rotate, cls.path):
            assert c.wait_for_server(rospy.Duration(30)), 'driver action servers did not come up'
        cls.edit_pub = rospy.Publisher('/hal/driver/path_edit', PathEdit, queue_size=5)
        cls.opponent_pub = rospy.Publisher('/test/opponent', PointStamped, queue_size=1)
        cls.diag_pub = rospy.Publisher('/diagnostics', DiagnosticArray, queue_size=5)
        cls.paths = []
        rospy.Subscriber('/hal/driver/path', Path, lambda m: cls.paths.append(m))
        time.sleep(1.0)

    def setUp(self):
        self.robot.localize = True
        self.robot.odometry = True
        self.robot.walled = False
        self.robot.probability = 0.9
        self.robot.place(0.5, 0.5, 0.0)
        time.sleep(0.3)

    def assertStoppedAfter(self, t0, within=0.1):
        """The last command is zero and it came within `within` s of t0."""
        # The zero command and the action result travel on different connections: the result can be
        # handled here first, so wait (a bounded time) for the command to be delivered too. The latency
        # below is still measured from the command's arrival.
        deadline = time.monotonic() + 1.0
        while time.monotonic() < deadline and not [c for c in self.robot.commands_since(t0) if c[1:] == (0.0, 0.0)]:
            time.sleep(0.005)
        cmds = self.robot.commands_since(t0)
        self.assertTrue(cmds, 'no command after t0')
        zero = [c for c in cmds if c[1] == 0.0 and c[2] == 0.0]
        self.assertTrue(zero, 'no zero command after t0')
        self.assertLessEqual(zero[0][0] - t0, within)
        self.assertEqual((cmds[-1][1], cmds[-1][2]), (0.0, 0.0), 'a non-zero command came after the stop')

    def test_goto_reaches_the_goal(self):
        self.goto.send_goal(GotoGoal(x=1.5, y=1.2, angle=1.0, timeout=30.0))
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(30)))
        self.assertEqual(self.goto.get_state(), GoalStatus.SUCCEEDED, self.goto.get_goal_status_text())
        r = self.goto.get_result()
        self.assertEqual(r.code, GotoResult.REACHED)
        x, y, th = self.robot.pose()
        self.assertLess(math.hypot(x - 1.5, y - 1.2), 0.010)
        self.assertLess(abs(wrap_angle(th - 1.0)), math.radians(2))
        # Limits: no command beyond the configured speeds.
        for _, v, w in self.robot.commands_since(0):
            self.assertLessEqual(abs(v), 0.5 + 1e-9)
            self.assertLessEqual(abs(w), 3.0 + 1e-9)

    def test_cancel_stops_the_wheels_at_once(self):
        latencies = []
        for _ in range(5):
            self.robot.place(0.5, 0.5, 0.0)
            self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0))
            time.sleep(1.0)
            self.assertGreater(self.robot.commands_since(time.monotonic() - 0.1)[-1][1], 0.1, 'not driving yet')
            t0 = time.monotonic()
            self.goto.cancel_goal()
            self.assertTrue(self.goto.wait_for_result(rospy.Duration(5)))
            time.sleep(0.3)
            self.assertEqual(self.goto.get_state(), GoalStatus.PREEMPTED)
            self.assertEqual(self.goto.get_result().code, GotoResult.CANCELED)
            self.assertStoppedAfter(t0, within=0.05)
            zero = [c for c in self.robot.commands_since(t0) if c[1] == 0.0]
            latencies.append(zero[0][0] - t0)
        print('cancel -> zero cmd_vel: max %.1f ms' % (1e3 * max(latencies)))

    def test_new_goal_on_another_action_preempts(self):
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0))
        time.sleep(0.8)
        self.rotate.send_goal(RotateByGoal(angle=0.5))
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(2)))
        self.assertEqual(self.goto.get_state(), GoalStatus.PREEMPTED)
        self.assertTrue(self.rotate.wait_for_result(rospy.Duration(10)))
        self.assertEqual(self.rotate.get_state(), GoalStatus.SUCCEEDED, self.rotate.get_goal_status_text())

    def test_stale_localization_aborts(self):
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0))
        time.sleep(0.8)
        t0 = time.monotonic()
        self.robot.localize = False
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(3)))
        self.assertEqual(self.goto.get_state(), GoalStatus.ABORTED)
        r = self.goto.get_result()
        self.assertEqual(r.code, GotoResult.LOCALIZATION_STALE, r.message)
        self.assertIn('stale', r.message)
        self.assertIn('held for longer than max_hold', r.message)
        time.sleep(0.2)
        self.assertStoppedAfter(t0, within=0.6 + 0.05 + 0.25)  # max_pose_age + one localization period + slack
        # The wheels stop when the hold begins; the goal ends max_hold later with no command between.
        self.assertGreaterEqual(time.monotonic() - t0, 0.6 + 1.0)

    def test_dead_odometry_stops_a_relative_move(self):
        # A robot builder's guarantee: when odometry really dies, the wheels stop (max_odom_age).
        self.robot.localize = False
        self.straight.send_goal(GoStraightGoal(distance=1.0))
        time.sleep(0.5)
        t0 = time.monotonic()
        self.robot.odometry = False
        self.assertTrue(self.straight.wait_for_result(rospy.Duration(3)))
        self.assertEqual(self.straight.get_state(), GoalStatus.ABORTED)
        r = self.straight.get_result()
        self.assertEqual(r.code, GoStraightResult.ODOMETRY_STALE, r.message)
        self.assertStoppedAfter(t0, within=0.5 + 0.02 + 0.25)  # max_odom_age + one control period + slack

    def test_uncertain_localization_aborts(self):
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0))
        time.sleep(0.8)
        self.robot.probability = 0.2
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(3)))
        r = self.goto.get_result()
        self.assertEqual(r.code, GotoResult.LOCALIZATION_UNCERTAIN, r.message)
        self.assertIn('0.20', r.message)

    def test_motor_fault_aborts(self):
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0))
        time.sleep(0.8)
        d = DiagnosticArray()
        d.header.stamp = rospy.Time.now()
        d.status = [DiagnosticStatus(level=DiagnosticStatus.ERROR, name='/hal/drive: device', message='motor board stale')]
        self.diag_pub.publish(d)
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(3)))
        r = self.goto.get_result()
        self.assertEqual(r.code, GotoResult.MOTOR_FAULT, r.message)
        self.assertIn('motor board stale', r.message)
        self.assertIn('held for longer than max_hold', r.message)
        d.status[0].level = DiagnosticStatus.OK
        d.status[0].message = 'ok'
        self.diag_pub.publish(d)
        time.sleep(0.2)

    def test_a_passing_localization_outage_holds_the_goal_then_it_goes_on(self):
        waiting = []
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0, timeout=30.0), feedback_cb=lambda f: waiting.append(f.waiting))
        time.sleep(0.8)
        t0 = time.monotonic()
        self.robot.localize = False
        time.sleep(1.2)  # stale after max_pose_age (0.6 s): held about 0.6 s, less than max_hold (1.0 s)
        self.assertStoppedAfter(t0, within=0.6 + 0.05 + 0.25)
        held_at = self.robot.pose()
        self.robot.localize = True
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(20)))
        self.assertEqual(self.goto.get_state(), GoalStatus.SUCCEEDED, self.goto.get_goal_status_text())
        self.assertTrue([w for w in waiting if w.startswith('localization stale')], 'the feedback never said why it held')
        self.assertEqual(waiting[-1], '', 'the feedback still says it waits after the goal went on')
        self.assertGreater(math.hypot(self.robot.pose()[0] - held_at[0], self.robot.pose()[1] - held_at[1]), 0.3)

    def test_a_passing_motor_fault_holds_the_goal_then_it_goes_on(self):
        waiting = []
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0, timeout=30.0), feedback_cb=lambda f: waiting.append(f.waiting))
        time.sleep(0.8)
        d = DiagnosticArray()
        d.header.stamp = rospy.Time.now()
        d.status = [DiagnosticStatus(level=DiagnosticStatus.ERROR, name='/hal/drive: device', message='motor board stale')]
        t0 = time.monotonic()
        self.diag_pub.publish(d)
        time.sleep(0.5)
        self.assertStoppedAfter(t0, within=0.1)
        d.status[0].level = DiagnosticStatus.OK
        d.status[0].message = 'ok'
        self.diag_pub.publish(d)
        self.assertTrue(self.goto.wait_for_result(rospy.Duration(20)))
        self.assertEqual(self.goto.get_state(), GoalStatus.SUCCEEDED, self.goto.get_goal_status_text())
        self.assertTrue([w for w in waiting if 'motor board stale' in w], 'the feedback never said why it held')

    def test_a_relative_move_held_for_odometry_keeps_its_target(self):
        self.robot.localize = False
        self.straight.send_goal(GoStraightGoal(distance=0.6, timeout=30.0))
        time.sleep(0.5)
        self.robot.odometry = False
        time.sleep(0.8)  # stale after max_odom_age (0.5 s): held about 0.3 s
        self.robot.odometry = True
        self.assertTrue(self.straight.wait_for_result(rospy.Duration(20)))
        self.assertEqual(self.straight.get_state(), GoalStatus.SUCCEEDED, self.straight.get_goal_status_text())
        self.assertAlmostEqual(self.robot.pose()[0], 0.5 + 0.6, delta=0.02)

    def test_a_stall_ends_the_goal_blocked(self):
        # Pushing a wall no sensor sees: commanded, odometry reads no motion for stall_timeout (1 s).
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0, timeout=30.0))
        time.sleep(0.8)
        t0 = time.monotonic()
        self.robot.walled = True
        try:
            self.assertTrue(self.goto.wait_for_result(rospy.Duration(5)))
            r = self.goto.get_result()
            self.assertEqual(r.code, GotoResult.BLOCKED, r.message)
            self.assertIn('stalled', r.message)
            self.assertGreaterEqual(time.monotonic() - t0, 1.0)
            self.assertStoppedAfter(t0, within=1.0 + 0.5)
        finally:
            self.robot.walled = False

    def test_deactivation_aborts_and_refuses(self):
        deactivate = rospy.ServiceProxy('/effectors/deactivate', Trigger)
        activate = rospy.ServiceProxy('/effectors/activate', Trigger)
        self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0))
        time.sleep(0.8)
        t0 = time.monotonic()
        deactivate()
        try:
            self.assertTrue(self.goto.wait_for_result(rospy.Duration(3)))
            self.assertEqual(self.goto.get_result().code, GotoResult.DEACTIVATED)
            self.assertStoppedAfter(t0, within=0.1)
            self.goto.send_goal(GotoGoal(x=1.0, y=0.5, angle=0.0))
            self.assertTrue(self.goto.wait_for_result(rospy.Duration(3)))
            self.assertEqual(self.goto.get_result().code, GotoResult.DEACTIVATED)
        finally:
            activate()
            time.sleep(0.3)

    def test_go_straight_and_rotate_by_from_odometry(self):
        self.robot.localize = False  # relative moves need odometry only
        self.straight.send_goal(GoStraightGoal(distance=0.3))
        self.assertTrue(self.straight.wait_for_result(rospy.Duration(10)))
        self.assertEqual(self.straight.get_state(), GoalStatus.SUCCEEDED, self.straight.get_goal_status_text())
        x, y, th = self.robot.pose()
        self.assertAlmostEqual(x, 0.8, delta=0.006)
        self.straight.send_goal(GoStraightGoal(distance=0.1, backwards=True))
        self.assertTrue(self.straight.wait_for_result(rospy.Duration(10)))
        self.assertAlmostEqual(self.robot.pose()[0], 0.7, delta=0.006)
        self.rotate.send_goal(RotateByGoal(angle=2 * math.pi + 0.5))
        self.assertTrue(self.rotate.wait_for_result(rospy.Duration(15)))
        self.assertEqual(self.rotate.get_state(), GoalStatus.SUCCEEDED, self.rotate.get_goal_status_text())
        self.assertAlmostEqual(self.robot.pose()[2], 0.5, delta=math.radians(2))

    def test_follow_path_with_an_edit(self):
        self.paths[:] = []
        cps = [Checkpoint(x=1.0, y=0.7), Checkpoint(x=1.5, y=0.5), Checkpoint(x=2.0, y=0.8), Checkpoint(x=2.2, y=1.3)]
        self.path.send_goal(FollowPathGoal(checkpoints=cps, timeout=40.0))
        time.sleep(1.0)
        self.assertTrue(self.paths and self.paths[-1].header.frame_id == 'map' and len(self.paths[-1].poses) > 20)
        # While driving: replace the last checkpoint and append one more.
        self.edit_pub.publish(PathEdit(op=PathEdit.REPLACE, index=3, checkpoint=Checkpoint(x=2.3, y=1.2)))
        self.edit_pub.publish(PathEdit(op=PathEdit.APPEND, checkpoint=Checkpoint(x=1.8, y=1.5)))
        self.assertTrue(self.path.wait_for_result(rospy.Duration(40)))
        self.assertEqual(self.path.get_state(), GoalStatus.SUCCEEDED, self.path.get_goal_status_text())
        r = self.path.get_result()
        self.assertEqual(r.checkpoints_passed, 5)
        x, y, _ = self.robot.pose()
        self.assertLess(math.hypot(x - 1.8, y - 1.5), 0.010)
        self.assertLess(r.max_cross_track_error, 0.03)
        last = self.paths[-1].poses[-1].pose.position
        self.assertAlmostEqual(last.x, 1.8, delta=1e-6)

    def opponent_at(self, x, y):
        """Publish a tracked opponent at (x, y) until the returned event is set."""
        stop = threading.Event()

        def run():
            while not stop.is_set():
                p = PointStamped()
                p.header.stamp = rospy.Time.now()
                p.header.frame_id = 'map'
                p.point.x, p.point.y = x, y
                self.opponent_pub.publish(p)
                time.sleep(0.05)
        threading.Thread(target=run, daemon=True).start()
        return stop

    def test_opponent_on_the_route_detour_goes_around(self):
        detour = actionlib.SimpleActionClient('/hal/driver_detour/goto', GotoAction)
        self.assertTrue(detour.wait_for_server(rospy.Duration(10)))
        stop = self.opponent_at(1.6, 0.6)
        try:
            closest = [1e9]
            done = threading.Event()

            def watch():
                while not done.is_set():
                    x, y, _ = self.robot.pose()
                    closest[0] = min(closest[0], math.hypot(1.6 - x, 0.6 - y))
                    time.sleep(0.01)
            threading.Thread(target=watch, daemon=True).start()
            detour.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0))
            self.assertTrue(detour.wait_for_result(rospy.Duration(30)))
            done.set()
            r = detour.get_result()
            self.assertEqual(detour.get_state(), GoalStatus.SUCCEEDED, r.message)
            self.assertEqual(r.avoidance, 'detour')
            self.assertGreaterEqual(r.detours, 1)
            x, y, _ = self.robot.pose()
            self.assertLess(math.hypot(x - 2.5, y - 0.5), 0.010)
            self.assertGreater(closest[0], 0.16 + 0.2, 'came within the two outlines of the opponent')
        finally:
            stop.set()

    def test_opponent_on_the_route_stops_then_blocks(self):
        stop = threading.Event()

        def opponent():
            while not stop.is_set():
                p = PointStamped()
                p.header.stamp = rospy.Time.now()
                p.header.frame_id = 'map'
                p.point.x, p.point.y = 1.6, 0.5
                self.opponent_pub.publish(p)
                time.sleep(0.05)
        t = threading.Thread(target=opponent, daemon=True)
        t.start()
        try:
            feedback = []
            self.goto.send_goal(GotoGoal(x=2.5, y=0.5, angle=0.0), feedback_cb=lambda f: feedback.append(f.avoidance))
            self.assertTrue(self.goto.wait_for_result(rospy.Duration(15)))
            r = self.goto.get_result()
            self.assertEqual(r.code, GotoResult.BLOCKED, r.message)
            self.assertEqual(r.avoidance, 'stopped')
            self.assertIn('stopped', feedback)
            x, y, _ = self.robot.pose()
            # No collision: our outline (0.16) and the opponent's (0.2) never touched.
            self.assertGreater(math.hypot(1.6 - x, 0.5 - y), 0.36)
        finally:
            stop.set()
            t.join()


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'driver_device', DriverDeviceTest, sys.argv)
