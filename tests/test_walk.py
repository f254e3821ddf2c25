"""The walk written once (docking.study.designs.walk, issue 51): given the bracketing's or its
continuation's parameters, it builds the cells each of them builds, stage after stage, on
synthetic scores; the two pinned designs keep their own code (their rules' digests cover it)."""

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
                br.learner_config(world, learner, **setting),
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


def _walk_stages(design_extend, walk: Walk, own: _Results, stages: int) -> _Results:
    """Each stage: the design's cells and the walk's are the same; both walk on."""
    for _ in range(stages):
        theirs, mine = design_extend(own), walk.extend(own)
        if not theirs:
            assert mine == []
            break
        _same_cells(mine, theirs)
        own = own.extended(theirs)
    return own


def _bracketing_walk(addendum) -> Walk:
    """The bracketing's parameters, its scores before it the addendum's tuning cells."""
    return Walk(
        name=br.NAME,
        variant="bracket",
        compare_seeds=br.COMPARE_SEEDS,
        budget=br.BUDGET,
        before=lambda world, learner: scores_of(addendum, f"tune-{learner}", world, learner),
    )


def test_the_walk_with_the_bracketings_parameters_is_the_bracketings_walk(monkeypatch):
    addendum = _tuning()
    monkeypatch.setattr(br, "addendum", lambda: addendum)
    walk = _bracketing_walk(addendum)
    own = _walk_stages(br._extend, walk, _Results([]), br.STAGES)
    for world in ad.WORLDS:
        for learner in ad.LEARNERS:
            assert walk.tuned(own, world, learner) == br.tuned(own, world, learner)
            assert walk.bracketed(own, world, learner) == br.bracketed(own, world, learner)
            assert walk.runs_used(own, world, learner) == br.runs_used(own, world, learner)


def test_the_walk_with_the_continuations_parameters_is_the_continuations_walk(monkeypatch):
    addendum = _tuning()
    monkeypatch.setattr(br, "addendum", lambda: addendum)
    # the bracketing's results: two of its stages, then the continuation walks on
    first = _walk_stages(br._extend, _bracketing_walk(addendum), _Results([]), 2)
    bracketing = _Results([c for c in first.cells if c.coords["variant"].startswith("bracket")])
    bracketing.cells = addendum.cells + bracketing.cells
    bracketing.runs = first.runs
    monkeypatch.setattr(bc, "bracketing", lambda: bracketing)
    walk = Walk(
        name=bc.NAME,
        variant="continue",
        compare_seeds=bc.COMPARE_SEEDS,
        budget=bc.BUDGET,
        before=lambda world, learner: br.scores(bracketing, world, learner),
    )
    own = _walk_stages(bc._extend, walk, _Results([]), bc.STAGES)
    assert own.cells  # it walked
    for world in ad.WORLDS:
        for learner in ad.LEARNERS:
            assert walk.tuned(own, world, learner) == bc.tuned(own, world, learner)
            assert walk.bracketed(own, world, learner) == bc.bracketed(own, world, learner)


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
