#!/usr/bin/env python3
"""A simulated eurobot2009 match recorded with record:=true replays through localization:
1. the bag holds the HCL state, /odom, /mcl/pose and the ground truth;
2. launch/replay.launch (HAL alone, on the bag's clock) gives localization estimates that
   follow the ones of the match (played beside them on /recorded/mcl/pose) and the truth;
3. the match report of that bag has a localization error, a trajectory and the brain's states.
The match: the start cord is pulled (sim /sim/set_switch) so the strategy drives."""
import bisect
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import rosbag
import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
MATCH_SECONDS = 10.0


def roslaunch(*args, log):
    return subprocess.Popen(['roslaunch', '--wait'] + list(args), stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)


def stop(proc, timeout=30.0):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def xy(msg):
    p = msg.pose.pose.position
    return p.x, p.y


class Track(object):
    def __init__(self, topic, msg_type):
        self.lock = threading.Lock()
        self.items = []  # (stamp, x, y)
        self.sub = rospy.Subscriber(topic, msg_type, self.cb, queue_size=1000)

    def cb(self, msg):
        with self.lock:
            self.items.append((msg.header.stamp.to_sec(),) + xy(msg))

    def get(self):
        with self.lock:
            return sorted(self.items)


def nearest(track, t):
    times = [i[0] for i in track]
    k = bisect.bisect_left(times, t)
    best = [track[j] for j in (k - 1, k) if 0 <= j < len(track)]
    return min(best, key=lambda i: abs(i[0] - t)) if best else None


class ReplayLocalizationTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_product_replay_localization')
        cls.tmp = tempfile.mkdtemp(prefix='product_mcl_bag_')
        cls.bag = os.path.join(cls.tmp, 'match.bag')
        cls.log = open(os.path.join(cls.tmp, 'launch.log'), 'w')
        launch = roslaunch(os.path.join(ROOT, 'launch', 'eurobot2009.launch'), 'record:=true', 'bag:=' + cls.bag,
                           log=cls.log)
        try:
            rospy.wait_for_message('/mcl/pose', PoseWithCovarianceStamped, timeout=60.0)
            time.sleep(3.0)
            subprocess.run(['rosservice', 'call', '/sim/set_switch', '{name: start_cord, closed: false}'],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=20)
            time.sleep(MATCH_SECONDS)
        finally:
            stop(launch)

    @classmethod
    def tearDownClass(cls):
        cls.log.close()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_1_bag_has_what_replay_needs(self):
        with rosbag.Bag(self.bag) as bag:
            topics = bag.get_type_and_topic_info().topics
        for topic in ('/mcl/pose', '/odom', '/sim/ground_truth', '/tf', '/diagnostics'):
            self.assertIn(topic, topics, sorted(topics))
        self.assertTrue([t for t in topics if t.startswith('/hcl/')], sorted(topics))

    def test_2_replayed_estimates_follow_the_match(self):
        replayed = Track('/mcl/pose', PoseWithCovarianceStamped)
        recorded = Track('/recorded/mcl/pose', PoseWithCovarianceStamped)
        truth = Track('/sim/ground_truth', Odometry)
        replay = roslaunch(os.path.join(ROOT, 'launch', 'replay.launch'), 'bag:=' + self.bag, 'robot:=eurobot2009',
                           'sim:=true', 'rviz:=false', log=self.log)
        try:
            replay.wait(timeout=120.0)
        except subprocess.TimeoutExpired:
            self.fail('replay did not end with the bag')
        finally:
            stop(replay)
        new, old, true = replayed.get(), recorded.get(), truth.get()
        self.assertGreater(len(old), 20, 'the match estimates were not played back')
        self.assertGreater(len(new), 0.5 * len(old), 'replay gave %d estimates, the match %d' % (len(new), len(old)))
        diffs, errors = [], []
        for t, x, y in new:
            o = nearest(old, t)
            if o and abs(o[0] - t) < 0.2:
                diffs.append(math.hypot(x - o[1], y - o[2]))
            g = nearest(true, t)
            if g and abs(g[0] - t) < 0.1:
                errors.append(math.hypot(x - g[1], y - g[2]))
        diffs.sort()
        errors.sort()
        sys.stdout.write('replayed estimates: %d; vs match median %.3f m p90 %.3f m; vs truth median %.3f m\n' % (
            len(new), diffs[len(diffs) // 2], diffs[int(0.9 * len(diffs))], errors[len(errors) // 2]))
        self.assertGreater(len(diffs), 0.5 * len(new))
        self.assertLess(diffs[len(diffs) // 2], 0.05, 'replayed estimates differ from the match')
        self.assertLess(errors[len(errors) // 2], 0.10, 'replayed estimates far from the truth')

    def test_3_report_of_the_match(self):
        png = os.path.join(self.tmp, 'report.png')
        out = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'match_report.py'), self.bag, '-o', png],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=120)
        text = out.stdout.decode()
        self.assertEqual(out.returncode, 0, text)
        lines = dict(l.split(': ', 1) for l in text.splitlines() if ': ' in l and not l.startswith('  '))
        self.assertTrue(lines['localization error'].startswith('RMS'), text)
        self.assertTrue(lines['estimate'].startswith('/mcl/pose'), text)
        self.assertNotIn('/sim/ground_truth', lines['absent topics'])


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'product_replay_localization', ReplayLocalizationTest, sys.argv)
