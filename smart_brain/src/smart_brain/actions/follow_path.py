"""follow_path: drive through checkpoints joined by Hermite curves (/hal/driver/follow_path),
from a list of (x, y) / (x, y, heading) or from the userdata key `points_key`."""
from smart_brain.actions import register_action
from smart_brain.actions.driver_state import DriverState


def checkpoints(points):
    from hal_nodes.msg import Checkpoint
    out = []
    for p in points:
        cp = Checkpoint(x=float(p[0]), y=float(p[1]))
        if len(p) > 2 and p[2] is not None:
            cp.has_heading, cp.heading = True, float(p[2])
        out.append(cp)
    return out


@register_action('follow_path')
def follow_path(points=None, points_key=None, tolerance=0.0, max_speed=0.0, timeout=0.0, exec_timeout=None):
    from hal_nodes.msg import FollowPathAction, FollowPathGoal

    def goal_cb(ud, _goal):
        pts = ud[points_key] if points_key else points
        return FollowPathGoal(checkpoints=checkpoints(pts), tolerance=tolerance, max_speed=max_speed, timeout=timeout)
    if points is None and points_key is None:
        raise TypeError('follow_path needs points or points_key')
    return DriverState('follow_path', FollowPathAction, goal_cb=goal_cb,
                       input_keys=[points_key] if points_key else (), exec_timeout=exec_timeout)
