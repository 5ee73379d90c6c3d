#!/usr/bin/env python3
"""`make calibrate` finds what is there (test/launch/calibrate_recovery_eurobot2009.test): the
calibration run (strategy calibration: UMBmark's square both ways, as a team records it on the
table) recorded from a simulator whose robot was changed by amounts the calibration is not told
(wheel base and radius +-3 %, one motor's full speed +-15 % and time constant +-30 %, ranger and
beacon noise x2), then scripts/calibrate.py on the bag alone. Two cases: one seed with one set of
changes, another seed with the opposite ones on the other motor.

Asserts against the changed simulator: ticks per metre and track width within 0.3 %, motor full
speed within 5 % and time constant within 20 % (the unchanged motor too), beacon and ranger noise
within 20 %; the odometry's drift against the simulator's ground truth at least halved by the
calibrated robot overlay; the recorded commands replayed through the calibrated motor model within
1 % of the recorded encoder counts, several times closer than the config's model. And a bag
without the topics the fit needs is refused (exit 2) with the list of what is missing."""
import copy
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import rosbag
import rospy
import rostest
import yaml
from robot_core.config_tree import simulated_robot

from match_runner import run_runner  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.calibration.geometry import Segments, odometry_drift
from robot_tools.calibration import signals as sig
from robot_tools.matches import match_config

ROBOT = 'eurobot2009'
STRATEGY = 'calibration'
DURATION = None  # the whole match: the run's two squares each way
# (seed, the simulator's changes): fractions of the config's values
CASES = [(31, {'wheel_base': +0.03, 'wheel_radius': -0.03, 'motor': 'left', 'max_speed': +0.15, 'time_constant': +0.30}),
         (32, {'wheel_base': -0.03, 'wheel_radius': +0.03, 'motor': 'right', 'max_speed': -0.15, 'time_constant': -0.30})]
NOISE = 2.0
CLOSING = re.compile(r'^calibrate (?P<robot>\S+): (?P<p>\d+) parameters, fit_rmse_wheel_speed (?P<s>[\d.]+) m/s, '
                     r'odometry_drift_after (?P<after>[\d.]+) mm/m \(before (?P<before>[\d.]+) mm/m\)$')
REPLAY = re.compile(r'replay (?P<side>\w+) motor: encoder counts off by +(?P<after>[\d.]+) % of the recording '
                    r'\(config\'s model: (?P<before>[\d.]+) %\)')


def changed_world(config, change):
    """The sim/world overlay of one case, from the config's own values."""
    world = config['sim']['world']
    robot = simulated_robot(config)  # the geometry the simulator takes from the description
    motor = robot['motors'][change['motor']]
    over = {'robot': {
        'wheel_base': robot['wheel_base'] * (1 + change['wheel_base']),
        'wheel_radius': robot['wheel_radius'] * (1 + change['wheel_radius']),
        'motors': {change['motor']: {'max_speed': motor['max_speed'] * (1 + change['max_speed']),
                                     'time_constant': motor['time_constant'] * (1 + change['time_constant'])}},
        'rangers': {name: {'noise_std': r['noise_std'] * NOISE, 'noise_rel': r['noise_rel'] * NOISE}
                    for name, r in robot['rangers'].items()}},
        'beacons': {'noise_std': world['beacons']['noise_std'] * NOISE}}
    return over


def truth_segments(bag_path, config):
    """The driven wheels' counts and the simulator's ground truth of a bag, 2 m stretches at a time."""
    with rosbag.Bag(bag_path) as bag:
        s = sig.read(bag, config)
        truth = sorted((m.header.stamp.to_sec(), m.pose.pose.position.x, m.pose.pose.position.y,
                        2 * math.atan2(m.pose.pose.orientation.z, m.pose.pose.orientation.w))
                       for _, m, _ in bag.read_messages(topics=['/sim/ground_truth']))
    truth = np.array(truth)
    tl, cl = s.encoders['left']
    tr, cr = s.encoders['right']
    return Segments(tl, cl, np.interp(tl, tr, cr), truth[:, 0], truth[:, 1], truth[:, 2], truth[:, 3], length=2.0)


def truth_drift(segs, tpm_l, tpm_r, track):
    """[mm/m] the odometry with these values against the simulator's ground truth."""
    return odometry_drift(segs, tpm_l, tpm_r, track)


class CalibrateRecoveryTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_calibrate_recovery')
        cls.factor = float(rospy.get_param('~factor', 0.0))
        cls.config = match_config.robot_config(ROBOT)
        cls.tmp = tempfile.mkdtemp(prefix='calibrate_recovery_')

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def record_and_calibrate(self, seed, change):
        folder = os.path.join(self.tmp, 'seed%d' % seed)
        os.makedirs(folder)
        world = changed_world(self.config, change)
        overlay = match_config.with_duration(
            match_config.merged({'sim': {'world': world}}, {'sim': {'world': {'opponent': {'enabled': False}}}}), DURATION)
        overlay_path = match_config.write_overlay(folder, overlay)
        rc, output = run_runner([sys.executable, os.path.join(ROOT, 'scripts', 'run_match.py'), ROBOT, '--out', folder,
                                 '--seed', str(seed), '--real-time-factor', repr(self.factor), '--strategy', STRATEGY,
                                 '--overlay', overlay_path], 600.0)
        self.assertEqual(rc, 0, output[-3000:])
        bag = os.path.join(folder, '%s_match.bag' % ROBOT)
        calibrated = os.path.join(folder, 'calibrated')
        done = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'calibrate.py'), ROBOT, bag,
                               '--out', calibrated, '--report', os.path.join(folder, 'report')],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=600)
        print(done.stdout)
        self.assertEqual(done.returncode, 0, done.stdout[-3000:])
        with open(os.path.join(calibrated, ROBOT + '.calibrated.yaml')) as f:
            robot = yaml.safe_load(f)
        with open(os.path.join(calibrated, ROBOT + '.calibrated.sim.yaml')) as f:
            sim = yaml.safe_load(f)
        return bag, world, robot, sim['sim']['world'], done.stdout

    def check_case(self, seed, change):
        bag, world, robot, sim, output = self.record_and_calibrate(seed, change)
        base = self.config['sim']['world']
        true_world = match_config.merged(base, world)
        truth = simulated_robot({'robot': self.config['robot'], 'sim': {'world': true_world}})

        # the robot's geometry: what the changed simulator's wheels count per metre, its wheel base
        driven = robot['hal']['odometry']['pairs']['driven']
        encoders = truth['encoders']
        for side in ('left', 'right'):
            motor = next(n for n, m in truth['motors'].items() if m.get('drive') == side)
            tpr = next(float(e['ticks_per_rev']) for e in encoders.values() if e.get('motor') == motor)
            want = tpr / (2 * math.pi * truth['wheel_radius'])
            got = driven['%s_ticks_per_meter' % side]
            self.assertLess(abs(got / want - 1), 0.003, 'seed %d: %s ticks per metre %.2f, the simulator\'s %.2f'
                            % (seed, side, got, want))
        self.assertLess(abs(sim['robot']['wheel_base'] / truth['wheel_base'] - 1), 0.003,
                        'seed %d: track %.5f, the simulator\'s %.5f' % (seed, sim['robot']['wheel_base'], truth['wheel_base']))

        # the motors: the changed one and the one left as it was
        for name, fitted in sim['robot']['motors'].items():
            want = truth['motors'][name]
            self.assertLess(abs(fitted['max_speed'] / want['max_speed'] - 1), 0.05, 'seed %d: motor %s max_speed %.3f, '
                            'the simulator\'s %.3f' % (seed, name, fitted['max_speed'], want['max_speed']))
            self.assertLess(abs(fitted['time_constant'] / want['time_constant'] - 1), 0.20, 'seed %d: motor %s '
                            'time_constant %.4f, the simulator\'s %.4f' % (seed, name, fitted['time_constant'],
                                                                           want['time_constant']))

        # the noise: the beacons' and each ranger's at two ranges within a GP2D12's 0.8 m
        want = true_world['beacons']['noise_std']
        self.assertLess(abs(sim['beacons']['noise_std'] / want - 1), 0.20, 'seed %d: beacon noise %.3g s, the '
                        'simulator\'s %.3g s' % (seed, sim['beacons']['noise_std'], want))
        for name, fitted in sim['robot'].get('rangers', {}).items():
            for r in (0.25, 0.6):
                got = fitted['noise_std'] + fitted['noise_rel'] * r
                want = truth['rangers'][name]['noise_std'] + truth['rangers'][name]['noise_rel'] * r
                self.assertLess(abs(got / want - 1), 0.20, 'seed %d: ranger %s noise at %.1f m %.4f m, the simulator\'s '
                                '%.4f m' % (seed, name, r, got, want))

        # the odometry against the ground truth, before and after
        hal = self.config['hal']['odometry']['pairs']['driven']
        segs = truth_segments(bag, self.config)  # the bag read once for both
        before = truth_drift(segs, hal['left_ticks_per_meter'], hal['right_ticks_per_meter'],
                             hal.get('track_width', self.config['robot']['track_width']))
        after = truth_drift(segs, driven['left_ticks_per_meter'], driven['right_ticks_per_meter'],
                            sim['robot']['wheel_base'])
        print('seed %d: odometry drift against the truth %.1f mm/m before, %.1f mm/m after' % (seed, before, after))
        self.assertLessEqual(after, 0.5 * before, 'seed %d: drift %.1f -> %.1f mm/m' % (seed, before, after))

        # the recorded commands replayed through the model
        replays = {m.group('side'): (float(m.group('after')), float(m.group('before'))) for m in REPLAY.finditer(output)}
        self.assertEqual(set(replays), {'left', 'right'}, output)
        for side, (after_pct, before_pct) in replays.items():
            self.assertLessEqual(after_pct, 1.0, 'seed %d: %s replay off by %.2f %%' % (seed, side, after_pct))
        changed_side = truth['motors'][change['motor']]['drive']
        self.assertGreaterEqual(replays[changed_side][1], 3 * max(replays[changed_side][0], 0.5),
                                'seed %d: the config\'s model should be several times further off' % seed)

        closing = output.strip().splitlines()[-1]
        m = CLOSING.match(closing)
        self.assertIsNotNone(m, closing)
        self.assertLess(float(m.group('after')), float(m.group('before')), closing)

    def test_first_seed(self):
        self.check_case(*CASES[0])

    def test_second_seed_other_motor(self):
        self.check_case(*CASES[1])

    def test_bag_without_the_topics_is_refused(self):
        path = os.path.join(self.tmp, 'thin.bag')
        from std_msgs.msg import String
        with rosbag.Bag(path, 'w') as bag:
            bag.write('/chatter', String('nothing the fit needs'), rospy.Time(1))
        done = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'calibrate.py'), ROBOT, path,
                               '--out', os.path.join(self.tmp, 'thin')], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, universal_newlines=True, timeout=120)
        self.assertEqual(done.returncode, 2, done.stdout)
        for topic in sig.needed(copy.deepcopy(self.config)):
            self.assertIn(topic, done.stdout)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, 'thin')), 'a refused bag writes nothing')


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'calibrate_recovery', CalibrateRecoveryTest, sys.argv)
