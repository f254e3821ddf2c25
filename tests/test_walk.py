"""The walk written once (docking.study.designs.walk): on synthetic scores it climbs to the
optimum and brackets it, keeps within its budget; the bracketing and its continuation walk by
it (their records' replay on the ledger's runs, tests/test_records.py, shows that it walks as
their committed code did)."""

from __future__ import annotations

import math
import types

import numpy as np
import pytest

from docking.study.design import Cell
from docking.study.designs import addendum as ad
from docking.study.designs import bracketing as br
from docking.study.designs import bracketing_continued as bc
from docking.study.designs.walk import Walk, scores_of

#: The optimum of the synthetic surface, per learner (inside the ladders).
OPTIMUM = {
    "paper": dict(eps_q=0.03, beta_a_train=100.0, eps_w=1.5),
    "linear": dict(eps_q=0.03, beta_a_train=50.0),
}


def _surface(world: str, learner: str, setting: dict, seed: int) -> float:
    """A smooth peak at :data:`OPTIMUM`, a little different per world and seed."""
    optimum = OPTIMUM[learner]
    d = sum((math.log10(v) - math.log10(optimum[k])) ** 2 for k, v in setting.items())
    return 0.9 - 0.1 * d - 0.01 * (world == "nao") + 0.001 * (seed % 3)


class _Results:
    """A design's results as the walks read them: cells, runs (their seeds) and scores."""

    def __init__(self, cells):
        self.cells = list(cells)
        self.runs = {c.key: [types.SimpleNamespace(seed=s) for s in c.seeds] for c in self.cells}

    def score(self, key: str) -> np.ndarray:
        c = next(c for c in self.cells if c.key == key)
        setting = {k: c.coords[k] for k in ad.KNOBS[c["learner"]]}
        return np.array([_surface(c["world"], c["learner"], setting, s) for s in c.seeds])

    def extended(self, cells):
        return _Results(self.cells + list(cells))


def _tuning() -> _Results:
    """The addendum's tuning cells: each learner's untuned setting, on every compared seed."""
    cells = []
    for world, learner in ((w, lr) for w in ad.WORLDS for lr in ad.LEARNERS):
        setting = {k: ad.START[k][1] for k in ad.KNOBS[learner]}
        cells.append(
            Cell(
                f"{world}/tune-{learner}/{ad.tag(setting)}",
                br.WALK.learner_config(world, learner, **setting),
                {"world": world, "variant": f"tune-{learner}", "learner": learner} | setting,
                seeds=br.COMPARE_SEEDS,
            )
        )
    return _Results(cells)


def _same_cells(mine: list[Cell], theirs: list[Cell]) -> None:
    assert [c.key for c in mine] == [c.key for c in theirs] and mine
    for a, b in zip(mine, theirs, strict=True):
        assert a.config.to_dict() == b.config.to_dict() and a.config == b.config
        assert dict(a.coords) == dict(b.coords) and a.label == b.label and a.seeds == b.seeds


def test_the_walk_climbs_to_the_surfaces_optimum_and_brackets_it():
    """Walked on a smooth surface with budget enough, each learner's incumbent climbs to the
    optimum, every neighbour of it complete and worse: bracketed, and the walk stops."""
    addendum = _tuning()
    walk = Walk(
        "a-walk",
        "walk",
        br.COMPARE_SEEDS,
        10_000,
        lambda world, learner: scores_of(addendum, f"tune-{learner}", world, learner),
    )
    own = _Results([])
    for _ in range(20):
        cells = walk.extend(own)
        if not cells:
            break
        own = own.extended(cells)
    else:
        pytest.fail("the walk did not stop")
    for world in ad.WORLDS:
        for learner in ad.LEARNERS:
            assert walk.tuned(own, world, learner) == OPTIMUM[learner]
            assert walk.bracketed(own, world, learner)


def test_the_bracketing_designs_walk_by_the_one_walk():
    """Written once: both designs' stages are the one walk's (their records' replay shows it
    walks as their committed code did, tests/test_records.py)."""
    assert br._extend == br.WALK.extend and bc._extend == bc.WALK.extend
    assert (br.WALK.variant, bc.WALK.variant) == ("bracket", "continue")
    assert (br.WALK.budget, bc.WALK.budget) == (br.BUDGET, bc.BUDGET)


@pytest.mark.parametrize("budget", [0, 25])
def test_the_walk_keeps_within_its_budget(budget):
    start = {k: ad.START[k][1] for k in ad.KNOBS["paper"]}
    found = {tuple(start.items()): {s: 0.9 for s in br.COMPARE_SEEDS}}
    walk = Walk("a-walk", "walk", br.COMPARE_SEEDS, budget, lambda w, lr: found)
    cells = walk.extend(None)
    per: dict = {}
    for c in cells:
        per[c["world"], c["learner"]] = per.get((c["world"], c["learner"]), 0) + len(c.seeds)
        assert c.config.name == "a-walk" and c.key.split("/")[1] == f"walk-{c['learner']}"
    assert all(n <= budget for n in per.values()) and bool(cells) == (budget > 0)
