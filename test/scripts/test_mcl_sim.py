#!/usr/bin/env python3
"""Localization on the whole simulated 2009 robot (launch/mcl_sim_eurobot2009.test).

The test drives /hal/drive/cmd_vel itself (the product's drive effector, no driver), steering
each leg on the localization's own /mcl/pose as a robot does (on /odom while lost on purpose). Only this test reads /sim/*: every /mcl/pose is compared with /sim/ground_truth
interpolated at the pose's own stamp (sim time), so processing delay on a loaded machine does
not count as error, only a wrong estimate does.

  1. tracking from the known start over two laps of the table (~15 m, ~60 s simulated) with
     beacon 2 silenced for 10 s at the start of lap 2 (/sim/inject_fault beacon_silent): RMSE
     < 15 mm and max < 40 mm over the whole route (see RMSE_BOUND), never lost and within 40 mm
     while silenced, back to RMSE < 15 mm from 3 s after the beacon returns;
  2. ~global_localization (uniform cloud over the table) while driving: converged (within 30 mm
     and 3 deg, and staying there) in under 10 s simulated;
  3. kidnap (/sim/teleport 1 m away, heading turned by pi/2): the filter says so on /mcl/quality
     (lost, or probability < 0.5) within 5 s and recovers by itself in under 15 s simulated.

Figures (errors, convergence and recovery times, /mcl/pose rate, the device's cost per step
from /diagnostics, hal_node CPU from /proc) are printed, and written to ~figures (a file path)
when set: scripts/bench/mcl.sh reads them."""
import bisect
import math
import os
import threading
import time
import unittest
import xmlrpc.client

import rosgraph
import rospy
from robot_core.geometry import wrap_angle, yaw_of
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Pose2D, PoseWithCovarianceStamped, Twist
from hal_nodes.msg import BeaconRange, LocalizationQuality
from nav_msgs.msg import Odometry
from robot_sim.srv import InjectFault, Teleport
from std_srvs.srv import Empty
from test_support import percentile

# The synthetic runs' bounds are RMSE < 10 mm and max < 40 mm. In the whole simulation the
# emulated beacon timing noise alone (2e-5 s, 6.9 mm per range) is of the order of the synthetic
# RMSE bound already, so RMSE is held to 15 mm and the max to 40 mm: a filter lagging, lost or
# misled by a belt fails them.
RMSE_BOUND = 0.015       # [m]
MAX_BOUND = 0.040        # [m]
CONVERGED_XY = 0.030     # [m] global localization / kidnap: converged means within this
CONVERGED_TH = math.radians(3.0)
GLOBAL_LIMIT = 10.0      # [s simulated]
KIDNAP_DETECT_LIMIT = 5.0
KIDNAP_RECOVER_LIMIT = 15.0


class Record(object):
    """Everything the test compares, stamped in sim time."""

    def __init__(self):
        self.lock = threading.Lock()
        self.truth_t, self.truth = [], []  # /sim/ground_truth (test only)
        self.poses = []                    # (stamp, x, y, th) of /mcl/pose
        self.quality = []                  # (stamp, lost, probability)
        self.costs = []                    # (sim time, cost per step [ms]) from /diagnostics
        self.slips = None                  # the device's count of wheel slips, from /diagnostics
        self.odom = None
        self.beacon_stamps = {}            # beacon id -> stamps of its ranges (HAL beacons device)
        rospy.Subscriber('/sim/ground_truth', Odometry, self._truth, queue_size=200, tcp_nodelay=True)
        rospy.Subscriber('/mcl/pose', PoseWithCovarianceStamped, self._pose, queue_size=200, tcp_nodelay=True)
        rospy.Subscriber('/mcl/quality', LocalizationQuality, self._quality, queue_size=200, tcp_nodelay=True)
        rospy.Subscriber('/odom', Odometry, self._odom, queue_size=10, tcp_nodelay=True)
        rospy.Subscriber('/diagnostics', DiagnosticArray, self._diag, queue_size=50)
        rospy.Subscriber('/hal/beacons/ranges', BeaconRange, self._range, queue_size=100)

    def _range(self, m):
        with self.lock:
            self.beacon_stamps.setdefault(m.beacon_id, []).append(m.header.stamp.to_sec())

    def ranges_between(self, beacon_id, t0, t1):
        with self.lock:
            return sum(1 for t in self.beacon_stamps.get(beacon_id, []) if t0 <= t <= t1)

    def _truth(self, m):
        p = m.pose.pose
        with self.lock:
            self.truth_t.append(m.header.stamp.to_sec())
            self.truth.append((p.position.x, p.position.y, yaw_of(p.orientation)))

    def _pose(self, m):
        p = m.pose.pose
        with self.lock:
            self.poses.append((m.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation)))

    def _quality(self, m):
        with self.lock:
            self.quality.append((m.header.stamp.to_sec(), m.lost, m.probability))

    def _odom(self, m):
        with self.lock:
            self.odom = m.pose.pose

    def _diag(self, m):
        for s in m.status:
            if 'localization' not in s.name:
                continue
            for kv in s.values:
                if kv.key == 'cost per step [ms]':
                    with self.lock:
                        self.costs.append((rospy.get_time(), float(kv.value)))
                elif kv.key == 'wheel slips detected':
                    with self.lock:
                        self.slips = int(kv.value)

    def odom_pose(self):
        with self.lock:
            o = self.odom
        return (o.position.x, o.position.y, yaw_of(o.orientation)) if o else None

    def truth_at(self, t):
        """Ground truth interpolated at sim time t (None outside the recorded span)."""
        with self.lock:
            i = bisect.bisect_left(self.truth_t, t)
            if i == 0 or i >= len(self.truth_t):
                return None
            t0, t1 = self.truth_t[i - 1], self.truth_t[i]
            a, b = self.truth[i - 1], self.truth[i]
        f = (t - t0) / (t1 - t0) if t1 > t0 else 0.0
        return (a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), wrap_angle(a[2] + f * wrap_angle(b[2] - a[2])))

    def latest_truth(self):
        with self.lock:
            return (self.truth_t[-1],) + self.truth[-1] if self.truth else None

    def errors(self, t0, t1):
        """(stamp, position error, heading error) of every estimate stamped in [t0, t1]."""
        with self.lock:
            poses = [p for p in self.poses if t0 <= p[0] <= t1]
        out = []
        for t, x, y, th in poses:
            tr = self.truth_at(t)
            if tr is not None:
                out.append((t, math.hypot(x - tr[0], y - tr[1]), abs(wrap_angle(th - tr[2]))))
        return out

    def count_poses(self, t0, t1):
        with self.lock:
            return sum(1 for p in self.poses if t0 <= p[0] <= t1)

    def quality_between(self, t0, t1):
        with self.lock:
            return [q for q in self.quality if t0 <= q[0] <= t1]


def settled_time(errors, xy, th):
    """Stamp from which every estimate stays within (xy, th); None if the last one is not."""
    t_ok = None
    for t, e, eth in errors:
        if e <= xy and eth <= th:
            if t_ok is None:
                t_ok = t
        else:
            t_ok = None
    return t_ok


def process_cpu_seconds(pid):
    with open('/proc/%d/stat' % pid) as f:
        fields = f.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')  # utime + stime


def node_pid(name):
    uri = rosgraph.Master('/test_mcl_sim').lookupNode(name)
    return xmlrpc.client.ServerProxy(uri).getPid('/test_mcl_sim')[2]


class McLSimTest(unittest.TestCase):
    figures = {}

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_mcl_sim')
        cls.rec = Record()
        cls.cmd = rospy.Publisher('/hal/drive/cmd_vel', Twist, queue_size=1)
        deadline = time.monotonic() + 120.0  # wall: the whole stack starting on a loaded machine
        while time.monotonic() < deadline and not (cls.rec.odom_pose() and cls.rec.latest_truth() and
                                                   cls.rec.count_poses(0.0, 1e9) > 20):
            time.sleep(0.2)
        try:
            cls.hal_pid = node_pid('/hal')
        except Exception as e:  # figures only: the test itself does not need it
            rospy.logwarn('no pid for /hal: %s', e)
            cls.hal_pid = None

    @classmethod
    def tearDownClass(cls):
        lines = ['%s %s' % (k, v) for k, v in sorted(cls.figures.items())]
        print('\n'.join(['mcl_sim figures:'] + lines))
        path = rospy.get_param('~figures', '')
        if path:
            with open(path, 'w') as f:
                f.write('\n'.join(lines) + '\n')

    # ---------------------------------------------------------------- driving on /odom
    def drive(self, v, w):
        t = Twist()
        t.linear.x, t.angular.z = v, w
        self.cmd.publish(t)

    def pause(self, seconds):
        """Stand still for a simulated duration, the drive effector kept fed (cmd_timeout)."""
        end = rospy.get_time() + seconds
        while not rospy.is_shutdown() and rospy.get_time() < end:
            self.drive(0.0, 0.0)
            rospy.sleep(0.05)

    def estimate(self):
        with self.rec.lock:
            return self.rec.poses[-1][1:] if self.rec.poses else None

    def goto(self, x, y, speed=0.4, anchor=None):
        """Turn towards (x, y), then drive there steering on the way, as a robot does on its
        own estimate (/mcl/pose), so the route stays clear of the borders whatever odometry
        drift. While the estimate is not to be trusted (lost on purpose), anchor = (a known
        map pose, the /odom pose at that moment) and the leg is followed on /odom."""
        pose = self.rec.odom_pose if anchor else self.estimate
        if anchor:  # the target in the odom frame
            (ex, ey, eth), (ox, oy, oth) = anchor
            c, s_ = math.cos(oth - eth), math.sin(oth - eth)
            dx, dy = x - ex, y - ey
            x, y = ox + c * dx - s_ * dy, oy + s_ * dx + c * dy
        px, py, _ = pose()
        self.turn_to(math.atan2(y - py, x - px), pose)
        v, t_prev = 0.0, rospy.get_time()
        end = t_prev + math.hypot(x - px, y - py) / 0.1 + 5.0  # a leg that never ends fails the route, not the run
        while not rospy.is_shutdown() and rospy.get_time() < end:
            px, py, pth = pose()
            left = math.hypot(x - px, y - py)
            if left < 0.01:
                break
            now = rospy.get_time()
            v = min(min(speed, max(0.08, 1.2 * left)), v + 1.0 * (now - t_prev))  # 1 m/s^2: little slip
            t_prev = now
            w = 2.0 * wrap_angle(math.atan2(y - py, x - px) - pth) if left > 0.05 else 0.0
            self.drive(v, max(-1.0, min(1.0, w)))
            rospy.sleep(0.02)
        self.pause(0.3)

    def turn_to(self, heading, pose):
        end = rospy.get_time() + 10.0
        while not rospy.is_shutdown() and rospy.get_time() < end:
            err = wrap_angle(heading - pose()[2])
            if abs(err) < 0.03:
                break
            self.drive(0.0, max(-1.5, min(1.5, 2.0 * err + math.copysign(0.4, err))))
            rospy.sleep(0.02)
        self.pause(0.2)

    def lap(self):
        """Round the table clear of the columns and 0.12 m or more from the borders."""
        for x, y in ((2.6, 1.7), (2.6, 0.29), (0.4, 0.29), (0.4, 1.7)):
            self.goto(x, y)

    # ---------------------------------------------------------------- tests
    def test_1_tracking_route_with_a_beacon_silenced(self):
        self.assertIsNotNone(self.rec.odom_pose(), 'no /odom from the HAL')
        self.assertIsNotNone(self.rec.latest_truth(), 'no /sim/ground_truth')
        self.assertGreater(self.rec.count_poses(0.0, 1e9), 20, 'no /mcl/pose from the localization')
        start_truth = self.rec.latest_truth()
        t_start = rospy.get_time()
        wall0 = time.monotonic()
        cpu0 = process_cpu_seconds(self.hal_pid) if self.hal_pid else None

        self.lap()  # from the start pose (0.25, 1.80)
        inject = rospy.ServiceProxy('/sim/inject_fault', InjectFault)
        res = inject(kind='beacon_silent', target='2', start=0.0, duration=10.0, magnitude=0.0, clear=False)
        self.assertTrue(res.ok, res.message)
        t_silent = rospy.get_time()
        self.lap()
        t_end = rospy.get_time()

        wall = time.monotonic() - wall0
        errs = self.rec.errors(t_start, t_end)
        self.assertGreater(len(errs), 10 * (t_end - t_start), 'too few /mcl/pose over the route')
        rmse = math.sqrt(sum(e * e for _, e, _ in errs) / len(errs))
        worst = max(errs, key=lambda r: r[1])
        heading_rmse = math.degrees(math.sqrt(sum(h * h for _, _, h in errs) / len(errs)))
        silent = [r for r in errs if t_silent <= r[0] <= t_silent + 10.0]
        back = [r for r in errs if t_silent + 13.0 <= r[0] <= t_end]
        back_rmse = math.sqrt(sum(e * e for _, e, _ in back) / max(1, len(back)))
        lost_while_silent = [q for q in self.rec.quality_between(t_silent, t_silent + 10.0) if q[1]]
        end_truth = self.rec.latest_truth()
        dist = self.route_length(t_start, t_end)
        f = McLSimTest.figures
        f['track_route_m'] = '%.2f' % dist
        f['track_lost_flags'] = str(sum(1 for q in self.rec.quality_between(t_start, t_end) if q[1]))
        f['track_duration_s'] = '%.1f' % (t_end - t_start)
        f['track_rmse_mm'] = '%.1f' % (1e3 * rmse)
        f['track_max_mm'] = '%.1f' % (1e3 * worst[1])
        f['track_max_at_s'] = '%.1f' % (worst[0] - t_start)
        f['track_heading_rmse_deg'] = '%.2f' % heading_rmse
        f['track_heading_max_deg'] = '%.2f' % math.degrees(max(h for _, _, h in errs))
        f['track_pose_rate_hz'] = '%.1f' % (len(errs) / (t_end - t_start))
        f['silenced_max_mm'] = '%.1f' % (1e3 * max(e for _, e, _ in silent))
        f['silenced_back_max_mm'] = '%.1f' % (1e3 * max(e for _, e, _ in back))
        f['silenced_back_rmse_mm'] = '%.1f' % (1e3 * back_rmse)
        dump = rospy.get_param('~dump', '')
        if dump:  # for analysis: every estimate's error over the route
            with open(dump, 'w') as out:
                for t, e, h in errs:
                    tr = self.rec.truth_at(t)
                    out.write('%.3f %.4f %.4f %.3f %.3f %.3f\n' % (t - t_start, e, h, tr[0], tr[1], tr[2]))
        f['real_time_factor_achieved'] = '%.2f' % ((t_end - t_start) / wall)
        costs = [c for t, c in self.rec.costs if t_start <= t <= t_end and c > 0.0]
        if costs:
            f['cost_per_step_ms_p50'] = '%.3f' % percentile(costs, 50)
            f['cost_per_step_ms_p90'] = '%.3f' % percentile(costs, 90)
            f['cost_per_step_ms_p99'] = '%.3f' % percentile(costs, 99)
            f['cost_per_step_ms_max'] = '%.3f' % max(costs)
            f['cost_samples'] = str(len(costs))
        if self.rec.slips is not None:
            f['wheel_slips_detected'] = str(self.rec.slips)  # since the device started
        if cpu0 is not None:
            f['hal_node_cpu_percent'] = '%.1f' % (100.0 * (process_cpu_seconds(self.hal_pid) - cpu0) / wall)
        print('tracking: %.2f m in %.1f s from (%.2f, %.2f) to (%.2f, %.2f): RMSE %.1f mm, max %.1f mm at +%.1f s, '
              'heading RMSE %.2f deg; beacon 2 silenced: max %.1f mm, %d lost flags; 3 s after: max %.1f mm' % (
                  dist, t_end - t_start, start_truth[1], start_truth[2], end_truth[1], end_truth[2], 1e3 * rmse,
                  1e3 * worst[1], worst[0] - t_start, heading_rmse, 1e3 * max(e for _, e, _ in silent),
                  len(lost_while_silent), 1e3 * max(e for _, e, _ in back)))
        self.assertGreater(dist, 13.0, 'the route was not driven')
        self.assertGreater(len(silent), 100, 'too few estimates while the beacon was silent')
        self.assertLess(rmse, RMSE_BOUND)
        self.assertLess(worst[1], MAX_BOUND)
        self.assertEqual(lost_while_silent, [], 'lost while one beacon was silent')
        # the fault really silenced beacon 2 (and only for its 10 s): ranges stop, then come back
        self.assertEqual(self.rec.ranges_between(2, t_silent + 0.5, t_silent + 9.5), 0, 'beacon 2 was not silenced')
        self.assertGreater(self.rec.ranges_between(2, t_silent + 11.0, t_end), 10, 'beacon 2 did not come back')
        self.assertLess(max(e for _, e, _ in silent), MAX_BOUND)
        self.assertGreater(len(back), 50)
        self.assertLess(back_rmse, RMSE_BOUND, 'not back to tracking accuracy 3 s after the beacon returned')

    def route_length(self, t0, t1):
        with self.rec.lock:
            pts = [p for t, p in zip(self.rec.truth_t, self.rec.truth) if t0 <= t <= t1]
        return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(pts, pts[1:]))

    def test_2_global_localization_converges(self):
        rospy.wait_for_service('/hal/localization/global_localization', 10.0)
        anchor = (self.estimate(), self.rec.odom_pose())  # about (0.4, 1.7) after the route
        t_call = rospy.get_time()
        rospy.ServiceProxy('/hal/localization/global_localization', Empty)()
        self.goto(1.2, 1.7, anchor=anchor)
        self.goto(1.2, 1.45, anchor=anchor)
        self.pause(max(0.0, t_call + GLOBAL_LIMIT + 1.0 - rospy.get_time()))
        errs = self.rec.errors(t_call + 1e-3, rospy.get_time())
        lost = [q for q in self.rec.quality_between(t_call, t_call + 1.0) if q[1]]
        t_conv = settled_time(errs, CONVERGED_XY, CONVERGED_TH)
        McLSimTest.figures['global_converged_s'] = '%.2f' % (t_conv - t_call) if t_conv else 'never'
        print('global localization: converged (%.0f mm, %.0f deg) after %s s simulated; lost flagged: %s' % (
            1e3 * CONVERGED_XY, math.degrees(CONVERGED_TH),
            '%.2f' % (t_conv - t_call) if t_conv else 'never', bool(lost)))
        self.assertTrue(lost, 'the uniform cloud was not reported as lost on /mcl/quality')
        self.assertIsNotNone(t_conv, 'not converged')
        self.assertLess(t_conv - t_call, GLOBAL_LIMIT)

    def test_3_kidnap_detected_and_recovered(self):
        # From about (1.2, 1.45) heading south: carried 1 m east and turned to face west.
        before = self.rec.latest_truth()
        self.pause(0.5)
        t_kid = rospy.get_time()
        res = rospy.ServiceProxy('/sim/teleport', Teleport)(pose=Pose2D(x=2.2, y=1.5, theta=math.pi))
        self.assertTrue(res.ok, res.message)
        rospy.sleep(0.2)
        anchor = ((2.2, 1.5, math.pi), self.rec.odom_pose())  # where the test put it: drives on /odom
        self.pause(0.8)
        self.goto(1.6, 1.5, anchor=anchor)
        self.goto(1.6, 1.75, anchor=anchor)
        self.pause(max(0.0, t_kid + KIDNAP_RECOVER_LIMIT + 1.0 - rospy.get_time()))
        flagged = [q for q in self.rec.quality_between(t_kid, t_kid + KIDNAP_DETECT_LIMIT) if q[1] or q[2] < 0.5]
        errs = self.rec.errors(t_kid + 0.1, rospy.get_time())
        t_rec = settled_time(errs, CONVERGED_XY, CONVERGED_TH)
        f = McLSimTest.figures
        f['kidnap_detected_s'] = '%.2f' % (flagged[0][0] - t_kid) if flagged else 'never'
        f['kidnap_recovered_s'] = '%.2f' % (t_rec - t_kid) if t_rec else 'never'
        print('kidnap from (%.2f, %.2f) to (2.20, 1.50): detected after %s s, recovered after %s s simulated' % (
            before[1], before[2], f['kidnap_detected_s'], f['kidnap_recovered_s']))
        self.assertTrue(flagged, 'the kidnap was not reported on /mcl/quality (lost or probability < 0.5)')
        self.assertIsNotNone(t_rec, 'not recovered')
        self.assertLess(t_rec - t_kid, KIDNAP_RECOVER_LIMIT)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_mcl_sim', McLSimTest)
