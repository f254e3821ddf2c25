"""The docking library, in one import: what a user needs to build a world, run a learner in it
and look at one run. It is the top level of the package, ``docking/``; the *study layer*, the
machinery that asks the paper's questions of many runs (the results store and ledger, sweeps,
designs, claims, statistics, the contest, the report, the figures and the command line), is
the folder ``docking/study/``.

    from docking.core import DockingEnv, WorldConfig, EXPERIMENT_2, run_experiment

    env = DockingEnv(WorldConfig(), seed=0)  # a dm_env.Environment
    result = run_experiment(EXPERIMENT_2, seed=0)  # one run of the paper's learner

The core's modules (docs/guide/layers.md draws the two layers):

- the world: :mod:`~docking.scene` (``WorldConfig``, the action sets), :mod:`~docking.world`
  (``DockingEnv``), :mod:`~docking.camera`, :mod:`~docking.render`, :mod:`~docking.region`;
- the model: :mod:`~docking.network` (Eq. 1-16), :mod:`~docking.trial` (one SARSA trial);
- experiments: :mod:`~docking.experiments` (``run_experiment``), :mod:`~docking.presets`,
  :mod:`~docking.policies` and :mod:`~docking.oracle` (the yardsticks);
- any learner: :mod:`~docking.protocol` (its streams, worlds and held-out judgement);
- Gymnasium: :mod:`~docking.gym` and :mod:`~docking.gym_ids`;
- their helpers: :mod:`~docking.validate`, :mod:`~docking.arith`, :mod:`~docking.glenv`,
  :mod:`~docking.fileio`.

An import-linter contract ("the core never imports the study layer", run by ``make check``)
keeps the core free of the study: no module of the top level imports ``docking.study``,
directly or through another module. This module imports the core only, and no module of the
package imports it.

Why the core stays at the top level rather than moving into a folder of its own: a stored run
is keyed by the code that computed it, module by module under its name
(:mod:`docking.study.fingerprint`), so moving ``docking/world.py`` to ``docking/core/world.py``
would re-key every stored run of the paper's learner and every row of the committed ledger
for no change of a single number. The study layer's modules key no learner's run (PPO's runs,
keyed by ``docking.study.ppo``, were migrated when it moved: ``python -m docking ledger
migrate``).
"""

from __future__ import annotations

from docking import policies
from docking.camera import CameraConfig, preprocess
from docking.experiments import (
    Curriculum,
    ExperimentConfig,
    ExperimentResult,
    TrialLog,
    heldout_trials,
    run_experiment,
)
from docking.gym import DockingGymEnv
from docking.network import RULES, Network, NetworkConfig
from docking.oracle import oracle_action
from docking.policies import run_episode
from docking.presets import EXPERIMENT_1, EXPERIMENT_2, FLOOR_WORLD, NAO_WORLD, SEEDS
from docking.protocol import LearnerResult, heldout_env, judge, streams, training_env
from docking.region import StartRegion
from docking.scene import ACTION_SETS, Distractor, WorldConfig
from docking.trial import TrialRecord, run_trial
from docking.world import DockingEnv

__all__ = [
    # the world
    "ACTION_SETS",
    "CameraConfig",
    "Distractor",
    "DockingEnv",
    "StartRegion",
    "WorldConfig",
    "preprocess",
    # the model
    "RULES",
    "Network",
    "NetworkConfig",
    "TrialRecord",
    "run_trial",
    # experiments and yardsticks
    "Curriculum",
    "EXPERIMENT_1",
    "EXPERIMENT_2",
    "ExperimentConfig",
    "ExperimentResult",
    "FLOOR_WORLD",
    "NAO_WORLD",
    "SEEDS",
    "TrialLog",
    "heldout_trials",
    "oracle_action",
    "policies",
    "run_episode",
    "run_experiment",
    # any learner
    "LearnerResult",
    "heldout_env",
    "judge",
    "streams",
    "training_env",
    # Gymnasium
    "DockingGymEnv",
]
