"""The estimators of `make calibrate` (scripts/calibrate.py): each one fits what a recorded match
says about the robot, from plain arrays (robot_tools.calibration.signals reads them from a bag),
with an uncertainty. No ROS here: the tests feed them synthetic signals with a known answer.

  geometry      the driven wheels' ticks per metre (left, right) and the track width that make the
                odometry agree with the localization's estimate, segment by segment (UMBmark's
                aim, from a whole match instead of a square path)
  motor         per drive motor: the wheel speed at full PWM, the time constant and the dead band
                of a first-order motor, from the PWM commanded to the wheel speed the encoder saw
  slip          how much the driven wheels' travel exceeds the ground's, against their acceleration
  range_errors  a ranger's bias and noise against the table's borders at the estimated pose, and
                the beacons' range noise against the estimate
"""
import math

import numpy as np

TWO_PI = 2.0 * math.pi


class Fit(object):
    """A fitted value with its standard uncertainty (None when the data cannot tell)."""
    __slots__ = ('value', 'sigma')

    def __init__(self, value, sigma=None):
        self.value, self.sigma = float(value), (None if sigma is None else float(sigma))

    def __repr__(self):
        return '%.6g +- %s' % (self.value, '?' if self.sigma is None else '%.2g' % self.sigma)


def unwrap(raw, bits):
    """Counter readings that wrap modulo 2^bits as one unbounded count (int64)."""
    raw = np.asarray(raw, dtype=np.int64)
    span = np.int64(1) << np.int64(bits)
    d = np.diff(raw)
    d = (d + span // 2) % span - span // 2
    return np.concatenate([[raw[0]], raw[0] + np.cumsum(d)]) if len(raw) else raw


def robust_mask(residuals, k=4.0):
    """Inliers: within k scaled MADs of the median (all, when there is no spread)."""
    r = np.asarray(residuals, dtype=float)
    med = np.median(r)
    mad = 1.4826 * np.median(np.abs(r - med))
    if not mad > 0.0:
        return np.ones(len(r), dtype=bool)
    return np.abs(r - med) <= k * mad


# ---- geometry ------------------------------------------------------------------------------------

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
    moving = (np.abs(np.diff(ticks_l)) + np.abs(np.diff(ticks_r))) > 0
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


# ---- motor ---------------------------------------------------------------------------------------

def wheel_speed(t, ticks, ticks_per_rev, window=0.04):
    """(times, wheel speed [rad/s]) from encoder counts: differences over `window` seconds."""
    t = np.asarray(t, dtype=float)
    ticks = np.asarray(ticks, dtype=float)
    j = np.searchsorted(t, t + window)
    ok = j < len(t)
    i = np.nonzero(ok)[0]
    j = j[ok]
    dt = t[j] - t[i]
    w = (ticks[j] - ticks[i]) / dt * TWO_PI / ticks_per_rev
    return 0.5 * (t[i] + t[j]), w


def _motor_steps(t, u_of_t, max_speed, time_constant, dead_band, max_accel, dt, limit=np.inf):
    """Yields (index into t, wheel speed of every model) as the first-order motor runs (the
    simulator's robot_sim/src/world/motor_model.cpp, step for step)."""
    grid = np.arange(t[0], t[-1] + dt, dt)
    u = u_of_t(grid)
    w = np.zeros(np.broadcast(max_speed, time_constant, dead_band).shape)
    a = np.exp(-dt / time_constant)
    at = np.searchsorted(grid, t)  # the grid step each time of t falls on
    dw = max_accel * dt
    i = 0
    # (ufuncs, not np.clip: this loop runs every 2 ms of a match for every model, and np.clip's
    # argument checks cost several times the arithmetic)
    for k, uk in enumerate(u):
        mag = np.maximum(0.0, abs(uk) - dead_band) / (1.0 - dead_band)
        back = w / max_speed
        # the H-bridge's current limiter: the effective command stays within `limit` of the back-EMF
        target = (back + np.minimum(np.maximum(math.copysign(1.0, uk) * mag - back, -limit), limit)) * max_speed
        nxt = target + (w - target) * a
        w = np.minimum(np.maximum(nxt, w - dw), w + dw)
        while i < len(t) and at[i] <= k:
            yield i, w
            i += 1
    while i < len(t):
        yield i, w
        i += 1


def simulate_motor(t, u_of_t, max_speed, time_constant, dead_band, max_accel=np.inf, dt=0.002, limit=np.inf):
    """The first-order motor's wheel speed [rad/s] at times `t` for the command u(t) in -1..1
    (a function of time): below `dead_band` of full command it does not turn; above, the target
    speed grows from 0 to max_speed; the speed follows with `time_constant`, at most `max_accel`;
    the effective command stays within `limit` (current_limit / stall_current) of the back-EMF.
    max_speed, time_constant and dead_band may be arrays (one model per element)."""
    max_speed, time_constant, dead_band = (np.asarray(v, dtype=float) for v in (max_speed, time_constant, dead_band))
    out = np.empty((len(t),) + np.broadcast(max_speed, time_constant, dead_band).shape)
    for i, w in _motor_steps(np.asarray(t, dtype=float), u_of_t, max_speed, time_constant, dead_band, max_accel, dt,
                             limit):
        out[i] = w
    return out


def motor_rms(t, w_measured, u_of_t, max_speed, time_constant, dead_band, max_accel=np.inf, dt=0.002, limit=np.inf,
              use=None):
    """The RMS error [rad/s] of each model against the measured wheel speed (at the samples `use`
    marks, all by default), without keeping the runs."""
    max_speed, time_constant, dead_band = (np.asarray(v, dtype=float) for v in (max_speed, time_constant, dead_band))
    use = np.ones(len(t), dtype=bool) if use is None else np.asarray(use, dtype=bool)
    sse = np.zeros(np.broadcast(max_speed, time_constant, dead_band).shape)
    for i, w in _motor_steps(np.asarray(t, dtype=float), u_of_t, max_speed, time_constant, dead_band, max_accel, dt,
                             limit):
        if use[i]:
            sse += (w - w_measured[i]) ** 2
    return np.sqrt(sse / max(1, int(use.sum())))


MAX_LAG = 0.03  # [s] the longest dead time between a command's stamp and the wheel's answer the fit tries


def fit_motor(t_cmd, u, t_w, w, guess_speed, max_accel=np.inf, limit=np.inf):
    """(max_speed, time_constant, dead_band) as Fits and the RMS error [rad/s] of the fitted model,
    from the commands (t_cmd, u in -1..1, held until the next) and the measured wheel speed
    (t_w, w). A grid, refined twice around its best; a dead time before the command acts (the
    bus and the board: not the motor's, so not in the result), found for that best, and the grid
    again; then once more without the samples the best
    model misses by more than 4 spreads (the wheel held by a contact: the free motor model cannot
    know it). The uncertainties from the curvature of the error around the minimum."""
    t_cmd = np.asarray(t_cmd, dtype=float)
    u = np.asarray(u, dtype=float)
    t_w = np.asarray(t_w, dtype=float)
    w = np.asarray(w, dtype=float)
    keep = (t_w >= t_cmd[0]) & (t_w <= t_cmd[-1])
    t_w, w = t_w[keep], w[keep]

    lag = [0.0]  # the command's way to the motor (bus, board), and the counters' back: found below

    def u_of_t(tt):
        k = np.clip(np.searchsorted(t_cmd, np.asarray(tt) - lag[0], side='right') - 1, 0, len(u) - 1)
        return u[k]

    use = np.ones(len(w), dtype=bool)

    def errors(speeds, taus, bands):
        S, T, B = np.meshgrid(speeds, taus, bands, indexing='ij')
        return motor_rms(t_w, w, u_of_t, S.ravel(), T.ravel(), B.ravel(), max_accel, limit=limit,
                         use=use).reshape(S.shape), S, T, B

    def search():
        speeds = np.linspace(0.5, 1.6, 23) * guess_speed
        taus = np.geomspace(0.01, 0.4, 19)
        bands = np.linspace(0.0, 0.2, 9)
        for _ in range(3):
            e, S, T, B = errors(speeds, taus, bands)
            k = np.unravel_index(np.argmin(e), e.shape)
            best = (S[k], T[k], B[k])
            ds, dtau, db = (speeds[1] - speeds[0]), taus[min(k[1] + 1, len(taus) - 1)] / taus[k[1]], \
                (bands[1] - bands[0]) if len(bands) > 1 else 0.01
            speeds = np.linspace(best[0] - 2 * ds, best[0] + 2 * ds, 9)
            taus = np.geomspace(best[1] / dtau ** 2, best[1] * dtau ** 2, 9)
            bands = np.clip(np.linspace(best[2] - 2 * db, best[2] + 2 * db, 9), 0.0, 0.5)
        return best, float(e[k])

    best, e0 = search()
    # The delay between a command's stamp and the wheel's answer, as a dead time: left in, the
    # time constant would take it up.
    delays = np.arange(0.0, MAX_LAG + 1e-9, 0.002)
    errs = []
    for d in delays:
        lag[0] = d
        errs.append(motor_rms(t_w, w, u_of_t, best[0], best[1], best[2], max_accel, limit=limit, use=use))
    lag[0] = float(delays[int(np.argmin(errs))])
    best, e0 = search()
    residual = simulate_motor(t_w, u_of_t, best[0], best[1], best[2], max_accel, limit=limit) - w
    inliers = robust_mask(residual)
    if not inliers.all():
        use = inliers
        best, e0 = search()
    sigmas = []
    n = int(use.sum())
    for i, v in enumerate(best):
        step = 0.01 * v if v > 0 else 0.005
        lo, hi = list(best), list(best)
        lo[i] -= step
        hi[i] += step
        e_lo = errors([lo[0]], [lo[1]], [lo[2]])[0].item()
        e_hi = errors([hi[0]], [hi[1]], [hi[2]])[0].item()
        curv = (e_lo ** 2 + e_hi ** 2 - 2 * e0 ** 2) / step ** 2  # of the mean squared error
        sigmas.append(math.sqrt(2.0 * e0 ** 2 / (n * curv)) if curv > 0 else None)
    return tuple(Fit(v, s) for v, s in zip(best, sigmas)), e0


# ---- slip ----------------------------------------------------------------------------------------

def fit_slip(odo_distance, est_distance, accel):
    """(per_accel, noise_std, share slipping) of the driven wheels: their travel over the ground's
    (odo / est - 1) per segment against the segment's mean wheel acceleration [m/s^2] (least
    squares through 0), the spread left, and the share of segments off by more than 3 spreads."""
    odo = np.asarray(odo_distance, dtype=float)
    est = np.asarray(est_distance, dtype=float)
    acc = np.asarray(accel, dtype=float)
    ok = np.abs(est) > 0.05
    frac = odo[ok] / est[ok] - 1.0
    a = np.abs(acc[ok])
    if len(frac) < 3:
        return Fit(0.0), Fit(0.0), 0.0
    k = float(a @ frac / (a @ a)) if a @ a > 0 else 0.0
    rest = frac - k * a
    inl = robust_mask(rest)
    std = float(np.std(rest[inl]))
    k_sigma = std / math.sqrt(float(a @ a)) if a @ a > 0 else None
    return Fit(k, k_sigma), Fit(std, std / math.sqrt(2.0 * max(1, inl.sum()))), float(np.mean(~inl))


# ---- rangers and beacons -------------------------------------------------------------------------

def fit_errors(measured, expected, outlier=0.1):
    """(bias, noise) as Fits of measured - expected, from the readings within `outlier` of the
    median (an opponent or an element in front of a ranger is no border echo), and how many."""
    r = np.asarray(measured, dtype=float) - np.asarray(expected, dtype=float)
    r = r[np.isfinite(r)]
    if len(r) < 5:
        return Fit(float('nan')), Fit(float('nan')), 0
    r = r[np.abs(r - np.median(r)) <= outlier]
    r = r[robust_mask(r)]
    n = len(r)
    std = float(np.std(r))
    return Fit(float(np.mean(r)), std / math.sqrt(n)), Fit(std, std / math.sqrt(2.0 * max(1, n - 1))), n


def noise_with_range(residuals, ranges, bias=0.0, bins=4):
    """(noise_std, noise_rel): the spread a + b * range of residuals that grow with the range (an
    infrared ranger's), from the spread in `bins` range bins (least squares, both >= 0)."""
    r = np.asarray(residuals, dtype=float) - bias
    d = np.asarray(ranges, dtype=float)
    keep = np.abs(r - np.median(r)) <= 0.3  # gross echoes only: each bin drops its own outliers
    r, d = r[keep], d[keep]
    if len(r) < 4 * bins:
        s = float(np.std(r)) if len(r) else float('nan')
        return s, 0.0
    edges = np.quantile(d, np.linspace(0.0, 1.0, bins + 1))
    xs, ss = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (d >= lo) & (d <= hi)
        if m.sum() >= 4:
            inl = robust_mask(r[m])
            xs.append(float(np.mean(d[m][inl])))
            ss.append(float(np.std(r[m][inl])))
    if len(xs) < 2:
        return float(np.std(r)), 0.0
    b, a = np.polyfit(xs, ss, 1)
    if a < 0.0:
        return 0.0, max(0.0, float(np.mean(np.array(ss) / np.array(xs))))
    if b < 0.0:
        return float(np.mean(ss)), 0.0
    return float(a), float(b)
