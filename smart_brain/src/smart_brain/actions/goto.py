"""goto: drive to an absolute pose in `map` (/hal/driver/goto), from arguments or from the
userdata key `pose_key` holding (x, y, angle)."""
from smart_brain.actions import register_action
from smart_brain.actions.driver_state import DriverState


@register_action('goto')
def goto(x=None, y=None, angle=0.0, pose_key=None, position_tolerance=0.0, angle_tolerance=0.0, max_speed=0.0,
         allow_reverse=False, timeout=0.0, exec_timeout=None):
    from hal_nodes.msg import GotoAction, GotoGoal

    def goal_cb(ud, _goal):
        px, py, pa = ud[pose_key] if pose_key else (x, y, angle)
        return GotoGoal(x=float(px), y=float(py), angle=float(pa), position_tolerance=position_tolerance,
                        angle_tolerance=angle_tolerance, max_speed=max_speed, allow_reverse=allow_reverse,
                        timeout=timeout)
    if pose_key is None and (x is None or y is None):
        raise TypeError('goto needs x and y, or pose_key')
    return DriverState('goto', GotoAction, goal_cb=goal_cb, input_keys=[pose_key] if pose_key else (),
                       exec_timeout=exec_timeout)
