"""hand: open, close or lift the 2009 robot's column gripper (/hal/hand, hal_nodes/HandAction)."""
from smart_brain.actions import register_action
from smart_brain.statemachine import ActionState

HAND_ACTION = '/hal/hand'


@register_action('hand')
def hand(command, height=0.0, exec_timeout=10.0, action=HAND_ACTION):
    from hal_nodes.msg import HandAction, HandGoal
    codes = {'open': HandGoal.OPEN, 'close': HandGoal.CLOSE, 'lift': HandGoal.LIFT}
    if command not in codes:
        raise TypeError("hand command '%s'; allowed values: %s" % (command, ', '.join(codes)))
    goal = HandGoal(command=codes[command], height=float(height))
    return ActionState(action, HandAction, goal=goal, exec_timeout=exec_timeout,
                       result_cb=lambda ud, status, result: None if result is None or result.success or status != 3
                       else 'aborted')
