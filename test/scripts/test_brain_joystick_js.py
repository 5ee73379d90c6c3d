#!/usr/bin/env python3
"""The joystick strategy from real js_event input (test/launch/brain_joystick_js.test): raw
stick and button values go into the simulator's joystick emulator, which writes struct
js_event into the FIFO the HCL Joystick driver reads; HAL names them; the brain drives.
Raw values are Linux's: -32767..32767, stick forward is negative on the xpad's Y axes."""
import sys
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist
from std_msgs.msg import Bool, Int16MultiArray, UInt8MultiArray
from test_support import Recorder, wait_for

AXES = 6       # xpad: left_x 0, left_y 1, lt 2, right_x 3, right_y 4, rt 5
BUTTONS = 12   # a 0, b 1, x 2, y 3, lb 4, rb 5, back 6, start 7
LB, BACK, START = 4, 6, 7


class JoystickJsEventTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_brain_joystick_js')
        cls.cmd = Recorder('/hal/drive/cmd_vel', Twist, queue_size=200)
        cls.deactivated = Recorder('/effectors/deactivated', Bool, queue_size=200)
        cls.diagnostics = Recorder('/diagnostics', DiagnosticArray, queue_size=1000)
        cls.axes = rospy.Publisher('/sim/js/axes', Int16MultiArray, queue_size=10)
        cls.buttons = rospy.Publisher('/sim/js/buttons', UInt8MultiArray, queue_size=10)
        assert wait_for(lambda: cls.axes.get_num_connections() and cls.buttons.get_num_connections(), 40.0, step=0.02), \
            'the joystick emulator is not up'
        assert wait_for(lambda: cls.cmd.last() is not None, 40.0, step=0.02), 'the brain never commanded the drive'
        assert wait_for(lambda: cls.deactivated.last() is not None, 10.0, step=0.02), 'hal_node not up'

    def pad(self, left_y=0, right_x=0, buttons=()):
        axes = [0] * AXES
        axes[1], axes[3] = left_y, right_x
        pressed = [1 if i in buttons else 0 for i in range(BUTTONS)]
        self.buttons.publish(UInt8MultiArray(data=pressed))
        self.axes.publish(Int16MultiArray(data=axes))

    def test_1_stick_forward_with_the_deadman_drives_forward(self):
        t0 = time.monotonic()
        # Full deflections: both layers' dead zones (HCL deadzone, HAL dead_zone) rescale to 1 there.
        self.pad(left_y=-32767, right_x=32767, buttons=(LB,))   # left stick forward, right stick right
        ok = wait_for(lambda: any(abs(m.linear.x - 0.5) < 0.01 and abs(m.angular.z + 2.0) < 0.03
                                  for m in self.cmd.messages(t0)), 3.0, step=0.02)
        self.assertTrue(ok, 'expected 0.5 m/s, -2.0 rad/s (turning right) from js_events; got %s' % self.cmd.last())

    def test_2_releasing_the_deadman_stops(self):
        self.pad(left_y=-32767, buttons=(LB,))
        self.assertTrue(wait_for(lambda: abs(self.cmd.last().linear.x - 0.5) < 0.01, 3.0, step=0.02))
        t0 = time.monotonic()
        self.pad(left_y=-32767)      # lb released, stick still forward
        self.assertTrue(wait_for(lambda: any(m.linear.x == 0.0 for m in self.cmd.messages(t0)), 2.0, step=0.02),
                        'still driving after the deadman was released: %s' % self.cmd.last())
        time.sleep(0.3)
        t1 = time.monotonic()
        time.sleep(0.5)
        self.assertTrue(all(m.linear.x == 0.0 and m.angular.z == 0.0 for m in self.cmd.messages(t1)))

    def test_3_buttons_call_effector_callbacks(self):
        self.pad(buttons=(BACK,))
        self.assertTrue(wait_for(lambda: self.deactivated.last().data, 3.0, step=0.02), 'back did not deactivate the effectors')
        self.pad()
        self.pad(buttons=(START,))
        self.assertTrue(wait_for(lambda: not self.deactivated.last().data, 3.0, step=0.02), 'start did not activate them')
        self.pad()


    def test_4_a_pad_unplugged_while_driving_stops_the_robot_and_replugging_drives_again(self):
        from diagnostic_msgs.msg import DiagnosticStatus
        from std_srvs.srv import SetBool
        max_age = rospy.get_param('/brain/joystick/max_age')
        rospy.wait_for_service('/sim/js/plugged', 10.0)
        plug = rospy.ServiceProxy('/sim/js/plugged', SetBool)
        self.pad(left_y=-32767, buttons=(LB,))
        self.assertTrue(wait_for(lambda: abs(self.cmd.last().linear.x - 0.5) < 0.01, 3.0, step=0.02))
        t0 = time.monotonic()
        self.assertTrue(plug(False).success)
        # Stopped within the brain's command timeout (its ~joystick/max_age) of the unplug.
        self.assertTrue(wait_for(lambda: any(m.linear.x == 0.0 for m in self.cmd.messages(t0)), max_age, step=0.01),
                        'still driving %.1f s after the pad was unplugged: %s' % (max_age, self.cmd.last()))
        # ... and /diagnostics names the pad.
        def pad_errors():
            return ['%s: %s' % (s.name, s.message) for _, arr in self.diagnostics.since(t0) for s in arr.status
                    if s.level >= DiagnosticStatus.ERROR and 'hcl/joystick' in s.name]
        self.assertTrue(wait_for(pad_errors, 3.0), 'no ERROR on /diagnostics for the unplugged pad')
        print('unplugged: %s' % sorted(set(pad_errors())))
        time.sleep(0.5)
        t1 = time.monotonic()
        time.sleep(0.5)
        self.assertTrue(all(m.linear.x == 0.0 for m in self.cmd.messages(t1)), 'drove with the pad unplugged')
        # Plugged back in (no restart): the kernel's init events give the held stick, and it drives.
        self.assertTrue(plug(True).success)
        self.pad(left_y=-32767, buttons=(LB,))
        self.assertTrue(wait_for(lambda: abs(self.cmd.last().linear.x - 0.5) < 0.01, 5.0, step=0.02),
                        'the replugged pad does not drive: %s' % self.cmd.last())
        self.pad()

    def test_5_a_pad_that_stops_sending_stops_the_robot(self):
        """The HCL's joystick board stalls (its process stopped: nothing comes from the pad any
        more, as with a board whose loop hangs): the HAL device goes stale and says so, the
        brain stops within its command timeout of the pad's last data, and it drives again once
        the input is back."""
        import os
        import signal
        import rosgraph
        import xmlrpc.client
        from diagnostic_msgs.msg import DiagnosticStatus
        max_age = rospy.get_param('/brain/joystick/max_age')
        device_age = rospy.get_param('/hal/joystick/max_input_age', 0.5)
        # The pad's data ages from its stamp in both layers: stopped within the larger of their
        # timeouts (not their sum), one brain period to notice and one of scheduling slack for
        # a loaded machine, plus this test's polling.
        limit = max(max_age, device_age) + 3.0 / rospy.get_param('/brain/rate')
        uri = rosgraph.Master('/test_brain_joystick_js').lookupNode('/hcl')
        pid = xmlrpc.client.ServerProxy(uri).getPid('/test_brain_joystick_js')[2]
        self.pad(left_y=-32767, buttons=(LB,))
        self.assertTrue(wait_for(lambda: abs(self.cmd.last().linear.x - 0.5) < 0.01, 3.0, step=0.02))
        t0 = time.monotonic()
        os.kill(pid, signal.SIGSTOP)
        try:
            stopped = wait_for(lambda: any(m.linear.x == 0.0 for m in self.cmd.messages(t0)), limit, step=0.01)
            named = wait_for(lambda: any(s.level >= DiagnosticStatus.ERROR and 'hal/joystick' in s.name and
                                         'no fresh joystick state' in s.message
                                         for _, arr in self.diagnostics.since(t0) for s in arr.status), 3.0)
        finally:
            os.kill(pid, signal.SIGCONT)
        zero_at = next((t for t, m in self.cmd.since(t0) if m.linear.x == 0.0), None)
        print('stopped sending: zero speed %.3f s after the HCL stalled (limit %.2f s)'
              % ((zero_at - t0) if zero_at else float('nan'), limit))
        self.assertTrue(stopped, 'still driving %.1f s after the pad stopped sending: %s' % (limit, self.cmd.last()))
        self.assertTrue(named, 'no ERROR on /diagnostics saying the joystick input is stale')
        self.pad(left_y=-32767, buttons=(LB,))
        self.assertTrue(wait_for(lambda: abs(self.cmd.last().linear.x - 0.5) < 0.01, 5.0, step=0.02),
                        'the pad does not drive once it sends again: %s' % self.cmd.last())
        self.pad()


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'brain_joystick_js', JoystickJsEventTest, sys.argv)
