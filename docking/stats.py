"""Confidence intervals over seeds (95% bootstrap, ``scipy.stats.bootstrap``).

The unit of replication is the seed: one number per seed (e.g. a network's success rate on
its held-out test trials). :func:`mean_ci` gives the mean over seeds with a percentile
bootstrap interval; :func:`difference_ci` the difference of two groups' means (a variant
minus the paper's configuration) with a bootstrap that resamples each group's seeds
independently (stratified by group). Both are seeded, so the same numbers give the same
interval.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import stats

__all__ = ["Interval", "mean_ci", "difference_ci", "removed_share_ci"]

#: Bootstrap resamples; at 10^4 the interval's ends are stable to about 0.1 percentage points
#: for success rates over ten seeds.
N_RESAMPLES = 10_000


@dataclasses.dataclass(frozen=True)
class Interval:
    """A point estimate with a confidence interval ``[low, high]`` and the per-seed values."""

    estimate: float
    low: float
    high: float
    values: tuple[float, ...]
    confidence: float = 0.95

    def negated(self) -> Interval:
        """The interval of ``-x`` (e.g. "cell minus baseline" from "baseline minus cell")."""
        return Interval(-self.estimate, -self.high, -self.low, self.values, self.confidence)

    def contains(self, x: float) -> bool:
        return self.low <= x <= self.high

    def excludes_zero(self) -> bool:
        """True if the interval lies entirely above or entirely below 0."""
        return self.low > 0 or self.high < 0

    def format(self, scale: float = 100.0, unit: str = "", digits: int = 1) -> str:
        """``"95.4 [93.5, 97.7]"`` (values times ``scale``)."""
        f = f"{{:.{digits}f}}"
        return (
            f"{f.format(scale * self.estimate)}{unit} "
            f"[{f.format(scale * self.low)}, {f.format(scale * self.high)}]"
        )


def _values(values, name: str) -> np.ndarray:
    array = np.asarray(values, dtype=np.float64).reshape(-1)
    if len(array) < 2:
        raise ValueError(f"{name} needs at least 2 values (one per seed), got {len(array)}")
    if not np.isfinite(array).all():
        raise ValueError(f"{name} must be finite, got {array}")
    return array


def _interval(estimate, samples, statistic, confidence, seed, values, paired=False) -> Interval:
    if np.ptp(np.concatenate(samples)) == 0:  # all equal: the bootstrap has no spread
        return Interval(estimate, estimate, estimate, values, confidence)
    result = stats.bootstrap(
        samples,
        statistic,
        confidence_level=confidence,
        n_resamples=N_RESAMPLES,
        method="percentile",
        paired=paired,
        vectorized=True,
        random_state=np.random.default_rng(seed),
    )
    low, high = result.confidence_interval
    return Interval(estimate, float(low), float(high), values, confidence)


def mean_ci(values, confidence: float = 0.95, seed: int = 0) -> Interval:
    """The mean of ``values`` (one per seed) with a percentile bootstrap interval."""
    x = _values(values, "mean_ci")
    return _interval(
        float(x.mean()),
        (x,),
        lambda a, axis: a.mean(axis=axis),
        confidence,
        seed,
        tuple(x.tolist()),
    )


def difference_ci(values, baseline, confidence: float = 0.95, seed: int = 0) -> Interval:
    """``mean(values) - mean(baseline)`` with a bootstrap interval that resamples the seeds
    of each group independently. ``values`` of the result are the variant's."""
    a, b = _values(values, "difference_ci"), _values(baseline, "difference_ci baseline")
    return _interval(
        float(a.mean() - b.mean()),
        (a, b),
        lambda x, y, axis: x.mean(axis=axis) - y.mean(axis=axis),
        confidence,
        seed,
        tuple(a.tolist()),
    )


def removed_share_ci(
    failures, baseline_failures, paired: bool, confidence: float = 0.95, seed: int = 0
) -> Interval:
    """The share of the baseline's failures that are gone in a variant,
    ``1 - mean(failures) / mean(baseline_failures)`` (failure rates, one per seed), with a
    bootstrap interval. ``paired``: the seeds are resampled jointly (the same trials run
    twice, e.g. with and without heading noise); otherwise each group's seeds independently.
    ``values`` of the result are the variant's failure rates."""
    a = _values(failures, "removed_share_ci")
    b = _values(baseline_failures, "removed_share_ci baseline")
    if paired and len(a) != len(b):
        raise ValueError(f"paired groups need as many values, got {len(a)} and {len(b)}")
    if not b.mean() > 0:
        raise ValueError("removed_share_ci: the baseline has no failures to remove")

    def share(base, x, axis=-1):
        return 1 - x.mean(axis=axis) / base.mean(axis=axis)

    return _interval(
        float(share(b, a)), (b, a), share, confidence, seed, tuple(a.tolist()), paired=paired
    )
