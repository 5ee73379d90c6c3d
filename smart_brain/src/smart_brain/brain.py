"""The brain node: loads the strategy named by ~strategy and runs it under the match timer.

Parameters: the `brain:` block of config/<robot>.yaml, read at start by brain_config.py (every
one in smart_brain/PARAMETERS.md). `~match/resume` is written by the brain at the start
({started_at, clock, strategy}): a brain respawned mid-match finds it and resumes the match (no
start signal, the elapsed time kept, the strategy from its first state); the launch clears it
(clear_params), so a new launch starts a new match. At the start the brain publishes the match's
end (ROS time) on `~match/end_topic`; hal_node switches the effectors off then by itself should
the brain be dead or stuck at the end.

Interface:
  ~start (std_srvs/Trigger)              start signal without the cord (operator, tests)
  ~switch_strategy (SwitchStrategy)      replace the strategy at runtime (refused after the match end)
  ~start_action (StartAction), ~stop_action (std_srvs/Trigger): the BrainSlave
  ~match_status (MatchStatus, latched: state, ready and what is not), ~action_status (ActionStatus),
  ~smach/* (introspection)

At the match end, whatever the strategy is doing (even blocked in execute()), the match
timer's thread closes the goal guard (every action goal cancelled, new ones refused),
zeroes /hal/drive/cmd_vel, calls /effectors/deactivate until it succeeds, then stops the
strategy and the BrainSlave.
"""
import sys
import threading
import time

import rospy
from robot_core import sim_time_sleep
from robot_core.params import ParameterError, Params
from std_srvs.srv import Trigger, TriggerResponse

from smart_brain import strategy as strategies
from smart_brain.brain_config import read_config, unknown
from smart_brain.statemachine import GOAL_GUARD, clock
from smart_brain.strategy import StrategyError
from smart_brain.table_settings import TableSettings


def hal_devices_present():
    """Names of HAL devices that publish something: /hal/<device>/<topic>."""
    present = set()
    for topic, _type in rospy.get_published_topics('/hal'):
        parts = topic.split('/')
        if len(parts) >= 4:
            present.add(parts[2])
    return present


def topics_present():
    return {topic for topic, _type in rospy.get_published_topics()}


def missing_requirements(strategy):
    missing = ['/hal/' + m for m in sorted(set(strategy.required_devices) - hal_devices_present())]
    if strategy.required_topics:
        missing += sorted(set(strategy.required_topics) - topics_present())
    return missing


def wait_for_devices(strategy, timeout):
    """Wait until every required device and topic publishes; StrategyError naming the missing ones.
    Wall time: processes starting up take wall time whatever the simulated clock does."""
    deadline = time.monotonic() + timeout
    while not rospy.is_shutdown():
        missing = missing_requirements(strategy)
        if not missing:
            return
        if time.monotonic() > deadline:
            raise StrategyError('strategy %s: HAL device(s)/topic(s) missing after %.0f s: %s '
                                '(is hal_node running with them configured?)'
                                % (strategy.name, timeout, ', '.join(missing)))
        time.sleep(0.2)


class Brain(object):
    def __init__(self):
        # Every parameter of the brain and its strategy, read at once (brain_config.py).
        self.params = Params.from_server('~')
        self.table = TableSettings.from_server()  # handed to every strategy (and its world view, triggers)
        _, settings = read_config(self.params, self.table)  # and every other strategy the config sets up
        for line in unknown(self.params):
            rospy.logwarn('brain: %s', line)
        self.strategy = settings.strategy
        self.rate_hz, self.device_timeout = settings.rate_hz, settings.device_timeout
        self.timed, self.duration, self.start_mode = settings.timed, settings.duration, settings.start_mode
        self.start_topic, self.funny = settings.start_topic, settings.funny
        self.deactivate_service, self.end_topic = settings.deactivate_service, settings.end_topic
        self.saved_match = settings.saved_match
        if self.saved_match and self.saved_match.get('strategy', self.strategy.name) != self.strategy.name:
            # switched before the restart
            self.strategy = strategies.create(str(self.saved_match['strategy']), self.params, self.table)
        rospy.loginfo('brain: strategy %s: %s', self.strategy.name, self.strategy.description)
        wait_for_devices(self.strategy, self.device_timeout)

        from smart_brain.msg import ActionStatus, MatchStatus
        from smart_brain.slave import BrainSlave
        from smart_brain.srv import StartAction, SwitchStrategy
        self._MatchStatus, self._ActionStatus = MatchStatus, ActionStatus
        self.slave = BrainSlave()
        from smart_brain.actions import stop
        stop.prepare()
        self._switch_lock = threading.Lock()
        self._switch_to = None
        self._hmi_strategy = None
        self.match_over = False
        self.deactivated = False
        self._end_done = threading.Event()
        self._match_pub = rospy.Publisher('~match_status', MatchStatus, queue_size=1, latch=True)
        self._action_pub = rospy.Publisher('~action_status', ActionStatus, queue_size=1)
        from std_msgs.msg import String
        from smart_brain.readiness import Readiness
        self.readiness = Readiness(settings.ready_nodes, settings.ready_optional)
        self.ready, self.readiness_text = False, 'not ready: not checked yet'
        self.ready_grace = settings.ready_grace
        self._display_pub = rospy.Publisher(settings.ready_display, String, queue_size=1)
        from std_msgs.msg import Time
        self._Time = Time
        self._match_end_pub = rospy.Publisher(self.end_topic, Time,
                                              queue_size=1, latch=True)
        self._String = String
        self.timer = None
        if self.timed:
            from smart_brain.match_timer import MatchTimer
            # The brain's clock: the match lasts `duration` simulated seconds at any speed.
            self.timer = MatchTimer(self.duration, self._on_match_start, self._on_match_end, clock=clock.now,
                                    poll=clock.POLL if clock.simulated() else None)
            if self.start_mode == 'cord':
                from hal_nodes.msg import HumanInput
                self._start_sub = rospy.Subscriber(self.start_topic, HumanInput, self._on_hmi, queue_size=1)
        if self.timer is not None and self.saved_match:
            self._resume_match(self.saved_match)
        self._start_command_gate()
        from smart_brain.srv import StartActionResponse, SwitchStrategyResponse
        rospy.Service('~start', Trigger, self._gated('~start', self._srv_start, lambda why: TriggerResponse(False, why)))
        rospy.Service('~switch_strategy', SwitchStrategy, self._gated(
            '~switch_strategy', self._srv_switch, lambda why: SwitchStrategyResponse(False, why, [])))
        rospy.Service('~start_action', StartAction, self._gated(
            '~start_action', self._srv_start_action, lambda why: StartActionResponse(False, why)))
        rospy.Service('~stop_action', Trigger, self._gated(
            '~stop_action', self._srv_stop_action, lambda why: TriggerResponse(False, why)))
        self._status_timer = rospy.Timer(rospy.Duration(0.2), lambda _ev: self.publish_status())
        self._ready_thread = threading.Thread(target=self._watch_readiness, name='readiness', daemon=True)
        self._ready_thread.start()

    # ---- commands from outside the robot (robot_core/robot_network.py) ----
    def _start_command_gate(self):
        """A caller of the brain's services from outside the robot's network is refused while a
        match runs (/effectors/match_end in the future, as HAL's gate judges it), obeyed otherwise;
        both said on /diagnostics once a second."""
        import rosgraph
        from diagnostic_msgs.msg import DiagnosticArray
        from robot_core.robot_network import CommandGate, RobotNetwork
        self._match_end = None
        rospy.Subscriber(self.end_topic, self._Time,
                         lambda m: setattr(self, '_match_end', m.data), queue_size=1)
        try:
            network = RobotNetwork.from_param_server()
        except ValueError as e:
            rospy.logerr('brain: %s; only this computer is trusted', e)
            network = RobotNetwork()
        self.command_gate = CommandGate(network, rosgraph.Master(rospy.get_name()), lambda: bool(
            self._match_end and not self._match_end.is_zero() and rospy.Time.now() < self._match_end))
        gate_pub = rospy.Publisher('/diagnostics', DiagnosticArray, queue_size=5)

        def report(_event):
            statuses = self.command_gate.statuses(rospy.get_name())
            if statuses:
                gate_pub.publish(DiagnosticArray(status=statuses))
        self._gate_timer = rospy.Timer(rospy.Duration(1.0), report)

    def _gated(self, name, handler, refuse):
        """`handler` behind the command gate; `refuse(why)` is the answer to a refused caller."""
        service = rospy.resolve_name(name)

        def call(req):
            caller = getattr(req, '_connection_header', {}).get('callerid', '')
            if not self.command_gate.accept(caller, service):
                rospy.logerr_throttle(1.0, 'brain: %s called by %s from outside the robot\'s network during the '
                                      'match: refused' % (service, caller))
                return refuse('refused: %s is outside the robot\'s network and a match runs' % caller)
            return handler(req)
        return call

    # ---- readiness (before the start) ----
    def _watch_readiness(self):
        """Twice a second until the match starts: is the robot ready? Says so on change (log,
        status, the HMI display), so a team reads "ready" only when it is."""
        last = None
        started = time.monotonic()  # wall: the grace covers processes starting up, in wall time
        while not rospy.is_shutdown() and not (self.timer is not None and self.timer.started) and not self.match_over:
            self.ready, self.readiness_text, what = self.readiness.check()
            if what != last:  # said once per change of what is (not) ready, not per new figure
                if self.ready and self.timer is not None:
                    rospy.loginfo('brain: ready: waiting for the start signal on %s (or %s)', self.start_topic,
                                  rospy.resolve_name('~start'))
                elif self.ready:
                    rospy.loginfo('brain: ready')
                elif time.monotonic() - started < self.ready_grace:
                    rospy.loginfo('brain: %s', self.readiness_text)  # still coming up
                else:
                    rospy.logwarn('brain: %s', self.readiness_text)
                last = what
            if self.timer is not None:
                self._display_pub.publish(self._String('ready: pull cord' if self.ready else self.readiness_text))
            clock.sleep(0.5)  # the display text stays fresh (2 s) on the HMI at any speed

    # ---- start signal ----
    def _on_hmi(self, msg):
        # The keypad's strategy list: a new choice before the start switches the strategy (the
        # first message only tells what the display shows; the launch's strategy stands).
        if self._hmi_strategy is not None and msg.strategy and msg.strategy != self._hmi_strategy \
                and not self.timer.started:
            rospy.loginfo('brain: strategy %s chosen on the keypad', msg.strategy)
            ok, why = self.request_switch(msg.strategy)
            if not ok:
                rospy.logwarn('brain: keypad strategy %s refused: %s', msg.strategy, why)
        self._hmi_strategy = msg.strategy
        if msg.started and self.timer.start():
            rospy.loginfo('brain: start signal from %s', self.start_topic)
            self._warn_if_not_ready()

    def _warn_if_not_ready(self):
        if not self.ready:
            rospy.logwarn('brain: the match started while %s', self.readiness_text)

    def _srv_start(self, _req):
        if self.timer is None:
            return TriggerResponse(False, 'strategy %s is not under the match timer' % self.strategy.name)
        if self.timer.start():
            rospy.loginfo('brain: start signal from %s', rospy.resolve_name('~start'))
            self._warn_if_not_ready()
            return TriggerResponse(True, 'match started')
        return TriggerResponse(False, 'the match had already started')

    def _clock_kind(self):
        return 'ros' if clock.simulated() else 'monotonic'

    def _resume_match(self, saved):
        """A brain respawned mid-match: the match goes on from when it started."""
        if clock.simulated():
            # The first /clock: before it ROS time reads 0, so this wait cannot be measured in
            # ROS time; it is a process starting up, bounded on the wall clock (as wait_for_devices).
            deadline = time.monotonic() + 5.0
            while rospy.get_time() <= 0.0 and time.monotonic() < deadline and not rospy.is_shutdown():
                time.sleep(0.01)
        try:
            started_at, kind = float(saved['started_at']), saved['clock']
        except (KeyError, TypeError, ValueError):
            rospy.logwarn('brain: ~match/resume %r is not a saved match: ignored', saved)
            return
        now = clock.now()
        if kind != self._clock_kind() or started_at > now:
            rospy.logwarn('brain: ~match/resume is from another clock (%s at %.1f, now %.1f): a new match', kind,
                          started_at, now)
            return
        rospy.logwarn('brain: restarted during a match: resuming it %.1f s after its start (%.1f s left), '
                      'strategy %s from its first state', now - started_at, max(0.0, self.duration - (now - started_at)),
                      self.strategy.name)
        self.timer.start(at=started_at)

    def _on_match_start(self):
        rospy.loginfo('brain: match started (%.0f s)', self.duration)
        self._save_match()
        # hal_node's backstop: it ends the match at this time should the brain not.
        end = rospy.Time.now() + rospy.Duration(self.timer.remaining())
        self._match_end_pub.publish(self._Time(end))
        if self.timer.remaining() > 0.0:  # resumed after the end: the end follows at once, not "running"
            self.publish_status()

    def _save_match(self):
        rospy.set_param('~match/resume', {'started_at': self.timer.started_at, 'clock': self._clock_kind(),
                                          'strategy': self.strategy.name})

    # ---- match end: the guard above every strategy ----
    def _on_match_end(self):
        t0 = time.monotonic()  # wall: how long the stop took to execute, reported in ms
        self.match_over = True
        cancelled = GOAL_GUARD.close('match end')
        from smart_brain.actions.stop import publish_zero
        publish_zero(times=3)
        self.deactivated = self._deactivate_effectors()
        # The match end is routine (INFO); effectors left on are not (ERROR).
        log = rospy.loginfo if self.deactivated else rospy.logerr
        log('brain: MATCH END after %.1f s: %d goal(s) cancelled, effectors %s (%.0f ms)',
            self.timer.elapsed(), cancelled, 'deactivated' if self.deactivated else 'NOT deactivated',
            1000 * (time.monotonic() - t0))
        self.publish_status()
        self.slave.stop()
        self.strategy.stop()
        if self.funny:
            self._funny_action()
        self._end_done.set()

    def _deactivate_effectors(self, timeout=3.0):
        # A service's reply window: wall time (hal_node answers in wall time).
        proxy = rospy.ServiceProxy(self.deactivate_service, Trigger)
        deadline = time.monotonic() + timeout
        while not rospy.is_shutdown():
            try:
                rospy.wait_for_service(self.deactivate_service, timeout=0.5)
                res = proxy()
                if res.success:
                    return True
                rospy.logerr('brain: %s refused: %s', self.deactivate_service, res.message)
            except (rospy.ROSException, rospy.ServiceException) as e:
                rospy.logerr('brain: %s failed: %s', self.deactivate_service, e)
            if time.monotonic() > deadline:
                return False
            time.sleep(0.05)
        return False

    def _funny_action(self):
        rospy.loginfo('brain: funny action of %s', self.strategy.name)
        try:
            self.strategy.funny_action()
        except Exception as e:
            rospy.logerr('brain: funny action failed: %s', e)

    # ---- strategy switching ----
    def _srv_switch(self, req):
        from smart_brain.srv import SwitchStrategyResponse
        ok, text = self.request_switch(req.name)
        return SwitchStrategyResponse(ok, text, strategies.available())

    def request_switch(self, name):
        """(True, description) once the switch to strategy `name` is queued; (False, why) if not."""
        if self.match_over:
            return False, 'the match is over'
        try:
            new = strategies.create(name, self.params, self.table)
            missing = missing_requirements(new)
            if missing:
                raise StrategyError('strategy %s: HAL device(s)/topic(s) missing: %s' % (name, ', '.join(missing)))
        except (StrategyError, ParameterError) as e:
            return False, str(e)
        with self._switch_lock:
            self._switch_to = new
        rospy.loginfo('brain: switching to strategy %s', new.name)
        return True, new.description

    def _do_switch(self):
        with self._switch_lock:
            new, self._switch_to = self._switch_to, None
        if new is None:
            return
        old = self.strategy
        old.stop()
        old.finalize()
        self.strategy = new
        new.initialize()
        if self.timer is not None and self.timer.started:
            self._save_match()
        self.publish_status()

    # ---- BrainSlave ----
    def _srv_start_action(self, req):
        import yaml
        from smart_brain import actions
        from smart_brain.srv import StartActionResponse
        if GOAL_GUARD.closed:
            return StartActionResponse(False, 'refused: %s' % GOAL_GUARD.reason)
        try:
            args = yaml.safe_load(req.args_yaml) if req.args_yaml.strip() else {}
            if args is not None and not isinstance(args, dict):
                raise ValueError('args_yaml must be a mapping, got %r' % (args,))
            if req.id == self.slave.current_id and self.slave.running():
                return StartActionResponse(True, 'already running')
            state = actions.create(req.action, args)
            return StartActionResponse(True, self.slave.start(req.id, state))
        except Exception as e:
            return StartActionResponse(False, str(e))

    def _srv_stop_action(self, _req):
        return TriggerResponse(self.slave.stop(), 'stopped %s' % self.slave.current_id)

    # ---- status ----
    def publish_status(self):
        if rospy.is_shutdown():
            return
        m = self._MatchStatus()
        m.header.stamp = rospy.Time.now()
        if self.timer is None:
            m.state = 'untimed'
        elif self.match_over:
            m.state = 'ended'
        else:
            m.state = 'running' if self.timer.started else 'waiting_for_start'
        m.ready, m.readiness = self.ready, self.readiness_text
        m.strategy = self.strategy.name
        if self.timer is not None:
            m.elapsed, m.remaining = self.timer.elapsed(), self.timer.remaining()
        m.effectors_deactivated = self.deactivated
        self._match_pub.publish(m)
        aid, state, elapsed, progress, outcome = self.slave.status()
        a = self._ActionStatus(id=aid, state=state, elapsed=elapsed, progress=progress, outcome=outcome)
        a.header.stamp = m.header.stamp
        self._action_pub.publish(a)

    # ---- main loop ----
    def run(self):
        self.strategy.initialize()
        if self.timer is not None:
            if self.start_mode == 'immediate':
                self.timer.start()
            while not rospy.is_shutdown() and not self.timer.wait_started(0.05):
                self._do_switch()
        rate = rospy.Rate(self.rate_hz)
        finished = False
        try:
            while not rospy.is_shutdown() and not self.match_over:
                self._do_switch()
                if not finished and self.strategy.execute() is False:
                    rospy.loginfo('brain: strategy %s finished', self.strategy.name)
                    finished = True
                    if self.timer is None:
                        break
                rate.sleep()
        except rospy.ROSInterruptException:
            pass
        finally:
            self.strategy.stop()
            self.strategy.finalize()
        if self.timer is not None and not rospy.is_shutdown():
            self._end_done.wait()
            rospy.spin()   # stay up: status latched, services answer (refusing), nodes can ping


def main():
    sim_time_sleep.install()  # its rospy timers and rate wake at their deadline, not at every /clock
    rospy.init_node('brain')
    # Set by the launch for the whole graph, not a brain parameter: read as rospy itself reads it.
    if rospy.get_param('/use_sim_time', False):
        clock.use_ros_time()  # every timeout, hold-off and the match timer on /clock
    try:
        brain = Brain()
    except (StrategyError, ParameterError) as e:
        rospy.logfatal('brain: %s', e)
        sys.exit(2)
    brain.run()
