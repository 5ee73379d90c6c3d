"""Strategies used by the brain rostests only (loaded with the brain's ~strategy_modules):
a three-leg drive over actionlib's own TestAction served by the test, so the match timer,
triggers, history and the match-end guard are tested against a real action server."""
from actionlib.msg import TestAction, TestGoal

from smart_brain.machine_strategy import MachineStrategy
from smart_brain.statemachine import ActionState, StateMachine
from smart_brain.strategy import register

LONG_ACTION = '/test/long_action'


@register
class BrainTestDrive(MachineStrategy):
    name = 'brain_test_drive'
    description = 'test: three legs over /test/long_action (TestAction goal = leg number)'
    required_topics = (LONG_ACTION + '/status',)

    def build(self):
        sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
        for leg in (1, 2, 3):
            nxt = 'LEG_%d' % (leg + 1) if leg < 3 else 'succeeded'
            sm.add('LEG_%d' % leg, ActionState(LONG_ACTION, TestAction, goal=TestGoal(goal=leg), server_wait_timeout=5.0),
                   transitions={'succeeded': nxt, 'aborted': 'aborted', 'preempted': 'preempted'})
        return sm


@register
class BrainBenchIdle(MachineStrategy):
    """For scripts/bench/brain.sh: a long preemptible state under the configured triggers."""
    name = 'brain_bench_idle'
    description = 'bench: one long preemptible state, triggers around it'

    def build(self):
        from smart_brain.statemachine import WaitState
        sm = StateMachine(outcomes=['succeeded', 'aborted', 'preempted'])
        sm.add('IDLE', WaitState(1e6), transitions={'succeeded': 'succeeded', 'preempted': 'preempted'})
        return sm
