"""Idle time of a match: the stretches with no HAL action goal active (the driver's, the hand's)
and a zero commanded speed, between the start signal and the match end. One definition for the
match report, the match runner and the tests.

A robot that stands idle while time remains scores nothing: no idle stretch may last longer
than IDLE_LIMIT while more than IDLE_LIMIT of the match remain.
"""

IDLE_LIMIT = 10.0   # [s]
STILL = 1e-3        # [m/s, rad/s] a commanded speed below this is zero


def idle_stretches(goals, commands, start, end):
    """[(t0, t1)] idle between `start` and `end`.

    goals: [(t_sent, t_end)] of the HAL action goals (t_end None: still running at the end);
    commands: [(t, v, w)] the commanded speeds (/hal/drive/cmd_vel), in time order."""
    if start is None or end is None or end <= start:
        return []
    cuts = {start, end}
    for t0, t1 in goals:
        cuts.update(t for t in (t0, t1) if t is not None and start < t < end)
    cuts.update(t for t, _, _ in commands if start < t < end)
    cuts = sorted(cuts)
    stretches = []
    moving_cmd = False
    ci = 0
    for a, b in zip(cuts, cuts[1:]):
        while ci < len(commands) and commands[ci][0] <= a:
            moving_cmd = abs(commands[ci][1]) > STILL or abs(commands[ci][2]) > STILL
            ci += 1
        busy = moving_cmd or any(t0 <= a and (t1 is None or a < t1) for t0, t1 in goals)
        if busy:
            continue
        if stretches and stretches[-1][1] == a:
            stretches[-1] = (stretches[-1][0], b)
        else:
            stretches.append((a, b))
    return stretches


def too_long(stretches, end, limit=IDLE_LIMIT):
    """The stretches idle for longer than `limit` while more than `limit` of the match remained:
    [(t0, seconds idle before the last `limit` of the match)]."""
    out = []
    for t0, t1 in stretches:
        idle = min(t1, end - limit) - t0
        if idle > limit:
            out.append((t0, idle))
    return out
