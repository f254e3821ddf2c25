"""The addendum's bracketing (docking.study.designs.bracketing): its rules, pinned before its runs,
and its search, walked on synthetic scores."""

from __future__ import annotations

import hashlib
import math

import pinned
import pytest

from docking.study import provenance
from docking.study.designs import addendum as ad
from docking.study.designs import bracketing as br

#: The SHA-256 of rules_text() when the rules were committed, before any of its runs.
RULES_DIGEST = "061f85bf9f2da895b0038717c06fc814a98c213ab4f01bd8f64c1c14b1978077"
#: The SHA-256 of rules_text() since the study layer moved into docking/study/ (issue 51): the
#: same rules, its and the addendum's import statements naming the moved modules
#: (:func:`test_the_rules_moved_unchanged` proves it from the history).
MOVED_DIGEST = "18b5fb068d825ca1c8c11ab4dbcc72fa5d6d79653b6cb72790a6716de7c98af5"


def test_rules_are_the_committed_ones():
    """The rules as committed: their digest since the move, which is the digest pinned at the
    rules' commit with only import statements changed (:func:`test_the_rules_moved_unchanged`)."""
    assert hashlib.sha256(br.rules_text().encode()).hexdigest() == MOVED_DIGEST


def test_the_rules_moved_unchanged():
    """Which proof holds: the digest at the rules' commit, from the history (tests/pinned.py).
    The rules now, with this module's and the addendum's tokens and the judging functions' source
    read as at the rules' commit, have :data:`RULES_DIGEST`; both modules differ from then only in
    import statements; the judging functions' text is the same but for
    ``report.paired_over_shared_seeds``'s import of ``t_paired_ci`` (the addendum's rules, part of
    these, by the same proof)."""
    if not pinned.history():
        pytest.skip("a shallow clone (or no git): the history that pinned the rules is not here")
    commit = provenance.RULES_COMMITS[br.NAME][0]
    read = pinned.check_moved(br.rules_text, commit, [br, ad], RULES_DIGEST)
    assert sorted(read["functions"]) == [
        "docking.study.report.contest_gaps",
        "docking.study.report.paired_over_shared_seeds",
        "docking.study.stats.t_paired_ci",
    ]
    assert pinned.changed_functions(read) == {"docking.study.report.paired_over_shared_seeds"}


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
        missing = br.missing_neighbours(found, br.incumbent(found))
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
    assert br.incumbent(found) == optimum
    assert not br.missing_neighbours(found, optimum)  # every neighbour complete and worse


def test_a_partial_setting_is_topped_up_to_the_compared_seeds_only():
    start = dict(eps_q=0.1, beta_a_train=10.0)
    found = {
        tuple(start.items()): {s: 0.9 for s in br.COMPARE_SEEDS},
        (("eps_q", 0.3), ("beta_a_train", 10.0)): {5900: 0.5, 5901: 0.5},
        (("eps_q", 0.03), ("beta_a_train", 10.0)): {s: 0.5 for s in br.COMPARE_SEEDS},
    }
    missing = dict((ad.tag(s), seeds) for s, seeds in br.missing_neighbours(found, start))
    assert missing["eps_q=0.3,beta_a_train=10"] == br.COMPARE_SEEDS[2:]
    assert "eps_q=0.03,beta_a_train=10" not in missing  # complete already
    assert missing["eps_q=0.1,beta_a_train=5"] == br.COMPARE_SEEDS


def test_an_incomplete_setting_never_becomes_the_incumbent():
    found = {
        (("eps_q", 0.1), ("beta_a_train", 10.0)): {s: 0.8 for s in br.COMPARE_SEEDS},
        (("eps_q", 0.3), ("beta_a_train", 10.0)): {5900: 1.0},
    }
    assert br.incumbent(found) == dict(eps_q=0.1, beta_a_train=10.0)


def test_ties_go_to_the_first_evaluated():
    found = {
        (("eps_q", 0.1), ("beta_a_train", 10.0)): {s: 0.8 for s in br.COMPARE_SEEDS},
        (("eps_q", 0.3), ("beta_a_train", 10.0)): {s: 0.8 for s in br.COMPARE_SEEDS},
    }
    assert br.incumbent(found) == dict(eps_q=0.1, beta_a_train=10.0)


def test_the_extension_stage_keeps_within_the_budget(monkeypatch):
    start = dict(eps_q=0.3, beta_a_train=50.0, eps_w=0.5)
    found = {tuple(start.items()): {s: 0.9 for s in br.COMPARE_SEEDS}}
    monkeypatch.setattr(br, "scores", lambda own, world, learner: found)
    monkeypatch.setattr(br, "runs_used", lambda own, world, learner: br.BUDGET - 25)
    cells = br._extend(None)
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
    missing = br.missing_neighbours({}, start)
    assert len(missing) == 2 * len(ad.KNOBS[learner])
