"""The 2009 match ("Temples of Atlantis"): take columns with the hand and build.

Loop: choose the nearest column (seen by the vision device, else the next configured
position not tried yet), stop `approach` before it facing it, open the hand, creep in,
close, lift to carry height; once `max_carry` are held or no column is left, drive to the
build zone, lift to the next floor's height, open, back off; again until nothing is left.
A failed approach marks that column as tried. A column already lying in one of our scoring
zones (the table's score_zones that count `column_kind`, /table/score_zones) is never taken
again: once built, the temple is left alone.

It plays until the match ends. A build zone it could not reach (blocked by the opponent,
localization held too long) is set aside for `zone_retry_after` seconds and the next one in
`build_zones` is tried. A machine that aborts starts again (MachineStrategy.restart_on). When
every column was tried, the ones not scored are tried again.

Config: ~match2009/{columns, build_zones (or one build_zone), build_heights, carry_height,
approach, creep, max_carry, column_kind, vision_topic, zone_retry_after}.
"""
import logging
import math

from smart_brain.actions.go_straight import go_straight
from smart_brain.actions.goto import goto
from smart_brain.actions.hand import hand
from smart_brain.machine_strategy import MachineStrategy
from smart_brain.statemachine import CBState, Retry, StateMachine, clock
from smart_brain.strategy import StrategyError, register
from smart_brain.world_view import WorldView, approach_pose

log = logging.getLogger('smart_brain.statemachine')


@register
class Match2009Strategy(MachineStrategy):
    name = 'match2009'
    description = '2009: take columns with the hand and build temples in the build zone'
    required_devices = ('driver', 'hand')
    required_topics = ('/mcl/pose',)
    restart_on = ('aborted', 'succeeded')

    def _pose_param(self, key, value, size):
        """`value` (the parameter ~<name>/<key>) as a list of `size` numbers, else a StrategyError."""
        try:
            value = [float(v) for v in value]
            if len(value) != size:
                raise ValueError
        except (TypeError, ValueError):
            raise StrategyError('parameter ~%s/%s = %r: must be a list of %d numbers' % (self.name, key, value, size))
        return value

    def build(self):
        self.columns = [tuple(float(v) for v in c[:2]) for c in self.param('columns', [])]
        zones = self.param('build_zones', None)
        if zones is None:
            zones = [self.param('build_zone', [1.5, 0.3, -math.pi / 2])]
        if not isinstance(zones, list) or not zones:
            raise StrategyError('parameter ~%s/build_zones = %r: must be a non-empty list of [x, y, theta]' % (self.name, zones))
        self.build_zones = [self._pose_param('build_zones[%d]' % i, z, 3) for i, z in enumerate(zones)]
        self.build_zone = self.build_zones[0]
        self.zone_retry_after = float(self.param('zone_retry_after', 20.0))
        self.zone = 0                 # the build zone in use
        self.zone_failed = {}         # build zone index -> clock time it could not be reached
        self.floors = [0] * len(self.build_zones)
        self.build_heights = [float(h) for h in self.param('build_heights', [0.0, 0.03, 0.06])]
        carry = float(self.param('carry_height', 0.04))
        approach = float(self.param('approach', 0.25))
        creep = float(self.param('creep', 0.12))
        self.max_carry = int(self.param('max_carry', 2))
        self.kind = self.param('column_kind', 'column')
        self.world = WorldView(self.param('vision_topic', '/hal/vision/elements'))
        self.tried = []
        import rospy
        self.scored_zones = [z['rect'] for z in rospy.get_param('/table/score_zones', [])
                             if not z.get('kinds') or self.kind in z.get('kinds')]

        sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
        sm.userdata.carried = 0
        sm.userdata.target = None
        sm.userdata.approach = None
        sm.userdata.build_pose = tuple(self.build_zones[0])
        with sm:
            StateMachine.add('CHOOSE', CBState(self._choose, outcomes=['found', 'none', 'build'],
                                               input_keys=['carried'], output_keys=['target', 'approach']),
                             transitions={'found': 'APPROACH', 'none': 'FINISH', 'build': 'PICK_ZONE'})
            StateMachine.add('APPROACH', Retry(goto(pose_key='approach', exec_timeout=15.0)),
                             transitions={'succeeded': 'OPEN', 'aborted': 'CHOOSE', 'preempted': 'preempted'})
            StateMachine.add('OPEN', hand('open'), transitions={'succeeded': 'CREEP', 'aborted': 'CHOOSE',
                                                                'preempted': 'preempted'})
            StateMachine.add('CREEP', go_straight(creep, exec_timeout=5.0),
                             transitions={'succeeded': 'CLOSE', 'aborted': 'CLOSE', 'preempted': 'preempted'})
            StateMachine.add('CLOSE', hand('close'), transitions={'succeeded': 'CARRY', 'aborted': 'CHOOSE',
                                                                  'preempted': 'preempted'})
            StateMachine.add('CARRY', hand('lift', height=carry), transitions={'succeeded': 'COUNT', 'aborted': 'COUNT',
                                                                                'preempted': 'preempted'})
            StateMachine.add('COUNT', CBState(self._count, outcomes=['more', 'full'], io_keys=['carried']),
                             transitions={'more': 'CHOOSE', 'full': 'PICK_ZONE'})
            StateMachine.add('PICK_ZONE', CBState(self._pick_zone, outcomes=['zone'], output_keys=['build_pose']),
                             transitions={'zone': 'TO_BUILD'})
            StateMachine.add('TO_BUILD', Retry(goto(pose_key='build_pose', exec_timeout=20.0), attempts=2),
                             transitions={'succeeded': 'FLOOR', 'aborted': 'ZONE_FAILED', 'preempted': 'preempted'})
            StateMachine.add('ZONE_FAILED', CBState(self._zone_failed, outcomes=['next']),
                             transitions={'next': 'PICK_ZONE'})
            StateMachine.add('FLOOR', CBState(self._floor, outcomes=['lift']), transitions={'lift': 'LIFT'})
            StateMachine.add('LIFT', _LiftToFloor(self), transitions={'succeeded': 'RELEASE', 'aborted': 'RELEASE',
                                                                      'preempted': 'preempted'})
            StateMachine.add('RELEASE', hand('open'), transitions={'succeeded': 'BACK_OFF', 'aborted': 'BACK_OFF',
                                                                   'preempted': 'preempted'})
            StateMachine.add('BACK_OFF', go_straight(0.15, backwards=True, exec_timeout=5.0),
                             transitions={'succeeded': 'BUILT', 'aborted': 'BUILT', 'preempted': 'preempted'})
            StateMachine.add('BUILT', CBState(self._built, outcomes=['again'], output_keys=['carried']),
                             transitions={'again': 'CHOOSE'})
            StateMachine.add('FINISH', CBState(lambda ud: 'done', outcomes=['done']), transitions={'done': 'succeeded'})
        return sm

    def _candidates(self, forget_tried=False):
        seen = [(x, y) for _, x, y in self.world.elements([self.kind])]
        tried = [] if forget_tried else self.tried
        return [c for c in seen + self.columns
                if all(math.hypot(c[0] - t[0], c[1] - t[1]) > 0.05 for t in tried) and not self._scored(c)]

    def next_round(self, outcome):
        if outcome == 'succeeded':   # every column tried: those not scored get another chance
            self.tried = []
            return bool(self._candidates())
        return True

    def _choose(self, ud):
        if ud.carried >= self.max_carry:    # a column in hand (an earlier build failed): build first
            return 'build'
        robot = self.world.pose() or (self.build_zone[0], self.build_zone[1])
        candidates = self._candidates()
        if not candidates:
            return 'build' if ud.carried > 0 else 'none'
        target = min(candidates, key=lambda c: math.hypot(c[0] - robot[0], c[1] - robot[1]))
        self.tried.append(target)
        ud.target = target
        ud.approach = approach_pose(robot, target, float(self.param('approach', 0.25)))
        return 'found'

    def _scored(self, point):
        """The point lies in one of our scoring zones (with a column radius of margin)."""
        m = 0.04
        return any(r[0] - m <= point[0] <= r[2] + m and r[1] - m <= point[1] <= r[3] + m for r in self.scored_zones)

    def _count(self, ud):
        ud.carried = ud.carried + 1
        return 'full' if ud.carried >= self.max_carry else 'more'

    def _pick_zone(self, ud):
        """The first build zone not set aside in the last zone_retry_after seconds, else the one
        set aside longest ago."""
        now = clock.now()
        free = [i for i in range(len(self.build_zones))
                if now - self.zone_failed.get(i, -1e9) >= self.zone_retry_after]
        self.zone = free[0] if free else min(self.zone_failed, key=self.zone_failed.get)
        ud.build_pose = tuple(self.build_zones[self.zone])
        return 'zone'

    def _zone_failed(self, ud):
        self.zone_failed[self.zone] = clock.now()
        log.warning('match2009: build zone %d %s not reached: trying the next one', self.zone, self.build_zones[self.zone])
        return 'next'

    @property
    def floor(self):
        return self.floors[self.zone]

    def _floor(self, ud):
        return 'lift'

    def _built(self, ud):
        self.floors[self.zone] += 1
        ud.carried = 0
        return 'again'


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
