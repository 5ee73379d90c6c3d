"""Supervisor: runs a body machine and preempts it when a trigger fires, then follows
what the trigger's handler decided (history).

    sup = Supervisor(body, triggers=[Trigger('opponent', opponent_ahead, AvoidState(), debounce=0.05)])

The handler state's outcome decides:
  'resume'    re-enter the body where it was interrupted (deep history: nested machines too)
  'restart'   start the body again from its initial state
  '<label>'   start the body at that state of the body machine (go to)
  'aborted'   end the supervisor with 'aborted'
  'preempted' the handler itself was preempted: end with 'preempted'
The supervisor's outcomes are the body's, except those in `restart_on`: a body ending with one
of them starts again from its initial state. After 'aborted' (something failed: give it time to
change) it waits a back-off first (`backoff` = (first, longest) [s] on the brain's clock:
doubling while the body keeps ending sooner than `longest` after its start, back to `first`
after a longer run); after another outcome (e.g. 'succeeded': nothing found, look again) it
starts at once, unless its run was shorter than `first` (no busy loop). `before_restart(outcome)`, when given, runs first
(the strategy forgets a failed task, picks the next one) and may return False: nothing is left
to do, the supervisor ends with that outcome. A match strategy gives up on a task, never on the
match:

    Supervisor(body, triggers, restart_on=('aborted',), backoff=(0.5, 4.0))

One event queue (body ended, handler ended,
preempt, trigger wake-up) is read by the supervisor's thread only, so every preempt is
consumed exactly once; body and handlers run one at a time on one persistent Runner.
"""
import logging
import queue

from smart_brain.statemachine import clock
from smart_brain.statemachine.container import Container
from smart_brain.statemachine.errors import InvalidTransitionError
from smart_brain.statemachine.runner import Runner
from smart_brain.statemachine.state import State
from smart_brain.statemachine.userdata import Remapper

log = logging.getLogger('smart_brain.statemachine')

_DECISIONS = ('resume', 'restart', 'aborted', 'preempted')


class Supervisor(Container):
    def __init__(self, body, triggers=(), poll_period=0.02, input_keys=(), output_keys=(),
                 restart_on=(), backoff=(0.5, 4.0), before_restart=None):
        outcomes = list(body.get_registered_outcomes())
        for extra in ('aborted', 'preempted'):
            if extra not in outcomes:
                outcomes.append(extra)
        Container.__init__(self, outcomes, input_keys, output_keys)
        self.userdata = body.userdata
        self._add_child('BODY', body)
        self.body = body
        self.triggers = sorted(triggers, key=lambda t: -t.priority)
        self.poll_period = poll_period
        self._events = queue.Queue()
        self._runner = Runner('supervisor')
        self._phase = None        # 'BODY' or the trigger name whose handler runs
        self.log = []             # (monotonic time, what) for tests and reports
        self.restart_on = tuple(restart_on)
        self.backoff = (float(backoff[0]), float(backoff[1]))
        if not 0.0 <= self.backoff[0] <= self.backoff[1]:
            raise ValueError('backoff %r: must be (first, longest) with 0 <= first <= longest' % (backoff,))
        self.before_restart = before_restart
        self.restarts = 0
        for trig in self.triggers:
            self._add_child(trig.name, trig.handler)
            trig.attach(self.wake_up)

    def check_consistency(self):
        labels = set(self.body.get_children())
        for trig in self.triggers:
            for outcome in trig.handler.get_registered_outcomes():
                if outcome not in _DECISIONS and outcome not in labels:
                    raise InvalidTransitionError("trigger %s: handler outcome '%s' is neither one of %s nor a state of the body"
                                                 % (trig.name, outcome, ', '.join(_DECISIONS)))
        self.body.check_consistency()

    def get_active_states(self):
        return [self._phase] if self._phase else []

    def get_initial_states(self):
        return ['BODY']

    def get_internal_edges(self):
        edges = [(o, 'BODY', o) for o in self.body.get_registered_outcomes()]
        for trig in self.triggers:
            edges.append(('fired', 'BODY', trig.name))
            edges += [(o, trig.name, 'BODY' if o not in ('aborted', 'preempted') else o)
                      for o in trig.handler.get_registered_outcomes()]
        return edges

    def wake_up(self):
        self._events.put(('poll',))

    def request_preempt(self):
        if not State.request_preempt(self):
            return False
        self._events.put(('preempt',))
        return True

    def _note(self, what):
        self.log.append((clock.now(), what))
        log.info('supervisor: %s', what)

    def _start(self, label, state):
        self._phase = label
        self._notify(self._transition_cbs, [label])
        ud = Remapper(self.userdata, state.get_registered_input_keys(), state.get_registered_output_keys())
        if state is self.body:
            ud = self.userdata
        self._runner.start(state, ud, on_done=lambda outcome, error: self._events.put(('done', label, outcome, error)))

    def _execute_container(self):
        self.check_consistency()
        while True:   # drop events of a previous run
            try:
                self._events.get_nowait()
            except queue.Empty:
                break
        for trig in self.triggers:
            trig.reset()
        self._notify(self._start_cbs, ['BODY'])
        self._start('BODY', self.body)
        self.restarts = 0
        body_started = clock.now()
        delay = 0.0           # the last back-off
        restart_at = None     # backing off: the body starts again at this time
        fired = None          # the trigger whose handler runs (or will, once the body stopped)
        body_outcome = None   # how the interrupted body ended
        preempted = False
        while True:
            try:
                event = self._events.get(timeout=self.poll_period)
            except queue.Empty:
                event = ('poll',)
            kind = event[0]
            if kind == 'preempt':
                if self.service_preempt() and not preempted:
                    preempted = True
                    self._note('preempted from above')
                    if restart_at is not None:   # backing off: nothing runs
                        return self._finish('preempted')
                    self._runner.preempt()
                continue
            if kind == 'poll':
                if restart_at is not None and clock.now() >= restart_at:
                    restart_at = None
                    self.restarts += 1
                    self.body.restart_next()
                    body_started = clock.now()
                    self._start('BODY', self.body)
                elif self._phase == 'BODY' and fired is None and not preempted:
                    now = clock.now()
                    for trig in self.triggers:
                        if trig.update(now):
                            fired = trig
                            if trig.on_fire is not None:
                                trig.on_fire()
                            self._note('trigger %s fired: preempting the body' % trig.name)
                            self._runner.preempt()
                            break
                continue
            # kind == 'done': the body or a handler ended
            _, label, outcome, error = event
            if error is not None:
                self._phase = None
                raise error
            if preempted:
                self._phase = None
                return self._finish('preempted')
            ended = None   # the body's run is over with this outcome (unless it starts again)
            if label == 'BODY':
                if fired is None:
                    ended = outcome
                else:
                    # The body stopped for the trigger (or ended by itself at the same time:
                    # the handler still runs, then the decision applies).
                    body_outcome = outcome
                    self._note('body stopped (%s) at %s; running handler %s' % (outcome, self.body.history(), fired.name))
                    self._start(fired.name, fired.handler)
                    continue
            else:
                fired.handled()
                decision = outcome
                fired = None
                self._note('handler %s decided %s' % (label, decision))
                if decision in ('aborted', 'preempted'):
                    ended = decision
                elif decision == 'resume' and body_outcome != 'preempted':
                    ended = body_outcome   # the body had finished on its own before the trigger stopped it
                else:
                    if decision == 'resume':
                        self.body.resume_next()
                    elif decision == 'restart':
                        self.body.restart_next()
                    else:
                        self.body.restart_next(decision)
                    self._start('BODY', self.body)
                    continue
            self._phase = None
            if ended not in self.restart_on or not self._wants_restart(ended):
                return self._finish(ended)
            ran = clock.now() - body_started
            if ended != 'aborted':
                delay = 0.0 if ran >= self.backoff[0] else self.backoff[0]
            else:
                delay = self.backoff[0] if ran >= self.backoff[1] or delay == 0.0 else min(2.0 * delay, self.backoff[1])
            restart_at = clock.now() + delay
            self._note('body ended %s: starting it again in %.1f s' % (ended, delay))

    def _wants_restart(self, outcome):
        if self.before_restart is None:
            return True
        if self.before_restart(outcome) is False:
            self._note('body ended %s and nothing is left to do' % outcome)
            return False
        return True

    def _finish(self, outcome):
        self._notify(self._transition_cbs, [])
        self._notify(self._termination_cbs, ['BODY'], outcome)
        return outcome
