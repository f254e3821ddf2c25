"""The configurations ``python -m docking run NAME`` (and ``sweep NAME``) names besides the
paper's two experiments (:data:`docking.presets.EXPERIMENTS`): Experiment 2 in the study's
worlds, with the paper's learner at its published settings and with the tuned learners.

* ``floor``, ``nao``: Experiment 2 (its network, trials, test and a curriculum grown as in
  :func:`docking.study.designs.builders.experiment2_in`) in the floor world
  (:data:`docking.presets.FLOOR_WORLD`) or the Nao-like world
  (:data:`docking.presets.NAO_WORLD`): :func:`published`.
* ``floor-tuned``, ``nao-tuned``: the same with the paper's learner at the tuned settings
  currently published; ``floor-linear``, ``nao-linear``: with linear SARSA at its
  (:func:`docking.study.designs.builders.linear_sarsa`): :func:`tuned`, from the one table
  :data:`TUNED` (the design that chose them, and their values).

Each is judged as ``run experiment2`` is (its test trials); ``--heldout-trials 500
--test-trials 0`` judges it as the study's runs are. Each is stored under its own name and
runs for Experiment 2's seeds (:data:`SEEDS`) unless told otherwise.

When a later design's choices are published, :data:`TUNED` is the one place to repoint;
tests/test_cli.py checks it, and these configurations, against the design it names and the
designs' builders. They are written here, not imported from the designs: ``python -m
docking`` builds them each time it starts, and a design file imports SciPy (and a run of a
preset loads no design file, tests/test_layers.py). Not in :mod:`docking.presets`, whose code
keys PPO's runs (it is among the modules :mod:`docking.study.ppo` imports).
"""

from __future__ import annotations

import dataclasses

from docking.experiments import Curriculum, ExperimentConfig
from docking.presets import EXPERIMENT_2, FLOOR_WORLD, NAO_WORLD
from docking.presets import SEEDS as PRESET_SEEDS

__all__ = ["LEARNERS", "SEEDS", "TUNED", "WORLDS", "named", "published", "tuned"]

#: The worlds by the names of their entries, and what the help calls them.
WORLDS = {"floor": ("floor world", FLOOR_WORLD), "nao": ("Nao-like world", NAO_WORLD)}

#: The tuned learners by the suffix of their entries' names: the design's name of the learner
#: (a key of :data:`TUNED`'s settings) and what the help calls it.
LEARNERS = {"tuned": ("paper", "the paper's learner"), "linear": ("linear", "linear SARSA")}

#: The tuned settings currently published: the design that chose them (its name), and its
#: network settings per world and learner (``paper``: the paper's learner; ``linear``: linear
#: SARSA). Those of the bracketing replication
#: (:data:`docking.study.designs.replication.TUNED`, the bracketing continued's last
#: incumbents).
TUNED = (
    "bracketing-replication",
    {
        "floor": {
            "paper": {"eps_q": 0.03, "beta_a_train": 100.0, "eps_w": 0.5},
            "linear": {"eps_q": 0.1, "beta_a_train": 10.0},
        },
        "nao": {
            "paper": {"eps_q": 0.3, "beta_a_train": 50.0, "eps_w": 0.5},
            "linear": {"eps_q": 0.03, "beta_a_train": 10.0},
        },
    },
)

#: The seeds an entry runs for by default: Experiment 2's.
SEEDS = PRESET_SEEDS["experiment2"]


def published(world: str, name: str | None = None) -> ExperimentConfig:
    """Experiment 2 in ``world`` (``"floor"`` or ``"nao"``), the paper's learner at its
    published settings, stored under ``name`` (default: the world's): its curriculum starts
    0.12 m beyond the start region's near edge and grows over 1400 trials, as
    :func:`docking.study.designs.builders.experiment2_in`'s."""
    found = WORLDS[world][1]
    curriculum = Curriculum(far_initial=found.start_near + 0.12, grow_trials=1400)
    name = world if name is None else name
    return dataclasses.replace(EXPERIMENT_2, name=name, world=found, curriculum=curriculum)


def tuned(world: str, learner: str) -> ExperimentConfig:
    """:func:`published` with ``learner`` (``"paper"`` or ``"linear"``: one feature unit per
    input and no feature layer, as :func:`docking.study.designs.builders.linear_sarsa`) at its
    tuned settings (:data:`TUNED`), stored under its entry's name (``floor-tuned``,
    ``nao-linear``, ...)."""
    suffix = next(k for k, (name, _) in LEARNERS.items() if name == learner)
    base = published(world, f"{world}-{suffix}")
    settings = dict(TUNED[1][world][learner])
    if learner == "linear":
        settings.update(n_features=base.network.n_inputs, feature_layer="none")
    return dataclasses.replace(base, network=dataclasses.replace(base.network, **settings))


def named() -> dict[str, tuple[ExperimentConfig, str]]:
    """``{name: (its configuration, what it is in a line)}`` of every entry, world by world."""
    found = {}
    for world, (words, _) in WORLDS.items():
        found[world] = (published(world), f"the paper's learner, published settings, {words}")
        for suffix, (learner, who) in LEARNERS.items():
            what = f"{who}, tuned ({TUNED[0]}), {words}"
            found[f"{world}-{suffix}"] = (tuned(world, learner), what)
    return found
