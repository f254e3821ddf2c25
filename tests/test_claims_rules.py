"""The third edition's rules: the equivalence rule judged against its margin."""

import numpy as np

from docking import claims
from docking.stats import Interval


def _ci(low, high):
    return Interval((low + high) / 2, low, high, (), se=(high - low) / 4, df=9)


def test_equivalence_is_contradicted_only_outside_its_margin():
    rule = claims.Equivalent(0.02)
    assert rule.decide(_ci(-0.01, 0.015)) == claims.SUPPORTED
    assert rule.decide(_ci(0.023, 0.069)) == claims.CONTRADICTED  # wholly beyond +2 pp
    assert rule.decide(_ci(0.005, 0.03)) == claims.NOT_SUPPORTED  # excludes 0, not the margin
    assert claims.Within(0.02).decide(_ci(0.005, 0.03)) == claims.CONTRADICTED  # the old rule
    p, side = rule.p_side(_ci(0.04, 0.08))
    assert side == claims.CONTRADICTED and p < 0.05


def test_a_paired_rule_uses_the_per_seed_differences():
    base = np.array([0.9, 0.8, 0.95, 0.7, 0.85, 0.75, 0.9, 0.8, 0.92, 0.88])
    cell = base - 0.03 + np.linspace(-0.005, 0.005, 10)
    paired = claims.Above(0.0, method="paired").statistic(base, cell)
    welch = claims.Above(0.0, method="t").statistic(base, cell)
    assert paired.low > 0 > welch.low  # the same seeds' arms: pairing decides
    assert claims.Above(0.0, method="paired").decide(paired) == claims.SUPPORTED
