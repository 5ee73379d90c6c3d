#!/usr/bin/env python3
"""A simulated eurobot2009 match recorded with record:=true replays through localization:
1. the bag holds the HCL state, /odom, /mcl/pose and the ground truth;
2. launch/replay.launch (the localization alone on the recorded HAL outputs, on the bag's clock)
   gives the match's own estimates again: every replayed /mcl/pose within 1 cm and 1 deg of the
   recorded one of the same stamp (played beside them on /recorded/mcl/pose), over the whole bag
   from its first second to its last, at rates 1 and 2, at least 95 % of them, as the replay's own
   summary line says; through:=hal (every device on the
   recorded board states) follows the match and the truth;
3. the match report of that bag has a localization error, a trajectory and the brain's states.
The match: the start cord is pulled (sim /sim/set_switch) so the strategy drives."""
import bisect
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import unittest

import rosbag
import rospy
from robot_core.geometry import wrap_angle, yaw_of
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
from robot_sim.srv import SetSwitch

from test_support import roslaunch, stop  # beside this script

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
MATCH_SECONDS = 10.0


def xy(msg):
    p = msg.pose.pose.position
    return p.x, p.y


def xyyaw(msg):
    q = msg.pose.pose.orientation
    return xy(msg) + (yaw_of(q),)


class Track(object):
    def __init__(self, topic, msg_type):
        self.lock = threading.Lock()
        self.items = []  # (stamp, x, y, yaw)
        self.sub = rospy.Subscriber(topic, msg_type, self.cb, queue_size=1000)

    def cb(self, msg):
        with self.lock:
            self.items.append((msg.header.stamp.to_sec(),) + xyyaw(msg))

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
        # Recorded at real time: the replays take the bag's simulated length, and start-up (wall
        # time) would add simulated seconds at a higher factor.
        launch = roslaunch(os.path.join(ROOT, 'launch', 'eurobot2009.launch'), 'record:=true', 'bag:=' + cls.bag,
                           log=cls.log)
        try:
            rospy.wait_for_message('/mcl/pose', PoseWithCovarianceStamped, timeout=60.0)
            rospy.wait_for_service('/sim/set_switch', 20.0)
            rospy.sleep(3.0)
            rospy.ServiceProxy('/sim/set_switch', SetSwitch)(name='start_cord', closed=False)
            rospy.sleep(MATCH_SECONDS)
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

    def replay(self, *args):
        """Runs replay.launch on the match's bag; (replayed, recorded, truth) tracks."""
        replayed = Track('/mcl/pose', PoseWithCovarianceStamped)
        recorded = Track('/recorded/mcl/pose', PoseWithCovarianceStamped)
        truth = Track('/sim/ground_truth', Odometry)
        log_path = os.path.join(self.tmp, 'replay_%s.log' % '_'.join(a.replace(':=', '') for a in args))
        with open(log_path, 'w') as log:
            replay = roslaunch(os.path.join(ROOT, 'launch', 'replay.launch'), 'bag:=' + self.bag, 'robot:=eurobot2009',
                               'sim:=true', *args, log=log)
            try:
                rc = replay.wait(timeout=120.0)
            except subprocess.TimeoutExpired:
                self.fail('replay did not end with the bag')
            finally:
                stop(replay)
                for t in (replayed, recorded, truth):
                    t.sub.unregister()
        self.assertEqual(rc, 0, 'replay.launch did not end cleanly at the bag end')
        with open(log_path) as f:
            self.summary = [l.strip() for l in f if l.startswith('replay: reproduced')]
        return replayed.get(), recorded.get(), truth.get()

    def check_reproduces(self, rate):
        new, old, _ = self.replay('rate:=%s' % rate)
        self.assertGreater(len(old), 20, 'the match estimates were not played back')
        by_stamp = {round(t, 6): (x, y, a) for t, x, y, a in old}
        matched, worst_xy, worst_yaw, off = [], 0.0, 0.0, []
        for t, x, y, a in new:
            o = by_stamp.get(round(t, 6))
            if o is None:
                continue
            d = math.hypot(x - o[0], y - o[1])
            da = abs(wrap_angle(a - o[2]))
            matched.append(t)
            worst_xy, worst_yaw = max(worst_xy, d), max(worst_yaw, da)
            if d > 0.01 or da > math.radians(1.0):
                off.append('%.2f s: %.3f m, %.2f deg' % (t - old[0][0], d, math.degrees(da)))
        sys.stdout.write('rate %s: %d replayed estimates, %d at a stamp of the match (of %d); worst %.4f m, %.3f deg\n'
                         % (rate, len(new), len(matched), len(old), worst_xy, math.degrees(worst_yaw)))
        self.assertEqual(off, [], 'replayed estimates more than 1 cm / 1 deg from the match at the same stamp')
        self.assertGreater(len(matched), 0.5 * len(old), 'too few replayed estimates at the match\'s stamps')
        # The whole bag, from its first second to its last: estimates at the match's stamps in
        # every second of it after the first.
        seconds = {int(t - old[0][0]) for t in matched}
        missing = [k for k in range(1, int(old[-1][0] - old[0][0])) if k not in seconds]
        sys.stdout.write('rate %s: first match %.2f s, last %.2f s before the end\n'
                         % (rate, min(matched) - old[0][0], old[-1][0] - max(matched)))
        self.assertEqual(missing, [], 'seconds of the bag without a replayed estimate at a stamp of the match')
        # The replay says it itself, in one line: at least 95 % reproduced.
        self.assertEqual(len(self.summary), 1, 'no summary line from the replay')
        share = float(re.search(r'\(([0-9.]+) %\)', self.summary[0]).group(1))
        self.assertGreaterEqual(share, 95.0, self.summary[0])
        self.assertGreaterEqual(len(matched), 0.95 * len(old), self.summary[0])

    def test_2_replay_through_localization_reproduces_the_match_at_rate_1(self):
        self.check_reproduces(1.0)

    def test_3_replay_through_localization_reproduces_the_match_at_rate_2(self):
        self.check_reproduces(2.0)

    def test_4_replay_through_hal_follows_the_match(self):
        new, old, true = self.replay('through:=hal')
        self.assertGreater(len(old), 20, 'the match estimates were not played back')
        self.assertGreater(len(new), 0.5 * len(old), 'replay gave %d estimates, the match %d' % (len(new), len(old)))
        diffs, errors = [], []
        for t, x, y, _ in new:
            o = nearest(old, t)
            if o and abs(o[0] - t) < 0.2:
                diffs.append(math.hypot(x - o[1], y - o[2]))
            g = nearest(true, t)
            if g and abs(g[0] - t) < 0.1:
                errors.append(math.hypot(x - g[1], y - g[2]))
        diffs.sort()
        errors.sort()
        sys.stdout.write('through hal: %d estimates; vs match median %.3f m p90 %.3f m; vs truth median %.3f m\n' % (
            len(new), diffs[len(diffs) // 2], diffs[int(0.9 * len(diffs))], errors[len(errors) // 2]))
        self.assertGreater(len(diffs), 0.5 * len(new))
        self.assertLess(diffs[len(diffs) // 2], 0.05, 'replayed estimates differ from the match')
        self.assertLess(errors[len(errors) // 2], 0.10, 'replayed estimates far from the truth')

    def test_5_report_of_the_match(self):
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
