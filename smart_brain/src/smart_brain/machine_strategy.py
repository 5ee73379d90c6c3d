"""MachineStrategy: a strategy written as a state machine, run beside the triggers.

Subclasses implement build() -> StateMachine. initialize() wraps it in a Supervisor with
the triggers configured under the brain's ~triggers (opponent ahead, stuck, localization
lost, ...; a strategy may narrow them with `trigger_kinds`), publishes it for
smach_viewer under /brain/smach/... and execute() runs it on one persistent thread; stop()
preempts it (goals cancelled) and waits for it.

A timed strategy gives up on a task, never on the match: when its machine ends with one of
`restart_on` (default 'aborted'), the Supervisor starts it again from its initial state after a
back-off (`backoff`, [s] first and longest), once next_round(outcome) has let the strategy
forget the failed task. Only the match end (or a next_round that returns False: nothing is left
to do) ends it.
"""
import rospy

from smart_brain import triggers as trigger_kinds
from smart_brain.statemachine import Runner, Supervisor
from smart_brain.strategy import Strategy


class MachineStrategy(Strategy):
    #: trigger kinds this strategy accepts from ~triggers (None: every configured one)
    trigger_kinds = None
    #: machine outcomes that start it again instead of ending the strategy (timed strategies only)
    restart_on = ('aborted',)
    #: [s] (first, longest) pause before the machine starts again; doubles while runs stay short
    backoff = (0.5, 4.0)

    def next_round(self, outcome):
        """Called before the machine starts again after ending with `outcome`: forget what
        failed, choose anew. Return False when nothing is left to do (the strategy ends)."""
        return True

    def build(self):
        raise NotImplementedError

    def read_config(self, brain, table):
        """The strategy's block (Strategy.read_config) and the triggers' blocks (~triggers) it runs with."""
        Strategy.read_config(self, brain, table)
        self.trigger_settings = trigger_kinds.settings(brain.block('triggers'), self.trigger_kinds, table)

    def param(self, key, default=None):
        """~<strategy name>/<key> of the brain node (the strategy's own config block), as read by
        read_config's reader."""
        return self.params(key, default)

    def initialize(self):
        self.ensure_config()
        self.machine = self.build()
        self.machine.check_consistency()
        self.triggers = trigger_kinds.make(self.trigger_settings)
        restart_on = tuple(self.restart_on) if self.timed else ()
        if self.triggers or restart_on:
            self.root = Supervisor(self.machine, self.triggers, restart_on=restart_on, backoff=self.backoff,
                                   before_restart=self._next_round)
        else:
            self.root = self.machine
        self.introspection = None
        try:
            from smart_brain.statemachine.introspection import IntrospectionServer
            self.introspection = IntrospectionServer('~', self.root, '/' + self.name.upper()).start()
        except ImportError as e:  # messages not built: run without the viewer topics
            rospy.logwarn('brain: no introspection (%s)', e)
        self.runner = Runner('strategy-' + self.name)
        self.started = False
        self.stopped = False

    def _next_round(self, outcome):
        if self.stopped:
            return False
        again = self.next_round(outcome) is not False
        if again:
            rospy.logwarn('brain: strategy %s: its machine ended %s; it plays on', self.name, outcome)
        return again

    def execute(self):
        if self.stopped:
            return False
        if not self.started:
            self.started = True
            self.runner.start(self.root, self.machine.userdata)
            return True
        if self.runner.is_running():
            return True
        if self.runner.error is not None:
            rospy.logerr('brain: strategy %s failed: %s', self.name, self.runner.error)
        else:
            rospy.loginfo('brain: strategy %s ended: %s', self.name, self.runner.outcome)
        return False

    @property
    def outcome(self):
        return self.runner.outcome

    def stop(self, timeout=3.0):
        self.stopped = True
        if getattr(self, 'runner', None) is not None and self.runner.is_running():
            self.runner.preempt()
            if not self.runner.wait(timeout):
                rospy.logerr('brain: strategy %s did not stop within %.1f s', self.name, timeout)

    def finalize(self):
        self.stop()
        if getattr(self, 'introspection', None) is not None:
            self.introspection.stop()
