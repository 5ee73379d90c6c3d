"""check_config (make check-config, and every robot's launch file): every robot's own config passes;
a bad one is refused in seconds, one line per error naming the parameter and the value given, and
a launch with a bad parameter ends before it starts anything (no ROS master is needed or started).
"""
import glob
import os
import subprocess
import tempfile
import time
import unittest

import yaml
from robot_core import start_zone
from robot_core.config_tree import merged
from robot_tools.matches.match_config import robot_config  # the config and its sim overlay, as the launch merges them

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))  # the checkout, not the src/ symlink
CHECK = os.path.join(ROOT, 'robot_description', 'scripts', 'check_config')
# The check answers in about 2 s here; the bound keeps a loaded CI machine from failing it while
# still telling a check from a launch that waits two minutes for a robot to become ready.
ANSWER_BOUND_S = 10.0


def robots():
    """Every robot the product ships: config/ROBOT.yaml with its launch/ROBOT.launch."""
    names = [os.path.basename(p)[:-len('.launch')] for p in glob.glob(os.path.join(ROOT, 'launch', '*.launch'))]
    return sorted(n for n in names if os.path.exists(os.path.join(ROOT, 'config', n + '.yaml')))


def run(args):
    t0 = time.monotonic()
    done = subprocess.run([CHECK] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
    return done.returncode, done.stdout, done.stderr, time.monotonic() - t0


class CheckConfigTest(unittest.TestCase):
    def overlay(self, text):
        f = tempfile.NamedTemporaryFile('w', suffix='.yaml', delete=False)
        f.write(text)
        f.close()
        self.addCleanup(os.unlink, f.name)
        return f.name

    def refused(self, args, *expected):
        code, out, err, elapsed = run(args)
        self.assertEqual(code, 1, 'not refused: %s%s' % (out, err))
        errors = [l for l in err.splitlines() if l.startswith('config error: ')]
        for text in expected:
            self.assertTrue(any(text in l for l in errors), '%r in no error line of:\n%s' % (text, err))
        self.assertLess(elapsed, ANSWER_BOUND_S)
        return errors

    def test_every_shipped_robot_passes(self):
        self.assertGreaterEqual(len(robots()), 3)
        for robot in robots():
            for sim in ('true', 'false'):
                code, out, err, _ = run([robot, '--sim', sim])
                self.assertEqual(code, 0, '%s sim=%s: %s' % (robot, sim, err))
                self.assertIn('ok', out)

    def test_unknown_strategy(self):
        self.refused(['eurobot2009', '--strategy', 'mach'],
                     "/brain/strategy = 'mach': unknown strategy; allowed values: ", 'match2009')

    def test_wrong_type_quotes_the_value(self):
        path = self.overlay('hal:\n  driver:\n    limits: {max_linear_speed: "fast"}\n')
        self.refused(['eurobot2009', '--overlay', path],
                     "/hal/driver/limits/max_linear_speed = 'fast' has the wrong type: expected a number")

    def test_every_error_at_once_value_out_of_range_and_unknown_board(self):
        path = self.overlay('hal:\n  localization: {particles: 5}\nhcl:\n  motor_board: {type: Motorboard}\n'
                            'sim:\n  world:\n    beacons: {noise_std: -1}\n')
        errors = self.refused(['logion', '--overlay', path],
                              '/hal/localization/particles = 5: must be in',
                              "/hcl/motor_board/type = 'Motorboard': unknown board type; allowed values: ",
                              '/sim/world/beacons/noise_std = -1')
        self.assertEqual(len(errors), 3)

    def test_unknown_key_in_a_board_block_names_what_the_board_reads(self):
        path = self.overlay('hcl:\n  io: {adress: 0x21}\n')
        errors = self.refused(['logion', '--overlay', path],
                              '/hcl/io/adress = 33: not a parameter of board type MCP23016 (it reads: ')
        self.assertEqual(len(errors), 1)
        self.assertIn('address', errors[0])

    def test_a_boards_and_a_devices_own_readers_run(self):
        # values only the board's or the device's reader knows: a conversion time the SRF02 cannot
        # wait, an unknown key inside a device's named block
        path = self.overlay('hcl:\n  ranger_front: {conversion_time: 0.01}\n'
                            'hal:\n  odometry: {pairs: {driven: {left_tiks: 3}}}\n')
        errors = self.refused(['logion', '--overlay', path],
                              '/hcl/ranger_front/conversion_time = 0.01: must be in [0.065, 1]',
                              '/hal/odometry/pairs/driven/left_tiks = 3: not a parameter of device type Odometry')
        self.assertEqual(len(errors), 2)

    def test_an_emulators_and_a_hosts_own_readers_run(self):
        # sim/firmware blocks go through each emulator's own reader (a misspelt key, a value out of
        # range), the hosts' own values through theirs, the robot's network through its one reader
        path = self.overlay('sim:\n  firmware:\n    motor_board: {node_idd: 10}\n    epos: {nominal_rpm: -5}\n'
                            'hcl:\n  realtime_priority: 100\ncomputer:\n  network: {adress: 10.0.0.2}\n')
        errors = self.refused(['eurobot2009', '--overlay', path],
                              '/sim/firmware/motor_board/node_idd = 10: not a parameter of emulator type MotorBoard '
                              '(it reads: ',
                              '/sim/firmware/epos/nominal_rpm = -5: must be',
                              '/hcl/realtime_priority = 100: must be in',
                              '/computer/network/adress')
        self.assertEqual(len(errors), 4)
        self.assertIn('node_id', errors[[i for i, e in enumerate(errors) if 'node_idd' in e][0]].split('(it reads: ')[1])

    def test_several_overlays_each_over_the_one_before(self):
        bad = self.overlay('hal:\n  driver:\n    limits: {max_linear_speed: "fast"}\n')
        fixed = self.overlay('hal:\n  driver:\n    limits: {max_linear_speed: 0.4}\n')
        code, _, err, _ = run(['eurobot2009', '--overlay', bad + ',' + fixed])
        self.assertEqual(code, 0, err)

    def moved_to_the_other_zone(self, robot, also_the_rest):
        """An overlay that starts the simulated robot in the start zone it does not start in, with
        (also_the_rest) or without the side switch, initial_pose and opponent moved along; read from
        the robot's own config."""
        def load(name):
            with open(os.path.join(ROOT, 'config', name)) as f:
                return yaml.safe_load(f)
        config, sim = load(robot + '.yaml'), load(robot + '.sim.yaml')
        zones = config['table']['start_zones']
        start = sim['sim']['world']['robot']['start']
        inside = lambda p, z: z['rect'][0] <= p[0] <= z['rect'][2] and z['rect'][1] <= p[1] <= z['rect'][3]
        ours = next(z for z in zones if inside(start, z))
        other = next(z for z in zones if z is not ours)
        centre = lambda z: [(z['rect'][0] + z['rect'][2]) / 2, (z['rect'][1] + z['rect'][3]) / 2]
        there = centre(other) + [3.14159]
        tree = {'sim': {'world': {'robot': {'start': there}}}}
        if also_the_rest:
            hmi = config['hal']['hmi']
            switch = hmi['side_switch']['input']
            tree['sim']['world']['robot']['switches'] = {switch: {'closed': hmi['sides'].index(other['name']) == 1}}
            tree['sim']['world']['opponent'] = {'start': centre(ours) + [0.0]}
            tree['hal'] = {'localization': {'initial_pose': there}}
        return self.overlay(yaml.safe_dump(tree)), other['name']

    def test_the_start_zone_decides_side_switch_initial_pose_and_opponent(self):
        path, zone = self.moved_to_the_other_zone('eurobot2009', also_the_rest=False)
        errors = self.refused(['eurobot2009', '--overlay', path],
                              "/closed = false: the side switch then says",
                              "/hal/localization/initial_pose = [",
                              "/sim/world/opponent/start = [")
        self.assertEqual(len(errors), 3)
        self.assertTrue(all('starts in the %s zone' % zone in e for e in errors), errors)
        path, _ = self.moved_to_the_other_zone('eurobot2009', also_the_rest=True)
        code, _, err, _ = run(['eurobot2009', '--overlay', path])
        self.assertEqual(code, 0, err)

    def test_one_side_choice_sets_start_initial_pose_switch_and_opponent(self):
        # SIDE=zone (robot_core.start_zone.side_overlay) over each table robot, for each of its
        # zones: the rules above find nothing to disagree with, and the robot stands in that zone.
        played = 0
        for robot in robots():
            tree = robot_config(robot)
            zones = (tree.get('table') or {}).get('start_zones') or []
            for zone in zones:
                over = start_zone.side_overlay(tree, zone['name'])
                moved = merged(tree, over)
                self.assertEqual(start_zone.errors(moved), [], '%s from %s' % (robot, zone['name']))
                self.assertEqual(start_zone.zone_of(moved['sim']['world']['robot']['start'], zones), zone['name'])
                for block in moved['hal'].values():
                    if isinstance(block, dict) and 'initial_pose' in block:
                        self.assertEqual(start_zone.zone_of(block['initial_pose'], zones), zone['name'])
                played += 1
        self.assertGreaterEqual(played, 4)  # two table robots, two zones each
        with self.assertRaises(ValueError) as no_zone:
            start_zone.side_overlay(robot_config('logion'), 'purple')
        self.assertIn('SIDE=purple: allowed values: red, blue', str(no_zone.exception))

    def test_check_config_plays_a_side(self):
        code, out, err, _ = run(['eurobot2009', '--side', 'green'])
        self.assertEqual(code, 0, err)
        self.assertIn('from the green zone: ok', out)
        self.refused(['logion', '--side', 'green'], 'SIDE=green: allowed values: red, blue')

    def test_a_simulated_start_outside_every_start_zone(self):
        path = self.overlay('sim:\n  world:\n    robot: {start: [1.5, 1.0, 0.0]}\n')
        self.refused(['logion', '--overlay', path], '/sim/world/robot/start = [1.5, 1.0, 0.0]: in no start zone')

    def test_unreadable_files_are_named(self):
        code, _, err, _ = run(['no_such_robot'])
        self.assertEqual(code, 2)
        self.assertIn('no_such_robot.yaml', err)
        listed = err.split('robots here: ', 1)[1].split(')', 1)[0].split(', ')
        self.assertEqual(listed, robots())  # the robots there are, and no other config
        path = self.overlay('hal: [1\n')
        code, _, err, _ = run(['eurobot2009', '--overlay', path])
        self.assertEqual(code, 1)
        self.assertIn('is not valid YAML', err)

    def test_a_launch_with_a_bad_parameter_ends_before_any_node(self):
        env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1')  # no master: none may be needed
        t0 = time.monotonic()
        done = subprocess.run(['roslaunch', os.path.join(ROOT, 'launch', 'logion.launch'), 'strategy:=mach'],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, env=env,
                              timeout=60)
        elapsed = time.monotonic() - t0
        self.assertNotEqual(done.returncode, 0, done.stdout)
        lines = [l for l in done.stdout.splitlines() if l.startswith('config error: ')]
        self.assertEqual(len(lines), 1, done.stdout)
        self.assertIn("/brain/strategy = 'mach'", lines[0])
        self.assertNotIn('started roslaunch server', done.stdout)
        self.assertNotIn('process[', done.stdout)  # no node started, so none respawns
        self.assertLess(elapsed, ANSWER_BOUND_S)


if __name__ == '__main__':
    unittest.main()
