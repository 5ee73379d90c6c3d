#!/usr/bin/env python3
"""`make matches`: many seeded simulated matches of a robot, one at a time, headless, with a
row of figures per match, a summary PNG and a check of the invariants every match must keep.

    scripts/run_matches.py ROBOT [--n 20] [--seed 1] [--factor 0] [--out DIR] [--strategy NAME] [--overlay FILE]
                           [--side ZONE]
                           [--cluster tcp://HOST:8786] [--workers W] [--fetch-bags] [--match-duration S]

The matches run on a Dask distributed cluster (scripts/match_cluster.py): the scheduler at
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
`overlay`; `make tune` adds a trial's parameters to it). Every figure comes from the match's bag (scripts/match_report.py's Match) and
launch log:
  score ours / opponent  the referee's last /sim/match
  result                 won, lost or draw: ours against the opponent's
  contacts               times our true outline and the opponent's come within touching
                         distance (/sim/ground_truth, /sim/opponent; radii from the config)
  triggers, stuck        trigger firings (Match.triggers()), of them the `stuck` trigger's
  stalls, in contact     driver goals that ended on a stall (the wheels turned, the odometry did
                         not), and of them those that ended with the outlines touching
  false alarms           diagnostics at ERROR or STALE during the match (scripts/false_alarms.py:
                         nothing is injected here, so nothing explains one)
  loc RMSE / max         /mcl/pose against /sim/ground_truth from the start signal to the end
  idle / idle max        [s] idle while the match runs (scripts/idle_time.py: no driver goal
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
import bisect
import collections
import math
import os
import re
import socket
import subprocess
import sys
import time

import yaml
from robot_core import start_zone
from robot_core.config_tree import merged, simulated_robot  # the config as roslaunch loads it; the simulated robot

SCRIPTS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(SCRIPTS)
sys.path.insert(0, SCRIPTS)
import run_folders  # noqa: E402
import run_match  # noqa: E402  (free_port: the project's own port range)
import false_alarms  # noqa: E402
from chaos_invariants import statuses  # noqa: E402
from idle_time import IDLE_LIMIT, too_long  # noqa: E402
from match_report import Match, errors_against_truth  # noqa: E402

OPPONENTS = ('random_walk', 'route', 'blocker', 'player')
TOUCHING = 0.01  # [m] gap between the outlines that counts as a contact (the simulator stops them at ~0)
SEPARATED = 0.03  # [m] gap that ends a contact: a robot pushing along the opponent is one contact, not many
EFFECTORS_GRACE = 1.0  # [s] after the match end by which the effectors must be off
ROUTE_CLEARANCE = 0.30  # [m] between the game elements' centres and the route
BLOCKER_PAUSE = 1.0e6  # [s] at the goal: longer than any match, so the blocker never leaves

MatchRow = collections.namedtuple('MatchRow', 'seed opponent folder ours theirs contacts triggers stuck stalls '
                                              'stalls_in_contact false_alarms loc_rmse loc_max idle idle_max '
                                              'effectors_off wall errors violations')


def result(row):
    """won, lost or draw (ours against the opponent's score), None when the match has no score."""
    if row.ours is None or row.theirs is None:
        return None
    return 'won' if row.ours > row.theirs else 'lost' if row.ours < row.theirs else 'draw'


def results_line(rows, label=''):
    """`wins W losses L draws D` of the scored rows (with `label` and the win rate in front when given)."""
    outcomes = [result(r) for r in rows]
    won, lost, draw = outcomes.count('won'), outcomes.count('lost'), outcomes.count('draw')
    line = 'wins %d losses %d draws %d' % (won, lost, draw)
    if label:
        scored = won + lost + draw
        line = '%s: %s win_rate %s' % (label, line, '%.0f%%' % (100.0 * won / scored) if scored else '-')
    return line


def log(msg):
    print('matches: ' + msg, flush=True)


# ---- the robot's configuration (as the launch loads it) ----------------------------------------

def robot_config(robot):
    """config/ROBOT.yaml with config/ROBOT.sim.yaml over it (the simulated robot's parameters)."""
    config = {}
    for name in (robot + '.yaml', robot + '.sim.yaml'):
        path = os.path.join(ROOT, 'config', name)
        if os.path.exists(path):
            with open(path) as f:
                config = merged(config, yaml.safe_load(f) or {})
    return config


def zone_centre(zone):
    x0, y0, x1, y1 = zone['rect']
    return [(x0 + x1) / 2.0, (y0 + y1) / 2.0]


def our_colour(config):
    """The start zone our robot starts in (the referee's rule for our colour), else `red`."""
    start = config['sim']['world']['robot'].get('start', [0.25, 1.8, 0.0])
    return start_zone.zone_of(start, config['table'].get('start_zones', [])) or 'red'


def our_goal(config):
    """Centre of the first score zone that scores for us: team `placer` or our colour."""
    colour = our_colour(config)
    for zone in config['table'].get('score_zones', []):
        if zone.get('team') in ('placer', colour):
            return zone_centre(zone)
    raise SystemExit('matches: no table/score_zones zone with team placer or %s in the config' % colour)


def route_around_elements(config):
    """A loop around the game elements (their bounding box grown by ROUTE_CLEARANCE), kept off
    the borders and out of the start zones (where a waiting robot would stop the route),
    starting at the corner nearest the opponent's start and going round."""
    table, opponent = config['table'], config['sim']['world']['opponent']
    length, width = table['length'], table['width']
    radius = opponent.get('radius', 0.16)
    points = [e['at'] for e in table.get('elements', [])] or [[length / 4, width / 4], [3 * length / 4, 3 * width / 4]]
    x0 = min(p[0] for p in points) - ROUTE_CLEARANCE
    x1 = max(p[0] for p in points) + ROUTE_CLEARANCE
    y0 = min(p[1] for p in points) - ROUTE_CLEARANCE
    y1 = max(p[1] for p in points) + ROUTE_CLEARANCE
    keep_off = radius + 0.05
    for zone in table.get('start_zones', []):
        zx0, zy0, zx1, zy1 = zone['rect']
        if zx1 + keep_off < x0 or zx0 - keep_off > x1:
            continue  # beside the loop
        if (zy0 + zy1) / 2 > (y0 + y1) / 2:
            y1 = min(y1, zy0 - keep_off)
        else:
            y0 = max(y0, zy1 + keep_off)
    x0, x1 = max(x0, keep_off), min(x1, length - keep_off)
    y0, y1 = max(y0, keep_off), min(y1, width - keep_off)
    loop = [[x1, y1], [x1, y0], [x0, y0], [x0, y1]]
    start = opponent.get('start', [length, width])
    first = min(range(4), key=lambda i: math.hypot(loop[i][0] - start[0], loop[i][1] - start[1]))
    return [[round(v, 3) for v in p] for p in loop[first:] + loop[:first]]


def opponent_params(kind, config):
    """The sim/world/opponent parameters of one opponent kind."""
    if kind == 'random_walk':
        return {'mode': 'random_walk'}
    if kind == 'route':
        return {'mode': 'script', 'waypoints': route_around_elements(config)}
    if kind == 'blocker':
        return {'mode': 'script', 'waypoints': [[round(v, 3) for v in our_goal(config)]], 'pause': BLOCKER_PAUSE}
    if kind == 'player':
        return {'mode': 'player'}
    raise ValueError(kind)


def match_overlay(opponent, params=None):
    """A match's parameters over the config: `params` (a tuning trial's, or none) and its opponent."""
    return merged(params or {}, {'sim': {'world': {'opponent': opponent}}})


def user_overlay(paths, who):
    """The parameters of a user's overlay files (OVERLAY=a.yaml or OVERLAY="a.yaml b.yaml", here
    comma-separated, each over the one before), {} for none; a clear exit when one is unreadable."""
    out = {}
    for path in [p for p in (paths or '').split(',') if p]:
        try:
            with open(path) as f:
                data = yaml.safe_load(f) or {}
        except (OSError, yaml.YAMLError) as e:
            sys.exit('%s: --overlay %s: %s' % (who, path, e))
        if not isinstance(data, dict):
            sys.exit('%s: --overlay %s: must be a YAML dictionary of parameters (as config/<robot>.yaml)' % (who, path))
        out = merged(out, data)
    return out


def side_overlay(robot, user, side, who):
    """The overlay that plays `side` (a start zone) over the config and the user's overlay
    (robot_core.start_zone.side_overlay); a clear exit when the config has no such zone."""
    try:
        return start_zone.side_overlay(merged(robot_config(robot), user), side)
    except ValueError as e:
        sys.exit('%s: %s' % (who, e))


def side_overlay_file(robot, overlay_paths, side, folder, who):
    """side_overlay written to FOLDER/side.yaml, for a launch's overlay argument: its path."""
    path = os.path.join(folder, 'side.yaml')
    with open(path, 'w') as f:
        f.write('# scripts/run_matches.py: the parameters that play from the %s start zone\n' % side)
        yaml.safe_dump(side_overlay(robot, user_overlay(overlay_paths, who), side, who), f, default_flow_style=None)
    return path


def with_duration(overlay, seconds):
    """`overlay` with the match shortened to `seconds` (brain/match/duration, which the simulated
    referee follows too): a quick check of a runner's machinery, not of the robot. None: as is."""
    return merged(overlay, {'brain': {'match': {'duration': seconds}}}) if seconds else overlay


def write_overlay(folder, overlay):
    """FOLDER/overlay.yaml, the launch argument overlay: loaded after the robot's config."""
    path = os.path.join(folder, 'overlay.yaml')
    with open(path, 'w') as f:
        f.write('# scripts/run_matches.py: this match\'s opponent and parameters (launch argument overlay)\n')
        yaml.safe_dump(overlay, f, default_flow_style=None)
    return path


# ---- one match ---------------------------------------------------------------------------------

def run_one(robot, seed, factor, folder, overlay, strategy, index, n, extra=()):
    """scripts/run_match.py on a ROS master of its own (each run starts and stops its master; two
    in a row on one port, or on a test's master, would share parameters and latched topics).
    Its `run:` lines are shown, its whole output kept in the folder. Returns its exit code."""
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % run_match.free_port(socket.SOCK_STREAM))
    cmd = [sys.executable, os.path.join(SCRIPTS, 'run_match.py'), robot, '--out', folder, '--seed', str(seed),
           '--real-time-factor', '%g' % factor, '--overlay', overlay]
    if strategy:
        cmd += ['--strategy', strategy]
    cmd += list(extra)
    with open(os.path.join(folder, 'run_match.out'), 'w') as out:
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                universal_newlines=True, errors='replace', preexec_fn=run_match.die_with_parent)
        try:
            for line in proc.stdout:
                out.write(line)
                if line.startswith('run: '):  # the report's summary stays in the folder's .txt
                    print('  [%d/%d] %s' % (index, n, line.rstrip()), flush=True)
        except KeyboardInterrupt:
            # run_match.py got the Ctrl-C too and stops its robot, printing as it goes: keep its
            # pipe open until it is done, or it dies on the closed pipe and leaves the robot running.
            out.write(proc.stdout.read())
            proc.wait()
            raise
        return proc.wait()


def node_deaths(launch_log):
    """{process: first line saying it died} of the launch log (roslaunch says it twice for a
    required node: "[brain-5] process has died [...]" and "REQUIRED process [brain-5] has died!")."""
    died = collections.OrderedDict()
    if os.path.exists(launch_log):
        with open(launch_log, errors='replace') as f:
            for line in f:
                found = re.search(r'\[([^\]]+)\] process has died', line) or \
                    re.search(r'REQUIRED process \[([^\]]+)\] has died', line)
                if found:
                    died.setdefault(found.group(1), line.strip())
    return died


def match_span(launch_log):
    """((wall, simulated) at the brain's match start, the same at its match end) from the launch
    log's "brain: match started" and "brain: MATCH END" lines (rospy stamps both clocks); None
    for a line that is not there."""
    begin = finish = None
    if os.path.exists(launch_log):
        with open(launch_log, errors='replace') as f:
            for line in f:
                m = re.search(r'\[(\d+\.\d+), (\d+\.\d+)\]: brain: (match started|MATCH END)', line)
                if m:
                    stamp = (float(m.group(1)), float(m.group(2)))
                    if m.group(3) == 'match started':
                        begin = stamp
                    else:
                        finish = stamp
    return begin, finish


def effectors_off_delay(m, end):
    """[s] from the match end to the latched /effectors/deactivated last going true, judged
    EFFECTORS_GRACE after the end; None when they were not off by then."""
    off, since = False, None
    for _, msg, t in m.read('/effectors/deactivated'):
        t = t.to_sec()
        if t > end + EFFECTORS_GRACE:
            break
        if msg.data and not off:
            since = t
        off = msg.data
    return since - end if off else None


def contacts(truth, opponent, radii):
    """Times the two outlines come within TOUCHING of each other (one contact lasts until they
    are SEPARATED again). errors_against_truth gives the distance of our centre to the opponent's,
    interpolated at our stamps."""
    count, touching = 0, False
    for _, distance, _ in errors_against_truth(truth, opponent):
        gap = distance - radii
        if not touching and gap <= TOUCHING:
            count, touching = count + 1, True
        elif touching and gap > SEPARATED:
            touching = False
    return count


def stalled_goals(m, radii):
    """(driver goals that ended on a stall, of them those that ended with our outline and the
    opponent's within TOUCHING): the truth at the goal's end."""
    stalls = [g['t_end'] for g in m.driver_goals() if g['t_end'] is not None and 'stalled' in g['message']]
    distances = errors_against_truth(m.poses('/sim/ground_truth'), m.poses('/sim/opponent'))
    times = [t for t, _, _ in distances]
    touching = 0
    for t in stalls:
        i = bisect.bisect_left(times, t)
        near = [d for _, d, _ in distances[max(0, i - 1):i + 1]]
        if near and min(near) - radii <= TOUCHING:
            touching += 1
    return len(stalls), touching


def localization_errors(m, start, end):
    """Position errors [m] of /mcl/pose against the truth between the start signal and the end."""
    return [e for t, e, _ in errors_against_truth(m.poses('/mcl/pose'), m.poses('/sim/ground_truth'))
            if start <= t <= end]


def off_table(truth, length, width):
    """The first true pose (t, x, y) outside the table, or None."""
    for t, x, y, _ in truth:
        if not (0.0 <= x <= length and 0.0 <= y <= width):
            return t, x, y
    return None


def figures(m, config, start, end, idle):
    """The row's figures of one recorded match (None where the bag cannot tell); `idle`: its idle
    stretches (Match.idle)."""
    out = dict(ours=None, theirs=None, loc_rmse=None, loc_max=None, idle=None, idle_max=None, effectors_off=None, errors=[])
    _, _, score = m.score_series()
    if score:
        out.update(ours=score[-1][1], theirs=score[-1][2])
    radii = simulated_robot(config)['radius'] + config['sim']['world']['opponent']['radius']
    out['contacts'] = contacts(m.poses('/sim/ground_truth'), m.poses('/sim/opponent'), radii)
    out['stalls'], out['stalls_in_contact'] = stalled_goals(m, radii)
    fired = m.triggers()
    out.update(triggers=len(fired), stuck=sum(1 for _, name in fired if name == 'stuck'))
    if start is not None and end is not None:
        errors = localization_errors(m, start, end)
        if errors:
            out.update(errors=errors, loc_rmse=math.sqrt(sum(e * e for e in errors) / len(errors)),
                       loc_max=max(errors))
        out['effectors_off'] = effectors_off_delay(m, end)
        out.update(idle=sum(b - a for a, b in idle), idle_max=max([b - a for a, b in idle] or [0.0]))
    return out


def broken_invariants(m, config, start, end, effectors_off, idle, alarms=()):
    """What the recorded match did that no match may do; `alarms`: its false alarms."""
    broken = [text for _, text in alarms]
    if start is None:
        broken.append('the match never started')
    elif end is None:
        broken.append('the match never ended')
    elif effectors_off is None:
        broken.append('the effectors were still on %.0f s after the match end' % EFFECTORS_GRACE)
    if start is not None and end is not None:
        for t0, seconds in too_long(idle, end):
            broken.append('idle for %.1f s from %.1f s into the match with more than %.0f s left'
                          % (seconds, t0 - start, IDLE_LIMIT))
    left = off_table(m.poses('/sim/ground_truth'), config['table']['length'], config['table']['width'])
    if left:
        broken.append('our robot left the table at (%.3f, %.3f), %.1f s into the bag'
                      % (left[1], left[2], left[0] - m.start))
    return broken


def analyse(seed, kind, folder, robot, config, rc, wall):
    """The match's row from its bag and launch log, with the invariants it broke."""
    bag = os.path.join(folder, robot + '_match.bag')
    row = dict(seed=seed, opponent=kind, folder=folder, wall=wall, ours=None, theirs=None, contacts=None,
               triggers=None, stuck=None, stalls=None, stalls_in_contact=None, false_alarms=None, loc_rmse=None,
               loc_max=None, idle=None, idle_max=None, effectors_off=None, errors=[])
    violations = ['node %s died: %s' % died for died in node_deaths(os.path.join(folder, robot + '_launch.log')).items()]
    if os.path.exists(bag):
        m = Match(bag)
        start, _ = m.start_signal()
        end = m.match_end()
        idle = m.idle(start, end)  # read from the bag once, for the row and the invariant
        row.update(figures(m, config, start, end, idle))
        alarms = []
        if start is not None:
            alarms = false_alarms.false_alarms(statuses(m), start, end if end is not None else m.end, [], start, config)
        row['false_alarms'] = len(alarms)
        violations += broken_invariants(m, config, start, end, row['effectors_off'], idle, alarms)
        m.bag.close()
    else:
        violations.append('the match never started (no bag: see %s)' % os.path.join(folder, 'run_match.out'))
    if rc != 0 and not violations:
        violations.append('run_match.py exited with code %d (see %s)' % (rc, os.path.join(folder, 'run_match.out')))
    return MatchRow(violations=violations, **row)


# ---- output ------------------------------------------------------------------------------------

COLUMNS = (('seed', '%4s', '%4d'), ('opponent', '%-11s', '%-11s'), ('ours', '%4s', '%4d'), ('opp', '%4s', '%4d'),
           ('result', '%6s', '%6s'),
           ('contacts', '%8s', '%8d'), ('triggers', '%8s', '%8d'), ('stuck', '%5s', '%5d'),
           ('stalls', '%6s', '%6d'), ('in_contact', '%10s', '%10d'), ('false_alarms', '%12s', '%12d'),
           ('loc_rmse_m', '%10s', '%10.4f'), ('loc_max_m', '%9s', '%9.4f'), ('idle_s', '%6s', '%6.1f'),
           ('idle_max_s', '%10s', '%10.1f'), ('eff_off_s', '%9s', '%9.3f'),
           ('wall_s', '%6s', '%6.0f'))


def table_lines(rows):
    lines = [' '.join(head % name for name, head, _ in COLUMNS)]
    for r in rows:
        values = (r.seed, r.opponent, r.ours, r.theirs, result(r), r.contacts, r.triggers, r.stuck, r.stalls,
                  r.stalls_in_contact, r.false_alarms, r.loc_rmse, r.loc_max,
                  r.idle, r.idle_max, r.effectors_off, r.wall)
        lines.append(' '.join((cell % v) if v is not None else head % '-'
                              for (_, head, cell), v in zip(COLUMNS, values)))
    return lines


def summary_lines(rows, wall, factor, notes=()):
    """The table `make matches` prints and writes: a row per match, the violations, NOTES, the
    results per opponent and in all, and the closing line (tune.py writes its verdict's arms so)."""
    violations = [(r.seed, v) for r in rows for v in r.violations]
    lines = table_lines(rows) + ['violation: seed %d: %s' % sv for sv in violations] + list(notes)
    lines += [results_line([r for r in rows if r.opponent == kind], 'opponent ' + kind)
              for kind in OPPONENTS if any(r.opponent == kind for r in rows)]
    return lines + [results_line(rows), closing_line(rows, len(violations), wall, factor)]


def closing_line(rows, violations, wall, factor):
    scores = [r.ours for r in rows if r.ours is not None]
    mean = sum(scores) / float(len(scores)) if scores else float('nan')
    lowest = min(scores) if scores else float('nan')
    return 'matches %d score_mean %.2f score_min %s violations %d wall_s %.0f factor %g' % (
        len(rows), mean, lowest, violations, wall, factor)


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

    import match_cluster
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
