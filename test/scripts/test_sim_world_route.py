#!/usr/bin/env python3
"""The simulated world under a scripted route of direct motor commands (launch/sim_world_route.test).

Three simulators run side by side: a (real-time factor 1, seed 7), b (factor 4, seed 7) and
c (factor 4, seed 8). Each gets the same timed route on <ns>/sim/debug/motor_command while
paused, then runs. The ground truth must follow the route integrated here independently
(first-order motor lag with acceleration and current limits, no slip), a and b must be
identical sample by sample, and c must differ (its slip noise differs)."""
import math
import threading
import time
import unittest

import rospy
from robot_core.config_tree import simulated_robot
from robot_core.geometry import wrap_angle, yaw_of
import rostest
from nav_msgs.msg import Odometry
from robot_sim.msg import DebugMotorCommand
from std_srvs.srv import SetBool

NAMESPACES = ('a', 'b', 'c')
# (simulated time [s], left, right): straight, turn right on the spot, arc, stop (clear of
# the borders from the eurobot2009 start pose).
ROUTE = [(0.5, 0.3, 0.3), (2.5, 0.2, -0.2), (3.5, 0.35, 0.25), (5.0, 0.0, 0.0)]
END = 6.0
POS_TOL = 0.02   # [m] slip noise and the step grid, not model error
YAW_TOL = 0.03   # [rad]


class Motor(object):
    """The motor as documented in config (first-order lag, acceleration and current limits)."""

    def __init__(self, p):
        self.p = p
        self.speed = 0.0

    def step(self, u, dt):
        p = self.p
        back = self.speed / p['max_speed']
        margin = p['current_limit'] / p['stall_current']
        u_eff = back + max(-margin, min(margin, u - back))
        target = u_eff * p['max_speed']
        nxt = target + (self.speed - target) * math.exp(-dt / p['time_constant'])
        dv = p['max_accel'] * dt
        self.speed = max(self.speed - dv, min(self.speed + dv, nxt))
        return self.speed


def integrate_route(world, until):
    """Expected poses keyed by step index, integrated independently of the simulator."""
    robot = world['robot']
    dt = world['dt']
    r, b = robot['wheel_radius'], robot['wheel_base']
    motors = robot['motors']
    left, right = Motor(motors['left']), Motor(motors['right'])
    x, y, th = robot['start']
    cmd = (0.0, 0.0)
    out = {}
    route = list(ROUTE)
    for k in range(1, int(round(until / dt)) + 1):
        t = k * dt
        while route and route[0][0] <= t + 1e-9:
            cmd = route.pop(0)[1:]
        vl = left.step(cmd[0], dt) * r
        vr = right.step(cmd[1], dt) * r
        v, w = 0.5 * (vl + vr), (vr - vl) / b
        if abs(w * dt) < 1e-9:
            x += v * dt * math.cos(th + 0.5 * w * dt)
            y += v * dt * math.sin(th + 0.5 * w * dt)
        else:
            x += v / w * (math.sin(th + w * dt) - math.sin(th))
            y -= v / w * (math.cos(th + w * dt) - math.cos(th))
        th = wrap_angle(th + w * dt)
        out[k] = (x, y, th)
    return out


class Truth(object):
    def __init__(self, ns):
        self.lock = threading.Lock()
        self.samples = {}  # stamp in ns -> (x, y, yaw)
        self.wall_at = {}  # first wall time each simulated second was seen
        self.sub = rospy.Subscriber('/%s/sim/ground_truth' % ns, Odometry, self._cb, queue_size=1000)

    def _cb(self, m):
        with self.lock:
            self.samples[m.header.stamp.to_nsec()] = (m.pose.pose.position.x, m.pose.pose.position.y,
                                                      yaw_of(m.pose.pose.orientation))
            sec = int(m.header.stamp.to_sec())
            self.wall_at.setdefault(sec, time.monotonic())

    def latest(self):
        with self.lock:
            return max(self.samples) * 1e-9 if self.samples else 0.0


class SimWorldRouteTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_sim_world_route')
        cls.truth = {ns: Truth(ns) for ns in NAMESPACES}
        pubs = {ns: rospy.Publisher('/%s/sim/debug/motor_command' % ns, DebugMotorCommand, queue_size=20)
                for ns in NAMESPACES}
        for ns in NAMESPACES:
            rospy.wait_for_service('/%s/sim/pause' % ns, timeout=20.0)
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline and not all(p.get_num_connections() for p in pubs.values()):
            time.sleep(0.05)
        time.sleep(0.5)
        for ns, pub in pubs.items():
            for at, left, right in ROUTE:
                pub.publish(DebugMotorCommand(at=at, motors=['left', 'right'], fractions=[left, right]))
        time.sleep(0.5)  # delivered before the clock runs
        cls.wall_start = time.monotonic()
        for ns in NAMESPACES:
            rospy.ServiceProxy('/%s/sim/pause' % ns, SetBool)(False)
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline and min(t.latest() for t in cls.truth.values()) < END:
            time.sleep(0.1)
        cls.world = rospy.get_param('/a/sim/world')
        # the simulated robot as the simulator reads it: its geometry from the description /a/robot
        cls.world['robot'] = simulated_robot({'robot': rospy.get_param('/a/robot'), 'sim': {'world': cls.world}})
        cls.expected = integrate_route(cls.world, END + 0.5)

    def test_1_every_simulator_reached_the_end(self):
        for ns, t in self.truth.items():
            self.assertGreaterEqual(t.latest(), END, '%s stopped at %.2f s' % (ns, t.latest()))

    def test_2_ground_truth_follows_the_integrated_command(self):
        dt = self.world['dt']
        for ns, t in self.truth.items():
            with t.lock:
                samples = dict(t.samples)
            checked = 0
            worst_pos = worst_yaw = 0.0
            for stamp, (x, y, th) in samples.items():
                k = int(round(stamp * 1e-9 / dt))
                if k not in self.expected:
                    continue
                ex, ey, eth = self.expected[k]
                worst_pos = max(worst_pos, math.hypot(x - ex, y - ey))
                worst_yaw = max(worst_yaw, abs(wrap_angle(th - eth)))
                checked += 1
            self.assertGreater(checked, 250, ns)
            self.assertLess(worst_pos, POS_TOL, '%s: position off by %.4f m' % (ns, worst_pos))
            self.assertLess(worst_yaw, YAW_TOL, '%s: yaw off by %.4f rad' % (ns, worst_yaw))
        # The route really moved and turned the robot.
        x0, y0, _ = self.expected[1]
        xe, ye, the = self.expected[int(round(END / dt))]
        self.assertGreater(math.hypot(xe - x0, ye - y0), 0.5)
        self.assertGreater(abs(wrap_angle(the - self.world['robot']['start'][2])), 0.5)

    def test_3_same_seed_same_trajectory_at_any_real_time_factor(self):
        a, b, c = (self.truth[ns].samples for ns in NAMESPACES)
        common = sorted(set(a) & set(b))
        self.assertGreater(len(common), 250)
        for s in common:
            self.assertEqual(a[s], b[s], 'a and b differ at t=%.3f' % (s * 1e-9))
        other = sorted(set(a) & set(c))
        self.assertGreater(max(abs(a[s][0] - c[s][0]) + abs(a[s][1] - c[s][1]) for s in other), 1e-7,
                           'a different seed gave the identical trajectory')

    def test_4_real_time_factor_paces_the_clock(self):
        a, b = self.truth['a'].wall_at, self.truth['b'].wall_at
        wall_a = a[5] - a[1]  # 4 simulated seconds
        wall_b = b[5] - b[1]
        self.assertAlmostEqual(wall_a, 4.0, delta=0.6)
        self.assertAlmostEqual(wall_b, 1.0, delta=0.4)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'sim_world_route', SimWorldRouteTest)
