#!/usr/bin/env python3
"""The issue 6 HAL devices in a real hal_node, fed with HCL messages by this test."""
import math
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Twist
from hal_nodes.msg import BeaconRange, Contacts, Heading, JoystickEvent, JoystickState
from hal_nodes.srv import FitBeaconEquation, SetBeaconEquation
from hcl_drivers.msg import BeaconDelta, Bearing, DigitalInputs, EncoderCounter, MotorCommand
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Joy, Range
from std_srvs.srv import Trigger


class Recorder(object):
    def __init__(self, topic, msg_type):
        self.lock = threading.Lock()
        self.items = []
        self.sub = rospy.Subscriber(topic, msg_type, self._cb, queue_size=500, tcp_nodelay=True)

    def _cb(self, msg):
        with self.lock:
            self.items.append((time.monotonic(), msg))

    def since(self, t0):
        with self.lock:
            return [(t, m) for t, m in self.items if t >= t0]

    def last(self):
        with self.lock:
            return self.items[-1][1] if self.items else None


def wait_for(pred, timeout, step=0.02):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        v = pred()
        if v:
            return v
        time.sleep(step)
    return pred()


class FakeEncoders(object):
    """Two encoder pairs as boards would publish them (16-bit counters), at 50 Hz."""

    def __init__(self):
        self.pubs = {n: rospy.Publisher('/hcl/fake/encoder/' + n, EncoderCounter, queue_size=1, latch=True)
                     for n in ('left_measuring', 'right_measuring', 'left', 'right')}
        self.ticks = {n: 1000 for n in self.pubs}
        self.resets = {n: 0 for n in self.pubs}
        self.enabled = {n: True for n in self.pubs}
        self.lock = threading.Lock()
        self.timer = rospy.Timer(rospy.Duration(0.02), self._tick)

    def move(self, measuring_m, driven_m, seconds):
        """Move both wheels forward by the given surface distances, spread over `seconds`."""
        steps = max(1, int(seconds / 0.02))
        for _ in range(steps):
            with self.lock:
                self.ticks['left_measuring'] += 20000 * measuring_m / steps
                self.ticks['right_measuring'] -= 20000 * measuring_m / steps  # mirrored
                self.ticks['left'] += 10000 * driven_m / steps
                self.ticks['right'] += 10000 * driven_m / steps
            time.sleep(0.02)

    def _tick(self, _):
        now = rospy.Time.now()
        with self.lock:
            for n, pub in self.pubs.items():
                if not self.enabled[n]:
                    continue
                m = EncoderCounter()
                m.header.stamp = now
                m.name = n
                m.bits = 16
                m.raw = int(round(self.ticks[n])) % 65536
                m.board_resets = self.resets[n]
                pub.publish(m)


def diag_level(recorder, name_part, t0):
    for _, arr in reversed(recorder.since(t0)):
        for s in arr.status:
            if name_part in s.name:
                return s.level, s.message
    return None


class HalDevicesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_hal_devices')
        cls.diag = Recorder('/diagnostics', DiagnosticArray)
        cls.odom = Recorder('/odom', Odometry)
        cls.odom_measuring = Recorder('/hal/odometry/measuring', Odometry)
        cls.motor_left = Recorder('/hcl/fake/motor/left/command', MotorCommand)
        cls.motor_right = Recorder('/hcl/fake/motor/right/command', MotorCommand)
        cls.enc = FakeEncoders()
        wait_for(lambda: cls.odom.last() is not None, 20.0)

    def test_odometry_straight_through_wraps_reset_and_stale(self):
        self.assertIsNotNone(wait_for(lambda: self.odom.last(), 10.0), 'no /odom')
        x0 = self.odom.last().pose.pose.position.x
        # 4 m forward: the measuring encoders (20000 ticks/m) wrap a 16-bit counter once.
        self.enc.move(4.0, 4.0, 2.0)
        time.sleep(0.3)
        o = self.odom.last()
        self.assertAlmostEqual(o.pose.pose.position.x - x0, 4.0, delta=0.01)
        self.assertAlmostEqual(o.pose.pose.position.y, 0.0, delta=0.01)
        self.assertEqual(o.header.frame_id, 'odom')
        self.assertEqual(o.child_frame_id, 'base_link')
        var_x = o.pose.covariance[0]
        self.assertGreater(var_x, 0.0)
        # The driven wheels slip (they report 10 % more): reliability 0.25 vs 1 bounds the error.
        x1 = o.pose.pose.position.x
        self.enc.move(1.0, 1.1, 0.5)
        time.sleep(0.3)
        o = self.odom.last()
        self.assertAlmostEqual(o.pose.pose.position.x - x1, (1.0 * 1.0 + 0.25 * 1.1) / 1.25, delta=0.01)
        self.assertGreater(o.pose.covariance[0], var_x)  # grows with distance
        pm = self.odom_measuring.last()
        self.assertIsNotNone(pm)
        self.assertAlmostEqual(pm.pose.pose.position.x, 5.0, delta=0.01)
        # A board reboot of the driven pair: its counters restart at 0, no jump.
        x2 = o.pose.pose.position.x
        with self.enc.lock:
            for n in ('left', 'right'):
                self.enc.ticks[n] = 0
                self.enc.resets[n] = 1
        time.sleep(0.3)
        self.assertAlmostEqual(self.odom.last().pose.pose.position.x, x2, delta=0.002)
        # The measuring pair goes stale: the driven pair carries on alone.
        with self.enc.lock:
            self.enc.enabled['left_measuring'] = False
            self.enc.enabled['right_measuring'] = False
        time.sleep(0.5)
        self.enc.move(0.5, 0.5, 0.5)
        time.sleep(0.3)
        self.assertAlmostEqual(self.odom.last().pose.pose.position.x - x2, 0.5, delta=0.01)
        # It comes back after the driven pair covered the gap: not counted twice.
        with self.enc.lock:
            self.enc.enabled['left_measuring'] = True
            self.enc.enabled['right_measuring'] = True
        time.sleep(0.3)
        self.assertAlmostEqual(self.odom.last().pose.pose.position.x - x2, 0.5, delta=0.01)
        # Everything stale: no more /odom, diagnostics STALE.
        with self.enc.lock:
            for n in self.enc.enabled:
                self.enc.enabled[n] = False
        time.sleep(0.5)
        t0 = time.monotonic()
        time.sleep(0.6)
        self.assertEqual(len(self.odom.since(t0)), 0, '/odom published while every pair is stale')
        lv = diag_level(self.diag, 'odometry', t0)
        self.assertIsNotNone(lv)
        self.assertEqual(lv[0], DiagnosticStatus.STALE, lv[1])
        self.assertIn('stale', lv[1])
        with self.enc.lock:
            for n in self.enc.enabled:
                self.enc.enabled[n] = True
        self.assertTrue(wait_for(lambda: self.odom.since(time.monotonic() - 0.1), 2.0), 'odometry did not resume')

    def test_drive_units_timeout_and_deactivation(self):
        pub = rospy.Publisher('/hal/drive/cmd_vel', Twist, queue_size=1)
        wait_for(lambda: pub.get_num_connections() > 0, 5.0)
        cmd = Twist()
        cmd.linear.x = 0.4
        cmd.angular.z = 0.8  # wheels 0.4 -+ 0.1 m/s
        t0 = time.monotonic()
        for _ in range(10):
            pub.publish(cmd)
            time.sleep(0.05)
        left = [m.value for _, m in self.motor_left.since(t0 + 0.2)]
        right = [m.value for _, m in self.motor_right.since(t0 + 0.2)]
        self.assertIn(300, left)
        self.assertIn(-500, right)  # units_per_mps -1000: mirrored motor
        # Commands stop: the wheels stop after cmd_timeout (0.3 s).
        t_stop = time.monotonic()
        time.sleep(0.6)
        tail = [m.value for t, m in self.motor_left.since(t_stop + 0.45)]
        self.assertTrue(tail and all(v == 0 for v in tail), tail)
        # Driving again, then /effectors/deactivate: zero within 50 ms of the call.
        stop_flag = threading.Event()

        def keep_driving():
            while not stop_flag.is_set():
                pub.publish(cmd)
                time.sleep(0.02)
        th = threading.Thread(target=keep_driving)
        th.start()
        try:
            time.sleep(0.5)
            self.assertEqual(self.motor_left.last().value, 300)
            rospy.wait_for_service('/effectors/deactivate', 5.0)
            t_call = time.monotonic()
            rospy.ServiceProxy('/effectors/deactivate', Trigger)()
            zero = wait_for(lambda: [t for t, m in self.motor_left.since(t_call) if m.value == 0], 1.0, step=0.002)
            self.assertTrue(zero, 'no zero command after deactivate')
            latency = zero[0] - t_call
            print('deactivate -> zero command latency: %.1f ms' % (1e3 * latency))
            self.assertLess(latency, 0.050)
            time.sleep(0.3)
            later = [m.value for _, m in self.motor_left.since(t_call + 0.1)]
            self.assertTrue(all(v == 0 for v in later), 'drove while deactivated: %s' % later)
            rospy.ServiceProxy('/effectors/activate', Trigger)()
            self.assertTrue(wait_for(lambda: self.motor_left.last().value == 300, 2.0), 'not driving after activate')
        finally:
            stop_flag.set()
            th.join()

    def test_beacons_equation_and_fit(self):
        ranges = Recorder('/hal/beacons/ranges', BeaconRange)
        pub = rospy.Publisher('/hcl/fake/delta', BeaconDelta, queue_size=50)
        wait_for(lambda: pub.get_num_connections() > 1, 5.0)  # the device subscribes twice
        time.sleep(0.3)
        c = 331.3 * math.sqrt(1 + 20.0 / 273.15)
        t0 = time.monotonic()
        for i, d in enumerate([0.5, 1.0, 2.0, 3.0, 9.0]):  # 9 m: an outlier
            m = BeaconDelta()
            m.header.stamp = rospy.Time.now()
            m.beacon_id = i % 3
            m.delta_us = int(round(1e6 * d / c))
            pub.publish(m)
        got = wait_for(lambda: len(ranges.since(t0)) >= 4 and ranges.since(t0), 3.0)
        time.sleep(0.2)
        got = [m for _, m in ranges.since(t0)]
        self.assertEqual([round(m.range, 3) for m in got], [0.5, 1.0, 2.0, 3.0])
        self.assertTrue(all(m.variance > 0 for m in got))
        self.assertGreater(got[3].variance, got[0].variance)
        # Fit: true distances say the sound is 2 % faster and there is a 3 cm offset.
        fit = rospy.ServiceProxy('/hal/beacons/fit_equation', FitBeaconEquation)
        deltas = [1e6 * d / c for d in (0.5, 1.0, 1.5, 2.0, 2.5, 3.0)]
        truth = [1.02 * c * 1e-6 * t + 0.03 for t in deltas]
        r = fit(delta_us=deltas, distance=truth, beacon_id=[], apply=True)
        self.assertTrue(r.success, r.message)
        self.assertAlmostEqual(r.scale, 1.02, places=4)
        self.assertAlmostEqual(r.offset, 0.03, places=4)
        self.assertAlmostEqual(rospy.get_param('/hal/beacons/scale'), 1.02, places=4)
        t1 = time.monotonic()
        m = BeaconDelta()
        m.header.stamp = rospy.Time.now()
        m.delta_us = 5000
        pub.publish(m)
        self.assertTrue(wait_for(lambda: ranges.since(t1), 2.0))
        self.assertAlmostEqual(ranges.since(t1)[0][1].range, 1.02 * c * 0.005 + 0.03, places=3)
        # Setting the equation directly, and refusing nonsense.
        setter = rospy.ServiceProxy('/hal/beacons/set_equation', SetBeaconEquation)
        self.assertFalse(setter(temperature=20.0, scale=-1.0, offset=0.0, beacon_offsets=[]).success)
        self.assertTrue(setter(temperature=30.0, scale=1.0, offset=0.0, beacon_offsets=[0.0, 0.1]).success)
        t2 = time.monotonic()
        m.beacon_id = 1
        pub.publish(m)
        self.assertTrue(wait_for(lambda: ranges.since(t2), 2.0))
        c30 = 331.3 * math.sqrt(1 + 30.0 / 273.15)
        self.assertAlmostEqual(ranges.since(t2)[0][1].range, c30 * 0.005 + 0.1, places=3)

    def test_compass_rangers_bumpers(self):
        heading = Recorder('/hal/compass/heading', Heading)
        front = Recorder('/hal/rangers/front', Range)
        contacts = Recorder('/hal/bumpers/contacts', Contacts)
        bpub = rospy.Publisher('/hcl/fake/bearing', Bearing, queue_size=1, latch=True)
        b = Bearing()
        b.header.stamp = rospy.Time.now()
        b.degrees = 90.0  # module east of its north: yaw = north_yaw - pi/2 = 0
        bpub.publish(b)
        self.assertTrue(wait_for(lambda: heading.last(), 3.0))
        self.assertAlmostEqual(heading.last().yaw, 0.0, places=4)
        self.assertEqual(heading.last().header.frame_id, 'map')
        # Ranger: steady 1 m with one spike and one NaN: the output never leaves 1 m.
        rpub = rospy.Publisher('/hcl/fake/range/front', Range, queue_size=10)
        wait_for(lambda: rpub.get_num_connections() > 0, 5.0)
        t0 = time.monotonic()
        for v in [1.0, 1.0, 1.0, 0.2, 1.0, float('nan'), 1.0, 1.0]:
            r = Range()
            r.header.stamp = rospy.Time.now()
            r.header.frame_id = 'board_frame'
            r.min_range, r.max_range, r.range = 0.15, 6.0, v
            rpub.publish(r)
            time.sleep(0.06)
        outs = [m for _, m in front.since(t0)]
        self.assertGreaterEqual(len(outs), 6)
        self.assertTrue(all(abs(m.range - 1.0) < 1e-6 for m in outs), [m.range for m in outs])
        self.assertEqual(outs[0].header.frame_id, 'ranger_front')
        # Bumpers: edges by input name and by bit.
        ipub = rospy.Publisher('/hcl/fake/inputs', DigitalInputs, queue_size=1, latch=True)
        stop = threading.Event()
        state = {'bits': 0}

        def feed():
            while not stop.is_set():
                m = DigitalInputs()
                m.header.stamp = rospy.Time.now()
                m.bits = state['bits']
                m.names = ['x', 'bumper_fl']
                ipub.publish(m)
                time.sleep(0.02)
        th = threading.Thread(target=feed)
        th.start()
        try:
            time.sleep(0.5)
            t1 = time.monotonic()
            state['bits'] = 0b1010  # bumper_fl (bit 1) and rear (bit 3)
            self.assertTrue(wait_for(lambda: [m for _, m in contacts.since(t1) if m.pressed], 2.0))
            pressed = sum((list(m.pressed) for _, m in contacts.since(t1)), [])
            self.assertEqual(sorted(pressed), ['front_left', 'rear'])
            time.sleep(0.1)
            self.assertEqual(sorted(contacts.last().closed), ['front_left', 'rear'])
            t2 = time.monotonic()
            state['bits'] = 0b1000
            self.assertTrue(wait_for(lambda: [m for _, m in contacts.since(t2) if m.released], 2.0))
            released = sum((list(m.released) for _, m in contacts.since(t2)), [])
            self.assertEqual(released, ['front_left'])
        finally:
            stop.set()
            th.join()

    def test_joystick_names_and_edges(self):
        events = Recorder('/hal/joystick/events', JoystickEvent)
        state = Recorder('/hal/joystick/state', JoystickState)
        pub = rospy.Publisher('/hcl/fake/joy', Joy, queue_size=1, latch=True)
        joy = Joy()
        joy.axes = [0.5, -1.0]
        joy.buttons = [0, 0, 0, 0, 0, 1]
        t0 = time.monotonic()
        for _ in range(10):
            joy.header.stamp = rospy.Time.now()
            pub.publish(joy)
            time.sleep(0.03)
        s = wait_for(lambda: state.last(), 2.0)
        self.assertEqual(list(s.axis_names), ['angular', 'linear'])
        self.assertAlmostEqual(s.axes[0], -(0.5 - 0.05) / 0.95, places=4)  # inverted, dead zone
        self.assertAlmostEqual(s.axes[1], -1.0, places=4)
        self.assertEqual([(m.button, m.pressed) for _, m in events.since(t0)], [('deadman', True)])
        # The pad goes silent while the dead-man button is held: it is released.
        t1 = time.monotonic()
        ev = wait_for(lambda: events.since(t1), 2.0)
        self.assertEqual([(m.button, m.pressed) for _, m in ev], [('deadman', False)])


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_hal_devices', HalDevicesTest)
