#!/usr/bin/env python3
"""CAN motor board driver (hcl_drivers/MotorBoard) against its emulator over CAN-over-UDP."""
import struct
import time
import unittest

import rospy
import rosnode
import rostest
from diagnostic_msgs.msg import DiagnosticStatus
from hcl_drivers.msg import EncoderCounter, MotorBoardState, MotorCommand
from robot_sim.msg import CanFirmware

from can_test_common import CanUdp, Diagnostics, Recorder, ERR_BUSOFF, ERR_RESTARTED, truth_value, value

PORT, NODE = 27010, 10


def signed(u):
    return u - (1 << 32) if u >= (1 << 31) else u


class MotorBoardTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_can_motor_board')
        cls.state = Recorder('/hcl/motor_board/state', MotorBoardState)
        cls.encoder = Recorder('/hcl/motor_board/encoder/left', EncoderCounter)
        cls.truth = Recorder('/sim/motor_board/firmware', CanFirmware)
        cls.diag = Diagnostics()
        cls.left = rospy.Publisher('/hcl/motor_board/motor/left/command', MotorCommand, queue_size=1)
        cls.right = rospy.Publisher('/hcl/motor_board/motor/right/command', MotorCommand, queue_size=1)
        assert cls.state.wait_for(lambda m: m.node.answering, 30.0), 'the motor board never answered'
        cls.bus = CanUdp(PORT)

    def command(self, left, right, duration):
        end = time.monotonic() + duration
        while time.monotonic() < end:
            for pub, v, name in ((self.left, left, 'left'), (self.right, right, 'right')):
                pub.publish(MotorCommand(header=rospy.Header(stamp=rospy.Time.now()), name=name, value=v))
            time.sleep(0.05)

    def test_1_polls_at_the_configured_rate(self):
        s = self.diag.wait_status('/hcl/motor_board', lambda s: float(value(s, 'achieved rate [Hz]') or 0) > 90, 10.0)
        self.assertIsNotNone(s)
        self.assertGreater(float(value(s, 'achieved rate [Hz]')), 90.0)
        self.assertEqual(s.level, DiagnosticStatus.OK, s.message)
        m = self.state.last()
        self.assertEqual(m.node.nmt_state, 'operational')
        self.assertEqual(m.node.bus_state, 'error-active')
        # 0x1008 is 21 bytes: the driver read it by segmented SDO at configuration.
        self.assertEqual(value(s, 'device name'), 'robot_sim motor_board')

    def test_2_commands_drive_the_firmware_and_encoders_count(self):
        e0 = self.encoder.last().raw
        s0 = self.state.last().encoder_raw[1]
        self.command(500, -300, 1.0)
        t = self.truth.last()
        self.assertEqual(truth_value(t, 'pwm0'), 500)
        self.assertEqual(truth_value(t, 'pwm1'), -300)
        m = self.state.last()
        self.assertEqual(list(m.pwm_applied), [500, -300])
        self.assertEqual(list(m.pwm_commanded), [500, -300])
        # bench world: 4000 ticks/s at full duty
        self.assertGreater(signed((self.encoder.last().raw - e0) & 0xFFFFFFFF), 1000)
        self.assertLess(signed((m.encoder_raw[1] - s0) & 0xFFFFFFFF), -600)
        self.assertEqual(self.encoder.last().bits, 32)

    def test_3_a_stale_command_stops_the_motor(self):
        self.command(400, 400, 0.5)
        t_stop = time.monotonic()
        stopped = self.truth.wait_for(lambda t: truth_value(t, 'pwm0') == 0 and truth_value(t, 'pwm1') == 0, 2.0)
        self.assertIsNotNone(stopped, 'the driver kept driving on a stale command')
        self.assertLess(time.monotonic() - t_stop, 0.25 + 0.25)
        self.assertEqual(truth_value(stopped, 'watchdog_stopped'), 0, 'the driver, not the firmware, must stop it')

    def test_4_malformed_and_unknown_frames_are_counted_and_dropped(self):
        before = self.state.last().node
        self.bus.send(0x180 + NODE, b'\x01\x02\x03')  # TPDO1 of the wrong length
        self.bus.send(0x480 + NODE, b'\x01')           # a COB-ID the driver does not know
        m = self.state.wait_for(lambda m: m.node.malformed_frames > before.malformed_frames and
                                m.node.unknown_frames > before.unknown_frames, 3.0)
        self.assertIsNotNone(m, 'malformed/unknown frames not counted')
        self.assertTrue(self.state.wait_for(lambda m: m.node.answering, 1.0))

    def test_5_a_reset_board_is_restarted(self):
        self.bus.send(0x000, bytes([0x81, NODE]))  # NMT reset node: the firmware reboots
        m = self.state.wait_for(lambda m: m.node.boot_ups >= 1 and m.node.answering, 5.0)
        self.assertIsNotNone(m, 'boot-up not noticed')
        self.assertEqual(m.node.nmt_state, 'operational')
        self.assertIsNotNone(self.encoder.wait_for(lambda e: e.board_resets >= 1, 2.0))
        t = self.truth.wait_for(lambda t: t.resets >= 1 and t.nmt_state == 'operational', 2.0)
        self.assertIsNotNone(t, 'the driver did not start the node again')

    def test_6_bus_off_is_reported_and_recovers(self):
        self.bus.send(ERR_BUSOFF, dlc=8, error=True)
        m = self.state.wait_for(lambda m: m.node.bus_state == 'bus-off', 3.0)
        self.assertIsNotNone(m, 'bus-off not on the state topic')
        s = self.diag.wait_status('/hcl/motor_board', lambda s: 'bus-off' in s.message, 3.0)
        self.assertIn('bus-off', s.message)
        self.assertGreaterEqual(s.level, DiagnosticStatus.ERROR)
        self.bus.send(ERR_RESTARTED, dlc=8, error=True)
        m = self.state.wait_for(lambda m: m.node.bus_state == 'error-active' and m.node.answering, 5.0)
        self.assertIsNotNone(m, 'no recovery after the controller restarted')
        s = self.diag.wait_status('/hcl/motor_board', lambda s: s.level == DiagnosticStatus.OK, 5.0)
        self.assertEqual(s.level, DiagnosticStatus.OK, s.message)

    def test_6b_a_bus_off_shorter_than_the_report_period_is_still_reported(self):
        # The controller restarts 50 ms after going bus-off: between two 1 Hz diagnostics reports.
        self.assertIsNotNone(self.diag.wait_status('/hcl/motor_board', lambda s: s.level == DiagnosticStatus.OK, 5.0))
        self.bus.send(ERR_BUSOFF, dlc=8, error=True)
        time.sleep(0.05)
        self.bus.send(ERR_RESTARTED, dlc=8, error=True)
        s = self.diag.wait_status('/hcl/motor_board', lambda s: 'bus-off' in s.message, 3.0)
        self.assertIsNotNone(s, 'a short bus-off never reached /diagnostics')
        self.assertGreaterEqual(s.level, DiagnosticStatus.ERROR)
        s = self.diag.wait_status('/hcl/motor_board', lambda s: s.level == DiagnosticStatus.OK, 5.0)
        self.assertEqual(s.level, DiagnosticStatus.OK, s.message)

    def test_7_the_firmware_watchdog_stops_the_motor_without_a_driver(self):
        rosnode.kill_nodes(['/hcl'])
        time.sleep(1.0)
        self.bus.send(0x000, bytes([0x01, NODE]))                       # keep it operational
        self.bus.send(0x200 + NODE, struct.pack('<hh', 600, 0))         # one command, then silence
        t_cmd = time.monotonic()
        driving = self.truth.wait_for(lambda t: truth_value(t, 'pwm0') == 600, 1.0)
        self.assertIsNotNone(driving, 'the injected command did not reach the firmware')
        stopped = self.truth.wait_for(lambda t: truth_value(t, 'pwm0') == 0 and truth_value(t, 'watchdog_stopped') == 1, 2.0)
        self.assertIsNotNone(stopped, 'the firmware kept the motor running without commands')
        self.assertLess(time.monotonic() - t_cmd, 0.2 + 0.2)

    def sdo(self, request, timeout=1.0):
        """One SDO request (8 bytes) to the emulator's server; its 8-byte answer, or None."""
        t0 = time.monotonic()
        self.bus.send(0x600 + NODE, bytes(request))
        end = t0 + timeout
        while time.monotonic() < end:
            answers = self.bus.seen(t0, 0x580 + NODE)
            if answers:
                return bytes(answers[0][3])
            time.sleep(0.005)
        return None

    def test_8_segmented_sdo_in_the_emulator(self):
        # After test_7 no driver is on the bus: this test is the SDO client, byte-exact (CiA 301).
        name = b'robot_sim motor_board'
        self.assertEqual(self.sdo([0x40, 0x08, 0x10, 0, 0, 0, 0, 0]), bytes([0x41, 0x08, 0x10, 0, len(name), 0, 0, 0]))
        self.assertEqual(self.sdo([0x60] + [0] * 7), bytes([0x00]) + name[0:7])            # t=0, 7 bytes
        self.assertEqual(self.sdo([0x70] + [0] * 7), bytes([0x10]) + name[7:14])           # t=1
        self.assertEqual(self.sdo([0x60] + [0] * 7), bytes([0x01]) + name[14:21])          # t=0, n=0, c=1
        # Segmented download of 10 bytes into the user label 0x2100, then read back.
        label = b'left+right'
        self.assertEqual(self.sdo([0x21, 0x00, 0x21, 0, 10, 0, 0, 0]), bytes([0x60, 0x00, 0x21, 0, 0, 0, 0, 0]))
        self.assertEqual(self.sdo(bytes([0x00]) + label[:7]), bytes([0x20] + [0] * 7))
        self.assertEqual(self.sdo(bytes([0x10 | (4 << 1) | 1]) + label[7:] + bytes(4)), bytes([0x30] + [0] * 7))
        self.assertEqual(self.sdo([0x40, 0x00, 0x21, 0, 0, 0, 0, 0]), bytes([0x41, 0x00, 0x21, 0, 10, 0, 0, 0]))
        self.assertEqual(self.sdo([0x60] + [0] * 7), bytes([0x00]) + label[:7])
        self.assertEqual(self.sdo([0x70] + [0] * 7), bytes([0x19]) + label[7:] + bytes(4))  # t=1, 3 bytes: n=4, c=1
        # A toggle error aborts with 0x05030000; a segment without a transfer with 0x05040001.
        self.assertEqual(self.sdo([0x40, 0x08, 0x10, 0, 0, 0, 0, 0])[0], 0x41)
        self.assertEqual(self.sdo([0x70] + [0] * 7), bytes([0x80, 0x08, 0x10, 0, 0x00, 0x00, 0x03, 0x05]))
        self.assertEqual(self.sdo([0x60] + [0] * 7), bytes([0x80, 0x08, 0x10, 0, 0x01, 0x00, 0x04, 0x05]))
        # A client that stops mid-transfer: the server aborts with 0x05040000 after its 1 s timeout.
        self.assertEqual(self.sdo([0x40, 0x08, 0x10, 0, 0, 0, 0, 0])[0], 0x41)
        t0 = time.monotonic()
        abort = None
        while time.monotonic() < t0 + 3.0 and abort is None:
            abort = next((f for f in self.bus.seen(t0, 0x580 + NODE) if f[3][0] == 0x80), None)
            time.sleep(0.02)
        self.assertIsNotNone(abort, 'the server never timed the transfer out')
        self.assertEqual(bytes(abort[3]), bytes([0x80, 0x08, 0x10, 0, 0x00, 0x00, 0x04, 0x05]))
        self.assertGreater(abort[0] - t0, 0.5)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'can_motor_board', MotorBoardTest)
