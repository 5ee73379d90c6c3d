#!/usr/bin/env python3
"""The HAL devices in a real hal_node, fed with HCL messages by this test."""
import math
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from geometry_msgs.msg import Twist
from hal_nodes.msg import BeaconRange, Contacts, Heading, JoystickEvent, JoystickState
from hal_nodes.srv import FitBeaconEquation, SetBeaconEquation
from hcl_drivers.msg import BeaconDelta, Bearing, DigitalInputs, EncoderCounter, MotorCommand
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Joy, Range

from test_support import DeviceDiagnostics, EffectorSwitch, Recorder, is_ok, value, wait_for


class FakeEncoders(object):
    """Two encoder pairs as boards would publish them (16-bit counters), at 50 Hz."""

    def __init__(self):
        self.pubs = {n: rospy.Publisher('/hcl/fake/encoder/' + n, EncoderCounter, queue_size=1, latch=True)
                     for n in ('left_measuring', 'right_measuring', 'left', 'right')}
        self.ticks = {n: 1000 for n in self.pubs}
        self.resets = {n: 0 for n in self.pubs}
        self.enabled = {n: True for n in self.pubs}
        self.lock = threading.Lock()
        self.changed = 0        # counts changes of ticks/resets/enabled
        self.published = (-1, None)  # (change count, stamp) of the newest publication
        self.timer = rospy.Timer(rospy.Duration(0.02), self._tick)

    def change(self, fn):
        """Apply fn() to the counters under the lock, as one change."""
        with self.lock:
            fn()
            self.changed += 1

    def published_stamp(self, timeout=3.0):
        """The stamp of the first publication that carries every change so far."""
        with self.lock:
            wanted = self.changed

        def done():
            with self.lock:
                return self.published[1] if self.published[0] >= wanted else None
        stamp = wait_for(done, timeout)
        assert stamp is not None, 'the fake encoders did not publish'
        return stamp

    def move(self, measuring_m, driven_m, seconds):
        """Move both wheels forward by the given surface distances, spread over `seconds`."""
        steps = max(1, int(seconds / 0.02))
        for _ in range(steps):
            with self.lock:
                self.ticks['left_measuring'] += 20000 * measuring_m / steps
                self.ticks['right_measuring'] -= 20000 * measuring_m / steps  # mirrored
                self.ticks['left'] += 10000 * driven_m / steps
                self.ticks['right'] += 10000 * driven_m / steps
                self.changed += 1
            time.sleep(0.02)

    def _tick(self, _):
        now = rospy.Time.now()
        with self.lock:
            if not any(self.enabled.values()) or rospy.is_shutdown():
                return
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
            self.published = (self.changed, now)


class HalDevicesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_hal_devices')
        cls.diag = DeviceDiagnostics()
        cls.odom = Recorder('/odom', Odometry)
        cls.odom_measuring = Recorder('/hal/odometry/measuring', Odometry)
        cls.motor_left = Recorder('/hcl/fake/motor/left/command', MotorCommand)
        cls.motor_right = Recorder('/hcl/fake/motor/right/command', MotorCommand)
        cls.enc = FakeEncoders()
        cls.effectors = EffectorSwitch()
        wait_for(lambda: cls.odom.last() is not None, 20.0)

    def odom_at(self, stamp, timeout=3.0, recorder=None):
        """The first odometry (/odom, or `recorder`'s) computed from the publication after the
        counters stamped `stamp`: every counter of `stamp` has arrived by then. (A refresh may run
        between two counters' topics of one publication on a loaded machine, its output stamped
        `stamp` with one wheel still at its previous count.)"""
        recorder = recorder or self.odom
        m = wait_for(lambda: next((m for m in recorder.messages() if m.header.stamp > stamp), None), timeout)
        self.assertIsNotNone(m, 'no odometry from the counters after %s' % stamp.to_sec())
        return m

    def wait_pair_active(self, pair, active, since):
        want = 'True' if active else 'False'
        s = self.diag.wait_for('hal/odometry', lambda s: value(s, 'pair %s active' % pair) in (want, str(int(active))),
                               3.0, since=since)
        self.assertIsNotNone(s, 'odometry pair %s never reported active=%s' % (pair, active))

    def test_odometry_straight_through_wraps_reset_and_stale(self):
        self.assertIsNotNone(wait_for(lambda: self.odom.last(), 10.0), 'no /odom')
        x0 = self.odom_at(self.enc.published_stamp()).pose.pose.position.x
        # 4 m forward: the measuring encoders (20000 ticks/m) wrap a 16-bit counter once.
        self.enc.move(4.0, 4.0, 2.0)
        o = self.odom_at(self.enc.published_stamp())
        self.assertAlmostEqual(o.pose.pose.position.x - x0, 4.0, delta=0.01)
        self.assertAlmostEqual(o.pose.pose.position.y, 0.0, delta=0.01)
        self.assertEqual(o.header.frame_id, 'odom')
        self.assertEqual(o.child_frame_id, 'base_link')
        var_x = o.pose.covariance[0]
        self.assertGreater(var_x, 0.0)
        # The driven wheels slip (they report 10 % more): reliability 0.25 vs 1 bounds the error.
        x1 = o.pose.pose.position.x
        self.enc.move(1.0, 1.1, 0.5)
        stamp = self.enc.published_stamp()
        o = self.odom_at(stamp)
        self.assertAlmostEqual(o.pose.pose.position.x - x1, (1.0 * 1.0 + 0.25 * 1.1) / 1.25, delta=0.01)
        self.assertGreater(o.pose.covariance[0], var_x)  # grows with distance
        pm = self.odom_at(stamp, recorder=self.odom_measuring)
        self.assertAlmostEqual(pm.pose.pose.position.x, 5.0, delta=0.01)
        # A board reboot of the driven pair: its counters restart at 0, no jump.
        x2 = o.pose.pose.position.x

        def reboot_driven():
            for n in ('left', 'right'):
                self.enc.ticks[n] = 0
                self.enc.resets[n] = 1
        self.enc.change(reboot_driven)
        stamp = self.enc.published_stamp()
        self.odom_at(stamp)
        time.sleep(0.1)  # a few more refreshes on the rebooted counters
        after = [m.pose.pose.position.x for m in self.odom.messages() if m.header.stamp >= stamp]
        self.assertTrue(after)
        self.assertTrue(all(abs(x - x2) < 0.002 for x in after), (x2, after))
        # The measuring pair goes stale (the device says so): the driven pair carries on alone.
        t_stale = time.monotonic()
        self.enc.change(lambda: self.enc.enabled.update(left_measuring=False, right_measuring=False))
        self.wait_pair_active('measuring', False, t_stale)
        self.enc.move(0.5, 0.5, 0.5)
        o = self.odom_at(self.enc.published_stamp())
        self.assertAlmostEqual(o.pose.pose.position.x - x2, 0.5, delta=0.01)
        # It comes back after the driven pair covered the gap: not counted twice.
        t_back = time.monotonic()
        self.enc.change(lambda: self.enc.enabled.update(left_measuring=True, right_measuring=True))
        stamp = self.enc.published_stamp()
        self.wait_pair_active('measuring', True, t_back)
        o = self.odom_at(stamp)
        time.sleep(0.1)
        xs = [m.pose.pose.position.x - x2 for m in self.odom.messages() if m.header.stamp >= stamp]
        self.assertTrue(all(abs(x - 0.5) < 0.01 for x in xs), xs)
        # Everything stale: no more /odom, diagnostics STALE.
        t_off = time.monotonic()
        self.enc.change(lambda: self.enc.enabled.update({n: False for n in self.enc.enabled}))
        last_stamp = self.enc.published[1]  # the newest counters there will be
        st = self.diag.wait_for('hal/odometry', lambda s: s.level == DiagnosticStatus.STALE, 3.0, since=t_off)
        self.assertIsNotNone(st, 'odometry never reported STALE: %s' % self.diag.status('hal/odometry'))
        self.assertIn('stale', st.message)
        t0 = time.monotonic()
        time.sleep(0.6)
        self.assertEqual(len(self.odom.since(t0 + 0.1)), 0, '/odom published while every pair is stale')
        self.assertFalse([m for m in self.odom.messages() if m.header.stamp > last_stamp], 'odometry extrapolated')
        self.enc.change(lambda: self.enc.enabled.update({n: True for n in self.enc.enabled}))
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
        last_cmd = rospy.Time.now()
        self.assertTrue(wait_for(lambda: 300 in [m.value for _, m in self.motor_left.since(t0)], 2.0))
        self.assertTrue(wait_for(lambda: -500 in [m.value for _, m in self.motor_right.since(t0)], 2.0))  # mirrored motor
        # Commands stop: the wheels stop after cmd_timeout (0.3 s) and stay stopped (times by the drive's stamps).
        first_zero = wait_for(lambda: next((m for m in self.motor_left.messages()
                                            if m.header.stamp >= last_cmd and m.value == 0), None), 2.0)
        self.assertIsNotNone(first_zero, 'the wheels did not stop after the commands stopped')
        self.assertLess((first_zero.header.stamp - last_cmd).to_sec(), 0.45)
        self.assertTrue(wait_for(lambda: [m for m in self.motor_left.messages()
                                          if (m.header.stamp - last_cmd).to_sec() > 0.6], 2.0))
        tail = [m.value for m in self.motor_left.messages() if m.header.stamp >= first_zero.header.stamp]
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
            self.assertTrue(wait_for(lambda: self.motor_left.last().value == 300, 2.0), 'not driving')
            # From the request (on an open connection) to the zero command leaving the HAL (its
            # stamp): the test's subscriber thread is not part of the product path.
            t_call = time.monotonic()
            stamp_call = rospy.Time.now()
            self.effectors.deactivate()
            zero = wait_for(lambda: [m for _, m in self.motor_left.since(t_call) if m.value == 0], 1.0, step=0.002)
            self.assertTrue(zero, 'no zero command after deactivate')
            latency = (zero[0].header.stamp - stamp_call).to_sec()
            print('deactivate -> zero command sent: %.1f ms' % (1e3 * latency))
            self.assertLess(latency, 0.050)
            time.sleep(0.3)
            later = [m.value for m in self.motor_left.messages() if m.header.stamp >= zero[0].header.stamp]
            self.assertTrue(all(v == 0 for v in later), 'drove while deactivated: %s' % later)
            self.effectors.activate()
            self.assertTrue(wait_for(lambda: self.motor_left.last().value == 300, 2.0), 'not driving after activate')
        finally:
            stop_flag.set()
            th.join()

    def test_beacons_equation_and_fit(self):
        ranges = Recorder('/hal/beacons/ranges', BeaconRange)
        pub = rospy.Publisher('/hcl/fake/delta', BeaconDelta, queue_size=50)
        self.assertTrue(wait_for(lambda: pub.get_num_connections() > 0, 5.0))  # its two subscriptions share one connection
        self.assertTrue(ranges.connected())  # ranges are events: none may be lost to a late subscription
        time.sleep(0.3)
        c = 331.3 * math.sqrt(1 + 20.0 / 273.15)
        t0 = time.monotonic()
        for i, d in enumerate([0.5, 1.0, 2.0, 3.0, 9.0]):  # 9 m: an outlier
            m = BeaconDelta()
            m.header.stamp = rospy.Time.now()
            m.beacon_id = i % 3
            m.delta_us = int(round(1e6 * d / c))
            pub.publish(m)
        wait_for(lambda: len(ranges.since(t0)) >= 4, 3.0)
        time.sleep(0.2)  # the outlier must not come later either
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
        b.degrees = 90.0  # module east of its north: yaw = north_yaw - pi/2 = 0

        def fresh_bearing():  # as a board would: fresh readings until the device has one
            if heading.last():
                return True
            b.header.stamp = rospy.Time.now()
            bpub.publish(b)
            return False
        self.assertTrue(wait_for(fresh_bearing, 5.0, step=0.05))
        self.assertAlmostEqual(heading.last().yaw, 0.0, places=4)
        self.assertEqual(heading.last().header.frame_id, 'map')
        # Ranger: steady 1 m with one spike and one NaN: the output never leaves 1 m.
        rpub = rospy.Publisher('/hcl/fake/range/front', Range, queue_size=10)
        self.assertTrue(wait_for(lambda: rpub.get_num_connections() > 0, 5.0))
        self.assertTrue(front.connected())
        t0 = time.monotonic()
        for v in [1.0, 1.0, 1.0, 0.2, 1.0, float('nan'), 1.0, 1.0]:
            r = Range()
            r.header.stamp = rospy.Time.now()
            r.header.frame_id = 'board_frame'
            r.min_range, r.max_range, r.range = 0.15, 6.0, v
            rpub.publish(r)
            time.sleep(0.06)
        wait_for(lambda: len(front.since(t0)) >= 6, 2.0)
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
            # The device knows every contact open (fresh inputs): a closing from now on is an edge.
            self.assertTrue(self.diag.wait_for('hal/bumpers', is_ok, 3.0), self.diag.status('hal/bumpers'))
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
        self.assertTrue(events.connected())  # edges are events: none may be lost to a late subscription
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
        # The pad goes silent while the dead-man button is held: it is released, once stale.
        ev = wait_for(lambda: len(events.since(t0)) >= 2 and events.since(t0), 3.0)
        time.sleep(0.1)  # nothing else follows
        ev = [m for _, m in events.since(t0)]
        self.assertEqual([(m.button, m.pressed) for m in ev], [('deadman', True), ('deadman', False)])
        self.assertLessEqual(ev[0].header.stamp, joy.header.stamp)  # pressed while the pad spoke
        self.assertGreaterEqual((ev[1].header.stamp - joy.header.stamp).to_sec(), 0.5)  # ~max_input_age


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_hal_devices', HalDevicesTest)
