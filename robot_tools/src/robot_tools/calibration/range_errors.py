"""A ranger's bias and noise against the table's borders at the estimated pose, and the beacons'
range bias and noise: the outlier-robust bias and noise of measured minus expected, and the noise
that grows with the range (an infrared ranger's). Plain arrays, no ROS."""
import math

import numpy as np

from robot_tools.calibration.stats import Fit, robust_mask


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
