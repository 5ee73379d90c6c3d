"""The driven wheels' ticks per metre (left, right) and the track width that make the odometry
agree with the localization's estimate, segment by segment (UMBmark's aim, from a whole match
instead of a square path): the match cut into segments (one second each, or stop to stop), the
Gauss-Newton fit, and the odometry's drift per metre before and after. Plain arrays, no ROS."""
import math

import numpy as np

from robot_tools.calibration.stats import Fit, robust_mask


class Segments(object):
    """The match cut into segments of about `length` seconds of the reference (the estimate): for
    each, the wheels' tick increments step by step (the encoders' own rate) and where the reference
    says the robot went, in the segment's start frame. Segments where nothing moved are left out."""

    def __init__(self, t_odo, ticks_l, ticks_r, t_ref, x, y, theta, length=1.0, min_move=0.01):
        t_odo = np.asarray(t_odo, dtype=float)
        t_ref = np.asarray(t_ref, dtype=float)
        theta = np.unwrap(np.asarray(theta, dtype=float))
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        self.dl, self.dr, self.seg, self.target, self.start = [], [], [], [], []
        i, k = 0, 0
        while True:
            j = int(np.searchsorted(t_ref, t_ref[i] + length)) if i < len(t_ref) else len(t_ref)
            if j >= len(t_ref):
                break
            inside = (t_odo >= t_ref[i]) & (t_odo <= t_ref[j])
            grid = np.concatenate([[t_ref[i]], t_odo[inside], [t_ref[j]]])
            gl, gr = np.interp(grid, t_odo, ticks_l), np.interp(grid, t_odo, ticks_r)
            c, s = math.cos(theta[i]), math.sin(theta[i])
            dx, dy = x[j] - x[i], y[j] - y[i]
            local = (c * dx + s * dy, -s * dx + c * dy, theta[j] - theta[i])
            moved = abs(gl[-1] - gl[0]) + abs(gr[-1] - gr[0]) > 0 and \
                (math.hypot(local[0], local[1]) > min_move or abs(local[2]) > 5 * min_move)
            if moved:
                self.dl.append(np.diff(gl))
                self.dr.append(np.diff(gr))
                self.seg.append(np.full(len(grid) - 1, k))
                self.target.append(local)
                self.start.append(t_ref[i])
                k += 1
            i = j
        self.count = k
        if k:
            self.dl, self.dr = np.concatenate(self.dl), np.concatenate(self.dr)
            self.seg = np.concatenate(self.seg)
            self.bounds = np.concatenate([[0], np.nonzero(np.diff(self.seg))[0] + 1])
        self.target = np.array(self.target).reshape(-1, 3)
        self.start = np.array(self.start)

    def integrate(self, tpm_l, tpm_r, track):
        """Each segment's (dx, dy, dtheta) in its start frame as the odometry with these values sees it."""
        sl, sr = self.dl / tpm_l, self.dr / tpm_r
        ds, dth = (sl + sr) / 2.0, (sr - sl) / track
        out = np.empty((self.count, 3))
        for k, (a, b) in enumerate(zip(self.bounds, list(self.bounds[1:]) + [len(ds)])):
            th = np.concatenate([[0.0], np.cumsum(dth[a:b])])
            mid = th[:-1] + 0.5 * dth[a:b]
            out[k] = (np.sum(ds[a:b] * np.cos(mid)), np.sum(ds[a:b] * np.sin(mid)), th[-1])
        return out

    def travel(self):
        return np.hypot(self.target[:, 0], self.target[:, 1])


def stops(t_odo, ticks_l, ticks_r, min_still=0.3, still_ticks=1):
    """[(start, end)] of the stretches the wheels stood still for at least `min_still` seconds
    (at most `still_ticks` counted meanwhile): where the reference is best (the localization has
    no motion to lag behind, and its estimate can be averaged)."""
    t = np.asarray(t_odo, dtype=float)
    out, start = [], None
    base_l = base_r = None
    for k in range(1, len(t)):
        if start is None:
            start, base_l, base_r = t[k - 1], ticks_l[k - 1], ticks_r[k - 1]
        if abs(ticks_l[k] - base_l) + abs(ticks_r[k] - base_r) > still_ticks:
            if t[k - 1] - start >= min_still:
                out.append((start, t[k - 1]))
            start = None
    if start is not None and t[-1] - start >= min_still:
        out.append((start, t[-1]))
    return out


def stop_to_stop(t_odo, ticks_l, ticks_r, t_ref, x, y, theta, min_still=0.4, settle=0.2):
    """Segments (as Segments) from the middle of one stop to the middle of the next, the
    reference there the average of its estimates over the stop after `settle` seconds: the
    localization's lag while moving (its measurements come a few milliseconds late) cancels out,
    and so does the wheels' slip, which speeding up and slowing down make in equal parts."""
    t_ref = np.asarray(t_ref, dtype=float)
    theta = np.unwrap(np.asarray(theta, dtype=float))
    points = []
    for a, b in stops(t_odo, ticks_l, ticks_r, min_still):
        m = (t_ref >= a + settle) & (t_ref <= b)  # once the estimate has settled on the stop
        if m.sum() >= 3:
            points.append((0.5 * (a + b), float(np.mean(np.asarray(x)[m])), float(np.mean(np.asarray(y)[m])),
                           float(np.mean(theta[m]))))
    if len(points) < 2:
        return Segments(t_odo, ticks_l, ticks_r, [0.0], [0.0], [0.0], [0.0])
    p = np.array(points)
    return Segments(t_odo, ticks_l, ticks_r, p[:, 0], p[:, 1], p[:, 2], p[:, 3], length=1e-9)


def _geometry_residuals(p, segs, mask, sigma_xy, sigma_th):
    got = segs.integrate(*p)[mask]
    want = segs.target[mask]
    return np.concatenate([(got[:, 0] - want[:, 0]) / sigma_xy, (got[:, 1] - want[:, 1]) / sigma_xy,
                           (got[:, 2] - want[:, 2]) / sigma_th])


def fit_geometry(segs, tpm_l, tpm_r, track, sigma_xy=0.004, sigma_th=0.012, iterations=20):
    """(ticks per metre left, right, track width) as Fits, the inlier mask and the residual RMS
    (in sigmas): each segment's odometry, integrated step by step, against where the reference
    says the robot went; Gauss-Newton from the config's values; segments off by more than 4 MADs
    (a wheel spinning, a contact) dropped and the fit redone."""
    mask = np.ones(segs.count, dtype=bool)
    p = np.array([float(tpm_l), float(tpm_r), float(track)])
    for _ in range(4):
        for _ in range(iterations):
            r = _geometry_residuals(p, segs, mask, sigma_xy, sigma_th)
            J = np.empty((len(r), 3))
            for k in range(3):
                h = 1e-6 * abs(p[k])
                q = p.copy()
                q[k] += h
                J[:, k] = (_geometry_residuals(q, segs, mask, sigma_xy, sigma_th) - r) / h
            step, *_ = np.linalg.lstsq(J, -r, rcond=None)
            p = p + step
            if np.all(np.abs(step) <= 1e-9 * np.abs(p)):
                break
        full = _geometry_residuals(p, segs, np.ones(segs.count, dtype=bool), sigma_xy, sigma_th).reshape(3, -1)
        new_mask = robust_mask(full[0]) & robust_mask(full[1]) & robust_mask(full[2])
        if np.array_equal(new_mask, mask):
            break
        mask = new_mask
    r = _geometry_residuals(p, segs, mask, sigma_xy, sigma_th)
    s2 = float(r @ r) / max(1, len(r) - 3)
    try:
        cov = np.linalg.inv(J.T @ J) * s2
    except np.linalg.LinAlgError:
        cov = np.full((3, 3), np.nan)
    fits = tuple(Fit(v, math.sqrt(max(cov[k, k], 0.0))) for k, v in enumerate(p))
    return fits, mask, math.sqrt(s2)


def odometry_drift(segs, tpm_l, tpm_r, track, mask=None):
    """[mm per m] how far the odometry ends from the reference per metre travelled, over the
    segments (the median: a contact in one segment does not decide it)."""
    got = segs.integrate(tpm_l, tpm_r, track)
    err = np.hypot(got[:, 0] - segs.target[:, 0], got[:, 1] - segs.target[:, 1])
    travel = segs.travel()
    ok = travel > 0.1
    if mask is not None:
        ok &= mask
    return 1000.0 * float(np.median(err[ok] / travel[ok])) if np.any(ok) else float('nan')
