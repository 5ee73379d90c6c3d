#!/usr/bin/env python3
"""EPOS driver (hcl_drivers/Epos) against its emulator over CAN-over-UDP: DS-402 enable,
velocity, feedback on a non-default COB-ID, fault and fault reset, unplugging."""
import time
import unittest

import rospy
import rosnode
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from hcl_drivers.msg import EncoderCounter, EposState, MotorCommand
from robot_sim.msg import CanFirmware
from robot_sim.srv import InjectFault
from std_srvs.srv import SetBool, Trigger

from can_test_common import Diagnostics, Recorder, truth_value


class EposTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_can_epos')
        cls.state = Recorder('/hcl/epos/state', EposState)
        cls.encoder = Recorder('/hcl/epos/encoder/turret', EncoderCounter)
        cls.truth = Recorder('/sim/epos/firmware', CanFirmware)
        cls.diag = Diagnostics()
        cls.cmd = rospy.Publisher('/hcl/epos/motor/turret/command', MotorCommand, queue_size=1)
        assert cls.state.wait_for(lambda m: m.node.answering, 30.0), 'the EPOS never answered'
        rospy.wait_for_service('/hcl/epos/enable', 10)
        cls.enable = rospy.ServiceProxy('/hcl/epos/enable', SetBool)
        cls.fault_reset = rospy.ServiceProxy('/hcl/epos/fault_reset', Trigger)
        cls.inject = rospy.ServiceProxy('/sim/epos/inject_fault', InjectFault)

    def drive(self, rpm, duration):
        end = time.monotonic() + duration
        while time.monotonic() < end:
            self.cmd.publish(MotorCommand(header=rospy.Header(stamp=rospy.Time.now()), name='turret', value=rpm))
            time.sleep(0.05)

    def test_1_configured_and_disabled_at_start(self):
        m = self.state.last()
        self.assertEqual(m.mode_display, 3, 'profile velocity mode written by SDO')
        self.assertEqual(m.drive_state, 'ready-to-switch-on')
        self.assertFalse(m.enable_requested)

    def test_2_enable_and_velocity(self):
        self.assertTrue(self.enable(True).success)
        m = self.state.wait_for(lambda m: m.drive_state == 'operation-enabled', 3.0)
        self.assertIsNotNone(m, 'DS-402 enable sequence did not reach operation-enabled: %s' % self.state.last())
        p0 = self.encoder.last().raw
        self.drive(4000, 1.5)
        m = self.state.last()
        self.assertEqual(m.target_rpm, 4000)
        self.assertGreater(m.velocity_rpm, 0)
        self.assertGreater(self.encoder.last().raw - p0, 500, 'position actual (0x381 PDO) must count')
        self.assertEqual(truth_value(self.truth.last(), 'target_rpm'), 4000)

    def test_3_stale_velocity_command_is_zeroed(self):
        self.drive(3000, 0.5)
        t = self.truth.wait_for(lambda t: truth_value(t, 'target_rpm') == 0, 2.0)
        self.assertIsNotNone(t, 'EPOS kept a stale velocity')

    def test_4_fault_is_reported_and_reset_on_request_only(self):
        self.assertTrue(self.inject(kind='epos_fault', clear=False).ok)
        m = self.state.wait_for(lambda m: m.fault, 3.0)
        self.assertIsNotNone(m, 'fault not on the state topic')
        self.assertEqual(m.drive_state, 'fault')
        self.assertEqual(m.error_code, 0x3210)
        self.assertEqual(m.target_rpm, 0)
        s = self.diag.wait_status('/hcl/epos', lambda s: s.level >= DiagnosticStatus.ERROR, 3.0)
        self.assertGreaterEqual(s.level, DiagnosticStatus.ERROR)
        time.sleep(0.5)
        self.assertTrue(self.state.last().fault, 'never reset a fault automatically')
        self.assertTrue(self.fault_reset().success)
        m = self.state.wait_for(lambda m: not m.fault and m.drive_state == 'operation-enabled', 3.0)
        self.assertIsNotNone(m, 'fault reset + enable request did not bring the drive back: %s' % self.state.last())

    def test_5_disable(self):
        self.assertTrue(self.enable(False).success)
        m = self.state.wait_for(lambda m: m.drive_state == 'ready-to-switch-on', 3.0)
        self.assertIsNotNone(m)

    def test_6_unplugged_drive_is_stale_and_refuses_enable(self):
        rosnode.kill_nodes(['/firmware'])
        m = self.state.wait_for(lambda m: not m.node.answering, 5.0)
        self.assertIsNotNone(m)
        s = self.diag.wait_status('/hcl/epos', lambda s: s.level == DiagnosticStatus.STALE, 5.0)
        self.assertEqual(s.level, DiagnosticStatus.STALE)
        r = self.enable(True)
        self.assertFalse(r.success)
        self.assertIn('not answering', r.message)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'can_epos', EposTest)
