"""How much the driven wheels' travel exceeds the ground's, against their acceleration: the slip
fit over the geometry's segments. Plain arrays, no ROS."""
import math

import numpy as np

from robot_tools.calibration.stats import Fit, robust_mask


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
