"""Experiment 3, beyond the paper: turning actions and precision docking (notebook 06).

The paper blames its failures on rotation that "currently is not compensated" (Sec. III) and
names its next step: "a real-world precision approach including turning of Nao" (Sec. IV).
Do six actions (four steps and two turns) dock better than the paper's four, in the paper's
task and in precision docking, as the heading noise grows? Experiment 3 is Experiment 2
(same world, network, curriculum and trial counts) in a grid of cells over the action set
(:data:`COMPARED`), the task (:data:`TASKS`) and the heading noise (:data:`NOISE_DEG`), each
judged on :data:`~docking.study.designs.builders.HELDOUT_TRIALS` held-out trials of networks of
:data:`~docking.study.designs.builders.SEEDS` (no learning curve, no final test). The cell with
four actions, the paper's task and 2 deg *is* the study's paper configuration (the same
runs); the pose oracle in every cell (:data:`ORACLE`) shows that each is solvable.
"""

from __future__ import annotations

import dataclasses
import itertools

from docking.experiments import ExperimentConfig
from docking.presets import EXPERIMENT_2
from docking.scene import ACTION_SETS, WorldConfig
from docking.study.claims import ShareAbove
from docking.study.design import Cell, Design, yardstick_config
from docking.study.designs.builders import HELDOUT_TRIALS, SEEDS, YARDSTICK_SEEDS, variant

__all__ = [
    "LONGER",
    "LONGER_KEY",
    "NOISE_DEG",
    "ORACLE",
    "PRECISION_DEG",
    "TASKS",
    "cell_key",
    "experiment3_cells",
    "run",
]

#: Heading noise per step (deg): the world's default first, then 4 and 6 deg, fixed from the
#: oracle alone before any learner ran. (The issue asked for 5 and 8 deg; at 8 deg the
#: six-action oracle docks only about 98% of trials, below the 99% that proves a world
#: solvable, and 6 deg is the largest whole value at which it keeps that bound with a margin.)
NOISE_DEG = (2.0, 4.0, 6.0)

#: The precision task's heading tolerance (deg; the issue's example): one turn (``turn_deg``,
#: 10 deg) spans it.
PRECISION_DEG = 10.0

#: The tasks: the paper's (None: the reference point alone) and precision docking.
TASKS = {"paper task": None, "precision": PRECISION_DEG}

#: The action sets compared (keys of :data:`docking.world.ACTION_SETS`).
COMPARED = ("paper", "turning")

#: The extra cell (``python -m docking design run experiment3 --full``; not in ``make
#: reproduce`` or CI): do six actions need more training than the paper's 2000 trials? Six
#: actions in the paper's task at 2 deg, trained this many times as long (the curriculum
#: stretched in proportion).
LONGER = 2

#: The rule for "the reason for most of the unsuccessful trials" (Sec. III): the share of
#: failures removed lies above one half (the studies' rule for the same claim).
ROTATION_RULE = ShareAbove(0.5)

#: Its key.
LONGER_KEY = "6 actions, paper task, 2 deg, trained twice as long"


def cell_key(actions: str, task: str, noise: float) -> str:
    """The key of a cell, e.g. ``"6 actions, precision, 4 deg"``."""
    return f"{len(ACTION_SETS[actions])} actions, {task}, {noise:g} deg"


def world(actions: str, task: str, noise: float, base: WorldConfig | None = None) -> WorldConfig:
    """Experiment 2's world (or ``base``) with the action set, task and heading noise of a
    cell."""
    base = EXPERIMENT_2.world if base is None else base
    return dataclasses.replace(
        base, actions=actions, dock_heading_deg=TASKS[task], step_noise_yaw_deg=float(noise)
    )


def _paper_config() -> ExperimentConfig:
    """The paper's configuration as a study run: Experiment 2 with held-out trials and a
    learning curve, stored with the studies' runs of it."""
    return variant(EXPERIMENT_2, "study-sideboard", True)


def experiment3_cells(full: bool = False) -> list[Cell]:
    """Every cell of Experiment 3 (with ``full``, also the six-action cell trained
    :data:`LONGER` times as long). A six-action cell's baseline is the four-action cell of the
    same task and noise; four-action cells have none."""
    paper = _paper_config()
    found = []
    for task, noise, actions in itertools.product(TASKS, NOISE_DEG, COMPARED):
        key = cell_key(actions, task, noise)
        w = world(actions, task, noise, paper.world)
        if w == paper.world:
            config = paper  # the study's runs
        else:
            config = dataclasses.replace(
                paper,
                name="experiment3",
                world=w,
                network=dataclasses.replace(paper.network, n_actions=w.n_actions),
                eval_trials=0,
            )
        baseline = None if actions == "paper" else cell_key("paper", task, noise)
        label = f"{w.n_actions} actions ({', '.join(w.action_letters)}), {task}, {noise:g} deg"
        coords = {"actions": actions, "task": task, "noise_deg": float(noise), "longer": 1}
        found.append(Cell(key, config, coords, label, baseline, claim="turning"))
    if not full:
        return found
    # Is six actions' deficit a matter of training time? The same cell trained twice as long,
    # its curriculum stretched in proportion.
    six = next(c for c in found if c.key == cell_key("turning", "paper task", NOISE_DEG[0]))
    longer = dataclasses.replace(
        six.config,
        train_trials=LONGER * six.config.train_trials,
        curriculum=dataclasses.replace(
            six.config.curriculum, grow_trials=LONGER * six.config.curriculum.grow_trials
        ),
    )
    label = f"{six.label}, {longer.train_trials} training trials"
    coords = {**six.coords, "longer": LONGER}
    found.append(Cell(LONGER_KEY, longer, coords, label, six.baseline, core=False, claim="turning"))
    return found


#: The seeds whose held-out failures the failure taxonomy pools (notebook 06): the ledger
#: keeps their paths (those of every seed would take 7.7 MB of its 20).
TAXONOMY_SEEDS = SEEDS[:5]

DESIGN = Design(
    name="experiment3",
    title="turning actions and precision docking at three heading noises (beyond the paper)",
    cells=tuple(experiment3_cells(full=True)),
    seeds=SEEDS,
    measure="heldout",
    whole={"6 actions, precision, 2 deg": (0,)},  # notebook 06 draws its network
    keep=frozenset({"paths"}),  # the failure taxonomy ...
    kept_seeds={"paths": TAXONOMY_SEEDS},  # ... of the first five seeds' failures
)

#: The pose oracle (:func:`docking.policies.oracle`, a yardstick run,
#: :func:`docking.study.design.yardstick_config`) in the world of every cell of :data:`DESIGN` but
#: the one trained longer (its world is its six-action cell's), one cell per Experiment 3 cell
#: under the same key: which cells are solvable. For the yardstick seeds
#: (:data:`~docking.study.designs.builders.YARDSTICK_SEEDS`), with
#: :data:`~docking.study.designs.builders.HELDOUT_TRIALS` held-out trials each, the held-out starts
#: of the learners' first seeds.
ORACLE = Design(
    name="experiment3-oracle",
    title="the pose oracle in the world of every cell of Experiment 3",
    cells=tuple(
        Cell(c.key, yardstick_config(c.config, "oracle", HELDOUT_TRIALS), c.coords, c.label)
        for c in experiment3_cells()
    ),
    seeds=YARDSTICK_SEEDS,
    measure="heldout",
)

#: The designs of this file (``python -m docking design run experiment3|experiment3-oracle``).
DESIGNS = {DESIGN.name: DESIGN, ORACLE.name: ORACLE}

#: Run (or load) Experiment 3: :meth:`Design.run` of :data:`DESIGN` (one sweep; stored runs,
#: e.g. the study's paper configuration, are loaded; ``full``: also the cell trained longer).
run = DESIGN.run
