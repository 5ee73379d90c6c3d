"""The bag reader of the match report: Match reads a recorded match topic by topic (poses, goals,
score, states, logs, diagnostics, triggers), with the small helpers that read a message's fields
(stamp_of: match time). The report, the match rows and the chaos invariants all read bags through it;
it needs neither a ROS master nor the project's message packages (rosbag rebuilds the classes)."""
import rosbag
from robot_core.geometry import yaw_of

from robot_tools.matches.idle_time import idle_stretches

DEFAULT_TABLE = (3.0, 2.1)
ERROR_LEVELS = (8, 16)  # rosgraph_msgs/Log ERROR, FATAL
DRIVER_ACTIONS = ('goto', 'go_straight', 'rotate_by', 'follow_path')
# actionlib_msgs/GoalStatus
STATUS_NAMES = {0: 'PENDING', 1: 'ACTIVE', 2: 'PREEMPTED', 3: 'SUCCEEDED', 4: 'ABORTED', 5: 'REJECTED',
                6: 'PREEMPTING', 7: 'RECALLING', 8: 'RECALLED', 9: 'LOST'}


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
