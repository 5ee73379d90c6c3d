#!/usr/bin/env python3
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
import textwrap

import matplotlib
matplotlib.use('Agg')  # headless: no display needed
import matplotlib.pyplot as plt
import rosbag
from robot_core.geometry import wrap_angle, yaw_of

from robot_tools.matches.idle_time import IDLE_LIMIT, idle_stretches, too_long

DEFAULT_TABLE = (3.0, 2.1)
ERROR_LEVELS = (8, 16)  # rosgraph_msgs/Log ERROR, FATAL
WARN_LEVEL = 4
GRACE = 5.0  # [s] of the bag during which bad diagnostics are start-up, when there is no start signal
DRIVER_ACTIONS = ('goto', 'go_straight', 'rotate_by', 'follow_path')
# actionlib_msgs/GoalStatus
STATUS_NAMES = {0: 'PENDING', 1: 'ACTIVE', 2: 'PREEMPTED', 3: 'SUCCEEDED', 4: 'ABORTED', 5: 'REJECTED',
                6: 'PREEMPTING', 7: 'RECALLING', 8: 'RECALLED', 9: 'LOST'}
STATUS_COLOURS = {'SUCCEEDED': '#2e7d32', 'ABORTED': '#d32f2f', 'PREEMPTED': '#ef6c00', 'REJECTED': '#6a1b9a',
                  'RECALLED': '#8d6e63', 'LOST': '#000000', 'no result': '#9e9e9e'}
X_LABEL = 'match time [s] (0 = start signal)'


def pose_of(msg):
    """(x, y, yaw) of a PoseWithCovarianceStamped, Odometry or PoseStamped; None otherwise."""
    p = getattr(msg, 'pose', None)
    if p is None:
        return None
    p = getattr(p, 'pose', p)  # PoseWithCovariance -> Pose
    if not hasattr(p, 'position'):
        return None
    return p.position.x, p.position.y, yaw_of(p.orientation)


OTHER_CLOCK = 1.0e6  # [s] a stamp this far from the bag's time is on another clock


def stamp_of(msg, t):
    """The message's header stamp, else its bag time `t`. A stamp on another clock than the bag's
    (a wall-clock prober such as process_watch in a simulated match: epoch seconds against
    simulated ones) is not match time: the bag time is used for it too."""
    h = getattr(msg, 'header', None)
    if h is not None and getattr(h, 'stamp', None) is not None and h.stamp.to_sec() > 0 and \
            abs(h.stamp.to_sec() - t.to_sec()) < OTHER_CLOCK:
        return h.stamp.to_sec()
    return t.to_sec()


def first_line(text):
    return text.strip().splitlines()[0] if text and text.strip() else ''


def number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def element_colour(kind):
    """The simulator's marker colour of an element kind (robot_sim ros_world_io.cpp)."""
    for word, colour in (('red', '#e53935'), ('blue', '#1e4ee6'), ('green', '#1db233'), ('white', '#f2f2f2'),
                         ('column', '#f2d98c')):
        if word in kind:
            return colour
    return '#cccccc'


def constant_names(cls, prefix_skip=()):
    """{value: NAME} of a message class's integer constants (the .action's result codes)."""
    out = {}
    for name in dir(cls):
        if name.isupper() and not name.startswith('_') and name not in prefix_skip:
            v = getattr(cls, name)
            if isinstance(v, int) and not isinstance(v, bool):
                out.setdefault(v, name)
    return out


class Match(object):
    """Everything the report needs, read from the bag topic by topic."""

    def __init__(self, path):
        self.path = path
        self.bag = rosbag.Bag(path)
        info = self.bag.get_type_and_topic_info().topics
        self.topics = {t: (i.msg_type, i.message_count) for t, i in info.items()}
        self.start = self.bag.get_start_time() if self.topics else 0.0
        self.end = self.bag.get_end_time() if self.topics else 0.0
        self.asked = set()  # every topic a reader looked for: what a recorder must keep

    def has(self, topic):
        self.asked.add(topic)
        return topic in self.topics

    def find(self, prefix, word=''):
        found = sorted(t for t in self.topics if t.startswith(prefix) and word in t)
        if not found:
            self.asked.add('%s*%s' % (prefix, word))  # a pattern that matched nothing
        return found

    def read(self, topic):
        if not self.has(topic):
            return iter(())
        return self.bag.read_messages(topics=[topic])

    def poses(self, topic):
        out = []
        for _, msg, t in self.read(topic):
            p = pose_of(msg)
            if p is not None:
                out.append((stamp_of(msg, t),) + p)
        out.sort()
        return out

    def markers(self):
        """(topic, {ns: [marker]}) of the first table drawing: /table_markers, else /sim/markers."""
        for topic in ('/table_markers', '/sim/markers'):
            found = {}
            for _, msg, _ in self.read(topic):
                for mk in getattr(msg, 'markers', []):
                    if getattr(mk, 'action', 0) == 0:
                        found.setdefault(mk.ns, {})[mk.id] = mk
                if 'table' in found or 'score_zones' in found or 'start_zones' in found:
                    break
            if found:
                return topic, {ns: [ms[i] for i in sorted(ms)] for ns, ms in found.items()}
        return None, {}

    def table(self, markers=None):
        """(length, width) from the recorded table marker, else the default table."""
        if markers is None:
            markers = self.markers()[1]
        for mk in markers.get('table', []):
            if mk.scale.x > 0 and mk.scale.y > 0:
                return mk.scale.x, mk.scale.y
        return DEFAULT_TABLE

    def zones(self, markers):
        """{ns: [(x0, y0, sx, sy, rgba)]} of the start and score zones."""
        out = {}
        for ns in ('start_zones', 'score_zones'):
            for mk in markers.get(ns, []):
                sx, sy = mk.scale.x, mk.scale.y
                c = mk.color
                out.setdefault(ns, []).append((mk.pose.position.x - sx / 2, mk.pose.position.y - sy / 2, sx, sy,
                                               (c.r, c.g, c.b)))
        return out

    def elements(self):
        """(elements at the first, at the last /sim/elements): [(kind, x, y, radius, carried)]."""
        first = last = None
        for _, msg, _ in self.read('/sim/elements'):
            state = [(e.kind, e.pose.x, e.pose.y, e.radius, bool(getattr(e, 'carried', False)))
                     for e in getattr(msg, 'elements', [])]
            if first is None:
                first = state
            last = state
        return first or [], last or []

    def start_signal(self):
        """(time, source) of the start signal, or (None, None): the brain's first `running`
        /brain/match_status (stamp - elapsed), else the simulator's first `started` /sim/match."""
        for topic in self.find('/brain/', 'match_status'):
            for _, msg, t in self.read(topic):
                if getattr(msg, 'state', '') == 'running':
                    return stamp_of(msg, t) - float(getattr(msg, 'elapsed', 0.0)), topic + ' (running)'
        for _, msg, t in self.read('/sim/match'):
            if getattr(msg, 'started', False):
                return stamp_of(msg, t) - float(getattr(msg, 'elapsed', 0.0)), '/sim/match (started)'
        return None, None

    def brain_states(self):
        """(topic, [(t, state)]): the brain's active state over time. From the state machine's
        introspection (<brain>/smach/container_status: the chain of active states from the root
        container down, e.g. MATCH/TAKE_COLUMN/GOTO), else from a /brain/ topic with a `state`."""
        for topic in self.find('/brain/', 'container_status'):
            latest, states = {}, []
            for _, msg, t in self.bag.read_messages(topics=[topic]):
                latest[msg.path] = list(msg.active_states)
                root = min(latest, key=lambda p: (p.count('/'), len(p)))
                parts, path = [], root
                while latest.get(path):
                    parts.append(latest[path][0])
                    path = path + '/' + latest[path][0]
                label = '/'.join([root.strip('/')] + parts)
                if not states or states[-1][1] != label:
                    states.append((stamp_of(msg, t), label))
            if states:
                return topic, states
        for topic in self.find('/brain/'):
            states = []
            for _, msg, t in self.bag.read_messages(topics=[topic]):
                name = None
                if isinstance(getattr(msg, 'state', None), str):
                    name = msg.state
                elif isinstance(getattr(msg, 'current_state', None), str):
                    name = msg.current_state
                elif isinstance(getattr(msg, 'data', None), str) and 'state' in topic:
                    name = msg.data
                if name is None:
                    break
                if not states or states[-1][1] != name:
                    states.append((stamp_of(msg, t), name))
            if states:
                return topic, states
        return None, []

    def match_status(self):
        """The brain's last /brain/match_status (state, strategy, elapsed), or None."""
        last = None
        for topic in self.find('/brain/', 'match_status'):
            for _, msg, _ in self.bag.read_messages(topics=[topic]):
                last = msg
        return last

    def score_series(self):
        """(topic, attributed, [(t, ours, opponent or None)]): the score over time. /sim/match with
        score_ours/score_opponent (attributed), else its plain `score`, else /sim/score or another
        ...score... topic (a number in score, data, points or total)."""
        series, attributed = [], False
        for _, msg, t in self.read('/sim/match'):
            ours, theirs = getattr(msg, 'score_ours', None), getattr(msg, 'score_opponent', None)
            if number(ours) and number(theirs):
                attributed = True
                series.append((stamp_of(msg, t), ours, theirs))
            elif number(getattr(msg, 'score', None)):
                series.append((stamp_of(msg, t), msg.score, None))
        if series:
            return '/sim/match', attributed, series
        for topic in ['/sim/score'] + [t for t in self.find('/sim/', 'score') + self.find('/brain/', 'score')
                                       if t not in ('/sim/score', '/sim/score_events')]:
            for _, msg, t in self.read(topic):
                for field in ('score', 'data', 'points', 'total'):
                    v = getattr(msg, field, None)
                    if number(v):
                        series.append((stamp_of(msg, t), v, None))
                        break
            if series:
                return topic, False, series
        return None, False, []

    def colours(self):
        """(ours, opponent) start colours of the last /sim/match that has them, or None."""
        found = None
        for _, msg, _ in self.read('/sim/match'):
            ours, theirs = getattr(msg, 'colour_ours', ''), getattr(msg, 'colour_opponent', '')
            if ours or theirs:
                found = (ours or '?', theirs or '?')
        return found

    def score(self):
        """(topic, last score) of score_series (ours only when attributed)."""
        topic, _, series = self.score_series()
        return (topic, series[-1][1]) if series else (None, None)

    def score_events(self):
        """[(match time, team, points, element, zone)] of every /sim/score_events message (the
        latched list, or increments of it), without repeats."""
        seen, out = set(), []
        for _, msg, _ in self.read('/sim/score_events'):
            for e in getattr(msg, 'events', []):
                key = (round(float(getattr(e, 'time', 0.0)), 3), str(getattr(e, 'team', '')),
                       int(getattr(e, 'points', 0)), str(getattr(e, 'element', '')), str(getattr(e, 'zone', '')))
                if key not in seen:
                    seen.add(key)
                    out.append(key)
        return sorted(out)

    def driver_goals(self):
        """[dict(action, n, t_sent, t_end, goal, status, text, code, message)] of the driver's
        actionlib goals (/hal/.../<action>/goal and /result), in the order sent; n counts per action."""
        goals = []
        for action in DRIVER_ACTIONS:
            for goal_topic in self.find('/hal/', '/%s/goal' % action):
                if not goal_topic.endswith('/%s/goal' % action):
                    continue
                base = goal_topic[:-len('/goal')]
                by_id = {}
                for _, msg, t in self.read(goal_topic):
                    gid = msg.goal_id.id or '%s#%d' % (base, len(by_id))
                    t_sent = msg.goal_id.stamp.to_sec() if msg.goal_id.stamp.to_sec() > 0 else stamp_of(msg, t)
                    by_id[gid] = dict(action=action, topic=base, t_sent=t_sent, t_end=None, goal=msg.goal,
                                      status='no result', text='', code=None, message='')
                for _, msg, t in self.read(base + '/result'):
                    g = by_id.get(msg.status.goal_id.id)
                    if g is None:
                        continue
                    g['t_end'] = stamp_of(msg, t)
                    g['status'] = STATUS_NAMES.get(msg.status.status, str(msg.status.status))
                    g['text'] = msg.status.text
                    res = msg.result
                    code = getattr(res, 'code', None)
                    if number(code):
                        g['code'] = constant_names(type(res)).get(code, str(code))
                    g['message'] = str(getattr(res, 'message', '') or '')
                ordered = sorted(by_id.values(), key=lambda g: g['t_sent'])
                for i, g in enumerate(ordered):
                    g['n'] = i + 1
                goals.extend(ordered)
                break
        return sorted(goals, key=lambda g: g['t_sent'])

    def match_end(self):
        """Bag time of the match end: the brain's first `ended` or the referee's first `over`, the
        earlier. Bag (receive) times: /effectors/deactivated has no header to compare."""
        ends = []
        for _, msg, t in self.read('/brain/match_status'):
            if msg.state == 'ended':
                ends.append(t.to_sec())
                break
        for _, msg, t in self.read('/sim/match'):
            if msg.over:
                ends.append(t.to_sec())
                break
        return min(ends) if ends else None

    def hal_goal_spans(self):
        """[(t_sent, t_end or None)] of every HAL action goal (driver, hand, ...), bag times."""
        spans = []
        for goal_topic in self.find('/hal/', '/goal'):
            base = goal_topic[:-len('/goal')]
            if not goal_topic.endswith('/goal') or not self.has(base + '/result'):
                continue
            sent = {msg.goal_id.id: t.to_sec() for _, msg, t in self.read(goal_topic)}
            ended = {msg.status.goal_id.id: t.to_sec() for _, msg, t in self.read(base + '/result')}
            spans += [(t, ended.get(gid)) for gid, t in sent.items()]
        # A goal that never ended (its server killed mid-goal) has no end: it sorts last among
        # goals sent at the same time instead of being compared with a number.
        return sorted(spans, key=lambda span: (span[0], float('inf') if span[1] is None else span[1]))

    def idle(self, start, end):
        """The idle stretches [(t0, t1)] between start and end (idle_time.py): no HAL action goal
        active (driver, hand) and a zero speed on /hal/drive/cmd_vel. Bag times, like match_end()."""
        if start is None or end is None:
            return []
        goals = self.hal_goal_spans()
        commands = [(t.to_sec(), msg.linear.x, msg.angular.z) for _, msg, t in self.read('/hal/drive/cmd_vel')]
        return idle_stretches(goals, commands, start, end)

    def log_lines(self):
        """[(t, level, node, first line)] of /rosout."""
        out = []
        for _, msg, t in self.read('/rosout'):
            out.append((stamp_of(msg, t), getattr(msg, 'level', 0), getattr(msg, 'name', ''),
                        first_line(getattr(msg, 'msg', ''))))
        return out

    def errors(self):
        """(rosout ERROR/FATAL lines, diagnostics names that went ERROR or STALE) of the whole bag."""
        lines = ['%s: %s' % (node, text) for _, level, node, text in self.log_lines() if level in ERROR_LEVELS]
        return lines, sorted(self.bad_diagnostics(float('-inf')))

    def bad_diagnostics(self, after):
        """{name: (first t, level, message)} of the /diagnostics statuses that went ERROR (2) or
        STALE (3) at or after `after` (before it: the start-up grace period)."""
        bad = {}
        for _, msg, t in self.read('/diagnostics'):
            when = stamp_of(msg, t)
            if when < after:
                continue
            for s in msg.status:
                if s.level >= 2 and s.name not in bad:
                    bad[s.name] = (when, s.level, first_line(s.message))
        return bad

    def triggers(self):
        """[(t, trigger name)] of trigger firings: the supervisor's root container switching to a
        trigger's handler (edges labelled `fired` in container_structure), else /brain/...trigger...
        topics, else brain log lines saying a trigger fired."""
        names = set()
        for topic in self.find('/brain/', 'container_structure'):
            for _, msg, _ in self.bag.read_messages(topics=[topic]):
                for outcome, to in zip(getattr(msg, 'internal_outcomes', []), getattr(msg, 'outcomes_to', [])):
                    if outcome == 'fired':
                        names.add(to)
        fired = []
        if names:
            for topic in self.find('/brain/', 'container_status'):
                previous = {}
                for _, msg, t in self.bag.read_messages(topics=[topic]):
                    active = list(msg.active_states)
                    for name in active:
                        if name in names and name not in previous.get(msg.path, []):
                            fired.append((stamp_of(msg, t), name))
                    previous[msg.path] = active
            return sorted(fired)
        for topic in self.find('/brain/', 'trigger'):
            for _, msg, t in self.bag.read_messages(topics=[topic]):
                text = getattr(msg, 'name', None) or getattr(msg, 'data', None) or topic
                fired.append((stamp_of(msg, t), str(text)))
        if not fired and self.has('/rosout'):
            for _, msg, t in self.bag.read_messages(topics=['/rosout']):
                if 'brain' in msg.name and 'trigger' in msg.msg.lower() and 'fire' in msg.msg.lower():
                    fired.append((t.to_sec(), msg.msg.splitlines()[0]))
        return sorted(fired)


def errors_against_truth(estimate, truth):
    """[(t, position error [m], heading error [rad])], truth interpolated at each estimate."""
    out = []
    if len(truth) < 2:
        return out
    j = 0
    for t, x, y, a in estimate:
        while j + 1 < len(truth) and truth[j + 1][0] < t:
            j += 1
        if j + 1 >= len(truth) or t < truth[0][0]:
            continue
        (t0, x0, y0, a0), (t1, x1, y1, a1) = truth[j], truth[j + 1]
        f = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
        tx, ty = x0 + f * (x1 - x0), y0 + f * (y1 - y0)
        ta = a0 + f * wrap_angle(a1 - a0)
        out.append((t, math.hypot(x - tx, y - ty), abs(wrap_angle(a - ta))))
    return out


def is_brain_or_driver(node, text):
    return 'brain' in node or text.startswith('brain:') or text.startswith('driver:')


def counted(lines):
    """['3x text (first at 12.3 s)'] of [(t, text)], in order of first appearance; lines that
    differ only in their numbers count together (the first one is shown)."""
    groups = {}
    for t, text in lines:
        key = re.sub(r'-?\d+(\.\d+)?', '#', text)
        if key in groups:
            groups[key][1] += 1
            groups[key][3] = groups[key][3] or text != groups[key][2]
        else:
            groups[key] = [t, 1, text, False]
    return ['%dx %s (%sfirst at %.1f s)' % (n, text, 'and similar; ' if similar else '', t) if n > 1
            else '%s (at %.1f s)' % (text, t) for t, n, text, similar in sorted(groups.values(), key=lambda g: g[0])]


def goal_target(g):
    """A short text of what a driver goal asked for."""
    goal = g['goal']
    if g['action'] == 'goto':
        return 'to (%.2f, %.2f, %.0f deg)' % (goal.x, goal.y, math.degrees(goal.angle))
    if g['action'] == 'go_straight':
        return '%s %.2f m' % ('back' if goal.backwards else 'ahead', goal.distance)
    if g['action'] == 'rotate_by':
        return 'by %.0f deg' % math.degrees(goal.angle)
    if g['action'] == 'follow_path':
        cps = list(getattr(goal, 'checkpoints', []))
        last = cps[-1] if cps else None
        where = ''
        if last is not None:
            p = getattr(last, 'pose', last)
            if hasattr(p, 'x'):
                where = ' to (%.2f, %.2f)' % (p.x, p.y)
            elif hasattr(p, 'position'):
                where = ' to (%.2f, %.2f)' % (p.position.x, p.position.y)
        return '%d checkpoint(s)%s' % (len(cps), where)
    return ''


def wrap(lines, width):
    """The summary wrapped to `width` characters; continuation lines keep the indentation."""
    out = []
    for line in lines:
        indent = len(line) - len(line.lstrip(' '))
        out.extend(textwrap.wrap(line, width, subsequent_indent=' ' * (indent + 4), break_long_words=True,
                                 break_on_hyphens=False) or [''])
    return out


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


def draw(m, bag_path, out_png, v):
    """The PNG: a fixed layout (the table keeps its size and aspect whatever the bag's length)."""
    t0, length, width = v['t0'], v['length'], v['width']
    fig_w, fig_h, dpi = 20.0, 15.0, 80
    fig = plt.figure(figsize=(fig_w, fig_h))
    fig.suptitle('match report: %s' % os.path.basename(bag_path), fontsize=15, x=0.01, y=0.995, ha='left',
                 weight='bold')
    left_w = 0.60  # of the figure: the table and the timelines; the text panel right of it
    margin = 0.2
    # The table: equal aspect, as wide as the left column, its height from the table's dimensions.
    tab_w_in = left_w * fig_w - 1.0
    tab_h_in = min(6.0, tab_w_in * (width + 2 * margin) / (length + 2 * margin))
    tab_w_in = tab_h_in * (length + 2 * margin) / (width + 2 * margin)
    tab_bottom = 1.0 - 0.045 - tab_h_in / fig_h
    ax = fig.add_axes([0.04, tab_bottom, tab_w_in / fig_w, tab_h_in / fig_h])
    draw_table(ax, v)

    # Timelines below the table, sharing the match time axis.
    x_lo = min(0.0, m.start - t0) if m.topics else 0.0
    x_hi = max(m.end - t0, x_lo + 1.0)
    lanes = [('score', 1.0), ('localization', 0.8), ('goals', 0.7), ('states', 2.0)]
    top, bottom, gap = tab_bottom - 0.065, 0.04, 0.027
    total = sum(h for _, h in lanes)
    avail = top - bottom - gap * (len(lanes) - 1)
    y = top
    axes = {}
    for name, h in lanes:
        hh = avail * h / total
        axes[name] = fig.add_axes([0.105, y - hh, left_w - 0.15, hh], sharex=axes.get('score'))
        y -= hh + gap
    draw_score(axes['score'], v)
    draw_localization(axes['localization'], v)
    draw_goals(axes['goals'], v)
    draw_states(axes['states'], v, m.end)
    for name, a in axes.items():
        if x_lo < 0:
            a.axvspan(x_lo, 0.0, color='#bbbbbb', alpha=0.25, lw=0)
        for t, trig in v['fired']:
            a.axvline(t - t0, color='red', lw=0.9, alpha=0.7)
        if name != 'states':
            plt.setp(a.get_xticklabels(), visible=False)
    for t, trig in v['fired']:
        axes['states'].annotate(trig, (t - t0, 0.03), xycoords=('data', 'axes fraction'), xytext=(-2, 0),
                                textcoords='offset points', fontsize=7, color='red', rotation=90, va='bottom',
                                ha='right')
    axes['states'].set_xlim(x_lo, x_hi)
    axes['states'].set_xlabel(X_LABEL if v['t_signal'] is not None else
                              'match time [s] (no start signal in this bag: 0 = bag start)')

    # The text panel: wrapped to its width, cut (with a note) at its height.
    tx = fig.add_axes([left_w + 0.005, 0.02, 1.0 - left_w - 0.01, 0.95])
    tx.axis('off')
    tx.set_title('summary', loc='left', fontsize=11)
    fontsize = 8.5
    chars = int((1.0 - left_w - 0.02) * fig_w * 72 / (0.62 * fontsize)) - 2  # monospace: 0.6 em a character
    rows = int(0.95 * fig_h * 72 / (1.22 * fontsize)) - 2
    lines = wrap(v['summary'], chars)
    if len(lines) > rows:
        lines = lines[:rows - 1] + ['... (%d more lines in %s)' % (len(lines) - rows + 1,
                                                                os.path.basename(os.path.splitext(out_png)[0] + '.txt'))]
    tx.text(0.0, 1.0, '\n'.join(lines), va='top', ha='left', family='monospace', fontsize=fontsize,
            transform=tx.transAxes, linespacing=1.15)
    fig.savefig(out_png, dpi=dpi)
    plt.close(fig)


def draw_table(ax, v):
    length, width = v['length'], v['width']
    ax.add_patch(plt.Rectangle((0, 0), length, width, facecolor='#2e7d32', alpha=0.15, edgecolor='#5d4037', lw=3))
    for ns in ('start_zones', 'score_zones'):
        for i, (x, y, sx, sy, rgb) in enumerate(v['zones'].get(ns, [])):
            if ns == 'start_zones':  # in its team's colour
                style = dict(facecolor=rgb + (0.35,), edgecolor=rgb, lw=1.5, ls='-', label='start zone')
            else:  # the markers draw them pale (white): here one visible style
                style = dict(facecolor=(1.0, 0.76, 0.03, 0.30), edgecolor='#b8860b', lw=1.5, ls='--', hatch='//',
                             label='score zone')
            if i:
                style['label'] = None
            ax.add_patch(plt.Rectangle((x, y), sx, sy, **style))
    start, end = v['elements_start'], v['elements_end']
    for i, (kind, x, y, r, _) in enumerate(start):
        ax.add_patch(plt.Circle((x, y), max(r, 0.01), facecolor='none', edgecolor=element_colour(kind), lw=1.2,
                                ls=':', label='element at start' if i == 0 else None))
    for i, (kind, x, y, r, carried) in enumerate(end):
        ax.add_patch(plt.Circle((x, y), max(r, 0.01), facecolor=element_colour(kind), edgecolor='black', lw=0.6,
                                alpha=0.9, label='element at end' if i == 0 else None))
        if carried:
            ax.plot(x, y, 'x', color='black', ms=6)
        if i < len(start) and math.hypot(x - start[i][1], y - start[i][2]) > 0.02:
            ax.annotate('', (x, y), (start[i][1], start[i][2]),
                        arrowprops=dict(arrowstyle='->', color='#555555', lw=0.8, ls='--'))
    opp = v['opponent']
    if opp:
        ax.plot([p[1] for p in opp], [p[2] for p in opp], '-', color='#8e24aa', lw=1.3, alpha=0.8,
                label='opponent (/sim/opponent)')
        ax.plot(opp[0][1], opp[0][2], 's', color='#8e24aa', ms=6)
        ax.plot(opp[-1][1], opp[-1][2], 'D', color='#8e24aa', ms=6)
    truth, estimate = v['truth'], v['estimate']
    if truth:
        ax.plot([p[1] for p in truth], [p[2] for p in truth], '-', color='#0d47a1', lw=2, label='ours, true')
    if estimate:
        ax.plot([p[1] for p in estimate], [p[2] for p in estimate], '--', color='darkorange', lw=1.3,
                label='ours, estimated (%s)' % v['est_topic'])
    path = truth or estimate
    if path:
        ax.plot(path[0][1], path[0][2], 'o', color='black', ms=7, label='ours: start (o), end (D)')
        ax.plot(path[-1][1], path[-1][2], 'D', color='black', ms=6)
    arrow = 0.12
    shown = set()
    for g in v['goals']:
        if g['action'] != 'goto':
            continue
        goal, colour = g['goal'], STATUS_COLOURS.get(g['status'], '#9e9e9e')
        label = 'goto %s' % g['status'].lower() if g['status'] not in shown else None
        shown.add(g['status'])
        ax.annotate('', (goal.x + arrow * math.cos(goal.angle), goal.y + arrow * math.sin(goal.angle)),
                    (goal.x, goal.y), arrowprops=dict(arrowstyle='-|>', color=colour, lw=1.8, mutation_scale=12))
        ax.plot(goal.x, goal.y, '.', color=colour, ms=7, label=label)
        if g['status'] in ('ABORTED', 'REJECTED', 'LOST'):
            ax.annotate('#%d' % g['n'], (goal.x, goal.y), xytext=(4, -10), textcoords='offset points',
                        fontsize=8, color=colour, weight='bold')
    if not path and not opp:
        ax.text(length / 2, width / 2, 'no trajectory in this bag', ha='center', va='center')
    ax.set_xlim(-0.2, length + 0.2)
    ax.set_ylim(-0.2, width + 0.2)
    ax.set_aspect('equal', adjustable='box')
    ax.set_xlabel('x [m] (map)')
    ax.set_ylabel('y [m]')
    ax.set_title('the table: paths, zones, elements (dotted: start, filled: end), goto goals (#: aborted)',
                 fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(handles, labels, loc='upper left', bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)


def draw_score(ax, v):
    t0, series, events = v['t0'], list(v['score_series']), v['events']
    if series and v['m'].end > series[-1][0]:
        series.append((v['m'].end,) + tuple(series[-1][1:]))  # the last score holds to the bag's end
    if series:
        ts = [s[0] - t0 for s in series]
        if v['attributed']:
            ax.step(ts, [s[1] for s in series], where='post', color='#1565c0', lw=2, label='ours')
            ax.step(ts, [s[2] for s in series], where='post', color='#8e24aa', lw=2, label='opponent')
        else:
            ax.step(ts, [s[1] for s in series], where='post', color='#1565c0', lw=2,
                    label='score (%s, no attribution)' % v['score_topic'])
    elif events:
        for team, colour in (('ours', '#1565c0'), ('opponent', '#8e24aa')):
            ts, total, ys = [0.0], 0, [0]
            for e in events:
                if e[1] == team:
                    total += e[2]
                    ts.append(e[0])
                    ys.append(total)
            ax.step(ts, ys, where='post', color=colour, lw=2, label=team + ' (from score events)')
    for e in events:
        colour = '#1565c0' if e[1] == 'ours' else '#8e24aa'
        ax.plot(e[0], 0, '^' if e[2] > 0 else 'v', color=colour, ms=6, clip_on=False)
    if series or events:
        ax.legend(loc='upper left', fontsize=8)
        ax.set_ylim(bottom=min(0, ax.get_ylim()[0]))
    else:
        ax.text(0.5, 0.5, 'score: absent', ha='center', va='center', transform=ax.transAxes)
    ax.set_ylabel('points')
    ax.set_title('score (triangles: score events; red lines: trigger firings)', fontsize=10, loc='left')
    ax.grid(alpha=0.3)


def draw_localization(ax, v):
    err, t0 = v['err'], v['t0']
    if err:
        ax.plot([e[0] - t0 for e in err], [e[1] for e in err], color='crimson', label='position error [m]')
        ax2 = ax.twinx()
        ax2.plot([e[0] - t0 for e in err], [math.degrees(e[2]) for e in err], color='steelblue', lw=0.8,
                 label='heading error [deg]')
        ax2.set_ylabel('heading [deg]')
        ax.set_ylim(bottom=0.0, top=max(0.05, 1.1 * max(e[1] for e in err)))
        ax2.set_ylim(bottom=0.0, top=max(5.0, 1.1 * math.degrees(max(e[2] for e in err))))
        ax.legend(loc='upper left', fontsize=8)
        ax2.legend(loc='upper right', fontsize=8)
    else:
        ax.text(0.5, 0.5, 'localization error: absent (needs %s and /sim/ground_truth)'
                % (v['est_topic'] or '/mcl/pose'), ha='center', va='center', transform=ax.transAxes)
    ax.set_ylabel('position [m]')
    ax.set_title('localization error (estimate vs truth)', fontsize=10, loc='left')
    ax.grid(alpha=0.3)


def draw_goals(ax, v):
    goals, t0, end = v['goals'], v['t0'], v['m'].end
    actions = [a for a in DRIVER_ACTIONS if any(g['action'] == a for g in goals)]
    for g in goals:
        row = actions.index(g['action'])
        t_end = g['t_end'] if g['t_end'] is not None else end
        colour = STATUS_COLOURS.get(g['status'], '#9e9e9e')
        ax.broken_barh([(g['t_sent'] - t0, max(t_end - g['t_sent'], 0.05))], (row - 0.35, 0.7),
                       facecolors=colour, edgecolors='white', lw=0.5)
        if g['status'] in ('ABORTED', 'REJECTED', 'LOST'):
            ax.text(t_end - t0, row + 0.38, '#%d' % g['n'], fontsize=7, color=colour, weight='bold', va='bottom')
    if goals:
        ax.set_yticks(range(len(actions)))
        ax.set_yticklabels(actions, fontsize=8)
        ax.set_ylim(-0.6, len(actions) - 0.4 + 0.3)
        used = []
        for g in goals:
            if g['status'] not in used:
                used.append(g['status'])
        for s in used:
            ax.plot([], [], 's', color=STATUS_COLOURS.get(s, '#9e9e9e'), label=s.lower())
        ax.legend(loc='upper left', bbox_to_anchor=(1.005, 1.0), fontsize=7, borderaxespad=0.0)
    else:
        ax.set_yticks([])
        ax.text(0.5, 0.5, 'driver goals: absent', ha='center', va='center', transform=ax.transAxes)
    ax.set_title('driver goals by result', fontsize=10, loc='left')
    ax.grid(alpha=0.3, axis='x')


def draw_states(ax, v, bag_end):
    states, t0 = v['states'], v['t0']
    depth = None
    if states:
        # A long match visits many state chains: show them as deep as 20 rows allow.
        deepest = max(n.count('/') + 1 for _, n in states)
        for depth in range(deepest, 0, -1):
            if len({'/'.join(n.split('/')[:depth]) for _, n in states}) <= 20:
                break
        states = [(t, '/'.join(n.split('/')[:depth])) for t, n in states]
        if depth == deepest:
            depth = None
        names = []
        for _, n in states:
            if n not in names:
                names.append(n)
        xs = [s[0] - t0 for s in states] + [bag_end - t0]
        ys = [names.index(s[1]) for s in states]
        ax.step(xs, ys + [ys[-1]], where='post', color='purple')
        ax.set_yticks(range(len(names)))
        size = 7
        ax.set_yticklabels([n if len(n) <= 36 else '...' + n[-33:] for n in names], fontsize=size)
    else:
        ax.set_yticks([])
        ax.text(0.5, 0.5, 'brain states: absent', ha='center', va='center', transform=ax.transAxes)
    ax.set_title('brain states%s (red: trigger firings)' % (' (chains cut to %d levels)' % depth if depth else ''),
                 fontsize=10, loc='left')
    ax.grid(alpha=0.3, axis='x')


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
