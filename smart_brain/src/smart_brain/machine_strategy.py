"""MachineStrategy: a strategy written as a state machine, run beside the triggers.

Subclasses implement build() -> StateMachine. initialize() wraps it in a Supervisor with
the triggers configured under the brain's ~triggers (opponent ahead, stuck, localization
lost, ...; a strategy may narrow them with `trigger_kinds`), publishes it for
smach_viewer under /brain/smach/... and execute() runs it on one persistent thread; stop()
preempts it (goals cancelled) and waits for it.
"""
import rospy

from smart_brain import triggers as trigger_kinds
from smart_brain.statemachine import Runner, Supervisor
from smart_brain.strategy import Strategy


class MachineStrategy(Strategy):
    #: trigger kinds this strategy accepts from ~triggers (None: every configured one)
    trigger_kinds = None

    def build(self):
        raise NotImplementedError

    def param(self, key, default=None):
        """~<strategy name>/<key> of the brain node (the strategy's own config block)."""
        return rospy.get_param('~%s/%s' % (self.name, key), default)

    def initialize(self):
        self.machine = self.build()
        self.machine.check_consistency()
        config = rospy.get_param('~triggers', {})
        if self.trigger_kinds is not None:
            config = {k: v for k, v in config.items() if k in self.trigger_kinds}
        self.triggers = trigger_kinds.build(config)
        self.root = Supervisor(self.machine, self.triggers) if self.triggers else self.machine
        self.introspection = None
        try:
            from smart_brain.statemachine.introspection import IntrospectionServer
            self.introspection = IntrospectionServer('~', self.root, '/' + self.name.upper()).start()
        except ImportError as e:  # messages not built: run without the viewer topics
            rospy.logwarn('brain: no introspection (%s)', e)
        self.runner = Runner('strategy-' + self.name)
        self.started = False
        self.stopped = False

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
