"""What makes it learn: the paper's claims as variants of its experiments (notebook 05).

Every *cell* of the study is an :class:`~docking.experiments.ExperimentConfig` (a variant of
Experiment 1 or 2, in the sideboard world or the floor world) run for :data:`STUDY_SEEDS`,
each network judged on :data:`HELDOUT_TRIALS` held-out trials: start poses, step noise and
action draws from random streams that training, the learning curve and the main test never
use (``ExperimentConfig.heldout_trials``). The cells are data; running them is
:func:`docking.store.run_seeds` / :mod:`docking.sweep`; the statistics are
:mod:`docking.stats`; the verdicts are asserted in the notebook.

Choices named here:

* Exp. 2 variants keep the paper's 2000 training trials; they skip the final 725-trial test
  (``test_trials = 0``: the held-out trials are the measure) and the learning curve, except
  the three curriculum cells, whose curves are part of the claim.
* ``beta_s`` 10 and 30: the rule absorbs the exact gradient's factor ``beta_s`` into
  ``eps_w`` (notebook 01), so the gradient step is ``eps_w / beta_s``; these cells keep it at
  the paper configuration's ``0.05 / 100`` (``eps_w = 0.005`` and ``0.015``).
* The unmodulated control replaces delta in Eq. (8) by a constant equal to the mean
  ``|delta|`` of the paper configuration's training steps (measured, passed in).
* The two-stage learner pre-trains W on the frames of 200 random-walk trials (about 3000
  frames) by winner-take-all competitive learning (rate 0.05), then runs SARSA with W frozen.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.experiments import (
    EXPERIMENT_1,
    EXPERIMENT_2,
    FLOOR_WORLD,
    Curriculum,
    ExperimentConfig,
    ExperimentResult,
)
from docking.network import NetworkConfig
from docking.world import Distractor, WorldConfig

__all__ = [
    "Cell",
    "HELDOUT_TRIALS",
    "STUDY_SEEDS",
    "cells",
    "control_cell",
    "heldout_success",
    "mean_abs_delta",
]

#: Seeds of every cell (verdicts rest on them: at least ten).
STUDY_SEEDS = tuple(range(10))

#: Held-out greedy trials per network.
HELDOUT_TRIALS = 500

#: The red cup of the distractor cells: on the sideboard 0.3 m to the landmark's left (in the
#: floor world on the floor, at the same place).
_CUP = Distractor.cup(y=0.30)
_FLOOR_CUP = Distractor("cylinder", _CUP.size, (_CUP.position[0], 0.30, _CUP.size[1]))


@dataclasses.dataclass(frozen=True)
class Cell:
    """One variant of the study.

    Attributes:
      key: Short identifier (``"frozen"``, ``"floor/local"``, ...).
      claim: Which claim of the paper it tests (a key of the notebook's claim table).
      label: What it is, for tables and figures.
      config: The run; ``config.heldout_world`` is where its networks are judged.
      baseline: The key of the cell it is compared with (the paper's configuration in the same
        world and experiment), or None for that cell itself.
    """

    key: str
    claim: str
    label: str
    config: ExperimentConfig
    baseline: str | None


def _variant(base: ExperimentConfig, name: str, curve: bool = False, **changes):
    """``base`` as a study run: held-out trials, no final test, a curve only if asked."""
    settings = dict(heldout_trials=HELDOUT_TRIALS, test_trials=0, eval_trials=50 if curve else 0)
    return dataclasses.replace(base, name=name, **settings, **changes)


def _net(base: ExperimentConfig, **changes) -> NetworkConfig:
    return dataclasses.replace(base.network, **changes)


def _with_cup(world: WorldConfig) -> WorldConfig:
    cup = _CUP if world.scene == "sideboard" else _FLOOR_CUP
    return dataclasses.replace(world, distractors=(cup,))


def _experiment2_cells(world_key: str, base: ExperimentConfig, full: bool) -> list[Cell]:
    """The Experiment 2 variants in one world (``full``: all of them; else the key ones)."""
    p = f"{world_key}/" if world_key != "sideboard" else ""
    name = f"study-{world_key}"
    paper = f"{p}paper"
    near = base.curriculum.far_initial
    cup_world = _with_cup(base.world)
    out = [
        Cell(
            paper,
            "features",
            "the paper's rule (Eq. 8, non-local)",
            _variant(base, name, True),
            None,
        ),
        Cell(
            f"{p}frozen",
            "features",
            "W frozen (eps_W = 0)",
            _variant(base, name, network=_net(base, eps_w=0.0)),
            paper,
        ),
        Cell(
            f"{p}local",
            "features",
            "local rule (Eq. 8 without the bracket)",
            _variant(base, name, network=_net(base, rule="local")),
            paper,
        ),
        Cell(
            f"{p}none",
            "curriculum",
            "no curriculum (full region from trial 0)",
            _variant(base, name, True, curriculum=Curriculum(near, grow_trials=0)),
            paper,
        ),
        Cell(
            f"{p}near-only",
            "curriculum",
            f"trained only near ({base.world.start_near:.2f}-{near:.2f} m)",
            _variant(base, name, True, curriculum=Curriculum(near, grow_trials=0, far_final=near)),
            paper,
        ),
        Cell(
            f"{p}no-yaw-noise",
            "rotation",
            "tested without heading noise (0 deg per step)",
            _variant(
                base, name, heldout_world=dataclasses.replace(base.world, step_noise_yaw_deg=0.0)
            ),
            paper,
        ),
        Cell(
            f"{p}cup-test",
            "distractor",
            "red cup at test only",
            _variant(base, name, heldout_world=cup_world),
            paper,
        ),
        Cell(
            f"{p}cup",
            "distractor",
            "red cup in training and test",
            _variant(base, name, world=cup_world),
            paper,
        ),
        Cell(
            f"{p}cup-frozen",
            "distractor",
            "red cup in training and test, W frozen",
            _variant(base, name, world=cup_world, network=_net(base, eps_w=0.0)),
            paper,
        ),
    ]
    if full:
        eps_w = base.network.eps_w
        out += [
            Cell(
                f"{p}epsW-x10",
                "features",
                f"eps_W x10 ({10 * eps_w:g})",
                _variant(base, name, network=_net(base, eps_w=10 * eps_w)),
                paper,
            ),
            Cell(
                f"{p}beta-10",
                "features",
                "beta_s = 10 (eps_W = 0.005)",
                _variant(
                    base,
                    name,
                    network=_net(base, beta_s=10.0, eps_w=eps_w * 10 / base.network.beta_s),
                ),
                paper,
            ),
            Cell(
                f"{p}beta-30",
                "features",
                "beta_s = 30 (eps_W = 0.015)",
                _variant(
                    base,
                    name,
                    network=_net(base, beta_s=30.0, eps_w=eps_w * 30 / base.network.beta_s),
                ),
                paper,
            ),
            Cell(
                f"{p}two-stage",
                "alternative",
                "two-stage: competitive features first, then SARSA",
                _variant(base, name, network=_net(base, eps_w=0.0), pretrain_trials=200),
                paper,
            ),
            Cell(
                f"{p}linear",
                "alternative",
                "linear SARSA on the 320 pixels",
                _variant(
                    base,
                    name,
                    network=_net(base, n_features=base.network.n_inputs, feature_layer="none"),
                ),
                paper,
            ),
        ]
    return out


def _experiment1_cells() -> list[Cell]:
    base, name = EXPERIMENT_1, "study-experiment1"
    return [
        Cell(
            "exp1/local",
            "features",
            "Exp. 1, local rule (the paper's)",
            _variant(base, name, True),
            None,
        ),
        Cell(
            "exp1/frozen",
            "features",
            "Exp. 1, W frozen",
            _variant(base, name, True, network=_net(base, eps_w=0.0)),
            "exp1/local",
        ),
        Cell(
            "exp1/nonlocal",
            "features",
            "Exp. 1, non-local rule",
            _variant(base, name, True, network=_net(base, rule="nonlocal")),
            "exp1/local",
        ),
    ]


#: Experiment 2 in the floor world: the paper's configuration, its curriculum starting 0.12 m
#: beyond the start region's near edge as in the sideboard world.
FLOOR_EXPERIMENT_2 = dataclasses.replace(
    EXPERIMENT_2,
    name="experiment2-floor",
    world=FLOOR_WORLD,
    curriculum=Curriculum(far_initial=FLOOR_WORLD.start_near + 0.12, grow_trials=1400),
)


def cells() -> list[Cell]:
    """Every cell but the unmodulated control (:func:`control_cell`, which needs a measured
    constant): Experiment 2 in the sideboard world (all variants), Experiment 1, Experiment 2
    in the floor world (the key variants)."""
    return (
        _experiment2_cells("sideboard", EXPERIMENT_2, full=True)
        + _experiment1_cells()
        + _experiment2_cells("floor", FLOOR_EXPERIMENT_2, full=False)
    )


def control_cell(constant: float) -> Cell:
    """Eq. (8) with delta replaced by ``constant`` (the paper configuration's mean |delta|)."""
    base = EXPERIMENT_2
    return Cell(
        "constant-delta",
        "delta",
        f"Eq. 8 with a constant {constant:.3g} in place of delta",
        _variant(base, "study-sideboard", network=_net(base, feature_delta=float(constant))),
        "paper",
    )


def mean_abs_delta(results: list[ExperimentResult]) -> float:
    """The mean |delta| over every training step of ``results``."""
    return float(np.mean(np.abs(np.concatenate([r.train.deltas for r in results]))))


def heldout_success(results: list[ExperimentResult]) -> np.ndarray:
    """Per seed, the held-out success rate."""
    return np.array([r.heldout.success_rate for r in results])
