"""A design with stages: its ledger entries, its absent runs, a design under way."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from helpers import TINY

from docking.study.design import Cell, Design, absent_runs, ledger_runs


def _stage(results):
    """Round 2 of a tiny successive halving: the better of two settings on seed 2."""
    best = max(("a", "b"), key=lambda k: (float(np.mean(results.score(k))), k == "a"))
    return [dataclasses.replace(results.cell(best), key=f"{best}/round2", seeds=(2,))]


DESIGN = Design(
    name="tiny-stages",
    title="a tiny design with a stage",
    cells=(
        Cell("a", TINY, {"v": "a"}, seeds=(0,)),
        Cell(
            "b",
            dataclasses.replace(TINY, network=dataclasses.replace(TINY.network, eps_q=0.3)),
            {"v": "b"},
            seeds=(0,),
        ),
    ),
    seeds=(0,),
    stages=(_stage,),
    keep=frozenset({"ends"}),
    networks={"a": (0,)},
)


@pytest.fixture
def store(tmp_path, monkeypatch):
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))
    return tmp_path / "results"


def test_a_stage_is_asked_once_the_runs_before_it_are_there(store):
    assert {(j.config.network.eps_q, j.seed) for j in absent_runs(DESIGN)} == {(0.1, 0), (0.3, 0)}
    assert ledger_runs(DESIGN, stored_only=True) == []  # nothing stored: nothing written
    first = DESIGN.run(progress=False, workers=1)
    assert absent_runs(DESIGN) == []
    # where each trained cell's runs came from, the stage's cell too
    assert list(first.sources.values()) == [["computed"]] * 3
    assert set(first.sources) == {"a", "b"} | {c.key for c in first.cells[2:]}
    found = ledger_runs(DESIGN)
    assert [(c.network.eps_q, s) for c, s, _, _ in found][:2] == [(0.1, 0), (0.3, 0)]
    assert len(found) == 3 and found[2][1] == 2  # the stage's cell, on its own seed
    assert [k for *_, k in found] == [frozenset({"ends", "networks"})] + [frozenset({"ends"})] * 2
    # its summary shows single-seed cells (a tuning round's) without an interval
    from docking.study.design import summary

    again = DESIGN.run(progress=False, workers=1)
    assert list(again.sources.values()) == [["store"]] * 3
    text = summary(again)
    assert "| a/round2 |" in text or "| b/round2 |" in text
    assert "(seeds: 1)" in text


def test_a_design_under_way_writes_what_is_stored(store):
    first = dataclasses.replace(DESIGN, cells=DESIGN.cells[:1], stages=())
    first.run(progress=False, workers=1)
    found = ledger_runs(DESIGN, stored_only=True)
    assert [(c.network.eps_q, s) for c, s, _, _ in found] == [(0.1, 0)]  # no stage yet
    with pytest.raises(LookupError, match="cell 'b'.*--under-way tiny-stages"):
        ledger_runs(DESIGN)


def test_tuning_keeps_the_best_settings_and_tunes_to_the_best_mean():
    """Round 2 keeps the best ``keep`` settings of round 1 (ties in grid order); the tuned
    setting is the best mean over every tuning seed, which round 2 can reorder."""
    import dataclasses

    import numpy as np

    from docking.presets import EXPERIMENT_1
    from docking.study.design import Cell
    from docking.study.designs.builders import Tuning

    def make(world, learner, **setting):
        network = dataclasses.replace(EXPERIMENT_1.network, **setting)
        return dataclasses.replace(EXPERIMENT_1, network=network)

    def cell(world, key, config, label, seeds=None):
        return Cell(f"{world}/{key}", config, {"world": world, "variant": key}, label, seeds=seeds)

    grids = {"paper": [dict(eps_q=q) for q in (0.1, 0.2, 0.3, 0.4)]}
    tuning = Tuning(("w",), grids, (7, 8, 9), 2, make, cell, judged_seeds={"paper": (1, 2)})
    assert tuning.runs == 4 + 2 * 2
    round1 = tuning.round1("w", "paper")
    assert [c.key for c in round1] == [f"w/tune-paper-{i}" for i in range(4)]
    assert all(c.seeds == (7,) for c in round1)
    scores = {"w/tune-paper-0": [0.5], "w/tune-paper-1": [0.9], "w/tune-paper-2": [0.9]}
    scores["w/tune-paper-3"] = [0.1]

    class Results:
        def __init__(self, cells):
            self.cells = cells

        def cell(self, key):
            return next(c for c in self.cells if c.key == key)

        def score(self, key):
            return np.array(scores[key])

    round2 = tuning.stages()[0](Results(round1))
    assert [c.key for c in round2] == ["w/tune-paper-1/round2", "w/tune-paper-2/round2"]
    assert all(c.seeds == (8, 9) for c in round2)
    scores.update({"w/tune-paper-1/round2": [0.5, 0.5], "w/tune-paper-2/round2": [0.8, 0.9]})
    results = Results(round1 + round2)
    assert tuning.tuned_setting(results, "w", "paper") == 2
    (tuned,) = tuning.stages()[1](results)
    assert tuned.key == "w/paper-tuned" and tuned.seeds == (1, 2)
    assert tuned.config.network.eps_q == 0.3


def test_the_ledger_keeps_what_kept_seeds_names_only_for_those_seeds():
    from docking.presets import EXPERIMENT_1
    from docking.study.design import Cell, Design, ledger_runs

    cell = Cell("a", EXPERIMENT_1, {"x": 1}, "a")
    design = Design(
        "kept",
        "t",
        (cell,),
        (0, 1, 2),
        keep=frozenset({"paths", "starts"}),
        kept_seeds={"paths": (0, 2)},
    )
    keeps = {seed: keep for _, seed, _, keep in ledger_runs(design)}
    assert keeps == {0: {"paths", "starts"}, 1: {"starts"}, 2: {"paths", "starts"}}


def test_only_keeps_the_matching_cells_and_the_baselines_they_need(store):
    part = DESIGN.only(["a*"])
    assert [c.key for c in part.cells] == ["a"] and part.stages == () and part.claims == ()
    assert part.run(progress=False, workers=1).score("a").shape == (1,)
    with pytest.raises(ValueError, match="no cell matching 'c/\\*'"):
        DESIGN.only(["c/*"])
    from docking.study.designs import untested

    moved = untested.DESIGN.only(["along the wall/paper"])  # test-only: its baseline comes too
    assert [c.key for c in moved.cells] == ["home/paper", "along the wall/paper"]


def test_part_of_a_design_with_a_report_is_summarised_without_it():
    """The paper design's report is the README's table of both experiments: a part holding
    only Experiment 1 drops it (as it drops stages and claims), so its summary is the cells'
    table, not a KeyError for the cell it lacks."""
    from docking.study.designs import design

    paper = design("paper")
    part = paper.only(["experiment1"])
    assert paper.report is not None and part.report is None
    assert [c.key for c in part.cells] == ["experiment1"]


def test_read_reads_every_stage_from_the_store_and_never_computes(store, monkeypatch):
    """Design.read: the runs of the core cells and of each stage (the stage asked of the runs
    read before it), read from the store; a cell it does not hold is a LookupError naming it,
    with nothing computed (the runner is never called)."""
    from docking.study import store as stored
    from docking.study import sweep

    first = dataclasses.replace(DESIGN, cells=DESIGN.cells[:1], stages=())
    first.run(progress=False, workers=1)

    def refuse(*args, **kwargs):
        raise AssertionError("read computed a run")

    def refusing():
        monkeypatch.setattr(stored, "compute", refuse)
        monkeypatch.setattr(sweep, "run_configs", refuse)

    refusing()
    with pytest.raises(LookupError, match="cell 'b'"):
        DESIGN.read()
    monkeypatch.undo()
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    monkeypatch.setenv("DOCKING_RESULTS", str(store))
    ran = DESIGN.run(progress=False, workers=1)
    refusing()
    read = DESIGN.read()
    assert [c.key for c in read.cells] == [c.key for c in ran.cells]  # the stage's cell too
    assert {k: list(v) for k, v in read.scores.items()} == {
        k: list(v) for k, v in ran.scores.items()
    }
