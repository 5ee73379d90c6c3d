"""The drive motors: the wheel speed from encoder counts, the simulator's first-order motor model
(speed at full PWM, time constant, dead band, acceleration and current limits) run over a
commanded PWM, and its fit to the wheel speed a match recorded (with the command's dead time).
Plain arrays, no ROS."""
import math

import numpy as np

from robot_tools.calibration.stats import Fit, robust_mask

TWO_PI = 2.0 * math.pi


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
