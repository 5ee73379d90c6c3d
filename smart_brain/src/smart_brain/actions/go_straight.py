"""go_straight: drive a distance along the current heading, from odometry (/hal/driver/go_straight)."""
from smart_brain.actions import register_action
from smart_brain.actions.driver_state import DriverState


@register_action('go_straight')
def go_straight(distance, backwards=False, tolerance=0.0, max_speed=0.0, timeout=0.0, exec_timeout=None):
    from hal_nodes.msg import GoStraightAction, GoStraightGoal
    goal = GoStraightGoal(distance=abs(float(distance)), backwards=bool(backwards) or distance < 0,
                          tolerance=tolerance, max_speed=max_speed, timeout=timeout)
    return DriverState('go_straight', GoStraightAction, goal=goal, exec_timeout=exec_timeout)
