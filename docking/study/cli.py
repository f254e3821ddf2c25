"""The command line, ``python -m docking`` (also installed as ``docking``).

Built by tyro from the configuration dataclasses and their docstrings, so every field of an
:class:`~docking.experiments.ExperimentConfig` (but its held-out world, see :data:`HIDDEN`) is
an option with its documented default::

    python -m docking run experiment2 --seeds 0-19 --network.eps-w 0
    python -m docking sweep experiment2 --seeds 0-9 --grid network.eps_w=0,0.05 \\
        --scheduler tcp://127.0.0.1:8786
    python -m docking design list
    python -m docking design run experiment3 [--full]
    python -m docking report --readme README.md
    python -m docking benchmark --steps 2000

``run`` and ``sweep`` store every run they compute in the results store
(:mod:`docking.study.store`), keyed by its configuration and seed; a run the store or the committed
ledger holds is loaded, not recomputed, so an interrupted command resumes where it stopped. Progress
bars go to the terminal (stderr). ``--help`` (of the command and of each subcommand) prints usage
and starts nothing.
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import functools
import inspect
import json
import os
import re
import signal
import sys
from pathlib import Path
from typing import Annotated, Literal, Union

import numpy as np
import tyro

from docking import _PROG, _check_opengl_platform
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
from docking.study.designs import names as _design_names
from docking.validate import parse_int, parse_real

PROG = _PROG  # the name in every message: one place, docking/__init__.py
DESCRIPTION = (
    "Kleesiek et al. (2011) on dm-control: run the experiments, sweep parameters on a Dask "
    "cluster, print the results table, benchmark the environment."
)

#: The option that prints every option of an experiment (``--help`` shows the common ones,
#: :data:`COMMON`).
HELP_ALL = "--help-all"

# One subcommand per named experiment, its configuration as the defaults.
_Experiment = Union[  # noqa: UP007 (tyro needs a runtime Union of Annotated members)
    tuple(
        Annotated[
            ExperimentConfig,
            tyro.conf.subcommand(
                name,
                default=config,
                description=(
                    f"{name} as in docking.experiments; any field can be overridden. --help "
                    f"shows the common options, {HELP_ALL} every one."
                ),
            ),
        ]
        for name, config in EXPERIMENTS.items()
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
    str | None, _shown("STR", "the experiment's seeds, docking.presets.SEEDS")
]
_DesignSeeds = Annotated[str | None, _shown("STR", "the design's")]


def _seeds_of(config: ExperimentConfig, text: str | None) -> list[int]:
    from docking.study.sweep import parse_seeds

    if text is None:
        return list(SEEDS.get(config.name, (HEADLINE_SEED,)))
    return parse_seeds(text)


def _summary(results) -> str:
    """The line of a configuration's runs: their test success, or, for runs without test
    trials (``--test-trials 0``, as the designs' runs judged on held-out trials), that they
    have none, and their held-out success if they have held-out trials (a mean of no trials
    is no number)."""
    if len(results[0].test.success):
        return _success_line("test", [r.test for r in results], results)
    heldout = [r.heldout for r in results]
    text = "no test trials (--test-trials 0)"
    if all(log is not None and len(log.success) for log in heldout):
        text += "; " + _success_line("held-out", heldout, results)
    return text


def _success_line(what: str, logs, results) -> str:
    """``what`` success of ``logs`` (one per run of ``results``): the mean, the minimum and
    each seed's successes."""
    rates = np.array([log.success_rate for log in logs])
    per_seed = ", ".join(
        f"{r.seed}: {int(np.sum(log.success))}/{len(log.success)}"
        for r, log in zip(results, logs, strict=True)
    )
    return (
        f"{what} success mean {100 * rates.mean():.1f}% (min {100 * rates.min():.1f}%; {per_seed})"
    )


@dataclasses.dataclass
class Run:
    """Run (or load) an experiment for several seeds; a run computed is saved in the results
    store, one the store or the committed ledger holds is loaded.

    EXPERIMENT names a configuration of docking.presets.EXPERIMENTS; options after it
    override its fields (e.g. --network.eps-w 0, --train-trials 500)."""

    experiment: _ExperimentArg
    seeds: _ExperimentSeeds = None
    """Seeds as ranges or lists: 0-19, 0,3,5 or 0-4,10."""
    processes: _Processes = None
    """Worker processes of the embedded Dask cluster; 1 runs the seeds one after another in
    this process."""
    scheduler: _Scheduler = None
    """Run on an existing Dask cluster instead, e.g. tcp://HOST:8786."""
    results_dir: _ResultsDir = None
    """The results store."""
    force: bool = False
    """Recompute and replace stored runs."""

    def execute(self) -> int:
        config = self.experiment
        seeds = _seeds_of(config, self.seeds)
        _warn_short_curriculum(config)
        sources, paths, results = _run(self, [config], seeds, f"{config.name}, {len(seeds)} seeds")
        print(f"{_label(config)}: {_summary(results)}")
        print(_sources_text(seeds, sources, paths[0].parent))
        return 0


def _preset_of(config: ExperimentConfig) -> ExperimentConfig:
    """The preset (:data:`docking.presets.EXPERIMENTS`) ``config`` differs least from (its
    namesake first)."""
    return min(
        EXPERIMENTS.values(),
        key=lambda p: (len(_overrides(config, p)), p.name != config.name),
    )


def _flat(value, prefix: str = "") -> dict[str, object]:
    """``{dotted.field: value}`` of a configuration's :meth:`to_dict` (a list of
    configurations, such as the distractors, is one value)."""
    if isinstance(value, dict):
        return {
            k: v
            for name, part in value.items()
            for k, v in _flat(part, prefix + name + ".").items()
        }
    return {prefix[:-1]: value}


def _option(field: str, value) -> str:
    """The command-line option that sets ``field`` (dotted) to ``value``."""
    head, _, name = field.rpartition(".")
    flag = f"--{head + '.' if head else ''}{name}".replace("_", "-")
    if isinstance(value, bool):
        return flag if value else f"--{head + '.' if head else ''}no-{name}".replace("_", "-")
    if isinstance(value, list) and not any(isinstance(v, dict | list) for v in value):
        return f"{flag} {' '.join(map(str, value))}"
    return f"{flag} {value}"


def _overrides(config: ExperimentConfig, preset: ExperimentConfig) -> list[str]:
    """The options that turn ``preset`` into ``config``, in the order of the fields."""
    ours, theirs = _flat(config.to_dict()), _flat(preset.to_dict())
    return [_option(k, v) for k, v in ours.items() if theirs.get(k, v) != v or k not in theirs]


def _label(config: ExperimentConfig) -> str:
    """How a run's line names ``config``: its name, and the options by which it differs from
    its preset (``experiment2 (--train-trials 100, --network.eps-w 0.0)``)."""
    preset = _preset_of(config)
    changed = [o for o in _overrides(config, preset) if not o.startswith("--name ")]
    if preset.name != config.name:
        changed.insert(0, f"{preset.name} --name {config.name}")
    return f"{config.name} ({', '.join(changed)})" if changed else config.name


def _curriculum_cut(config: ExperimentConfig) -> str | None:
    """If ``config`` trains for fewer trials than its curriculum grows over, what training
    then sees and what to do (None if the curriculum is whole, or there is none)."""
    grow, trials = config.curriculum.grow_trials, config.train_trials
    if config.policy != "network" or trials == 0 or not trials < grow:
        return None
    world = config.world
    final = world.start_far if config.curriculum.far_final is None else config.curriculum.far_final
    first, last = (config.curriculum.far_at(t, world.start_far) for t in (0, trials - 1))
    return (
        f"--train-trials {trials} is shorter than the curriculum's growth "
        f"(--curriculum.grow-trials {grow}): the training region's far edge only grows from "
        f"{first:.2f} m to {last:.2f} m, so training sees starts {world.start_near:.2f}-"
        f"{last:.2f} m away, never the {final:.2f} m the curriculum grows to"
        + (" (the test region's far edge)" if final == world.start_far else "")
        + f". Pass --curriculum.grow-trials {trials} (or fewer) to grow it within the training"
    )


def _warn_short_curriculum(*configs: ExperimentConfig) -> None:
    """A warning on stderr for each configuration whose training cuts its curriculum short."""
    for text in dict.fromkeys(filter(None, map(_curriculum_cut, configs))):
        print(f"{PROG}: warning: {text}", file=sys.stderr)


def _run(command: Run | Sweep, configs, seeds, desc: str) -> tuple[list, list, list]:
    """Run (or load) every configuration of ``configs`` for every seed as ``command``'s
    options say: per run (configuration by configuration), where it came from (computed,
    store or ledger), its path in the store, and the run. Each job is located once
    (:func:`docking.study.runs.locate`), before anything computes: the ledger's runs are read
    there, so a damaged file of theirs is an error before any computation."""
    from docking.study.runs import locate
    from docking.study.sweep import _to_compute, jobs_for, sweep

    jobs = jobs_for(configs, seeds)
    root = command.results_dir if command.results_dir is not None else paths.results_dir()
    if command.force:
        located = [_to_compute(j, Path(root).resolve()) for j in jobs]
    else:
        located = [locate(j.config, j.seed, root) for j in jobs]
    computed = sum(found.place == "computed" for found in located)
    if computed:
        note = _ledger_note()
        if note:
            print(f"{PROG}: note: {note}; computing {computed} runs", file=sys.stderr)
        _say_where(command.results_dir)
    found = sweep(
        jobs,
        command.results_dir,
        scheduler=command.scheduler,
        workers=command.processes,
        desc=desc,
        located=located,
    )
    return [f.place for f in found], [f.path for f in found], [f.run for f in found]


def _say_where(results_dir) -> None:
    """Before an installed package first stores runs in the per-user data folder (the results
    store when no checkout, ``DOCKING_RESULTS`` nor ``--results-dir`` names one), a note on
    stderr that names it."""
    if results_dir is not None:
        return
    folder = paths.results_dir()
    if paths.in_user_data(folder) and not folder.exists():
        print(
            f"{PROG}: note: this installed package stores its runs in the per-user data folder "
            f"{folder} (DOCKING_RESULTS or --results-dir names another)",
            file=sys.stderr,
        )


def _ledger_note() -> str | None:
    """Why the ledger serves no run, in one line that names it, if it is missing or no
    ledger (None if it is switched off by DOCKING_LEDGER=off, or is a ledger); a damaged or
    stale ledger is an error (:class:`docking.study.ledger.CorruptLedger`,
    :class:`docking.study.ledger.StaleLedger`): every file is checked
    (:func:`docking.study.ledger.check_files`), not only those of the runs asked for."""
    from docking.study import ledger

    if paths.ledger_off():
        return None
    folder = paths.ledger_dir()
    if folder is None:
        return "this installed package has no ledger (DOCKING_LEDGER names none)"
    if not folder.is_dir():
        return f"the ledger folder {folder} does not exist: no run is read from it"
    if not (folder / "manifest.json").is_file():
        return f"{folder} is not a ledger (it has no manifest.json): no run is read from it"
    try:
        ledger.check_files(folder)
    except ledger.StaleLedger as exc:
        raise type(exc)(f"{exc} (DOCKING_LEDGER=off computes without the ledger)") from None
    return None


def _source_words(folder) -> dict[str, str]:
    """What each place a run came from is called (:data:`docking.study.runs.PLACES`, in
    the order they are shown), ``folder`` the store's folder."""
    return {
        "ledger": f"read from the committed ledger, {paths.ledger_dir()} (its files checked "
        "against their SHA-256, its digests and wall times against their seal; nothing "
        "computed)",
        "store": f"loaded from the results store, {folder}",
        "computed": f"computed now and stored in {folder}",
    }


def _sources_text(seeds, sources, folder) -> str:
    """Where each seed's run came from, in one or two lines (the store's folder named only
    where a run is in it)."""
    lines = []
    for kind, words in _source_words(folder).items():
        mine = [s for s, k in zip(seeds, sources, strict=True) if k == kind]
        if mine:
            lines.append(f"seeds {_seed_text(mine)}: {words}")
    return "\n".join(lines)


def _seed_text(seeds) -> str:
    """``0-4, 7`` for ``[0, 1, 2, 3, 4, 7]``."""
    parts, start = [], None
    for i, s in enumerate(seeds):
        if start is None:
            start = s
        if i + 1 == len(seeds) or seeds[i + 1] != s + 1:
            parts.append(str(start) if start == s else f"{start}-{s}")
            start = None
    return ", ".join(parts)


@dataclasses.dataclass
class Sweep:
    """Run (or load) a parameter grid x seeds as jobs on a Dask cluster (embedded by default).

    EXPERIMENT is the base configuration; options after it override its fields, --grid
    entries vary them. Each (configuration, seed) is one job; results land in the store, so
    an interrupted sweep resumes and finished runs are never recomputed."""

    experiment: _ExperimentArg
    seeds: _ExperimentSeeds = None
    """Seeds as ranges or lists: 0-19, 0,3,5."""
    grid: Annotated[
        tuple[str, ...],
        tyro.conf.arg(help_behavior_hint="(default: none, the base configuration alone)"),
    ] = ()
    """Fields to vary, each PATH=V1,V2,...; all combinations are run, e.g.
    --grid network.eps_w=0,0.05 world.step_forward=0.1,0.15."""
    scheduler: _Scheduler = None
    """Address of an existing Dask scheduler (tcp://HOST:PORT; started with dask scheduler,
    workers with dask worker tcp://HOST:PORT)."""
    processes: _Processes = None
    """Worker processes of the embedded cluster."""
    results_dir: _ResultsDir = None
    """The results store; with a remote cluster, the same path on every worker (a shared
    file system)."""
    force: bool = False
    """Recompute and replace stored runs."""

    def execute(self) -> int:
        from docking.study.sweep import MAX_RUNS, grid_configs

        configs = grid_configs(self.experiment, self.grid)
        seeds = _seeds_of(self.experiment, self.seeds)
        if len(configs) * len(seeds) > MAX_RUNS:
            raise ValueError(
                f"at most {MAX_RUNS} runs in one command; the sweep names "
                f"{len(configs) * len(seeds):,} ({len(configs)} configurations x "
                f"{len(seeds)} seeds)"
            )
        _warn_short_curriculum(*configs)
        desc = f"sweep: {len(configs)} configurations x {len(seeds)} seeds"
        sources, paths, results = _run(self, configs, seeds, desc)
        for k, config in enumerate(configs):
            rows = slice(k * len(seeds), (k + 1) * len(seeds))
            print(f"{_label(config)}: {_summary(results[rows])}")
            where = _sources_text(seeds, sources[rows], paths[rows][0].parent)
            print("\n".join(f"  {line}" for line in where.splitlines()))
        return 0


#: The designs' names (docking.study.designs), as choices.
_DesignName = Literal[tuple(_design_names())]  # type: ignore[valid-type]


@dataclasses.dataclass
class DesignRun:
    """Run (or load) designs of docking.study.designs: every cell for the design's seeds in one
    sweep on a Dask cluster (embedded by default), then the cells that need measured runs;
    prints each design's summary (its table and the verdicts of its claims)."""

    names: Annotated[
        tyro.conf.Positional[tuple[_DesignName, ...]],
        tyro.conf.arg(
            help_behavior_hint=lambda shown: f"(default: {shown})" if shown else "(required)"
        ),
    ]
    """The designs to run (python -m docking design list)."""
    full: bool = False
    """Also the design's sensitivity cells (about twice the runs for the study)."""
    seeds: _DesignSeeds = None
    """Seeds as ranges or lists, e.g. 0-4."""
    cells: Annotated[tuple[str, ...], _shown("PATTERN ...", "every cell")] = ()
    """Only the cells whose keys match one of these shell-style patterns (e.g. 'floor/*'),
    without the design's stages and claims: part of a design first, on the same runs."""
    scheduler: _Scheduler = None
    """Address of an existing Dask scheduler (tcp://HOST:PORT)."""
    processes: _Processes = None
    """Worker processes of the embedded cluster."""
    results_dir: _ResultsDir = None
    """The results store."""

    def execute(self) -> int:
        from docking.study.design import run_design, summary
        from docking.study.designs import design
        from docking.study.sweep import parse_seeds

        if not self.names:
            raise ValueError("name at least one design (python -m docking design list)")
        seeds = None if self.seeds is None else parse_seeds(self.seeds)
        _say_where(self.results_dir)
        for name in self.names:
            found = design(name).only(self.cells) if self.cells else design(name)
            results = run_design(
                found,
                full=self.full,
                seeds=seeds,
                results_dir=self.results_dir,
                scheduler=self.scheduler,
                workers=self.processes,
            )
            print(f"\n{name}: {found.title}\n")
            print(summary(results))
            print(f"\n{_counted(results.sources, self.results_dir)}")
        return 0


def _counted(sources: dict[str, list[str]], results_dir) -> str:
    """How many of a design's trained runs came from where (``Results.sources``), in
    :func:`_sources_text`'s words."""
    counts = collections.Counter(k for found in sources.values() for k in found)
    words = _source_words(results_dir or paths.results_dir())
    return "runs: " + "; ".join(f"{counts[k]} {text}" for k, text in words.items() if counts[k])


@dataclasses.dataclass
class DesignList:
    """List the designs: name, cells (core / all), seeds, measure and what each asks."""

    def execute(self) -> int:
        from docking.study.designs import design, names

        for name in names():
            d = design(name)
            core = len(d.select(False))
            print(
                f"{name:26s} {core:3d} / {len(d.cells):3d} cells x {len(d.seeds):2d} seeds, "
                f"{d.measure:7s} {d.title}"
            )
        return 0


_DesignSubcommand = Union[  # noqa: UP007 (tyro needs a runtime Union)
    Annotated[DesignRun, tyro.conf.subcommand("run")],
    Annotated[DesignList, tyro.conf.subcommand("list")],
]


@dataclasses.dataclass
class DesignCommand:
    """Experiment designs (docking.study.designs): list them, or run some."""

    command: Annotated[_DesignSubcommand, tyro.conf.arg(name=""), tyro.conf.OmitSubcommandPrefixes]
    """list: the designs; run NAME ...: run (or load) them."""

    def execute(self) -> int:
        return self.command.execute()


@dataclasses.dataclass
class Report:
    """Print the results: the paper's numbers beside ours, Experiment 3's table, the third
    edition's contest and verdict table, and the summary above them, from the runs the
    results store or the committed ledger holds (--compute: computing any that neither
    holds; without it, the report refuses to compute)."""

    readme: Annotated[Path | None, _shown("PATH", "none, the tables are only printed")] = None
    """Also write the table into this README, between <!-- results:start --> and
    <!-- results:end -->."""
    processes: _Processes = None
    """Worker processes for missing runs."""
    results_dir: _ResultsDir = None
    """The results store."""
    experiment3: bool = True
    """Also the table of Experiment 3 (notebook 06; runs it if it is not stored, and the
    oracle in every cell), into the README between <!-- experiment3:start --> and
    <!-- experiment3:end -->."""
    third_edition: bool = True
    """Also the third edition (notebook 07): its contest in the README's summary and its table
    between <!-- third-edition:start --> and <!-- third-edition:end -->, its verdict table
    between <!-- verdicts:start --> and <!-- verdicts:end -->."""
    figures: bool = False
    """Also save Figs. 2-5 and the learning curves of Experiments 1 and 2 into figures/
    (or DOCKING_FIGURES)."""

    compute: bool = False
    """Compute the runs that neither the results store nor the ledger holds (without it, the
    report refuses to start a computation: Experiment 3 is hours on 2 cores)."""

    def execute(self) -> int:
        from docking.study import report
        from docking.study.designs import design

        if not self.compute:
            _refuse_to_compute(self.experiment3, self.results_dir, self.third_edition)
        paper = design("paper").run(results_dir=self.results_dir, workers=self.processes)
        results = [paper.runs["experiment1"], paper.runs["experiment2"]]
        if self.figures:
            report.save_figures(*results)
        changed = self._write(report.results_table(*results))
        comparisons, first = None, None
        if self.experiment3:
            comparisons, rates, text = self._experiment3()
            changed |= self._write(text, report.EXPERIMENT3_START, report.EXPERIMENT3_END)
            first = rates[comparisons[0].four_key]
        contest, claims, untested, decisions, added = None, None, [], None, None
        if self.third_edition:
            contest, claims, untested, decisions, changed_here = self._third_edition()
            changed |= changed_here
            added = self._addendum()
        summary = report.summary_text(
            *results, comparisons, first, contest, claims, corrected=added is not None
        )
        if added is not None:
            from docking.study.designs import addendum

            unmerged = getattr(self, "_unmerged", None) or added  # the addendum as it ran
            summary += "\n\n" + report.addendum_summary(unmerged, contest, addendum)
            if getattr(self, "_bracketing", None):
                summary += "\n\n" + report.bracketing_summary(self._bracketing, added, addendum)
        for found, _ in untested:
            if found.design.name == "untested":
                summary += "\n\n" + report.untested_summary(found)
            else:
                from docking.study.designs import revisited

                self._revisited = report.revisited_rows(found, revisited)
                summary += "\n\n" + report.revisited_summary(self._revisited, found, revisited)
        if self.third_edition:
            summary += "\n\n" + report.candour_text()
        changed |= self._write(summary, report.SUMMARY_START, report.SUMMARY_END)
        if contest is not None:
            changed |= self._glance(results, comparisons, contest, added, decisions)
        if self.readme is not None:
            changed |= _write_timings(self.readme)
            print(f"{self.readme}: {'updated' if changed else 'already up to date'}")
        return 0

    def _write(self, text: str, *markers: str) -> bool:
        """Print ``text`` and write it into the README between ``markers`` (default: the
        results table's); whether the README changed."""
        from docking.study.report import update_readme

        print(text)
        return self.readme is not None and update_readme(self.readme, text, *markers)

    def _experiment3(self) -> tuple:
        """Experiment 3's four-against-six comparisons, the oracle's rates and its table."""
        from docking.study import report
        from docking.study.designs import experiment3

        found = experiment3.run(results_dir=self.results_dir, workers=self.processes)
        oracle = experiment3.ORACLE.run(results_dir=self.results_dir, workers=self.processes)
        comparisons, rates = report.turning_comparisons(found), report.oracle_rates(oracle)
        return comparisons, rates, report.turning_table(comparisons, rates)

    def _third_edition(self) -> tuple:
        """The third edition's contest table and verdict table (with the untested claims'
        rows, :meth:`_untested`) written; its results, its claims' sentence, the untested
        rows and whether the README changed."""
        from docking.study import report
        from docking.study.claims import design_verdicts, judge_family
        from docking.study.designs import third_edition

        contest = third_edition.DESIGN.run(results_dir=self.results_dir, workers=self.processes)
        untested = self._untested()
        changed = self._write(
            report.contest_table(contest, report.CONTEST_WORLDS),
            report.THIRD_EDITION_START,
            report.THIRD_EDITION_END,
        )
        changed |= self._verdicts(
            design_verdicts(contest, *untested, notes=report.OUTSIDE_COUNTS),
            report.claims_glance_rows(contest, *untested, notes=report.OUTSIDE_COUNTS),
        )
        design = contest.design
        decisions = judge_family(design.claims, contest, alpha=design.alpha, per_claim=True)
        claims = report.claims_summary(design.claims, decisions)
        return contest, claims, untested, decisions, changed

    def _verdicts(self, table: str, rows: list) -> bool:
        """The full verdict table into the site's page beside the README
        (:data:`docking.study.report.VERDICTS_PAGE`, where it exists), and into the README the
        claims at a glance (its figure, saved into the figures folder) with a link to the
        page; whether either file changed."""
        from docking.study import figures, report
        from docking.study.report import update_readme

        print(table)
        fig = figures.fig_claims(rows)
        png = Path(report.save_named(fig, report.CLAIMS_FIGURE))
        text = (
            f"\n![The paper's claims at a glance](figures/{png.name}) **The paper's claims at a "
            "glance:** one row per claim, one box per comparison (its world or setting, its 95% "
            "interval, its decision by the committed rule), coloured by the decision (green "
            "supported, red contradicted, orange at the bound, grey not supported; pale: outside "
            "the counts). The full verdict table, with the paper's words, every p-value and the "
            f"verdicts under both decision rules, is [a page of its own]({report.VERDICTS_PAGE}).\n"
        )
        changed = self._write(text, report.VERDICTS_START, report.VERDICTS_END)
        if self.readme is not None:
            page = self.readme.parent / report.VERDICTS_PAGE
            if page.exists():
                changed |= update_readme(page, table, report.VERDICTS_START, report.VERDICTS_END)
        return changed

    def _addendum(self):
        """The third edition's addendum's results, once every run of it is stored or in the
        ledger (None before), with the bracketing's tuned learners in place once its runs
        are in (:func:`docking.study.report.bracketed_addendum`; its rows kept for the first
        screen)."""
        from docking.study.design import absent_runs
        from docking.study.designs import addendum

        if absent_runs(addendum.DESIGN, self.results_dir):
            return None
        added = addendum.DESIGN.run(results_dir=self.results_dir, workers=self.processes)
        from docking.study import report
        from docking.study.designs import bracketing, bracketing_continued

        walk = None  # the last of the bracketing's designs whose every run is in
        for module in (bracketing, bracketing_continued):
            if not absent_runs(module.DESIGN, self.results_dir):
                walk = module
        if walk is None:
            return added
        own = walk.DESIGN.run(results_dir=self.results_dir, workers=self.processes)
        self._bracketing = report.bracketing_rows(own, walk)
        self._unmerged = added
        return report.bracketed_addendum(added, own, walk)

    def _glance(self, results, comparisons, contest, added, decisions) -> bool:
        """The README's first screen: the figure of every learner's held-out success per
        world (saved into the figures folder) and at most five sentences under it."""
        from docking.study import figures, report

        fig = figures.fig_glance(*report.glance_data(contest, added))
        png = Path(report.save_named(fig, report.GLANCE_FIGURE))
        tuned, unbracketed = None, ()
        if added is not None:
            from docking.study.designs import addendum

            tuned = {
                w: added.cell(f"{w}/paper-tuned").config.network.beta_a_train
                for w in addendum.WORLDS
            }
            rows = getattr(self, "_bracketing", None) or report.bracketed_rows(added, addendum)
            unbracketed = tuple(
                dict.fromkeys(
                    knob
                    for r in rows
                    if r["learner"] == "paper"
                    for knob, (_, where) in r["positions"].items()
                    if where.startswith("at the edge")
                )
            )
        text = report.glance_text(
            *results,
            comparisons,
            contest,
            added,
            contest.design.claims,
            decisions,
            tuned,
            unbracketed,
            getattr(self, "_revisited", None),
        )
        image = (
            f"![The answer per world](figures/{png.name}) **The answer per world:** each dot "
            "one network's success on 500 held-out start poses, the mean with its 95% interval; "
            "lines: the *pose oracle* (it reads the true pose), a centroid rule, random actions."
        )
        return self._write(f"\n{image}\n\n{text}\n", report.GLANCE_START, report.GLANCE_END)

    def _untested(self) -> list:
        """The untested claims' rows of the verdict table
        (:data:`docking.study.report.UNTESTED_IN_README`) and their revisit's
        (:data:`docking.study.report.REVISITED_IN_README`), each once every run of its design
        (``untested.part("judged")``, ``revisited.DESIGN``) is stored or in the ledger."""
        from docking.study.design import absent_runs
        from docking.study.designs import revisited, untested
        from docking.study.report import REVISITED_IN_README, UNTESTED_IN_README

        found = []
        for design, keys in (
            (untested.part("judged"), UNTESTED_IN_README),
            (revisited.DESIGN, REVISITED_IN_README),
        ):
            if not absent_runs(design, self.results_dir):
                runs = design.run(results_dir=self.results_dir, workers=self.processes)
                found.append((runs, keys))
        return found


def _write_timings(readme: Path) -> bool:
    """The README's paragraph of times from the ledger (its runs' wall times and the tiers'
    record of tools/time_tiers.py); whether the README changed."""
    from docking.study import ledger
    from docking.study.report import TIMINGS_END, TIMINGS_START, timings_text, update_readme

    data = ledger.manifest()
    if data is None:
        return False
    walls = sum(r["wall_seconds"] for r in data["runs"].values())
    text = timings_text(
        ledger.timings(), len(data["runs"]), walls, ledger_bytes=ledger.size_bytes()
    )
    return update_readme(readme, text, TIMINGS_START, TIMINGS_END)


def _refuse_to_compute(experiment3: bool, results_dir, third_edition: bool = False) -> None:
    """``ValueError`` if the report would compute runs: it names how many and the option."""
    from docking.study.design import absent_runs
    from docking.study.designs import design
    from docking.study.designs import third_edition as te

    names = ["paper"] + ["experiment3", "experiment3-oracle"] * experiment3
    designs = [design(name) for name in names] + [te.DESIGN] * third_edition
    absent = [job for d in designs for job in absent_runs(d, results_dir)]
    if absent:
        kinds = sorted({j.config.name for j in absent})
        text = f"{len(absent)} runs ({', '.join(kinds)}) are neither stored nor in the ledger"
        how = (
            "pass --compute to compute them (from minutes to hours), or run the designs first "
            "(python -m docking design run ...)"
        )
        raise ValueError(_absent(text, how))


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


@dataclasses.dataclass
class Figures:
    """Regenerate Figs. 2-5 and the learning curves of Experiments 1 and 2 from their runs in
    the results store or the committed ledger (never computing one); Experiment 3's figures
    are written by notebook 06, the study's by notebooks 07 and 08."""

    folder: _FiguresDir = None
    """Where the .png and .pdf files go."""
    results_dir: _ResultsDir = None
    """The results store."""

    def execute(self) -> int:
        from docking.presets import EXPERIMENT_1, EXPERIMENT_2
        from docking.study.report import save_figures
        from docking.study.runs import load_run

        results = []
        for config in (EXPERIMENT_1, EXPERIMENT_2):
            runs = [load_run(config, s, self.results_dir) for s in SEEDS[config.name]]
            absent = [s for s, r in zip(SEEDS[config.name], runs, strict=True) if r is None]
            if absent:
                text = (
                    f"{config.name} seeds {_seed_text(absent)} are neither stored nor in the ledger"
                )
                how = f"compute them with python -m docking run {config.name}"
                raise ValueError(_absent(text, how))
            results.append(runs)
        for fig in save_figures(*results, self.folder):
            del fig
        print(f"figures written to {self.folder or paths.figures_dir()}")
        return 0


@dataclasses.dataclass
class Ledger:
    """Write the results ledger (ledger/, committed) from the results store: the runs of every
    design (python -m docking design list), as results tables and the few runs the designs
    keep whole; show what the ledger holds; or migrate its runs to this code."""

    action: tyro.conf.Positional[Literal["update", "show", "migrate"]]
    """update: write the ledger from the results store; show: its runs, size, fingerprint,
    every file checked; migrate: after a change of code that changes no number, recompute a
    sample covering every table, kind of run and world, and only if every recomputed run
    equals the ledger, re-key the ledger's runs (and the results store's) to this code."""
    results_dir: _ResultsDir = None
    """The results store (update, and migrate: its runs are re-keyed too)."""
    under_way: Annotated[tuple[str, ...], _shown("NAME ...", "none: every design complete")] = ()
    """Designs whose runs are under way: only the cells whose runs the store holds are
    written (update only)."""
    only: Annotated[tuple[str, ...], _shown("NAME ...", "every design")] = ()
    """Write only these designs' results tables, keeping every other table of the ledger as
    it is (checked against its digests and this code): the results store need not hold the
    other designs' runs (update only)."""

    def execute(self) -> int:
        from docking.study import ledger

        folder = paths.ledger_dir()  # ValueError if DOCKING_LEDGER is not off or a folder
        if folder is None:
            raise ValueError(_no_ledger())
        if self.action == "migrate":
            return _migrate(folder, self.results_dir)
        if self.action == "update":
            from docking.study.design import ledger_runs
            from docking.study.designs import design, names

            unknown = sorted((set(self.under_way) | set(self.only)) - set(names()))
            if unknown:
                raise ValueError(f"no design {', '.join(unknown)}; the designs are {names()}")
            runs = {}
            for name in self.only or names():
                partial = name in self.under_way
                for config, seed, whole, keep in ledger_runs(
                    design(name), stored_only=partial, results_dir=self.results_dir
                ):
                    key = (json.dumps(config.to_dict(), sort_keys=True), seed)
                    old = runs.get(key, (config, seed, False, frozenset()))
                    runs[key] = (config, seed, whole or old[2], keep | old[3])
            from docking.study.designs import rules_digest

            rules = {name: rules_digest(name) for name in self.only or names()}
            data = ledger.update(
                list(runs.values()),
                results_dir=self.results_dir,
                only=self.only or None,
                rules=rules,
            )
        else:
            data = ledger.manifest(folder)
            if data is None:
                raise ValueError(f"no ledger in {folder} (it has no manifest.json)")
        checked = ledger.check_files(folder)  # CorruptLedger naming the first damaged file
        print(_ledger_table(data, folder, checked, ledger.size_bytes(folder)))
        return 0


def _migrate(folder: Path, results_dir) -> int:
    """``ledger migrate``: what :func:`docking.study.migrate.migrate` did, in a few lines; 1 if a
    recomputed run differs (nothing migrated)."""
    from docking.study import migrate

    done = migrate.migrate(folder, results_dir)
    if done.differ:
        print(f"{PROG}: nothing migrated: this code computes other arrays for", file=sys.stderr)
        for name, seed, what in done.differ:
            print(f"  {name} seed {seed}: {what} differ", file=sys.stderr)
        return 1
    if done.record is None:
        print(f"{folder}: its runs are keyed by this code already: nothing to migrate")
    else:
        record = done.record
        for name in sorted(record["to"]):
            print(
                f"{folder}: {record['moved'][name]} {name} runs re-keyed from "
                f"{record['from'][name][:16]} to {record['to'][name][:16]} "
                f"(changed: {', '.join(record['changed'][name])[:200]})"
            )
        print(
            f"proof: {len(record['recomputed'])} runs recomputed, covering every table, "
            "kind of run and world, each equal to the ledger (digest and table row)"
        )
    if done.store is not None:
        moved = done.store
        print(
            f"results store: {moved['moved']} runs re-keyed, {moved['current']} keyed by "
            f"this code already, {moved['left']} left (other code, no proven migration)"
        )
    return 0


#: The widest line ``ledger show`` prints.
LEDGER_WIDTH = 100


def _ledger_table(data: dict, folder: Path, checked: dict, size: int) -> str:
    """What ``ledger show`` prints of the manifest ``data`` of the ledger in ``folder``
    (``size`` bytes; ``checked``: :func:`docking.study.ledger.check_files`'s counts): a line of
    totals, one row per results table (its runs by runner, configurations, whole runs, bytes
    and the runs' recorded wall time), the code and rendering stack, and what was checked;
    no line wider than :data:`LEDGER_WIDTH`."""
    import textwrap

    runs = data["runs"].values()
    runners = sorted({r["runner"] for r in runs})
    kinds = collections.Counter(r["runner"] for r in runs)

    def fill(text: str) -> str:
        return textwrap.fill(text, LEDGER_WIDTH, subsequent_indent="  ", break_on_hyphens=False)

    def row(name, mine, mib) -> str:
        configs = {json.dumps(r["config"], sort_keys=True) for r in mine}
        counts = collections.Counter(r["runner"] for r in mine)
        hours = sum(r["wall_seconds"] for r in mine) / 3600
        cells = [f"{counts[k]:>7d}" for k in runners]
        whole = sum(1 for r in mine if r.get("whole"))
        return (
            f"{name[:30]:30s} {len(mine):>6d} {' '.join(cells)} {len(configs):>7d} "
            f"{whole:>5d} {mib:>6.1f} {hours:>7.1f}"
        )

    lines = [
        fill(
            f"{folder}: {len(data['runs'])} runs ("
            + ", ".join(f"{n} {k}" for k, n in sorted(kinds.items()))
            + f") of {len(data['configs'])} configurations in {len(data['tables'])} results "
            f"tables, {size / 2**20:.1f} MiB"
        ),
        f"{'results table':30s} {'runs':>6s} {' '.join(f'{k[:7]:>7s}' for k in runners)} "
        f"{'configs':>7s} {'whole':>5s} {'MiB':>6s} {'run (h)':>7s}",
    ]
    for name in sorted(data["tables"]):
        mine = [r for r in runs if r["name"] == name]
        files = [folder / "tables" / f"{name}.npz"] + [
            folder / r["whole"] for r in mine if r.get("whole")
        ]
        mib = sum(p.stat().st_size for p in files if p.is_file()) / 2**20
        lines.append(row(name, mine, mib))
    lines.append(row("all", list(runs), size / 2**20))
    sources = ", ".join(f"{k} {v[:16]}" for k, v in sorted(data["fingerprints"].items()))
    lines.append(fill(f"code: {sources}; rendered by {data['rendering_stack']}"))
    lines.append(
        fill(
            f"checked: the manifest against this code's fingerprints and its seals (each "
            f"table's SHA-256 with its runs' digests and wall times); the {checked['tables']} "
            f"tables and {checked['whole']} whole runs against their SHA-256; every row of "
            f"every table against its record's row digest; the whole runs' arrays against "
            f"their digests; the {checked['runs']} runs' keys against their configurations "
            "and seeds. Digests catch an edit, not a forgery resealed by someone who can run "
            "this code: that a run's arrays are its own is shown only by recomputing it "
            "(python -m docking verify)."
        )
    )
    return "\n".join(lines)


@dataclasses.dataclass
class Verify:
    """Recompute runs of the ledger and check each one against the ledger: its record's
    content digest and the row its results table serves, column by column. Every run of
    Experiments 1 and 2, plus SAMPLE others chosen from the current commit (successive
    commits check different runs); --table NAME: every run of a table; --all: every run."""

    sample: int = 3
    """How many runs besides Experiments 1 and 2 (0 or more)."""
    all: bool = False
    """Recompute every run of the ledger (hours on 2 cores; use --scheduler for a cluster)."""
    table: Annotated[tuple[str, ...], _shown("NAME ...", "none: the sample")] = ()
    """Recompute every run of these results tables instead (python -m docking ledger show
    lists them)."""
    scheduler: _Scheduler = None
    """Address of an existing Dask scheduler (tcp://HOST:PORT)."""
    processes: _Processes = None
    """Worker processes of the embedded cluster."""

    def execute(self) -> int:
        from docking.study import verify

        if self.sample < 0:
            raise ValueError(f"--sample must be 0 or more, got {self.sample}")
        if self.table and self.all:
            raise ValueError("--table and --all: give one of them")
        print(
            _verify_plan(self.sample, self.all, self.processes, self.scheduler, self.table),
            flush=True,
        )
        checks = verify.verify(
            None if self.all else self.sample,
            self.scheduler,
            workers=self.processes,
            tables=self.table,
        )
        bad = [c for c in checks if not c.ok]
        for c in checks:
            differs = "" if c.ok else f": {c.differences()} differ"
            print(
                f"{'ok' if c.ok else 'MISMATCH':8s} {c.name} seed {c.seed} ({c.key[:16]}){differs}"
            )
        print(f"{len(checks) - len(bad)} of {len(checks)} recomputed runs equal the ledger")
        for line in verify.platform_lines(bool(bad)):
            print(line)
        return 1 if bad else 0


def _verify_plan(
    sample: int,
    everything: bool,
    processes: int | None,
    scheduler: str | None = None,
    tables: tuple[str, ...] = (),
) -> str:
    """What ``verify`` is about to recompute, in one line: how many runs (``--sample`` capped
    at the other runs the ledger holds) and about how long, from the ledger's wall times of
    those runs, on ``processes`` workers (default: one per core; on a ``scheduler``'s
    cluster, their sum)."""
    from docking.study import ledger, verify

    data = ledger.manifest()
    if data is None:  # verify.verify says so
        return "verify: no ledger"
    commit = verify._commit()
    keys = verify.chosen(data, None if everything else sample, commit, tables)
    paper = len(verify.chosen(data, 0, commit))
    others = len(verify.chosen(data, len(data["runs"]), commit)) - paper
    seconds = sum(data["runs"][k]["wall_seconds"] for k in keys)
    workers = max(1, min(processes or os.cpu_count() or 1, len(keys)))
    what = (
        f"every run of the ledger ({len(keys)})"
        if everything
        else f"every run of {', '.join(tables)} ({len(keys)})"
        if tables
        else (
            f"{len(keys)} runs: the {paper} of {' and '.join(verify.PAPER_RUNS)} and "
            f"{len(keys) - paper} of the {others} others the ledger holds"
            + (f" (--sample {sample} capped at {others})" if sample > others else "")
        )
    )
    if scheduler is not None:
        return f"verify: recomputing {what} on {scheduler}: {_duration(seconds)} of wall time"
    return (
        f"verify: recomputing {what}; about {_duration(seconds / workers)} on {workers} "
        f"processes ({_duration(seconds)} of the runs' wall times in the ledger)"
    )


def _duration(seconds: float) -> str:
    """``1 h 05 min``, ``12 min``, ``40 s``."""
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds} s"
    hours, minutes = divmod(round(seconds / 60), 60)
    return f"{hours} h {minutes:02d} min" if hours else f"{minutes} min"


@dataclasses.dataclass
class Benchmark:
    """Environment steps per second against their floor (rendering + physics + preprocessing
    alone), and full Experiment 2 runs, one process and two (benchmarks/env_speed.py of a
    clone of the repository)."""

    repeats: Annotated[int | None, _shown("INT", "5; 3 with --quick")] = None
    """Repetitions of each timing (min and median are reported)."""
    steps: Annotated[int | None, _shown("INT", "2000; 500 with --quick")] = None
    """Environment steps per repetition."""
    seeds: str = "0-1"
    """Seeds of the Experiment 2 runs, as ranges or lists (0-1, 0,3)."""
    quick: bool = False
    """A smoke test of about 10 s on two idle cores: fewer, shorter repetitions and an
    Experiment 2 of 30 training and 10 test trials without its learning curve."""

    def execute(self) -> int:
        from docking.study.sweep import parse_seeds

        benchmark_module().run(self.repeats, self.steps, parse_seeds(self.seeds), self.quick)
        return 0


def benchmark_module():
    """The benchmark, ``benchmarks/env_speed.py`` of the clone this package runs from (it is
    not part of the package: a wheel has none, and says so)."""
    import importlib

    root = Path(__file__).resolve().parents[2]
    if not (root / "benchmarks" / "env_speed.py").is_file():
        raise ValueError(
            f"the benchmark is benchmarks/env_speed.py of the repository, and {root} holds "
            "none (an installed package): run it from a clone"
        )
    if str(root) not in sys.path:  # also where the benchmark's spawned processes look
        sys.path.insert(0, str(root))
    return importlib.import_module("benchmarks.env_speed")


Command = Union[  # noqa: UP007
    Annotated[Run, tyro.conf.subcommand("run")],
    Annotated[Sweep, tyro.conf.subcommand("sweep")],
    Annotated[DesignCommand, tyro.conf.subcommand("design")],
    Annotated[Report, tyro.conf.subcommand("report")],
    Annotated[Figures, tyro.conf.subcommand("figures")],
    Annotated[Ledger, tyro.conf.subcommand("ledger")],
    Annotated[Verify, tyro.conf.subcommand("verify")],
    Annotated[Benchmark, tyro.conf.subcommand("benchmark")],
]


def _exit_on_sigterm(signum, frame):
    # SystemExit unwinds the stack: a running sweep closes its cluster and workers.
    raise SystemExit(128 + signum)


#: The folder options whose empty value tyro would read as the current folder.
_FOLDER_OPTIONS = ("--results-dir", "--results_dir", "--folder")


def _empty_folder_option(argv: list[str]) -> str | None:
    """The first folder option of ``argv`` given an empty value (``--results-dir ''`` or
    ``--results-dir=``), which ``Path`` would turn into the current folder; else None."""
    for k, arg in enumerate(argv):
        name, equals, value = arg.partition("=")
        if name not in _FOLDER_OPTIONS:
            continue
        if not equals:
            value = argv[k + 1] if k + 1 < len(argv) else None
        if value is not None and not value.strip():
            return name
    return None


_LIST_ITEM = re.compile(r"\s*([-*\u2022]|\d+\.)\s")


def _reflow(text: str) -> str:
    """``text`` (a docstring) as one line per paragraph: blank lines and list items
    ("- ", "* ", "1. ") keep their breaks, every other line break becomes a space."""
    paragraphs = re.split(r"\n\s*\n", inspect.cleandoc(text))
    return "\n\n".join(
        "".join(
            ("\n" + line) if _LIST_ITEM.match(line) else (" " if k else "") + line.strip()
            for k, line in enumerate(p.split("\n"))
        )
        for p in paragraphs
    )


@contextlib.contextmanager
def _reflowed_help():
    """Help texts reflowed by :func:`_reflow` while tyro builds the parser. tyro 1.0 keeps a
    docstring's line break wherever the next line does not begin with a letter, and reads an
    option's docstring with its indentation, so every continued line of an option's text
    (and a line beginning ``_,`` or ``25-action``) broke the help mid-sentence."""
    from tyro import _strings

    original = getattr(_strings, "remove_single_line_breaks", None)
    if original is None:  # another tyro: its own reflowing
        yield
        return
    _strings.remove_single_line_breaks = _reflow
    try:
        yield
    finally:
        _strings.remove_single_line_breaks = original


#: The narrowest help tyro is given: at a few columns its formatter never ends (issue 41).
MIN_COLUMNS = 40


@contextlib.contextmanager
def _wide_enough():
    """``COLUMNS`` at least :data:`MIN_COLUMNS` while tyro builds the parser and its help: a
    narrower terminal (or ``COLUMNS=5``) gets the help at that width, wrapped by the
    terminal."""
    import shutil

    saved = os.environ.get("COLUMNS")
    if shutil.get_terminal_size().columns < MIN_COLUMNS:
        os.environ["COLUMNS"] = str(MIN_COLUMNS)
    try:
        yield
    finally:
        if saved is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = saved


@contextlib.contextmanager
def _help_of(argv: list[str]):
    """``argv`` with :data:`HELP_ALL` read as ``--help``; while tyro builds the parser for a
    ``--help`` (not :data:`HELP_ALL`), an experiment's options are its common ones
    (:data:`COMMON`)."""
    global _brief
    saved = _brief
    _brief = HELP_ALL not in argv and any(a in ("-h", "--help") for a in argv)
    try:
        yield ["--help" if a == HELP_ALL else a for a in argv]
    finally:
        _brief = saved


def parse(argv: list[str]) -> Command:
    """The command ``argv`` names, parsed and checked, not run (``SystemExit`` as argparse
    exits: on bad input, and after printing ``--help``)."""
    with _reflowed_help(), _wide_enough(), _help_of(argv) as args:
        return tyro.cli(
            Command,
            args=args,
            prog=PROG,
            description=DESCRIPTION,
            config=(tyro.conf.CascadeSubcommandArgs,),
            registry=_registry,
        )


def main(argv=None) -> int:
    """Parse ``argv`` (default ``sys.argv[1:]``) and run the subcommand; its exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    empty = _empty_folder_option(argv)
    if empty is not None:  # as DOCKING_RESULTS / DOCKING_FIGURES set but empty are refused
        print(
            f"{PROG}: error: {empty} is empty; name a folder, or leave the option out",
            file=sys.stderr,
        )
        return 2
    try:
        command = parse(argv)
    except KeyboardInterrupt:  # Ctrl-C while tyro builds the parser
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    signal.signal(signal.SIGTERM, _exit_on_sigterm)
    try:
        _check_opengl_platform()  # RenderingUnavailable, a RuntimeError: one line
        return command.execute()
    except KeyboardInterrupt:  # Ctrl-C: a running sweep has closed its cluster on the way
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except ValueError as exc:  # bad input (seeds, grid entries, configuration values)
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    except (OSError, RuntimeError, LookupError) as exc:
        # A folder that cannot be written, a scheduler that does not answer, code or a
        # ledger that changed (StaleCode, StaleLedger), a run the ledger does not keep.
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 1
