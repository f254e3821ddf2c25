"""The contest as a function: any learner through the third edition's contest, its row beside
the published rows (docs/guide/bring_your_own_learner.md).

:func:`contest` runs a learner (a registered one, :mod:`docking.study.learners`, or the package's
own) as the third edition (:mod:`docking.study.designs.third_edition`) ran the paper's learner,
linear SARSA and PPO:

* **the same tuning budget** in each world: a successive halving over the learner's grid of
  9 settings (its default first), :class:`docking.study.designs.builders.Tuning` itself: round 1
  trains every setting on the first tuning seed, the best 3 train again on the two other
  tuning seeds, the best mean over the tuning seeds' held-out trials is the tuned setting
  (ties: grid order); 15 training runs per world;
* **fresh tuning seeds** (:data:`TUNING_SEEDS`), used by no published design, so that tuning
  never reads the streams the published rows were judged or tuned on;
* **matched seeds**: the tuned setting is judged on the published judged seeds
  (3000-3019), each run on its own seed's held-out stream
  (:func:`docking.protocol.heldout_log`), 500 trials each, so its success is compared seed
  by seed with the published rows' (the seeds are matched; the trials are not paired: each
  run's first start pose is the same, its later ones and its step noise follow its own path);
* **the gap rule**: per world, each published tuned learner's lead over the new learner,
  over the seeds both have (the per-seed differences' Student-t interval), is *closed* if its
  interval lies below 5 pp
  (:data:`docking.study.designs.third_edition.GAP_CLOSED`), *remains* if above, else
  *undecided*: the rule the edition judged linear SARSA's lead over the paper's learner by
  (:func:`docking.study.report.contest_gaps`).

The published rows are read from the committed ledger, never computed (:func:`published`:
``LookupError`` if the ledger lacks one): the contest's own (the third edition's, judged on
the same seeds, so the gap rule compares them seed by seed) and, where they exist, the
current ones (:data:`BRACKETED`: the floor and Nao-like worlds' learners tuned alike to
bracketed optima and judged on other fresh seeds, :func:`bracketed`), shown beside them and
compared by Welch's interval, their seeds being others. The table says where the learner's
runs are stored and how many were computed and how many read. The learner's own runs are a
design (:class:`docking.study.design.Design`) run by :func:`docking.study.design.run_design`: a
sweep on the embedded Dask cluster or on an existing scheduler (``scheduler=``), with progress bars,
stored in the results store and re-used (a second call computes nothing).

A smaller budget (:func:`small_budget`: fewer worlds, settings, seeds or held-out trials)
runs in seconds, for examples and tests; its table and figure say that it is not the
contest.
"""

from __future__ import annotations

import collections
import dataclasses
import functools
import inspect
import json
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from docking.presets import EXPERIMENT_2
from docking.scene import WorldConfig
from docking.study import kinds, paths
from docking.study.design import Cell, Design, Results, run_design
from docking.study.designs import third_edition as published_contest
from docking.study.designs.builders import HELDOUT_TRIALS, YARDSTICK_LABELS, Tuning
from docking.validate import MAX_COUNT, check_instance, check_int, check_name

__all__ = [
    "CONTEST_BUDGET",
    "TUNING_SEEDS",
    "WORLDS",
    "Budget",
    "Contest",
    "contest",
    "published",
    "small_budget",
]

#: The contest's worlds, ``{key: WorldConfig}``: the sideboard, floor and Nao-like worlds.
WORLDS: dict[str, WorldConfig] = {
    key: published_contest.WORLDS[key][1] for key in published_contest.CONTEST
}

#: The tuning seeds of every contest run here: fresh, used by no published design (which use
#: 0-9, 3000-3019, 3900-3902, 4000-4019, 5000-5009 and 5900-5929).
TUNING_SEEDS = (3910, 3911, 3912)

#: The published tuned learners (cell variants) and what tables call them.
TUNED = {
    "linear-tuned": "linear SARSA, tuned",
    "paper-tuned": "the paper's learner, tuned",
    "ppo-tuned": "PPO, tuned",
}

#: The published rows of the table, in order: the tuned and untuned learners, the yardsticks.
ROWS = {
    "oracle": "pose oracle",
    **TUNED,
    "paper": "the paper's learner, untuned",
    "linear": "linear SARSA, untuned",
    **{k: v for k, v in YARDSTICK_LABELS.items() if k != "oracle"},
}

#: The current published rows where they exist (the bracketing continued's judged cells,
#: tuned alike to bracketed optima, judged on seeds 7000-7009): ``{variant: label}``.
BRACKETED = {
    "paper-bracketed": "the paper's learner, bracketed",
    "linear-bracketed": "linear SARSA, bracketed",
    "ppo-matched": "PPO at the paper learner's training steps",
}

#: Names a learner's label may not take: they name the published cells' variants.
_RESERVED = frozenset({*published_contest.LEARNERS, *YARDSTICK_LABELS})


@dataclasses.dataclass(frozen=True)
class Budget:
    """What :func:`contest` spends: the published contest's budget by default
    (:data:`CONTEST_BUDGET`).

    Attributes:
      worlds: The contest's worlds it runs in (keys of :data:`WORLDS`).
      settings: The settings of the learner's grid (9).
      keep: Settings trained again in round 2 (3).
      tuning_seeds: The tuning seeds (round 1 trains on the first; 3, fresh).
      judged: The tuned setting is judged on the first this many of the published judged
        seeds (20: 3000-3019).
      heldout_trials: Held-out trials per run, in tuning and judged runs (500).
    """

    worlds: tuple[str, ...] = published_contest.CONTEST
    settings: int = published_contest.GRID_SIZE
    keep: int = published_contest.ROUND_2
    tuning_seeds: tuple[int, ...] = TUNING_SEEDS
    judged: int = len(published_contest.SEEDS)
    heldout_trials: int = HELDOUT_TRIALS

    def __post_init__(self):
        owner = "Budget"
        worlds = tuple(self.worlds)
        if not worlds or len(set(worlds)) != len(worlds) or not set(worlds) <= set(WORLDS):
            raise ValueError(
                f"Budget.worlds must be distinct worlds of {tuple(WORLDS)}, got {self.worlds!r}"
            )
        settings = check_int(owner, "settings", self.settings, lo=1, hi=100)
        seeds = tuple(check_int(owner, "tuning_seeds[]", s, lo=0) for s in self.tuning_seeds)
        if len(seeds) < 2 or len(set(seeds)) != len(seeds):
            raise ValueError(
                f"Budget.tuning_seeds must be two or more distinct seeds (round 1 trains on the "
                f"first, round 2 on the others), got {seeds!r}"
            )
        if set(seeds) & set(published_contest.SEEDS):
            raise ValueError(
                f"Budget.tuning_seeds must not be judged seeds ({published_contest.SEEDS[0]}-"
                f"{published_contest.SEEDS[-1]}): tuning would read the streams it is judged on"
            )
        object.__setattr__(self, "worlds", worlds)
        object.__setattr__(self, "tuning_seeds", seeds)
        check_int(owner, "keep", self.keep, lo=1, hi=settings)
        check_int(owner, "judged", self.judged, lo=2, hi=len(published_contest.SEEDS))
        check_int(owner, "heldout_trials", self.heldout_trials, lo=1, hi=MAX_COUNT)

    @property
    def judged_seeds(self) -> tuple[int, ...]:
        """The seeds the tuned setting is judged on: the first :attr:`judged` published ones."""
        return published_contest.SEEDS[: self.judged]

    @property
    def runs(self) -> int:
        """Training runs per world: the tuning's and the judged ones."""
        return self.settings + self.keep * (len(self.tuning_seeds) - 1) + self.judged

    @property
    def is_the_contest(self) -> bool:
        """Whether this is the published contest's budget (:data:`CONTEST_BUDGET`)."""
        return self == CONTEST_BUDGET

    def describe(self) -> str:
        """One paragraph (Markdown): what this budget runs, and whether it is the contest's."""
        seeds = self.tuning_seeds
        judged = self.judged_seeds
        text = (
            f"per world ({', '.join(self.worlds)}): {self.settings} settings on tuning seed "
            f"{seeds[0]}, the best {self.keep} again on "
            f"{len(seeds) - 1} more tuning seed{'s' if len(seeds) != 2 else ''}, the tuned "
            f"setting judged on seeds {judged[0]}-{judged[-1]} ({self.heldout_trials} held-out "
            f"trials each, the published rows' held-out streams): {self.runs} runs per world."
        )
        if self.is_the_contest:
            return f"**The published contest's budget**: {text}"
        return (
            f"**Not the contest: {'a smaller' if self.smaller else 'another'} budget** "
            f"({text}) The published rows beside it had the contest's ({CONTEST_BUDGET.runs} "
            f"runs per world, {CONTEST_BUDGET.heldout_trials} held-out trials per seed, tuning "
            f"seeds {', '.join(map(str, CONTEST_BUDGET.tuning_seeds))}); compare with care."
        )

    @property
    def smaller(self) -> bool:
        """Whether this budget spends less than the contest's in any respect."""
        contest = CONTEST_BUDGET
        return (
            len(self.worlds) < len(contest.worlds)
            or self.settings < contest.settings
            or self.keep < contest.keep
            or len(self.tuning_seeds) < len(contest.tuning_seeds)
            or self.judged < contest.judged
            or self.heldout_trials < contest.heldout_trials
        )


#: The published contest's budget.
CONTEST_BUDGET = Budget()


def small_budget(
    worlds: Sequence[str] = ("sideboard",),
    settings: int = 2,
    keep: int = 1,
    tuning_seeds: Sequence[int] = TUNING_SEEDS[:2],
    judged: int = 3,
    heldout_trials: int = 20,
) -> Budget:
    """A budget for examples and tests (seconds, not hours), labelled as not the contest in
    every table and figure: by default the sideboard world, 2 settings, the best one again
    on a second tuning seed, judged on 3 seeds of 20 held-out trials."""
    return Budget(tuple(worlds), settings, keep, tuple(tuning_seeds), judged, heldout_trials)


@dataclasses.dataclass
class Contest:
    """What :func:`contest` returns.

    Attributes:
      label: The learner's name in the tables (its cells: ``{world}/{label}-tuned``).
      budget: The budget spent.
      grid: The settings tried.
      tuned: ``{world: the tuned setting}``.
      results: The learner's runs, tuning and judged (:class:`docking.study.design.Results`).
      published: The published contest's results, read from the ledger (:func:`published`).
      gaps: Per world and published tuned learner, its lead over the new learner and the
        gap rule's verdict (:class:`docking.study.report.ContestGap`).
      table: The Markdown: the budget, the success table (the learner's row first, then the
        published rows), the gaps, the tuned settings and training steps.
      figure: The learners' held-out success per world (each seed a dot, the mean with its
        interval) beside the published tuned learners, the yardsticks as lines.
    """

    label: str
    budget: Budget
    grid: list[dict]
    tuned: dict[str, dict]
    results: Results
    published: Results
    gaps: list
    table: str
    figure: object

    def __str__(self) -> str:
        return self.table

    def _repr_markdown_(self) -> str:  # Jupyter shows the table
        return self.table


def contest(
    learner,
    grid: Sequence[Mapping],
    budget: Budget = CONTEST_BUDGET,
    *,
    label: str | None = None,
    results_dir=None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
) -> Contest:
    """Run ``learner`` through the contest (see the module docstring) and place its row
    beside the published rows.

    Args:
      learner: A learner's configuration (each world, each setting and the budget's
        held-out trials replace its fields: ``dataclasses.replace(learner, world=...,
        heldout_trials=..., **setting)``), or ``make(world, **setting)`` returning one (its
        held-out trials are set to the budget's).
      grid: The settings tried (``{field: value}`` each), ``budget.settings`` of them (9 in
        the contest), the default first (ties go to the earlier setting), no two giving the
        same configuration.
      budget: :data:`CONTEST_BUDGET`, or a smaller one (:func:`small_budget`).
      label: The learner's name in tables (default: its configuration's ``name``); not one
        of the published variants' (paper, linear, ppo, oracle, ...).
      results_dir: The results store (default :func:`docking.study.paths.results_dir`).
      scheduler: An existing Dask scheduler (``tcp://HOST:PORT``); None: the embedded
        cluster of ``workers`` processes (default: one per core; 1: in this process).
      progress: Show the sweeps' progress bars.

    A learner, grid or label of the wrong kind is a ``TypeError`` or ``ValueError`` naming it,
    raised before anything is read or run.
    """
    grid, make, label = _checked(learner, grid, budget, label)
    tuning, design = _tuning(label, grid, budget, make)
    shown = published(results_dir)  # before any run: a ledger without them fails first
    mine = run_design(
        design, results_dir=results_dir, scheduler=scheduler, workers=workers, progress=progress
    )
    tuned = {w: grid[tuning.tuned_setting(mine, w, label)] for w in budget.worlds}
    current = bracketed(results_dir)
    both = _merged(shown if current is None else _merged(shown, current), mine)
    gaps = _gaps(both, budget.worlds, label)
    table = "\n\n".join(
        [
            budget.describe(),
            _stored_line(mine, results_dir),
            _success_table(both, budget, label),
            _gaps_table(gaps, label),
            _bracketed_table(both, budget, label),
            _tuned_lines(mine, budget, label, tuned),
        ]
    )
    figure = _figure(both, budget, label)
    return Contest(label, budget, grid, tuned, mine, shown, gaps, table, figure)


def _checked(learner, grid, budget: Budget, label: str | None) -> tuple[list, Callable, str]:
    """The contest's arguments checked before anything is read or run: the settings, the
    learner's maker and its label (a ``TypeError`` or ``ValueError`` naming what is wrong)."""
    check_instance("contest", "budget", budget, Budget)
    _check_learner(learner)
    grid = _settings(grid)
    if len(grid) != budget.settings:
        raise ValueError(
            f"contest: the grid has {len(grid)} settings, the budget {budget.settings} "
            f"({'the contest' if budget.is_the_contest else 'a smaller budget'})"
        )
    make = _maker(learner, budget.heldout_trials)
    first = make(budget.worlds[0], "", **grid[0])
    label = check_name("contest", "label", first.name if label is None else label)
    if label in _RESERVED:
        raise ValueError(f"contest: the label {label!r} names a published learner or yardstick")
    _check_distinct(make, budget.worlds[0], grid)
    return grid, make, label


def _tuning(label: str, grid: list[dict], budget: Budget, make: Callable) -> tuple:
    """``(tuning, design)``: the learner's :class:`Tuning` under ``budget``, and the design
    that runs it (the first round's cells in every world, the later rounds as its stages,
    the tuned settings judged on the budget's fresh seeds)."""
    tuning = Tuning(
        budget.worlds, {label: grid}, budget.tuning_seeds, budget.keep, make=make, cell=_cell
    )
    round1 = [c for world in budget.worlds for c in tuning.round1(world, label)]
    design = Design(
        name=f"contest-{label}",
        title=f"{label} through the contest",
        cells=tuple(round1),
        seeds=budget.judged_seeds,
        measure="heldout",
        stages=tuning.stages(),
    )
    return tuning, design


def _is_config(learner) -> bool:
    """Whether ``learner`` is a configuration (a dataclass instance), not a maker."""
    return dataclasses.is_dataclass(learner) and not isinstance(learner, type)


def _check_learner(learner) -> None:
    """``TypeError`` naming ``learner`` unless it is a configuration with a world or a
    callable (a maker, ``make(world, **setting)``)."""
    if _is_config(learner) and hasattr(learner, "world"):
        return
    if callable(learner) and not _is_config(learner) and not isinstance(learner, type):
        return
    raise TypeError(
        "contest: learner must be a learner's configuration (a dataclass with world and "
        "heldout_trials fields) or make(world, **setting) returning one, got "
        f"{learner!r:.80} ({type(learner).__name__})"
    )


def _settings(grid) -> list[dict]:
    """``grid`` as a list of settings (``{field: value}``); ``TypeError`` naming it unless
    it is a sequence (not a text) of mappings with field names for keys."""
    if isinstance(grid, str | bytes) or not isinstance(grid, Sequence):
        raise TypeError(
            "contest: grid must be a list of settings, each a mapping of field names to "
            f"values (e.g. [{{}}, {{'alpha': 0.1}}]), got {grid!r:.80} ({type(grid).__name__})"
        )
    for k, setting in enumerate(grid):
        if not isinstance(setting, Mapping) or not all(isinstance(n, str) for n in setting):
            raise TypeError(
                f"contest: grid[{k}] must be a mapping of field names to values, got "
                f"{setting!r:.80} ({type(setting).__name__})"
            )
    return [dict(s) for s in grid]


def _check_distinct(make: Callable, world: str, grid: list[dict]) -> None:
    """``ValueError`` naming the grid if two of its settings give one configuration in
    ``world`` (as a sweep's ``--grid`` refuses them: the tuning would run it twice)."""
    seen: dict[str, int] = {}
    for k, setting in enumerate(grid):
        text = json.dumps(make(world, "", **setting).to_dict(), sort_keys=True)
        if text in seen:
            j = seen[text]
            raise ValueError(
                f"contest: grid[{j}] ({grid[j]!r:.60}) and grid[{k}] ({grid[k]!r:.60}) give "
                "the same configuration; each setting of the grid must differ"
            )
        seen[text] = k


def _maker(learner, heldout_trials: int) -> Callable:
    """``make(world key, learner label, **setting)``: the learner's configuration in the
    world with the setting and ``heldout_trials`` held-out trials (what :class:`Tuning`
    calls)."""

    def make(world: str, _label: str, **setting):
        where = WORLDS[world]
        if callable(learner) and not hasattr(learner, "world"):
            config = _made(learner, where, setting)
            config = dataclasses.replace(config, heldout_trials=heldout_trials)
        else:
            _check_fields(learner, setting)
            config = dataclasses.replace(
                learner, world=where, heldout_trials=heldout_trials, **setting
            )
        kinds.runner_for(config)  # TypeError for what is no registered learner's
        if config.world != where:
            raise ValueError(f"contest: the learner made for the {world} world is in another")
        return config

    return make


def _made(learner: Callable, world: WorldConfig, setting: dict):
    """``learner(world, **setting)``: a configuration with a ``heldout_trials`` field;
    ``TypeError`` naming the learner if it cannot be called so or returns something else."""
    try:
        inspect.signature(learner).bind(world, **setting)
    except TypeError as exc:
        raise TypeError(
            f"contest: learner must be callable as make(world, **setting); "
            f"{getattr(learner, '__name__', repr(learner))}(world, **{setting!r:.60}) "
            f"cannot be: {exc}"
        ) from None
    except ValueError:  # no signature to read (some builtins): the call says
        pass
    config = learner(world, **setting)
    if not _is_config(config) or not hasattr(config, "heldout_trials"):
        raise TypeError(
            f"contest: learner(world, **{setting!r:.60}) must return a learner's "
            f"configuration (a dataclass with world and heldout_trials fields), returned "
            f"{config!r:.80} ({type(config).__name__})"
        )
    return config


def _check_fields(config, setting: dict) -> None:
    """``ValueError`` naming the grid's setting if it names a field ``config`` has not."""
    fields = {f.name for f in dataclasses.fields(config)}
    unknown = sorted(set(setting) - fields)
    if unknown:
        raise ValueError(
            f"contest: the grid's setting {setting!r:.80} names {', '.join(unknown)}, not "
            f"fields of {type(config).__name__} ({', '.join(sorted(fields))})"
        )


def _cell(world: str, variant: str, config, label: str, seeds=None) -> Cell:
    return Cell(
        f"{world}/{variant}", config, {"world": world, "variant": variant}, label, seeds=seeds
    )


@functools.lru_cache(maxsize=2)
def _published(ledger: str, results_dir: str | None) -> Results:
    from docking.study import design

    part = published_contest.part("contest")

    def runs_of(new, _before):  # the store, then the ledger; never computed
        return design._loaded(part, new, results_dir)

    try:
        return design._walk(part, part.select(False), runs_of, results_dir)[1]
    except LookupError as exc:
        raise LookupError(
            f"the published contest's rows are read from the committed ledger ({ledger}), "
            f"which lacks some: {exc}"
        ) from None


def published(results_dir=None) -> Results:
    """The published contest's results (the third edition's contest part, its tuning stages
    walked), every run read from the results store or the committed ledger, never computed
    (``LookupError`` if neither holds one)."""
    ledger = paths.ledger_dir()
    return _published(str(ledger), None if results_dir is None else str(results_dir))


@functools.lru_cache(maxsize=2)
def _bracketed(ledger: str, results_dir: str | None) -> Results | None:
    from docking.study import design
    from docking.study.designs import bracketing_continued as bc

    def runs_of(new, _before):  # the store, then the ledger; never computed
        return design._loaded(bc.DESIGN, new, results_dir)

    try:
        own = design._walk(bc.DESIGN, bc.DESIGN.select(False), runs_of, results_dir)[1]
    except LookupError:
        return None
    keys = [f"{w}/{v}" for w in ("floor", "nao") for v in BRACKETED if f"{w}/{v}" in own.runs]
    return Results(
        own.design,
        [own.cell(k) for k in keys],
        {k: own.runs[k] for k in keys},
        {k: own.logs[k] for k in keys},
    )


def bracketed(results_dir=None) -> Results | None:
    """The current published rows where they exist (:data:`BRACKETED`, the floor and
    Nao-like worlds), read from the results store or the committed ledger, never computed;
    None if neither holds them."""
    ledger = paths.ledger_dir()
    return _bracketed(str(ledger), None if results_dir is None else str(results_dir))


def _stored_line(mine: Results, results_dir) -> str:
    """Where the learner's runs are stored, and how many were computed and read."""
    counts = collections.Counter(s for found in mine.sources.values() for s in found)
    folder = paths.results_dir() if results_dir is None else results_dir
    read = ", ".join(
        f"{n} from the {source}" for source, n in sorted(counts.items()) if source != "computed"
    )
    return (
        f"Your learner's runs are stored under {folder}: {counts.get('computed', 0)} computed "
        f"now, {read or 'none read'} (a second call computes nothing)."
    )


def _merged(shown: Results, mine: Results) -> Results:
    """One :class:`Results` of the published cells and the learner's."""
    return Results(
        mine.design,
        [*shown.cells, *mine.cells],
        {**shown.runs, **mine.runs},
        {**shown.logs, **mine.logs},
    )


def _gaps(both: Results, worlds, label: str) -> list:
    """Per world and published tuned learner: its lead over ``label``'s tuned learner,
    paired over the seeds both have, and the gap rule's verdict."""
    from docking.study.report import ContestGap, paired_over_shared_seeds

    bound, found = published_contest.GAP_CLOSED, []
    for world in worlds:
        for other in TUNED:
            ci = paired_over_shared_seeds(both, f"{world}/{other}", f"{world}/{label}-tuned")
            verdict = "closed" if ci.high < bound else "remains" if ci.low > bound else "undecided"
            found.append(ContestGap(world, other, ci, verdict))
    return found


def _success_table(both: Results, budget: Budget, label: str) -> str:
    from docking.study.claims import rate_interval
    from docking.study.designs.third_edition_report import CONTEST_WORLDS
    from docking.study.report import md_table

    def row(name: str, variant: str) -> tuple:
        keys = [f"{w}/{variant}" for w in budget.worlds]
        seeds = sorted({len(both.score(k)) for k in keys})
        trials = sorted({len(log) for k in keys for log in both.logs[k]})
        values = [rate_interval(both, k).format(unit="%") for k in keys]
        return (name, ", ".join(map(str, seeds)), ", ".join(map(str, trials)), *values)

    rows = [row(f"**{label}, tuned (yours)**", f"{label}-tuned")]
    rows += [row(name, variant) for variant, name in ROWS.items()]
    header = ("held-out success (95% interval)", "seeds", "trials per seed")
    return md_table((*header, *(CONTEST_WORLDS[w] for w in budget.worlds)), rows)


def _gaps_table(gaps: list, label: str) -> str:
    from docking.study.report import md_table

    bound = 100 * published_contest.GAP_CLOSED
    rows = [
        (
            g.world,
            TUNED[g.other],
            f"{g.interval.format(unit=' pp')} (n = {len(g.interval.values)})",
            g.verdict,
        )
        for g in gaps
    ]
    header = ("world", "published learner", f"its lead over {label} (matched by seed)")
    note = (
        f"The gap rule (the third edition's): a gap is closed if the interval of the published "
        f"learner's lead lies below {bound:g} pp, remains if above, else undecided."
    )
    return md_table((*header, "gap"), rows) + "\n\n" + note


def _bracketed_table(both: Results, budget: Budget, label: str) -> str:
    """The current published rows (:data:`BRACKETED`) beside the learner, where they exist:
    their success and the learner's lead over each by Welch's interval (their seeds are
    others, so the seeds are not matched)."""
    from docking.study.claims import rate_interval
    from docking.study.report import md_table
    from docking.study.stats import t_difference_ci

    rows = []
    for world in budget.worlds:
        for variant, name in BRACKETED.items():
            key = f"{world}/{variant}"
            if key not in both.runs:
                continue
            lead = t_difference_ci(both.score(key), both.score(f"{world}/{label}-tuned"))
            rows.append(
                (world, name, rate_interval(both, key).format(unit="%"), lead.format(unit=" pp"))
            )
    if not rows:
        return "No current published rows (bracketed) in these worlds."
    header = ("world", "current published row", "held-out success", f"its lead over {label}")
    return (
        "The current published rows, tuned alike to bracketed optima (their tuning took about "
        "200 runs per learner and world, this contest's 15), judged on seeds 7000-7009; their "
        "lead over yours is Welch's interval (other seeds, not matched):\n\n"
        + md_table(header, rows)
    )


def _tuned_lines(mine: Results, budget: Budget, label: str, tuned: dict) -> str:
    from docking.study.learners import training_steps

    lines = []
    for world in budget.worlds:
        steps = [training_steps(r) for r in mine.runs[f"{world}/{label}-tuned"]]
        known = [s for s in steps if s is not None]
        shown = f"{np.mean(known):,.0f}" if known else "not recorded"
        setting = ", ".join(f"{k} = {v!r}" for k, v in tuned[world].items()) or "the default"
        lines.append(f"- {world}: tuned setting {setting}; training steps per judged run {shown}")
    return (
        "Tuned settings (by the budget's successive halving) and training steps (the published "
        f"learners trained for {EXPERIMENT_2.train_trials:,} trials of at most "
        f"{EXPERIMENT_2.world.max_steps} actions, PPO for {published_contest.PPO_STEPS:,} "
        "steps):\n\n" + "\n".join(lines)
    )


def _figure(both: Results, budget: Budget, label: str):
    from docking.study.designs.third_edition_report import CONTEST_NAMES
    from docking.study.figures import fig_glance

    names = {w: CONTEST_NAMES[w] for w in budget.worlds}
    learners = {f"{label}-tuned": f"{label}, tuned (yours)", **TUNED}
    seeds = {
        (names[w], name): both.score(f"{w}/{variant}")
        for w in budget.worlds
        for variant, name in learners.items()
    }
    yardsticks = {
        (names[w], name): float(np.mean(both.score(f"{w}/{variant}")))
        for w in budget.worlds
        for variant, name in YARDSTICK_LABELS.items()
    }
    fig = fig_glance(list(names.values()), list(learners.values()), seeds, yardsticks)
    title = "the contest" if budget.is_the_contest else "NOT the contest: another budget"
    if budget.smaller:
        title = "NOT the contest: a smaller budget"
    fig.suptitle(f"{label} beside the published learners ({title})", fontsize=10)
    return fig
