#!/usr/bin/env python3
"""CAN stepper board driver (hcl_drivers/StepperBoard) against its emulator over CAN-over-UDP."""
import unittest

import rospy
import rosnode
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from hcl_drivers.msg import DigitalInputs, StepperBoardState
from std_msgs.msg import Int32

from can_test_common import Diagnostics, Recorder, value


class StepperBoardTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_can_stepper_board')
        cls.state = Recorder('/hcl/stepper_board/state', StepperBoardState)
        cls.inputs = Recorder('/hcl/stepper_board/inputs', DigitalInputs)
        cls.diag = Diagnostics()
        cls.target = rospy.Publisher('/hcl/stepper_board/stepper/lift_left/target', Int32, queue_size=1, latch=True)
        assert cls.state.wait_for(lambda m: m.node.answering, 30.0), 'the stepper board never answered'

    def test_1_at_rest_on_the_min_end_switch(self):
        m = self.state.last()
        self.assertEqual(list(m.stepper_names), ['lift_left', 'lift_right'])
        self.assertEqual(list(m.position), [0, 0])
        i = self.inputs.wait_for(lambda i: i.bits & 0x5 == 0x5, 2.0)
        self.assertIsNotNone(i, 'both min end switches should be closed at 0 steps')
        self.assertEqual(list(i.names), ['lift_left_min', 'lift_left_max', 'lift_right_min', 'lift_right_max'])

    def test_2_a_target_moves_the_stepper(self):
        self.target.publish(Int32(3000))
        m = self.state.wait_for(lambda m: m.position[0] == 3000 and not m.moving[0], 5.0)
        self.assertIsNotNone(m, 'stepper did not reach its target: %s' % self.state.last())
        self.assertEqual(m.target[0], 3000)
        self.assertEqual(m.position[1], 0, 'the other stepper must not move')
        self.assertIsNotNone(self.inputs.wait_for(lambda i: i.bits & 0x1 == 0, 1.0), 'min switch still closed')

    def test_3_the_end_switch_stops_it(self):
        self.target.publish(Int32(-5000))
        m = self.state.wait_for(lambda m: m.position[0] == 0 and not m.moving[0], 5.0)
        self.assertIsNotNone(m, 'stepper did not stop at its min end switch: %s' % self.state.last())
        self.assertEqual(m.end_switches & 0x1, 1)

    def test_4_unplugged_board_goes_stale_and_refuses_targets(self):
        rosnode.kill_nodes(['/firmware'])
        m = self.state.wait_for(lambda m: not m.node.answering, 5.0)
        self.assertIsNotNone(m, 'state topic does not show the board is gone')
        s = self.diag.wait_status('/hcl/stepper_board', lambda s: s.level == DiagnosticStatus.STALE, 5.0)
        self.assertEqual(s.level, DiagnosticStatus.STALE, s.message)
        refused = int(value(s, 'commands refused'))
        self.target.publish(Int32(100))
        s = self.diag.wait_status('/hcl/stepper_board', lambda s: int(value(s, 'commands refused')) > refused, 3.0)
        self.assertGreater(int(value(s, 'commands refused')), refused, 'a target for an unplugged board was not refused')


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'can_stepper_board', StepperBoardTest)
