#!/usr/bin/env python3
"""The latency bench's measuring side (scripts/bench/latency.sh): runs test/scripts/reflex_trace.py
on the robot latency.launch started and prints p50/p99 per hop, end to end, the HAL devices'
refresh times and wake counts, and the pose age.
    latency_bench.py reflex|avoid [N]   ends with `figures <name> <value> ..` lines"""
import sys
import time

import rospy
from nav_msgs.msg import Odometry

from reflex_trace import ReflexBench
from test_support import percentile


def report(name, events, hops):
    print('%s: %d events' % (name, len(events)))
    for a, b in hops:
        d = [1e3 * (e[b] - e[a]) for e in events if e.get(a) is not None and e.get(b) is not None]
        if d:
            print('  %-26s p50 %6.2f ms  p99 %6.2f ms  (n %d)' % ('%s -> %s' % (a, b), percentile(d, 50), percentile(d, 99), len(d)))
    total = [1e3 * (e['bus'] - e['pdo']) for e in events]
    names = [a for a, _ in hops] + [hops[-1][1]]
    for e in sorted(events, key=lambda e: e['pdo'] - e['bus'])[:3]:  # the slowest: where their time went
        print('  slow event %.1f ms: %s' % (1e3 * (e['bus'] - e['pdo']), '  '.join(
            '%s %+.1f' % (k, 1e3 * (e[k] - e['pdo'])) if e.get(k) is not None else '%s -' % k for k in names)))
    if total:
        print('  %-26s p50 %6.2f ms  p99 %6.2f ms  max %6.2f ms' % ('bus frame -> bus frame', percentile(total, 50),
                                                                   percentile(total, 99), max(total)))
    return total


def main():
    """latency_bench.py reflex|avoid [N]: prints the hops, then `figures <name> <value>..`."""
    mode = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    rospy.init_node('latency_bench')
    b = ReflexBench()
    if not rospy.wait_for_message('/sim/ground_truth', Odometry, 60.0):
        print('no ground truth')
        return 1
    time.sleep(5.0)  # the brain's idle state and the localization settle
    nan = float('nan')
    if mode == 'reflex':
        events = b.reflex_events(n)
        total = report('reflex (the brain\'s opponent_ahead trigger)', events,
                       [('pdo', 'hcl'), ('hcl', 'hal'), ('hal', 'brain'), ('brain', 'command'), ('command', 'bus')])
        print('figures reflex_p50_ms %.1f reflex_p99_ms %.1f' % (percentile(total, 50), percentile(total, 99)))
    else:
        events = b.avoidance_events(n)
        total = report('avoidance (the driver alone; from the reading it acted on to the frame carrying its first braking command)', events,
                       [('pdo', 'hcl'), ('hcl', 'hal'), ('hal', 'brain'), ('brain', 'command'), ('command', 'bus')])
        print('figures avoid_p99_ms %.1f' % percentile(total, 99))
    print('HAL devices, mean refresh time [ms]: ' + ', '.join(
        '%s %s' % (k.split('/')[-1], v['mean refresh time [ms]']) for k, v in sorted(b.refresh_ms.items())))
    for k, v in sorted(b.refresh_ms.items()):
        if v.get('woken refreshes', '0') != '0' or v.get('wakes deferred to the rate limit', '0') != '0':
            print('  %s: %s' % (k, v))
    ages = [1e3 * a for a in b.pose_ages[len(b.pose_ages) // 10:]]
    if ages:
        print('pose age at arrival: p50 %.1f ms  p99 %.1f ms  (n %d)' % (percentile(ages, 50), percentile(ages, 99), len(ages)))
    for name, d in (('/mcl/pose', b.pose_after_odom), ('tf map -> odom', b.tf_after_odom)):
        d = [1e3 * a for a in d[len(d) // 10:]]
        if d:
            print('%s after the /odom it includes: p50 %.1f ms  p99 %.1f ms  (n %d)' % (
                name, percentile(d, 50), percentile(d, 99), len(d)))
    print('figures pose_age_p99_ms %.1f' % (percentile(ages, 99) if ages else nan))
    b.sniffer.close()
    return 0 if len(events) >= max(1, n // 2) else 1


if __name__ == '__main__':
    sys.exit(main())
