#!/usr/bin/env python3
"""The hardware doctor (rosrun hcl_drivers doctor ROBOT --sim) against the simulator's emulators
started alone by the .test (emulators_only:=true, channels of their own): every board OK, then
one fault at a time, injected through /sim/inject_fault or configured in an overlay, named by
the doctor as the issue asks. ~robot picks the cases: eurobot2009 (CAN, serial), logion (I2C)."""
import json
import os
import subprocess
import tempfile
import time
import unittest

import rospy
import rostest
import yaml
from robot_sim.srv import InjectFault


def doctor(*extra, overlay=None):
    """Runs the doctor against this test's emulators: (exit code, rows, stderr)."""
    cmd = ['rosrun', 'hcl_drivers', 'doctor', rospy.get_param('~robot'), '--sim', '--json']
    for name in ('can_bus', 'sim_dir', 'camera_port'):
        if rospy.has_param('~' + name):
            cmd += ['--' + name.replace('_', '-'), str(rospy.get_param('~' + name))]
    if overlay:
        f = tempfile.NamedTemporaryFile('w', suffix='.yaml', delete=False)
        yaml.safe_dump(overlay, f)
        f.close()
        cmd += ['--overlay', f.name]
    out = subprocess.run(cmd + list(extra), stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True,
                         timeout=120)
    rows = json.loads(out.stdout) if out.stdout.strip().startswith('[') else []
    return out.returncode, rows, out.stderr


def rows_of(rows, board):
    return [r for r in rows if r['board'] == board]


def configured_boards(robot):
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, '..', '..', 'config', robot + '.yaml')) as f:
        hcl = yaml.safe_load(f)['hcl']
    return sorted(name for name, block in hcl.items() if isinstance(block, dict) and 'type' in block
                  and block.get('enabled', True))


class DoctorTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_doctor')
        cls.robot = rospy.get_param('~robot')
        rospy.wait_for_service('/sim/inject_fault', timeout=60.0)
        cls.inject = rospy.ServiceProxy('/sim/inject_fault', InjectFault)
        time.sleep(1.0)  # the emulators open their channels as the simulator starts

    def fault(self, kind, target, clear=False):
        res = self.inject(kind=kind, target=target, clear=clear)
        self.assertTrue(res.ok, res.message)

    def test_1_all_boards_present(self):
        rc, rows, err = doctor()
        failing = [r for r in rows if r['status'] != 'OK']
        self.assertEqual(failing, [], 'not all OK: %s\n%s' % (json.dumps(failing, indent=1), err))
        self.assertEqual(rc, 0, err)
        self.assertEqual(sorted({r['board'] for r in rows if not r['board'].startswith('bus ')}),
                         configured_boards(self.robot))

    def test_2_table_and_closing_line(self):
        cmd = ['rosrun', 'hcl_drivers', 'doctor', self.robot, '--sim', '--boards', 'beacons']
        for name in ('can_bus', 'sim_dir', 'camera_port'):
            if rospy.has_param('~' + name):
                cmd += ['--' + name.replace('_', '-'), str(rospy.get_param('~' + name))]
        out = subprocess.run(cmd, stdout=subprocess.PIPE, universal_newlines=True, timeout=60).stdout.splitlines()
        self.assertEqual(out[0].split()[:6], ['BOARD', 'CHECK', 'EXPECTED', 'FOUND', 'STATUS', 'HINT'])
        self.assertRegex(out[-1], r'^doctor %s: 1 boards, \d+ checks: \d+ OK, 0 WARN, 0 FAIL$' % self.robot)

    # ---- eurobot2009: CAN and serial ----
    def test_3_silent_can_board_fails(self):
        if self.robot != 'eurobot2009':
            self.skipTest('CAN: eurobot2009')
        self.fault('board_silent', 'servo_board')
        try:
            rc, rows, err = doctor('--boards', 'servo_board', '--load-window', '0.5')
        finally:
            self.fault('board_silent', 'servo_board', clear=True)
        self.assertEqual(rc, 1, err)
        node = [r for r in rows_of(rows, 'servo_board') if r['check'] == 'node']
        self.assertEqual(len(node), 1, rows)
        self.assertEqual(node[0]['status'], 'FAIL')
        self.assertIn('no answer', node[0]['found'])
        self.assertTrue(node[0]['hint'])

    def test_4_can_board_at_wrong_node_id_is_found(self):
        if self.robot != 'eurobot2009':
            self.skipTest('CAN: eurobot2009')
        # The config expects the stepper board at 15; its emulator answers at 11.
        rc, rows, err = doctor('--boards', 'stepper_board', '--load-window', '0.5',
                               overlay={'hcl': {'stepper_board': {'node_id': 15}}})
        self.assertEqual(rc, 1, err)
        node = [r for r in rows_of(rows, 'stepper_board') if r['check'] == 'node']
        self.assertEqual(node[0]['status'], 'FAIL', rows)
        self.assertEqual(node[0]['found'], 'found at 11, expected 15')
        self.assertIn('node_id: 11', node[0]['hint'])
        # The other configured boards are no strangers, though only the stepper board was checked.
        self.assertEqual([r for r in rows if r['check'] == 'unconfigured node'], [])

    def test_5_serial_garbage_warns_with_error_rate(self):
        if self.robot != 'eurobot2009':
            self.skipTest('serial fault: eurobot2009')
        self.fault('serial_garbage', 'beacons')
        try:
            rc, rows, err = doctor('--boards', 'beacons')
        finally:
            self.fault('serial_garbage', 'beacons', clear=True)
        frames = [r for r in rows_of(rows, 'beacons') if r['check'] == 'frames']
        self.assertEqual(frames[0]['status'], 'WARN', rows)
        self.assertRegex(frames[0]['found'], r'[1-9]\d* parse errors \(\d+ %\)|[1-9]\d* garbage bytes')
        self.assertEqual(rc, 0, 'a WARN alone must not fail the doctor: ' + err)

    # ---- logion: I2C ----
    def test_6_i2c_chip_at_another_address_is_named(self):
        if self.robot != 'logion':
            self.skipTest('I2C: logion')
        rc, rows, err = doctor('--boards', 'ranger_back', overlay={'hcl': {'ranger_back': {'address': 0x74}}})
        self.assertEqual(rc, 1, err)
        address = [r for r in rows_of(rows, 'ranger_back') if r['check'] == 'address']
        self.assertEqual(address[0]['status'], 'FAIL', rows)
        self.assertEqual(address[0]['found'], 'found at 0x73, expected 0x74')
        self.assertEqual([r for r in rows if r['check'] == 'unconfigured chip'], [])

    def test_7_silent_i2c_chip_fails(self):
        if self.robot != 'logion':
            self.skipTest('I2C: logion')
        self.fault('board_silent', 'compass')
        try:
            rc, rows, err = doctor('--boards', 'compass')
        finally:
            self.fault('board_silent', 'compass', clear=True)
        self.assertEqual(rc, 1, err)
        address = [r for r in rows_of(rows, 'compass') if r['check'] == 'address']
        self.assertEqual(address[0]['status'], 'FAIL', rows)
        self.assertIn('no answer', address[0]['found'])


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'test_doctor', DoctorTest)
