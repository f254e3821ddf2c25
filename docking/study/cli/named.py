"""An experiment on the command line: the configurations ``python -m docking run NAME`` (and
``sweep NAME``) names (:data:`NAMED`), as tyro's subcommands (:data:`EXPERIMENT`), and the
configuration dataclasses' fields as their options (:func:`as_options`). Imported only by a
command whose options are an experiment's (run and sweep), as they are built.

Besides the paper's two experiments (:data:`docking.presets.EXPERIMENTS`), the names are
Experiment 2 in the study's worlds, with the paper's learner at its published settings and
with the tuned learners.

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
designs' builders. They are written here, not imported from the designs: every run or sweep
command builds them as it starts, and a design file imports SciPy (and a run of a preset
loads no design file, tests/test_layers.py). Not in :mod:`docking.presets`, whose code
keys PPO's runs (it is among the modules :mod:`docking.study.ppo` imports).
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Annotated, Literal, Union

import tyro

from docking.camera import CameraConfig
from docking.experiments import POLICIES, PRETRAIN_RULES, Curriculum, ExperimentConfig
from docking.network import FEATURE_LAYERS, RULES, NetworkConfig
from docking.presets import EXPERIMENT_2, EXPERIMENTS, FLOOR_WORLD, HEADLINE_SEED, NAO_WORLD
from docking.presets import SEEDS as PRESET_SEEDS
from docking.scene import (
    ACTION_SETS,
    DISTRACTOR_SHAPES,
    LANDMARK_SHAPES,
    ROOMS,
    SCENES,
    Distractor,
    WorldConfig,
)
from docking.study.cli import HELP_ALL

__all__ = [
    "CHOICES",
    "COMMON",
    "CONFIGS",
    "EXPERIMENT",
    "HIDDEN",
    "LEARNERS",
    "NAMED",
    "NOTES",
    "SEEDS",
    "TUNED",
    "WORLDS",
    "as_options",
    "named",
    "published",
    "seeds_of",
    "tuned",
]

#: The worlds by the names of their entries, and what the help calls them.
WORLDS = {"floor": ("floor world", FLOOR_WORLD), "nao": ("Nao-like world", NAO_WORLD)}

#: The tuned learners by the suffix of their entries' names: the design's name of the learner
#: (a key of :data:`TUNED`'s settings) and what the help calls it.
LEARNERS = {"tuned": ("paper", "the paper's learner"), "linear": ("linear", "linear SARSA")}

#: The tuned settings currently published: the design that chose them (its name), and its
#: network settings per world and learner (``paper``: the paper's learner; ``linear``: linear
#: SARSA). Those of the equal contest (:func:`docking.study.designs.equal_contest.chosen`:
#: every learner selected alike; tests/test_cli.py reads them from the ledger).
TUNED = (
    "equal-contest",
    {
        "floor": {
            "paper": {"eps_q": 0.03, "beta_a_train": 50.0, "eps_w": 0.5},
            "linear": {"beta_a_train": 10.0, "eps_q": 0.1},
        },
        "nao": {
            "paper": {"eps_q": 0.3, "beta_a_train": 100.0, "eps_w": 1.5},
            "linear": {"beta_a_train": 100.0, "eps_q": 0.3},
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


def _named() -> dict[str, tuple[ExperimentConfig, str, tuple[int, ...]]]:
    """``{name: (configuration, what it is, its seeds)}`` of every configuration ``run`` and
    ``sweep`` name: the paper's experiments (:data:`docking.presets.EXPERIMENTS`, their seeds
    :data:`docking.presets.SEEDS`), then the study's worlds at the paper's published settings
    and with its tuned learners (:func:`named`)."""
    found = {
        name: (
            config,
            f"the paper's {name.replace('experiment', 'Experiment ')}",
            PRESET_SEEDS[name],
        )
        for name, config in EXPERIMENTS.items()
    }
    found.update({n: (c, what, SEEDS) for n, (c, what) in named().items()})
    return found


#: The configurations ``run`` and ``sweep`` name (:func:`_named`).
NAMED = _named()


def seeds_of(name: str) -> tuple[int, ...]:
    """The seeds a configuration called ``name`` runs for by default (a configuration renamed
    with ``--name`` runs for :data:`docking.presets.HEADLINE_SEED`)."""
    return NAMED[name][2] if name in NAMED else (HEADLINE_SEED,)


#: run's and sweep's EXPERIMENT: one subcommand per named configuration, its configuration as
#: the defaults.
EXPERIMENT = Union[  # noqa: UP007 (tyro needs a runtime Union of Annotated members)
    tuple(
        Annotated[
            ExperimentConfig,
            tyro.conf.subcommand(
                name,
                default=config,
                description=f"{what}. --help: common options, {HELP_ALL} every one.",
            ),
        ]
        for name, (config, what, _) in NAMED.items()
    )
]


# The configuration fields whose value is one of a few names (checked by check_choice in
# their __post_init__, which a test compares with this table): tyro shows them as choices and
# refuses any other value in one line. The dataclasses keep plain ``str`` annotations (they
# are part of the runs' fingerprint); the CLI gives these fields Literal types instead.
CHOICES: dict[type, dict[str, tuple[str, ...]]] = {
    ExperimentConfig: {"pretrain_rule": PRETRAIN_RULES, "policy": POLICIES},
    NetworkConfig: {"rule": RULES, "feature_layer": FEATURE_LAYERS},
    WorldConfig: {
        "scene": SCENES,
        "actions": tuple(ACTION_SETS),
        "landmark_shape": LANDMARK_SHAPES,
        "room": ROOMS,
    },
    Distractor: {"shape": tuple(DISTRACTOR_SHAPES)},
}


#: The configuration dataclasses that appear on the command line, each shown by
#: :func:`as_options`.
CONFIGS = (ExperimentConfig, Curriculum, WorldConfig, CameraConfig, NetworkConfig, Distractor)


#: Fields left off the command line (the configuration keeps its preset's value):
#: ExperimentConfig.heldout_world (a WorldConfig or None) and ExperimentConfig.before (an
#: ExperimentConfig or None), which tyro can only offer as a choice of two subcommands
#: ({world-config,none}). The designs set them (docking.study.designs); their held-out worlds carry
#: distractors, which no option can give.
HIDDEN: dict[type, tuple[str, ...]] = {ExperimentConfig: ("heldout_world", "before")}


#: The options ``run EXPERIMENT --help`` (and ``sweep``'s) shows, per configuration: the
#: common fields; a nested configuration absent from this table (the camera, distractors) is
#: shown by ``--help-all`` alone. Every field is an option either way.
COMMON: dict[type, tuple[str, ...]] = {
    ExperimentConfig: ("train_trials", "test_trials", "heldout_trials", "policy"),
    Curriculum: ("grow_trials",),
    WorldConfig: ("scene", "actions", "room", "start_near", "start_far"),
    NetworkConfig: ("n_features", "beta_a_train", "eps_q", "eps_w", "rule"),
}


#: Added to an option's help (the dataclasses' docstrings are part of the runs' fingerprint).
NOTES: dict[tuple[type, str], str] = {
    (ExperimentConfig, "train_trials"): (
        "Fewer than --curriculum.grow-trials cut the curriculum short: the training region's "
        "far edge never reaches the test region's (a warning says which range training sees)."
    ),
}


def as_options(owner: type, fields: tuple, brief: bool) -> tuple:
    """tyro's fields of ``owner``, if it is a configuration dataclass (:data:`CONFIGS`), as the
    command line shows them (:func:`docking.study.cli.options.registry` asks): the named-value
    fields as Literals, the hidden fields suppressed, an optional number shown as FLOAT|None,
    and, if ``brief`` (``--help``), only the common fields (:data:`COMMON`); other fields as
    they are."""
    if owner not in CONFIGS:
        return fields
    choices = CHOICES.get(owner, {})
    hidden = HIDDEN.get(owner, ())
    common = COMMON.get(owner, ())
    shown = []
    for field in fields:
        kind, helptext = field.type, field.helptext
        if field.name in choices:
            kind = Literal[choices[field.name]]
        elif field.name in hidden:
            kind = Annotated[kind, tyro.conf.Suppress]
        elif kind in _OPTIONAL_METAVARS:
            kind = Annotated[kind, tyro.conf.arg(metavar=_OPTIONAL_METAVARS[kind])]
        if brief and field.name not in common and field.type not in COMMON:
            kind = Annotated[kind, tyro.conf.Suppress]  # --help: the common options only
        note = NOTES.get((owner, field.name))
        if note is not None:
            helptext = functools.partial(_noted, helptext, note)
        shown.append(dataclasses.replace(field, type=kind, helptext=helptext))
    return tuple(shown)


def _noted(helptext, note: str) -> str:
    """An option's help (a text, or tyro's callable that gives it) with ``note`` after it."""
    text = (helptext() if callable(helptext) else helptext) or ""
    return f"{text.rstrip()} {note}".strip()


#: The optional values of the configurations, as their options show them (tyro's own is
#: "{None}|FLOAT").
_OPTIONAL_METAVARS = {float | None: "FLOAT|None", int | None: "INT|None", str | None: "STR|None"}
