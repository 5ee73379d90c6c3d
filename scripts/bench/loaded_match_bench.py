#!/usr/bin/env python3
"""A 2009 match at real_time_factor 1 while stress-ng loads every core at normal priority (a
laptop in the pits running a second simulation, a loaded CI): does the robot keep its timing?
Called by scripts/bench/loaded_match.sh with the workspace sourced.

    loaded_match_bench.py OUT_FOLDER [--seed K] [--no-stress]

Figures from the match's bag, each against its target:
  lost_s             time /mcl/quality said lost after the start          target 0
  pose_gap_max_s     the longest gap between /mcl/pose estimates (stale)   target < 0.5
  errors             board or device statuses at ERROR or STALE after the start (every one is a
                     false alarm: nothing is injected)                     target 0
  factor_reached     simulated / wall time over the match (at factor 1 the simulator slows down
                     rather than skip, so below 1 the machine could not keep up)
Ends with: loaded_match lost_s L pose_gap_max_s G errors E factor_reached F stress S
"""
import argparse
import os
import shutil
import signal
import socket
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
from robot_tools.chaos import invariants as chaos_invariants
from robot_tools.matches import false_alarms
from robot_tools.matches import run_match
from robot_tools.matches import match_config
from robot_tools.matches import match_rows
from robot_tools.report.match_bag import Match

ROBOT = 'eurobot2009'
POSE_STALE = 0.5  # [s] of simulated time without an estimate: the localization went stale


def lost_seconds(m, start, end):
    total, since = 0.0, None
    for _, msg, t in m.read('/mcl/quality'):
        t = t.to_sec()
        if t < start or t > end:
            continue
        if msg.lost and since is None:
            since = t
        elif not msg.lost and since is not None:
            total, since = total + t - since, None
    return total + (end - since if since is not None else 0.0)


def pose_gap_max(m, start, end):
    stamps = [t.to_sec() for _, _, t in m.read('/mcl/pose') if start <= t.to_sec() <= end]
    return max((b - a for a, b in zip(stamps, stamps[1:])), default=float('inf'))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('out')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--no-stress', action='store_true', help='the same match unloaded, to compare')
    args = parser.parse_args()
    stress = None
    cores = os.cpu_count() or 1
    if not args.no_stress:
        if not shutil.which('stress-ng'):
            sys.exit('loaded_match: stress-ng is not installed (apt-get install stress-ng; make deps installs it)')
        stress = subprocess.Popen(['stress-ng', '--cpu', str(cores), '--quiet'], preexec_fn=run_match.die_with_parent)
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % run_match.free_port(socket.SOCK_STREAM))
    try:
        rc = subprocess.call([sys.executable, os.path.join(ROOT, 'scripts', 'run_match.py'), ROBOT, '--out', args.out,
                              '--seed', str(args.seed), '--real-time-factor', '1'], env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
    finally:
        if stress:
            stress.send_signal(signal.SIGINT)
            stress.wait()
    bag = os.path.join(args.out, ROBOT + '_match.bag')
    if rc != 0 or not os.path.exists(bag):
        sys.exit('loaded_match: the match failed (exit %d): see %s' % (rc, os.path.join(args.out, ROBOT + '_launch.log')))
    m = Match(bag)
    start, _ = m.start_signal()
    end = m.match_end() or m.end
    config = match_config.robot_config(ROBOT)
    alarms = false_alarms.false_alarms(chaos_invariants.statuses(m), start, end, [], start, config)
    for _, text in alarms:
        print('  ' + text)
    lost = lost_seconds(m, start, end)
    gap = pose_gap_max(m, start, end)
    factor = float('nan')
    began, ended = match_rows.match_span(os.path.join(args.out, ROBOT + '_launch.log'))
    if began is not None and ended is not None and ended[0] > began[0]:
        factor = (ended[1] - began[1]) / (ended[0] - began[0])
    print('targets: lost_s 0, pose_gap_max_s < %.1f, errors 0' % POSE_STALE)
    print('loaded_match lost_s %.2f pose_gap_max_s %.3f errors %d factor_reached %.2f stress %s'
          % (lost, gap, len(alarms), factor, 'none' if args.no_stress else 'cpu%d' % cores))
    return 0 if lost == 0 and gap < POSE_STALE and not alarms else 1


if __name__ == '__main__':
    sys.exit(main())
