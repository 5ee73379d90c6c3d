#!/usr/bin/env python3
"""CAN servo board driver (hcl_drivers/ServoBoard) against its emulator over CAN-over-UDP."""
import unittest

import rospy
import rostest
from hcl_drivers.msg import DigitalInputs, ServoBoardState
from robot_sim.msg import CanFirmware
from sensor_msgs.msg import Range
from std_msgs.msg import UInt16

from can_test_common import Recorder, truth_value


class ServoBoardTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_can_servo_board')
        cls.state = Recorder('/hcl/servo_board/state', ServoBoardState)
        cls.range = Recorder('/hcl/servo_board/range/sharp_front', Range)
        cls.inputs = Recorder('/hcl/servo_board/inputs', DigitalInputs)
        cls.truth = Recorder('/sim/servo_board/firmware', CanFirmware)
        cls.flag = rospy.Publisher('/hcl/servo_board/servo/flag/pulse_us', UInt16, queue_size=1, latch=True)
        assert cls.state.wait_for(lambda m: m.node.answering, 30.0), 'the servo board never answered'

    def test_1_sharp_rangers_in_metres(self):
        r = self.range.wait_for(lambda r: True, 2.0)
        self.assertIsNotNone(r)
        self.assertEqual(r.radiation_type, Range.INFRARED)
        self.assertAlmostEqual(r.min_range, 0.10, places=3)
        self.assertAlmostEqual(r.max_range, 0.80, places=3)
        self.assertAlmostEqual(r.range, 0.35, delta=0.02)  # bench world: 35 cm, 1 LSB ADC noise
        self.assertEqual(r.header.frame_id, 'sharp_front')
        m = self.state.last()
        self.assertEqual(len(m.ranger_raw), 2)
        self.assertTrue(m.ranger_raw[0] > 100)

    def test_2_switches(self):
        i = self.inputs.wait_for(lambda i: True, 2.0)
        self.assertEqual(i.bits, 0x2)  # only 'colour' closed on the bench
        self.assertEqual(list(i.names), ['start_cord', 'colour', 'bumper'])

    def test_3_servo_pulse_reaches_the_firmware(self):
        self.flag.publish(UInt16(1800))
        t = self.truth.wait_for(lambda t: truth_value(t, 'pulse1') == 1800, 3.0)
        self.assertIsNotNone(t, 'servo command not applied')
        self.assertEqual(truth_value(t, 'pulse0'), 0, 'an uncommanded servo stays off')
        self.assertEqual(list(self.state.last().servo_pulse_us), [0, 1800])

    def test_4_impossible_pulses_are_refused(self):
        self.flag.publish(UInt16(3000))
        rospy.sleep(0.5)
        self.assertEqual(truth_value(self.truth.last(), 'pulse1'), 1800)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'can_servo_board', ServoBoardTest)
