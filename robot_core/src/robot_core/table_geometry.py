"""The playing table as the sensors see it: the twin of include/robot_core/table_geometry.h,
checked against the same vectors (test/table_geometry_vectors.yaml).

The inside of [0, length] x [0, width] (x along the length, REP-103 map frame), fixed blocks
(axis-aligned rectangles (x0, y0, x1, y1)) and, per query, circles (x, y, r) that move.
"""
import math

_INF = float('inf')


def _ray_rect(x, y, c, s, rect):
    """Entry distance of the ray into rect (the ray starts outside it), inf if it misses."""
    t0, t1 = 0.0, _INF
    for o, d, lo, hi in ((x, c, rect[0], rect[2]), (y, s, rect[1], rect[3])):
        if abs(d) < 1e-12:
            if o < lo or o > hi:
                return _INF
        else:
            a, b = (lo - o) / d, (hi - o) / d
            if a > b:
                a, b = b, a
            t0, t1 = max(t0, a), min(t1, b)
    return t0 if t0 <= t1 else _INF


def _ray_circle(x, y, c, s, circle):
    """Entry distance of the ray into the circle: 0 when it starts inside, inf when it misses."""
    ox, oy = circle[0] - x, circle[1] - y
    along = ox * c + oy * s
    d2 = ox * ox + oy * oy - along * along
    r2 = circle[2] * circle[2]
    if d2 > r2:
        return _INF
    half_chord = math.sqrt(r2 - d2)
    t = along - half_chord
    if t >= 0.0:
        return t
    return _INF if along + half_chord < 0.0 else 0.0


class TableGeometry(object):
    def __init__(self, length, width, blocks=()):
        self.length, self.width = float(length), float(width)
        if not (self.length > 0.0 and self.width > 0.0):
            raise ValueError('table: length and width must be > 0')
        self.blocks = [tuple(float(v) for v in b) for b in blocks]
        for b in self.blocks:
            if not (b[2] > b[0] and b[3] > b[1]):
                raise ValueError('table: blocks need x0 < x1 and y0 < y1')

    def open(self, x, y):
        """Whether (x, y) is strictly inside the table and outside every block."""
        if not (0.0 < x < self.length and 0.0 < y < self.width):
            return False
        return not any(b[0] < x < b[2] and b[1] < y < b[3] for b in self.blocks)

    def ray_range(self, x, y, angle, circles=()):
        """Distance along `angle` to the first border, block or circle; 0 when (x, y) is not open
        or inside a circle. Always finite: the caller applies its sensor's max range."""
        if not self.open(x, y):
            return 0.0
        c, s = math.cos(angle), math.sin(angle)
        t = _INF
        if c > 1e-12:
            t = min(t, (self.length - x) / c)
        if c < -1e-12:
            t = min(t, -x / c)
        if s > 1e-12:
            t = min(t, (self.width - y) / s)
        if s < -1e-12:
            t = min(t, -y / s)
        for b in self.blocks:
            t = min(t, _ray_rect(x, y, c, s, b))
        for k in circles:
            t = min(t, _ray_circle(x, y, c, s, k))
        return t

    def cone_range(self, x, y, angle, beam_width, circles=()):
        """Distance to the nearest border, block or circle point in the cone of full width
        `beam_width` around `angle` (a sonar's first echo). Exact, as the C++ one."""
        half = 0.5 * beam_width
        if not half > 1e-9:
            return self.ray_range(x, y, angle, circles)
        best = self.ray_range(x, y, angle - half, circles)
        if best <= 0.0:
            return best
        best = min(best, self.ray_range(x, y, angle + half, circles))
        ux, uy, cos_half = math.cos(angle), math.sin(angle), math.cos(half)

        def in_cone(dx, dy, d):
            return dx * ux + dy * uy >= d * cos_half

        candidates = []
        for x0, y0, x1, y1 in [(0.0, 0.0, self.length, self.width)] + self.blocks:
            fx, fy = min(max(x, x0), x1), min(max(y, y0), y1)
            candidates += [(fx, y0), (fx, y1), (x0, fy), (x1, fy), (x0, y0), (x1, y0), (x0, y1), (x1, y1)]
        for px, py in candidates:
            dx, dy = px - x, py - y
            d = math.hypot(dx, dy)
            if d < best and in_cone(dx, dy, d):
                best = d
        for cx, cy, r in circles:
            dx, dy = cx - x, cy - y
            d = math.hypot(dx, dy)
            if d - r < best and in_cone(dx, dy, d):
                best = d - r
        return best

    def distance_to_edge(self, x, y):
        """Distance to the nearest border or block edge; 0 when (x, y) is not open."""
        if not self.open(x, y):
            return 0.0
        d = min(x, self.length - x, y, self.width - y)
        for x0, y0, x1, y1 in self.blocks:
            d = min(d, math.hypot(max(x0 - x, 0.0, x - x1), max(y0 - y, 0.0, y - y1)))
        return d
