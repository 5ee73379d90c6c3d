"""TaskCost: which task next, by a cost a team tunes (the strategy's `cost` block):

    cost = travel_weight * seconds it needs
         + contested_weight * how contested its place is (recent meetings near it, up to 3)
         - points_weight * the points it brings

A task needs (the strategy's estimate) its travel at `speed` plus its handling time; one that
cannot finish in the time left (less `reserve`) is not offered, so the last seconds go to a task
that can finish. Contested: the opponent was met (a trigger, a blocked goal) within
`contested_radius` of the place in the last `contested_memory` seconds, or the place lies on the
opponent's half of the table (weight `their_half`).
"""
import math

MAX_CONTEST = 3  # meetings counted near a place


class TaskCost(object):
    DEFAULTS = dict(travel_weight=1.0, contested_weight=8.0, points_weight=1.0, speed=0.35, reserve=2.0,
                    contested_radius=0.4, contested_memory=20.0, their_half=0.5)

    def __init__(self, params=None, table=(3.0, 2.1), our_side=None):
        p = dict(self.DEFAULTS)
        for k, v in (params or {}).items():
            if k not in p:
                raise ValueError("cost/%s: unknown; allowed: %s" % (k, ', '.join(sorted(p))))
            p[k] = float(v)
        self.p = p
        self.table = table
        self.our_side = our_side  # 'left' (x < length/2), 'right', or None: not known yet (no half is theirs)
        self.meetings = []        # (time, x, y) where the opponent was met

    def met_opponent(self, now, x, y):
        self.meetings.append((now, x, y))

    def contested(self, now, x, y):
        """How contested (x, y) is: the recent meetings with the opponent near it (each one more:
        a place it blocked twice weighs twice), else their half's share."""
        self.meetings = [m for m in self.meetings if now - m[0] <= self.p['contested_memory']]
        near = sum(1 for _, mx, my in self.meetings if math.hypot(mx - x, my - y) <= self.p['contested_radius'])
        if near:
            return float(min(near, MAX_CONTEST))
        if self.our_side is None:
            return 0.0
        theirs = x > self.table[0] / 2.0 if self.our_side == 'left' else x < self.table[0] / 2.0
        return self.p['their_half'] if theirs else 0.0

    def seconds(self, path, handling):
        """Travel along `path` [(x, y), ...] at the strategy's speed, plus `handling` [s]."""
        length = sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(path, path[1:]))
        return length / self.p['speed'] + handling

    def fits(self, seconds, time_left):
        return time_left is None or seconds + self.p['reserve'] <= time_left

    def cost(self, now, seconds, place, points):
        return (self.p['travel_weight'] * seconds + self.p['contested_weight'] * self.contested(now, place[0], place[1])
                - self.p['points_weight'] * points)
