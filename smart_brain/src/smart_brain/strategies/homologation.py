"""Homologation: leave the start zone, score one point the safest way, avoid the opponent.

The route is the robot's config (~homologation/steps: registered actions with arguments,
e.g. go_straight out of the start zone, goto the scoring place, hand open), each step
retried once if the driver aborts it. The opponent_ahead trigger (~triggers) stops the
robot and resumes the interrupted step when the way is clear.
"""
from smart_brain.machine_strategy import MachineStrategy
from smart_brain.steps import build_sequence
from smart_brain.strategy import register


@register
class HomologationStrategy(MachineStrategy):
    name = 'homologation'
    description = 'leave the start zone, score one point with the highest certainty, avoid the opponent'
    required_devices = ('driver',)

    parameters = {
        'steps': 'the route: [{action: NAME, ..its arguments, attempts, label, on_abort}, ..] (smart_brain/actions)',
        'attempts': 'tries of each step whose driver goal aborts (a step may set its own)',
    }

    def read_config(self, brain, table):
        MachineStrategy.read_config(self, brain, table)
        self.steps = self.params('steps', [])
        self.attempts = int(self.params('attempts', 2))

    def build(self):
        return build_sequence(self.steps, '~homologation/steps', default_attempts=self.attempts)
