"""The same geometry (ticks per metre left, right, track width) fitted against the beacons instead of
the localization's estimate: the match cut at its stops into long stretches, each dead-reckoned
from the wheels alone and held against the beacon ranges measured meanwhile, with the damped
Gauss-Newton that fits the start poses, the geometry and the receiver's delay and offset together;
and the odometry's drift per metre against the beacons. Plain arrays, no ROS."""
import math

import numpy as np

from robot_tools.calibration.geometry import stops
from robot_tools.calibration.stats import Fit, robust_mask


class BeaconChunks(object):
    """The match cut at its stops into stretches of at least `length` seconds, each dead-reckoned
    from the wheels alone and held against every beacon range measured meanwhile: the beacons are
    the reference, independent of the odometry (the localization's estimate leans on the
    odometry it is meant to check, and at a stop it carries a centimetre of noise). Each stretch
    has its own start pose (x, y, theta), fitted with the geometry; a contact's slip spoils one
    stretch, not the match."""

    def __init__(self, t_odo, ticks_l, ticks_r, ranges, beacons, receiver, start_pose_at, length=10.0,
                 min_still=0.4):
        t_odo = np.asarray(t_odo, dtype=float)
        ticks_l, ticks_r = np.asarray(ticks_l, dtype=float), np.asarray(ticks_r, dtype=float)
        ranges = np.asarray(ranges, dtype=float).reshape(-1, 3)
        beacons = np.asarray(beacons, dtype=float)
        self.receiver = receiver
        cuts = [0.5 * (a + b) for a, b in stops(t_odo, ticks_l, ticks_r, min_still)]
        cuts = [t_odo[0]] + cuts + [t_odo[-1]]
        bounds, start = [], cuts[0]
        for c in cuts[1:]:
            if c - start >= length:
                bounds.append((start, c))
                start = c
        if not bounds:  # a short match: one stretch
            bounds = [(cuts[0], cuts[-1])]
        elif t_odo[-1] - start < length:  # a short tail joins the last stretch
            bounds[-1] = (bounds[-1][0], t_odo[-1])
        self.chunks = []
        for a, b in bounds:
            m = (t_odo >= a) & (t_odo <= b)
            r = ranges[(ranges[:, 0] >= a) & (ranges[:, 0] <= b)]
            moved = np.abs(np.diff(ticks_l[m])).sum() + np.abs(np.diff(ticks_r[m])).sum()
            if m.sum() < 10 or len(r) < 20 or moved <= 0:
                continue
            self.chunks.append(dict(t=t_odo[m], dl=np.diff(ticks_l[m]), dr=np.diff(ticks_r[m]), rt=r[:, 0],
                                    bx=beacons[r[:, 1].astype(int), 0], by=beacons[r[:, 1].astype(int), 1],
                                    range=r[:, 2], start=np.array(start_pose_at(a), dtype=float), span=(a, b)))
        self.count = len(self.chunks)

    def poses(self, k, tpm_l, tpm_r, track, start):
        """(t, x, y, theta) of stretch k dead-reckoned from `start` with these values."""
        c = self.chunks[k]
        sl, sr = c['dl'] / tpm_l, c['dr'] / tpm_r
        ds, dth = (sl + sr) / 2.0, (sr - sl) / track
        th = start[2] + np.concatenate([[0.0], np.cumsum(dth)])
        mid = th[:-1] + 0.5 * dth
        x = start[0] + np.concatenate([[0.0], np.cumsum(ds * np.cos(mid))])
        y = start[1] + np.concatenate([[0.0], np.cumsum(ds * np.sin(mid))])
        return c['t'], x, y, th

    def predicted(self, k, tpm_l, tpm_r, track, start, delay=0.0, scale=1.0, offset=0.0):
        """The ranges stretch k's beacons would measure from the dead-reckoned poses (the
        receiver's equation: scale x distance + offset; its clock `delay` behind the wheels')."""
        c = self.chunks[k]
        t, x, y, th = self.poses(k, tpm_l, tpm_r, track, start)
        tq = c['rt'] - delay
        px, py, pth = np.interp(tq, t, x), np.interp(tq, t, y), np.interp(tq, t, th)
        mx, my = self.receiver
        rx = px + np.cos(pth) * mx - np.sin(pth) * my
        ry = py + np.sin(pth) * mx + np.cos(pth) * my
        return scale * np.hypot(c['bx'] - rx, c['by'] - ry) + offset

    def travel(self, k):
        c = self.chunks[k]
        return float(np.sum(np.abs(c['dl'] + c['dr'])) / 2.0)


SHARED = 6  # tpm_l, tpm_r, track, delay, scale, offset; then x, y, theta per stretch


def _start(q, k):
    return q[SHARED + 3 * k:SHARED + 3 * k + 3]


def _beacon_residuals(q, chunks, use, sigma):
    tpm_l, tpm_r, track, delay, scale, offset = q[:SHARED]
    out = []
    for k in range(chunks.count):
        if use[k] is None:
            continue
        r = (chunks.chunks[k]['range'] - chunks.predicted(k, tpm_l, tpm_r, track, _start(q, k), delay, scale,
                                                          offset)) / sigma
        out.append(r[use[k]])
    return np.concatenate(out) if out else np.zeros(0)


def _jacobian(residuals, q, r, free):
    """Forward-difference Jacobian of `residuals` at q (r = residuals(q)); zero for held columns."""
    J = np.zeros((len(r), len(q)))
    for i in np.nonzero(free)[0]:
        h = 1e-6 * max(abs(q[i]), 1e-3)
        dq = q.copy()
        dq[i] += h
        J[:, i] = (residuals(dq) - r) / h
    return J


def _gauss_newton(residuals, q, free, iterations=30):
    """Gauss-Newton (Levenberg-damped) over the parameters `free` marks; (q, J at the end)."""
    q = np.array(q, dtype=float)
    lam = 1e-3
    r = residuals(q)
    J = None
    for _ in range(iterations):
        J = _jacobian(residuals, q, r, free)
        Jf = J[:, free]
        A = Jf.T @ Jf
        g = Jf.T @ r
        while True:
            step = np.linalg.solve(A + lam * np.diag(np.diag(A) + 1e-12), -g)
            trial = q.copy()
            trial[free] += step
            rt = residuals(trial)
            if rt @ rt < r @ r:
                q, r, lam = trial, rt, lam * 0.3
                break
            lam *= 10.0
            if lam > 1e8:
                return q, J
        if np.all(np.abs(step) <= 1e-9 * np.maximum(np.abs(q[free]), 1e-3)):
            break
    return q, J


def fit_geometry_beacons(chunks, tpm_l, tpm_r, track, sigma=0.01):
    """(ticks per metre left, right, track width) as Fits, the stretches kept (bool per stretch),
    the range residual RMS [m] and all the parameters: every stretch dead-reckoned with the values
    against its beacon ranges, the start poses, the geometry and the receiver's delay behind the
    wheels fitted together; ranges off by more than 4 MADs dropped (echoes), then stretches whose
    residual is more than 3 times the best one's (a contact's slip), and the fit redone. The
    receiver's offset is fitted with them (left out, it biased the ticks per metre by 0.08 % in
    the recovery runs); its scale is the HAL's, held: fitted too, it trades against the ticks
    per metre (a formal uncertainty 5 times larger, and 0.46 % off in one recovery run)."""
    n = chunks.count
    q = np.concatenate([[float(tpm_l), float(tpm_r), float(track), 0.0, 1.0, 0.0]] +
                       [c['start'] for c in chunks.chunks])
    use = [np.ones(len(c['range']), dtype=bool) for c in chunks.chunks]
    free = np.ones(len(q), dtype=bool)
    free[4] = False  # the scale: see above

    def residuals(v):
        return _beacon_residuals(v, chunks, use, sigma)
    for _ in range(5):
        q, _ = _gauss_newton(residuals, q, free)
        new_use, rms = [], []
        for k in range(n):
            if use[k] is None:
                new_use.append(None)
                rms.append(np.nan)
                continue
            r = chunks.chunks[k]['range'] - chunks.predicted(k, *q[:3], _start(q, k), *q[3:SHARED])
            new_use.append(robust_mask(r))
            rms.append(float(np.sqrt(np.mean(r[new_use[-1]] ** 2))))
        floor = np.nanmin(rms)  # the best stretch: the beacons' own noise
        for k in range(n):
            if new_use[k] is not None and rms[k] > 3.0 * floor:
                new_use[k] = None
        changed = any((a is None) != (b is None) or (a is not None and not np.array_equal(a, b))
                      for a, b in zip(use, new_use))
        use = new_use
        for k in range(n):  # a dropped stretch's start pose is no longer fitted
            free[SHARED + 3 * k:SHARED + 3 * k + 3] = use[k] is not None
        if not changed:
            break
    r = residuals(q)
    s2 = float(r @ r) / max(1, len(r) - int(free.sum()))
    J = _jacobian(residuals, q, r, free)
    try:
        cov = np.linalg.inv(J[:, free].T @ J[:, free]) * s2
    except np.linalg.LinAlgError:
        cov = np.full((int(free.sum()), int(free.sum())), np.nan)
    fits = tuple(Fit(q[i], math.sqrt(max(cov[i, i], 0.0))) for i in range(3))
    kept = np.array([u is not None for u in use])
    return fits, kept, math.sqrt(s2) * sigma, q


def beacon_drift(chunks, tpm_l, tpm_r, track, scale=1.0, offset=0.0, kept=None, sigma=0.01):
    """[mm per m] the odometry with these values against the beacons: each stretch's start pose
    fitted to its ranges with the rest held, then the RMS range residual over the stretch per
    metre it travelled (the median over the stretches; the beacons' own noise sets its floor)."""
    out = []
    for k in range(chunks.count):
        if kept is not None and not kept[k]:
            continue
        use = [None] * chunks.count
        use[k] = np.ones(len(chunks.chunks[k]['range']), dtype=bool)
        q = np.concatenate([[float(tpm_l), float(tpm_r), float(track), 0.0, scale, offset]] +
                           [c['start'] for c in chunks.chunks])
        free = np.zeros(len(q), dtype=bool)
        free[SHARED + 3 * k:SHARED + 3 * k + 3] = True
        q, _ = _gauss_newton(lambda v: _beacon_residuals(v, chunks, use, sigma), q, free)
        r = chunks.chunks[k]['range'] - chunks.predicted(k, tpm_l, tpm_r, track, _start(q, k), 0.0, scale, offset)
        r = r[robust_mask(r)]
        travel = chunks.travel(k) / ((tpm_l + tpm_r) / 2.0)
        if travel > 0.2:
            out.append(1000.0 * float(np.sqrt(np.mean(r ** 2))) / travel)
    return float(np.median(out)) if out else float('nan')
