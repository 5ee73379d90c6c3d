#!/usr/bin/env python3
"""HCL + HAL of a robot against the simulator: odometry vs /sim/ground_truth over a 10 m
route, beacon ranges vs true distances, /effectors/deactivate latency at the motors, and where
the robot has them, compass headings and ranger readings vs the emulators' truth. Launched as fast
as the machine goes (everything but the deactivation is judged in simulated time); the
deactivation runs at real time (test_support.real_time).

Private parameters (robot specific, from the .test file):
  ~motor_check     can_bus: the motor board's zero command frame on the CAN-over-UDP bus
                   (/hcl/motor_board/*); hbmotor: the HBmotor boards' read-back duty (~motor_states)
  ~motor_states    HBMotorState topics (hbmotor)
  ~compass_truth   the compass emulator's truth topic (std_msgs/Float64 [deg]), empty: no compass
  ~rangers         {HAL ranger name: the SRF02 emulator's truth topic (std_msgs/Float64 [m])}"""
import contextlib
import math
import socket
import struct
import threading
import time
import unittest

import rospy
from robot_core.geometry import wrap_angle, yaw_of
import rostest
from geometry_msgs.msg import Twist
from hal_nodes.msg import BeaconRange
from hal_nodes.msg import Heading
from hcl_drivers.msg import HBMotorState, MotorBoardState
from sensor_msgs.msg import Range
from std_msgs.msg import Float64
from nav_msgs.msg import Odometry

from test_support import DeviceDiagnostics, EffectorSwitch, Latest, is_active, real_time, wait_for


def median(values):
    values = sorted(values)
    return values[len(values) // 2] if values else float('nan')


class CanBusListener(object):
    """A participant of the CAN-over-UDP bus (hcl_drivers/transport/udp_can_bus.h) that keeps
    every frame with the kernel's receive time (SO_TIMESTAMPNS, wall clock): the moment the hub
    forwarded it, as the board emulators get it, whatever this process's threads are doing."""
    SO_TIMESTAMPNS = 35

    def __init__(self, url):
        host, port = url.replace('udp://', '').split(':')
        self.hub = (host, int(port))
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(('127.0.0.1', 0))
        self.sock.setsockopt(socket.SOL_SOCKET, self.SO_TIMESTAMPNS, 1)
        self.sock.settimeout(0.05)
        self.lock = threading.Lock()
        self.frames = []  # (kernel receive time [s, wall], id, flags, data)
        self.running = True
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        next_hello = 0.0
        while self.running:
            if time.monotonic() >= next_hello:  # keepalive: the hub forgets silent peers after 2 s
                self.sock.sendto(b'CN' + bytes([2]) + bytes(14), self.hub)
                next_hello = time.monotonic() + 0.2
            try:
                d, anc, _, _ = self.sock.recvmsg(64, 64)
            except (socket.timeout, OSError):
                continue
            if len(d) != 17 or d[:2] != b'CN' or d[2] != 1:
                continue
            stamp = time.time()
            for level, kind, data in anc:
                if level == socket.SOL_SOCKET and kind == self.SO_TIMESTAMPNS:
                    sec, nsec = struct.unpack('qq', data[:16])
                    stamp = sec + 1e-9 * nsec
            with self.lock:
                self.frames.append((stamp, struct.unpack('<I', d[4:8])[0], d[3], d[9:9 + d[8]]))

    def data_frames(self, can_id, since):
        with self.lock:
            return [(t, data) for t, i, flags, data in self.frames if i == can_id and not flags & 1 and t >= since]

    def close(self):
        self.running = False


class HalSimTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_hal_sim')
        cls.start = rospy.get_param('/sim/world/robot/start')  # odom starts where the robot stood
        cls.truth = Latest('/sim/ground_truth', Odometry, queue_size=200)
        cls.odom = Latest('/odom', Odometry, queue_size=200)
        cls.cmd = rospy.Publisher('/hal/drive/cmd_vel', Twist, queue_size=1)
        cls.diag = DeviceDiagnostics()
        cls.effectors = EffectorSwitch(60.0)
        t0 = time.monotonic()
        assert cls.diag.wait_for('hal/drive:', is_active, 30.0, since=t0), 'the drive is not active'
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline and not (cls.truth.get() and cls.odom.get()):
            time.sleep(0.1)

    def odom_in_map(self):
        """The odometry pose composed with the start pose (odom starts where the robot stood)."""
        o = self.odom.get().pose.pose
        x0, y0, t0 = self.start
        c, s = math.cos(t0), math.sin(t0)
        return (x0 + c * o.position.x - s * o.position.y, y0 + s * o.position.x + c * o.position.y,
                wrap_angle(t0 + yaw_of(o.orientation)))

    def drive(self, v, w):
        t = Twist()
        t.linear.x, t.angular.z = v, w
        self.cmd.publish(t)

    def truth_pose(self):
        p = self.truth.get().pose.pose
        return '(%.3f, %.3f, %.2f)' % (p.position.x, p.position.y, yaw_of(p.orientation))

    def odom_yaw(self):
        return yaw_of(self.odom.get().pose.pose.orientation)

    def settle(self, timeout=2.0):
        """Stop and wait (bounded) until the odometry says the robot stands still: the motors
        lag the command (the next leg starts from rest, a turn does not coast into it)."""
        self.drive(0.0, 0.0)
        t0 = time.monotonic()
        rospy.sleep(0.1)
        still = wait_for(lambda: abs(self.odom.get().twist.twist.linear.x) < 0.005 and
                         abs(self.odom.get().twist.twist.angular.z) < 0.02, timeout, 0.02)
        if not still:
            print('settle: the robot did not stand still within %.1f s' % timeout)
        return time.monotonic() - t0

    def straight(self, dist, heading, speed=0.35):
        """Drive dist [m] holding the absolute odometry heading [rad] of the route's leg."""
        t_leg = time.monotonic()
        o0 = self.odom.get().pose.pose.position
        v = 0.0
        done = 0.0
        deadline = time.monotonic() + 20.0  # a leg that never ends fails the route, not the test run
        while not rospy.is_shutdown() and time.monotonic() < deadline:
            o = self.odom.get().pose.pose
            done = math.hypot(o.position.x - o0.x, o.position.y - o0.y)
            if done >= dist - 0.005:
                break
            target = min(speed, max(0.12, 1.5 * (dist - done)))
            v = min(target, v + 0.02)  # ~1 m/s^2 at 50 Hz: gentle, little slip
            self.drive(v, 2.0 * wrap_angle(heading - yaw_of(o.orientation)))
            rospy.sleep(0.02)
        settled = self.settle()
        print('leg %.2f m: %.1f s wall (%.1f s to stand still), %.3f m by odometry, truth %s' %
              (dist, time.monotonic() - t_leg, settled, done, self.truth_pose()))

    def turn(self, heading):
        """Turn in place to the absolute odometry heading [rad]; the motors lag, so the
        robot coasts past the point where the command stops: correct until it stands at it."""
        t_leg = time.monotonic()
        settled = 0.0
        for _ in range(3):
            deadline = time.monotonic() + 15.0
            while not rospy.is_shutdown() and time.monotonic() < deadline:
                err = wrap_angle(heading - self.odom_yaw())
                coast = 0.12 * self.odom.get().twist.twist.angular.z  # [rad] turned after the stop command
                if abs(err) < 0.02 or abs(err - coast) < 0.02 or (err - coast) * err < 0:
                    break
                self.drive(0.0, max(-1.5, min(1.5, 2.0 * err + math.copysign(0.6, err))))
                rospy.sleep(0.02)
            settled += self.settle()
            if abs(wrap_angle(heading - self.odom_yaw())) < 0.03:
                break
        print('turn to %.2f rad: %.1f s wall (%.1f s to stand still), odometry %.3f rad, truth %s' %
              (heading, time.monotonic() - t_leg, settled, self.odom_yaw(), self.truth_pose()))

    def test_1_odometry_over_a_10m_route(self):
        self.assertIsNotNone(self.odom.get(), 'no /odom from the HAL')
        self.assertIsNotNone(self.truth.get(), 'no /sim/ground_truth')
        # Two rectangle laps inside the table: 2 x (1.8 + 0.9 + 1.8 + 0.9) = 10.8 m.
        truth_path = [0.0]
        last = [None]

        def on_truth(m):
            p = m.pose.pose.position
            if last[0] is not None:
                truth_path[0] += math.hypot(p.x - last[0][0], p.y - last[0][1])
            last[0] = (p.x, p.y)
        sub = rospy.Subscriber('/sim/ground_truth', Odometry, on_truth, queue_size=100)
        t_route = time.monotonic()
        heading = self.odom_yaw()
        for _ in range(2):
            for leg in (1.8, 0.9, 1.8, 0.9):
                self.straight(leg, heading)
                heading = wrap_angle(heading - math.pi / 2)
                self.turn(heading)
        print('route: %.1f s wall' % (time.monotonic() - t_route))
        sub.unregister()
        rospy.sleep(0.5)
        est = self.odom_in_map()
        tp = self.truth.get().pose.pose
        err = math.hypot(est[0] - tp.position.x, est[1] - tp.position.y)
        dist = truth_path[0]
        print('odometry route: %.2f m travelled, position error %.3f m (%.2f %%), heading error %.3f rad' %
              (dist, err, 100.0 * err / dist, wrap_angle(est[2] - yaw_of(tp.orientation))))
        self.assertGreater(dist, 10.0)
        self.assertLess(err, 0.02 * dist)
        cov = self.odom.get().pose.covariance
        self.assertGreater(cov[0] + cov[7], 0.0)

    def test_2_standing_still_readings_match_the_sim(self):
        """Beacon ranges vs the true distances; compass and rangers (where the robot has them)
        vs what the emulated modules measured. One window: the robot stands still."""
        compass_truth = rospy.get_param('~compass_truth', '')
        rangers = rospy.get_param('~rangers', {})
        beacons = rospy.get_param('/table/beacons')
        ranges = Latest('/hal/beacons/ranges', BeaconRange, keep=True, queue_size=200)
        heading = Latest('/hal/compass/heading', Heading, keep=True, queue_size=200) if compass_truth else None
        bearing = Latest(compass_truth, Float64, keep=True, queue_size=200) if compass_truth else None
        hal = {n: Latest('/hal/rangers/' + n, Range, keep=True, queue_size=200) for n in rangers}
        truth = {n: Latest(t, Float64, keep=True, queue_size=200) for n, t in rangers.items()}
        t0 = time.monotonic()
        rospy.sleep(4.0)  # simulated: the same number of readings at any real-time factor
        tp = self.truth.get().pose.pose
        self.check_beacons([m for t, m in ranges.items if t >= t0], beacons, tp.position)
        if compass_truth:
            self.check_compass(heading, bearing, yaw_of(tp.orientation))
        if rangers:
            self.check_rangers(hal, truth)

    def check_beacons(self, got, beacons, tp):
        self.assertGreater(len(got), 20, 'too few beacon ranges')
        errors = []
        for m in got:
            bx, by = beacons[m.beacon_id]
            errors.append(m.range - math.hypot(bx - tp.x, by - tp.y))
        errors.sort()
        median = errors[len(errors) // 2]
        inliers = [e for e in errors if abs(e) < 0.05]
        print('beacons: %d ranges, median error %.4f m, %d within 5 cm' % (len(got), median, len(inliers)))
        self.assertLess(abs(median), 0.02)
        self.assertGreater(len(inliers), 0.9 * len(got))

    def check_compass(self, heading, bearing, true_yaw):
        # Each side samples its own noise: compare medians over the window.
        north = rospy.get_param('/hal/compass/north_yaw')
        sign = -1.0 if rospy.get_param('/hal/compass/mounting_clockwise', False) else 1.0
        hal_yaw = [m.yaw for _, m in heading.items]
        emu_yaw = [wrap_angle(north + sign * math.radians(m.data)) for _, m in bearing.items]
        self.assertGreater(len(hal_yaw), 20, 'too few headings')
        e_emu = wrap_angle(median(hal_yaw) - median(emu_yaw))
        e_true = wrap_angle(median(hal_yaw) - true_yaw)
        print('compass: %d headings, median vs the emulated module %.4f rad, vs the true yaw %.3f rad' %
              (len(hal_yaw), e_emu, e_true))
        self.assertLess(abs(e_emu), 0.02)  # the HAL's conversion of what the module measured
        self.assertLess(abs(e_true), 0.15)  # the module's bias (sim: 4 deg) and noise, nothing more

    def check_rangers(self, hal, truth):
        compared = 0
        for n in hal:
            t_med = median([m.data for _, m in truth[n].items])
            h = [m.range for _, m in hal[n].items if math.isfinite(m.range)]
            if not 0.2 < t_med < 5.0:  # no echo, or too close for an SRF02: nothing to compare
                print('ranger %s: true distance %.3f m, not compared' % (n, t_med))
                continue
            self.assertGreater(len(h), 10, 'too few readings of ranger ' + n)
            print('ranger %s: %d readings, median %.3f m vs the emulator\'s %.3f m' % (n, len(h), median(h), t_med))
            self.assertLess(abs(median(h) - t_med), 0.05)
            compared += 1
        self.assertGreater(compared, 0, 'no ranger saw anything to compare')

    @contextlib.contextmanager
    def driving(self, v):
        """Keep commanding v [m/s] straight ahead (as the brain would) inside the block."""
        stop = threading.Event()

        def keep_driving():
            while not stop.is_set():
                self.drive(v, 0.0)
                time.sleep(0.02)
        th = threading.Thread(target=keep_driving)
        th.start()
        try:
            yield
        finally:
            stop.set()
            th.join()

    def test_3_deactivate_stops_the_motors_within_50ms(self):
        at_can_bus = rospy.get_param('~motor_check', 'can_bus') == 'can_bus'
        try:
            with real_time(), self.driving(0.2):
                latency = self.deactivate_at_can_bus() if at_can_bus else self.deactivate_at_hbmotors()
                time.sleep(0.5)  # + the 0.5 s watch for new commands: 1 s after the call
            speed = abs(self.truth.get().twist.twist.linear.x)
            print('speed 1 s after deactivate: %.3f m/s' % speed)
            self.assertLess(latency, 0.05)
            self.assertLess(speed, 0.01)
        finally:
            self.effectors.activate()

    def deactivate_at_can_bus(self):
        """From the request (on an open connection) to the motor board's zero command on the
        bus (kernel receive stamp): deactivate service -> drive effector -> HCL motor board
        driver -> the CAN frame the emulator applies on receipt. Returns it [s]."""
        state = Latest('/hcl/motor_board/state', MotorBoardState, keep=True, queue_size=200)
        bus = CanBusListener(rospy.get_param('/hcl/motor_board/bus'))
        cob_id = int(str(rospy.get_param('/hcl/motor_board/command_cob_id', 0x200 + 10)), 0)
        try:
            self.assertTrue(wait_for(lambda: state.get() and any(state.get().pwm_applied), 5.0), 'the motors are not driven')
            self.assertTrue(wait_for(lambda: bus.data_frames(cob_id, time.time() - 0.1), 3.0), 'no motor command on the bus')
            t_call = time.monotonic()
            wall_call = time.time()
            self.effectors.deactivate()
            zero = wait_for(lambda: [t for t, d in bus.data_frames(cob_id, wall_call) if d[:4] == bytes(4)], 1.0)
            self.assertTrue(zero, 'no zero motor command on the bus after deactivate')
            stopped = wait_for(lambda: [t for t, m in state.items if t >= t_call and not any(m.pwm_applied)], 1.0)
            self.assertTrue(stopped, 'the motor board never reported the motors stopped')
            time.sleep(0.5)
            self.assertFalse([t for t, d in bus.data_frames(cob_id, zero[0]) if d[:4] != bytes(4)],
                             'the motors were commanded again while deactivated')
            print('deactivate -> zero motor command on the bus: %.1f ms (state reporting 0 reached the test after %.1f ms)' %
                  (1e3 * (zero[0] - wall_call), 1e3 * (stopped[0] - t_call)))
            return zero[0] - wall_call
        finally:
            bus.close()

    def deactivate_at_hbmotors(self):
        """From the request (on an open connection) to every HBmotor board reading back duty 0,
        stamped (simulated time) at the poll that read it. Returns it [s]."""
        states = [Latest(t, HBMotorState, keep=True, queue_size=200) for t in rospy.get_param('~motor_states')]
        self.assertTrue(wait_for(lambda: all(s.get() and s.get().command != 0 for s in states), 5.0),
                        'the motors are not driven')
        t_call = time.monotonic()
        sim_call = rospy.Time.now()
        self.effectors.deactivate()
        firsts = []
        for s in states:
            z = wait_for(lambda: [(t, m) for t, m in s.items if t >= t_call and m.command == 0], 1.0)
            self.assertTrue(z, 'a motor board never applied 0')
            firsts.append(z[0])
        seen = max(t for t, _ in firsts)
        time.sleep(0.5)
        self.assertFalse([m.command for s in states for t, m in s.items if t >= seen and m.command != 0],
                         'the motors were driven again while deactivated')
        latency = max((m.header.stamp - sim_call).to_sec() for _, m in firsts)
        print('deactivate -> every H-bridge reads back duty 0: %.1f ms simulated time (%.1f ms until the test saw it)' %
              (1e3 * latency, 1e3 * (seen - t_call)))
        return latency


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_hal_sim', HalSimTest)
