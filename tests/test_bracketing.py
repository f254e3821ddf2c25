"""The addendum's bracketing (docking.study.designs.bracketing): its rules, pinned before its runs,
and its search, walked on synthetic scores."""

from __future__ import annotations

import dataclasses
import math

import pytest

from docking.study.designs import addendum as ad
from docking.study.designs import bracketing as br


def _peak(optimum):
    def surface(setting):
        d = sum((math.log10(v) - math.log10(optimum.get(k, v))) ** 2 for k, v in setting.items())
        return 0.9 - 0.1 * d

    return surface


def _climb(start: dict, surface, budget=10_000):
    """The search's own functions, walked on ``surface``: from ``start`` (complete), run
    every incumbent's missing neighbours until none is missing or the budget ends."""
    found = {tuple(start.items()): {s: surface(start) for s in br.COMPARE_SEEDS}}
    used = 0
    for _ in range(50):
        missing = br.WALK.missing_neighbours(found, br.WALK.incumbent(found))
        if not missing:
            break
        for setting, seeds in missing:
            if used + len(seeds) <= budget:
                used += len(seeds)
                got = found.setdefault(tuple(setting.items()), {})
                got.update({s: surface(setting) for s in seeds})
    return found, used


def test_the_climb_ends_bracketed_at_an_interior_optimum():
    optimum = dict(eps_q=0.03, beta_a_train=100.0, eps_w=1.5)
    start = dict(eps_q=0.3, beta_a_train=20.0, eps_w=0.5)
    found, _ = _climb(start, _peak(optimum))
    assert br.WALK.incumbent(found) == optimum
    assert not br.WALK.missing_neighbours(found, optimum)  # every neighbour complete and worse


def test_a_partial_setting_is_topped_up_to_the_compared_seeds_only():
    start = dict(eps_q=0.1, beta_a_train=10.0)
    found = {
        tuple(start.items()): {s: 0.9 for s in br.COMPARE_SEEDS},
        (("eps_q", 0.3), ("beta_a_train", 10.0)): {5900: 0.5, 5901: 0.5},
        (("eps_q", 0.03), ("beta_a_train", 10.0)): {s: 0.5 for s in br.COMPARE_SEEDS},
    }
    missing = dict((ad.tag(s), seeds) for s, seeds in br.WALK.missing_neighbours(found, start))
    assert missing["eps_q=0.3,beta_a_train=10"] == br.COMPARE_SEEDS[2:]
    assert "eps_q=0.03,beta_a_train=10" not in missing  # complete already
    assert missing["eps_q=0.1,beta_a_train=5"] == br.COMPARE_SEEDS


def test_an_incomplete_setting_never_becomes_the_incumbent():
    found = {
        (("eps_q", 0.1), ("beta_a_train", 10.0)): {s: 0.8 for s in br.COMPARE_SEEDS},
        (("eps_q", 0.3), ("beta_a_train", 10.0)): {5900: 1.0},
    }
    assert br.WALK.incumbent(found) == dict(eps_q=0.1, beta_a_train=10.0)


def test_ties_go_to_the_first_evaluated():
    found = {
        (("eps_q", 0.1), ("beta_a_train", 10.0)): {s: 0.8 for s in br.COMPARE_SEEDS},
        (("eps_q", 0.3), ("beta_a_train", 10.0)): {s: 0.8 for s in br.COMPARE_SEEDS},
    }
    assert br.WALK.incumbent(found) == dict(eps_q=0.1, beta_a_train=10.0)


def test_the_extension_stage_keeps_within_the_budget():
    start = dict(eps_q=0.3, beta_a_train=50.0, eps_w=0.5)
    found = {tuple(start.items()): {s: 0.9 for s in br.COMPARE_SEEDS}}
    walk = dataclasses.replace(br.WALK, before=lambda world, learner: found, budget=25)
    cells = walk.extend(None)
    per = {(c["world"], c["learner"]): 0 for c in cells}
    for c in cells:
        per[c["world"], c["learner"]] += len(c.seeds)
        assert c.config.name == br.NAME and set(c.seeds) <= set(br.COMPARE_SEEDS)
    assert per and all(n == 20 for n in per.values())  # two whole neighbours fit in 25


def test_seeds_compared_are_the_addendums_round2_seeds():
    assert set(br.COMPARE_SEEDS) <= set(ad.TUNING_SEEDS)
    assert not set(br.COMPARE_SEEDS) & set(ad.SEEDS)
    assert br.DESIGN.seeds == ad.SEEDS


@pytest.mark.parametrize("learner", ad.LEARNERS)
def test_both_learners_search_the_addendums_ladders(learner):
    start = {k: ad.START[k][1] for k in ad.KNOBS[learner]}
    missing = br.WALK.missing_neighbours({}, start)
    assert len(missing) == 2 * len(ad.KNOBS[learner])
