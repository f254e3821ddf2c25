"""The equal contest (docking.study.designs.equal_contest): its rules, pinned before its runs;
its seeds, fresh; the ledger runs it reads, the ones it names; its procedure and its verdicts,
rules that can fail."""

from __future__ import annotations

import hashlib
import json
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from docking.study import records
from docking.study.designs import equal_contest as ec

REPO = Path(__file__).resolve().parents[1]
#: The SHA-256 of the rules text when the rules were committed, before any of its runs.
RULES_DIGEST = "b1de72d16f0eeccc43a727f11c3de0f02b8503dfc2de6d5cbfad4cecae00f145"
#: The commit that added the rules (and the procedure the record copies).
RULES_COMMIT = "319cc64"


def _runs():
    return json.loads((REPO / "ledger" / "manifest.json").read_text())["runs"]


def test_the_record_is_the_committed_rules():
    """The record's text is the one whose digest was pinned before the runs; its procedure's
    verbatim copy is the one the text's digest names, and the source the rules' commit held."""
    assert records.digest(ec.NAME) == RULES_DIGEST
    recorded = records.data(ec.NAME)
    source = records.procedure(ec.NAME)
    assert hashlib.sha256(source.encode()).hexdigest() == recorded["constants"]["procedure"]
    committed = subprocess.run(
        ["git", "show", f"{RULES_COMMIT}:docking/study/designs/equal_contest.py"],
        cwd=REPO,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    blocks = re.split(r"\n(?=def |@)", source)
    assert len(blocks) == 14 and all(block in committed for block in blocks)
    assert "def judgement(pairs: dict) -> dict:" in source and "class Ladder:" in source


def test_the_live_design_is_the_record_with_its_amendment():
    """Its constants, ladders and cells (keys, configurations, seeds) equal the record's with
    its one amendment applied (linear SARSA's eps_Q ladder stops at 2); the record itself is
    the pinned text, and without the amendment the live design is not it."""
    recorded, live = records.amended(ec.NAME), ec.rules_data()
    recorded["constants"].pop("procedure")
    assert live == recorded
    (amendment,) = records.amendments(ec.NAME)
    assert amendment["path"] == ["constants", "ladders", "linear", 1, "upper"]
    assert (amendment["before"], amendment["after"]) == (None, ec.LMS_LIMIT)
    original = records.data(ec.NAME)
    original["constants"].pop("procedure")
    assert live != original and records.digest(ec.NAME) == RULES_DIGEST


def test_an_amendment_that_misstates_the_value_it_changes_is_refused(monkeypatch):
    (amendment,) = records.amendments(ec.NAME)
    wrong = {**amendment, "before": 1.0}
    monkeypatch.setattr(records, "amendments", lambda name: [wrong])
    with pytest.raises(ValueError, match="amendment 1.*is None, not 1.0"):
        records.amended(ec.NAME)


def test_a_changed_constant_or_cell_is_not_the_record(monkeypatch):
    recorded = records.amended(ec.NAME)
    recorded["constants"].pop("procedure")
    monkeypatch.setattr(ec, "TOP_K", 2)
    assert ec.rules_data() != recorded
    monkeypatch.undo()
    changed = dict(ec.READ_FROM["floor"]["paper"])
    changed["fragility-landscape"] = changed["fragility-landscape"][1:]
    monkeypatch.setitem(ec.READ_FROM["floor"], "paper", changed)
    monkeypatch.setattr(ec, "DESIGN", ec.dataclasses.replace(ec.DESIGN, cells=ec.DESIGN.cells[:-1]))
    assert ec.rules_data() != recorded


def test_its_judged_and_selection_seeds_are_used_by_no_other_run_or_design():
    from docking.study import designs

    used = {r["seed"] for r in _runs().values() if r["name"] != ec.NAME}
    assert used and not used & (set(ec.SEEDS) | set(ec.SELECTION_SEEDS))
    for name in designs.names():
        if name == ec.NAME:
            continue
        design = designs.design(name)
        seeds = set(design.seeds) | {s for c in design.cells for s in (c.seeds or ())}
        assert not seeds & set(ec.SEEDS), name
    assert len(ec.SEEDS) >= 20 and len(set(ec.SEEDS)) == len(ec.SEEDS)


def test_the_ledger_runs_it_reads_are_the_ones_it_names():
    """Every grid point of READ_FROM is held by its table on both grid seeds, with the
    configuration the design builds; no other grid point of the floor and Nao-like SARSA
    learners is held on both seeds by an earlier table (so nothing the ledger holds is
    computed again, and nothing is read that is not named)."""
    runs = _runs()
    manifest = json.loads((REPO / "ledger" / "manifest.json").read_text())
    held = {}
    for r in runs.values():
        if r["name"] == ec.NAME:
            continue
        config = dict(manifest["configs"][r["config"]])
        name = config.pop("name")
        held.setdefault((json.dumps(config, sort_keys=True), r["seed"]), set()).add(name)
    for c in ec.DESIGN.cells:
        config = c.config.to_dict()
        name = config.pop("name")
        found = [held.get((json.dumps(config, sort_keys=True), s), set()) for s in ec.GRID_SEEDS]
        if name != ec.NAME:
            assert all(name in f for f in found), c.key
        elif c["learner"] != "ppo" and c["world"] != "sideboard":
            assert not all(found), (c.key, found)
    assert sum(c.config.name != ec.NAME for c in ec.DESIGN.cells) == 137


def test_the_grid_is_the_same_shape_for_every_learner():
    cells = ec.DESIGN.cells
    for world in ec.WORLDS:
        for learner in ec.LEARNERS:
            mine = [c for c in cells if c["world"] == world and c["learner"] == learner]
            assert len(mine) == ec.GRID_ROWS * ec.GRID_COLS
            assert {(c["row"], c["col"]) for c in mine} == {
                (r, k) for r in range(ec.GRID_ROWS) for k in range(ec.GRID_COLS)
            }
            assert all(c.seeds == ec.GRID_SEEDS for c in mine)
    paper = {c["beta_a_train"] for c in cells if c["learner"] == "paper"}
    assert paper == {1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0}
    assert {c["eps_w"] for c in cells if c["learner"] == "paper"} == {0.05, 0.15, 0.5, 1.5, 5.0}
    assert {c["eps_q"] for c in cells if c["learner"] == "linear"} == {0.01, 0.03, 0.1, 0.3, 1.0}
    assert {c["rollouts"] for c in cells if c["learner"] == "ppo"} == {8, 16, 32, 64, 128}
    assert all(c.config.steps == 50_000 for c in cells if c["learner"] == "ppo")


class _Fake:
    """Results of the procedure's stages with chosen scores (what the stage functions read)."""

    def __init__(self, scores):
        self.cells, self._scores = [], {}
        for (world, learner, point, stage), values in scores.items():
            seeds = ec.SELECTION_SEEDS if stage == "selection" else ec.GRID_SEEDS
            c = ec.SEARCH.cell(world, learner, point, stage, seeds)
            self.cells.append(c)
            self._scores[c.key] = np.asarray(values, float)

    def score(self, key):
        return self._scores[key]


def _grid(world, learner, best, value=0.9):
    """A grid whose scores fall with the distance from ``best``."""
    return {
        (world, learner, (r, c), "grid"): [value - 0.01 * (abs(r - best[0]) + abs(c - best[1]))] * 2
        for r in range(ec.GRID_ROWS)
        for c in range(ec.GRID_COLS)
    }


def test_an_edge_best_gets_the_rungs_beyond_it_first_and_every_learner_as_many():
    scores = {}
    for world in ec.WORLDS:
        scores |= _grid(world, "paper", (8, 2))  # on the top row: beta_a 500
        scores |= _grid(world, "linear", (4, 2))  # interior
        scores |= _grid(world, "ppo", (0, 4))  # a corner
    new = ec.SEARCH.extension(1)(_Fake(scores))
    for world in ec.WORLDS:
        for learner in ec.LEARNERS:
            mine = [c for c in new if c["world"] == world and c["learner"] == learner]
            assert len(mine) == ec.EXTENSION_POINTS
    floor = [(c["row"], c["col"]) for c in new if c["world"] == "floor"]
    assert floor[0] == (9, 2)  # beta_a 1000, above the paper's best
    ppo = [(c["row"], c["col"]) for c in new if c["world"] == "floor" and c["learner"] == "ppo"]
    assert ppo[:2] == [(-1, 4), (0, 5)]  # below the lowest learning rate, beyond 128 rollouts
    assert all(c["stage"] == "extension-1" and c.seeds == ec.GRID_SEEDS for c in new)


def test_only_bracketed_points_are_candidates():
    scores = _grid("floor", "paper", (8, 2))
    fake = _Fake(scores)
    points = ec.SEARCH.searched(fake, "floor", "paper")
    assert not ec.SEARCH.bracketed(points, "floor", "paper", (8, 2))
    found = ec.SEARCH.candidates(fake, "floor", "paper")
    assert (8, 2) not in found and found[0] == (7, 2) and len(found) == ec.TOP_K
    scores[("floor", "paper", (9, 2), "extension-1")] = [0.95, 0.95]
    scores[("floor", "paper", (9, 1), "extension-2")] = [0.5, 0.5]
    scores[("floor", "paper", (9, 3), "extension-2")] = [0.5, 0.5]
    scores[("floor", "paper", (10, 2), "extension-3")] = [0.5, 0.5]
    assert ec.SEARCH.candidates(_Fake(scores), "floor", "paper")[0] == (9, 2)


def test_a_rung_beyond_a_limit_is_never_searched():
    assert not ec.SEARCH.valid("floor", "ppo", (0, 6))  # 512 rollouts
    assert not ec.SEARCH.valid("floor", "ppo", (0, -4))  # half a rollout
    assert not ec.SEARCH.valid("floor", "ppo", (18, 0))  # a learning rate of 5
    assert not ec.SEARCH.valid("floor", "linear", (0, 5))  # eps_Q 3: amendment 1
    assert ec.SEARCH.valid("floor", "linear", (0, 4))  # eps_Q 1
    assert ec.COL_LADDERS["linear"].value(1) == 0.03 and ec.COL_LADDERS["paper"].value(3) == 1.5


def test_the_chosen_setting_is_the_best_on_the_selection_seeds():
    scores = {
        ("floor", "paper", (4, 2), "selection"): [0.90] * 4,
        ("floor", "paper", (5, 2), "selection"): [0.93] * 4,
        ("floor", "paper", (4, 1), "selection"): [0.93] * 4,
    }
    assert ec.SEARCH.chosen(_Fake(scores), "floor", "paper") == (5, 2)


def _pairs(shift, spread=0.01, n=20, seed=0):
    rng = np.random.default_rng(seed)
    paper = rng.uniform(0.88, 0.96, n)
    return paper + shift + rng.normal(0, spread, n), paper


def test_the_verdicts_say_each_outcome():
    found = ec.judgement(
        {
            "same": _pairs(0.0),
            "ahead": _pairs(0.03),
            "far": _pairs(0.10),
            "noisy": _pairs(0.02, spread=0.15),
        }
    )
    assert found["same"]["lead_verdict"] == "no lead shown"
    assert found["same"]["noninferiority"] == "non-inferior"
    assert found["same"]["equivalence"] == "equivalent"
    assert found["ahead"]["lead_verdict"] == "linear SARSA ahead"
    assert found["ahead"]["noninferiority"] == "non-inferior"
    assert found["far"]["noninferiority"] == "inferior by more than the margin"
    assert found["far"]["equivalence"] == "equivalence not shown"
    assert found["noisy"]["noninferiority"] == "undecided"
    assert found["noisy"]["equivalence"] == "equivalence not shown"
    behind = ec.judgement({"w": _pairs(-0.03), "v": _pairs(0.0, seed=1)})
    assert behind["w"]["lead_verdict"] == "the paper's learner ahead"
    low, high = found["ahead"]["low"], found["ahead"]["high"]
    assert low < found["ahead"]["lead"] < high
    assert found["far"]["failure_ratio"] > 1


def test_the_verdicts_are_holm_adjusted_over_the_worlds():
    import scipy.stats as sps

    pairs = {"a": _pairs(0.01, seed=2), "b": _pairs(0.005, seed=3), "c": _pairs(0.0, seed=4)}
    found = ec.judgement(pairs)
    raw = [sps.ttest_1samp(pairs[w][0] - pairs[w][1], 0).pvalue for w in pairs]
    assert min(found[w]["p_lead"] for w in pairs) == pytest.approx(3 * min(raw))
    assert all(found[w]["p_lead"] >= r for w, r in zip(pairs, raw, strict=True))


def _from_ledger(monkeypatch):
    """The equal contest's results, read from the committed ledger, never computed."""
    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    return ec.DESIGN.read()


@pytest.mark.slow
def test_every_learner_spent_the_same_selection_runs_in_every_world(monkeypatch):
    """Counted from the ledger's runs: the same grid, extension and selection runs for every
    learner and world (132), the same judged seeds (20)."""
    from docking.study.designs import equal_contest_report as ecr

    results = _from_ledger(monkeypatch)
    spent = ecr.spent(results)
    assert set(spent) == {(w, learner) for w in ec.WORLDS for learner in ec.LEARNERS}
    assert {tuple(s.values()) for s in spent.values()} == {(90, 30, 12, 20)}
    assert ec.SEARCH.runs_per_learner() == 132


@pytest.mark.slow
def test_every_chosen_value_is_bracketed_by_the_search_or_by_a_limit(monkeypatch):
    """No search stopped short: for each chosen point, each knob's rungs on both sides were
    searched on the grid seeds (the value is interior: strictly inside the values its knob
    took), or one side is beyond a limit of the rules (not a valid configuration) and the
    other was searched. Which chosen values sit at a limit is said, not hidden (notebook 07:
    ecr.limits_sentence); this was written after the grid's runs were seen and before any
    selection or judged run, when the grid put linear SARSA's floor-world best at eps_Q 1, the
    last rung below its limit."""
    from docking.study.designs import equal_contest_report as ecr

    results = _from_ledger(monkeypatch)
    found = ecr.bracketing(results)
    assert len(found) == len(ec.WORLDS) * len(ec.LEARNERS)
    assert all(how != "edge" for fields in found.values() for how in fields.values()), found
    assert ecr.interior(results) == {
        k: all(how == "interior" for how in v.values()) for k, v in found.items()
    }
    for (world, learner), setting in ecr.chosen(results).items():
        e = ec.SEARCH.entrants[learner]
        searched = ec.SEARCH.searched(results, world, learner)
        point = ec.SEARCH.chosen(results, world, learner)
        for knob, axis in ((e.row, 0), (e.col, 1)):
            took = {knob.ladder.value(p[axis]) for p in searched}
            value = setting[knob.field]
            if found[world, learner][knob.field] == "interior":
                assert min(took) < value < max(took)
            else:  # at a limit: the rung beyond it, on one side, is no valid configuration
                beyond = [knob.ladder.value(point[axis] + d) for d in (1, -1)]
                assert None in beyond and min(took) <= value <= max(took)


def _as_committed():
    """The equal contest's module as its rules' commit held it (the source the record's
    verbatim copy is taken from), executed apart from the package, with amendment 1 applied
    to its ladders."""
    import dataclasses
    import sys
    import types

    source = subprocess.run(
        ["git", "show", f"{RULES_COMMIT}:docking/study/designs/equal_contest.py"],
        cwd=REPO,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    module = types.ModuleType("equal_contest_as_committed")
    sys.modules[module.__name__] = module
    try:
        exec(compile(source, f"{RULES_COMMIT}:equal_contest.py", "exec"), module.__dict__)
    finally:
        del sys.modules[module.__name__]
    (amendment,) = records.amendments(ec.NAME)
    assert amendment["path"][:3] == ["constants", "ladders", "linear"]
    ladder = module.COL_LADDERS["linear"]
    module.COL_LADDERS["linear"] = dataclasses.replace(ladder, upper=amendment["after"])
    return module


@pytest.mark.slow
def test_the_committed_procedure_walks_the_live_cells_and_reaches_its_verdicts(monkeypatch):
    """Replayed on the ledger's runs, the procedure as committed (with its amendment) asks for
    exactly the live design's cells, stage by stage, configurations and seeds alike, and its
    verdict functions reach the live verdicts: the live code (docking.study.designs.search)
    is the committed procedure rewritten, not another one."""
    from docking.study import design
    from docking.study.designs import equal_contest_report as ecr

    committed = _as_committed()
    live = _from_ledger(monkeypatch)
    d = committed.DESIGN
    found = design._walk(d, d.select(False), lambda new, _: design._loaded(d, new), None)[1]
    assert [(c.key, c.config, c.seeds) for c in found.cells] == [
        (c.key, c.config, c.seeds) for c in live.cells
    ]
    found = ecr.judged(live)
    pairs = {w: (found[w]["linear"], found[w]["paper"]) for w in ec.WORLDS}
    # the live code names the pair's means "first" and "second" (search.judgement serves any
    # two learners) where the committed module said "linear" and "paper"; every value equal
    renamed = {"linear": "first", "paper": "second"}
    said = {
        w: {renamed.get(k, k): v for k, v in found.items()}
        for w, found in committed.judgement(pairs).items()
    }
    assert said == ecr.verdicts(live)
