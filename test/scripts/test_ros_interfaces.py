#!/usr/bin/env python3
"""amcl's and move_base's interfaces, and teleop, on the simulated 2009 robot
(test/launch/ros_interfaces_eurobot2009.test). What a ROS user reaches for first:
  0. `rosrun tf tf_echo map base_link` works (Debian's tf-tools);
  1. /amcl_pose and /particlecloud come in the map frame; /request_nomotion_update publishes
     the cloud at once;
  2. a /move_base goal reaches its pose within the driver's tolerance, by ground truth;
  3. a cancelled /move_base goal ends PREEMPTED and the robot stops;
  4. /move_base_simple/goal (rviz's "2D Nav Goal") moves the robot;
  5. /cmd_vel drives the base, and it stops after the 0.5 s teleop timeout;
  6. after a kidnap, /global_localization spreads the cloud (on /particlecloud) and the robot is
     found again on /amcl_pose once it drives (by /cmd_vel);
  7. a match in progress ignores /cmd_vel (the drive's /diagnostics counts it)."""
import math
import threading
import time
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Pose2D, PoseArray, PoseStamped, PoseWithCovarianceStamped, Twist
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry
from robot_core.geometry import wrap_angle, yaw_of
from robot_sim.srv import SetSwitch, Teleport
from smart_brain.msg import MatchStatus
from std_srvs.srv import Empty

from test_support import DeviceDiagnostics, Latest, Recorder, value, wait_for


def quaternion(yaw):
    from geometry_msgs.msg import Quaternion
    return Quaternion(0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def spread_of(cloud):
    """(position std [m], heading circular variance in [0, 1]) of a PoseArray."""
    n = float(len(cloud.poses))
    xs = [p.position.x for p in cloud.poses]
    ys = [p.position.y for p in cloud.poses]
    ths = [yaw_of(p.orientation) for p in cloud.poses]
    mx, my = sum(xs) / n, sum(ys) / n
    std = math.sqrt(sum((x - mx) ** 2 + (y - my) ** 2 for x, y in zip(xs, ys)) / n)
    resultant = math.hypot(sum(math.cos(t) for t in ths), sum(math.sin(t) for t in ths)) / n
    return std, 1.0 - resultant


class Truth(object):
    """/sim/ground_truth (the test's only): (sim stamp, x, y, yaw, speed)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.items = []
        rospy.Subscriber('/sim/ground_truth', Odometry, self._cb, queue_size=500, tcp_nodelay=True)

    def _cb(self, m):
        p = m.pose.pose
        with self.lock:
            self.items.append((m.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation),
                               math.hypot(m.twist.twist.linear.x, m.twist.twist.linear.y)))

    def last(self):
        with self.lock:
            return self.items[-1] if self.items else None

    def since(self, t):
        with self.lock:
            return [i for i in self.items if i[0] >= t]


class RosInterfacesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_ros_interfaces')
        cls.truth = Truth()
        cls.amcl_pose = Latest('/amcl_pose', PoseWithCovarianceStamped)
        cls.cloud = Latest('/particlecloud', PoseArray, keep=True)
        cls.match = Latest('/brain/match_status', MatchStatus)
        cls.diag = DeviceDiagnostics()
        cls.cmd_vel = rospy.Publisher('/cmd_vel', Twist, queue_size=1)
        cls.simple_goal = rospy.Publisher('/move_base_simple/goal', PoseStamped, queue_size=1)
        cls.move_base = actionlib.SimpleActionClient('/move_base', MoveBaseAction)
        assert cls.match.wait(120.0, lambda m: m.state == 'waiting_for_start' and m.ready), \
            'the robot never got ready: %s' % cls.match.get()
        assert cls.move_base.wait_for_server(rospy.Duration(30.0)), 'no /move_base action server'
        assert wait_for(lambda: cls.truth.last() is not None, 10.0)
        cls.tolerance = rospy.get_param('/hal/driver/default_position_tolerance')
        cls.angle_tolerance = rospy.get_param('/hal/driver/default_angle_tolerance')

    def estimate(self):
        m = self.amcl_pose.get()
        p = m.pose.pose
        return p.position.x, p.position.y, yaw_of(p.orientation)

    def error(self):
        """amcl_pose against the truth now (the robot standing still: stamps need no matching)."""
        x, y, th = self.estimate()
        t = self.truth.last()
        return math.hypot(x - t[1], y - t[2]), abs(wrap_angle(th - t[3]))

    def wait_still(self, timeout=10.0):
        return wait_for(lambda: self.truth.last()[4] < 0.005, timeout, step=0.05)

    def goal_towards_centre(self, distance):
        """A pose `distance` from the robot towards the table's centre, heading that way."""
        _, x, y, _, _ = self.truth.last()
        heading = math.atan2(1.05 - y, 1.5 - x)
        return x + distance * math.cos(heading), y + distance * math.sin(heading), heading

    def test_0_tf_echo_shows_where_the_robot_is(self):
        """rosrun tf tf_echo map base_link: the usual tool is installed and reads our tf tree."""
        import subprocess
        out = subprocess.run(['timeout', '-s', 'INT', '6', 'rosrun', 'tf', 'tf_echo', 'map', 'base_link'],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True).stdout
        self.assertIn('Translation: [', out, 'tf_echo printed: %s' % out[-500:])

    def test_1_amcl_topics_and_nomotion_update(self):
        m = self.amcl_pose.wait(20.0)
        self.assertIsNotNone(m, 'no /amcl_pose')
        self.assertEqual(m.header.frame_id, 'map')
        c = m.pose.covariance
        self.assertTrue(c[0] > 0 and c[7] > 0 and c[35] > 0, 'covariance not positive: %s' % list(c))
        d, a = self.error()
        self.assertLess(d, 0.03, '/amcl_pose %.3f m from the truth at the start' % d)
        cloud = self.cloud.wait(10.0)
        self.assertIsNotNone(cloud, 'no /particlecloud')
        self.assertEqual(cloud.header.frame_id, 'map')
        self.assertGreater(len(cloud.poses), 10)
        # A no-motion update publishes the particles at once (the next cloud of ~cloud_rate is
        # 0.2 s away): the call returns with a new cloud out.
        rospy.wait_for_service('/request_nomotion_update', 10.0)
        before = self.cloud.get()
        rospy.ServiceProxy('/request_nomotion_update', Empty)()
        self.assertIsNotNone(self.cloud.wait(2.0, lambda m: m is not before), 'no cloud after request_nomotion_update')

    def test_2_move_base_goal_reaches_its_pose(self):
        x, y, th = self.goal_towards_centre(0.35)
        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = 'map'
        goal.target_pose.header.stamp = rospy.Time.now()
        goal.target_pose.pose.position.x, goal.target_pose.pose.position.y = x, y
        goal.target_pose.pose.orientation = quaternion(th)
        self.move_base.send_goal(goal)
        self.assertTrue(self.move_base.wait_for_result(rospy.Duration(40.0)), 'the move_base goal never ended')
        self.assertEqual(self.move_base.get_state(), GoalStatus.SUCCEEDED, self.move_base.get_goal_status_text())
        self.wait_still()
        _, tx, ty, tth, _ = self.truth.last()
        d, a = math.hypot(tx - x, ty - y), abs(wrap_angle(tth - th))
        print('move_base goal: %.1f mm, %.3f rad from the target by ground truth (tolerance %.1f mm, %.3f rad)'
              % (1e3 * d, a, 1e3 * self.tolerance, self.angle_tolerance))
        self.assertLess(d, self.tolerance, 'the robot stopped %.1f mm from the goal' % (1e3 * d))
        self.assertLess(a, self.angle_tolerance, 'the robot stopped %.3f rad off the goal heading' % a)

    def test_3_cancelled_move_base_goal_is_preempted_and_stops(self):
        x, y, th = self.goal_towards_centre(0.5)
        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = 'map'
        goal.target_pose.pose.position.x, goal.target_pose.pose.position.y = x, y
        goal.target_pose.pose.orientation = quaternion(th)
        start = self.truth.last()
        self.move_base.send_goal(goal)
        self.assertTrue(wait_for(lambda: math.hypot(self.truth.last()[1] - start[1], self.truth.last()[2] - start[2]) > 0.05,
                                 20.0), 'the robot did not move for the goal')
        self.move_base.cancel_goal()
        self.assertTrue(self.move_base.wait_for_result(rospy.Duration(5.0)))
        self.assertEqual(self.move_base.get_state(), GoalStatus.PREEMPTED, self.move_base.get_goal_status_text())
        self.assertTrue(self.wait_still(5.0), 'still moving after the cancel: %s' % (self.truth.last(),))
        self.assertGreater(math.hypot(self.truth.last()[1] - x, self.truth.last()[2] - y), 0.05,
                           'the cancelled goal was reached anyway')

    def test_4_move_base_simple_goal_moves_the_robot(self):
        x, y, th = self.goal_towards_centre(0.3)
        start = self.truth.last()
        g = PoseStamped()
        g.header.frame_id = 'map'
        g.header.stamp = rospy.Time.now()
        g.pose.position.x, g.pose.position.y = x, y
        g.pose.orientation = quaternion(th)
        self.assertTrue(wait_for(lambda: self.simple_goal.get_num_connections() > 0, 10.0))
        self.simple_goal.publish(g)
        self.assertTrue(wait_for(lambda: math.hypot(self.truth.last()[1] - x, self.truth.last()[2] - y) < 0.03, 40.0),
                        'the robot did not reach the 2D Nav Goal: %s' % (self.truth.last(),))
        moved = math.hypot(self.truth.last()[1] - start[1], self.truth.last()[2] - start[2])
        self.assertGreater(moved, 0.25)
        self.wait_still()

    def drive(self, v, w, seconds):
        """Publish /cmd_vel at 10 Hz for `seconds` of simulated time; the sim time of the last."""
        self.assertTrue(wait_for(lambda: self.cmd_vel.get_num_connections() > 0, 10.0))
        end = rospy.Time.now() + rospy.Duration(seconds)
        last = rospy.Time.now()
        while rospy.Time.now() < end:
            t = Twist()
            t.linear.x, t.angular.z = v, w
            self.cmd_vel.publish(t)
            last = rospy.Time.now()
            rospy.sleep(0.1)
        return last.to_sec()

    def test_5_cmd_vel_drives_and_stops_after_the_timeout(self):
        from hcl_drivers.msg import MotorCommand
        timeout = rospy.get_param('/hal/drive/teleop_timeout', 0.5)
        period = 1.0 / rospy.get_param('/hal/drive/rate')
        wheels = rospy.get_param('/hal/drive/wheels')
        commands = [Recorder(w['topic'], MotorCommand) for w in wheels.values()]
        self.wait_still()
        start = self.truth.last()
        v = 0.15
        last = self.drive(v, 0.0, 1.5)
        self.assertTrue(wait_for(lambda: self.truth.last()[0] > last + timeout + 2.0, 10.0))
        after = self.truth.since(last)
        moved = math.hypot(after[0][1] - start[1], after[0][2] - start[2])
        self.assertGreater(moved, 0.1, '/cmd_vel did not drive the base: %.3f m' % moved)
        # The drive's motor commands stay non-zero until the teleop timeout after the last
        # /cmd_vel, and are zero from then on (within one drive period); the base then stops.
        zero_at = []
        for rec in commands:
            late = [(m.header.stamp.to_sec(), m.value) for m in rec.messages() if m.header.stamp.to_sec() >= last]
            self.assertTrue(late, 'no motor commands after the last /cmd_vel')
            self.assertTrue(any(value != 0 for t, value in late if t <= last + 0.8 * timeout),
                            'the drive stopped before the teleop timeout: %s' % late[:10])
            zero_at.append(next(t for t, value in late if value == 0) - last)
            self.assertTrue(all(value == 0 for t, value in late if t >= last + zero_at[-1]), 'driving again after the stop')
        stopped_at = next((t for (t, _, _, _, s) in after if s < 0.005), None)
        print('cmd_vel: %.3f m driven; motor commands zero %.3f s and the base still %.3f s (simulated) after the last '
              '/cmd_vel (teleop timeout %.2f s)' % (moved, max(zero_at), stopped_at - last if stopped_at else float('nan'),
                                                     timeout))
        self.assertLess(max(zero_at), timeout + 2.0 * period + 0.02)
        self.assertGreater(min(zero_at), 0.8 * timeout)
        self.assertIsNotNone(stopped_at, 'the base never stopped after the last /cmd_vel')

    def test_6_kidnap_found_again_through_amcls_interface(self):
        rospy.wait_for_service('/sim/teleport', 10.0)
        ok = rospy.ServiceProxy('/sim/teleport', Teleport)(Pose2D(1.5, 0.8, 0.5))
        self.assertTrue(ok.ok, ok.message)
        self.wait_still()
        rospy.wait_for_service('/global_localization', 10.0)
        ok_at = rospy.Time.now()
        t0 = time.monotonic()
        rospy.ServiceProxy('/global_localization', Empty)()
        # The call publishes the spread cloud at once; the beacons then pin the position and
        # the heading down within a few steps, sometimes before the next cloud at ~cloud_rate.
        spread = wait_for(lambda: [c for c in self.cloud.since(t0) if c.header.stamp >= ok_at and spread_of(c)[1] > 0.5],
                          5.0, step=0.02)
        self.assertTrue(spread, 'no spread cloud on /particlecloud after /global_localization: %s'
                        % ([spread_of(c) for c in self.cloud.since(t0)][:5],))
        # The beacons give the position at once; the heading comes from motion: the robot
        # drives on /cmd_vel until the estimate is right and the whole cloud has converged on it
        # (particles with a wrong heading die out only while it moves).
        def found():
            d, a = self.error()
            cloud = self.cloud.get()
            std, circular_variance = spread_of(cloud)
            # circular variance 0.02: a heading spread of about 0.2 rad
            return d < 0.05 and a < 0.1 and std < 0.05 and circular_variance < 0.02
        ok = False
        for _ in range(4):
            self.drive(0.12, 0.0, 1.5)
            ok = wait_for(found, 3.0, step=0.05)
            if ok:
                break
        d, a = self.error()
        print('kidnap: found again %.1f s (wall) after /global_localization, %.1f mm / %.3f rad off; cloud %s'
              % (time.monotonic() - t0, 1e3 * d, a, spread_of(self.cloud.get())))
        self.assertTrue(ok, '/amcl_pose %.3f m, %.3f rad off the truth, cloud (std, circular variance) %s'
                        % (d, a, spread_of(self.cloud.get())))

    def test_7_a_match_in_progress_ignores_cmd_vel(self):
        # The earlier cases' /cmd_vel has timed out before the start: whatever drives with
        # teleop from here on does so during the match.
        before = time.monotonic()
        self.assertIsNotNone(self.diag.wait_for('hal/drive', lambda s: value(s, 'driven by') != 'teleop', 5.0,
                                                since=before), 'teleop still drives before the match')
        rospy.wait_for_service('/sim/set_switch', 10.0)
        self.assertTrue(rospy.ServiceProxy('/sim/set_switch', SetSwitch)('start_cord', False).ok)
        self.assertTrue(self.match.wait(10.0, lambda m: m.state == 'running'), 'the match did not start')
        t0 = time.monotonic()
        self.drive(0.0, 2.0, 1.0)
        s = self.diag.wait_for('hal/drive', lambda s: int(value(s, 'teleop commands ignored in a match') or 0) >= 5, 5.0,
                               since=t0)
        self.assertIsNotNone(s, 'the drive did not count /cmd_vel ignored in the match: %s' % self.diag.status('hal/drive'))
        statuses = [st for t, st in self.diag.items if t >= t0 and 'hal/drive' in st.name]
        self.assertFalse(any(value(st, 'driven by') == 'teleop' for st in statuses), 'teleop drove during the match')


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'ros_interfaces_eurobot2009', RosInterfacesTest)
