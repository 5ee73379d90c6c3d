"""The idle strategy: waits for the start, does nothing, ends at the match end.

Available to every robot (it needs no device): the baseline a change is judged against (a
strategy that scores no more than idle scores nothing of its own), and a safe choice for a
match where the robot must not move.
"""
from smart_brain.strategy import Strategy, register


@register
class IdleStrategy(Strategy):
    name = 'idle'
    description = 'every robot: waits for the start, does nothing, ends at the match end (the baseline)'
    required_devices = ()
    timed = True

    def execute(self):
        return True  # nothing to do until the match timer stops the brain
