"""`make matches`: many seeded simulated matches of a robot, one at a time, headless, with a
row of figures per match, a summary PNG and a check of the invariants every match must keep.

    scripts/run_matches.py ROBOT [--n 20] [--seed 1] [--factor 0] [--out DIR] [--strategy NAME] [--overlay FILE]
                           [--side ZONE]
                           [--cluster tcp://HOST:8786] [--workers W] [--fetch-bags] [--match-duration S]

The matches run on a Dask distributed cluster (robot_tools.matches.cluster): the scheduler at
--cluster, or a local cluster of --workers processes (default: one per two cores). Match k (seed
SEED + k) is one scripts/run_match.py run (launch with record:=true, wait for
"ready", pull the start cord, follow the match to its end, stop, write the match report) in
DIR/ROBOT_seed<seed>/ (DIR: a new report/ROBOT/matches_<UTC time>/, report/ROBOT/matches_latest
pointing to the last complete one), on a ROS master of its own. The opponent cycles
between matches through
  random_walk  the config's own opponent (sim/world/opponent),
  route        a scripted loop around the game elements (mode script),
  blocker      drives to our goal (the first table/score_zones zone whose team is `placer` or
               our colour) and stays there (mode script, one waypoint, a pause longer than a match),
  player       plays the game for the other colour (mode player, its config block sim/world/opponent/player),
written as one small YAML per match (DIR/ROBOT_seed<seed>/overlay.yaml, the launch argument
`overlay`; `make tune` adds a trial's parameters to it). Every figure comes from the match's bag (robot_tools.report.match_bag's Match) and
launch log:
  score ours / opponent  the referee's last /sim/match
  result                 won, lost or draw: ours against the opponent's
  contacts               times our true outline and the opponent's come within touching
                         distance (/sim/ground_truth, /sim/opponent; radii from the config)
  triggers, stuck        trigger firings (Match.triggers()), of them the `stuck` trigger's
  stalls, in contact     driver goals that ended on a stall (the wheels turned, the odometry did
                         not), and of them those that ended with the outlines touching
  false alarms           diagnostics at ERROR or STALE during the match (robot_tools.matches.false_alarms:
                         nothing is injected here, so nothing explains one)
  loc RMSE / max         /mcl/pose against /sim/ground_truth from the start signal to the end
  idle / idle max        [s] idle while the match runs (robot_tools.matches.idle_time: no driver goal
                         active and zero commanded speed), in all and the longest stretch
  effectors off          [s] from the match end (/brain/match_status ended or /sim/match over,
                         the earlier) to the latched /effectors/deactivated going true
  wall                   [s] from launch to report
Invariants (a violation makes the exit code 1, each is printed with its seed): no node died
(launch log), the match started (and ended), the effectors were off 1 s after the match end, our
robot's true pose stayed on the table ([0, length] x [0, width] of table:), no idle stretch over
10 s while more than 10 s of the match remained, no false alarm; a match lost with its workers is
a violation.
Before the last line, `cluster: W workers, R retries` (R: matches rerun because their worker
died), the results against each opponent (`opponent K: wins W losses L draws D win_rate R`) and
against all of them, and then the closing line:
    wins W losses L draws D
    matches N score_mean S score_min A violations V wall_s W factor F
"""
import argparse
import os
import sys
import time


from robot_tools.matches import cluster as match_cluster
from robot_tools.matches import run_folders
from robot_tools.matches.match_config import OPPONENTS, robot_config, side_overlay, user_overlay, with_duration
from robot_tools.matches.match_config import merged
from robot_tools.matches.match_rows import summary_lines
from robot_tools.paths import ROOT


def log(msg):
    print('matches: ' + msg, flush=True)

def summary_png(rows, path, robot, factor):
    """Score histogram, localization error per match, and the outcome of each seed."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator
    fig, (ax_hist, ax_loc, ax_seed) = plt.subplots(3, 1, figsize=(max(8.0, 0.55 * len(rows) + 3), 12))
    fig.suptitle('%s: %d matches at real-time factor %g%s' % (robot, len(rows), factor,
                 ' (as fast as the machine goes)' if factor == 0 else ''), weight='bold')
    scored = [r for r in rows if r.ours is not None]
    if scored:
        top = max(max(r.ours, r.theirs) for r in scored)
        bins = [b - 0.5 for b in range(0, top + 2)]
        ax_hist.hist([[r.ours for r in scored], [r.theirs for r in scored]], bins=bins, label=['ours', 'opponent'],
                     color=['#1565c0', '#8e24aa'])
        ax_hist.legend()
    ax_hist.set_xlabel('score')
    ax_hist.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax_hist.set_ylabel('matches')
    ax_hist.set_title('score histogram', loc='left')

    labels = ['%d\n%s' % (r.seed, r.opponent) for r in rows]
    with_errors = [(i, r) for i, r in enumerate(rows) if r.errors]
    if with_errors:
        ax_loc.boxplot([[1000.0 * e for e in r.errors] for _, r in with_errors], positions=[i for i, _ in with_errors],
                       widths=0.6, showfliers=True, flierprops=dict(markersize=2))
    ax_loc.set_xticks(range(len(rows)))
    ax_loc.set_xticklabels(labels, fontsize=7)
    ax_loc.set_xlim(-0.7, len(rows) - 0.3)
    ax_loc.set_ylabel('position error [mm]')
    ax_loc.set_title('localization error during the match (/mcl/pose vs truth)', loc='left')
    ax_loc.grid(alpha=0.3, axis='y')

    xs = range(len(rows))
    ax_seed.bar([x - 0.2 for x in xs], [r.ours or 0 for r in rows], 0.4, color='#1565c0', label='ours')
    ax_seed.bar([x + 0.2 for x in xs], [r.theirs or 0 for r in rows], 0.4, color='#8e24aa', label='opponent')
    for x, r in zip(xs, rows):
        if r.violations:
            ax_seed.plot(x, max(r.ours or 0, r.theirs or 0) + 0.5, 'x', color='red', ms=12, mew=3)
    ax_seed.plot([], [], 'x', color='red', ms=10, mew=3, label='invariant broken')
    ax_seed.set_xticks(list(xs))
    ax_seed.set_xticklabels(['%s\nc%s s%s' % (label, '-' if r.contacts is None else r.contacts,
                                               '-' if r.stuck is None else r.stuck)
                             for label, r in zip(labels, rows)], fontsize=7)
    ax_seed.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax_seed.set_xlim(-0.7, len(rows) - 0.3)
    ax_seed.set_ylabel('score')
    ax_seed.set_title('per seed: score (seed, opponent, c: contacts, s: stuck events)', loc='left')
    ax_seed.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


# ---- the runner --------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('robot')
    ap.add_argument('--n', type=int, default=20, help='number of matches')
    ap.add_argument('--seed', type=int, default=1, help='seed of the first match (then +1 each)')
    ap.add_argument('--factor', type=float, default=0.0, help='real_time_factor (0: as fast as the machine goes)')
    ap.add_argument('--out', default=None, help='where the match folders go (default: a new '
                    'report/ROBOT/matches_<UTC time>/, and report/ROBOT/matches_latest pointing to it at the end)')
    ap.add_argument('--overlay', default=None, help='YAML of parameters (several: comma-separated) over the config for every match '
                    '(as make run OVERLAY=...); each match adds its opponent')
    ap.add_argument('--strategy', default=None, help="the brain's strategy (default: the robot's)")
    ap.add_argument('--side', default=None, help='the start zone to play from (default: where the config starts '
                    'the simulated robot)')
    ap.add_argument('--cluster', default=None, help='Dask scheduler address, tcp://HOST:8786 (default: a local cluster)')
    ap.add_argument('--workers', type=int, default=None, help='local cluster size (default: one worker per two cores)')
    ap.add_argument('--fetch-bags', action='store_true', help="bring each match's bag back from its worker")
    ap.add_argument('--match-duration', type=float, default=None,
                    help="[s] shorter matches for a quick check of the machinery (default: the config's)")
    args = ap.parse_args()
    if args.cluster and args.workers:
        sys.exit('matches: --workers sizes the local cluster; a remote cluster has the workers it has')
    if not os.path.exists(os.path.join(ROOT, 'launch', args.robot + '.launch')):
        sys.exit('matches: ROBOT=%s: no launch/%s.launch' % (args.robot, args.robot))
    config = robot_config(args.robot)
    if 'opponent' not in config.get('sim', {}).get('world', {}):
        sys.exit('matches: %s has no simulated match (no sim/world/opponent in its config)' % args.robot)
    user = user_overlay(args.overlay, 'matches')
    if args.side:
        user = merged(user, side_overlay(args.robot, user, args.side, 'matches'))
    own_folder = args.out is None
    if own_folder:
        args.out = run_folders.new_folder(os.path.join(ROOT, 'report', args.robot), 'matches_' + run_folders.stamp())

    began = time.monotonic()
    jobs = [match_cluster.Job(robot=args.robot, seed=args.seed + k, opponent=OPPONENTS[k % len(OPPONENTS)],
                              factor=args.factor, strategy=args.strategy,
                              params=with_duration(user, args.match_duration), out=args.out,
                              fetch_bags=args.fetch_bags, shared_disk=not args.cluster) for k in range(args.n)]
    os.makedirs(args.out, exist_ok=True)
    client, cluster = match_cluster.connect(args.cluster, args.workers)
    workers = match_cluster.worker_count(client)
    log('%d match(es) on %s, %d worker(s)' % (args.n, args.cluster or 'a local cluster', workers))
    done = []

    def said(k, row, retried):
        done.append(k)
        log('[%d/%d] seed %d (%s) ended: score ours %s, opponent %s, %s s wall, %s%s' % (
            len(done), args.n, row.seed, row.opponent, '-' if row.ours is None else row.ours,
            '-' if row.theirs is None else row.theirs, '-' if row.wall is None else '%.0f' % row.wall,
            'violations: %d' % len(row.violations) if row.violations else 'no violation',
            ', %d retries so far' % retried if retried else ''))

    interrupted = False
    try:
        rows, retried = match_cluster.run_jobs(client, jobs, said)
    except KeyboardInterrupt:
        log('interrupted: no summary (the matches still running are stopped with their workers)')
        interrupted, rows, retried = True, [], 0
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    if interrupted:
        run_folders.mark_incomplete(args.out, 'interrupted')
        return 130

    wall = time.monotonic() - began
    png = os.path.join(args.out, '%s_matches.png' % args.robot)
    summary_png(rows, png, args.robot, args.factor)
    lines = summary_lines(rows, wall, args.factor,
                          ['summary: %s' % png, 'cluster: %d workers, %d retries' % (workers, retried)])
    with open(os.path.join(args.out, '%s_matches.txt' % args.robot), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    if own_folder:
        lines.insert(len(lines) - 2, 'folder: %s (%s)' % (args.out, run_folders.mark_complete(args.out, 'matches_latest')))
    print('\n'.join(lines), flush=True)
    return 1 if any(r.violations for r in rows) else 0


if __name__ == '__main__':
    sys.exit(main())
