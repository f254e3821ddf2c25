"""The command line's options: the configuration dataclasses as options (tyro's registry,
the choices of the fields that take one of a few names, the common options ``--help`` shows),
the option types the commands share, and the words every command says (where a run came
from, why the ledger serves none).
"""

from __future__ import annotations

import dataclasses
import functools
import os
from pathlib import Path
from typing import Annotated, Literal, Union

import tyro

from docking import _PROG
from docking.camera import CameraConfig
from docking.experiments import POLICIES, PRETRAIN_RULES, Curriculum, ExperimentConfig
from docking.network import FEATURE_LAYERS, RULES, NetworkConfig
from docking.presets import EXPERIMENTS, HEADLINE_SEED, SEEDS
from docking.scene import (
    ACTION_SETS,
    DISTRACTOR_SHAPES,
    LANDMARK_SHAPES,
    ROOMS,
    SCENES,
    Distractor,
    WorldConfig,
)
from docking.study import paths
from docking.validate import parse_int, parse_real

PROG = _PROG  # the name in every message: one place, docking/__init__.py


#: The option that prints every option of an experiment (``--help`` shows the common ones,
#: :data:`COMMON`).
HELP_ALL = "--help-all"


def _named() -> dict[str, tuple[ExperimentConfig, str, tuple[int, ...]]]:
    """``{name: (configuration, what it is, its seeds)}`` of every configuration ``run`` and
    ``sweep`` name: the paper's experiments (:data:`docking.presets.EXPERIMENTS`, their seeds
    :data:`docking.presets.SEEDS`), then the study's worlds at the paper's published settings
    and with its tuned learners (:func:`docking.study.cli.named.named`)."""
    from docking.study.cli import named

    found = {
        name: (config, f"the paper's {name.replace('experiment', 'Experiment ')}", SEEDS[name])
        for name, config in EXPERIMENTS.items()
    }
    found.update({n: (c, what, named.SEEDS) for n, (c, what) in named.named().items()})
    return found


#: The configurations ``run`` and ``sweep`` name (:func:`_named`).
NAMED = _named()


def seeds_of(name: str) -> tuple[int, ...]:
    """The seeds a configuration called ``name`` runs for by default (a configuration renamed
    with ``--name`` runs for :data:`docking.presets.HEADLINE_SEED`)."""
    return NAMED[name][2] if name in NAMED else (HEADLINE_SEED,)


# One subcommand per named configuration, its configuration as the defaults.
_Experiment = Union[  # noqa: UP007 (tyro needs a runtime Union of Annotated members)
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


_ExperimentArg = Annotated[_Experiment, tyro.conf.arg(name=""), tyro.conf.OmitSubcommandPrefixes]


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
#: _as_options below.
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


_registry = tyro.constructors.ConstructorRegistry()


_expanding: set[type] = set()


#: Whether the parser being built is for ``--help`` (the common options, :data:`COMMON`).
_brief = False


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


#: Every integer and real option (and each number of a tuple option), read as the seeds are:
#: ASCII digits, no underscores (tyro's own ``int`` and ``float`` would read ``1_0`` as 10
#: and other scripts' digits as theirs). ``(parse, is_instance)`` per type.
_NUMBERS = {
    int: (parse_int, _is_int),
    float: (parse_real, lambda v: isinstance(v, float) or ("~" if _is_int(v) else False)),
}


@_registry.primitive_rule
def _as_number(info):
    """An ``int`` or ``float`` option read by :func:`docking.validate.parse_int` or
    :func:`docking.validate.parse_real` (tyro prints their error as the option's)."""
    if info.type not in _NUMBERS:
        return None
    parse, is_instance = _NUMBERS[info.type]
    return tyro.constructors.PrimitiveConstructorSpec(
        nargs=1,
        metavar=info.type.__name__.upper(),
        instance_from_str=lambda args: parse(args[0]),
        is_instance=is_instance,
        str_from_instance=lambda value: [str(value)],
    )


@_registry.struct_rule
def _as_options(info):
    """tyro's own expansion of a configuration dataclass, with its fields as options: the
    named-value fields as Literals, the hidden fields suppressed, an optional number shown
    as FLOAT|None."""
    if info.type not in CONFIGS or info.type in _expanding:
        return None
    _expanding.add(info.type)
    try:
        spec = tyro.constructors.ConstructorRegistry.get_struct_spec(info)
    finally:
        _expanding.discard(info.type)
    if not isinstance(spec, tyro.constructors.StructConstructorSpec):
        return spec
    choices = CHOICES.get(info.type, {})
    hidden = HIDDEN.get(info.type, ())
    common = COMMON.get(info.type, ())
    fields = []
    for field in spec.fields:
        kind, helptext = field.type, field.helptext
        if field.name in choices:
            kind = Literal[choices[field.name]]
        elif field.name in hidden:
            kind = Annotated[kind, tyro.conf.Suppress]
        elif kind in _OPTIONAL_METAVARS:
            kind = Annotated[kind, tyro.conf.arg(metavar=_OPTIONAL_METAVARS[kind])]
        if _brief and field.name not in common and field.type not in COMMON:
            kind = Annotated[kind, tyro.conf.Suppress]  # --help: the common options only
        note = NOTES.get((info.type, field.name))
        if note is not None:
            helptext = functools.partial(_noted, helptext, note)
        fields.append(dataclasses.replace(field, type=kind, helptext=helptext))
    return dataclasses.replace(spec, fields=tuple(fields))


def _noted(helptext, note: str) -> str:
    """An option's help (a text, or tyro's callable that gives it) with ``note`` after it."""
    text = (helptext() if callable(helptext) else helptext) or ""
    return f"{text.rstrip()} {note}".strip()


#: The optional values of the configurations, as their options show them (tyro's own is
#: "{None}|FLOAT").
_OPTIONAL_METAVARS = {float | None: "FLOAT|None", int | None: "INT|None", str | None: "STR|None"}


def _shown(metavar: str, default: str):
    """An option whose value None means "not given": its value as ``metavar`` (instead of
    tyro's "{None}|STR") and its default in words (instead of "(default: None)")."""
    return tyro.conf.arg(metavar=metavar, help_behavior_hint=f"(default: {default})")


_Processes = Annotated[int | None, _shown("INT", "one per core")]


_Scheduler = Annotated[str | None, _shown("STR", "an embedded cluster on 127.0.0.1")]


_ResultsDir = Annotated[
    Path | None,
    _shown("PATH", "DOCKING_RESULTS, the checkout's results/ or the per-user data folder's"),
]


_FiguresDir = Annotated[
    Path | None,
    _shown("PATH", "DOCKING_FIGURES, the checkout's figures/ or the per-user data folder's"),
]


_ExperimentSeeds = Annotated[
    str | None, _shown("STR", "the experiment's, docking.presets.SEEDS; a world's: Experiment 2's")
]


_DesignSeeds = Annotated[str | None, _shown("STR", "the design's")]


def _seed_text(seeds) -> str:
    """``0-4, 7`` for ``[0, 1, 2, 3, 4, 7]`` (:func:`docking.study.sweep.seeds_text`)."""
    from docking.study.sweep import seeds_text

    return seeds_text(seeds)


def _absent(text: str, how: str) -> str:
    """The error of runs that are neither stored nor in the ledger: ``text`` says which, then
    how to get the ledger if it is off or absent, then ``how`` to compute them."""
    why = _no_ledger()
    return f"{text}. {why[0].upper()}{why[1:]}. Or {how}" if why else f"{text}: {how}"


def _no_ledger() -> str | None:
    """Why the ledger serves no run, and what to do, if it is switched off or absent (an
    installed package: the ledger is the ledger/ folder of the project's git repository, which
    no wheel carries); None if there is a ledger."""
    if paths.ledger_off():
        return (
            f"the ledger is switched off by DOCKING_LEDGER={os.environ['DOCKING_LEDGER']}; "
            "unset it, or set it to a ledger folder"
        )
    if paths.ledger_dir() is None:
        return (
            "this installed package has no ledger (the committed runs that report and figures "
            "read are the ledger/ folder of the project's git repository, which no wheel "
            "carries): clone the repository and run python -m docking in the clone, or set "
            "DOCKING_LEDGER to the absolute path of the clone's ledger/ folder"
        )
    return None
