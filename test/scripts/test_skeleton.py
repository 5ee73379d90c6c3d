#!/usr/bin/env python3
"""System test of the skeleton robot (launch/skeleton.launch against its firmware emulator)."""
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from hal_nodes.msg import ExampleReading
from hcl_drivers.msg import ExampleBoardState
from robot_sim.msg import ExampleFirmware
from test_support import Recorder, wait_for

BOARD_RATE = 50.0   # config/skeleton.yaml hcl/example_board/rate
DEVICE_RATE = 20.0  # config/skeleton.yaml hal/example_device/rate


def lamp_for(dial_raw):
    """What the example strategy makes of a dial value, in the board's PWM units."""
    return round(255.0 * dial_raw / 1023.0)


class SkeletonTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_skeleton')
        cls.firmware = Recorder('/sim/example_board/firmware', ExampleFirmware, queue_size=200)
        cls.board = Recorder('/hcl/example_board/state', ExampleBoardState, queue_size=200)
        cls.reading = Recorder('/hal/example_device/reading', ExampleReading, queue_size=200)
        cls.diagnostics = Recorder('/diagnostics', DiagnosticArray, queue_size=200)
        # Wait for the whole chain to run: lamp PWM (set by the brain) must reach the firmware.
        deadline = time.monotonic() + 40.0
        while time.monotonic() < deadline:
            if any(m.lamp_pwm > 0 for _, m in cls.firmware.since(0)):
                break
            time.sleep(0.2)
        time.sleep(3.0)

    def test_1_rates_are_the_configured_ones(self):
        t0 = time.monotonic()
        time.sleep(4.0)
        board = len(self.board.since(t0)) / 4.0
        device = len(self.reading.since(t0)) / 4.0
        self.assertAlmostEqual(board, BOARD_RATE, delta=0.2 * BOARD_RATE, msg='board state rate %.1f Hz' % board)
        self.assertAlmostEqual(device, DEVICE_RATE, delta=0.2 * DEVICE_RATE, msg='device rate %.1f Hz' % device)

    def test_2_dial_goes_up_through_hcl_and_hal(self):
        # Every HAL reading is the board's dial scaled to 0..1, and the board mirrors the firmware.
        t0 = time.monotonic()
        time.sleep(3.0)
        board = self.board.since(t0)
        readings = self.reading.since(t0)
        self.assertGreater(len(readings), 20)
        firmware_dials = {m.dial_raw for _, m in self.firmware.since(t0 - 1.0)}
        board_dials = {m.dial_raw for _, m in board}
        self.assertGreater(len(board_dials), 10, 'the dial must move')
        # The board's values are values the firmware really had (within its truth sample rate).
        near = [d for d in board_dials if any(abs(d - f) <= 30 for f in firmware_dials)]
        self.assertGreater(len(near), 0.9 * len(board_dials))
        stamps = {m.header.stamp: m.dial_raw for _, m in board}
        matched = 0
        for _, r in readings:
            self.assertGreaterEqual(r.position, 0.0)
            self.assertLessEqual(r.position, 1.0)
            if r.header.stamp in stamps:
                self.assertAlmostEqual(r.position, stamps[r.header.stamp] / 1023.0, places=9)
                matched += 1
        self.assertGreater(matched, 0.8 * len(readings))

    def test_3_lamp_comes_down_from_the_brain_to_the_firmware(self):
        # The lamp PWM in the firmware follows the dial, through HAL -> brain -> HAL -> HCL.
        t0 = time.monotonic()
        time.sleep(4.0)
        fw = self.firmware.since(t0 - 1.0)
        dial_history = [(t, m.dial_raw) for t, m in fw]
        checked = good = 0
        lamps = set()
        for t, m in fw:
            if t < t0:
                continue
            lamps.add(m.lamp_pwm)
            # Some dial value of the last 0.6 s explains the lamp (pipeline latency < 0.6 s).
            recent = [d for (td, d) in dial_history if t - 0.6 <= td <= t]
            checked += 1
            if any(abs(lamp_for(d) - m.lamp_pwm) <= 3 for d in recent):
                good += 1
        self.assertGreater(checked, 50)
        self.assertGreater(len(lamps), 10, 'the lamp must follow a moving dial')
        self.assertGreater(good, 0.9 * checked, '%d of %d lamp samples follow the dial' % (good, checked))

    def test_4_diagnostics_report_board_and_device(self):
        t0 = time.monotonic()
        statuses = {}

        def both_reported():  # each says its status once a second (~diagnostic_period) while it holds
            for _, arr in self.diagnostics.since(t0):
                for s in arr.status:
                    statuses[s.name] = s
            return any('example_board' in n for n in statuses) and any('example_device' in n for n in statuses)
        wait_for(both_reported, 3.0, step=0.05)
        board = [s for n, s in statuses.items() if 'example_board' in n]
        device = [s for n, s in statuses.items() if 'example_device' in n]
        self.assertTrue(board, 'no diagnostics for the board: %s' % sorted(statuses))
        self.assertTrue(device, 'no diagnostics for the device: %s' % sorted(statuses))
        self.assertEqual(board[0].level, DiagnosticStatus.OK, board[0].message)
        self.assertEqual(device[0].level, DiagnosticStatus.OK, device[0].message)
        keys = {kv.key: kv.value for kv in board[0].values}
        self.assertAlmostEqual(float(keys['achieved rate [Hz]']), BOARD_RATE, delta=0.2 * BOARD_RATE)
        self.assertIn('last good exchange age [s]', keys)
        self.assertIn('errors', keys)

    def test_9_dead_board_goes_stale_within_one_second(self):
        subprocess.check_call(['rosnode', 'kill', '/sim/firmware'], stdout=subprocess.DEVNULL)
        killed = time.monotonic()
        level = None
        while time.monotonic() - killed < 1.0:
            for t, arr in self.diagnostics.since(killed):
                for s in arr.status:
                    if 'example_board' in s.name and s.level in (DiagnosticStatus.ERROR, DiagnosticStatus.STALE):
                        level = (t - killed, s.level, s.message)
            if level:
                break
            time.sleep(0.02)
        self.assertIsNotNone(level, 'board diagnostic not STALE/ERROR within 1 s of killing its emulator')
        # Nothing crashed: every product node still answers.
        time.sleep(1.0)
        for node in ('/hcl', '/hal', '/brain'):
            out = subprocess.run(['rosnode', 'ping', '-c', '1', node], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
            self.assertEqual(out.returncode, 0, '%s died: %s' % (node, out.stdout.decode()))
        # And the device says why it is unavailable.
        latest = {}
        for _, arr in self.diagnostics.since(killed + 0.5):
            for s in arr.status:
                latest[s.name] = s
        device = [s for n, s in latest.items() if 'example_device' in n]
        self.assertTrue(device)
        self.assertEqual(device[0].level, DiagnosticStatus.ERROR, device[0].message)
        self.assertIn('unavailable', device[0].message)


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'skeleton_end_to_end', SkeletonTest, sys.argv)
