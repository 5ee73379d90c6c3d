"""make new-robot: a robot made from each template is checked, launches, and (from a table robot)
plays a 30 s simulated match; names that are taken or unusable are refused with nothing written.
The robots made here are removed again whatever happens."""
import os
import socket
import subprocess
import tempfile
import unittest

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))  # the checkout, not the src/ symlink
NEW_ROBOT = os.path.join(ROOT, 'scripts', 'new_robot.py')
RUN_MATCH = os.path.join(ROOT, 'scripts', 'run_match.py')


def free_port():
    with socket.socket() as s:
        s.bind(('127.0.0.1', 0))
        return s.getsockname()[1]


def new_robot(*args):
    return subprocess.run(['python3', NEW_ROBOT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True)


class NewRobotTest(unittest.TestCase):
    def make(self, name, template):
        self.addCleanup(new_robot, name, '--remove')
        done = new_robot(name, '--from', template)
        self.assertEqual(done.returncode, 0, done.stdout)
        self.assertIn(': ok (', done.stdout)  # its config passed check_config
        return done.stdout

    def play_30_s(self, name):
        out = tempfile.mkdtemp(prefix='new_robot_%s_' % name)
        overlay = os.path.join(out, 'short.yaml')
        with open(overlay, 'w') as f:
            yaml.safe_dump({'brain': {'match': {'duration': 30}}}, f)
        env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % free_port())
        done = subprocess.run(['python3', RUN_MATCH, name, '--out', os.path.join(out, 'run'), '--overlay', overlay,
                               '--real-time-factor', '0', '--match-timeout', '240'],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, env=env,
                              timeout=600)
        self.assertEqual(done.returncode, 0, done.stdout[-3000:])
        self.assertRegex(done.stdout, r'score: ours \d+, opponent \d+')
        self.assertTrue(os.path.exists(os.path.join(out, 'run', name + '_match.bag')), done.stdout[-2000:])

    def test_from_eurobot2009_plays_a_match(self):
        self.make('ci_new_2009', 'eurobot2009')
        with open(os.path.join(ROOT, 'config', 'ci_new_2009.yaml')) as f:
            self.assertEqual(yaml.safe_load(f)['robot']['name'], 'ci_new_2009')
        with open(os.path.join(ROOT, 'launch', 'ci_new_2009.launch')) as f:
            self.assertIn('<arg name="robot" default="ci_new_2009"', f.read())
        self.play_30_s('ci_new_2009')

    def test_from_logion_plays_a_match(self):
        self.make('ci_new_logion', 'logion')
        self.play_30_s('ci_new_logion')

    def test_from_skeleton_launches(self):
        self.make('ci_new_skeleton', 'skeleton')
        env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:1')
        done = subprocess.run(['roslaunch', '--dump-params', os.path.join(ROOT, 'launch', 'ci_new_skeleton.launch')],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, env=env)
        self.assertEqual(done.returncode, 0, done.stdout)
        params = yaml.safe_load(done.stdout)
        self.assertIn('<robot name="ci_new_skeleton">', params['/robot_description'])

    def test_taken_and_bad_names_are_refused_with_nothing_written(self):
        before = sorted(os.listdir(os.path.join(ROOT, 'config')))
        for args, why in ((['logion', '--from', 'skeleton'], 'is taken'),
                          (['My-Robot', '--from', 'skeleton'], "a robot's name is"),
                          (['okname', '--from', 'nosuch'], 'allowed values: skeleton, eurobot2009, logion')):
            done = new_robot(*args)
            self.assertNotEqual(done.returncode, 0, done.stdout)
            self.assertIn(why, done.stdout)
        self.assertEqual(sorted(os.listdir(os.path.join(ROOT, 'config'))), before)
        done = new_robot('logion', '--remove')
        self.assertNotEqual(done.returncode, 0)
        self.assertTrue(os.path.exists(os.path.join(ROOT, 'config', 'logion.yaml')))


if __name__ == '__main__':
    unittest.main()
