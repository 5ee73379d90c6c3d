#!/usr/bin/env python3
"""Messages and bytes per second of every topic in a bag (docs/message-budget.md's figures).

    topic_rates.py BAG [--min-rate HZ]

Prints the totals, then one row per topic, busiest first: topic, type, messages/s, bytes/s
(serialized sizes over the bag's duration)."""
import argparse
import collections

import rosbag


def rates(path):
    """(duration [s], {topic: (type, messages/s, bytes/s)})."""
    with rosbag.Bag(path) as bag:
        duration = max(1e-9, bag.get_end_time() - bag.get_start_time())
        count, size, types = collections.Counter(), collections.Counter(), {}
        for topic, raw, _ in bag.read_messages(raw=True):
            count[topic] += 1
            size[topic] += len(raw[1])
            types[topic] = raw[0]
    return duration, {t: (types[t], count[t] / duration, size[t] / duration) for t in count}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('bag')
    parser.add_argument('--min-rate', type=float, default=0.0, help='rows for topics at least this busy [Hz]')
    args = parser.parse_args()
    duration, table = rates(args.bag)
    print('%.1f s, %d topics, %.0f messages/s, %.0f bytes/s' % (
        duration, len(table), sum(r for _, r, _ in table.values()), sum(b for _, _, b in table.values())))
    for topic, (kind, rate, size) in sorted(table.items(), key=lambda kv: -kv[1][1]):
        if rate >= args.min_rate:
            print('%-48s %-40s %8.1f %9.0f' % (topic, kind, rate, size))


if __name__ == '__main__':
    main()
