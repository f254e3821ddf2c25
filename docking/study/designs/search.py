"""The equal search: one selection procedure for any learners, the same number of runs for
each (what :mod:`docking.study.designs.equal_contest` runs for the published learners and
:func:`docking.study.contest.contest` for yours).

A :class:`Search` selects each learner's setting in each world by the same steps:

1. **A common grid**: ``rows x cols`` points over the learner's two knobs (each a
   :class:`Knob`: a configuration field and its log-spaced :class:`Ladder`, rungs ``0 ..
   rows - 1`` and ``0 .. cols - 1``), every point on the same grid seeds.
2. **Extension**: ``extension_stages`` stages of ``extension_points`` points each, for every
   learner in every world: the points searched so far ranked by their mean held-out success
   on the grid seeds (ties: the earlier searched); walking down the ranking, each point's
   lattice neighbours (one rung up or down either knob, the ladders continued beyond the grid)
   not yet searched are taken, in the order row up, row down, column up, column down, until
   the stage has its points. A rung that is not a valid configuration is a limit, never
   searched.
3. **Selection**: the ``top_k`` best *bracketed* points (every lattice neighbour searched or
   beyond a limit) train again on the selection seeds; the best mean there is the chosen
   setting (ties: the better ranked on the grid).
4. **Judgement**: each chosen setting on the judged seeds.

:func:`judgement` judges two learners' judged runs over matched seeds: the lead, a
non-inferiority test and an equivalence test (TOST), each Holm-adjusted over a family.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping

import numpy as np
from scipy import stats as sps

from docking.study.design import Cell, Design

__all__ = ["Entrant", "Knob", "Ladder", "Search", "holm", "judgement"]


@dataclasses.dataclass(frozen=True)
class Ladder:
    """A knob's log-spaced values: rung ``k`` is ``mantissas[k % n] * base ** (exponent + k //
    n)`` (``n`` mantissas), exact as a decimal literal for base 10; ``integer``: the knob takes
    whole numbers; ``upper``: the largest value allowed. A rung beyond a limit (not a whole
    number, above ``upper``) is None.

    ``Ladder((1, 2, 5), 0)`` is 1, 2, 5, 10, 20, ... from rung 0 (0.5 at rung -1);
    ``Ladder((8,), 0, base=2, integer=True)`` is 8, 16, 32, ... (4 at rung -1)."""

    mantissas: tuple
    exponent: int
    base: int = 10
    integer: bool = False
    upper: float | None = None

    def __post_init__(self):
        mantissas = tuple(self.mantissas)
        if not mantissas or not all(
            isinstance(m, int | float) and not isinstance(m, bool) and m > 0 for m in mantissas
        ):
            raise ValueError(f"Ladder.mantissas must be positive numbers, got {self.mantissas!r}")
        if isinstance(self.exponent, bool) or not isinstance(self.exponent, int):
            raise TypeError(f"Ladder.exponent must be an integer, got {self.exponent!r}")
        if isinstance(self.base, bool) or not isinstance(self.base, int) or self.base < 2:
            raise ValueError(f"Ladder.base must be an integer of 2 or more, got {self.base!r}")
        object.__setattr__(self, "mantissas", mantissas)

    def value(self, k: int):
        """Rung ``k``'s value, or None beyond a limit."""
        m, e = self.mantissas[k % len(self.mantissas)], self.exponent + k // len(self.mantissas)
        v = float(f"{m}e{e}") if self.base == 10 else float(m * self.base**e)
        if self.upper is not None and v > self.upper:
            return None
        if self.integer:
            return int(v) if v.is_integer() and v >= 1 else None
        return v

    def values(self, rungs: int) -> list:
        """The values of rungs ``0 .. rungs - 1`` (the grid's)."""
        return [self.value(k) for k in range(rungs)]


@dataclasses.dataclass(frozen=True)
class Knob:
    """A knob searched: a configuration field and its ladder."""

    field: str
    ladder: Ladder


@dataclasses.dataclass(frozen=True)
class Entrant:
    """One learner of a search.

    Attributes:
      make: ``make(world, name, **setting)``: the learner's configuration in world ``world``
        (a key of :attr:`Search.worlds`) with ``setting``, stored under ``name``.
      row, col: Its two knobs (the grid's rows and columns).
      fixed: ``{world: {field: value}}``: fields set in every setting of a world (a third knob
        held fixed), or empty.
    """

    make: Callable
    row: Knob
    col: Knob
    fixed: Mapping[str, Mapping[str, object]] = dataclasses.field(default_factory=dict)


@dataclasses.dataclass(frozen=True)
class Search:
    """The equal search of the module docstring, as a design's cells and stages.

    Attributes:
      name: The name its runs are stored under (a results table of the ledger).
      worlds: The worlds searched (keys the entrants' ``make`` takes).
      entrants: ``{learner: Entrant}``.
      grid_seeds, selection_seeds, judged_seeds: The seeds of each step.
      rows, cols: The grid's size.
      extension_stages, extension_points: The extension's stages and points per stage.
      top_k: The bracketed points trained again on the selection seeds.
      stored_under: ``{world: {learner: {name: ((row, col), ...)}}}``: grid points whose runs
        on the grid seeds are stored under another name (read from there).
    """

    name: str
    worlds: tuple[str, ...]
    entrants: Mapping[str, Entrant]
    grid_seeds: tuple[int, ...]
    selection_seeds: tuple[int, ...]
    judged_seeds: tuple[int, ...]
    rows: int = 9
    cols: int = 5
    extension_stages: int = 3
    extension_points: int = 5
    top_k: int = 3
    stored_under: Mapping = dataclasses.field(default_factory=dict)

    @property
    def learners(self) -> tuple[str, ...]:
        return tuple(self.entrants)

    # -- points and cells -----------------------------------------------------------------
    def setting(self, world: str, learner: str, point: tuple[int, int]) -> dict | None:
        """The field values of lattice point ``point`` (row rung, column rung) of ``learner``
        in ``world``, or None where a rung is beyond its ladder's limit."""
        e = self.entrants[learner]
        row, col = e.row.ladder.value(point[0]), e.col.ladder.value(point[1])
        if row is None or col is None:
            return None
        return {**e.fixed.get(world, {}), e.row.field: row, e.col.field: col}

    def config(self, world: str, learner: str, point: tuple[int, int], name: str | None = None):
        """The configuration of ``point``, stored under ``name`` (default :attr:`name`)."""
        knobs = self.setting(world, learner, point)
        if knobs is None:
            raise ValueError(f"point {point} of {learner} is beyond its ladders' limits")
        return self.entrants[learner].make(world, name or self.name, **knobs)

    def valid(self, world: str, learner: str, point: tuple[int, int]) -> bool:
        """Whether ``point`` is a configuration (every rung within its ladder's limits)."""
        if self.setting(world, learner, point) is None:
            return False
        try:
            self.config(world, learner, point)
        except ValueError:
            return False
        return True

    def _stored(self, world: str, learner: str, point: tuple[int, int]) -> str:
        for name, points in self.stored_under.get(world, {}).get(learner, {}).items():
            if tuple(point) in points:
                return name
        return self.name

    def cell(self, world: str, learner: str, point, stage: str, seeds, name=None) -> Cell:
        """The cell of ``point`` at ``stage`` (``"grid"``, ``"extension-k"``, ``"selection"``,
        ``"judged"``) on ``seeds``."""
        knobs = self.setting(world, learner, point)
        tag = ",".join(f"{k}={v:g}" for k, v in knobs.items())
        suffix = "" if stage in ("grid", "judged") else f"/{stage}"
        key = (
            f"{world}/{learner}/judged" if stage == "judged" else f"{world}/{learner}/{tag}{suffix}"
        )
        coords = {"world": world, "learner": learner, "stage": stage}
        coords |= {"row": int(point[0]), "col": int(point[1]), **knobs}
        return Cell(
            key,
            self.config(world, learner, point, name),
            coords,
            f"{learner} {tag} ({stage})",
            seeds=tuple(seeds),
        )

    def grid_cells(self) -> list[Cell]:
        """Every learner's ``rows x cols`` points in every world, on the grid seeds."""
        return [
            self.cell(w, learner, (r, c), "grid", self.grid_seeds, self._stored(w, learner, (r, c)))
            for w in self.worlds
            for learner in self.learners
            for r in range(self.rows)
            for c in range(self.cols)
        ]

    # -- the procedure --------------------------------------------------------------------
    @staticmethod
    def searched(results, world: str, learner: str) -> dict[tuple[int, int], float]:
        """Every point of ``learner`` in ``world`` searched on the grid seeds (the grid, then
        the extensions in order), with its mean held-out success over them."""
        return {
            (c["row"], c["col"]): float(np.mean(results.score(c.key)))
            for c in results.cells
            if c["world"] == world
            and c["learner"] == learner
            and (c["stage"] == "grid" or c["stage"].startswith("extension"))
        }

    @staticmethod
    def ranked(points: dict[tuple[int, int], float]) -> list[tuple[int, int]]:
        """The points best first (ties: the earlier searched)."""
        order = {p: i for i, p in enumerate(points)}
        return sorted(points, key=lambda p: (-points[p], order[p]))

    @staticmethod
    def neighbours(point: tuple[int, int]) -> list[tuple[int, int]]:
        """A point's lattice neighbours: row up, row down, column up, column down."""
        r, c = point
        return [(r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)]

    def extension(self, stage: int) -> Callable:
        """Extension stage ``stage`` (1, 2, ...): per world and learner,
        :attr:`extension_points` new points, the unsearched valid neighbours of the points in
        ranked order."""

        def cells(results) -> list[Cell]:
            found = []
            for world in self.worlds:
                for learner in self.learners:
                    points = self.searched(results, world, learner)
                    new = []
                    for p in self.ranked(points):
                        for n in self.neighbours(p):
                            if (
                                len(new) < self.extension_points
                                and n not in points
                                and n not in new
                            ):
                                if self.valid(world, learner, n):
                                    new.append(n)
                    found += [
                        self.cell(world, learner, n, f"extension-{stage}", self.grid_seeds)
                        for n in new
                    ]
            return found

        cells.__name__ = f"extension_{stage}"
        return cells

    def bracketed(self, points: dict, world: str, learner: str, point) -> bool:
        """Whether every lattice neighbour of ``point`` was searched or is beyond a limit."""
        return all(n in points or not self.valid(world, learner, n) for n in self.neighbours(point))

    def candidates(self, results, world: str, learner: str) -> list[tuple[int, int]]:
        """The :attr:`top_k` best bracketed points of ``learner`` in ``world``, best first;
        where fewer are bracketed (a grid too small to bracket any, as a small budget's), the
        best others after them."""
        points = self.searched(results, world, learner)
        ranked = self.ranked(points)
        inside = [p for p in ranked if self.bracketed(points, world, learner, p)]
        return (inside + [p for p in ranked if p not in inside])[: self.top_k]

    def selection(self, results) -> list[Cell]:
        """The candidates of every learner and world, on the selection seeds."""
        return [
            self.cell(world, learner, p, "selection", self.selection_seeds)
            for world in self.worlds
            for learner in self.learners
            for p in self.candidates(results, world, learner)
        ]

    @staticmethod
    def chosen(results, world: str, learner: str) -> tuple[int, int]:
        """The chosen point: the candidate with the best mean on the selection seeds (ties:
        the better ranked on the grid)."""
        found = [
            c
            for c in results.cells
            if c["world"] == world and c["learner"] == learner and c["stage"] == "selection"
        ]
        best = sorted(
            range(len(found)), key=lambda i: (-float(np.mean(results.score(found[i].key))), i)
        )[0]
        return found[best]["row"], found[best]["col"]

    def judged(self, results) -> list[Cell]:
        """Every learner's chosen setting in every world, on the judged seeds."""
        return [
            self.cell(
                world, learner, self.chosen(results, world, learner), "judged", self.judged_seeds
            )
            for world in self.worlds
            for learner in self.learners
        ]

    def stages(self) -> tuple[Callable, ...]:
        """A design's stages: the extensions, the selection, the judgement."""
        extensions = (self.extension(s) for s in range(1, self.extension_stages + 1))
        return (*extensions, self.selection, self.judged)

    def design(self, title: str, alpha: float | None = None) -> Design:
        """The search as a design (its grid the cells, the rest its stages)."""
        return Design(
            name=self.name,
            title=title,
            cells=tuple(self.grid_cells()),
            seeds=self.judged_seeds,
            measure="heldout",
            stages=self.stages(),
            alpha=alpha,
        )

    # -- what it spent and chose ----------------------------------------------------------
    def runs_per_learner(self) -> int:
        """Selection runs per learner and world (grid, extension, selection)."""
        grid = self.rows * self.cols * len(self.grid_seeds)
        extension = self.extension_stages * self.extension_points * len(self.grid_seeds)
        return grid + extension + self.top_k * len(self.selection_seeds)

    def spent(self, results, world: str, learner: str) -> dict[str, int]:
        """The runs of ``learner`` in ``world`` per step (``grid``, ``extension``,
        ``selection``, ``judged``) in ``results``."""
        found = {"grid": 0, "extension": 0, "selection": 0, "judged": 0}
        for c in results.cells:
            if c["world"] == world and c["learner"] == learner:
                found[c["stage"].split("-")[0]] += len(results.runs[c.key])
        return found


# ------------------------------------------------------------------------------------------
# The verdicts.
# ------------------------------------------------------------------------------------------


def holm(p) -> np.ndarray:
    """Holm's step-down adjusted p-values of a family, in the given order."""
    p = np.asarray(p, dtype=np.float64)
    order, adjusted, running = np.argsort(p, kind="stable"), np.empty(len(p)), 0.0
    for rank, k in enumerate(order):
        running = max(running, min(1.0, (len(p) - rank) * p[k]))
        adjusted[k] = running
    return adjusted


def _family_pvalues(diffs: list, margin: float) -> tuple[np.ndarray, ...]:
    """Holm-adjusted p-values over the family ``diffs``: the lead's two-sided test, the
    one-sided tests of "at least ``margin``" and "at most ``margin``", and TOST's."""
    lead = holm([sps.ttest_1samp(d, 0.0).pvalue for d in diffs])
    below = holm([sps.ttest_1samp(d, margin, alternative="less").pvalue for d in diffs])
    above = holm([sps.ttest_1samp(d, margin, alternative="greater").pvalue for d in diffs])
    tost = holm(
        [
            max(
                sps.ttest_1samp(d, -margin, alternative="greater").pvalue,
                sps.ttest_1samp(d, margin, alternative="less").pvalue,
            )
            for d in diffs
        ]
    )
    return lead, below, above, tost


def judgement(
    pairs: dict,
    margin: float = 0.05,
    alpha: float = 0.05,
    names: tuple[str, str] = ("linear SARSA", "the paper's learner"),
) -> dict:
    """The verdicts of a family of comparisons (``pairs``: ``{key: (first, second)}``,
    per-seed held-out success of two learners on matched seeds; ``names``: what the verdicts
    call the first and the second), each Holm-adjusted over the family: ``{key: {...}}`` with

    * the lead of the first over the second (``lead``, ``low``, ``high``: the per-seed
      differences' mean and Student-t ``1 - alpha`` interval; ``p_lead``: the two-sided
      t-test against zero; ``lead_verdict``: "<first> ahead", "<second> ahead" or "no lead
      shown");
    * non-inferiority of the second at ``margin`` (``p_noninferior``: the one-sided test of
      "the lead is at least the margin"; ``p_inferior``: of "at most the margin"; at
      ``alpha / 2`` each: ``noninferiority`` "non-inferior", "inferior by more than the
      margin" or "undecided");
    * equivalence within +-``margin`` (``p_tost``: the larger of the two one-sided tests'
      p-values; ``equivalence``: "equivalent" or "equivalence not shown", at ``alpha``);
    * ``failure_ratio``: the second's mean failure rate over the first's (a point estimate);
    * the means (``first``, ``second``) and the seeds (``seeds``)."""
    keys = list(pairs)
    diffs = [np.asarray(pairs[k][0], float) - np.asarray(pairs[k][1], float) for k in keys]
    for d in diffs:
        if d.ndim != 1 or len(d) < 2:
            raise ValueError(f"judgement needs matched series of 2 or more seeds, got {d!r}")
    lead, below, above, tost = _family_pvalues(diffs, margin)
    found = {}
    for i, (k, d) in enumerate(zip(keys, diffs, strict=True)):
        first, second = (np.asarray(x, float) for x in pairs[k])
        ci = sps.ttest_1samp(d, 0.0).confidence_interval(1 - alpha)
        side = f"{names[1]} ahead" if d.mean() < 0 else f"{names[0]} ahead"
        if below[i] < alpha / 2:
            noninferiority = "non-inferior"
        elif above[i] < alpha / 2:
            noninferiority = "inferior by more than the margin"
        else:
            noninferiority = "undecided"
        found[k] = dict(
            first=float(first.mean()),
            second=float(second.mean()),
            lead=float(d.mean()),
            low=float(ci.low),
            high=float(ci.high),
            p_lead=float(lead[i]),
            lead_verdict=side if lead[i] < alpha else "no lead shown",
            p_noninferior=float(below[i]),
            p_inferior=float(above[i]),
            noninferiority=noninferiority,
            p_tost=float(tost[i]),
            equivalence="equivalent" if tost[i] < alpha else "equivalence not shown",
            failure_ratio=float((1 - second.mean()) / (1 - first.mean()))
            if first.mean() < 1
            else float("inf"),
            seeds=len(d),
        )
    return found
