"""hand: open, close or lift the 2009 robot's column gripper (/hal/hand, hal_nodes/HandAction).
The state keeps the action's last result (`result.holding`: what the hand's sensor says it holds)."""
from smart_brain.actions import register_action
from smart_brain.statemachine import ActionState

HAND_ACTION = '/hal/hand'


class HandState(ActionState):
    def __init__(self, goal, exec_timeout, action):
        from hal_nodes.msg import HandAction
        ActionState.__init__(self, action, HandAction, goal=goal, exec_timeout=exec_timeout, result_cb=self._keep)
        self.result = None

    def _keep(self, ud, status, result):
        self.result = result
        return None if result is None or result.success or status != 3 else 'aborted'


@register_action('hand')
def hand(command, height=0.0, exec_timeout=10.0, action=HAND_ACTION):
    from hal_nodes.msg import HandGoal
    codes = {'open': HandGoal.OPEN, 'close': HandGoal.CLOSE, 'lift': HandGoal.LIFT}
    if command not in codes:
        raise TypeError("hand command '%s'; allowed values: %s" % (command, ', '.join(codes)))
    return HandState(HandGoal(command=codes[command], height=float(height)), exec_timeout, action)
