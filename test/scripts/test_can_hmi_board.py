#!/usr/bin/env python3
"""CAN human interface board driver (hcl_drivers/HmiBoard) against its emulator over CAN-over-UDP."""
import unittest

import rospy
import rostest
from hcl_drivers.msg import DigitalInputs, HmiBoardState
from robot_sim.msg import CanFirmware
from std_msgs.msg import String

from can_test_common import CanUdp, Recorder

PORT, NODE = 47014, 13


class HmiBoardTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_can_hmi_board')
        cls.state = Recorder('/hcl/hmi_board/state', HmiBoardState)
        cls.inputs = Recorder('/hcl/hmi_board/inputs', DigitalInputs)
        cls.truth = Recorder('/sim/hmi_board/firmware', CanFirmware)
        cls.lcd = rospy.Publisher('/hcl/hmi_board/lcd', String, queue_size=1, latch=True)
        assert cls.state.wait_for(lambda m: m.node.answering, 30.0), 'the HMI board never answered'

    def test_1_keypad(self):
        m = self.state.wait_for(lambda m: m.keys == 1 << 5, 2.0)
        self.assertIsNotNone(m, 'key 5 held on the bench')
        self.assertEqual(m.last_key, 5)
        self.assertEqual(m.key_presses, 1)
        i = self.inputs.last()
        self.assertEqual(i.bits, 1 << 5)
        self.assertEqual(i.names[5], '5')

    def test_2_lcd_text_reaches_the_display(self):
        self.lcd.publish(String('Hello robot\nScore: 42'))
        t = self.truth.wait_for(lambda t: t.text == 'Hello robot     \nScore: 42       ', 3.0)
        self.assertIsNotNone(t, 'LCD shows %r' % (self.truth.last().text,))
        self.assertEqual(list(self.state.last().lcd_lines), ['Hello robot     ', 'Score: 42       '])

    def test_3_lcd_is_rewritten_after_a_reset(self):
        bus = CanUdp(PORT)
        bus.send(0x000, bytes([0x81, NODE]))  # the board reboots: its LCD is blank
        t = self.truth.wait_for(lambda t: t.resets >= 1 and t.text == 'Hello robot     \nScore: 42       ', 5.0)
        self.assertIsNotNone(t, 'LCD not restored after the reset: %r' % (self.truth.last().text,))
        self.assertGreaterEqual(self.state.last().node.boot_ups, 1)
        bus.close()


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'can_hmi_board', HmiBoardTest)
