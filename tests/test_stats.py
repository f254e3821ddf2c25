"""Bootstrap intervals over seeds."""

import numpy as np
import pytest
from helpers import tool
from scipy import stats

from docking.study.stats import Interval, difference_ci, mean_ci


def test_mean_ci_brackets_the_mean_and_is_seeded():
    x = [0.95, 0.93, 0.97, 0.96, 0.91, 0.94, 0.98, 0.92, 0.95, 0.96]
    ci = mean_ci(x)
    assert ci.low < np.mean(x) < ci.high and ci.estimate == pytest.approx(np.mean(x))
    assert ci.high - ci.low < 0.04
    assert mean_ci(x) == ci  # same numbers, same interval
    assert ci.values == tuple(x)
    assert ci.format() == f"{100 * np.mean(x):.1f} [{100 * ci.low:.1f}, {100 * ci.high:.1f}]"


def test_a_constant_sample_has_a_point_interval():
    ci = mean_ci([1.0] * 10)
    assert ci.low == ci.high == ci.estimate == 1.0


def test_difference_ci_separates_clearly_different_groups_and_not_equal_ones():
    rng = np.random.default_rng(1)
    a = 0.95 + 0.01 * rng.standard_normal(10)
    b = 0.90 + 0.01 * rng.standard_normal(10)
    d = difference_ci(a, b)
    assert d.excludes_zero() and d.low > 0.03
    same = difference_ci(a, a[::-1])
    assert same.estimate == pytest.approx(0.0, abs=1e-15) and not same.excludes_zero()


def test_coverage_of_the_mean_is_near_95_percent():
    rng = np.random.default_rng(2)
    hits = sum(mean_ci(rng.normal(0.5, 0.1, 30), seed=k).contains(0.5) for k in range(200))
    assert 0.88 <= hits / 200 <= 0.99


@pytest.mark.parametrize("bad", [[0.5], [], [0.5, np.nan], [[0.1, np.inf]]])
def test_bad_samples_raise(bad):
    with pytest.raises(ValueError):
        mean_ci(bad)


def test_removed_share_ci_paired_and_unpaired():
    from docking.study.stats import removed_share_ci

    base = np.full(10, 0.10) + np.linspace(-0.01, 0.01, 10)
    half = base / 2
    paired = removed_share_ci(half, base, paired=True)
    assert paired.estimate == pytest.approx(0.5) and paired.low == pytest.approx(0.5)
    unpaired = removed_share_ci(half, base, paired=False)
    assert unpaired.low < 0.5 < unpaired.high
    assert removed_share_ci(base, base, paired=False).contains(0.0)
    with pytest.raises(ValueError, match="no failures"):
        removed_share_ci(half, np.zeros(10), paired=False)
    with pytest.raises(ValueError, match="paired"):
        removed_share_ci(half[:5], base, paired=True)


def test_power_matches_a_simulation_and_gives_the_seeds_it_needs():
    power_tool = tool("power_third_edition")
    power, seeds_for_power = power_tool.power, power_tool.seeds_for_power

    rng = np.random.default_rng(7)
    n, effect, sd = 10, 0.05, 0.06
    draws = rng.normal(effect, sd, size=(20000, n))
    lows = draws.mean(1) - stats.t.ppf(0.975, n - 1) * draws.std(1, ddof=1) / np.sqrt(n)
    assert abs(power(n, effect, sd) - np.mean(lows > 0)) < 0.01
    needed = seeds_for_power(effect, sd, target=0.8)
    assert power(needed, effect, sd) >= 0.8 > power(needed - 1, effect, sd)
    assert seeds_for_power(1.0, 0.01) == 10  # never fewer than ten
    assert seeds_for_power(0.001, 1.0, most=50) is None
    with pytest.raises(ValueError, match="effect > 0"):
        power(10, 0.0, 1.0)


def test_the_paired_interval_pairs_seeds_and_covers():
    from docking.study.stats import t_paired_ci

    coverage = tool("interval_coverage").coverage

    base = np.array([0.9, 0.8, 0.95, 0.7, 0.85])
    ci = t_paired_ci(base - 0.05, base)  # every seed 5 pp worse: no spread of differences
    assert ci.estimate == pytest.approx(-0.05) and ci.low == ci.high == pytest.approx(-0.05)
    noisy = base - 0.05 + np.array([0.01, -0.01, 0.02, -0.02, 0.0])
    paired, welch = t_paired_ci(noisy, base), stats.ttest_ind(noisy, base)
    assert paired.high < 0 and welch.pvalue > 0.05  # pairing resolves what Welch cannot
    with pytest.raises(ValueError, match="pairs seeds"):
        t_paired_ci(base, base[:4])
    assert 0.93 <= coverage("paired", n=10, repeats=800, seed=3) <= 0.97


def test_the_student_t_intervals_are_scipys():
    """t_mean_ci, t_paired_ci and t_difference_ci are scipy's ttest_1samp, ttest_rel and
    ttest_ind(equal_var=False) intervals (to 1e-12; the last bits differ), with their degrees
    of freedom and p-values; docking.study.stats says why they are computed by hand."""
    from docking.study.stats import t_difference_ci, t_mean_ci, t_paired_ci

    rng = np.random.default_rng(43)
    for k in range(300):
        x, y = rng.beta(8, 2, rng.integers(2, 21)), rng.beta(6, 3, rng.integers(2, 21))
        if k % 5 == 0:
            x = np.round(x * 500) / 500  # rates over 500 held-out trials
        confidence = (0.9, 0.95, 0.99)[k % 3]
        z = x + rng.normal(0, 0.05, len(x))
        assert t_paired_ci(z, x, confidence) == t_mean_ci(z - x, confidence)  # one formula
        for ours, theirs in (
            (t_mean_ci(x, confidence), stats.ttest_1samp(x, 0.0)),
            (t_paired_ci(z, x, confidence), stats.ttest_rel(z, x)),
            (t_difference_ci(x, y, confidence), stats.ttest_ind(x, y, equal_var=False)),
        ):
            low, high = theirs.confidence_interval(confidence)
            assert ours.low == pytest.approx(low, abs=1e-12, rel=0)
            assert ours.high == pytest.approx(high, abs=1e-12, rel=0)
            assert ours.df == pytest.approx(theirs.df, rel=1e-12)
            assert ours.p_value(0.0) == pytest.approx(theirs.pvalue, rel=1e-9, abs=1e-300)


def test_a_rate_where_every_trial_succeeds_or_fails_has_an_interval_in_0_1_of_some_width():
    """Ten seeds at 500/500: the Student-t interval is the point [1, 1]; the interval for a
    rate is Wilson's of the 5000 pooled trials, [0.99923, 1], and prints as such."""
    from docking.study.stats import rate_ci, t_mean_ci

    every = rate_ci(np.ones(10), 500)
    wilson = stats.binomtest(5000, 5000).proportion_ci(method="wilson")
    assert every.estimate == every.high == 1.0 and every.low == pytest.approx(wilson.low)
    assert 0.999 < every.low < 1.0
    assert t_mean_ci(np.ones(10)).low == 1.0  # what the tables showed: no width
    none = rate_ci(np.zeros(10), 500)
    assert none.low == none.estimate == 0.0 and 0.0 < none.high < 0.001
    assert rate_ci(np.ones(20), 500).format(unit="%") == "100.00% [99.96, 100.00]"
    assert rate_ci(np.ones(5), 500).format(unit="%") == "100.0% [99.8, 100.0]"
    # near 1 with one seed short of it: inside [0, 1] where the t interval is not
    near = np.array([1.0, 1.0, 1.0, 0.994, 1.0])
    assert t_mean_ci(near).high > 1.0
    ci = rate_ci(near, 500)
    assert 0.98 < ci.low < ci.estimate < ci.high <= 1.0


def test_a_rate_interval_is_wilsons_on_pooled_trials_or_the_t_interval_over_seeds():
    """Seeds that differ no more than binomially: Wilson's interval of the pooled trials
    (scipy's); seeds that differ much more: about the Student-t interval over seeds; trials
    per seed weigh the pooled rate."""
    from docking.study.stats import rate_ci, t_mean_ci

    same = rate_ci(np.full(10, 0.9), 500)
    wilson = stats.binomtest(4500, 5000).proportion_ci(method="wilson")
    assert (same.low, same.high) == (pytest.approx(wilson.low), pytest.approx(wilson.high))
    spread = np.array([0.5, 0.6, 0.7, 0.55, 0.65, 0.45, 0.75, 0.6, 0.62, 0.58])
    ci, t = rate_ci(spread, 500), t_mean_ci(spread)
    assert ci.estimate == pytest.approx(0.6) and ci.values == tuple(spread)
    assert 0.97 < (ci.high - ci.low) / (t.high - t.low) < 1.03
    assert ci.se is None  # reported, not tested: no p-value
    weighted = rate_ci([1.0, 0.5], [300, 100])
    assert weighted.estimate == pytest.approx(350 / 400)


@pytest.mark.parametrize(
    "bad, trials, match",
    [([0.5], 500, "at least 2"), ([0.5, 1.2], 500, "in \\[0, 1\\]"), ([0.5, 0.5], 0, "trials")]
    + [([0.5, 0.5001], 500, "whole successes")],
)
def test_a_rate_interval_refuses_what_is_not_a_rate_over_seeds(bad, trials, match):
    from docking.study.stats import rate_ci

    with pytest.raises(ValueError, match=match):
        rate_ci(bad, trials)


@pytest.mark.parametrize("n", [5, 10, 20])
@pytest.mark.parametrize("scenario", ["near one", "near one, skewed", "mid-range", "bimodal"])
def test_the_rate_interval_covers_near_95_percent(scenario, n):
    """Coverage on synthetic studies (``rate_coverage`` of tools/interval_coverage.py: 500
    trials per seed), near 1 and mid-range, with 5, 10 and 20 seeds: within 2.5 points of
    95%."""
    rate_coverage = tool("interval_coverage").rate_coverage

    assert 0.925 <= rate_coverage(scenario, n, seed=n) <= 0.975
    with pytest.raises(ValueError, match="scenario"):
        rate_coverage("uniform", n)


def test_an_interval_with_a_width_never_prints_as_a_point():
    near = Interval(0.9999, 0.9996, 1.0, ())
    assert near.format() == "99.99 [99.96, 100.00]"
    assert Interval(1.0, 1.0, 1.0, ()).format(unit="%") == "100.0% [100.0, 100.0]"  # a point
    assert Interval(0.5, 0.45, 0.55, ()).format(unit=" pp") == "50.0 pp [45.0, 55.0]"
    assert (
        Interval(0.5, 0.499999999, 0.5, ()).format(digits=0) == "50.000 [50.000, 50.000]"
    )  # 3 more at most
