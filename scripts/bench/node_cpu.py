#!/usr/bin/env python3
"""Each ROS node's share of one core over a window, sampled from /proc (a bench helper).

    node_cpu.py SECONDS [--wait-topic TOPIC --wait-field FIELD --wait-value VALUE]

Finds every node registered with the master (ROS_MASTER_URI), asks each for its pid (XML-RPC
getPid, as rosnode does), and reads the process's user + system jiffies at the start and the end
of the window. Prints one line per node, highest first, then the total. Nodes sharing a process
(nodelets) count once. With --wait-*, the window starts when a message's field has that value
(e.g. /brain/match_status state running), so it covers the match and not the start-up.
"""
import argparse
import os
import sys
import time
import xmlrpc.client

import rosgraph

HZ = os.sysconf('SC_CLK_TCK')


def node_pids(master):
    pids = {}
    pubs, subs, srvs = master.getSystemState()
    names = {n for _, nodes in pubs + subs + srvs for n in nodes}
    for name in sorted(names):
        try:
            code, _, pid = xmlrpc.client.ServerProxy(master.lookupNode(name)).getPid('/node_cpu')
            if code == 1:
                pids.setdefault(pid, name)
        except Exception:
            continue
    return pids


def jiffies(pid):
    try:
        with open('/proc/%d/stat' % pid) as f:
            fields = f.read().rsplit(')', 1)[1].split()
        return int(fields[11]) + int(fields[12])  # utime + stime
    except (OSError, IndexError, ValueError):
        return None


def wait_for_value(topic, field, value, timeout):
    import rospy
    import rostopic
    rospy.init_node('node_cpu', anonymous=True, disable_signals=True)
    cls, _, _ = rostopic.get_topic_class(topic, blocking=True)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            msg = rospy.wait_for_message(topic, cls, timeout=2.0)
        except rospy.ROSException:
            continue
        if str(getattr(msg, field, None)) == value:
            return True
    return False


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('seconds', type=float)
    ap.add_argument('--wait-topic')
    ap.add_argument('--wait-field', default='state')
    ap.add_argument('--wait-value', default='running')
    ap.add_argument('--wait-timeout', type=float, default=300.0)
    args = ap.parse_args()
    master = rosgraph.Master('/node_cpu')
    deadline = time.monotonic() + args.wait_timeout
    while True:
        try:
            master.getPid()
            break
        except Exception:
            if time.monotonic() > deadline:
                sys.exit('node_cpu: no ROS master')
            time.sleep(1.0)
    if args.wait_topic and not wait_for_value(args.wait_topic, args.wait_field, args.wait_value, args.wait_timeout):
        sys.exit('node_cpu: %s never had %s = %s' % (args.wait_topic, args.wait_field, args.wait_value))
    pids = {pid: name for pid, name in node_pids(master).items() if pid != os.getpid()}
    start = {pid: jiffies(pid) for pid in pids}
    t0 = time.monotonic()
    time.sleep(args.seconds)
    wall = time.monotonic() - t0
    rows = []
    for pid, name in pids.items():
        end = jiffies(pid)
        if start[pid] is None or end is None:
            continue
        rows.append((100.0 * (end - start[pid]) / HZ / wall, name))
    rows.sort(reverse=True)
    for share, name in rows:
        print('node_cpu %-24s %5.1f %%' % (name, share))
    print('node_cpu %-24s %5.1f %% of one core over %.0f s' % ('total', sum(r[0] for r in rows), wall))


if __name__ == '__main__':
    main()
