#!/usr/bin/env python3
"""The simulator's interface (launch/sim_world_services.test): /clock at the real-time factor,
ground truth, markers (our robot's outline among them), elements, match and score, and the
services to teleport the robot, place the opponent, flip switches, inject faults (now,
scripted, and from ~faults) and change the real-time factor of the running simulation."""
import math
import os
import signal
import subprocess
import time
import unittest

import rospy
from robot_core.geometry import yaw_of
import rostest
from geometry_msgs.msg import Pose2D
from nav_msgs.msg import Odometry
from robot_sim.msg import ActiveFaults, DebugMotorCommand, GameElements, MatchState
from robot_sim.srv import InjectFault, PlaceOpponent, SetRealTimeFactor, SetSwitch, Teleport
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Int32
from visualization_msgs.msg import MarkerArray
from test_support import Latest

RTF = 4.0




def sim_now(clock):
    m = clock.wait()
    return m.clock.to_sec() if m else 0.0


def wait_sim(clock, t, timeout=20.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and sim_now(clock) < t:
        time.sleep(0.01)


class SimServicesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_sim_world_services')
        cls.clock = Latest('/clock', Clock)
        cls.truth = Latest('/sim/ground_truth', Odometry)
        cls.opponent = Latest('/sim/opponent', Odometry)
        cls.elements = Latest('/sim/elements', GameElements)
        cls.match = Latest('/sim/match', MatchState)
        cls.score = Latest('/sim/score', Int32)
        cls.faults = Latest('/sim/faults', ActiveFaults, keep=True)
        cls.markers = Latest('/sim/markers', MarkerArray)
        cls.motors = rospy.Publisher('/sim/debug/motor_command', DebugMotorCommand, queue_size=10)
        for s in ('inject_fault', 'teleport', 'place_opponent', 'set_switch'):
            rospy.wait_for_service('/sim/' + s, timeout=20.0)
        cls.inject = rospy.ServiceProxy('/sim/inject_fault', InjectFault)
        cls.teleport = rospy.ServiceProxy('/sim/teleport', Teleport)
        cls.place = rospy.ServiceProxy('/sim/place_opponent', PlaceOpponent)
        cls.switch = rospy.ServiceProxy('/sim/set_switch', SetSwitch)
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline and not cls.motors.get_num_connections():
            time.sleep(0.05)

    def drive(self, left, right):
        self.motors.publish(DebugMotorCommand(at=0.0, motors=['left', 'right'], fractions=[left, right]))

    def test_1_clock_runs_at_the_real_time_factor(self):
        wait_sim(self.clock, 0.5)
        t0, w0 = sim_now(self.clock), time.monotonic()
        time.sleep(2.0)
        t1, w1 = sim_now(self.clock), time.monotonic()
        self.assertAlmostEqual((t1 - t0) / (w1 - w0), RTF, delta=0.6)
        m = self.truth.wait()
        self.assertEqual(m.header.frame_id, 'map')
        self.assertEqual(m.child_frame_id, 'base_link')

    def test_1b_the_real_time_factor_changes_while_running(self):
        set_factor = rospy.ServiceProxy('/sim/set_real_time_factor', SetRealTimeFactor)
        bad = set_factor(-1.0)
        self.assertFalse(bad.ok)
        self.assertIn('must be >= 0', bad.message)
        try:
            before = sim_now(self.clock)
            self.assertTrue(set_factor(1.5).ok)
            time.sleep(0.5)
            t0, w0 = sim_now(self.clock), time.monotonic()
            self.assertGreaterEqual(t0, before)  # simulated time goes on from where it was
            time.sleep(2.0)
            t1, w1 = sim_now(self.clock), time.monotonic()
            self.assertAlmostEqual((t1 - t0) / (w1 - w0), 1.5, delta=0.3)
        finally:
            self.assertTrue(set_factor(RTF).ok)

    def test_2_markers_elements_and_scripted_fault(self):
        markers = self.markers.wait()
        self.assertIsNotNone(markers)
        ns = set(m.ns for m in markers.markers)
        for want in ('table', 'borders', 'beacons', 'opponent', 'elements', 'start_zones', 'score_zones'):
            self.assertIn(want, ns)
        self.assertEqual(sum(1 for m in markers.markers if m.ns == 'beacons'), 3)
        # Our robot's outline (no footprint configured: a true circle, drawn with 48 vertices on
        # the radius) at its true pose, closed; the robot has not moved yet.
        outline = [m for m in markers.markers if m.ns == 'footprint']
        self.assertEqual(len(outline), 1)
        pts = outline[0].points
        self.assertEqual(len(pts), 49)
        self.assertEqual((pts[0].x, pts[0].y), (pts[-1].x, pts[-1].y))
        truth = self.truth.wait().pose.pose.position
        radius = rospy.get_param('/sim/world/robot/radius', rospy.get_param('/robot/radius'))  # the simulator's rule
        for p in pts:
            self.assertAlmostEqual(math.hypot(p.x - truth.x, p.y - truth.y), radius, delta=1e-6)
        elements = self.elements.wait()
        self.assertEqual(len(elements.elements), 12)
        self.assertTrue(all(e.kind.startswith('column') for e in elements.elements))
        # ~faults: beacon 1 silent from t=10 to t=12 (late enough for this node to listen).
        wait_sim(self.clock, 12.5)
        history = [(m.header.stamp.to_sec(), list(zip(m.kinds, m.targets))) for m in self.faults.since()]
        on = [t for t, f in history if ('beacon_silent', '1') in f]
        self.assertTrue(on, history)
        self.assertAlmostEqual(min(on), 10.0, delta=0.01)
        off_after = [t for t, f in history if t > min(on) and ('beacon_silent', '1') not in f]
        self.assertTrue(off_after, history)
        self.assertAlmostEqual(min(off_after), 12.0, delta=0.01)

    def test_3_teleport_and_opponent_placement(self):
        self.drive(0.0, 0.0)
        self.assertFalse(self.teleport(Pose2D(4.0, 1.0, 0.0)).ok)
        self.assertTrue(self.teleport(Pose2D(1.2, 0.9, 0.7)).ok)
        t = sim_now(self.clock)
        m = self.truth.wait(pred=lambda m: m.header.stamp.to_sec() > t + 0.05)
        self.assertAlmostEqual(m.pose.pose.position.x, 1.2, delta=1e-6)
        self.assertAlmostEqual(m.pose.pose.position.y, 0.9, delta=1e-6)
        self.assertAlmostEqual(yaw_of(m.pose.pose.orientation), 0.7, delta=1e-6)
        self.assertTrue(self.place(Pose2D(2.6, 0.4, 1.0), True).ok)
        t = sim_now(self.clock)
        wait_sim(self.clock, t + 2.0)
        o = self.opponent.wait()
        self.assertAlmostEqual(o.pose.pose.position.x, 2.6, delta=1e-6)  # held: the random walk waits
        self.assertAlmostEqual(o.pose.pose.position.y, 0.4, delta=1e-6)

    def test_4_injected_faults(self):
        r = self.inject(kind='wheel_fall_off')
        self.assertFalse(r.ok)
        self.assertIn('not a world fault', r.message)
        r = self.inject(kind='board_silent', target='no_such_board')
        self.assertFalse(r.ok)
        self.assertIn('not a running emulator', r.message)
        self.assertFalse(self.inject(kind='wheel_slip', target='caster').ok)
        self.assertTrue(self.inject(kind='beacon_silent', target='0').ok)
        self.assertTrue(self.inject(kind='beacon_silent', target='0', clear=True).ok)

        # A hard slip of the left wheel, scripted 1 s ahead for 1 s, turns a straight run left.
        self.assertTrue(self.place(Pose2D(2.7, 1.8, 0.0), True).ok)
        self.assertTrue(self.teleport(Pose2D(0.4, 0.5, 0.0)).ok)
        self.drive(0.25, 0.25)
        now = sim_now(self.clock)
        r = self.inject(kind='wheel_slip', target='left', start=now + 1.0, duration=1.0, magnitude=0.5)
        self.assertTrue(r.ok, r.message)
        self.assertEqual(r.message, 'scheduled')
        wait_sim(self.clock, now + 0.95)
        before = yaw_of(self.truth.wait().pose.pose.orientation)
        wait_sim(self.clock, now + 2.1)
        during = yaw_of(self.truth.wait().pose.pose.orientation)
        wait_sim(self.clock, now + 2.6)
        after = yaw_of(self.truth.wait().pose.pose.orientation)
        self.drive(0.0, 0.0)
        self.assertLess(abs(before), 0.02)
        self.assertGreater(during - before, 0.2)
        self.assertLess(abs(after - during), 0.05)  # over: straight again

        # The opponent blocks the path: it stands right in front of us, and we stop on it.
        self.assertTrue(self.place(Pose2D(2.7, 1.8, 0.0), False).ok)
        now = sim_now(self.clock)
        r = self.inject(kind='opponent_blocks', duration=2.0, magnitude=0.05)
        self.assertTrue(r.ok, r.message)
        wait_sim(self.clock, now + 0.2)
        us, them = self.truth.wait(), self.opponent.wait()
        dx = them.pose.pose.position.x - us.pose.pose.position.x
        dy = them.pose.pose.position.y - us.pose.pose.position.y
        self.assertAlmostEqual(math.hypot(dx, dy), 0.16 + 0.16 + 0.05, delta=0.02)
        self.drive(0.3, 0.3)
        wait_sim(self.clock, now + 1.5)
        us2 = self.truth.wait()
        self.drive(0.0, 0.0)
        self.assertAlmostEqual(us2.twist.twist.linear.x, 0.0, delta=1e-9)

    def test_5_start_cord_starts_the_match(self):
        m = self.match.wait()
        self.assertFalse(m.started)
        self.assertEqual(m.year, '2009')
        self.assertFalse(self.switch('no_such_switch', False).ok)
        self.assertTrue(self.switch('start_cord', False).ok)
        m = self.match.wait(pred=lambda m: m.started and m.elapsed > 0.5)
        self.assertIsNotNone(m)
        # One match length for the robot and the referee: the brain's (config brain/match/duration).
        self.assertAlmostEqual(m.elapsed + m.remaining, rospy.get_param('/brain/match/duration'), delta=1e-6)
        self.assertIsNotNone(self.score.wait())

    def test_6_a_bad_parameter_stops_the_simulator_with_one_line(self):
        env = dict(os.environ)
        p = subprocess.run(['rosrun', 'robot_sim', 'simulator', '__name:=bad_sim', '_real_time_factor:=-2'],
                           capture_output=True, text=True, timeout=30, env=env)
        self.assertNotEqual(p.returncode, 0)
        out = p.stdout + p.stderr
        self.assertIn('/bad_sim/real_time_factor', out)
        self.assertEqual(sum(1 for line in out.splitlines() if 'real_time_factor' in line), 1, out)

    def test_7_both_robot_configs_load(self):
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'config')
        for robot in ('eurobot2009', 'logion'):
            ns = '/config_check_' + robot
            for f in (robot + '.yaml', robot + '.sim.yaml'):
                subprocess.run(['rosparam', 'load', os.path.join(root, f), ns], check=True, timeout=30)
            env = dict(os.environ, ROSCONSOLE_STDOUT_LINE_BUFFERED='1')
            p = subprocess.Popen(['rosrun', 'robot_sim', 'simulator', '__ns:=' + ns, '__name:=sim',
                                  '_firmware_enabled:=false', '_real_time_factor:=1.0'],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                                 start_new_session=True)
            try:
                out, _ = p.communicate(timeout=5.0)  # a bad config exits at once
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGINT)
                out, _ = p.communicate(timeout=15.0)
            self.assertIn('simulator: seed', out, '%s: %s' % (robot, out))
            self.assertNotIn('FATAL', out, '%s: %s' % (robot, out))
            self.assertIn('game elements', out)

    def test_8_board_faults_reach_the_emulators(self):
        # A simulator of its own (namespace /fw_check) hosting one HBmotor emulator on a private bus.
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'config')
        ns = '/fw_check'
        for f in ('logion.yaml', 'logion.sim.yaml'):
            subprocess.run(['rosparam', 'load', os.path.join(root, f), ns], check=True, timeout=30)
        if rospy.has_param(ns + '/sim/firmware'):
            rospy.delete_param(ns + '/sim/firmware')
        rospy.set_param(ns + '/sim/firmware/motor_left', {
            'type': 'HBMotor', 'bus': 'sim:///tmp/robot_sim/test/world_%d/i2c-1' % os.getpid(), 'address': 16,
            'motor': 'left', 'encoder': 'left_driven'})
        env = dict(os.environ, ROSCONSOLE_STDOUT_LINE_BUFFERED='1')
        p = subprocess.Popen(['rosrun', 'robot_sim', 'simulator', '__ns:=' + ns, '__name:=sim'],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                             start_new_session=True)
        try:
            rospy.wait_for_service(ns + '/sim/inject_fault', timeout=20.0)
            inject = rospy.ServiceProxy(ns + '/sim/inject_fault', InjectFault)
            r = inject(kind='board_silent', target='motor_left')
            self.assertTrue(r.ok, r.message)
            self.assertTrue(inject(kind='board_silent', target='motor_left', clear=True).ok)
            r = inject(kind='can_bus_off', target='motor_left')
            self.assertFalse(r.ok)
            self.assertIn('does not emulate', r.message)
            r = inject(kind='board_silent', target='motor_right')
            self.assertFalse(r.ok)
            self.assertIn('motor_left', r.message)  # names the running emulators
        finally:
            os.killpg(p.pid, signal.SIGINT)
            out, _ = p.communicate(timeout=15.0)
        self.assertIn('emulating board motor_left (HBMotor)', out)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'sim_world_services', SimServicesTest)
