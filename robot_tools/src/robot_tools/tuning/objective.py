"""What a tuning trial is worth (scripts/tune.py), and whether a tuned overlay beats the shipped
config on seeds the study never saw. No Optuna, no ROS: unit-tested in test/unit/test_tune.py.

A trial plays the same seeds against the same opponents as every other trial. Each match is
worth our score, less `contact_penalty` per contact with the opponent, less
`invariant_penalty` when it broke an invariant (a lost match, a robot off the table, effectors
on after the end, a node died: match_rows.broken_invariants). The trial's value is the mean
over its matches: one broken match in five costs invariant_penalty / 5, far more than any score,
so a parameter set that breaks the robot sinks whatever it scores. Both weights are in
config/tune/<robot>.yaml (`objective:`).
"""
import math

DEFAULTS = {'contact_penalty': 0.5, 'invariant_penalty': 100.0}


def match_value(row, weights=DEFAULTS):
    """One match's worth: ours - contact_penalty * contacts - invariant_penalty if it broke one.
    A match with no score (it never ran) counts 0 points, and is broken anyway."""
    value = float(row.ours or 0) - float(weights['contact_penalty']) * float(row.contacts or 0)
    if row.violations:
        value -= float(weights['invariant_penalty'])
    return value


def trial_value(rows, weights=DEFAULTS):
    if not rows:
        raise ValueError('a trial with no match')
    return sum(match_value(r, weights) for r in rows) / len(rows)


def t_quantile_975(dof):
    """The 97.5 % quantile of Student's t with `dof` degrees of freedom."""
    from scipy.stats import t
    return float(t.ppf(0.975, dof))


def mean_interval(values):
    """(mean, low, high): the mean and its 95 % interval (Student's t); nan bounds with fewer
    than 2 values (one match tells nothing of luck), all nan with none."""
    values = [float(v) for v in values]
    n = len(values)
    if n == 0:
        return float('nan'), float('nan'), float('nan')
    mean = sum(values) / n
    if n < 2:
        return mean, float('nan'), float('nan')
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    half = t_quantile_975(n - 1) * sd / math.sqrt(n)
    return mean, mean - half, mean + half


def paired_verdict(tuned, shipped):
    """Mean of our score per held-out seed, tuned and shipped, their mean difference and its 95 %
    interval (paired t: both played the same seeds against the same opponents)."""
    if len(tuned) != len(shipped) or not tuned:
        raise ValueError('the verdict needs the same held-out seeds for both: %d and %d' % (len(tuned), len(shipped)))
    a = [float(r.ours or 0) for r in tuned]
    b = [float(r.ours or 0) for r in shipped]
    mean, low, high = mean_interval([x - y for x, y in zip(a, b)])
    return sum(a) / len(a), sum(b) / len(b), mean, low, high


def closing_line(trials, best, baseline, improvement, low, high):
    return 'trials %d best_score %.2f baseline_score %.2f improvement %.2f ci95 [%.2f, %.2f]' % (
        trials, best, baseline, improvement, low, high)
