#!/usr/bin/env python3
"""`make matches CLUSTER=...` across two network namespaces of this machine, joined by a veth
pair and nothing else (launch/matches_cluster.test):
  netns "scheduler" (10.x.y.1/30): the Dask scheduler (as `make scheduler` starts it) and the
                                   runner, scripts/run_matches.py --cluster tcp://10.x.y.1:8786
  netns "workers"   (10.x.y.2/30): two Dask workers (as `make worker` starts them), each a
                                   process group of its own, like two machines
Two eurobot2009 matches of 40 s (--match-duration). Once a match runs on worker A, its whole process group is killed -9:
the worker dies mid-match, as a machine that loses power. Checked: that match is run once more
on worker B (the summary counts one retry), the runner exits 0 with both rows and no violation,
each match's report came back to the runner's folder while its bag stayed on the worker (its
path in remote_bag.txt), and nothing of the killed worker's simulation is left running.
Needs root (ip netns)."""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import psutil
import rospy
import rostest

import netns_pair  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
PID = os.getpid()
NET = '10.214.%d' % (PID % 250)
SCHEDULER_IP, WORKERS_IP = NET + '.1', NET + '.2'
NS_SCHEDULER, NS_WORKERS = 'mc_sched_%d' % PID, 'mc_work_%d' % PID
VETH = ('mcs%d' % (PID % 100000), 'mcw%d' % (PID % 100000))
ADDRESS = 'tcp://%s:8786' % SCHEDULER_IP
ROBOT, N = 'eurobot2009', 2
RUNNER_TIMEOUT = 900.0  # [s, wall]
MID_MATCH = 8.0         # [s, wall] after the killed worker's simulator started
MATCH_DURATION = 40     # [s] the machinery is under test, not the robot: shorter matches


def descendants(pid):
    try:
        return psutil.Process(pid).children(recursive=True)
    except psutil.NoSuchProcess:
        return []


def named(procs, word):
    out = []
    for p in procs:
        try:
            if any(word in part for part in p.cmdline()):
                out.append(p)
        except psutil.Error:
            pass
    return out


class MatchesClusterTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_matches_cluster', anonymous=True)
        cls.tmp = tempfile.mkdtemp(prefix='matches_cluster_')
        cls.out = os.path.join(cls.tmp, 'out')
        cls.procs = {}
        netns_pair.create((NS_SCHEDULER, NS_WORKERS), VETH, (SCHEDULER_IP, WORKERS_IP))
        env = dict(os.environ, DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES='1')
        cls.start('scheduler', NS_SCHEDULER, ['dask', 'scheduler', '--host', SCHEDULER_IP, '--port', '8786',
                                               '--no-dashboard'], env)
        worker_env = dict(os.environ, ROS_IP='127.0.0.1')  # each match's own master is on the worker's loopback
        for name in ('worker_a', 'worker_b'):
            cls.start(name, NS_WORKERS, ['dask', 'worker', ADDRESS, '--host', WORKERS_IP, '--nthreads', '1',
                                         '--nworkers', '1', '--name', name, '--no-dashboard',
                                         '--local-directory', os.path.join(cls.tmp, name)], worker_env)
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline and not all(cls.registered(n) for n in ('worker_a', 'worker_b')):
            time.sleep(0.5)
        cmd = ['ip', 'netns', 'exec', NS_SCHEDULER, sys.executable, os.path.join(ROOT, 'scripts', 'run_matches.py'),
               ROBOT, '--n', str(N), '--seed', '1', '--factor', '0', '--out', cls.out, '--cluster', ADDRESS,
               '--match-duration', str(MATCH_DURATION)]
        cls.killed_at, cls.leftover = None, None
        runner = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                                  start_new_session=True)
        cls.kill_worker_a_mid_match()
        try:
            cls.output = runner.communicate(timeout=RUNNER_TIMEOUT)[0]
            cls.rc = runner.returncode
        except subprocess.TimeoutExpired:
            os.killpg(runner.pid, signal.SIGINT)
            cls.output, cls.rc = runner.communicate()[0] + '\n(the runner did not finish)', None
        print(cls.output, flush=True)

    @classmethod
    def kill_worker_a_mid_match(cls):
        """Worker A's process group killed -9 MID_MATCH seconds after its match's simulator
        started; then what is left of that match (its roslaunch'ed nodes are in sessions of
        their own) is looked for after it has had time to stop."""
        worker = cls.procs['worker_a'][0]
        deadline = time.monotonic() + 240.0
        started = None
        while time.monotonic() < deadline:
            if named(descendants(worker.pid), 'simulator'):
                started = time.monotonic()
                break
            time.sleep(0.5)
        if started is None:
            return
        time.sleep(MID_MATCH)
        doomed = [p.pid for p in named(descendants(worker.pid), 'run_match.py')]
        simulation = descendants(doomed[0]) if doomed else []
        os.killpg(worker.pid, signal.SIGKILL)
        cls.killed_at = time.monotonic()
        time.sleep(20.0)
        cls.leftover = [p for p in simulation if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
        cls.leftover_names = [' '.join(p.cmdline()[:2]) for p in cls.leftover if p.is_running()]

    @classmethod
    def registered(cls, name):
        with open(cls.procs[name][1], errors='replace') as f:
            return 'Registered to' in f.read()

    @classmethod
    def start(cls, name, ns, cmd, env):
        log = open(os.path.join(cls.tmp, name + '.log'), 'w')
        p = subprocess.Popen(['ip', 'netns', 'exec', ns] + cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                             start_new_session=True)
        cls.procs[name] = (p, log.name)

    @classmethod
    def tearDownClass(cls):
        for p, _ in cls.procs.values():
            netns_pair.stop(p)
        netns_pair.delete((NS_SCHEDULER, NS_WORKERS))
        if cls.rc == 0:
            shutil.rmtree(cls.tmp, ignore_errors=True)

    def logs(self):
        text = ''
        for name, (_, path) in self.procs.items():
            with open(path, errors='replace') as f:
                text += '\n--- %s ---\n%s' % (name, f.read()[-1500:])
        return text

    def test_1_worker_a_was_killed_mid_match(self):
        self.assertIsNotNone(self.killed_at, 'no match started on worker A' + self.logs())

    def test_2_the_match_ran_again_and_every_row_came_back(self):
        self.assertEqual(self.rc, 0, self.output[-3000:] + self.logs())
        self.assertIn('cluster: 2 workers, 1 retries', self.output.splitlines(), self.output[-3000:])
        m = re.search(r'^matches (\d+) score_mean \S+ score_min \S+ violations (\d+) ', self.output, re.M)
        self.assertIsNotNone(m, self.output[-2000:])
        self.assertEqual((int(m.group(1)), int(m.group(2))), (N, 0))

    def test_3_reports_came_back_and_bags_stayed_on_the_worker(self):
        for seed in range(1, N + 1):
            folder = os.path.join(self.out, '%s_seed%d' % (ROBOT, seed))
            for name in ('run_match.out', ROBOT + '_match.png', ROBOT + '_launch.log', 'overlay.yaml'):
                self.assertTrue(os.path.exists(os.path.join(folder, name)), 'seed %d: no %s' % (seed, name))
            self.assertFalse(os.path.exists(os.path.join(folder, ROBOT + '_match.bag')), 'a bag came back unasked')
            with open(os.path.join(folder, 'remote_bag.txt')) as f:
                host, path = f.read().strip().split(':', 1)
            self.assertTrue(os.path.exists(path), 'the bag is not where the worker said: %s' % path)

    def test_4_nothing_of_the_killed_match_runs_on(self):
        self.assertIsNotNone(self.leftover, 'no kill')
        self.assertEqual(self.leftover_names, [], 'still running 20 s after worker A was killed')


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'matches_cluster', MatchesClusterTest, sys.argv)
