"""``run``, ``sweep`` and ``design``: runs of a configuration, a parameter grid or a design,
each job located once (:func:`docking.study.runs.locate`) and the rest computed on a Dask
cluster; what each run's line says (its configuration's options, its success, where it came
from).
"""

from __future__ import annotations

import collections
import dataclasses
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, Union

import tyro

from docking.study import paths
from docking.study.cli import PROG
from docking.study.cli.options import (
    _DesignSeeds,
    _ExperimentSeeds,
    _Processes,
    _ResultsDir,
    _Scheduler,
    _seed_text,
    _shown,
)
from docking.study.designs import names as _design_names

if TYPE_CHECKING:
    from docking.experiments import ExperimentConfig


def _experiment():
    """The configurations EXPERIMENT names, as tyro's subcommands
    (:data:`docking.study.cli.named.EXPERIMENT`), imported when run's or sweep's options are
    built (the experiment's modules: no other command imports them to parse), once MuJoCo is
    known to render here (they import it)."""
    from docking.study.cli import check_rendering

    check_rendering()
    from docking.study.cli.named import EXPERIMENT

    return EXPERIMENT


#: run's and sweep's EXPERIMENT, an :class:`~docking.experiments.ExperimentConfig`.
_ExperimentArg = Annotated[
    Any,
    tyro.conf.arg(name="", constructor_factory=_experiment),
    tyro.conf.OmitSubcommandPrefixes,
]


def _seeds_of(config: ExperimentConfig, text: str | None) -> list[int]:
    from docking.study.cli.named import seeds_of
    from docking.study.sweep import parse_seeds

    if text is None:
        return list(seeds_of(config.name))
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
    import numpy as np

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

    EXPERIMENT names one of the paper's experiments (docking.presets.EXPERIMENTS) or
    Experiment 2 in a study world, floor or nao, with the paper's learner at its published
    settings or a learner at the settings the design named in parentheses tuned
    (docking.study.cli.named); options after it override its fields (e.g. --network.eps-w 0,
    --train-trials 500)."""

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
    """The named configuration (:data:`docking.study.cli.named.NAMED`) ``config`` differs
    least from (its namesake first)."""
    from docking.study.cli.named import NAMED

    return min(
        (named for named, _, _ in NAMED.values()),
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
