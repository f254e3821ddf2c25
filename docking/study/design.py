"""One way to ask a question: a *design* is data, one runner runs any design, and the results
have one shape.

A :class:`Design` is a grid of :class:`Cell` s (each an
:class:`~docking.experiments.ExperimentConfig` with typed coordinates, e.g.
``world="floor", variant="frozen"``), the seeds every cell runs for, the *measure* (the
held-out trials, or the main test), and the claims judged on it (:mod:`docking.study.claims`).
:func:`run_design` runs (or loads: :mod:`docking.study.store`, through the ledger when the store
lacks a run) every trained cell for every seed in one sweep (:mod:`docking.study.sweep`), judges
the *test-only* cells (a baseline's networks measured in another world), then any *stage*
whose cells depend on measured runs (e.g. a control whose constant is measured on the
paper's runs). It returns :class:`Results`: per cell, the runs in seed order, the measured
trial logs, and the per-seed success (``Results.scores``, one array per cell: rliable's
``score_dict``).

Design files live in :mod:`docking.study.designs` (``python -m docking design list``); a new study
is a new design file, nothing else.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping, Sequence
from types import MappingProxyType

import numpy as np

from docking.experiments import ExperimentConfig, ExperimentResult, TrialLog, heldout_trials
from docking.scene import WorldConfig
from docking.study.kinds import runner_for
from docking.validate import check_instance, check_name

__all__ = [
    "MEASURES",
    "Cell",
    "Design",
    "Results",
    "judge",
    "rules_text",
    "read_design",
    "run_design",
    "summary",
    "tested_in",
    "yardstick_config",
]

#: What a design measures: ``"heldout"`` (each run's held-out trials, or a test-only cell's
#: trials in its world) or ``"test"`` (each run's main test trials).
MEASURES = ("heldout", "test")


@dataclasses.dataclass(frozen=True, eq=False)
class Cell:
    """One cell of a design: a configuration and where it sits in the design.

    Attributes:
      key: Unique within the design (``"floor/frozen"``); names the cell in results, never
        parsed: ask :attr:`coords` instead.
      config: The run that trains the cell's networks (for a test-only cell: its
        baseline's configuration); a ``docking.study.ppo.PPOConfig`` for the pixel-level bound.
      coords: Typed coordinates (``{"world": "floor", "variant": "frozen"}``,
        ``{"actions": "turning", "task": "precision", "noise_deg": 4.0}``): what a notebook
        or figure selects and groups by.
      label: What the cell is, for tables and figures.
      baseline: The key of the cell it is compared with, or None.
      test_world: A test-only cell: its baseline's networks are measured in this world on
        the held-out streams (no training of its own). None: a trained cell.
      core: Part of the design's default run (else added by ``full=True``).
      claim: The key of the claim it bears on, if any.
      seeds: The cell's own seeds, if not the design's (e.g. fewer for a yardstick).
    """

    key: str
    config: ExperimentConfig
    coords: Mapping[str, object] = dataclasses.field(default_factory=dict)
    label: str = ""
    baseline: str | None = None
    test_world: WorldConfig | None = None
    core: bool = True
    claim: str | None = None
    seeds: tuple[int, ...] | None = None

    def __post_init__(self):
        if not isinstance(self.key, str) or not self.key:
            raise ValueError(f"Cell.key must be a non-empty string, got {self.key!r}")
        try:
            runner = runner_for(self.config)
        except TypeError:
            raise TypeError(
                f"Cell {self.key!r}: config must be an ExperimentConfig or a PPOConfig, got "
                f"{self.config!r:.80}"
            ) from None
        if not runner.test_elsewhere and self.test_world is not None:
            raise ValueError(f"Cell {self.key!r}: a {runner.name.upper()} cell cannot be test-only")
        if self.test_world is not None:
            check_instance(f"Cell {self.key!r}", "test_world", self.test_world, WorldConfig)
            if self.baseline is None:
                raise ValueError(f"Cell {self.key!r}: a test-only cell needs a baseline")
        object.__setattr__(self, "coords", MappingProxyType(dict(self.coords)))
        if self.seeds is not None:
            object.__setattr__(self, "seeds", tuple(int(x) for x in self.seeds))
        if not self.label:
            object.__setattr__(self, "label", ", ".join(f"{v}" for v in self.coords.values()))

    def __getitem__(self, name: str):
        """The coordinate ``name`` (``cell["world"]``); ``KeyError`` naming the cell's
        coordinates if it has none of that name."""
        if name not in self.coords:
            raise KeyError(
                f"cell {self.key!r} has no coordinate {name!r} ({', '.join(self.coords)})"
            )
        return self.coords[name]

    @property
    def trained(self) -> bool:
        """Whether the cell trains networks of its own (not a test-only cell)."""
        return self.test_world is None

    @property
    def world(self) -> WorldConfig:
        """The world the cell is measured in."""
        if self.test_world is not None:
            return self.test_world
        return getattr(self.config, "heldout_world", None) or self.config.world


@dataclasses.dataclass(frozen=True, eq=False)
class Design:
    """A question as data: cells x seeds, a measure, claims.

    Attributes:
      name: Identifies the design (``python -m docking design run NAME``).
      title: One line: what the design asks.
      cells: Every cell (core and sensitivity; see :attr:`Cell.core`).
      seeds: The seeds every cell runs for.
      measure: One of :data:`MEASURES`.
      claims: The :class:`docking.study.claims.Claim` s judged on the results.
      stages: Functions ``results -> [Cell, ...]`` for cells that need measured runs first
        (run after the cells above, in order).
      report: A function ``results -> str`` (Markdown) that :func:`summary` prints after the
        cells' numbers (e.g. a table of the design's own); None: nothing more.
      alpha: The level of the claims' verdicts (required with claims): Holm's adjustment
        within each claim over its comparisons decides, and one family of every comparison
        is reported beside it (:func:`docking.study.claims.design_verdicts`, what :func:`summary`
        prints, the README's verdict table).
      whole: ``{cell key: seeds}``: the runs the committed ledger keeps whole (those whose
        weights or trajectories an analysis or figure reads); the others it keeps as rows
        of its results table (:mod:`docking.study.ledger`).
      keep: What the ledger's table keeps of the design's runs beyond each trial's outcome:
        ``"paths"``, the paths (poses, actions) of the failed test and held-out trials (what
        the failure taxonomy reads); ``"starts"``, every trial's start pose; ``"networks"``,
        each run's W and Q; ``"winners"``, the winning unit of every test and held-out step;
        ``"ends"``, every test and held-out trial's final pose; ``"no-train"``
        (:data:`docking.study.ledger_rows.NO_TRAIN`), no training trial's outcome (where no analysis
        of the design reads them).
      networks: ``{cell key: seeds}``: runs whose W and Q the table keeps besides (as
        ``"networks"`` in :attr:`keep` does for every run).
      keep_cells: ``{cell key: what}``: what the table keeps of that cell's runs besides
        :attr:`keep` (e.g. final poses where a measure reads them).
      kept_seeds: ``{what: seeds}``: what of :attr:`keep` the table keeps only for these
        seeds (e.g. the failures' paths of the seeds an analysis pools).
    """

    name: str
    title: str
    cells: tuple[Cell, ...]
    seeds: tuple[int, ...]
    measure: str = "heldout"
    claims: tuple = ()
    stages: tuple[Callable[[Results], Sequence[Cell]], ...] = ()
    report: Callable[[Results], str] | None = None
    alpha: float | None = None
    whole: dict[str, tuple[int, ...]] = dataclasses.field(default_factory=dict)
    keep: frozenset[str] = frozenset()
    networks: dict[str, tuple[int, ...]] = dataclasses.field(default_factory=dict)
    keep_cells: dict[str, frozenset[str]] = dataclasses.field(default_factory=dict)
    kept_seeds: dict[str, tuple[int, ...]] = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        check_name("Design", "name", self.name)
        if self.alpha is not None and not 0 < self.alpha < 1:
            raise ValueError(f"Design.alpha must be in (0, 1) or None, got {self.alpha!r}")
        if self.claims and self.alpha is None:
            raise ValueError(f"Design {self.name!r} has claims: give the level of their verdicts")
        if self.measure not in MEASURES:
            raise ValueError(f"Design.measure must be one of {MEASURES}, got {self.measure!r}")
        keys = [c.key for c in self.cells]
        if len(set(keys)) != len(keys):
            raise ValueError(f"Design {self.name!r}: cell keys repeat")
        for c in self.cells:
            if c.test_world is not None and self.measure != "heldout":
                raise ValueError(f"Design {self.name!r}: test-only cells need measure='heldout'")
        if not self.seeds:
            raise ValueError(f"Design {self.name!r} has no seeds")
        object.__setattr__(self, "cells", tuple(self.cells))
        object.__setattr__(self, "seeds", tuple(int(s) for s in self.seeds))
        object.__setattr__(self, "claims", tuple(self.claims))
        object.__setattr__(self, "stages", tuple(self.stages))

    def run(self, full: bool = False, **options) -> Results:
        """:func:`run_design` of this design (options: ``seeds``, ``results_dir``,
        ``scheduler``, ``workers``, ``progress``)."""
        return run_design(self, full=full, **options)

    def read(self, results_dir=None) -> Results:
        """:func:`read_design` of this design: its results read, never computed."""
        return read_design(self, results_dir)

    def only(self, patterns: Sequence[str]) -> Design:
        """This design with only the cells whose keys match one of ``patterns`` (shell-style,
        e.g. ``"floor/*"``) and the baselines their test-only cells need, without stages,
        claims or report (they read every cell): the same runs, for computing part of a
        design first.
        A pattern that matches no cell is a ``ValueError`` naming the keys."""
        from fnmatch import fnmatchcase

        keys = [c.key for c in self.cells]
        for pattern in patterns:
            if not any(fnmatchcase(k, pattern) for k in keys):
                raise ValueError(f"design {self.name!r} has no cell matching {pattern!r}: {keys}")
        chosen = {k for k in keys if any(fnmatchcase(k, p) for p in patterns)}
        chosen |= {c.baseline for c in self.cells if c.key in chosen and not c.trained}
        cells = tuple(c for c in self.cells if c.key in chosen)
        return dataclasses.replace(self, cells=cells, stages=(), claims=(), report=None)

    def select(self, full: bool = False) -> list[Cell]:
        """The cells of a default run (the core ones), or every cell if ``full``."""
        return [c for c in self.cells if full or c.core]

    def cell(self, key: str) -> Cell:
        return _find(self.cells, key, self.name)


def rules_text(design: Design, constants: dict) -> str:
    """A design's rules as canonical text (JSON, sorted keys), what its test pins by a
    digest before its runs: ``constants`` (its named values), its claims (words, source,
    what is compared, the rule, the comparisons, the measure, judged or not) and every cell
    (key, configuration, baseline, seeds, test world)."""
    import json

    claims = [
        dict(
            key=c.key,
            words=c.words,
            source=c.source,
            compares=c.compares,
            rule=repr(c.rule),
            cells={
                w: [e if isinstance(e, str) else list(e) for e in v] for w, v in c.cells.items()
            },
            measure=c.measure.__name__,
            judged=c.judged,
        )
        for c in design.claims
    ]
    cells = [
        dict(
            key=c.key,
            config=c.config.to_dict(),
            baseline=c.baseline,
            seeds=c.seeds,
            test_world=None if c.test_world is None else dataclasses.asdict(c.test_world),
        )
        for c in design.cells
    ]
    text = {"constants": constants, "claims": claims, "cells": cells}
    return json.dumps(text, sort_keys=True, indent=1, default=list)


def rules_data(design: Design, constants: dict) -> dict:
    """A design's rules as data: :func:`rules_text` parsed (what its record is held against,
    :mod:`docking.study.records`)."""
    import json

    return json.loads(rules_text(design, constants))


def yardstick_config(base: ExperimentConfig, policy: str, heldout_trials: int) -> ExperimentConfig:
    """The yardstick run of ``policy`` (``ExperimentConfig.policy``: "oracle", "centroid",
    "forward", "random") in ``base``'s world: no training and no main test, ``heldout_trials``
    held-out trials per seed on ``base``'s held-out streams; stored under the name
    ``yardsticks`` (so that designs asking for the same yardstick share its runs)."""
    return dataclasses.replace(
        base,
        name="yardsticks",
        policy=policy,
        train_trials=0,
        eval_trials=0,
        test_trials=0,
        pretrain_trials=0,
        heldout_trials=heldout_trials,
    )


def _find(cells, key: str, where: str) -> Cell:
    for c in cells:
        if c.key == key:
            return c
    raise KeyError(f"{where} has no cell {key!r}")


@dataclasses.dataclass
class Results:
    """What :func:`run_design` returns: one shape for every design.

    Attributes:
      design: The design run.
      cells: The cells run, in order (a stage's cells last).
      runs: ``{cell key: runs in seed order}`` (a test-only cell: its baseline's runs
        tested in its world, :func:`tested_in`; a PPO cell: ``docking.study.ppo.PPOResult`` s).
      logs: ``{cell key: the measured trial logs in seed order}``.
      sources: ``{trained cell key: where each seed's run came from}``, ``"computed"``,
        ``"store"`` or ``"ledger"`` (:func:`docking.study.runs.locate`, asked before the run).
    """

    design: Design
    cells: list[Cell]
    runs: dict[str, list[ExperimentResult]]
    logs: dict[str, list[TrialLog]]
    sources: dict[str, list[str]] = dataclasses.field(default_factory=dict)
    _measured: dict = dataclasses.field(default_factory=dict, repr=False, compare=False)

    def cell(self, key: str) -> Cell:
        return _find(self.cells, key, f"the results of {self.design.name!r}")

    def measured(self, measure: Callable, key: str) -> np.ndarray:
        """``measure(self, key)`` (per-seed values of cell ``key``), computed once for these
        results and then served read-only: for a measure that costs seconds per cell (one
        that renders views), which several claims, tables and figures ask for."""
        found = self._measured.get((measure, key))
        if found is None:
            found = np.array(measure(self, key))
            found.flags.writeable = False
            self._measured[measure, key] = found
        return found

    def score(self, key: str) -> np.ndarray:
        """Per seed, the measured success rate of cell ``key``."""
        return np.array([log.success_rate for log in self.logs[key]])

    @property
    def scores(self) -> dict[str, np.ndarray]:
        """``{cell key: per-seed success}`` (rliable's ``score_dict``)."""
        return {c.key: self.score(c.key) for c in self.cells}

    def where(self, **coords) -> list[Cell]:
        """The cells whose coordinates include ``coords`` (``where(world="floor")``)."""
        return [
            c
            for c in self.cells
            if all(k in c.coords and c.coords[k] == v for k, v in coords.items())
        ]


def judge(
    design: Design, cells: Sequence[Cell], runs: Mapping[str, list], results_dir=None
) -> Results:
    """The results of ``cells`` from the runs of their trained cells: each trained cell's
    measured logs, and each test-only cell's held-out trials of its baseline's networks in
    its world (:func:`tested_in`: stored like runs, computed once)."""
    runs, logs = dict(runs), {}
    for c in cells:
        if not c.trained:
            runs[c.key] = [tested_in(r, c.test_world, results_dir) for r in runs[c.baseline]]
        logs[c.key] = [
            r.heldout if design.measure == "heldout" or not c.trained else r.test
            for r in runs[c.key]
        ]
    return Results(design, list(cells), runs, logs)


def tested_in(run: ExperimentResult, world: WorldConfig, results_dir=None) -> ExperimentResult:
    """``run``'s networks tested in ``world``: the run of ``run.config`` with
    ``heldout_world=world``. Its training and main test are ``run``'s (``heldout_world``
    changes only where the held-out trials are drawn), so it is derived from ``run`` by
    computing the held-out trials alone, bit for bit what ``run_experiment`` of that
    configuration computes (``python -m docking verify`` recomputes it in full). Stored and
    served like any run (the store, then the ledger); computed in memory, not stored, when
    ``run`` itself comes from the ledger."""
    from docking.study.kinds import load_result, result_path, run_key, save_result
    from docking.study.runs import load_run
    from docking.study.store import check_inside

    config = dataclasses.replace(run.config, heldout_world=world)
    found = load_run(config, run.seed, results_dir)  # its folder checked: written below
    if found is not None:
        return found
    source = check_inside(result_path(run.config, run.seed, results_dir))
    stored = source.exists()
    base = load_result(source, run_key(run.config, run.seed)) if stored else run
    t0 = time.perf_counter()
    heldout = heldout_trials(config, run.seed, base.network, world)
    result = ExperimentResult(
        config=config,
        seed=run.seed,
        network=base.network,
        train=base.train,
        test=base.test,
        curve_trials=base.curve_trials,
        curve_success=base.curve_success,
        curve_steps=base.curve_steps,
        curve_rewarded=base.curve_rewarded,
        wall_time_train=base.wall_time_train,
        wall_time_test=time.perf_counter() - t0,
        heldout=heldout,
    )
    if not stored:
        return result
    save_result(result, result_path(config, run.seed, results_dir))
    return result


def ledger_runs(
    design: Design, full: bool = False, stored_only: bool = False, results_dir=None
) -> list[tuple]:
    """The runs of ``design`` the committed ledger holds: ``(config, seed, whole, keep)``
    for every trained cell's seeds and every test-only cell's derived runs
    (:func:`tested_in`), ``whole`` and ``keep`` as :attr:`Design.whole`,
    :attr:`Design.keep` and :attr:`Design.networks` say; a stage's cells too (its
    function asked on the runs before it). ``stored_only``: only the cells whose runs the
    results store holds (a design whose runs are under way), and a stage only if the cells
    it reads and its own are all there."""
    cells = _ledger_cells(design, full, stored_only, results_dir)
    found = []
    for c in cells:
        for config, seed in _entries(design, cells, c):
            keep = design.keep | design.keep_cells.get(c.key, frozenset())
            if seed in design.networks.get(c.key, ()):
                keep |= {"networks"}
            keep -= {what for what, seeds in design.kept_seeds.items() if seed not in seeds}
            found.append((config, seed, seed in design.whole.get(c.key, ()), keep))
    return found


def _ledger_cells(design: Design, full: bool, stored_only: bool, results_dir) -> list[Cell]:
    """The cells whose runs :func:`ledger_runs` gives: the selected ones (``stored_only``:
    those stored), then the stages' (each asked on the runs before it)."""
    cells = design.select(full)
    if stored_only:
        cells = [c for c in cells if _stored(design, cells, c, results_dir)]
    if design.stages and len(cells) == len(design.select(full)):
        cells = _with_stages(design, cells, stored_only, results_dir)
    elif design.stages and stored_only:  # the stages may need only the cells stored so far
        try:
            cells = _with_stages(design, cells, stored_only, results_dir)
        except KeyError:  # a stage asked for a cell not stored yet: none of its cells
            pass
    return cells


def cell_runs(
    design: Design,
    patterns: Sequence[str] = (),
    seeds: Sequence[int] | None = None,
    results_dir=None,
) -> list[tuple[str, object, int]]:
    """``(cell key, config, seed)`` of each run the committed ledger keeps of ``design``'s
    cells (:func:`ledger_runs`: its core cells, a stage's cells, each test-only cell's derived
    runs) whose keys match one of the shell-style ``patterns`` (``"floor/paper"``,
    ``"floor/*"``; none: every cell), for their seeds or, of them, those of ``seeds``: the runs
    behind a number, which ``python -m docking verify --design`` recomputes. A stage's cells
    are asked of the runs before them (read from the store, else the ledger), as far as they
    are held (a design under way: the stages whose runs before them are all there).
    ``ValueError`` naming the cells for a pattern that matches none of them (and saying so of
    a cell outside the design's default run, whose runs the ledger does not keep), and naming
    the cells' seeds for a seed none of the chosen cells runs."""
    from fnmatch import fnmatchcase

    check_instance("cell_runs", "design", design, Design)
    patterns = (patterns,) if isinstance(patterns, str) else tuple(patterns)
    cells = _held_cells(design, results_dir)
    for pattern in patterns:
        _check_pattern(design, cells, pattern)
    chosen = [c for c in cells if not patterns or any(fnmatchcase(c.key, p) for p in patterns)]
    asked = None if seeds is None else [int(s) for s in seeds]
    if asked is not None:
        _check_seeds(design, chosen, asked)
    found = []
    for c in chosen:
        for config, seed in _entries(design, cells, c):
            if asked is None or seed in asked:
                found.append((c.key, config, seed))
    return found


def _held_cells(design: Design, results_dir) -> list[Cell]:
    """``design``'s core cells and its stages' cells, each stage asked of the runs before
    it while the store or the ledger holds them all (:func:`cell_runs`)."""
    cells = design.select(False)
    if not design.stages:
        return cells

    def runs_of(new, before):
        try:
            return _loaded(design, new, results_dir)
        except LookupError:  # not held (yet): the walk stops before this stage
            return None

    return _walk(design, cells, runs_of, results_dir)[0] or cells


def _check_pattern(design: Design, cells: list[Cell], pattern) -> None:
    """``ValueError`` unless ``pattern`` matches a key of ``cells`` (:func:`cell_runs`)."""
    from fnmatch import fnmatchcase

    if not isinstance(pattern, str) or not pattern:
        raise ValueError(f"cell_runs: a cell pattern must be a non-empty string, got {pattern!r}")
    keys = [c.key for c in cells]
    if any(fnmatchcase(k, pattern) for k in keys):
        return
    others = [c.key for c in design.cells if fnmatchcase(c.key, pattern)]
    if others:
        raise ValueError(
            f"design {design.name!r}: {', '.join(others)[:200]} (matching {pattern!r}) "
            "is outside its default run (design run --full): the ledger keeps no run of it"
        )
    raise ValueError(
        f"design {design.name!r} has no cell matching {pattern!r}; its cells: "
        f"{', '.join(keys)[:600]}"
    )


def _check_seeds(design: Design, chosen: list[Cell], asked: list[int]) -> None:
    """``ValueError`` unless some cell of ``chosen`` runs each seed of ``asked``."""
    from docking.study.sweep import seeds_text

    runs_seeds = {s for c in chosen for s in (c.seeds or design.seeds)}
    absent = [s for s in asked if s not in runs_seeds]
    if asked and not absent:
        return
    what = f"no cell chosen runs seed {', '.join(map(str, absent))[:200]}" if asked else "no seed"
    raise ValueError(
        f"design {design.name!r}: {what}; the chosen cells' seeds: {seeds_text(sorted(runs_seeds))}"
    )


def _entries(design: Design, cells, c: Cell) -> list[tuple]:
    """``(config, seed)`` of each run of cell ``c`` (a test-only cell: its derived runs)."""
    config = c.config
    if not c.trained:
        base = _find(cells, c.baseline, design.name).config
        config = dataclasses.replace(base, heldout_world=c.test_world)
    return [(config, seed) for seed in c.seeds or design.seeds]


def _stored(design: Design, cells, c: Cell, results_dir=None) -> bool:
    from docking.study.kinds import result_path

    return all(result_path(*e, results_dir).exists() for e in _entries(design, cells, c))


def _walk(design: Design, cells: list[Cell], runs_of, results_dir=None) -> tuple:
    """``cells``, then the cells of each of ``design``'s stages, each stage asked on the
    results before it, while ``runs_of(new, before)`` gives the runs of the ``new`` cells
    (``{key: runs}``; ``before``: the cells walked so far); its None stops the walk. The cells
    walked and their :class:`Results` (None if the first call stopped)."""
    runs = runs_of(cells, [])
    if runs is None:
        return [], None
    results = judge(design, cells, runs, results_dir)
    for stage in design.stages:
        extra = list(stage(results))
        more = runs_of(extra, cells)
        if more is None:
            break
        cells, runs = cells + extra, {**runs, **more}
        results = judge(design, cells, runs, results_dir)
    return cells, results


def _loaded(design: Design, cells, results_dir=None) -> dict[str, list]:
    """The runs of the trained ``cells``, from the store, else the ledger (LookupError if
    neither holds one)."""
    from docking.study.runs import load_run

    found = {}
    for c in (c for c in cells if c.trained):
        found[c.key] = [load_run(*e, results_dir) for e in _entries(design, cells, c)]
        if any(r is None for r in found[c.key]):
            raise LookupError(_absent(design, c))
    return found


def _absent(design: Design, cell: Cell) -> str:
    return (
        f"design {design.name!r}: runs of cell {cell.key!r} are neither stored nor in "
        "the ledger; run the design first (python -m docking design run "
        f"{design.name}), or write what is there (ledger update --under-way "
        f"{design.name})"
    )


def _with_stages(design: Design, cells: list[Cell], stored_only: bool, results_dir) -> list[Cell]:
    """``cells`` and the cells of ``design``'s stages (:func:`_walk`, the runs loaded); with
    ``stored_only``, a stage only if the store holds all its runs."""

    def runs_of(new, before):
        if before and stored_only:
            if not all(_stored(design, before + new, c, results_dir) for c in new):
                return None
        return _loaded(design, new, results_dir)

    return _walk(design, cells, runs_of, results_dir)[0]


def absent_runs(design: Design, results_dir=None) -> list:
    """The jobs (:class:`docking.study.sweep.Job`) of ``design``'s core cells that neither the
    results store nor the ledger holds, what :func:`run_design` would compute; a stage's
    cells are asked once every run before them is there. Each job is located once
    (:func:`docking.study.runs.locate`)."""
    from docking.study.runs import locate
    from docking.study.sweep import Job

    found = []

    def runs_of(new, before):
        runs = {}
        for c in (c for c in new if c.trained):
            located = [locate(*e, results_dir, warn=False) for e in _entries(design, new, c)]
            found.extend(Job(f.config, f.seed) for f in located if f.place == "computed")
            runs[c.key] = [f.run for f in located]
        return None if found else runs

    _walk(design, design.select(False), runs_of, results_dir)
    return found


def _sweep(cells, seeds, desc: str, options, sources: dict) -> dict[str, list]:
    """Run (or load) the trained ``cells``: one sweep per distinct seed list (a cell's own
    seeds, else ``seeds``); where each run comes from goes into ``sources``."""
    from docking.study.sweep import run_configs

    groups: dict[tuple[int, ...], dict] = {}
    for c in cells:
        if c.trained:
            groups.setdefault(c.seeds or tuple(seeds), {})[c.key] = c.config
    runs = {}
    for k, (group_seeds, configs) in enumerate(groups.items()):
        label = desc if len(groups) == 1 else f"{desc} ({k + 1}/{len(groups)})"
        runs.update(run_configs(configs, group_seeds, desc=label, sources=sources, **options))
    return runs


def run_design(
    design: Design,
    full: bool = False,
    seeds: Sequence[int] | None = None,
    results_dir=None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
) -> Results:
    """Run (or load) ``design``: its cells (every cell if ``full``, else the core ones) for
    its seeds (or ``seeds``) in one sweep, then its stages, each in a sweep of its own."""
    check_instance("run_design", "design", design, Design)
    seeds = design.seeds if seeds is None else tuple(seeds)
    options = dict(results_dir=results_dir, scheduler=scheduler, workers=workers, progress=progress)
    cells = design.select(full)
    for c in cells:
        if not c.trained and c.baseline not in {x.key for x in cells}:
            raise ValueError(f"design {design.name!r}: cell {c.key!r} needs its baseline's runs")
    stages = (f"{design.name} (stage {k + 1})" for k in range(len(design.stages)))
    labels, sources = iter([design.name, *stages]), {}

    def runs_of(new, _):
        return _sweep(new, seeds, next(labels), options, sources)

    results = _walk(design, cells, runs_of, results_dir)[1]
    results.sources.update(sources)
    return results


def read_design(design: Design, results_dir=None) -> Results:
    """``design``'s results (its core cells, then each stage's cells asked of the runs before
    it), every run read from the results store ``results_dir``, else the committed ledger;
    never computed: ``LookupError`` naming a cell whose runs neither holds (what a published
    study's reader wants: a report, a notebook, :func:`docking.study.contest.published`,
    where a missing run is news, not hours of computing to start unasked)."""
    check_instance("read_design", "design", design, Design)

    def runs_of(new, _before):
        return _loaded(design, new, results_dir)

    return _walk(design, design.select(False), runs_of, results_dir)[1]


def summary(results: Results) -> str:
    """What a design's run shows, as Markdown: every cell's measured success (over its
    seeds, with the 95% interval for a rate, :func:`docking.study.claims.rate_interval`), the
    design's own report, and its claims' verdict table
    (:func:`docking.study.claims.design_verdicts`)."""
    from docking.study.claims import rate_interval

    design = results.design
    lines = [f"| cell | {design.measure} success (95% interval) | what it is |", "|---|---|---|"]
    for c in results.cells:
        score = results.score(c.key)  # one seed (a tuning round's first): no interval
        shown = (
            rate_interval(results, c.key).format(unit="%")
            if len(score) > 1
            else f"{100 * score[0]:.1f}%"
        )
        lines.append(f"| {c.key} | {shown} (seeds: {len(score)}) | {c.label} |")
    parts = ["\n".join(lines)]
    if design.report is not None:
        parts.append(design.report(results))
    if design.claims:
        from docking.study.claims import design_verdicts

        parts.append(design_verdicts(results))
    return "\n\n".join(parts)
