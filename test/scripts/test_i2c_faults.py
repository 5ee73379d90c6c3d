#!/usr/bin/env python3
"""Faults injected by the simulator into Logion's I2C, serial and joystick boards."""
import sys
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hcl_drivers.msg import BeaconReceiverState, EncoderCounter, HBMotorState, JoystickState, MotorCommand
from robot_sim.srv import InjectFault
from std_msgs.msg import Int32
from test_support import Recorder, wait_for


class I2cFaultsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_i2c_faults')
        cls.duty = Recorder('/sim/motor_left/duty', Int32, queue_size=1000)
        cls.motor = Recorder('/hcl/motor_left/state', HBMotorState, queue_size=1000)
        cls.encoder = Recorder('/hcl/motor_left/encoder/left', EncoderCounter, queue_size=1000)
        cls.beacons = Recorder('/hcl/beacons/state', BeaconReceiverState, queue_size=1000)
        cls.joystick = Recorder('/hcl/joystick/state', JoystickState, queue_size=1000)
        cls.diagnostics = Recorder('/diagnostics', DiagnosticArray, queue_size=1000)
        cls.cmd = rospy.Publisher('/hcl/motor_left/motor/left/command', MotorCommand, queue_size=1)
        rospy.wait_for_service('/sim/inject_fault', 30.0)
        cls.inject = rospy.ServiceProxy('/sim/inject_fault', InjectFault)
        assert wait_for(lambda: cls.motor.last() and cls.beacons.last() and cls.joystick.last(), 40.0, step=0.02), 'boards not up'

    def fault(self, kind, target, clear=False):
        r = self.inject(kind=kind, target=target, start=0.0, duration=0.0, magnitude=0.0, clear=clear)
        self.assertTrue(r.ok, r.message)

    def level(self, board, t0):
        out = None
        for _, arr in self.diagnostics.since(t0):
            for s in arr.status:
                if 'hcl/%s:' % board in s.name:
                    out = s
        return out

    def describe(self, board, t0):
        """The board's statuses since t0 (receive time relative to t0, level, message), for a failure."""
        seen = ['%+.2f s %d %s' % (t - t0, s.level, s.message) for t, arr in self.diagnostics.since(t0 - 1.0)
                for s in arr.status if 'hcl/%s:' % board in s.name]
        return '; '.join(seen[-8:]) or 'none since 1 s before the fault'

    def drive(self, value, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.cmd.publish(MotorCommand(name='left', value=value))
            time.sleep(0.05)

    def test_1_silent_motor_board_goes_stale_and_its_motor_stops(self):
        stop = threading.Event()
        feeder = threading.Thread(target=lambda: [self.cmd.publish(MotorCommand(name='left', value=60)) or time.sleep(0.05)
                                                  for _ in iter(stop.is_set, True)])
        feeder.start()
        try:
            self.assertTrue(wait_for(lambda: self.duty.last() and self.duty.last().data == 60, 3.0, step=0.02))
            t0 = time.monotonic()
            self.fault('board_silent', 'motor_left')
            # The driver keeps commanding, but nothing reaches the board: its own watchdog (0.25 s) stops it.
            self.assertTrue(wait_for(lambda: self.duty.last().data == 0, 1.5, step=0.02), 'motor kept running on a silent board')
            self.assertTrue(wait_for(lambda: self.level('motor_left', t0 + 0.2) is not None and self.level(
                'motor_left', t0 + 0.2).level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE), 2.0, step=0.02))
            self.assertTrue(wait_for(lambda: self.level('motor_right', t0 + 0.5) is not None, 2.0, step=0.02),
                            'no report of the neighbour; its last status: %s' % self.describe('motor_right', t0))
            other = self.level('motor_right', t0 + 0.5)
            self.assertEqual(other.level, DiagnosticStatus.OK, 'a silent board must not disturb its bus neighbours')
            self.fault('board_silent', 'motor_left', clear=True)
            self.assertTrue(wait_for(lambda: self.duty.last().data == 60, 3.0, step=0.02), 'did not recover')
        finally:
            self.inject(kind='board_silent', target='motor_left', start=0.0, duration=0.0, magnitude=0.0, clear=True)
            stop.set()
            feeder.join()

    def test_2_rebooted_board_is_detected(self):
        resets = self.encoder.last().board_resets
        self.fault('board_reset', 'motor_left')
        self.assertTrue(wait_for(lambda: self.encoder.last().board_resets == resets + 1, 2.0, step=0.02))
        self.assertTrue(wait_for(lambda: self.motor.last().watchdog == 25, 2.0, step=0.02), 'watchdog not reconfigured')

    def test_3_serial_garbage_is_counted_and_deltas_keep_coming(self):
        before = self.beacons.last()
        self.fault('serial_garbage', 'beacons')
        self.fault('serial_truncate', 'beacons')
        time.sleep(3.0)
        self.fault('serial_garbage', 'beacons', clear=True)
        self.fault('serial_truncate', 'beacons', clear=True)
        after = self.beacons.last()
        self.assertGreater(after.garbage_bytes + after.malformed, before.garbage_bytes + before.malformed)
        time.sleep(1.5)
        self.assertGreater(self.beacons.last().messages, after.messages, 'no valid message after the garbage stopped')

    def test_4_unplugged_joystick_is_reported_and_comes_back(self):
        t0 = time.monotonic()
        self.fault('board_silent', 'joystick')
        self.assertTrue(wait_for(lambda: not self.joystick.last().connected, 2.0, step=0.02))
        self.assertTrue(wait_for(lambda: self.level('joystick', t0 + 0.3) is not None and self.level(
            'joystick', t0 + 0.3).level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE), 2.0, step=0.02),
            'unplugged joystick not reported; its last status: %s' % self.describe('joystick', t0))
        self.fault('board_silent', 'joystick', clear=True)
        self.assertTrue(wait_for(lambda: self.joystick.last().connected, 3.0, step=0.02))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'i2c_faults', I2cFaultsTest, sys.argv)
