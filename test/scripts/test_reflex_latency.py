#!/usr/bin/env python3
"""An opponent appearing in front of the driving robot stops the motors on the CAN bus, every
time, and the stop is driven by the reading, not by the next tick of a polling loop: the median
over 20 events, from the bus frame carrying the first reading inside the brain's opponent_ahead
distance to the zero-PWM frame (test/launch/reflex_latency.test), stays under 35 ms. With the
device loops waiting for their next tick the same path's median was above 40 ms. The tail (p99)
is a speed target and lives in the latency benchmark (scripts/bench/latency.sh, make bench),
which prints it against its target: on a slow or loaded machine the tail is the machine's."""
import sys
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

from reflex_trace import ReflexBench
from test_support import percentile

EVENTS = 20
BOUND_MS = 35.0  # [ms] the median: above it, the stop waits for a polling tick


class ReflexLatencyTest(unittest.TestCase):
    def test_an_opponent_ahead_stops_the_motors_on_the_bus_in_time(self):
        rospy.init_node('test_reflex_latency')
        bench = ReflexBench()
        self.assertIsNotNone(rospy.wait_for_message('/sim/ground_truth', Odometry, 60.0))
        time.sleep(5.0)  # the brain reaches its idle state, the localization settles
        events = bench.reflex_events(EVENTS)
        bench.sniffer.close()
        total = sorted(1e3 * (e['bus'] - e['pdo']) for e in events)
        for e in events:  # where each stop's time went: a failure names the hop
            print('reflex hops [ms]: ranger frame -> hcl %.1f -> hal %.1f -> brain %.1f -> command %.1f -> bus %.1f' % tuple(
                1e3 * (e[b] - e[a]) for a, b in (('pdo', 'hcl'), ('hcl', 'hal'), ('hal', 'brain'), ('brain', 'command'),
                                                 ('command', 'bus'))))
        print('reflex bus frame -> bus frame over %d events: p50 %.1f ms, p99 %.1f ms, max %.1f ms' % (
            len(total), percentile(total, 50), percentile(total, 99), total[-1] if total else float('nan')))
        self.assertGreaterEqual(len(events), EVENTS, 'only %d of %d stops could be traced' % (len(events), EVENTS))
        self.assertLess(percentile(total, 50), BOUND_MS, 'reflex p50 %.1f ms (all: %s)' % (
            percentile(total, 50), ', '.join('%.1f' % t for t in total)))


if __name__ == '__main__':
    rostest.rosrun('system_tests', 'reflex_latency', ReflexLatencyTest, sys.argv)
