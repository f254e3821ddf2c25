"""The fragility landscape (issue 50): how much of the tuning knobs' range docks well, for
the paper's learner and for linear SARSA, in the floor and Nao-like worlds. Descriptive: it
judges nothing; it fills the grid the tuning runs left sparse, so that a reader sees where
the tuned settings sit and how far the published one is from them.

The grid (fixed before its runs):

* the paper's learner: the training temperature beta_a (:data:`BETA_A`) x eps_W
  (:data:`EPS_W`), at its tuned eps_Q in each world
  (:data:`docking.study.designs.replication.TUNED`);
* linear SARSA: beta_a x eps_Q (:data:`EPS_Q`).

Every grid point the ledger holds fewer than :data:`MIN_RUNS` runs of (a run of the same
configuration under any name: the third edition's, the addendum's, the bracketing's) gets
:data:`SEEDS`, the first two of the seeds the bracketing compared settings on, listed in
:data:`MISSING` (a test checks the list against the ledger). The landscape then reads every
run of each grid point, whatever table holds it (its per-seed mean, with n).

Budget: about 200 runs, 1.5 h of one process. Cut: beta_a 0.5 (the ladder's lowest rung,
actions nearly uniform at Q's scale) and eps_W above 5.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np

from docking.study.design import Cell, Design
from docking.study.designs import addendum as ad
from docking.study.designs import replication as rp

NAME = "fragility-landscape"
#: The seeds of a grid point the ledger lacks (the bracketing's first two compared seeds).
SEEDS = (5900, 5901)
#: A grid point with fewer runs than this in the ledger gets :data:`SEEDS`.
MIN_RUNS = 2
BETA_A = (1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0)
EPS_W = (0.05, 0.15, 0.5, 1.5, 5.0)
EPS_Q = (0.01, 0.03, 0.1, 0.3, 1.0)
WORLDS = ("floor", "nao")

#: The grid points the ledger held fewer than :data:`MIN_RUNS` runs of when these rules were
#: committed: ``{world: {learner: ((beta_a, the other knob), ...)}}`` (eps_W for the paper's
#: learner, eps_Q for linear SARSA).
MISSING = {
    "floor": {
        "paper": (
            (1.0, 0.05),
            (1.0, 0.15),
            (1.0, 0.5),
            (1.0, 1.5),
            (1.0, 5.0),
            (2.0, 1.5),
            (2.0, 5.0),
            (5.0, 0.05),
            (5.0, 0.15),
            (5.0, 1.5),
            (5.0, 5.0),
            (10.0, 0.05),
            (10.0, 0.15),
            (10.0, 0.5),
            (10.0, 5.0),
            (20.0, 0.05),
            (20.0, 0.15),
            (20.0, 1.5),
            (20.0, 5.0),
            (50.0, 0.05),
            (50.0, 5.0),
            (100.0, 0.05),
            (100.0, 5.0),
        ),
        "linear": (
            (1.0, 0.01),
            (1.0, 0.03),
            (1.0, 0.1),
            (1.0, 0.3),
            (1.0, 1.0),
            (2.0, 0.01),
            (2.0, 1.0),
            (5.0, 0.01),
            (5.0, 1.0),
            (10.0, 0.01),
            (10.0, 1.0),
            (20.0, 0.01),
            (20.0, 0.03),
            (20.0, 0.3),
            (20.0, 1.0),
            (50.0, 0.01),
            (50.0, 0.03),
            (50.0, 0.1),
            (50.0, 0.3),
            (50.0, 1.0),
            (100.0, 0.01),
            (100.0, 0.03),
            (100.0, 0.1),
            (100.0, 0.3),
            (100.0, 1.0),
        ),
    },
    "nao": {
        "paper": (
            (1.0, 0.05),
            (1.0, 0.15),
            (1.0, 0.5),
            (1.0, 1.5),
            (1.0, 5.0),
            (2.0, 0.05),
            (2.0, 0.15),
            (2.0, 5.0),
            (5.0, 0.05),
            (5.0, 0.5),
            (5.0, 1.5),
            (5.0, 5.0),
            (10.0, 0.05),
            (10.0, 0.15),
            (10.0, 1.5),
            (10.0, 5.0),
            (20.0, 0.05),
            (20.0, 0.15),
            (20.0, 1.5),
            (20.0, 5.0),
            (50.0, 0.05),
            (50.0, 5.0),
            (100.0, 0.05),
            (100.0, 0.15),
            (100.0, 1.5),
            (100.0, 5.0),
        ),
        "linear": (
            (1.0, 0.01),
            (1.0, 0.03),
            (1.0, 0.1),
            (1.0, 0.3),
            (1.0, 1.0),
            (2.0, 0.01),
            (2.0, 1.0),
            (5.0, 0.01),
            (5.0, 1.0),
            (10.0, 1.0),
            (20.0, 0.01),
            (20.0, 0.1),
            (20.0, 0.3),
            (20.0, 1.0),
            (50.0, 0.01),
            (50.0, 0.03),
            (50.0, 0.1),
            (50.0, 0.3),
            (50.0, 1.0),
            (100.0, 0.01),
            (100.0, 0.03),
            (100.0, 0.1),
            (100.0, 0.3),
            (100.0, 1.0),
        ),
    },
}


def setting(world: str, learner: str, beta_a: float, other: float) -> dict:
    """The knobs of grid point ``(beta_a, other)`` of ``learner`` in ``world``."""
    if learner == "paper":
        eps_q = rp.TUNED[world]["paper"]["eps_q"]
        return {"eps_q": eps_q, "beta_a_train": beta_a, "eps_w": other}
    return {"eps_q": other, "beta_a_train": beta_a}


def grid(world: str, learner: str) -> list[tuple[float, float]]:
    """Every grid point of ``learner`` (``(beta_a, eps_W or eps_Q)``), row by row."""
    return [(b, o) for b in BETA_A for o in (EPS_W if learner == "paper" else EPS_Q)]


def _cell(world: str, learner: str, point: tuple[float, float]) -> Cell:
    knobs = setting(world, learner, *point)
    config = ad.learner_config(world, learner, **knobs)
    return Cell(
        f"{world}/{learner}/{ad.tag(knobs)}",
        dataclasses.replace(config, name=NAME),
        {"world": world, "learner": learner, **knobs},
        f"{learner} {ad.tag(knobs)}",
        seeds=SEEDS,
    )


DESIGN = Design(
    name=NAME,
    title="the fragility landscape: the tuning grid filled where the ledger is sparse",
    cells=tuple(
        _cell(w, learner, point)
        for w in WORLDS
        for learner in ("paper", "linear")
        for point in MISSING[w][learner]
    ),
    seeds=SEEDS,
    measure="heldout",
)

#: The constants that are rules (:func:`docking.study.designs.rules_data`).
RULES = "SEEDS MIN_RUNS BETA_A EPS_W EPS_Q WORLDS MISSING".split()


# ------------------------------------------------------------------------------------------
# The landscape, read from the ledger (every table's runs of each setting).
# ------------------------------------------------------------------------------------------

#: The tables whose runs the landscape reads: the tuning searches, their judged runs and this
#: design's. The searched settings (:func:`searched`) are those of the first four.
TUNING_TABLES = (
    "third-edition",
    "third-edition-addendum",
    "addendum-bracketing",
    "addendum-bracketing-continued",
)
TABLES = (*TUNING_TABLES, "bracketing-replication", NAME)
#: The published setting (the paper's beta_a; eps_Q and eps_W are our defaults, the paper
#: gives neither) and its label on the figure.
PUBLISHED = {"eps_q": 0.1, "beta_a_train": 2.0, "eps_w": 0.05}
#: A setting within this margin of the best docks "as well as the best"
#: (:func:`docking.study.designs.landscape_report.shares`).
MARGIN = 0.05


def _key(config: dict) -> str:
    return json.dumps({k: v for k, v in config.items() if k != "name"}, sort_keys=True)


def run_scores(tables=TABLES, folder=None) -> dict[str, list[float]]:
    """``{configuration without its name (JSON): each run's held-out success}`` over the
    ledger's runs of ``tables`` (each row checked against its record)."""
    from docking.study import ledger

    data = ledger.manifest(folder)
    found: dict[str, list[float]] = {}
    for name in tables:
        if name not in data["tables"]:
            continue
        for key, cells in ledger.table_rows(data, name).items():
            if "heldout.success" in cells and len(cells["heldout.success"]):
                config = _key(data["runs"][key]["config"])
                found.setdefault(config, []).append(float(np.mean(cells["heldout.success"])))
    return found


def _scores_of(scores: dict, world: str, learner: str, knobs: dict) -> list[float]:
    return scores.get(_key(ad.learner_config(world, learner, **knobs).to_dict()), [])
