#!/usr/bin/env python3
"""The joystick strategy (test/launch/brain_joystick.test): axes scaled to speeds, the
deadman button, zero speed when the pad goes stale, buttons calling effector callbacks."""
import sys
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from hal_nodes.msg import JoystickEvent, JoystickState
from std_msgs.msg import Bool
from test_support import Recorder, wait_for

AXES = ['left_x', 'left_y', 'right_x', 'right_y']
BUTTONS = ['a', 'b', 'lb', 'back', 'start']


class JoystickTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_brain_joystick')
        cls.cmd = Recorder('/hal/drive/cmd_vel', Twist, queue_size=200)
        cls.deactivated = Recorder('/effectors/deactivated', Bool, queue_size=200)
        cls.state_pub = rospy.Publisher('/hal/joystick/state', JoystickState, queue_size=1)
        cls.event_pub = rospy.Publisher('/hal/joystick/events', JoystickEvent, queue_size=10)
        cls.pad = {'axes': [0.0] * 4, 'buttons': [False] * 5, 'on': True}
        threading.Thread(target=cls._pad_loop, daemon=True).start()
        assert wait_for(lambda: cls.cmd.last() is not None, 40.0, step=0.02), 'the brain never commanded the drive'
        assert wait_for(lambda: cls.deactivated.last() is not None, 10.0, step=0.02), 'hal_node not up'

    @classmethod
    def _pad_loop(cls):
        while not rospy.is_shutdown():
            if cls.pad['on']:
                m = JoystickState(axis_names=AXES, axes=list(cls.pad['axes']), button_names=BUTTONS,
                                  buttons=list(cls.pad['buttons']))
                m.header.stamp = rospy.Time.now()
                cls.state_pub.publish(m)
            time.sleep(0.05)

    def set_pad(self, left_y=0.0, right_x=0.0, deadman=True):
        self.pad['axes'] = [0.0, left_y, right_x, 0.0]
        self.pad['buttons'] = [False, False, deadman, False, False]

    def test_1_axes_drive_with_the_deadman_held(self):
        self.set_pad(left_y=0.5, right_x=-0.25)
        t0 = time.monotonic()
        # right_x -0.25 is the stick a quarter to the left: turn left, +0.5 rad/s (REP-103)
        ok = wait_for(lambda: any(abs(m.linear.x - 0.25) < 1e-6 and abs(m.angular.z - 0.5) < 1e-6
                                  for m in self.cmd.messages(t0)), 2.0, step=0.02)
        self.assertTrue(ok, 'expected 0.25 m/s, 0.5 rad/s; got %s' % self.cmd.last())

    def test_2_releasing_the_deadman_stops(self):
        self.set_pad(left_y=1.0, deadman=False)
        time.sleep(0.3)
        t0 = time.monotonic()
        time.sleep(0.5)
        cmds = self.cmd.messages(t0)
        self.assertTrue(cmds)
        self.assertTrue(all(m.linear.x == 0.0 and m.angular.z == 0.0 for m in cmds))

    def test_3_a_stale_pad_gives_zero_speed(self):
        self.set_pad(left_y=1.0)
        time.sleep(0.3)
        self.pad['on'] = False
        t0 = time.monotonic()
        ok = wait_for(lambda: any(m.linear.x == 0.0 for m in self.cmd.messages(t0)), 1.0, step=0.02)
        self.pad['on'] = True
        self.assertTrue(ok, 'no zero speed within 1 s of the pad going silent')

    def test_4_buttons_call_effector_callbacks(self):
        self.event_pub.publish(JoystickEvent(button='back', pressed=True))
        self.assertTrue(wait_for(lambda: self.deactivated.last().data, 2.0, step=0.02), 'back did not deactivate the effectors')
        self.event_pub.publish(JoystickEvent(button='back', pressed=False))
        self.event_pub.publish(JoystickEvent(button='start', pressed=True))
        self.assertTrue(wait_for(lambda: not self.deactivated.last().data, 2.0, step=0.02), 'start did not activate them')


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'brain_joystick', JoystickTest, sys.argv)
