"""`make soak ROBOT=... N=...`: `make matches` and `make chaos` back to back, N matches each, and one
summary of both.

    scripts/soak.py ROBOT [--n N] [--seed S] [--factor 0] [--out DIR] [--match-duration S]

Into DIR (default a new report/ROBOT/soak_<UTC time>/): matches/ and chaos/ (each runner's own
folders and table), and ROBOT_soak.txt:
  violations by class     of both runs (robot_tools.chaos.invariants's classes: motor blind, not
                          named, lost, not recovered, false alarm, match end, process died, ...)
  false alarms            in the matches (nothing injected) and in chaos (not explained by a fault)
  worst recovery          per fault class: the longest the localization took to be back within 5 cm
                          after the fault ended (never: not back)
  scores                  ours without faults beside ours under faults
and last
    soak ROBOT matches M chaos C violations V
Exit code 1 on any violation.
"""
import argparse
import collections
import glob
import os
import re
import subprocess
import sys

import yaml

from robot_tools.paths import ROOT, SCRIPTS
from robot_tools.matches import run_folders
from robot_tools.chaos.invariants import violation_class


def log(msg):
    print('soak: ' + msg, flush=True)


def run(cmd):
    """Runs a runner, its output shown as it goes; its exit code."""
    log(' '.join(os.path.basename(c) if c.endswith('.py') else c for c in cmd[1:]))
    return subprocess.call(cmd)


def read_lines(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [l.rstrip('\n') for l in f]


def matches_part(folder, robot):
    """(rows [(ours, theirs)], violations [text], closing line) of a make matches folder."""
    lines = read_lines(os.path.join(folder, '%s_matches.txt' % robot))
    rows = []
    for l in lines:
        m = re.match(r'^\s*(\d+) (\S+)\s+(\d+|-)\s+(\d+|-)\s', l)
        if m and m.group(3) != '-':
            rows.append((int(m.group(3)), int(m.group(4))))
    violations = [re.sub(r'^violation: seed \d+: ', '', l) for l in lines if l.startswith('violation: ')]
    return rows, violations, lines[-1] if lines else ''


def chaos_part(folder, robot):
    """(rows [(ours, theirs)], violations [text], faults injected, recoveries [dict]) of a make chaos folder."""
    lines = read_lines(os.path.join(folder, '%s_chaos.txt' % robot))
    rows, faults = [], 0
    for l in lines:
        m = re.match(r'^\s*(\d+) (\S+)\s+(\d+)\s+(\d+|-)\s+(\d+|-)\s+(\d+)\s', l)
        if m:
            faults += int(m.group(3))
            if m.group(4) != '-':
                rows.append((int(m.group(4)), int(m.group(5))))
    violations = [re.sub(r'^violation: seed \d+ at [0-9.]+ s: ', '', l) for l in lines if l.startswith('violation: ')]
    recoveries = []
    for path in sorted(glob.glob(os.path.join(folder, '*_seed*', 'recoveries.yaml'))):
        with open(path) as f:
            recoveries += yaml.safe_load(f) or []
    return rows, violations, faults, recoveries


def mean(values):
    return sum(values) / float(len(values)) if values else float('nan')


def summary(robot, matches, chaos):
    m_rows, m_viol, _ = matches
    c_rows, c_viol, c_faults, recoveries = chaos
    by_class = collections.Counter(violation_class(v) for v in m_viol + c_viol)
    false_m = sum(1 for v in m_viol if violation_class(v) == 'false alarm')
    false_c = sum(1 for v in c_viol if violation_class(v) == 'false alarm')
    worst = {}
    for r in recoveries:
        after = r.get('recovered_after')
        key = r.get('class') or r.get('kind')
        before = worst.get(key, 0.0)
        worst[key] = float('inf') if after is None or before == float('inf') else max(before, after)
    lines = ['soak %s: %d matches without faults, %d with %d faults injected' % (robot, len(m_rows), len(c_rows), c_faults),
             'violations by class: %s' % (', '.join('%s %d' % kv for kv in sorted(by_class.items())) or 'none'),
             'false alarms: %d in the matches, %d in chaos' % (false_m, false_c),
             'worst recovery per fault class (localization within 5 cm after the fault ended): %s' % (
                 ', '.join('%s %s' % (k, 'never' if v == float('inf') else '%.1f s' % v)
                           for k, v in sorted(worst.items())) or 'none measured'),
             'score ours: %.2f without faults (min %s), %.2f under faults (min %s); theirs %.2f, %.2f' % (
                 mean([o for o, _ in m_rows]), min([o for o, _ in m_rows], default='-'),
                 mean([o for o, _ in c_rows]), min([o for o, _ in c_rows], default='-'),
                 mean([t for _, t in m_rows]), mean([t for _, t in c_rows])),
             'soak %s matches %d chaos %d violations %d' % (robot, len(m_rows), len(c_rows), len(m_viol) + len(c_viol))]
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('robot')
    ap.add_argument('--n', type=int, default=10, help='matches of each kind')
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--factor', type=float, default=0.0)
    ap.add_argument('--out', default=None)
    ap.add_argument('--match-duration', type=float, default=None, help='[s] shorter matches (a check of the machinery)')
    args = ap.parse_args()
    if not os.path.exists(os.path.join(ROOT, 'launch', args.robot + '.launch')):
        sys.exit('soak: ROBOT=%s: no launch/%s.launch' % (args.robot, args.robot))
    own_folder = args.out is None
    if own_folder:
        args.out = run_folders.new_folder(os.path.join(ROOT, 'report', args.robot), 'soak_' + run_folders.stamp())
    os.makedirs(args.out, exist_ok=True)
    common = ['--n', str(args.n), '--seed', str(args.seed), '--factor', '%g' % args.factor]
    duration = ['--match-duration', '%g' % args.match_duration] if args.match_duration else []
    m_out, c_out = os.path.join(args.out, 'matches'), os.path.join(args.out, 'chaos')
    run([sys.executable, os.path.join(SCRIPTS, 'run_matches.py'), args.robot, '--out', m_out] + common + duration)
    run([sys.executable, os.path.join(SCRIPTS, 'run_chaos.py'), args.robot, '--out', c_out] + common + duration)
    lines = summary(args.robot, matches_part(m_out, args.robot), chaos_part(c_out, args.robot))
    with open(os.path.join(args.out, '%s_soak.txt' % args.robot), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    if own_folder:
        run_folders.mark_complete(args.out, 'soak_latest')
    print('\n'.join(lines), flush=True)
    return 1 if not lines[-1].endswith(' violations 0') else 0


if __name__ == '__main__':
    sys.exit(main())
