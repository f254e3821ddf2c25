"""The fragility landscape (docking.study.designs.landscape): its rules pinned before its runs; its
list of grid points to fill is the ledger's sparse ones; its cells are the tuning runs'
configurations at those points."""

from __future__ import annotations

import dataclasses
import json
from collections import Counter
from pathlib import Path

from docking.study.designs import addendum as ad
from docking.study.designs import landscape as ls
from docking.study.designs import replication as rp

REPO = Path(__file__).resolve().parents[1]


def _counts() -> Counter:
    """Runs per configuration (its name left out) in the committed ledger, but this design's."""
    data = json.loads((REPO / "ledger" / "manifest.json").read_text())
    found = Counter()
    for record in data["runs"].values():
        if record["name"] in (ls.NAME, "equal-contest"):
            continue  # this design's, and the equal contest's (run later, filling its grid)
        config = dict(data["configs"][record["config"]])
        config.pop("name")
        found[json.dumps(config, sort_keys=True)] += 1
    return found


def test_the_missing_points_are_the_grid_points_the_ledger_has_too_few_runs_of():
    counts = _counts()
    for world in ls.WORLDS:
        for learner in ("paper", "linear"):
            sparse = []
            for point in ls.grid(world, learner):
                config = ad.learner_config(world, learner, **ls.setting(world, learner, *point))
                config = config.to_dict()
                config.pop("name")
                if counts[json.dumps(config, sort_keys=True)] < ls.MIN_RUNS:
                    sparse.append(point)
            assert tuple(sparse) == ls.MISSING[world][learner], (world, learner)


def test_each_cell_is_the_tuning_runs_configuration_renamed():
    for cell in ls.DESIGN.cells:
        world, learner = cell["world"], cell["learner"]
        knobs = {k: cell.coords[k] for k in ad.KNOBS[learner]}
        expected = ad.learner_config(world, learner, **knobs)
        assert cell.config == dataclasses.replace(expected, name=ls.NAME)
        if learner == "paper":
            assert knobs["eps_q"] == rp.TUNED[world]["paper"]["eps_q"]
        assert cell.seeds == ls.SEEDS
