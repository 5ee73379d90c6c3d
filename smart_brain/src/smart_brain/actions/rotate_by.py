"""rotate_by: turn in place by a relative angle [rad], from odometry (/hal/driver/rotate_by)."""
from smart_brain.actions import register_action
from smart_brain.actions.driver_state import DriverState


@register_action('rotate_by')
def rotate_by(angle, tolerance=0.0, max_speed=0.0, timeout=0.0, exec_timeout=None):
    from hal_nodes.msg import RotateByAction, RotateByGoal
    goal = RotateByGoal(angle=float(angle), tolerance=tolerance, max_speed=max_speed, timeout=timeout)
    return DriverState('rotate_by', RotateByAction, goal=goal, exec_timeout=exec_timeout)
