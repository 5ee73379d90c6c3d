"""The 2009 match ("Temples of Atlantis"): take columns with the hand and build.

Each round CHOOSE picks the next task by its cost (smart_brain/play/task_cost.py: the time it
needs, how contested its place is, the points it brings; a task that cannot finish in the time
left is not offered): take a column, or build with what the hand holds. Where the columns are
comes from what the robot senses (play/element_tracker.py): the configured start positions,
moved or dropped by what the camera sees; a column the hand closed on and did not hold is
dropped too. What the robot holds is what the hand's sensor says (the hand action's `holding`),
not the attempts it made: a hand that closed on nothing opens and chooses again, it never goes
to build. A goal that ended BLOCKED twice from about the same spot (play/blocked_spots.py)
makes it move away first. With nothing left to take it drives to its next lookout
(`look_from`) to see the table again.

Take: stop `approach` before the column, facing it; open, creep in, close, lift to carry height.
Build: drive to a build spot (the free one of `build_spots` nearest, each [x, y, theta, points]),
lift to the floor's height, open, back off. It plays until the match ends.

Config: ~match2009/..., each key in `parameters` below (smart_brain/PARAMETERS.md).
"""
import logging
import math

from smart_brain.actions.go_straight import go_straight
from smart_brain.actions.goto import goto
from smart_brain.actions.hand import hand
from smart_brain.machine_strategy import MachineStrategy
from smart_brain.play.blocked_spots import BlockedSpots
from smart_brain.play.element_tracker import ElementTracker
from smart_brain.play.task_cost import TaskCost
from smart_brain.statemachine import CBState, StateMachine, WaitState, clock
from smart_brain.strategy import StrategyError, register
from smart_brain.world_view import approach_pose

log = logging.getLogger('smart_brain.statemachine')

BLOCKED = 5  # hal_nodes/*Action result code


@register
class Match2009Strategy(MachineStrategy):
    name = 'match2009'
    description = '2009: take columns with the hand and build temples, task by task by their cost'
    required_devices = ('driver', 'hand')
    required_topics = ('/mcl/pose',)
    restart_on = ('aborted', 'succeeded')
    parameters = {
        'column_kind': 'the vision kind of the columns the hand takes',
        'columns': 'the columns\' start positions, [[x, y], ..] [m]',
        'build_spots': 'where it builds: [[x, y, theta, points], ..] [m, rad]',
        'build_heights': '[m] the hand\'s height for each floor of a temple',
        'carry_height': '[m] the hand\'s height while carrying',
        'approach': '[m] it stops this far before a column, facing it',
        'creep': '[m] then drives this far in with the hand open',
        'max_carry': 'columns carried at once',
        'take_time': '[s] open, creep, close, lift (the task cost\'s handling time)',
        'build_time': '[s] lift, open, back off (the task cost\'s handling time)',
        'look_from': 'lookouts it drives to when nothing is left to take: [[x, y, theta], ..]',
        'tracker': 'where the columns are (play/element_tracker.py): {gate [m], forget_after [s], '
                   'view [near, far, half-width] [m]}',
        'blocked': 'spots where a goal ended BLOCKED (play/blocked_spots.py): {radius [m], memory [s], distance [m]}',
        'cost': 'the task cost\'s weights (play/task_cost.py DEFAULTS: travel_weight, contested_weight, '
                'points_weight, speed, reserve, contested_radius, contested_memory, their_half)',
        'vision_topic': 'the camera\'s elements (hal_nodes/VisionElements)',
    }

    # ---------------------------------------------------------------- configuration
    def read_config(self, brain, table):
        MachineStrategy.read_config(self, brain, table)
        self.configure(self.params, table.size, table.score_zones)
        self.vision_topic = self.params('vision_topic', '/hal/vision/elements')

    def _numbers(self, key, value, size):
        try:
            value = [float(v) for v in value]
            if len(value) != size:
                raise ValueError
        except (TypeError, ValueError):
            raise StrategyError('parameter ~%s/%s = %r: must be a list of %d numbers' % (self.name, key, value, size))
        return value

    def configure(self, param, table, score_zones, our_side=None):
        """Everything but ROS: `param(key, default)` reads the strategy's block, `table` is
        (length, width), `score_zones` the table's (dicts with rect, kinds, points, team); `our_side` 'left' or
        'right' of the table (None: from the first pose, in our start zone)."""
        self.kind = param('column_kind', 'column')
        self.columns = [tuple(float(v) for v in c[:2]) for c in param('columns', [])]
        spots = param('build_spots', [[1.5, 0.35, -math.pi / 2, 3]])
        if not isinstance(spots, list) or not spots:
            raise StrategyError('parameter ~%s/build_spots = %r: must be a non-empty list of [x, y, theta, points]'
                                % (self.name, spots))
        self.spots = [self._numbers('build_spots[%d]' % i, s, 4) for i, s in enumerate(spots)]
        self.floors = [0] * len(self.spots)
        self.build_heights = [float(h) for h in param('build_heights', [0.0, 0.03, 0.06])]
        self.carry_height = float(param('carry_height', 0.04))
        self.approach = float(param('approach', 0.25))
        self.creep = float(param('creep', 0.12))
        self.max_carry = int(param('max_carry', 1))
        self.take_time = float(param('take_time', 4.0))    # [s] open, creep, close, lift
        self.build_time = float(param('build_time', 4.0))  # [s] lift, open, back off
        self.look_from = [self._numbers('look_from[%d]' % i, p, 3) for i, p in enumerate(param('look_from', []))]
        self.look_next = 0
        ours = [z['rect'] for z in score_zones if not z.get('kinds') or self.kind in z.get('kinds')]
        t = param('tracker', {}) or {}
        self.tracker = ElementTracker(self.columns, gate=float(t.get('gate', 0.12)),
                                      forget_after=float(t.get('forget_after', 1.0)),
                                      view=tuple(t.get('view', (0.4, 1.3, 0.4))), table=table, keep_out=ours)
        b = param('blocked', {}) or {}
        self.blocked = BlockedSpots(radius=float(b.get('radius', 0.15)), memory=float(b.get('memory', 30.0)),
                                    distance=float(b.get('distance', 0.35)), table=table)
        try:
            self.costs = TaskCost(param('cost', {}) or {}, table, our_side)
        except ValueError as e:
            raise StrategyError('parameter ~%s/%s' % (self.name, e))
        self.held = 0            # what the hand holds, by its sensor
        self.target = None       # the column being taken (x, y)
        self.spot = None         # the build spot in use (index)
        self.time_left = None    # [s] of the match, from /brain/match_status

    def _ros(self):
        """Subscriptions: the camera's elements into the tracker, the match's time left."""
        import rospy
        from smart_brain.msg import MatchStatus
        from smart_brain.world_view import WorldView
        self.world = WorldView(self.costs.table, self.vision_topic, on_elements=self._seen)
        self._status_sub = rospy.Subscriber('/brain/match_status', MatchStatus, self._on_status, queue_size=1)

    def _on_status(self, msg):
        self.time_left = msg.remaining if msg.state == 'running' else None

    def _seen(self, stamp, elements):
        self.tracker.update(stamp, self.world.pose(), [(x, y) for k, x, y in elements if k == self.kind])

    def pose(self):
        return self.world.pose()

    # ---------------------------------------------------------------- the machine
    def build(self):
        self._ros()
        self.approach_state = goto(pose_key='approach', exec_timeout=15.0)
        self.build_state = goto(pose_key='build_pose', exec_timeout=20.0)
        self.close_state = hand('close')
        sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
        sm.userdata.approach = None
        sm.userdata.build_pose = None
        sm.userdata.away = None
        sm.userdata.look = None
        p = {'preempted': 'preempted'}
        with sm:
            StateMachine.add('CHOOSE', CBState(self.choose, outcomes=['take', 'build', 'away', 'look', 'none'],
                                               output_keys=['approach', 'build_pose', 'away', 'look']),
                             transitions={'take': 'APPROACH', 'build': 'TO_BUILD', 'away': 'MOVE_AWAY', 'look': 'LOOK',
                                          'none': 'WAIT'})
            StateMachine.add('APPROACH', self.approach_state,
                             transitions=dict(p, succeeded='OPEN', aborted='APPROACH_FAILED'))
            StateMachine.add('APPROACH_FAILED', CBState(self.approach_failed, outcomes=['next']),
                             transitions={'next': 'CHOOSE'})
            StateMachine.add('OPEN', hand('open'), transitions=dict(p, succeeded='CREEP', aborted='CHOOSE'))
            StateMachine.add('CREEP', go_straight(self.creep, exec_timeout=5.0),
                             transitions=dict(p, succeeded='CLOSE', aborted='CLOSE'))
            StateMachine.add('CLOSE', self.close_state, transitions=dict(p, succeeded='CHECK_HELD', aborted='CHECK_HELD'))
            StateMachine.add('CHECK_HELD', CBState(self.check_held, outcomes=['held', 'empty']),
                             transitions={'held': 'CARRY', 'empty': 'OPEN_EMPTY'})
            StateMachine.add('OPEN_EMPTY', hand('open'), transitions=dict(p, succeeded='BACK_FROM_MISS',
                                                                          aborted='BACK_FROM_MISS'))
            StateMachine.add('BACK_FROM_MISS', go_straight(0.10, backwards=True, exec_timeout=4.0),
                             transitions=dict(p, succeeded='CHOOSE', aborted='CHOOSE'))
            StateMachine.add('CARRY', hand('lift', height=self.carry_height),
                             transitions=dict(p, succeeded='CHOOSE', aborted='CHOOSE'))
            StateMachine.add('TO_BUILD', self.build_state,
                             transitions=dict(p, succeeded='LIFT', aborted='BUILD_FAILED'))
            StateMachine.add('BUILD_FAILED', CBState(self.build_failed, outcomes=['next']),
                             transitions={'next': 'CHOOSE'})
            StateMachine.add('LIFT', _LiftToFloor(self), transitions=dict(p, succeeded='RELEASE', aborted='RELEASE'))
            StateMachine.add('RELEASE', hand('open'), transitions=dict(p, succeeded='BACK_OFF', aborted='BACK_OFF'))
            StateMachine.add('BACK_OFF', go_straight(0.15, backwards=True, exec_timeout=5.0),
                             transitions=dict(p, succeeded='BUILT', aborted='BUILT'))
            StateMachine.add('BUILT', CBState(self.built, outcomes=['again']), transitions={'again': 'CHOOSE'})
            StateMachine.add('MOVE_AWAY', goto(pose_key='away', exec_timeout=8.0, angle_tolerance=math.pi),
                             transitions=dict(p, succeeded='MOVED_AWAY', aborted='MOVED_AWAY'))
            StateMachine.add('MOVED_AWAY', CBState(self.moved_away, outcomes=['next']), transitions={'next': 'CHOOSE'})
            StateMachine.add('LOOK', goto(pose_key='look', exec_timeout=12.0),
                             transitions=dict(p, succeeded='LOOKING', aborted='CHOOSE'))
            StateMachine.add('LOOKING', WaitState(0.6), transitions=dict(p, succeeded='CHOOSE'))
            StateMachine.add('WAIT', WaitState(0.5), transitions=dict(p, succeeded='CHOOSE'))
        return sm

    def next_round(self, outcome):
        """The machine ended (a trigger gave up on the task: the opponent stayed in the way): where
        it was going is contested for a while, and where it stood counts as blocked."""
        if outcome == 'aborted':
            now, pose = clock.now(), self.pose()
            going = self.target if self.held == 0 or self.spot is None else self.spots[self.spot][:2]
            if going is not None:
                self.costs.met_opponent(now, going[0], going[1])
            self.blocked.note(now, pose)
        return True  # it plays until the match ends

    # ---------------------------------------------------------------- decisions
    def best_spot(self, frm):
        """(index, seconds) of the build spot to use from `frm`: the least built on, then the nearest."""
        least = min(self.floors)
        best = None
        for i, s in enumerate(self.spots):
            if self.floors[i] != least:
                continue
            secs = self.costs.seconds([frm, s[:2]], self.build_time)
            if best is None or secs < best[1]:
                best = (i, secs)
        return best

    def choose(self, ud):
        now = clock.now()
        pose = self.pose()
        if pose is None:
            return 'none'
        if self.costs.our_side is None:  # the first pose: the start zone is on our half
            self.costs.our_side = 'left' if pose[0] < self.costs.table[0] / 2.0 else 'right'
        if self.blocked.must_move_away(now, pose):
            away = self.blocked.away_from(pose)
            log.warning('match2009: blocked twice near (%.2f, %.2f): moving away to (%.2f, %.2f) first',
                        pose[0], pose[1], away[0], away[1])
            ud.away = away
            return 'away'
        options = []  # (cost, kind, payload)
        if self.held > 0:
            for i, s in enumerate(self.spots):
                secs = self.costs.seconds([pose, s[:2]], self.build_time)
                if self.costs.fits(secs, self.time_left):
                    # the least built-on spots first: stacking is for when every spot has a floor
                    extra = (self.floors[i] - min(self.floors)) * self.build_time
                    options.append((self.costs.cost(now, secs + extra, s, s[3] * self.held), 'build', i))
        if self.held < self.max_carry:
            for x, y, seen_at in self.tracker.candidates():
                approach = approach_pose(pose, (x, y), self.approach)
                spot = self.best_spot((x, y))
                secs = self.costs.seconds([pose, approach[:2]], self.take_time) + spot[1]
                if not self.costs.fits(secs, self.time_left):
                    continue
                points = self.spots[spot[0]][3]
                options.append((self.costs.cost(now, secs, (x, y), points), 'take', (x, y, approach)))
        if not options:
            if self.held == 0 and self.look_from:
                look = tuple(self.look_from[self.look_next % len(self.look_from)])
                self.look_next += 1
                if self.costs.fits(self.costs.seconds([pose, look[:2]], 0.0), self.time_left):
                    ud.look = look
                    return 'look'
            return 'none'
        _, kind, what = min(options, key=lambda o: o[0])
        if kind == 'build':
            self.spot = what
            ud.build_pose = tuple(self.spots[what][:3])
            return 'build'
        self.target = what[:2]
        ud.approach = what[2]
        return 'take'

    def check_held(self, ud):
        """Count what the hand holds: its sensor's word (unknown without one: the attempt counts)."""
        r = self.close_state.result
        holding = getattr(r, 'holding', -1) if r is not None else -1
        if holding == 0:
            log.warning('match2009: the hand closed on nothing at (%.2f, %.2f): the column is not there',
                        self.target[0], self.target[1])
            self.tracker.not_there(*self.target)
            return 'empty'
        self.held += 1
        self.tracker.taken(*self.target)
        return 'held'

    def _note_blocked(self, state):
        r = state.result
        if r is not None and getattr(r, 'code', None) == BLOCKED:
            now, pose = clock.now(), self.pose()
            self.blocked.note(now, pose)
            if pose is not None:
                self.costs.met_opponent(now, pose[0], pose[1])

    def approach_failed(self, ud):
        self._note_blocked(self.approach_state)
        if self.target is not None:  # contested: its cost rises for a while
            self.costs.met_opponent(clock.now(), *self.target)
        return 'next'

    def build_failed(self, ud):
        self._note_blocked(self.build_state)
        s = self.spots[self.spot]
        self.costs.met_opponent(clock.now(), s[0], s[1])
        return 'next'

    def built(self, ud):
        self.floors[self.spot] += 1
        self.held = 0
        return 'again'

    def moved_away(self, ud):
        pose = self.pose()
        if pose is not None:
            self.blocked.moved_away(pose)
        return 'next'

    @property
    def floor(self):
        return self.floors[self.spot]


class _LiftToFloor(CBState):
    """Lift the hand to the height of the next floor of the temple (the hand action, built
    when it runs because the height depends on how many floors are already built)."""

    def __init__(self, strategy):
        CBState.__init__(self, self._run, outcomes=['succeeded', 'aborted', 'preempted'])
        self._strategy = strategy
        self._current = None

    def request_preempt(self):
        ok = CBState.request_preempt(self)
        if ok and self._current is not None:
            self._current.request_preempt()
        return ok

    def _run(self, ud):
        s = self._strategy
        height = s.build_heights[min(s.floor, len(s.build_heights) - 1)]
        self._current = st = hand('lift', height=height)
        st._begin()     # from here a preempt reaches it; one that came just before is seen below
        try:
            if self.preempt_requested():
                return 'preempted'
            return st.run(None)
        finally:
            st._end()
            self._current = None
