"""wait: do nothing for `duration` seconds (monotonic), preemptible."""
from smart_brain.actions import register_action
from smart_brain.statemachine import WaitState


@register_action('wait')
def wait(duration):
    return WaitState(float(duration))
