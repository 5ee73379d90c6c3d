"""`make chaos`: simulated matches with faults injected while they run, and the invariants
every robot must keep whatever breaks.

    scripts/run_chaos.py ROBOT [--n 10] [--seed 1] [--factor 0] [--out DIR] [--schedule FILE]

Match k (seed SEED + k; opponent random walk, route, blocker in turn, as `make matches`) is one
scripts/run_match.py run on a ROS master of its own, with a fault schedule
(robot_tools.chaos.faults): the fault classes the robot has (on its buses, in the world, in its
processes) shuffled with the seed and dealt out over the matches, one every ~9 s at random
times, so that N matches together cover every class. --schedule FILE replaces the draw with a
fixed YAML list of schedules (one list of faults per match, used in turn). The invariants
(robot_tools.chaos.invariants): no motor runs blind, each fault is named on /diagnostics, nothing
is lost from the bag, the match still ends with the effectors off, the robot recovers its
localization after each fault, and no false alarm (robot_tools.matches.false_alarms: a diagnostic at ERROR
or STALE that no injected fault explains). Also: the match started and ended, and no process died that was
not killed on purpose.

A row per match (faults injected, violations), then every violation with its match time, and
    matches N faults F violations V
Exit code 1 on any violation. Every match keeps its folder DIR/ROBOT_seed<seed>/ (bag, match
report PNG and text, faults.yaml: what was injected when, launch log); DIR/ROBOT_chaos.txt has
the table.
"""
import argparse
import os
import sys
import time

import yaml

from robot_tools.paths import ROOT
from robot_tools.chaos import faults as chaos_faults
from robot_tools.chaos import invariants as inv
from robot_tools.matches import false_alarms
from robot_tools.matches import run_folders
from robot_tools.matches import match_config
from robot_tools.matches import match_rows
from robot_tools.matches import run_match
from robot_tools.report.match_bag import Match


def log(msg):
    print('chaos: ' + msg, flush=True)


def unexpected_deaths(folder, robot, faults):
    """Processes that died without being killed on purpose (launch log)."""
    killed = {f['target'].strip('/') for f in faults if f['kind'] == 'kill'}
    deaths = match_rows.node_deaths(os.path.join(folder, robot + '_launch.log'))
    return ['node %s died: %s' % (name, line) for name, line in deaths.items()
            if name.split('[')[-1].rsplit('-', 1)[0] not in killed]


def judge(folder, robot, config, rc):
    """(faults injected, [(match time, violation)], (our score, theirs) or None) of one finished
    match, from one reading of its bag."""
    bag = os.path.join(folder, robot + '_match.bag')
    log_path = os.path.join(folder, 'faults.yaml')
    faults = []
    if os.path.exists(log_path):
        with open(log_path) as f:
            faults = yaml.safe_load(f) or []
    violations = [(0.0, v) for v in unexpected_deaths(folder, robot, faults)]
    violations += [(f['start'], '%s %s was not injected: %s' % (f['kind'], f.get('target', ''), f['outcome']))
                   for f in faults if f['outcome'].startswith(('REFUSED', 'FAILED')) or 'NOT back' in f['outcome']]
    if not os.path.exists(bag):
        return faults, violations + [(0.0, 'no bag (see %s)' % os.path.join(folder, 'run_match.out'))], None
    try:
        m = Match(bag)
    except Exception as e:
        return faults, violations + [(0.0, 'the bag is not readable: %s' % e)], None
    _, _, series = m.score_series()
    score = (series[-1][1], series[-1][2]) if series else None
    start, _ = m.start_signal()
    end = m.match_end()
    if start is None:
        return faults, violations + [(0.0, 'the match never started')], score
    violations = [(t - start if t else 0.0, v) for t, v in violations]
    violations += inv.no_motor_runs_blind(m, config, faults, start)
    series = inv.statuses(m)
    violations += inv.faults_named(m, faults, start, series)
    violations += false_alarms.false_alarms(series, start, end if end is not None else m.end, faults, start, config)
    violations += inv.nothing_lost(m, faults, start, end if end is not None else m.end, start, config)
    violations += inv.match_ends(m, faults, end, start, match_rows.effectors_off_delay)
    found = inv.recoveries(m, faults, end)
    violations += inv.robot_recovers(m, faults, end, start, found)
    with open(os.path.join(folder, 'recoveries.yaml'), 'w') as f:  # for make soak's worst per class
        yaml.safe_dump([{'class': fl.get('class', fl['kind']), 'kind': fl['kind'], 'target': fl.get('target', ''),
                         'recovered_after': None if back is None else round(back - fl['end'], 3),
                         'worst_m': None if worst != worst else round(worst, 4)}
                        for fl, _, back, worst in found], f, default_flow_style=False)
    left = match_rows.off_table(m.poses('/sim/ground_truth'), config['table']['length'], config['table']['width'])
    if left:
        violations.append((left[0] - start, 'our robot left the table at (%.3f, %.3f)' % (left[1], left[2])))
    m.bag.close()
    if rc != 0 and not violations:
        violations.append((0.0, 'run_match.py exited with code %d' % rc))
    return faults, sorted(violations), score


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('robot')
    ap.add_argument('--n', type=int, default=10)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--factor', type=float, default=0.0, help='real_time_factor (0: as fast as the machine goes)')
    ap.add_argument('--out', default=None, help='where the match folders go (default: a new '
                    'report/ROBOT/chaos_<UTC time>/, and report/ROBOT/chaos_latest pointing to it at the end)')
    ap.add_argument('--schedule', default=None, help='YAML: a list of fault lists, one per match, used in turn')
    ap.add_argument('--match-duration', type=float, default=None,
                    help="[s] shorter matches for a quick check of the machinery (default: the config's)")
    args = ap.parse_args()
    if not os.path.exists(os.path.join(ROOT, 'launch', args.robot + '.launch')):
        sys.exit('chaos: ROBOT=%s: no launch/%s.launch' % (args.robot, args.robot))
    config = match_config.robot_config(args.robot)
    if 'opponent' not in config.get('sim', {}).get('world', {}):
        sys.exit('chaos: %s has no simulated match (no sim/world/opponent in its config)' % args.robot)
    duration = args.match_duration or float(config.get('brain', {}).get('match', {}).get('duration', 90.0))
    if args.schedule:
        with open(args.schedule) as f:
            fixed = yaml.safe_load(f)
        if not (isinstance(fixed, list) and fixed and all(isinstance(s, list) for s in fixed)):
            sys.exit('chaos: --schedule %s: must be a YAML list of fault lists (one per match)' % args.schedule)
        schedules = [fixed[k % len(fixed)] for k in range(args.n)]
    else:
        schedules = chaos_faults.draw_schedules(config, args.n, args.seed, duration)
    own_folder = args.out is None
    if own_folder:
        args.out = run_folders.new_folder(os.path.join(ROOT, 'report', args.robot), 'chaos_' + run_folders.stamp())
    os.makedirs(args.out, exist_ok=True)
    began = time.monotonic()
    rows, lines = [], []
    for k in range(args.n):
        seed, kind = args.seed + k, match_config.OPPONENTS[k % len(match_config.OPPONENTS)]
        folder = os.path.join(args.out, '%s_seed%d' % (args.robot, seed))
        os.makedirs(folder, exist_ok=True)
        opponent = match_config.opponent_params(kind, config)
        overlay = match_config.write_overlay(folder, match_config.with_duration(match_config.match_overlay(opponent),
                                                                             args.match_duration))
        schedule = os.path.join(folder, 'schedule.yaml')
        with open(schedule, 'w') as f:
            yaml.safe_dump(schedules[k], f, default_flow_style=None)
        log('[%d/%d] seed %d, opponent %s, faults: %s' % (k + 1, args.n, seed, kind, ', '.join(
            '%s %s at %.0f s' % (f['kind'], f.get('target', ''), f['at']) for f in schedules[k])))
        t0 = time.monotonic()
        rc = run_match.run_one(args.robot, seed, args.factor, folder, overlay, None, k + 1, args.n,
                                 extra=['--faults', schedule])
        faults, violations, m_score = judge(folder, args.robot, match_config.merged(
            config, {'sim': {'world': {'opponent': opponent}}}), rc)
        rows.append((seed, kind, len(faults), m_score, len(violations), time.monotonic() - t0))
        lines += ['violation: seed %d at %.1f s: %s' % (seed, t, v) for t, v in violations]
        log('[%d/%d] seed %d: %d fault(s), %s' % (k + 1, args.n, seed, len(faults),
                                                  '%d violation(s)' % len(violations) if violations else 'no violation'))
        for t, v in violations:
            log('  at %.1f s: %s' % (t, v))
    table = ['seed opponent    faults ours  opp violations wall_s']
    table += ['%4d %-11s %6d %4s %4s %10d %6.0f' % (s, kind, n, '-' if sc is None else sc[0], '-' if sc is None else sc[1],
                                                   v, w) for s, kind, n, sc, v, w in rows]
    total_faults, total_violations = sum(r[2] for r in rows), sum(r[4] for r in rows)
    closing = 'matches %d faults %d violations %d' % (len(rows), total_faults, total_violations)
    out = table + lines + ['wall %.0f s, factor %g, match folders in %s' % (time.monotonic() - began, args.factor, args.out),
                           closing]
    with open(os.path.join(args.out, '%s_chaos.txt' % args.robot), 'w') as f:
        f.write('\n'.join(out) + '\n')
    if own_folder:
        run_folders.mark_complete(args.out, 'chaos_latest')
    print('\n'.join(out), flush=True)
    return 1 if total_violations else 0


if __name__ == '__main__':
    sys.exit(main())
