"""ElementTracker: where the game elements of some kinds are, believed from what the robot senses
rather than from where the config put them at the start.

Each element starts at its configured position, believed but not seen. Each camera detection
moves the nearest tracked element within `gate` there (seen, at that time); a detection matching
none adds an element. An element the camera should see (in `view` of the robot: between
view_min and view_max ahead, within view_half_angle of the heading) but has not seen while in
view for `forget_after` seconds is gone (pushed away, taken): it is dropped. An element the hand
closed on and did not hold is dropped too (it is not where it was believed). Elements lying in a
scoring zone of ours are never offered (built: left alone).
"""
import math

from robot_core.geometry import wrap_angle


class Element(object):
    __slots__ = ('x', 'y', 'seen_at', 'unseen_in_view')

    def __init__(self, x, y, seen_at=None):
        self.x, self.y = float(x), float(y)
        self.seen_at = seen_at        # time of the last detection; None: the config's word only
        self.unseen_in_view = 0.0     # [s] in view without a detection since the last one

    def __repr__(self):
        return 'Element(%.3f, %.3f%s)' % (self.x, self.y, '' if self.seen_at is None else ', seen %.1f' % self.seen_at)


class ElementTracker(object):
    def __init__(self, configured, gate=0.12, forget_after=1.0, view=(0.4, 1.3, 0.4), table=(3.0, 2.1),
                 margin=0.05, keep_out=()):
        """`configured`: [(x, y)] start positions; `view`: (view_min, view_max, view_half_angle) of
        the camera from the robot's centre [m, m, rad]; `table`: (length, width); detections closer
        than `margin` to a border are none; `keep_out`: [(x0, y0, x1, y1)] zones whose elements
        are not offered (ours, built)."""
        self.elements = [Element(x, y) for x, y in configured]
        self.gate = float(gate)
        self.forget_after = float(forget_after)
        self.view_min, self.view_max, self.view_half_angle = [float(v) for v in view]
        self.table = table
        self.margin = float(margin)
        self.keep_out = [tuple(r) for r in keep_out]
        self._last = None   # time of the last update

    def in_view(self, pose, x, y):
        d = math.hypot(x - pose[0], y - pose[1])
        if not self.view_min <= d <= self.view_max:
            return False
        bearing = math.atan2(y - pose[1], x - pose[0]) - pose[2]
        return abs(wrap_angle(bearing)) <= self.view_half_angle

    def update(self, now, pose, detections):
        """One camera frame at `now`, the robot at `pose` (x, y, yaw), `detections` [(x, y)] of the
        tracked kinds."""
        dt = 0.0 if self._last is None else max(0.0, now - self._last)
        self._last = now
        matched = set()
        for x, y in detections:
            if not (self.margin <= x <= self.table[0] - self.margin and self.margin <= y <= self.table[1] - self.margin):
                continue
            best, best_d = None, self.gate
            for e in self.elements:
                d = math.hypot(e.x - x, e.y - y)
                if id(e) not in matched and d <= best_d:
                    best, best_d = e, d
            if best is None:
                best = Element(x, y)
                self.elements.append(best)
            best.x, best.y, best.seen_at, best.unseen_in_view = x, y, now, 0.0
            matched.add(id(best))
        if pose is None:
            return
        for e in list(self.elements):
            if id(e) in matched or not self.in_view(pose, e.x, e.y):
                continue
            e.unseen_in_view += dt
            if e.unseen_in_view >= self.forget_after:
                self.elements.remove(e)

    def not_there(self, x, y, radius=0.1):
        """The hand closed on nothing at (x, y): the element believed there is not there."""
        self.elements = [e for e in self.elements if math.hypot(e.x - x, e.y - y) > radius]

    def taken(self, x, y, radius=0.1):
        """The element at (x, y) is in the hand now."""
        self.not_there(x, y, radius)

    def in_keep_out(self, x, y, grow=0.04):
        return any(r[0] - grow <= x <= r[2] + grow and r[1] - grow <= y <= r[3] + grow for r in self.keep_out)

    def candidates(self):
        """The elements worth going for: [(x, y, seen_at)], not in a zone of ours."""
        return [(e.x, e.y, e.seen_at) for e in self.elements if not self.in_keep_out(e.x, e.y)]
