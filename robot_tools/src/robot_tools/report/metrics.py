"""Figures computed from what a Match read, for the report's summary and the match rows: the
localization error against the truth (errors_against_truth), repeated log lines counted together,
a driver goal's target in words."""
import math
import re

from robot_core.geometry import wrap_angle


def errors_against_truth(estimate, truth):
    """[(t, position error [m], heading error [rad])], truth interpolated at each estimate."""
    out = []
    if len(truth) < 2:
        return out
    j = 0
    for t, x, y, a in estimate:
        while j + 1 < len(truth) and truth[j + 1][0] < t:
            j += 1
        if j + 1 >= len(truth) or t < truth[0][0]:
            continue
        (t0, x0, y0, a0), (t1, x1, y1, a1) = truth[j], truth[j + 1]
        f = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
        tx, ty = x0 + f * (x1 - x0), y0 + f * (y1 - y0)
        ta = a0 + f * wrap_angle(a1 - a0)
        out.append((t, math.hypot(x - tx, y - ty), abs(wrap_angle(a - ta))))
    return out


def is_brain_or_driver(node, text):
    return 'brain' in node or text.startswith('brain:') or text.startswith('driver:')


def counted(lines):
    """['3x text (first at 12.3 s)'] of [(t, text)], in order of first appearance; lines that
    differ only in their numbers count together (the first one is shown)."""
    groups = {}
    for t, text in lines:
        key = re.sub(r'-?\d+(\.\d+)?', '#', text)
        if key in groups:
            groups[key][1] += 1
            groups[key][3] = groups[key][3] or text != groups[key][2]
        else:
            groups[key] = [t, 1, text, False]
    return ['%dx %s (%sfirst at %.1f s)' % (n, text, 'and similar; ' if similar else '', t) if n > 1
            else '%s (at %.1f s)' % (text, t) for t, n, text, similar in sorted(groups.values(), key=lambda g: g[0])]


def goal_target(g):
    """A short text of what a driver goal asked for."""
    goal = g['goal']
    if g['action'] == 'goto':
        return 'to (%.2f, %.2f, %.0f deg)' % (goal.x, goal.y, math.degrees(goal.angle))
    if g['action'] == 'go_straight':
        return '%s %.2f m' % ('back' if goal.backwards else 'ahead', goal.distance)
    if g['action'] == 'rotate_by':
        return 'by %.0f deg' % math.degrees(goal.angle)
    if g['action'] == 'follow_path':
        cps = list(getattr(goal, 'checkpoints', []))
        last = cps[-1] if cps else None
        where = ''
        if last is not None:
            p = getattr(last, 'pose', last)
            if hasattr(p, 'x'):
                where = ' to (%.2f, %.2f)' % (p.x, p.y)
            elif hasattr(p, 'position'):
                where = ' to (%.2f, %.2f)' % (p.position.x, p.position.y)
        return '%d checkpoint(s)%s' % (len(cps), where)
    return ''
