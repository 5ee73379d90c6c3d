#!/usr/bin/env python3
"""CAN human interface board driver (hcl_drivers/HmiBoard) against its emulator over CAN-over-UDP."""
import time
import unittest

import rospy
import rostest
from hcl_drivers.msg import DigitalInputs, HmiBoardState
from diagnostic_msgs.msg import DiagnosticStatus
from robot_sim.msg import CanFirmware
from robot_sim.srv import InjectFault
from std_msgs.msg import String

from can_test_common import CanUdp, Diagnostics, Recorder, value

PORT, NODE = 27014, 13


class HmiBoardTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_can_hmi_board')
        cls.state = Recorder('/hcl/hmi_board/state', HmiBoardState)
        cls.inputs = Recorder('/hcl/hmi_board/inputs', DigitalInputs)
        cls.truth = Recorder('/sim/hmi_board/firmware', CanFirmware)
        cls.diag = Diagnostics()
        cls.inject = rospy.ServiceProxy('/sim/hmi_board/inject_fault', InjectFault)
        cls.lcd = rospy.Publisher('/hcl/hmi_board/lcd', String, queue_size=1, latch=True)
        assert cls.state.wait_for(lambda m: m.node.answering, 30.0), 'the HMI board never answered'

    def test_1_keypad(self):
        m = self.state.wait_for(lambda m: m.keys == 1 << 5, 2.0)
        self.assertIsNotNone(m, 'key 5 held on the bench')
        self.assertEqual(m.last_key, 5)
        self.assertEqual(m.key_presses, 1)
        # /inputs and /state travel on different connections: wait for the inputs (bounded).
        i = self.inputs.wait_for(lambda i: i.bits == 1 << 5, 2.0)
        self.assertIsNotNone(i, 'key 5 not on ~inputs: %r' % (self.inputs.last(),))
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

    def test_4_a_silent_heartbeat_is_stale_before_the_pdos(self):
        s = self.diag.wait_status('/hcl/hmi_board', lambda s: value(s, 'NMT state (heartbeat)') == 'operational', 5.0)
        self.assertIsNotNone(s, 'no heartbeat state on /diagnostics')
        self.assertEqual(value(s, 'heartbeat producer time [ms]'), '50')
        self.assertLess(float(value(s, 'heartbeat age [ms]')), 200.0)
        self.assertTrue(self.inject(kind='board_silent', clear=False).ok)
        t0 = time.monotonic()
        try:
            s = self.diag.wait_status('/hcl/hmi_board', lambda s: s.level == DiagnosticStatus.STALE, 3.0)
            stale_after = time.monotonic() - t0
            self.assertIsNotNone(s, 'a silent board never reported STALE')
            self.assertIn('no heartbeat', s.message)
            # ~stale_timeout (PDOs) is 2.0 s; the heartbeat timeout 0.2 s, and a level change is said at once.
            self.assertLess(stale_after, 1.5, 'reported only after %.2f s' % stale_after)
            m = self.state.wait_for(lambda m: not m.node.answering, 1.5 - (time.monotonic() - t0))
            self.assertIsNotNone(m, 'commands still accepted without a heartbeat')
        finally:
            self.inject(kind='board_silent', clear=True)
        m = self.state.wait_for(lambda m: m.node.answering, 5.0)
        self.assertIsNotNone(m, 'not answering again after the heartbeat came back')
        s = self.diag.wait_status('/hcl/hmi_board', lambda s: s.level == DiagnosticStatus.OK, 5.0)
        self.assertEqual(s.level, DiagnosticStatus.OK, s.message)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'can_hmi_board', HmiBoardTest)
