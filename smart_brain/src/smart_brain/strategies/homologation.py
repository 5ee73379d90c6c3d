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

    def build(self):
        return build_sequence(self.param('steps', []), '~homologation/steps',
                              default_attempts=int(self.param('attempts', 2)))
