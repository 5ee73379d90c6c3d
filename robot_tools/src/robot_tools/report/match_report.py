"""Match report: one PNG (and the same summary as text) from any recorded bag, for the team to
read after a match.

    scripts/match_report.py [BAG] [-o OUT.png]      (make report [BAG=...])

BAG defaults to the newest *.bag in ~/.ros (where record:=true puts them). The figure shows
  1. the table (/table_markers or /sim/markers: score and start zones) with the game elements at
     the start and at the end (/sim/elements), the opponent's path (/sim/opponent), our true
     (/sim/ground_truth) and estimated path (/mcl/pose, else /odom), and every driver goto goal
     (/hal/driver/goto/goal + /result) as an arrow coloured by how it ended;
  2. timelines in match time (0 = the start signal: the brain's first /brain/match_status
     `running`, else the simulator's first /sim/match `started`): the score of both teams
     (/sim/match score_ours/score_opponent, /sim/score_events; the plain score of older bags),
     the localization error (estimate vs truth), the driver's goals by action and result, the
     brain's states; trigger firings are red lines across all of them;
  3. a text panel with the summary: score, start signal, driver goals and the aborted ones with
     their reasons, strategy outcomes, deduplicated ERROR/WARN lines of the brain and the driver
     (/rosout), diagnostics that went ERROR/STALE after the start, trigger firings, absent topics.
A topic that is not in the bag is listed as absent; nothing here needs a running ROS master or
the project's message packages (rosbag rebuilds message classes from the bag itself).
"""
import argparse
import glob
import math
import os
import re
import sys

import rosbag

from robot_tools.matches.idle_time import IDLE_LIMIT, too_long
from robot_tools.report.match_bag import DRIVER_ACTIONS, ERROR_LEVELS, Match
from robot_tools.report.metrics import counted, errors_against_truth, goal_target, is_brain_or_driver
from robot_tools.report.plots import draw

WARN_LEVEL = 4
GRACE = 5.0  # [s] of the bag during which bad diagnostics are start-up, when there is no start signal


def report(bag_path, out_png):
    m = Match(bag_path)
    absent = []
    est_topic = '/mcl/pose' if m.has('/mcl/pose') else ('/odom' if m.has('/odom') else None)
    for topic in ('/mcl/pose', '/odom', '/sim/ground_truth', '/rosout', '/diagnostics'):
        if not m.has(topic):
            absent.append(topic)
    estimate = m.poses(est_topic) if est_topic else []
    truth = m.poses('/sim/ground_truth')
    opponent = m.poses('/sim/opponent')
    err = errors_against_truth(estimate, truth)
    state_topic, states = m.brain_states()
    if not state_topic:
        absent.append('/brain/... (states)')
    score_topic, attributed, score_series = m.score_series()
    events = m.score_events()
    if score_topic is None and not events:
        absent.append('/sim/...score...')
    marker_topic, markers = m.markers()
    length, width = m.table(markers)
    zones = m.zones(markers)
    elements_start, elements_end = m.elements()
    goals = m.driver_goals()
    logs = m.log_lines()
    fired = m.triggers()
    t_signal, signal_source = m.start_signal()
    t0 = t_signal if t_signal is not None else m.start
    grace_end = t_signal if t_signal is not None else m.start + GRACE
    bad_diag = m.bad_diagnostics(grace_end)
    error_lines = [(t - t0, '%s: %s' % (node, text)) for t, level, node, text in logs if level in ERROR_LEVELS]
    warn_lines = [(t - t0, '%s: %s' % (node, text)) for t, level, node, text in logs
                  if level == WARN_LEVEL and is_brain_or_driver(node, text)]
    strategy_lines = [(t - t0, text) for t, _, node, text in logs
                      if re.search(r'strategy \S+ ended: ', text) and is_brain_or_driver(node, text)]

    # ---- the summary (the .txt and the text panel)
    summary = ['bag: %s' % os.path.basename(bag_path),
               'duration: %.1f s, %d topics, %d messages' % (m.end - m.start, len(m.topics),
                                                           sum(c for _, c in m.topics.values()))]
    if t_signal is not None:
        summary.append('start signal: %s, %.1f s after the bag start' % (signal_source, t_signal - m.start))
    else:
        summary.append('start signal: absent (times below count from the bag start)')
    if attributed:
        summary.append('score: ours %d, opponent %d' % (score_series[-1][1], score_series[-1][2]))
    elif events:
        ours = sum(e[2] for e in events if e[1] == 'ours')
        theirs = sum(e[2] for e in events if e[1] == 'opponent')
        summary.append('score: ours %d, opponent %d' % (ours, theirs))
    elif score_series:
        summary.append('score: %g (no attribution in this bag)' % score_series[-1][1])
    else:
        summary.append('score: absent')
    colours = m.colours()
    if colours:
        summary.append('colours: ours %s, opponent %s' % colours)
    summary.append('score source: %s%s' % (score_topic or 'absent',
                                           ', %d score event(s) on /sim/score_events' % len(events) if events else ''))
    for e in events[:12]:
        summary.append('  %6.1f s %-8s %+d %s in %s' % (e[0], e[1], e[2], e[3], e[4]))
    if len(events) > 12:
        summary.append('  ... %d more score events' % (len(events) - 12))
    match = m.match_status()
    if match is not None:
        summary.append('match: %s, strategy %s, %.1f s elapsed' % (match.state, match.strategy, match.elapsed))
    if strategy_lines:
        summary.append('strategy outcomes: %s' % '; '.join(
            '%s (at %.1f s)' % (re.sub(r'^brain: ', '', text), t) for t, text in strategy_lines))
    summary.append('estimate: %s (%d poses)' % (est_topic or 'absent', len(estimate)))
    summary.append('truth: %s' % ('/sim/ground_truth (%d poses)' % len(truth) if truth else 'absent'))
    if err:
        pos = [e[1] for e in err]
        rms = math.sqrt(sum(p * p for p in pos) / len(pos))
        summary.append('localization error: RMS %.3f m, max %.3f m, heading max %.1f deg'
                       % (rms, max(pos), math.degrees(max(e[2] for e in err))))
    else:
        summary.append('localization error: absent (needs an estimate and /sim/ground_truth)')
    summary.append('opponent: %s' % ('/sim/opponent (%d poses)' % len(opponent) if opponent else 'absent'))
    summary.append('brain states: %s' % ('%d changes on %s' % (len(states), state_topic) if states else 'absent'))
    if goals:
        per_action = []
        for action in DRIVER_ACTIONS:
            mine = [g for g in goals if g['action'] == action]
            if mine:
                count = {}
                for g in mine:
                    count[g['status']] = count.get(g['status'], 0) + 1
                per_action.append('%s %d (%s)' % (action, len(mine), ', '.join(
                    '%d %s' % (n, s.lower()) for s, n in sorted(count.items(), key=lambda i: -i[1]))))
        summary.append('driver goals: %s' % '; '.join(per_action))
    else:
        summary.append('driver goals: absent')
    t_end = m.match_end()
    idle = m.idle(t_signal, t_end)
    if t_signal is not None and t_end is not None:
        longest = max([b - a for a, b in idle] or [0.0])
        summary.append('idle while the match runs: %.1f s in %d stretch(es), the longest %.1f s%s'
                       % (sum(b - a for a, b in idle), len(idle), longest,
                          ''.join('; %.1f s idle from %.1f s with more than %.0f s left' % (s, a - t0, IDLE_LIMIT)
                                  for a, s in too_long(idle, t_end))))
    aborted = [g for g in goals if g['status'] in ('ABORTED', 'REJECTED', 'LOST')]
    summary.append('aborted goals: %d' % len(aborted))
    for g in aborted:
        why = g['message'] or g['text'] or 'no reason given'
        summary.append('  %6.1f s %s #%d %s: %s%s: %s' % (g['t_sent'] - t0, g['action'], g['n'], goal_target(g),
                                                        g['status'], '/' + g['code'] if g['code'] else '', why))
    summary.append('errors: %d ERROR/FATAL log line(s), %d diagnostic(s) went ERROR/STALE%s'
                   % (len(error_lines), len(bad_diag), (': ' + ', '.join(sorted(bad_diag))) if bad_diag else ''))
    for line in counted(error_lines)[:10]:
        summary.append('  ' + line)
    for name in sorted(bad_diag, key=lambda n: bad_diag[n][0]):
        when, level, message = bad_diag[name]
        summary.append('  diagnostic %s: %s at %.1f s%s' % (name, {2: 'ERROR', 3: 'STALE'}.get(level, level),
                                                          when - t0, ': ' + message if message else ''))
    summary.append('diagnostics grace: statuses before %s are start-up, not faults'
                   % ('the start signal' if t_signal is not None else 'the first %.0f s of the bag' % GRACE))
    warn_counted = counted(warn_lines)
    summary.append('warnings: %d WARN line(s) of the brain and the driver, %d distinct'
                   % (len(warn_lines), len(warn_counted)))
    for line in warn_counted[:12]:
        summary.append('  ' + line)
    if len(warn_counted) > 12:
        summary.append('  ... %d more distinct warnings' % (len(warn_counted) - 12))
    summary.append('trigger firings: %d%s' % (len(fired), (' (' + ', '.join(sorted({f[1] for f in fired})) + ')')
                                              if fired else ''))
    for t, name in fired[:10]:
        summary.append('  %6.1f s %s' % (t - t0, name))
    summary.append('table: %.2f x %.2f m (%s), %d start zone(s), %d score zone(s), %d element(s)'
                   % (length, width, marker_topic or 'default, no table markers',
                      len(zones.get('start_zones', [])), len(zones.get('score_zones', [])), len(elements_start)))
    for topic, what in (('/sim/elements', 'elements'), ('/sim/opponent', 'opponent'),
                        ('/hal/driver/goto/goal', 'driver goals'), ('/sim/score_events', 'score events')):
        if not m.has(topic):
            absent.append(topic)
    if marker_topic is None:
        absent.append('/table_markers, /sim/markers')
    summary.append('absent topics: %s' % (', '.join(absent) if absent else 'none'))

    draw(m, bag_path, out_png, locals())
    with open(os.path.splitext(out_png)[0] + '.txt', 'w') as f:
        f.write('\n'.join(summary) + '\n')
    return summary


def newest_bag():
    bags = glob.glob(os.path.expanduser('~/.ros/*.bag'))
    return max(bags, key=os.path.getmtime) if bags else None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('bag', nargs='?', help='recorded bag (default: newest ~/.ros/*.bag)')
    parser.add_argument('-o', '--output', help='PNG to write (default: the bag with .png)')
    args = parser.parse_args()
    bag = args.bag or newest_bag()
    if not bag:
        sys.stderr.write('match_report: no bag given and none in ~/.ros (record one with record:=true)\n')
        return 2
    if not os.path.isfile(bag):
        sys.stderr.write('match_report: %s does not exist\n' % bag)
        return 2
    out = args.output or os.path.splitext(bag)[0] + '.png'
    try:
        summary = report(bag, out)
    except rosbag.ROSBagException as e:
        sys.stderr.write('match_report: cannot read %s: %s (an unfinished bag: rosbag reindex it)\n' % (bag, e))
        return 2
    print('\n'.join(summary))
    print('match report: %s' % out)
    return 0


if __name__ == '__main__':
    sys.exit(main())
