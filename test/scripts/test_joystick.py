#!/usr/bin/env python3
"""Joystick driver against the emulated js_event FIFO."""
import sys
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hcl_drivers.msg import JoystickState
from sensor_msgs.msg import Joy
from std_msgs.msg import Int16MultiArray, UInt8MultiArray
from std_srvs.srv import SetBool
from test_support import Recorder, wait_for


class JoystickTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_joystick')
        cls.joy = Recorder('/hcl/joystick/joy', Joy, queue_size=1000)
        cls.state = Recorder('/hcl/joystick/state', JoystickState, queue_size=1000)
        cls.diagnostics = Recorder('/diagnostics', DiagnosticArray, queue_size=1000)
        cls.axes = rospy.Publisher('/sim/js/axes', Int16MultiArray, queue_size=10)
        cls.buttons = rospy.Publisher('/sim/js/buttons', UInt8MultiArray, queue_size=10)
        rospy.wait_for_service('/sim/js/plugged', 30.0)
        cls.plug = rospy.ServiceProxy('/sim/js/plugged', SetBool)
        assert wait_for(lambda: cls.joy.last() is not None, 30.0), 'no Joy'
        assert wait_for(lambda: cls.axes.get_num_connections() and cls.buttons.get_num_connections(), 10.0)

    def set_buttons(self, values):
        self.buttons.publish(UInt8MultiArray(data=values))

    def set_axes(self, values):
        self.axes.publish(Int16MultiArray(data=values))

    def level(self, t0):
        out = None
        for _, arr in self.diagnostics.since(t0):
            for s in arr.status:
                if 'hcl/joystick:' in s.name:
                    out = s
        return out

    def test_1_init_events_give_the_full_stick_and_idle_repeats_at_the_publish_rate(self):
        j = self.joy.last()
        self.assertEqual(len(j.axes), 4)
        self.assertEqual(len(j.buttons), 6)
        t0 = time.monotonic()
        time.sleep(2.0)
        n = len(self.joy.since(t0))
        self.assertAlmostEqual(n / 2.0, 5.0, delta=1.5)

    def test_2_press_is_published_on_change(self):
        t0 = time.monotonic()
        self.set_buttons([0, 0, 1, 0, 0, 0])
        self.assertTrue(wait_for(lambda: self.joy.last().buttons[2] == 1, 1.0))
        # On change, not on the 5 Hz repeat: well under 200 ms.
        first = [t for t, m in self.joy.since(t0) if m.buttons[2] == 1][0]
        self.assertLess(first - t0, 0.1)
        self.set_buttons([0] * 6)
        self.assertTrue(wait_for(lambda: self.joy.last().buttons[2] == 0, 1.0))

    def test_3_axes_with_deadzone(self):
        self.set_axes([2000, 16384, -32767, 0])
        self.assertTrue(wait_for(lambda: abs(self.joy.last().axes[1] - (0.5 - 0.1) / 0.9) < 1e-3, 1.0),
                        self.joy.last().axes)
        a = self.joy.last().axes
        self.assertEqual(a[0], 0.0)  # 2000/32767 = 0.06 is inside the 0.1 deadzone
        self.assertAlmostEqual(a[2], -1.0, places=5)

    def test_4_unplug_releases_everything_and_replug_restores_the_state(self):
        self.set_axes([0, 16384, 0, 0])
        self.set_buttons([1, 0, 0, 0, 0, 0])
        self.assertTrue(wait_for(lambda: self.joy.last().buttons[0] == 1, 1.0))
        t0 = time.monotonic()
        self.plug(False)
        self.assertTrue(wait_for(lambda: self.joy.last().buttons[0] == 0 and self.joy.last().axes[1] == 0.0, 1.0),
                        'a vanished joystick must not keep a button pressed')
        self.assertTrue(wait_for(lambda: not self.state.last().connected, 1.0))
        self.assertTrue(wait_for(lambda: self.level(t0 + 0.3) is not None and
                                 self.level(t0 + 0.3).level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE), 2.0))
        reconnects = self.state.last().reconnects
        t1 = time.monotonic()
        self.plug(True)
        # The init events on reopen bring back the true state (button still held, axis still out).
        self.assertTrue(wait_for(lambda: self.joy.last().buttons[0] == 1, 3.0))
        self.assertAlmostEqual(self.joy.last().axes[1], (0.5 - 0.1) / 0.9, places=3)
        self.assertTrue(wait_for(lambda: self.state.last().connected, 1.0))
        self.assertGreater(self.state.last().reconnects, reconnects)
        self.assertTrue(wait_for(lambda: self.level(t1 + 0.5) is not None and
                                 self.level(t1 + 0.5).level == DiagnosticStatus.OK, 3.0))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'joystick', JoystickTest, sys.argv)
