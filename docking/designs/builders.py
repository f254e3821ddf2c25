"""Shared builders of design cells: the held-out protocol, the variants of a configuration,
the distractor, the floor world's Experiment 2 and the yardsticks.

Design files build their cells from these, so that a variant means the same thing in every
design (and two designs asking for the same run share it in the store).
"""

from __future__ import annotations

import dataclasses

from docking.experiments import Curriculum, ExperimentConfig
from docking.network import NetworkConfig
from docking.presets import EXPERIMENT_2, FLOOR_WORLD
from docking.scene import Distractor, WorldConfig

#: Seeds of a cell whose verdicts rest on them (at least ten).
SEEDS = tuple(range(10))

#: Seeds of a yardstick cell (a fixed policy: its spread over seeds is small).
YARDSTICK_SEEDS = tuple(range(5))

#: Held-out greedy trials per network.
HELDOUT_TRIALS = 500

#: The red cup of the distractor cells: on the sideboard 0.3 m to the landmark's left (in the
#: floor world on the floor, at the same place).
CUP = Distractor.cup(y=0.30)
FLOOR_CUP = Distractor("cylinder", CUP.size, (CUP.position[0], 0.30, CUP.size[1]))

#: Experiment 2 in the floor world: the paper's configuration, its curriculum starting 0.12 m
#: beyond the start region's near edge as in the sideboard world.
FLOOR_EXPERIMENT_2 = dataclasses.replace(
    EXPERIMENT_2,
    name="experiment2-floor",
    world=FLOOR_WORLD,
    curriculum=Curriculum(far_initial=FLOOR_WORLD.start_near + 0.12, grow_trials=1400),
)

#: The yardsticks (``ExperimentConfig.policy``) and what tables call them.
YARDSTICK_LABELS = {
    "oracle": "pose oracle",
    "centroid": "centroid rule",
    "forward": "always forward",
    "random": "random",
}


def variant(base: ExperimentConfig, name: str, curve: bool = False, **changes):
    """``base`` as a study run stored under ``name``: :data:`HELDOUT_TRIALS` held-out
    trials, no final test, a learning curve (50 test trials per point) only if ``curve``."""
    settings = dict(heldout_trials=HELDOUT_TRIALS, test_trials=0, eval_trials=50 if curve else 0)
    return dataclasses.replace(base, name=name, **settings, **changes)


def net(base: ExperimentConfig, **changes) -> NetworkConfig:
    """``base``'s network with ``changes``."""
    return dataclasses.replace(base.network, **changes)


def with_cup(world: WorldConfig) -> WorldConfig:
    """``world`` with the red cup (:data:`CUP`, or :data:`FLOOR_CUP` in the floor world)."""
    return dataclasses.replace(
        world, distractors=(CUP if world.scene == "sideboard" else FLOOR_CUP,)
    )
