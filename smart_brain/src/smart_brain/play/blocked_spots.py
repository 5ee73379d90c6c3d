"""BlockedSpots: where the robot's goals ended BLOCKED. Two of them from about the same spot
(within `radius`, within `memory` seconds) mean the way from there is shut: move away before
trying again, to a point `distance` away, towards the middle of the table."""
import math


class BlockedSpots(object):
    def __init__(self, radius=0.15, memory=30.0, distance=0.35, table=(3.0, 2.1), margin=0.3):
        self.radius, self.memory, self.distance = float(radius), float(memory), float(distance)
        self.table, self.margin = table, float(margin)
        self.spots = []  # (time, x, y)

    def note(self, now, pose):
        if pose is not None:
            self.spots.append((now, pose[0], pose[1]))

    def _recent(self, now):
        self.spots = [s for s in self.spots if now - s[0] <= self.memory]
        return self.spots

    def must_move_away(self, now, pose):
        """Twice blocked from about where the robot stands."""
        if pose is None:
            return False
        near = [s for s in self._recent(now) if math.hypot(s[1] - pose[0], s[2] - pose[1]) <= self.radius]
        return len(near) >= 2

    def away_from(self, pose):
        """(x, y, heading) `distance` from `pose` towards the middle of the table, kept `margin` off
        the borders, facing the way it goes."""
        cx, cy = self.table[0] / 2.0, self.table[1] / 2.0
        d = math.hypot(cx - pose[0], cy - pose[1])
        if d < 1e-6:
            ux, uy = -math.cos(pose[2]), -math.sin(pose[2])  # in the middle already: back off
        else:
            ux, uy = (cx - pose[0]) / d, (cy - pose[1]) / d
        x = min(max(pose[0] + ux * self.distance, self.margin), self.table[0] - self.margin)
        y = min(max(pose[1] + uy * self.distance, self.margin), self.table[1] - self.margin)
        return x, y, math.atan2(y - pose[1], x - pose[0])

    def moved_away(self, pose):
        """Forget the spots near `pose` (the robot left them)."""
        self.spots = [s for s in self.spots if math.hypot(s[1] - pose[0], s[2] - pose[1]) > self.radius]
