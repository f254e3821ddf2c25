"""The third edition's addendum (docking.study.designs.addendum): its rules, pinned before its runs,
and its search, walked on synthetic scores."""

from __future__ import annotations

import json
import math
import types
from pathlib import Path

import numpy as np
import pytest

from docking.study import provenance
from docking.study.designs import addendum as ad
from docking.study.designs import landscape as lsc


def test_seeds_are_fresh():
    """No run of the committed ledger (before the addendum's) used a seed of the addendum."""
    manifest = Path(__file__).resolve().parents[1] / "ledger" / "manifest.json"
    runs = json.loads(manifest.read_text())["runs"].values()
    # the bracketing (docking.study.designs.bracketing) and its continuation
    # (docking.study.designs.bracketing_continued) continue the addendum on its seeds, by its rules
    walks = (ad.NAME, "addendum-bracketing", "addendum-bracketing-continued")
    # the fragility landscape (docking.study.designs.landscape) fills the tuning's grid on
    # the tuning seeds the walks compared settings on, never on a judged seed
    landscape = {r["seed"] for r in runs if r["name"] == lsc.NAME}
    assert landscape == set(lsc.SEEDS) and landscape <= set(ad.TUNING_SEEDS)
    # the equal contest (docking.study.designs.equal_contest) runs its common grid on the
    # landscape's seeds, by its rules; its selection and judged seeds are none of the addendum's
    from docking.study.designs import equal_contest as ec

    equal = {r["seed"] for r in runs if r["name"] == ec.NAME}
    assert set(ec.GRID_SEEDS) <= landscape and equal
    assert not (equal - set(ec.GRID_SEEDS)) & (set(ad.SEEDS) | set(ad.TUNING_SEEDS))
    used = {r["seed"] for r in runs if r["name"] not in (*walks, lsc.NAME, ec.NAME)}
    assert not used & (set(ad.SEEDS) | set(ad.TUNING_SEEDS))
    assert not set(ad.SEEDS) & set(ad.TUNING_SEEDS)


def test_the_same_knobs_and_ranges_for_both_sarsa_learners():
    shared = set(ad.KNOBS["paper"]) & set(ad.KNOBS["linear"])
    assert shared == {"eps_q", "beta_a_train"}
    for learner in ad.LEARNERS:
        settings = ad.round1_settings(learner)
        assert len(settings) == 9
        for knob in ad.KNOBS[learner]:
            assert sorted({s[knob] for s in settings}) == sorted(ad.START[knob])
    # L9: every pair of two knobs' values appears once
    paper = ad.round1_settings("paper")
    for a, b in [("eps_q", "beta_a_train"), ("eps_q", "eps_w"), ("beta_a_train", "eps_w")]:
        assert len({(s[a], s[b]) for s in paper}) == 9


def test_ladders_are_log_spaced_and_hold_the_start():
    for knob, ladder in ad.LADDERS.items():
        ratios = np.diff(np.log10(ladder))
        assert np.all(ratios > 0.25) and np.all(ratios < 0.55), knob
        assert set(ad.START[knob]) <= set(ladder)
        i = ladder.index(ad.START[knob][0])
        assert ladder[i : i + 3] == ad.START[knob]  # three neighbouring rungs


class _Fake:
    """What the stages read of a design's results, on a synthetic success surface."""

    def __init__(self, cells, surface):
        self.cells, self.surface = list(cells), surface
        self.runs = {}

    def cell(self, key):
        return next(c for c in self.cells if c.key == key)

    def score(self, key):
        c = self.cell(key)
        learner = c.coords.get("learner")
        if c.coords["variant"].startswith("tune-"):
            setting = {k: c.coords[k] for k in ad.KNOBS[learner]}
        else:
            network = c.config.network
            setting = {k: getattr(network, k) for k in ad.KNOBS.get(learner, ())}
        base = self.surface(learner, setting)
        return np.array([base + 0.001 * (s % 3) for s in c.seeds or ad.SEEDS])


def _walk(surface):
    fake = _Fake(ad.DESIGN.cells, surface)
    for stage in ad.DESIGN.stages[:-1]:
        fake.cells += stage(fake)
    for c in fake.cells:
        fake.runs[c.key] = [
            types.SimpleNamespace(train=types.SimpleNamespace(steps=np.full(2000, 18)))
            for _ in c.seeds or ad.SEEDS
        ]
    fake.cells += ad.DESIGN.stages[-1](fake)
    return fake


def _peak(optimum):
    """Success falling off with the log-distance from ``optimum`` (per learner)."""

    def surface(learner, setting):
        o = optimum.get(learner, {})
        d = sum((math.log10(v) - math.log10(o.get(k, v))) ** 2 for k, v in setting.items())
        return 0.9 - 0.1 * d

    return surface


def test_the_search_extends_past_the_start_until_the_optimum_is_interior():
    optimum = {
        "paper": dict(eps_q=0.3, beta_a_train=20.0, eps_w=5.0),
        "linear": dict(eps_q=0.01, beta_a_train=20.0),
    }
    fake = _walk(_peak(optimum))
    for world in ad.WORLDS:
        for learner in ad.LEARNERS:
            assert ad.TUNING.tuned(fake, world, learner) == optimum[learner]
            used = ad.TUNING.runs_used(fake, world, learner)
            assert ad.BUDGET - ad.ROUND_2 < used <= ad.BUDGET  # round 2 spends what is left
            for knob in optimum[learner]:
                assert ad.position(fake, world, learner, knob)[1] == "interior"


def test_an_optimum_past_a_ladder_is_at_its_stated_limit():
    optimum = {
        "paper": dict(eps_q=10.0, beta_a_train=5.0, eps_w=0.5),
        "linear": dict(eps_q=0.1, beta_a_train=5.0),
    }
    fake = _walk(_peak(optimum))
    tuned = ad.TUNING.tuned(fake, "floor", "paper")
    assert tuned["eps_q"] == ad.LADDERS["eps_q"][-1]
    values, where = ad.position(fake, "floor", "paper", "eps_q")
    assert where == f"at its limit: {ad.LIMITS['eps_q'][1]}"


def test_ppo_trains_for_the_paper_learners_mean_training_steps():
    fake = _walk(_peak({"paper": {}, "linear": {}}))
    for world in ad.WORLDS:
        ppo = fake.cell(f"{world}/ppo-matched").config
        assert ppo.steps == 2000 * 18  # the fake's training steps, a multiple of 16
        assert ppo.learning_rate == ad.PPO_SETTINGS[world]["learning_rate"]
        views = fake.cell(f"{world}/views-frozen").config
        assert views.network.eps_w == 0.0 and views.pretrain_trials == ad.PRETRAIN_TRIALS


#: The commit that added the addendum's rules, and its time (what the runs are compared with;
#: checked against the repository's history where the history is there).
RULES_COMMIT = provenance.RULES_COMMITS[ad.NAME]


def _rules_commit_time():
    from docking.study.report import utc

    return utc(RULES_COMMIT[1])


def test_the_rules_commit_is_the_one_history_holds():
    import subprocess

    root = Path(__file__).resolve().parents[1]
    git = [
        "git",
        "log",
        "--diff-filter=A",
        "--format=%H %cI",
        "--",
        "docking/designs/addendum.py",  # its path at the rules' commit
    ]
    shallow = subprocess.run(
        ["git", "rev-parse", "--is-shallow-repository"], capture_output=True, text=True, cwd=root
    ).stdout.strip()
    if shallow != "false":
        pytest.skip("a shallow clone (or no git): the history that added the rules is not here")
    log = subprocess.run(git, capture_output=True, text=True, check=True, cwd=root).stdout
    assert log.split() == list(RULES_COMMIT)


def _early(runs, rules) -> list:
    """The seeds of ``runs`` (ledger records) without a time or computed before ``rules``."""
    from docking.study.report import utc

    return [r["seed"] for r in runs if "computed_utc" not in r or utc(r["computed_utc"]) <= rules]


def test_every_run_of_the_addendum_was_computed_after_its_rules_commit():
    """Provenance from the ledger: each addendum run records when it was computed, and every
    one is later than the commit that added its rules."""
    manifest = Path(__file__).resolve().parents[1] / "ledger" / "manifest.json"
    runs = [r for r in json.loads(manifest.read_text())["runs"].values() if r["name"] == ad.NAME]
    assert runs, "the ledger holds no run of the addendum"
    assert _early(runs, _rules_commit_time()) == []


def test_a_run_older_than_its_rules_or_without_a_time_is_caught():
    rules = _rules_commit_time()
    runs = [
        {"seed": 1, "computed_utc": "2026-01-01T00:00:00+00:00"},
        {"seed": 2},
        {
            "seed": 3,
            "computed_utc": (rules + __import__("datetime").timedelta(seconds=1)).isoformat(),
        },
    ]
    assert _early(runs, rules) == [1, 2]
