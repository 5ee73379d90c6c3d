#!/usr/bin/env python3
"""Logion's I2C boards (HBmotor x2, MCP23016, SRF02, CMPS03) on one emulated bus and loop group."""
import math
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hcl_drivers.msg import Bearing, DigitalInputs, EncoderCounter, MotorCommand
from sensor_msgs.msg import Range
from std_msgs.msg import Int32, UInt16
from test_support import Recorder, wait_for

RATES = {'motor_left': 50.0, 'motor_right': 50.0, 'io': 20.0, 'ranger_front': 10.0, 'compass': 20.0}


class I2cBoardsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_i2c_boards')
        cls.enc_left = Recorder('/hcl/motor_left/encoder/left', EncoderCounter)
        cls.duty_left = Recorder('/sim/motor_left/duty', Int32)
        cls.inputs = Recorder('/hcl/io/inputs', DigitalInputs)
        cls.outputs = Recorder('/sim/io/outputs', UInt16)
        cls.range = Recorder('/hcl/ranger_front/range', Range)
        cls.bearing = Recorder('/hcl/compass/bearing', Bearing)
        cls.diagnostics = Recorder('/diagnostics', DiagnosticArray)
        cls.cmd_left = rospy.Publisher('/hcl/motor_left/motor/left/command', MotorCommand, queue_size=1)
        cls.leds = rospy.Publisher('/hcl/io/outputs', UInt16, queue_size=1, latch=True)
        assert wait_for(lambda: cls.enc_left.last() and cls.range.last() and cls.bearing.last(), 30.0, step=0.05), \
            'boards never published'

    def drive(self, value, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.cmd_left.publish(MotorCommand(name='left', value=value))
            time.sleep(0.05)

    def test_1_motor_command_reaches_the_firmware_and_the_encoder_counts(self):
        t0 = time.monotonic()
        self.drive(64, 2.0)
        duties = [m.data for _, m in self.duty_left.since(t0 + 0.5)]
        self.assertTrue(duties and all(d == 64 for d in duties), duties[-10:])
        enc = [(m.header.stamp.to_sec(), m.raw) for _, m in self.enc_left.since(t0 + 0.5)]
        (ta, a), (tb, b) = enc[0], enc[-1]
        rate = ((b - a) % 2**32) / (tb - ta)
        self.assertAlmostEqual(rate, 64 / 127.0 * 2000, delta=150, msg='encoder %.0f ticks/s' % rate)
        self.assertEqual(self.enc_left.last().bits, 32)

    def test_2_stale_motor_command_stops_the_motor(self):
        before = self.enc_left.last().raw
        self.drive(-50, 1.0)
        self.assertEqual(self.duty_left.last().data, -50)
        stopped = time.monotonic()
        self.assertTrue(wait_for(lambda: self.duty_left.last().data == 0, 1.0, step=0.05),
                        'motor still driven %.1f s after the last command' % (time.monotonic() - stopped))
        # Backwards counts down (modulo 2^32): about 50/127 * 2000 ticks in 1 s.
        delta = (self.enc_left.last().raw - before) % 2**32
        delta = delta - 2**32 if delta >= 2**31 else delta
        self.assertAlmostEqual(delta, -50 / 127.0 * 2000, delta=250)

    def test_3_buttons_in_leds_out(self):
        # Pin 0 pulled low (button to ground pressed) reads 1 through IPOL; pin 1 high reads 0.
        rospy.set_param('/sim/firmware/io/input_levels', 0xFFFE)
        self.assertTrue(wait_for(lambda: self.inputs.last().bits == 0x0001, 2.0, step=0.05), hex(self.inputs.last().bits))
        rospy.set_param('/sim/firmware/io/input_levels', 0xFFFD)
        self.assertTrue(wait_for(lambda: self.inputs.last().bits == 0x0002, 2.0, step=0.05), hex(self.inputs.last().bits))
        self.assertEqual(list(self.inputs.last().names), ['start', 'colour'])
        self.leds.publish(UInt16(0xA500))
        self.assertTrue(wait_for(lambda: self.outputs.last() and self.outputs.last().data == 0xA500, 2.0, step=0.05))

    def test_4_ranger_in_metres_without_blocking_the_bus(self):
        rospy.set_param('/sim/firmware/ranger_front/range', 2.5)
        self.assertTrue(wait_for(lambda: abs(self.range.last().range - 2.5) < 0.006, 2.0, step=0.05), self.range.last().range)
        m = self.range.last()
        self.assertEqual(m.radiation_type, Range.ULTRASOUND)
        self.assertAlmostEqual(m.min_range, 0.16, places=3)
        rospy.set_param('/sim/firmware/ranger_front/range', 9.0)  # nothing within 6 m: no echo
        self.assertTrue(wait_for(lambda: math.isinf(self.range.last().range), 2.0, step=0.05), self.range.last().range)
        rospy.set_param('/sim/firmware/ranger_front/range', 1.23)
        t0 = time.monotonic()
        time.sleep(3.0)
        n = len(self.range.since(t0))
        self.assertGreater(n / 3.0, 0.8 * 10.0, '%d ranges in 3 s' % n)

    def test_5_compass_bearing_in_degrees(self):
        rospy.set_param('/sim/firmware/compass/bearing', 359.9)
        self.assertTrue(wait_for(lambda: abs(self.bearing.last().degrees - 359.9) < 1e-6, 2.0, step=0.05))
        rospy.set_param('/sim/firmware/compass/bearing', 12.3)
        self.assertTrue(wait_for(lambda: abs(self.bearing.last().degrees - 12.3) < 1e-6, 2.0, step=0.05))

    def latest_status(self, t0):
        statuses = {}
        for _, arr in self.diagnostics.since(t0):
            for s in arr.status:
                statuses[s.name] = s
        return statuses

    def test_6_one_loop_shares_the_bus_at_the_configured_rates(self):
        t0 = time.monotonic()
        time.sleep(2.5)
        statuses = self.latest_status(t0 + 1.0)
        for board, rate in RATES.items():
            found = [s for n, s in statuses.items() if 'hcl/%s:' % board in n]
            self.assertTrue(found, 'no diagnostics for %s: %s' % (board, sorted(statuses)))
            s = found[0]
            kv = {v.key: v.value for v in s.values}
            self.assertEqual(s.level, DiagnosticStatus.OK, '%s: %s' % (board, s.message))
            self.assertEqual(kv['loop'], 'i2c-1')
            self.assertAlmostEqual(float(kv['achieved rate [Hz]']), rate, delta=0.2 * rate, msg=board)
            # The SRF02 never waits out its 65 ms conversion inside service().
            self.assertLess(float(kv['max service time [ms]']), 30.0, board)

    def test_9_dead_emulator_goes_stale_and_the_motor_is_halted(self):
        subprocess.check_call(['rosnode', 'kill', '/sim/firmware'], stdout=subprocess.DEVNULL)
        killed = time.monotonic()

        def every_board_named():
            # The newest status of each board since the kill: a level change is said at once,
            # then once a second (~diagnostic_period).
            statuses = self.latest_status(killed)
            found = {b: [s for n, s in statuses.items() if 'hcl/%s:' % b in n] for b in RATES}
            return all(f and f[0].level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE) for f in found.values())
        self.assertTrue(wait_for(every_board_named, 3.0, step=0.05),
                        'not every board ERROR or STALE: %s' % {n: (s.level, s.message) for n, s in
                                                              self.latest_status(killed).items()})
        out = subprocess.run(['rosnode', 'ping', '-c', '1', '/hcl'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.assertEqual(out.returncode, 0, out.stdout.decode())


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'i2c_boards', I2cBoardsTest, sys.argv)
