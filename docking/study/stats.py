"""Confidence intervals over seeds (95% bootstrap, ``scipy.stats.bootstrap``).

The unit of replication is the seed: one number per seed (e.g. a network's success rate on
its held-out test trials). :func:`mean_ci` gives the mean over seeds with a percentile
bootstrap interval; :func:`difference_ci` the difference of two groups' means (a variant
minus the paper's configuration) with a bootstrap that resamples each group's seeds
independently (stratified by group). Both are seeded, so the same numbers give the same
interval.

A success rate (a proportion: each seed's successes in its held-out trials) gets
:func:`rate_ci`, an interval made for proportions that stays in [0, 1] and has a width when
every seed succeeds in every trial (the Student-t and bootstrap intervals of such seeds are
the point ``[1, 1]``); ``tools/interval_coverage.py`` checks its coverage, and the other
intervals', on synthetic studies like the study's.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from scipy import stats

__all__ = [
    "Interval",
    "difference_ci",
    "holm",
    "mean_ci",
    "rate_ci",
    "removed_share_ci",
    "t_difference_ci",
    "t_interaction_ci",
    "t_mean_ci",
    "t_share_ci",
]

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
    se: float | None = None  # the Student-t intervals' standard error ...
    df: float | None = None  # ... and degrees of freedom (None: a bootstrap interval)

    def negated(self) -> Interval:
        """The interval of ``-x`` (e.g. "cell minus baseline" from "baseline minus cell")."""
        return Interval(
            -self.estimate, -self.high, -self.low, self.values, self.confidence, self.se, self.df
        )

    def p_value(self, bound: float) -> float:
        """The two-sided p-value of the estimate against ``bound`` (Student-t intervals
        only): small when the interval lies far on one side of ``bound``."""
        if self.se is None or self.df is None:
            raise ValueError("p_value needs a Student-t interval (t_mean_ci, ...)")
        if self.se == 0:
            return 0.0 if self.estimate != bound else 1.0
        t = (self.estimate - bound) / self.se
        return float(2 * stats.t.sf(abs(t), self.df))

    def contains(self, x: float) -> bool:
        return self.low <= x <= self.high

    def excludes_zero(self) -> bool:
        """True if the interval lies entirely above or entirely below 0."""
        return self.low > 0 or self.high < 0

    def format(self, scale: float = 100.0, unit: str = "", digits: int = 1) -> str:
        """``"95.4 [93.5, 97.7]"`` (values times ``scale``), with up to three more
        decimals where ``digits`` would print the ends of an interval of some width as one
        number (``"99.99 [99.96, 100.00]"``, not ``"100.0 [100.0, 100.0]"``); an interval
        of no width prints as one."""
        for shown in range(digits, digits + 4):
            f = f"{{:.{shown}f}}"
            low, high = f.format(scale * self.low), f.format(scale * self.high)
            if low != high or self.low == self.high:
                break
        return f"{f.format(scale * self.estimate)}{unit} [{low}, {high}]"


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


# ------------------------------------------------------------------------------------------
# Student-t intervals (the study's second edition; their coverage is checked by
# tools/interval_coverage.py).
# They are scipy's (ttest_1samp, ttest_rel, ttest_ind(equal_var=False); to 1e-12, not to the
# bit: tests/test_stats.py), written out because an Interval carries the standard error that
# scipy's result keeps private (p_value needs it), every t interval shares one formula
# (t_paired_ci(a, b) is t_mean_ci(a - b) bit for bit, and the rules' digests pin
# t_paired_ci's text), and scipy warns on seeds of one rate (every seed docking every time).
# ------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=4096)
def _t_quantile(q: float, df: float) -> float:
    """``scipy.stats.t.ppf(q, df)``, remembered: a study judges thousands of intervals (the
    coverage checks tens of thousands) on a few degrees of freedom, and each call of the
    distribution's method costs about 0.1 ms."""
    return float(stats.t.ppf(q, df))


def _t_interval(estimate: float, se: float, df: float, confidence: float, values) -> Interval:
    half = _t_quantile(0.5 + confidence / 2, float(df)) * se if se > 0 else 0.0
    return Interval(estimate, estimate - half, estimate + half, values, confidence, se, df)


def t_mean_ci(values, confidence: float = 0.95) -> Interval:
    """The mean of ``values`` (one per seed) with a Student-t interval (for a success rate,
    :func:`rate_ci`: this interval leaves [0, 1] near its ends and has no width when every
    seed has the same rate)."""
    x = _values(values, "t_mean_ci")
    se = float(x.std(ddof=1) / np.sqrt(len(x)))
    return _t_interval(float(x.mean()), se, len(x) - 1, confidence, tuple(x.tolist()))


def t_paired_ci(values, baseline, confidence: float = 0.95) -> Interval:
    """``mean(values - baseline)`` over seeds paired by index (the same seed's networks or
    held-out streams in both arms), with the paired Student-t interval (``n - 1`` degrees of
    freedom); ``values`` of the result are the per-seed differences."""
    a, b = _values(values, "t_paired_ci"), _values(baseline, "t_paired_ci baseline")
    if len(a) != len(b):
        raise ValueError(f"t_paired_ci pairs seeds: {len(a)} values against {len(b)}")
    d = a - b
    se = float(d.std(ddof=1) / np.sqrt(len(d)))
    return _t_interval(float(d.mean()), se, len(d) - 1, confidence, tuple(d.tolist()))


def _welch(groups, signs) -> tuple[float, float, float]:
    """Estimate, standard error and Welch-Satterthwaite degrees of freedom of
    ``sum(sign * mean(group))`` over independent groups."""
    est = float(sum(sg * g.mean() for g, sg in zip(groups, signs, strict=True)))
    parts = [g.var(ddof=1) / len(g) for g in groups]
    se2 = float(sum(parts))
    if se2 == 0:
        return est, 0.0, float(sum(len(g) - 1 for g in groups))
    df = se2**2 / sum(p**2 / (len(g) - 1) for p, g in zip(parts, groups, strict=True) if p > 0)
    return est, float(np.sqrt(se2)), float(df)


def t_difference_ci(values, baseline, confidence: float = 0.95) -> Interval:
    """``mean(values) - mean(baseline)`` (independent seeds) with Welch's t interval;
    ``values`` of the result are the variant's."""
    a, b = _values(values, "t_difference_ci"), _values(baseline, "t_difference_ci baseline")
    est, se, df = _welch((a, b), (1, -1))
    return _t_interval(est, se, df, confidence, tuple(a.tolist()))


def t_interaction_ci(a, b, c, d, confidence: float = 0.95) -> Interval:
    """``(mean(a) - mean(b)) - (mean(c) - mean(d))`` over four independent groups of seeds
    (e.g. how much more a change costs one learner than another), Welch's t interval."""
    groups = [
        _values(x, f"t_interaction_ci {n}") for x, n in zip((a, b, c, d), "abcd", strict=True)
    ]
    est, se, df = _welch(groups, (1, -1, -1, 1))
    return _t_interval(est, se, df, confidence, tuple(groups[0].tolist()))


def t_paired_interaction_ci(a, b, c, d, confidence: float = 0.95) -> Interval:
    """``mean((a - b) - (c - d))`` over seeds paired by index (four arms sharing each seed's
    networks or held-out streams), with the paired Student-t interval; ``values`` of the
    result are the per-seed values."""
    arms = [
        _values(x, f"t_paired_interaction_ci {n}")
        for x, n in zip((a, b, c, d), "abcd", strict=True)
    ]
    if len({len(x) for x in arms}) != 1:
        raise ValueError(f"t_paired_interaction_ci pairs seeds: {[len(x) for x in arms]} values")
    return t_paired_ci(arms[0] - arms[1], arms[2] - arms[3], confidence)


def t_share_ci(failures, baseline_failures, confidence: float = 0.95) -> Interval:
    """The share of the baseline's failures gone in a variant run on the same seeds,
    ``1 - mean(failures) / mean(baseline_failures)``, with a t interval from the delta
    method for a ratio of paired means (``se = sd(f - r b) / (sqrt(n) mean(b))``)."""
    f = _values(failures, "t_share_ci")
    b = _values(baseline_failures, "t_share_ci baseline")
    if len(f) != len(b):
        raise ValueError(f"t_share_ci pairs seeds: {len(f)} and {len(b)} values")
    if not b.mean() > 0:
        raise ValueError("t_share_ci: the baseline has no failures to remove")
    ratio = f.mean() / b.mean()
    se = float((f - ratio * b).std(ddof=1) / (np.sqrt(len(f)) * b.mean()))
    return _t_interval(float(1 - ratio), se, len(f) - 1, confidence, tuple(f.tolist()))


def holm(pvalues) -> np.ndarray:
    """Holm's step-down adjustment of a family of p-values (family-wise error control):
    the adjusted p-values, in the given order (reject where adjusted < alpha)."""
    p = np.asarray(pvalues, dtype=np.float64).reshape(-1)
    if not np.all((p >= 0) & (p <= 1)):
        raise ValueError(f"holm needs p-values in [0, 1], got {p}")
    m = len(p)
    order = np.argsort(p, kind="stable")
    adjusted = np.empty(m)
    running = 0.0
    for rank, k in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p[k]))
        adjusted[k] = running
    return adjusted


# ------------------------------------------------------------------------------------------
# Success rates: an interval made for proportions over seeds (issue 42).
# ------------------------------------------------------------------------------------------


def _rate_ci(successes: np.ndarray, trials: np.ndarray, confidence: float):
    """:func:`rate_ci`'s estimate and ends for ``successes`` of shape ``(..., seeds)`` (the
    leading axes: independent studies, as tools/interval_coverage.py draws them) and ``trials``
    of shape ``(seeds,)``."""
    k, n = np.asarray(successes, dtype=np.float64), np.asarray(trials, dtype=np.float64)
    m, total = k.shape[-1], n.sum()
    p = k.sum(axis=-1) / total
    # the ratio estimator's variance over seeds (clusters): s^2 / m for equal trials
    v = m / (m - 1) * np.sum((k - p[..., None] * n) ** 2, axis=-1) / total**2
    z = float(stats.norm.ppf(0.5 + confidence / 2))
    t = float(stats.t.ppf(0.5 + confidence / 2, m - 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        effective = np.where(v > 0, p * (1 - p) / v * (z / t) ** 2, total)
    effective = np.minimum(effective, total)  # design effect at least 1: no fewer trials
    shrink = 1 + z**2 / effective
    centre = (p + z**2 / (2 * effective)) / shrink
    half = z * np.sqrt(p * (1 - p) / effective + z**2 / (4 * effective**2)) / shrink
    low = np.where(p == 0, 0.0, np.clip(centre - half, 0.0, 1.0))
    high = np.where(p == 1, 1.0, np.clip(centre + half, 0.0, 1.0))
    return p, low, high


def rate_ci(rates, trials, confidence: float = 0.95) -> Interval:
    """A success rate over seeds: ``rates`` (one per seed, each its successes in ``trials``
    trials; ``trials`` one number or one per seed) pooled over the seeds' trials (for equal
    trials, the mean of the rates), with an interval made for proportions.

    The interval is Wilson's score interval on the pooled trials, with the trials replaced by
    their effective number under the seeds' clustering (the design effect; Kish 1965), and
    that number reduced by ``(z / t_{m-1})^2`` for a variance estimated from ``m`` seeds
    (Korn & Graubard 1998, the NCHS standard for proportions from clustered samples): with
    ``v`` the variance of the pooled rate over seeds (the ratio estimator's, ``s^2 / m`` for
    equal trials), the effective trials are ``p (1 - p) / v * (z / t)^2``, at most the pooled
    trials (a design effect below 1, seeds that differ less than binomially, and every rate 0
    or 1 count as 1).

    Why this interval: where the seeds differ more than their trials' binomial noise (the
    middle of [0, 1]), it is the Student-t interval over seeds in width, so it respects the
    seed-to-seed spread the verdict rules use; near 0 or 1, Wilson's interval is asymmetric,
    stays in [0, 1], and has a width even when every seed succeeds in every trial (then it is
    Wilson's interval of the pooled trials: 10 seeds at 500/500 give [99.92%, 100%]), where
    the t interval leaves [0, 1] or is a point and a bootstrap over seeds and trials is a
    point. Its coverage on synthetic studies like the study's (seeds' true rates near one,
    near one and skewed, mid-range and bimodal; 5, 10 and 20 seeds of 500 trials) is measured
    by ``rate_coverage`` in ``tools/interval_coverage.py``, and tests/test_stats.py holds it
    within 2.5 points of 95% in each; near one, the Student-t interval over seeds covers less,
    and Clopper-Pearson's on the same effective trials more.

    ``values`` of the result are the rates; it carries no standard error: it is reported,
    not tested (the rules' differences keep their paired Student-t intervals)."""
    r = _values(rates, "rate_ci")
    n = np.broadcast_to(np.asarray(trials, dtype=np.float64), r.shape)
    if not np.all((r >= 0) & (r <= 1)) or not np.all(n >= 1):
        raise ValueError(f"rate_ci needs rates in [0, 1] and trials >= 1, got {r}, {n}")
    k = r * n
    if not np.allclose(k, np.round(k), rtol=0, atol=1e-6):
        raise ValueError(f"rate_ci: rates {r} are not whole successes of {n} trials")
    p, low, high = _rate_ci(np.round(k), n, confidence)
    return Interval(float(p), float(low), float(high), tuple(r.tolist()), confidence)
