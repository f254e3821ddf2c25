"""How often the study's intervals cover the truth, on synthetic studies like its own: the
checks of :mod:`docking.study.stats`'s intervals (issue 43: simulations that only tests and notebook
07 use live beside the package, not in it).

* :func:`coverage`: bootstrap and Student-t intervals of a difference of two groups' means,
  and the paired Student-t interval (tests/test_stats.py);
* :func:`rule_coverage`: the intervals the third edition's rules decide by (notebook 07's
  table, tests/test_third_edition.py);
* :func:`rate_coverage`: :func:`docking.study.stats.rate_ci` near 0 and 1 (tests/test_stats.py).

Each is seeded: the same arguments give the same share. Load it by its path (it is not a
package): ``importlib.util.spec_from_file_location("interval_coverage", path)``.
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from docking.study.stats import (
    Interval,
    _rate_ci,  # rate_ci's bounds, vectorised over many studies at once
    t_difference_ci,
    t_paired_ci,
    t_paired_interaction_ci,
    t_share_ci,
)


def coverage(
    method: str,
    n: int = 10,
    trials: int = 500,
    repeats: int = 1000,
    mean: float = 0.85,
    spread: float = 0.08,
    seed: int = 0,
    confidence: float = 0.95,
) -> float:
    """How often an interval of ``method`` (``"percentile"``, ``"bca"``: bootstrap; ``"t"``:
    Student-t) covers the true difference of two groups' mean success, on synthetic seeds
    like the study's: each group has ``n`` seeds whose true success is drawn from a Beta
    distribution (mean ``mean`` and ``mean - 0.05``, standard deviation ``spread``: seeds
    differ), each measured on ``trials`` held-out trials (binomial). ``"paired"``: the paired
    Student-t interval (:func:`t_paired_ci`) where each seed's two arms share its network: the
    second arm's true success is the first's minus 0.05 plus a seed's own normal deviation
    (standard deviation ``spread / 2``). Returns the share of ``repeats`` intervals that
    cover the true difference (0.05)."""
    if method not in ("percentile", "bca", "t", "paired"):
        raise ValueError(f"coverage: method must be percentile, bca, t or paired, got {method!r}")
    rng = np.random.default_rng(seed)
    hits = 0
    for r in range(repeats):
        if method == "paired":  # one seed's two arms share its network: correlated
            true = _beta(rng, mean, spread, n)
            arms = (true, np.clip(true - 0.05 + rng.normal(0, spread / 2, n), 0, 1))
            groups = [rng.binomial(trials, p) / trials for p in arms]
            ci = t_paired_ci(*groups, confidence=confidence)
            hits += ci.low <= 0.05 <= ci.high
            continue
        groups = [
            rng.binomial(trials, _beta(rng, m, spread, n)) / trials for m in (mean, mean - 0.05)
        ]
        if method == "t":
            ci = t_difference_ci(*groups, confidence=confidence)
        else:
            ci = _interval_method(groups, method, confidence, seed + r)
        hits += ci.low <= 0.05 <= ci.high
    return hits / repeats


def _interval_method(groups, method: str, confidence: float, seed: int) -> Interval:
    a, b = groups
    result = stats.bootstrap(
        (a, b),
        lambda x, y, axis: x.mean(axis=axis) - y.mean(axis=axis),
        confidence_level=confidence,
        n_resamples=2000,
        method="BCa" if method == "bca" else "percentile",
        vectorized=True,
        random_state=np.random.default_rng(seed),
    )
    low, high = result.confidence_interval
    return Interval(float(a.mean() - b.mean()), float(low), float(high), (), confidence)


#: The kinds of interval :func:`rule_coverage` checks: a paired difference of success, a
#: paired interaction of four arms, the delta method's share of failures removed.
COVERAGE_KINDS = ("paired", "interaction", "share")


def _beta(rng: np.random.Generator, m: float, s: float, size) -> np.ndarray:
    """Draws of a Beta distribution with mean ``m`` and standard deviation ``s`` (moments
    matched): the synthetic seeds' true rates of the coverage checks."""
    k = m * (1 - m) / s**2 - 1
    return rng.beta(m * k, (1 - m) * k, size=size)


def rule_coverage(
    kind: str,
    n: int,
    bimodal: bool = False,
    trials: int = 500,
    repeats: int = 2000,
    seed: int = 0,
    confidence: float = 0.95,
) -> float:
    """How often the interval of ``kind`` (:data:`COVERAGE_KINDS`) covers the truth on
    synthetic studies of ``n`` seeds like the third edition's: each seed's true success is
    drawn from a Beta distribution (mean 0.85, standard deviation 0.08), or with ``bimodal``
    from a mixture (half near 0.25, half near 0.9: seeds that learn and seeds that do not, as
    eps_W x100 gave); the arms of one seed share it (the other arm 5 pp lower, or for
    ``share`` with 60% of its failures gone, each with a seed's own normal deviation) and
    each arm is measured on ``trials`` held-out trials (binomial). The truth is the same
    statistic of the arms' true means (from 200,000 synthetic seeds). Returns the share of
    ``repeats`` intervals that cover it."""
    if kind not in COVERAGE_KINDS:
        raise ValueError(f"rule_coverage: kind must be one of {COVERAGE_KINDS}, got {kind!r}")
    rng = np.random.default_rng(seed)

    def beta(m, s, size):
        return _beta(rng, m, s, size)

    def arms(size):
        base = beta(0.85, 0.08, size)
        if bimodal:
            base = np.where(rng.random(size) < 0.5, beta(0.25, 0.08, size), beta(0.9, 0.04, size))
        noise = [rng.normal(0, 0.04, size) for _ in range(3)]
        if kind == "share":
            return [base, np.clip(1 - 0.4 * (1 - base) + noise[0], 0, 1)]
        second = np.clip(base - 0.05 + noise[0], 0, 1)
        if kind == "paired":
            return [second, base]
        other = np.clip(base - 0.02 + noise[1], 0, 1)
        return [base, second, base, np.clip(other + noise[2], 0, 1)]

    def statistic(ps):
        if kind == "share":
            return 1 - np.mean(1 - ps[1]) / np.mean(1 - ps[0])
        if kind == "paired":
            return np.mean(ps[0] - ps[1])
        return np.mean((ps[0] - ps[1]) - (ps[2] - ps[3]))

    truth = statistic(arms(200_000))
    hits = 0
    for _ in range(repeats):
        measured = [rng.binomial(trials, p) / trials for p in arms(n)]
        if kind == "share":
            ci = t_share_ci(1 - measured[1], 1 - measured[0], confidence)
        elif kind == "paired":
            ci = t_paired_ci(*measured, confidence=confidence)
        else:
            ci = t_paired_interaction_ci(*measured, confidence=confidence)
        hits += ci.low <= truth <= ci.high
    return hits / repeats


#: The synthetic studies :func:`rate_coverage` checks :func:`rate_ci` on: seeds' true
#: success rates uniform on [0.99, 1] ("near one"), from a Beta distribution of mean 0.995
#: and standard deviation 0.005 ("near one, skewed": some seeds near 0.98), of mean 0.6 and
#: standard deviation 0.1 ("mid-range"), and the mixture of :func:`rule_coverage`
#: ("bimodal": seeds that learn and seeds that do not).
RATE_SCENARIOS = ("near one", "near one, skewed", "mid-range", "bimodal")


def rate_coverage(
    scenario: str,
    n: int,
    trials: int = 500,
    repeats: int = 2000,
    seed: int = 0,
    confidence: float = 0.95,
) -> float:
    """How often :func:`rate_ci` covers the true mean success of the seeds' population, on
    ``repeats`` synthetic studies of ``n`` seeds in ``scenario`` (:data:`RATE_SCENARIOS`),
    each seed's true rate drawn from the scenario and measured on ``trials`` held-out trials
    (binomial). The truth is the mean of 400,000 synthetic seeds' rates."""
    if scenario not in RATE_SCENARIOS:
        raise ValueError(f"rate_coverage: scenario must be one of {RATE_SCENARIOS}")
    rng = np.random.default_rng(seed)

    def beta(m, s, size):
        return _beta(rng, m, s, size)

    def rates(size):
        if scenario == "near one":
            return rng.uniform(0.99, 1.0, size)
        if scenario == "near one, skewed":
            return beta(0.995, 0.005, size)
        if scenario == "mid-range":
            return beta(0.6, 0.1, size)
        return np.where(rng.random(size) < 0.5, beta(0.25, 0.08, size), beta(0.9, 0.04, size))

    truth = float(rates(400_000).mean())
    successes = rng.binomial(trials, rates((repeats, n)))
    _, low, high = _rate_ci(successes, np.full(n, trials), confidence)
    return float(np.mean((low <= truth) & (truth <= high)))
