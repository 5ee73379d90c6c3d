"""The 2008 match ("Mission to Mars", Logion): harvest balls along a Hermite path and deliver them.

Each round CHOOSE picks the next task by its cost (smart_brain/play/task_cost.py: the time it
needs, how contested its place is, the points it brings; a task that cannot finish in the time
left is not offered): a harvest trip through some of the balls of our kinds, or a delivery of
what the harvester holds. Where the balls are comes from what the robot senses
(play/element_tracker.py, one tracker per kind): the table's start positions, moved or dropped by
what the camera sees. What it holds is what the harvester's throat sensor counted (/hal/harvester
/held), not the balls it drove through: a trip that swallowed nothing is not delivered. A goal
BLOCKED twice from about the same spot (play/blocked_spots.py) makes it move away first. With no
ball known it drives its search path to see the table again.

A harvest trip: the roller on, one Hermite path (/hal/driver/follow_path) through up to
`max_balls` balls, the most points per second first. A delivery: drive to the basket, run the
roller backwards `unload_time`. It plays until the match ends. Balls seen closer than
`border_margin` to a border are left: the harvester cannot take one lying against the border
without the robot pushing the border.

Config: ~match2008/..., each key in `parameters` below (smart_brain/PARAMETERS.md).
"""
import logging
import math

from smart_brain.actions.follow_path import follow_path
from smart_brain.actions.goto import goto
from smart_brain.machine_strategy import MachineStrategy
from smart_brain.play.blocked_spots import BlockedSpots
from smart_brain.play.element_tracker import ElementTracker
from smart_brain.play.task_cost import TaskCost
from smart_brain.statemachine import CBState, StateMachine, WaitState, clock
from smart_brain.strategy import StrategyError, register
from smart_brain.world_view import nearest_first

log = logging.getLogger('smart_brain.statemachine')

BLOCKED = 5  # hal_nodes/*Action result code


@register
class Match2008Strategy(MachineStrategy):
    name = 'match2008'
    description = '2008: harvest the balls worth the most per second along a Hermite path, deliver them'
    required_devices = ('driver',)
    required_topics = ('/mcl/pose',)
    restart_on = ('aborted', 'succeeded')
    parameters = {
        'ball_kinds': 'the vision kinds of the balls it harvests',
        'max_balls': 'balls on one harvest path at most',
        'basket': 'where it delivers: [x, y, theta] [m, rad]',
        'search': 'the path it drives to see the table when no ball is known: [[x, y], ..] [m]',
        'harvester_speed': "the roller's command while harvesting",
        'unload_speed': "the roller's command while delivering (negative: backwards)",
        'unload_time': '[s] how long the roller unloads at the basket',
        'harvest_time': '[s] per ball on a path: slowing, swallowing (the task cost\'s handling time)',
        'border_margin': '[m] a ball seen nearer a border than this is left',
        'tracker': 'where the balls are (play/element_tracker.py): {gate [m], forget_after [s], '
                   'view [near, far, half-width] [m]}',
        'blocked': 'spots where a goal ended BLOCKED (play/blocked_spots.py): {radius [m], memory [s], distance [m]}',
        'cost': 'the task cost\'s weights (play/task_cost.py DEFAULTS: travel_weight, contested_weight, '
                'points_weight, speed, reserve, contested_radius, contested_memory, their_half)',
        'harvester_topic': "the roller's std_msgs/Float64 command topic ('': no roller)",
        'held_topic': "the throat sensor's count of held balls, std_msgs/Int32 ('': none)",
        'vision_topic': 'the camera\'s elements (hal_nodes/VisionElements)',
    }

    # ---------------------------------------------------------------- configuration
    def read_config(self, brain, table):
        MachineStrategy.read_config(self, brain, table)
        self.configure(self.params, table.size, table.elements, table.score_zones, start_zones=table.start_zones)
        self.harvester_topic = self.params('harvester_topic', '')
        self.vision_topic = self.params('vision_topic', '/hal/vision/elements')
        self.held_topic = self.params('held_topic', '/hal/harvester/held')

    def configure(self, param, table, elements, score_zones, our_colour=None, start_zones=()):
        """Everything but ROS: `param(key, default)` reads the strategy's block; `table` (length,
        width); `elements` the table's start elements (dicts: kind, at); `score_zones` the
        table's; `our_colour` (None: from the first pose, the zone of `start_zones`, the table's,
        it stands in)."""
        self.kinds = list(param('ball_kinds', ['ball_red', 'ball_white']))
        self.max_balls = int(param('max_balls', 3))
        self.basket = tuple(float(v) for v in param('basket', [0.25, 1.75, math.pi]))
        if len(self.basket) != 3:
            raise StrategyError('parameter ~%s/basket = %r: must be [x, y, theta]' % (self.name, self.basket))
        self.search = [tuple(float(v) for v in p[:2]) for p in param('search', [[1.0, 1.0], [2.0, 1.0], [2.0, 0.5]])]
        self.speed = float(param('harvester_speed', 1.0))
        self.unload_speed = float(param('unload_speed', -1.0))
        self.unload_time = float(param('unload_time', 1.5))
        self.harvest_time = float(param('harvest_time', 1.0))  # [s] per ball on a path: slowing, swallowing
        self.border_margin = float(param('border_margin', 0.08))
        self.table = table
        self.score_zones = score_zones
        self.start_zones = list(start_zones)
        t = param('tracker', {}) or {}
        m = self.border_margin
        self.trackers = {}
        for kind in self.kinds:
            start = [tuple(e['at'][:2]) for e in elements if e.get('kind') == kind]
            self.trackers[kind] = ElementTracker(start, gate=float(t.get('gate', 0.1)),
                                                 forget_after=float(t.get('forget_after', 1.0)),
                                                 view=tuple(t.get('view', (0.35, 1.3, 0.45))), table=table, margin=m)
        b = param('blocked', {}) or {}
        self.blocked = BlockedSpots(radius=float(b.get('radius', 0.15)), memory=float(b.get('memory', 30.0)),
                                    distance=float(b.get('distance', 0.35)), table=table)
        try:
            self.costs = TaskCost(param('cost', {}) or {}, table)
        except ValueError as e:
            raise StrategyError('parameter ~%s/%s' % (self.name, e))
        self.colour = None
        self.points = {}
        if our_colour is not None:
            self._our_colour(our_colour)
        self.held = 0            # by the throat sensor (/hal/harvester/held)
        self.time_left = None
        self.path = []           # the trip being driven: [(kind, x, y)]
        self.search_next = 0

    def _our_colour(self, colour):
        """Our colour, the points each of our kinds brings (the best zone of our colour that counts
        it) and our half of the table."""
        self.colour = colour
        for kind in self.kinds:
            self.points[kind] = max([z.get('points', 0) for z in self.score_zones if z.get('team') == colour and
                                     (not z.get('kinds') or kind in z['kinds'])] or [0])
        for z in self.score_zones:
            if z.get('team') == colour:
                x0, _, x1, _ = z['rect']
                self.costs.our_side = 'left' if (x0 + x1) / 2.0 < self.table[0] / 2.0 else 'right'
                break

    def _ros(self):
        import rospy
        from smart_brain.msg import MatchStatus
        from std_msgs.msg import Float64, Int32
        from smart_brain.world_view import WorldView
        topic = self.harvester_topic
        self.harvester = rospy.Publisher(topic, Float64, queue_size=1, latch=True) if topic else None
        self.world = WorldView(self.table, self.vision_topic, border_margin=self.border_margin, on_elements=self._seen)
        self._subs = [rospy.Subscriber('/brain/match_status', MatchStatus, self._on_status, queue_size=1)]
        if self.held_topic:
            self._subs.append(rospy.Subscriber(self.held_topic, Int32, self._on_held, queue_size=1))

    def _on_status(self, msg):
        self.time_left = msg.remaining if msg.state == 'running' else None

    def _on_held(self, msg):
        self.held = int(msg.data)

    def _seen(self, stamp, elements):
        pose = self.world.pose()
        for kind, tracker in self.trackers.items():
            tracker.update(stamp, pose, [(x, y) for k, x, y in elements if k == kind])

    def pose(self):
        return self.world.pose()

    # ---------------------------------------------------------------- the machine
    def build(self):
        self._ros()
        self.harvest_state = follow_path(points_key='path_points', exec_timeout=25.0)
        self.deliver_state = goto(pose_key='basket', exec_timeout=20.0)
        sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
        sm.userdata.path_points = []
        sm.userdata.basket = self.basket
        sm.userdata.away = None
        sm.userdata.look = []
        p = {'preempted': 'preempted'}
        with sm:
            StateMachine.add('CHOOSE', CBState(self.choose, outcomes=['harvest', 'deliver', 'away', 'search', 'none'],
                                               output_keys=['path_points', 'away', 'look']),
                             transitions={'harvest': 'HARVEST_ON', 'deliver': 'DELIVER', 'away': 'MOVE_AWAY',
                                          'search': 'SEARCH', 'none': 'WAIT'})
            StateMachine.add('HARVEST_ON', CBState(self._roller, outcomes=['on'], cb_args=(self.speed,)),
                             transitions={'on': 'HARVEST'})
            StateMachine.add('HARVEST', self.harvest_state,
                             transitions=dict(p, succeeded='HARVESTED', aborted='HARVEST_FAILED'))
            StateMachine.add('HARVEST_FAILED', CBState(self.harvest_failed, outcomes=['next']),
                             transitions={'next': 'HARVESTED'})
            StateMachine.add('HARVESTED', CBState(self.harvested, outcomes=['next']), transitions={'next': 'CHOOSE'})
            StateMachine.add('DELIVER', self.deliver_state, transitions=dict(p, succeeded='UNLOAD', aborted='DELIVER_FAILED'))
            StateMachine.add('DELIVER_FAILED', CBState(self.deliver_failed, outcomes=['next']),
                             transitions={'next': 'CHOOSE'})
            StateMachine.add('UNLOAD', CBState(self._roller, outcomes=['on'], cb_args=(self.unload_speed,)),
                             transitions={'on': 'UNLOADING'})
            StateMachine.add('UNLOADING', WaitState(self.unload_time), transitions=dict(p, succeeded='UNLOADED'))
            StateMachine.add('UNLOADED', CBState(self.unloaded, outcomes=['next']), transitions={'next': 'CHOOSE'})
            StateMachine.add('MOVE_AWAY', goto(pose_key='away', exec_timeout=8.0, angle_tolerance=math.pi),
                             transitions=dict(p, succeeded='MOVED_AWAY', aborted='MOVED_AWAY'))
            StateMachine.add('MOVED_AWAY', CBState(self.moved_away, outcomes=['next']), transitions={'next': 'CHOOSE'})
            StateMachine.add('SEARCH', follow_path(points_key='look', exec_timeout=25.0),
                             transitions=dict(p, succeeded='CHOOSE', aborted='CHOOSE'))
            StateMachine.add('WAIT', WaitState(0.5), transitions=dict(p, succeeded='CHOOSE'))
        return sm

    def next_round(self, outcome):
        """The machine ended (a trigger gave up on the task: the opponent stayed in the way): where
        the trip was going is contested for a while, and where it stood counts as blocked."""
        if outcome == 'aborted':
            now, pose = clock.now(), self.pose()
            for _, x, y in self.path:
                self.costs.met_opponent(now, x, y)
            self.blocked.note(now, pose)
        return True  # it plays until the match ends

    def _roller(self, ud, speed):
        from std_msgs.msg import Float64
        if self.harvester is not None:
            self.harvester.publish(Float64(speed))
        return 'on'

    # ---------------------------------------------------------------- decisions
    def known_balls(self):
        """[(kind, x, y)] of the balls worth taking, off the borders and out of our containers."""
        ours = [z['rect'] for z in self.score_zones if z.get('team') == self.colour]
        m = self.border_margin
        out = []
        for kind, tracker in self.trackers.items():
            for x, y, _ in tracker.candidates():
                inside = any(r[0] <= x <= r[2] and r[1] <= y <= r[3] for r in ours)
                if not inside and m <= x <= self.table[0] - m and m <= y <= self.table[1] - m:
                    out.append((kind, x, y))
        return out

    def plan_trip(self, pose, room):
        """The trip through up to `room` balls from `pose` with the most points per second (greedy:
        each next ball the best points per second of travel from the last), or []."""
        left = self.known_balls()
        trip, at = [], pose[:2]
        while left and len(trip) < room:
            best = max(left, key=lambda b: (self.points.get(b[0], 0) + 0.1) /
                       (math.hypot(b[1] - at[0], b[2] - at[1]) / self.costs.p['speed'] + self.harvest_time))
            trip.append(best)
            left.remove(best)
            at = best[1:]
        return trip

    def trip_seconds(self, pose, trip):
        path = [pose[:2]] + [b[1:] for b in trip] + [self.basket[:2]]
        return self.costs.seconds(path, self.harvest_time * len(trip) + self.unload_time)

    def choose(self, ud):
        now = clock.now()
        pose = self.pose()
        if pose is None:
            return 'none'
        if self.colour is None:  # the first pose: the start zone we stand in
            self._our_colour(self._colour_at(pose))
        if self.blocked.must_move_away(now, pose):
            ud.away = self.blocked.away_from(pose)
            log.warning('match2008: blocked twice near (%.2f, %.2f): moving away first', pose[0], pose[1])
            return 'away'
        options = []
        room = self.max_balls - self.held
        # A trip: shorten it until it fits the time left (one ball at least).
        trip = self.plan_trip(pose, room) if room > 0 else []
        while trip and not self.costs.fits(self.trip_seconds(pose, trip), self.time_left):
            trip = trip[:-1]
        if trip:
            points = sum(self.points.get(k, 0) for k, _, _ in trip)
            secs = self.trip_seconds(pose, trip)
            # what is held is delivered at the end of the trip too
            options.append((self.costs.cost(now, secs, trip[0][1:], points + 2 * self.held), 'harvest', trip))
        if self.held > 0:
            secs = self.costs.seconds([pose[:2], self.basket[:2]], self.unload_time)
            if self.costs.fits(secs, self.time_left) or not trip:
                options.append((self.costs.cost(now, secs, self.basket, 2 * self.held), 'deliver', None))
        if not options:
            if self.search and (self.time_left is None or self.time_left > 5.0):
                ud.look = [self.search[(self.search_next + k) % len(self.search)] for k in range(len(self.search))]
                self.search_next += 1
                return 'search'
            return 'none'
        _, kind, trip = min(options, key=lambda o: o[0])
        if kind == 'deliver':
            return 'deliver'
        self.path = trip
        ud.path_points = nearest_first(pose[:2], [b[1:] for b in trip])
        return 'harvest'

    def _colour_at(self, pose):
        from robot_core.start_zone import zone_of
        return zone_of(pose, self.start_zones) or 'red'

    def _note_blocked(self, state):
        r = state.result
        if r is not None and getattr(r, 'code', None) == BLOCKED:
            now, pose = clock.now(), self.pose()
            self.blocked.note(now, pose)
            if pose is not None:
                self.costs.met_opponent(now, pose[0], pose[1])

    def harvest_failed(self, ud):
        self._note_blocked(self.harvest_state)
        return 'next'

    def harvested(self, ud):
        # The balls of the trip are in the harvester or not where they were believed: what the
        # camera sees next puts back any still on the table.
        for kind, x, y in self.path:
            self.trackers[kind].not_there(x, y)
        self.path = []
        return 'next'

    def deliver_failed(self, ud):
        self._note_blocked(self.deliver_state)
        return 'next'

    def unloaded(self, ud):
        self._roller(ud, 0.0)
        return 'next'

    def moved_away(self, ud):
        pose = self.pose()
        if pose is not None:
            self.blocked.moved_away(pose)
        return 'next'

    def finalize(self):
        MachineStrategy.finalize(self)
        if getattr(self, 'harvester', None) is not None:
            from std_msgs.msg import Float64
            self.harvester.publish(Float64(0.0))
