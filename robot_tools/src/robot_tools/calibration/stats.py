"""The value every calibration fit returns (Fit: a value with its standard uncertainty) and the
plain-array helpers the fits and the bag reader share: the robust inlier mask (median and scaled
MAD) and the unwrapping of counters that wrap. No ROS, no fitting of its own: every other
calibration module builds on it."""
import numpy as np


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
