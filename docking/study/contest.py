"""The contest as a function: any learner through the equal contest's procedure, judged seed by
seed against the current published rows (docs/guide/bring_your_own_learner.md).

:func:`contest` runs a learner (a registered one, :mod:`docking.study.learners`, or the package's
own) exactly as the equal contest (:mod:`docking.study.designs.equal_contest`) selected the
paper's learner, linear SARSA and PPO:

* **the same search** (:class:`docking.study.designs.search.Search`), in each world: a 9 x 5
  grid over the learner's two knobs (each a :class:`~docking.study.designs.search.Knob`: a
  field and its log-spaced ladder), every point on the grid seeds 5900-5901; 3 extension
  stages of 5 lattice neighbours of the best points; the 3 best bracketed points again on
  selection seeds 6500-6503; the best there judged: 132 selection runs per world, as every
  published learner had;
* **the same seeds**: the published learners' grid, selection and judged seeds (7200-7219), so
  that each judged run is compared with theirs seed by seed (matched seeds; each run draws its
  own held-out trials from its seed's stream, :func:`docking.protocol.heldout_log`);
* **the same verdicts** (:func:`docking.study.designs.search.judgement`): per world and published
  learner, its lead over yours with the Student-t 95% interval (within +-100 pp: a difference
  of rates), the two-sided test of a lead, non-inferiority of yours at a 5 pp margin and
  equivalence within +-5 pp (TOST), each Holm-adjusted over the family of worlds and published
  learners, and the failure ratio.

The published rows are read from the committed ledger, never computed (:func:`published`:
``LookupError`` if the ledger lacks one; PPO's rows need no optional extra to be read). The
rows the equal contest superseded (the third edition's, tuned with 15 runs per learner and
judged on seeds 3000-3019) are shown only when asked for (``superseded=True``), labelled, with
no verdict. The learner's own runs are a design (:class:`docking.study.design.Design`) run by
:func:`docking.study.design.run_design`: a sweep on the embedded Dask cluster or on an existing
scheduler (``scheduler=``), with progress, stored in the results store and re-used (a second
call computes nothing).

A smaller budget (:func:`small_budget`: fewer worlds, a smaller grid, fewer seeds or held-out
trials) runs in seconds, for examples and tests; its table and figure say that it is not the
contest, and nothing it finds is a verdict on the contest.
"""

from __future__ import annotations

import collections
import dataclasses
import functools
import inspect
import json
from collections.abc import Callable

import numpy as np

from docking.scene import WorldConfig
from docking.study import kinds, paths
from docking.study.design import Results, run_design
from docking.study.designs import equal_contest as ec
from docking.study.designs import search as sr
from docking.study.designs import third_edition as te
from docking.study.designs.builders import YARDSTICK_LABELS
from docking.validate import MAX_COUNT, check_instance, check_int, check_name

__all__ = [
    "CONTEST_BUDGET",
    "WORLDS",
    "Budget",
    "Contest",
    "Knob",
    "Ladder",
    "contest",
    "published",
    "small_budget",
]

Knob, Ladder = sr.Knob, sr.Ladder

#: The contest's worlds, ``{key: WorldConfig}``: the sideboard, floor and Nao-like worlds.
WORLDS: dict[str, WorldConfig] = {key: te.WORLDS[key][1] for key in ec.WORLDS}

#: The published learners and what tables call them.
PUBLISHED = {
    "paper": "the paper's learner",
    "linear": "linear SARSA",
    "ppo": "PPO",
}
#: The yardsticks drawn beside them (the third edition's runs: fixed policies, no tuning).
YARDSTICKS = {k: v for k, v in YARDSTICK_LABELS.items() if k != "forward"}

#: Names a learner's label may not take: they name the published learners and yardsticks.
_RESERVED = frozenset({*PUBLISHED, *YARDSTICK_LABELS, *te.LEARNERS})


@dataclasses.dataclass(frozen=True)
class Budget:
    """What :func:`contest` spends: the equal contest's by default (:data:`CONTEST_BUDGET`).

    Attributes:
      worlds: The worlds it runs in (keys of :data:`WORLDS`).
      rows, cols: The grid's rungs of the first and second knob (9 x 5).
      extension_stages, extension_points: The extension (3 stages of 5 points).
      top_k: Bracketed points trained again on the selection seeds (3).
      selection: Selection seeds, the first of the published ones (4: 6500-6503).
      judged: Judged seeds, the first of the published ones (20: 7200-7219).
      heldout_trials: Held-out trials per run (500).
    """

    worlds: tuple[str, ...] = ec.WORLDS
    rows: int = ec.GRID_ROWS
    cols: int = ec.GRID_COLS
    extension_stages: int = ec.EXTENSION_STAGES
    extension_points: int = ec.EXTENSION_POINTS
    top_k: int = ec.TOP_K
    selection: int = len(ec.SELECTION_SEEDS)
    judged: int = len(ec.SEEDS)
    heldout_trials: int = 500

    def __post_init__(self):
        owner = "Budget"
        worlds = tuple(self.worlds)
        if not worlds or len(set(worlds)) != len(worlds) or not set(worlds) <= set(WORLDS):
            raise ValueError(
                f"Budget.worlds must be distinct worlds of {tuple(WORLDS)}, got {self.worlds!r}"
            )
        object.__setattr__(self, "worlds", worlds)
        check_int(owner, "rows", self.rows, lo=1, hi=50)
        check_int(owner, "cols", self.cols, lo=1, hi=50)
        check_int(owner, "extension_stages", self.extension_stages, lo=0, hi=20)
        check_int(owner, "extension_points", self.extension_points, lo=1, hi=100)
        check_int(owner, "top_k", self.top_k, lo=1, hi=self.rows * self.cols)
        check_int(owner, "selection", self.selection, lo=1, hi=len(ec.SELECTION_SEEDS))
        check_int(owner, "judged", self.judged, lo=2, hi=len(ec.SEEDS))
        check_int(owner, "heldout_trials", self.heldout_trials, lo=1, hi=MAX_COUNT)

    @property
    def runs(self) -> int:
        """Runs per world: the selection's (grid, extension, selection) and the judged ones."""
        return self.search("x", {}).runs_per_learner() + self.judged

    def search(self, name: str, entrants: dict) -> sr.Search:
        """The search this budget runs (the published seeds, its sizes)."""
        return sr.Search(
            name=name,
            worlds=self.worlds,
            entrants=entrants,
            grid_seeds=ec.GRID_SEEDS,
            selection_seeds=ec.SELECTION_SEEDS[: self.selection],
            judged_seeds=ec.SEEDS[: self.judged],
            rows=self.rows,
            cols=self.cols,
            extension_stages=self.extension_stages,
            extension_points=self.extension_points,
            top_k=self.top_k,
        )

    @property
    def is_the_contest(self) -> bool:
        """Whether this is the equal contest's budget (:data:`CONTEST_BUDGET`)."""
        return self == CONTEST_BUDGET

    @property
    def smaller(self) -> bool:
        """Whether this budget spends less than the contest's in any respect."""
        c = CONTEST_BUDGET
        return len(self.worlds) < len(c.worlds) or any(
            getattr(self, f) < getattr(c, f)
            for f in ("rows", "cols", "extension_stages", "extension_points", "top_k")
            + ("selection", "judged", "heldout_trials")
        )

    def describe(self) -> str:
        """One paragraph (Markdown): what this budget runs, and whether it is the contest's."""
        s = self.search("x", {})
        text = (
            f"per world ({', '.join(self.worlds)}): a {self.rows} x {self.cols} grid on seeds "
            f"{', '.join(map(str, s.grid_seeds))}, {self.extension_stages} extension stages of "
            f"{self.extension_points} points, the {self.top_k} best bracketed points on "
            f"{self.selection} selection seeds, the chosen setting judged on seeds "
            f"{s.judged_seeds[0]}-{s.judged_seeds[-1]} ({self.heldout_trials} held-out trials "
            f"each): {self.runs} runs per world."
        )
        if self.is_the_contest:
            return f"**The equal contest's budget**, as every published learner had: {text}"
        return (
            f"**Not the contest: {'a smaller' if self.smaller else 'another'} budget** "
            f"({text}) The published rows beside it had the contest's ({CONTEST_BUDGET.runs} "
            f"runs per world, {CONTEST_BUDGET.heldout_trials} held-out trials per seed): what "
            "it finds is no verdict on the contest."
        )


#: The equal contest's budget.
CONTEST_BUDGET = Budget()


def small_budget(
    worlds=("sideboard",),
    rows: int = 2,
    cols: int = 1,
    extension_stages: int = 0,
    extension_points: int = 1,
    top_k: int = 1,
    selection: int = 1,
    judged: int = 3,
    heldout_trials: int = 20,
) -> Budget:
    """A budget for examples and tests (seconds, not hours), labelled as not the contest in
    every table and figure: by default the sideboard world, a 2 x 1 grid, no extension, the
    best bracketed point on one selection seed, judged on 3 seeds of 20 held-out trials."""
    return Budget(
        tuple(worlds),
        rows,
        cols,
        extension_stages,
        extension_points,
        top_k,
        selection,
        judged,
        heldout_trials,
    )


@dataclasses.dataclass
class Contest:
    """What :func:`contest` returns.

    Attributes:
      label: The learner's name in the tables (its cells: ``{world}/{label}/...``).
      budget: The budget spent.
      search: The search run (:class:`docking.study.designs.search.Search`).
      chosen: ``{world: the chosen setting}``.
      results: The learner's runs, every step (:class:`docking.study.design.Results`).
      published: The current published rows, read from the ledger (:func:`published`).
      verdicts: ``{(world, published learner): verdicts}``
        (:func:`docking.study.designs.search.judgement`, the published learner first).
      table: The Markdown: the budget, where the runs are, the success table (yours first),
        the verdicts, the chosen settings and the runs spent; the superseded rows if asked.
      figure: The learners' held-out success per world (each seed a dot, the mean with its
        interval) beside the published learners, the yardsticks as lines.
    """

    label: str
    budget: Budget
    search: sr.Search
    chosen: dict[str, dict]
    results: Results
    published: Results
    verdicts: dict
    table: str
    figure: object

    def __str__(self) -> str:
        return self.table

    def _repr_markdown_(self) -> str:  # Jupyter shows the table
        return self.table


def contest(
    learner,
    rows: sr.Knob,
    cols: sr.Knob,
    budget: Budget = CONTEST_BUDGET,
    *,
    superseded: bool = False,
    label: str | None = None,
    results_dir=None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
) -> Contest:
    """Run ``learner`` through the equal contest (see the module docstring) and judge it
    against the current published rows.

    Args:
      learner: A learner's configuration (each world, each setting and the budget's held-out
        trials replace its fields: ``dataclasses.replace(learner, world=...,
        heldout_trials=..., **setting)``), or ``make(world, **setting)`` returning one (its
        held-out trials are set to the budget's).
      rows, cols: The two knobs searched (:class:`Knob`: a field and its :class:`Ladder`);
        the grid is rungs ``0 .. budget.rows - 1`` of the first and ``0 .. budget.cols - 1``
        of the second, the extension walks beyond them.
      budget: :data:`CONTEST_BUDGET`, or a smaller one (:func:`small_budget`).
      superseded: Also show the third edition's rows (superseded; no verdicts).
      label: The learner's name in tables (default: its configuration's ``name``); not one
        of the published learners' or yardsticks' (paper, linear, ppo, oracle, ...).
      results_dir: The results store (default :func:`docking.study.paths.results_dir`).
      scheduler: An existing Dask scheduler (``tcp://HOST:PORT``); None: the embedded
        cluster of ``workers`` processes (default: one per core; 1: in this process).
      progress: Show the sweeps' progress.

    A learner, knob or label of the wrong kind is a ``TypeError`` or ``ValueError`` naming it,
    raised before anything is read or run.
    """
    search, label = _checked(learner, rows, cols, budget, label)
    shown = published(results_dir)  # before any run: a ledger without them fails first
    design = search.design(f"{label} through the equal contest")
    mine = run_design(
        design, results_dir=results_dir, scheduler=scheduler, workers=workers, progress=progress
    )
    chosen = {w: search.setting(w, label, search.chosen(mine, w, label)) for w in budget.worlds}
    verdicts = _verdicts(shown, mine, budget, label)
    parts = [
        budget.describe(),
        _stored_line(mine, results_dir),
        _success_table(shown, mine, budget, label),
        _verdicts_table(verdicts, label),
        _chosen_lines(search, mine, budget, label, chosen),
    ]
    if superseded:
        parts.append(_superseded_table(budget, results_dir))
    figure = _figure(shown, mine, budget, label)
    return Contest(label, budget, search, chosen, mine, shown, verdicts, "\n\n".join(parts), figure)


def _checked(learner, rows, cols, budget: Budget, label: str | None) -> tuple[sr.Search, str]:
    """The contest's arguments checked before anything is read or run: the learner, its knobs
    and its label (a ``TypeError`` or ``ValueError`` naming what is wrong); its search."""
    check_instance("contest", "budget", budget, Budget)
    _check_learner(learner)
    for name, knob in (("rows", rows), ("cols", cols)):
        check_instance("contest", name, knob, sr.Knob)
        check_instance(f"contest: {name}", "ladder", knob.ladder, sr.Ladder)
    if rows.field == cols.field:
        raise ValueError(f"contest: rows and cols both name the field {rows.field!r}")
    make = _maker(learner, budget.heldout_trials)
    corner = {rows.field: rows.ladder.value(0), cols.field: cols.ladder.value(0)}
    first = make(budget.worlds[0], "", **corner)  # a setting of both knobs, as the search asks
    if not callable(learner) or hasattr(learner, "world"):  # a configuration: knobs are fields
        _check_fields(first, {rows.field: None, cols.field: None})
    # a function's knobs are its arguments (linear SARSA's eps_Q sits in its network):
    # _check_distinct below asks that each grid point give another configuration
    label = check_name("contest", "label", first.name if label is None else label)
    if label in _RESERVED:
        raise ValueError(f"contest: the label {label!r} names a published learner or yardstick")
    search = budget.search(f"contest-{label}", {label: sr.Entrant(make, rows, cols)})
    _check_distinct(search, budget.worlds[0], label)
    return search, label


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


def _check_distinct(search: sr.Search, world: str, label: str) -> None:
    """``ValueError`` naming the grid if two of its points give one configuration (the
    search would run it twice: a knob the learner ignores, or a ladder that repeats)."""
    seen: dict[str, tuple] = {}
    for r in range(search.rows):
        for c in range(search.cols):
            if not search.valid(world, label, (r, c)):
                raise ValueError(
                    f"contest: the grid point {search.setting(world, label, (r, c))} (rungs "
                    f"{r}, {c}) is not a valid configuration; choose ladders whose grid is"
                )
            text = json.dumps(search.config(world, label, (r, c)).to_dict(), sort_keys=True)
            if text in seen:
                raise ValueError(
                    f"contest: the grid points {search.setting(world, label, seen[text])} and "
                    f"{search.setting(world, label, (r, c))} give the same configuration; each "
                    "point of the grid must differ"
                )
            seen[text] = (r, c)


def _maker(learner, heldout_trials: int) -> Callable:
    """``make(world key, name, **setting)``: the learner's configuration in the world with the
    setting and ``heldout_trials`` held-out trials (what the search calls; the learner keeps
    its own name)."""

    def make(world: str, _name: str, **setting):
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
    """``ValueError`` naming the setting if it names a field ``config`` has not."""
    fields = {f.name for f in dataclasses.fields(config)}
    unknown = sorted(set(setting) - fields)
    if unknown:
        raise ValueError(
            f"contest: the knob {', '.join(unknown)} is not a field of "
            f"{type(config).__name__} ({', '.join(sorted(fields))})"
        )


# ------------------------------------------------------------------------------------------
# The published rows.
# ------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=2)
def _published(ledger: str, results_dir: str | None) -> Results:
    from docking.study import design

    try:
        own = ec.DESIGN.read(results_dir)  # the store, then the ledger; never computed
        yard = te.part("contest")
        wanted = [c for c in yard.select(False) if c.coords.get("variant") in YARDSTICKS]
        sticks = design.judge(yard, wanted, design._loaded(yard, wanted, results_dir))
    except LookupError as exc:
        raise LookupError(
            f"the published contest's rows are read from the committed ledger ({ledger}), "
            f"which lacks some: {exc}"
        ) from None
    keys = [f"{w}/{learner}/judged" for w in ec.WORLDS for learner in ec.LEARNERS]
    return Results(
        own.design,
        [own.cell(k) for k in keys] + wanted,
        {**{k: own.runs[k] for k in keys}, **sticks.runs},
        {**{k: own.logs[k] for k in keys}, **sticks.logs},
    )


def published(results_dir=None) -> Results:
    """The current published rows: the equal contest's judged runs of every learner and world
    (cells ``{world}/{learner}/judged``) and the yardsticks (cells ``{world}/{yardstick}``, the
    third edition's), every run read from the results store or the committed ledger, never
    computed (``LookupError`` if neither holds one)."""
    ledger = paths.ledger_dir()
    return _published(str(ledger), None if results_dir is None else str(results_dir))


# ------------------------------------------------------------------------------------------
# The table and the figure.
# ------------------------------------------------------------------------------------------


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


def _verdicts(shown: Results, mine: Results, budget: Budget, label: str) -> dict:
    """Per world and published learner, the verdicts of its lead over yours over the matched
    judged seeds, Holm over the whole family (:func:`docking.study.designs.search.judgement`)."""
    pairs = {}
    for world in budget.worlds:
        yours = mine.score(f"{world}/{label}/judged")
        for learner in PUBLISHED:
            theirs = shown.score(f"{world}/{learner}/judged")[: len(yours)]
            pairs[world, learner] = (theirs, yours)
    spread = {k: float(np.std(a - b)) > 0 for k, (a, b) in pairs.items()}
    tested = {k: v for k, v in pairs.items() if spread[k]}
    found = sr.judgement(tested, ec.MARGIN, ec.ALPHA, ("it", "yours")) if len(tested) else {}
    for k, (a, b) in pairs.items():
        if k not in found:  # every seed gave the same difference: no interval, no test
            found[k] = dict(
                first=float(a.mean()),
                second=float(b.mean()),
                lead=float(a.mean() - b.mean()),
                seeds=len(a),
                spread=False,
            )
    return {k: found[k] for k in pairs}


def _pp(x: float) -> str:
    return f"{100 * x:+.1f}"


def _lead_text(v: dict) -> str:
    """A lead with its interval, clipped to +-100 pp (a difference of rates), or why none."""
    if v.get("spread") is False:
        return f"{_pp(v['lead'])} pp (the same on every seed: no interval, no test)"
    low, high = max(v["low"], -1.0), min(v["high"], 1.0)
    clipped = " (clipped)" if (low, high) != (v["low"], v["high"]) else ""
    return f"{_pp(v['lead'])} pp [{_pp(low)}, {_pp(high)}]{clipped}"


def _verdicts_table(verdicts: dict, label: str) -> str:
    from docking.study.report import md_table

    rows = []
    for (world, learner), v in verdicts.items():
        if v.get("spread") is False:
            rows.append(
                (world, PUBLISHED[learner], _lead_text(v), "no test", "no test", "no test", "-")
            )
            continue
        lead = v["lead_verdict"].replace("it ahead", f"{PUBLISHED[learner]} ahead")
        rows.append(
            (
                world,
                PUBLISHED[learner],
                f"{_lead_text(v)} (n = {v['seeds']})",
                f"{lead} (Holm p {v['p_lead']:.2g})",
                v["noninferiority"],
                v["equivalence"],
                f"{v['failure_ratio']:.2f}",
            )
        )
    header = (
        "world",
        "published learner",
        f"its lead over {label}, 95% interval (matched seeds)",
        "a lead",
        f"{label} non-inferior at {100 * ec.MARGIN:g} pp",
        f"equivalent within ±{100 * ec.MARGIN:g} pp (TOST)",
        f"{label}'s failures / its",
    )
    note = (
        "Each test Holm-adjusted over this table's comparisons (the equal contest's rules): a "
        f"lead where the two-sided test rejects at {ec.ALPHA:g}; non-inferior where the "
        f"one-sided test of a lead of {100 * ec.MARGIN:g} pp or more rejects at "
        f"{ec.ALPHA / 2:g}; equivalent where both one-sided tests of TOST reject at {ec.ALPHA:g}."
    )
    return md_table(header, rows) + "\n\n" + note


def _success_table(shown: Results, mine: Results, budget: Budget, label: str) -> str:
    from docking.study.claims import rate_interval
    from docking.study.designs.third_edition_report import CONTEST_WORLDS
    from docking.study.report import md_table

    def row(name: str, source: Results, keys: list[str]) -> tuple:
        seeds = sorted({len(source.score(k)) for k in keys})
        trials = sorted({len(log) for k in keys for log in source.logs[k]})
        values = [rate_interval(source, k).format(unit="%") for k in keys]
        return (name, ", ".join(map(str, seeds)), ", ".join(map(str, trials)), *values)

    worlds = budget.worlds
    rows = [row(f"**{label}, chosen (yours)**", mine, [f"{w}/{label}/judged" for w in worlds])]
    rows += [
        row(f"{name}, chosen", shown, [f"{w}/{learner}/judged" for w in worlds])
        for learner, name in PUBLISHED.items()
    ]
    rows += [row(name, shown, [f"{w}/{v}" for w in worlds]) for v, name in YARDSTICKS.items()]
    header = ("held-out success (95% interval)", "seeds", "trials per seed")
    return md_table((*header, *(CONTEST_WORLDS[w] for w in worlds)), rows)


def _chosen_lines(search, mine: Results, budget: Budget, label: str, chosen: dict) -> str:
    from docking.study.learners import training_steps

    lines = []
    for world in budget.worlds:
        steps = [training_steps(r) for r in mine.runs[f"{world}/{label}/judged"]]
        known = [s for s in steps if s is not None]
        shown = f"{np.mean(known):,.0f}" if known else "not recorded"
        spent = search.spent(mine, world, label)
        setting = ", ".join(f"{k} = {v!r}" for k, v in chosen[world].items())
        lines.append(
            f"- {world}: chosen {setting}; selection runs {spent['grid']} grid + "
            f"{spent['extension']} extension + {spent['selection']} selection; training steps "
            f"per judged run {shown}"
        )
    return (
        f"Chosen settings (each published learner had {ec.SEARCH.runs_per_learner()} selection "
        "runs per world):\n\n" + "\n".join(lines)
    )


def _superseded_table(budget: Budget, results_dir) -> str:
    """The third edition's tuned rows (superseded by the equal contest), labelled, no verdict."""
    from docking.study import design
    from docking.study.claims import rate_interval
    from docking.study.report import md_table

    part = te.part("contest")
    runs = design._walk(
        part, part.select(False), lambda new, _: design._loaded(part, new, results_dir), results_dir
    )[1]
    rows = [
        (
            f"{PUBLISHED[learner]}, tuned (third edition)",
            *(rate_interval(runs, f"{w}/{learner}-tuned").format(unit="%") for w in budget.worlds),
        )
        for learner in PUBLISHED
    ]
    return (
        "**Superseded rows** (the third edition: 15 tuning runs per learner, judged on seeds "
        "3000-3019; superseded by the equal contest, shown for the record, no verdict):\n\n"
        + md_table(("held-out success (95% interval)", *budget.worlds), rows)
    )


def _figure(shown: Results, mine: Results, budget: Budget, label: str):
    from docking.study.designs.third_edition_report import CONTEST_NAMES
    from docking.study.figures import fig_glance

    names = {w: CONTEST_NAMES[w] for w in budget.worlds}
    learners = {label: f"{label}, chosen (yours)", **PUBLISHED}
    seeds = {}
    for w in budget.worlds:
        seeds[names[w], learners[label]] = mine.score(f"{w}/{label}/judged")
        for learner, name in PUBLISHED.items():
            seeds[names[w], name] = shown.score(f"{w}/{learner}/judged")
    yardsticks = {
        (names[w], name): float(np.mean(shown.score(f"{w}/{v}")))
        for w in budget.worlds
        for v, name in YARDSTICKS.items()
    }
    fig = fig_glance(list(names.values()), list(learners.values()), seeds, yardsticks)
    title = "the equal contest" if budget.is_the_contest else "NOT the contest: another budget"
    if budget.smaller:
        title = "NOT the contest: a smaller budget"
    fig.suptitle(f"{label} beside the published learners ({title})", fontsize=10)
    return fig
