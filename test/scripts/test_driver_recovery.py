#!/usr/bin/env python3
"""The driver's recoveries on the whole simulated robot (test/launch/driver_recovery_eurobot2009.test):
a square robot with its right side along the bottom border and its left side against a parked
opponent gets a goal that needs a left turn. The turn stalls (its corners go into the border or
the opponent); the driver tries its recoveries instead of ending the goal BLOCKED: the feedback
names the back-off, the robot is free (moved 5 cm) within 3 s of the recovery's start, and the
goal is reached. Ground truth (/sim/*) is read by this test only."""
import math
import sys
import time
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Pose2D, PoseWithCovarianceStamped
from hal_nodes.msg import GotoAction, GotoGoal, LocalizationQuality
from nav_msgs.msg import Odometry
from robot_sim.srv import PlaceOpponent, Teleport

from test_support import Recorder, yaw_of

OPPONENT_RADIUS_PARAM = '/sim/world/opponent/radius'
FREE = 0.05  # [m] away from where it was pinned: free
GAP = 0.0  # [m] between the square's sides and the border, the opponent: touching both, it cannot turn at all


class DriverRecoveryTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_driver_recovery')
        cls.half = float(rospy.get_param('~half_side'))
        cls.opponent_radius = float(rospy.get_param(OPPONENT_RADIUS_PARAM))
        cls.truth = Recorder('/sim/ground_truth', Odometry)
        cls.quality = Recorder('/mcl/quality', LocalizationQuality)
        cls.estimate = Recorder('/mcl/pose', PoseWithCovarianceStamped)
        cls.initialpose = rospy.Publisher('/initialpose', PoseWithCovarianceStamped, queue_size=1, latch=True)
        cls.goto = actionlib.SimpleActionClient('/hal/driver/goto', GotoAction)
        assert cls.goto.wait_for_server(rospy.Duration(60)), 'no /hal/driver/goto'
        rospy.wait_for_service('/sim/place_opponent', 30)
        cls.place = rospy.ServiceProxy('/sim/place_opponent', PlaceOpponent)
        cls.teleport = rospy.ServiceProxy('/sim/teleport', Teleport)
        cls.place(pose=Pose2D(x=2.75, y=1.0, theta=0.0), hold=True)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            q = cls.quality.last()
            if q is not None and q.probability > 0.6 and cls.truth.last() is not None:
                break
            time.sleep(0.2)
        rospy.sleep(2.0)

    def truth_pose(self):
        m = self.truth.last()
        return m.pose.pose.position.x, m.pose.pose.position.y, yaw_of(m.pose.pose.orientation)

    def test_a_pinned_robot_frees_itself_and_reaches_its_goal(self):
        # Along the bottom border, heading east, the right side GAP off it, the opponent parked
        # against its left side: put there (a square robot cannot drive sideways into that spot)
        # and told to the localization as a team does with rviz's 2D Pose Estimate.
        x0, y0, th0 = 1.6, self.half + GAP, 0.0
        self.place(pose=Pose2D(x=x0, y=y0 + self.half + self.opponent_radius + GAP, theta=0.0), hold=True)
        self.assertTrue(self.teleport(pose=Pose2D(x=x0, y=y0, theta=th0)).ok)
        estimate = PoseWithCovarianceStamped()
        estimate.header.frame_id = 'map'
        estimate.header.stamp = rospy.Time.now()
        estimate.pose.pose.position.x, estimate.pose.pose.position.y = x0, y0
        estimate.pose.pose.orientation.w = 1.0
        for i in (0, 7, 35):
            estimate.pose.covariance[i] = 0.0004
        rospy.sleep(0.5)
        self.initialpose.publish(estimate)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            q, e = self.quality.last(), self.estimate.last()
            if q is not None and q.probability > 0.6 and e is not None and \
                    math.hypot(e.pose.pose.position.x - x0, e.pose.pose.position.y - y0) < 0.02:
                break
            time.sleep(0.1)
        else:
            self.fail('the localization did not take the pinned pose: %s' % self.quality.last())
        rospy.sleep(1.0)
        # A goal behind on the left: a left turn of about 125 degrees, then a clear way.
        feedback = []  # (ROS time, recovery): the simulated clock, as the driver's timing
        t0 = rospy.get_time()
        self.goto.send_goal(GotoGoal(x=x0 - 0.5, y=0.8, angle=math.pi / 2, timeout=40.0),
                            feedback_cb=lambda f: feedback.append((rospy.get_time() - t0, f.recovery)))
        freed_at = None
        wall0 = time.monotonic()
        while time.monotonic() - wall0 < 120.0 and not self.goto.wait_for_result(rospy.Duration(0.05)):
            x, y, th = self.truth_pose()
            if freed_at is None and math.hypot(x - x0, y - y0) > FREE:
                freed_at = rospy.get_time() - t0
        state, result = self.goto.get_state(), self.goto.get_result()
        recoveries = sorted({r for _, r in feedback if r})
        began = min([t for t, r in feedback if r] or [float('nan')])
        print('pinned square robot: recoveries %s (the first %.1f s into the goal), free after %s s, result %s: %s'
              % (recoveries, began, '%.1f' % freed_at if freed_at else 'never', state, result.message if result else None))
        self.assertTrue(any(r.startswith('back_off') for r in recoveries), 'no back-off in the feedback: %s' % recoveries)
        self.assertIsNotNone(freed_at, 'never got free')
        recovery_at = min(t for t, r in feedback if r)
        self.assertLess(freed_at - recovery_at, 3.0, 'free %.1f s after the recovery began' % (freed_at - recovery_at))
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.message if result else 'no result')
        x, y, _ = self.truth_pose()
        self.assertLess(math.hypot(x - (x0 - 0.5), y - 0.8), 0.05)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'driver_recovery_eurobot2009', DriverRecoveryTest, sys.argv)
