"""A played match's row of figures and its invariants, from its bag (robot_tools.report's Match)
and its launch log, and the tables and lines a series of rows is summed up in."""
import bisect
import collections
import math
import os
import re

from robot_core.config_tree import simulated_robot

from robot_tools.matches import false_alarms
from robot_tools.matches.match_config import OPPONENTS
from robot_tools.chaos.invariants import statuses
from robot_tools.matches.idle_time import IDLE_LIMIT, too_long
from robot_tools.report.match_bag import Match
from robot_tools.report.metrics import errors_against_truth

TOUCHING = 0.01  # [m] gap between the outlines that counts as a contact (the simulator stops them at ~0)
SEPARATED = 0.03  # [m] gap that ends a contact: a robot pushing along the opponent is one contact, not many
EFFECTORS_GRACE = 1.0  # [s] after the match end by which the effectors must be off

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
