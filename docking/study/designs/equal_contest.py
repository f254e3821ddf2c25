"""The equal contest (issue 59): every learner selected by one procedure, with the same number
of runs on a common grid, judged on fresh seeds, and its verdict named as the test it is.

**These rules were committed before any of its runs** and are not changed after seeing them
(``tests/test_equal_contest.py`` pins them by a digest of :func:`rules_text`, which covers its
constants, its cells and the source of its procedure and its verdict functions).

Why: the main finding so far ("tuned alike, the paper's learner docks within 5 pp of linear
SARSA", the bracketing and its replication) rests on searches that were not alike. The
paper's learner had 234 and 202 tuning runs (floor, Nao-like), linear SARSA 81 and 88, PPO 15;
linear SARSA's walk stopped at a local optimum below points of the landscape's fixed grid;
the paper's learner's floor optimum sat on the ladder's top rung (beta_a 100). Here the
search is the same for every learner, counted in runs.

The procedure, the same for the paper's learner, linear SARSA and PPO in each world of
:data:`WORLDS` (the sideboard, floor and Nao-like worlds):

1. **The common grid** (:data:`ROW_LADDERS`, :data:`COL_LADDERS`): 9 x 5 points over each
   learner's two most influential knobs, every point on the same :data:`GRID_SEEDS`. Rows:
   the training temperature beta_a (Eq. 4) for the SARSA learners, 1 to 500 on a 1-2-5
   ladder (the landscape's 1-100 and two rungs above it, since the paper's learner's floor
   optimum lay on 100); PPO's learning rate, 1e-5 to 5e-3 on the same 1-2-5 ladder. Columns:
   the paper's learner's eps_W (Eq. 8), 0.05 to 5; linear SARSA's eps_Q (Eq. 7), 0.01 to 1;
   PPO's rollouts per update, 8 to 128, doubling. The paper's learner's third knob, eps_Q, is
   fixed per world (:data:`PAPER_EPS_Q`) at the value its last tuning chose there (the third
   edition's in the sideboard world, the bracketing's in the floor and Nao-like worlds):
   information carried from a longer search, which favours the paper's learner.
2. **Extension** (:data:`EXTENSION_STAGES` stages of :data:`EXTENSION_POINTS` points, for every
   learner in every world, whatever its grid shows): the points searched so far are ranked by
   their mean held-out success on the grid seeds (ties: the earlier searched); walking down
   that ranking, each point's lattice neighbours (one rung up or down either knob, the
   ladders continued beyond the grid: :class:`Ladder`) not yet searched are taken, in the
   order row up, row down, column up, column down, until the stage has its points. So a best
   point on the grid's edge gets the rungs beyond it first, and every learner gets the same
   number of extension points. A rung that is not a valid configuration (a learning rate
   above 1, fewer than one rollout) is a limit, never searched.
3. **Selection**: the :data:`TOP_K` best *bracketed* points (every lattice neighbour searched or
   beyond a limit, so each chosen value is interior to what was searched) train again on
   :data:`SELECTION_SEEDS`, fresh; the best mean over those seeds alone is the learner's
   chosen setting (ties: the better ranked on the grid).
4. **Judgement**: each chosen setting on :data:`SEEDS`, fresh (no other design's run used
   them), 500 held-out trials each.

Selection runs per learner and world: 9 x 5 x 2 + 3 x 5 x 2 + 3 x 4 = 132 (grid, extension,
selection), judged runs 20: equal for every learner by construction.

PPO's training steps: :data:`PPO_STEPS`, the SARSA learners' allowance (2000 training trials
of at most 25 actions), not the steps they use (a docked trial ends early): fixed before the
runs, it favours PPO. Its other settings are skrl's defaults (``PPOConfig``).

The verdicts (:func:`judgement`), per world, of linear SARSA minus the paper's learner over
the matched judged seeds (each learner's run of a seed draws its own held-out stream; the
seeds are matched, the trials are not paired):

* **the lead**: the per-seed differences' mean and Student-t 95% interval; the two-sided
  one-sample t-test against zero, Holm-adjusted over the worlds at :data:`ALPHA`: *linear
  SARSA ahead*, *the paper's learner ahead*, or *no lead shown* (the replication's rule);
* **non-inferiority at a :data:`MARGIN` margin**: the one-sided t-test of "linear SARSA's
  lead is at least the margin", Holm over the worlds at ``ALPHA / 2`` (at one world, the 95%
  interval's upper end below the margin: what earlier editions called the gap *closed*):
  *non-inferior*; the one-sided test of "the lead is at most the margin" rejected the same
  way: *inferior by more than the margin* (the gap remains); else *undecided*;
* **equivalence within +-MARGIN** (TOST): the larger of the two one-sided t-tests' p-values
  against -MARGIN and +MARGIN, Holm over the worlds at ``ALPHA`` (at one world, the 90%
  interval inside +-MARGIN): *equivalent* or *equivalence not shown*;
* **the failure ratio**: the paper's learner's mean failure rate over linear SARSA's, a point
  estimate beside them (no test).

PPO is judged on the same seeds and shown beside them (its interval over seeds; no verdict).

Grid runs the committed ledger already holds (the landscape's fixed grid, seeds 5900-5901, and
the tuning tables' runs of the same configurations on those seeds: :data:`READ_FROM`) are read
from there under their own names; everything else is computed under :data:`NAME`.

Budget (issue 59: 10 h of one process), planned from the ledger's recorded run times on this
kind of machine (0.21 ms per environment step): 530 grid runs to compute (PPO 270 at about 45
s, the sideboard world's SARSA 180 at about 10 s, the 9 missing floor and Nao-like SARSA points
and the two new rows, 86 at about 16 s), 270 extension runs, 108 selection runs and 180 judged
runs: about 8 h. Nothing cut.
"""

from __future__ import annotations

import dataclasses
import hashlib
import inspect
import json

import numpy as np
from scipy import stats as sps

from docking.study.design import Cell, Design
from docking.study.design import rules_text as design_rules_text
from docking.study.designs import addendum as ad
from docking.study.designs import third_edition as te
from docking.study.designs.builders import HELDOUT_TRIALS, experiment2_in, linear_sarsa, net
from docking.study.designs.builders import variant as named_variant
from docking.study.ppo import PPOConfig

NAME = "equal-contest"
WORLDS = ("sideboard", "floor", "nao")
LEARNERS = ("paper", "linear", "ppo")
#: The seeds of every grid and extension point (the landscape's fixed grid's).
GRID_SEEDS = (5900, 5901)
#: The seeds the top points train on again: fresh (no earlier run used them).
SELECTION_SEEDS = (6500, 6501, 6502, 6503)
#: The judged seeds: fresh, used by no other design.
SEEDS = tuple(range(7200, 7220))
GRID_ROWS, GRID_COLS = 9, 5
EXTENSION_STAGES, EXTENSION_POINTS = 3, 5
TOP_K = 3
ALPHA = 0.05
MARGIN = 0.05
#: PPO's training steps: 2000 training trials x 25 actions, the SARSA learners' allowance.
PPO_STEPS = 2000 * 25
PPO_ENVS = 16
#: The paper's learner's eps_Q per world: the last tuned value there (third edition, sideboard;
#: the bracketing continued, floor and Nao-like).
PAPER_EPS_Q = {"sideboard": 0.03, "floor": 0.03, "nao": 0.3}
#: Each learner's knobs: ``(row knob, column knob)``.
KNOBS = {
    "paper": ("beta_a_train", "eps_w"),
    "linear": ("beta_a_train", "eps_q"),
    "ppo": ("learning_rate", "rollouts"),
}


@dataclasses.dataclass(frozen=True)
class Ladder:
    """A knob's log-spaced values: rung ``k`` is ``mantissas[k % n] * base ** (exponent + k //
    n)`` (``n`` mantissas), exact as a decimal literal for base 10; ``integer``: the knob takes
    whole numbers; ``upper``: the largest value allowed. A rung beyond a limit (not a whole
    number, above ``upper``) is None."""

    mantissas: tuple
    exponent: int
    base: int = 10
    integer: bool = False
    upper: float | None = None

    def value(self, k: int):
        m, e = self.mantissas[k % len(self.mantissas)], self.exponent + k // len(self.mantissas)
        v = float(f"{m}e{e}") if self.base == 10 else float(m * self.base**e)
        if self.upper is not None and v > self.upper:
            return None
        if self.integer:
            return int(v) if v.is_integer() and v >= 1 else None
        return v


#: Rows: rungs 0-8 are the grid. beta_a 1, 2, 5, ..., 500; PPO's learning rate 1e-5 ... 5e-3.
ROW_LADDERS = {
    "paper": Ladder((1, 2, 5), 0),
    "linear": Ladder((1, 2, 5), 0),
    "ppo": Ladder((1, 2, 5), -5),
}
#: Columns: rungs 0-4 are the grid. eps_W 0.05 ... 5; eps_Q 0.01 ... 1; rollouts 8 ... 128
#: (at most 256: 16 copies x 512 rollouts make XLA's compile of the update take minutes).
COL_LADDERS = {
    "paper": Ladder((5, 15), -2),
    "linear": Ladder((1, 3), -2),
    "ppo": Ladder((8,), 0, base=2, integer=True, upper=256),
}

#: The grid points whose runs on :data:`GRID_SEEDS` the committed ledger holds, by the table
#: (the run's name) that holds them: ``{world: {learner: {table: ((row rung, column rung),
#: ...)}}}`` (tests/test_equal_contest.py checks it against the ledger).
READ_FROM = {
    "floor": {
        "paper": {
            "fragility-landscape": (
                *((0, c) for c in range(5)),
                (1, 3),
                (1, 4),
                (2, 0),
                (2, 1),
                (2, 3),
                (2, 4),
                (3, 0),
                (3, 1),
                (3, 2),
                (3, 4),
                (4, 0),
                (4, 1),
                (4, 3),
                (4, 4),
                (5, 0),
                (5, 4),
                (6, 0),
                (6, 4),
            ),
            "third-edition-addendum": ((1, 1), (2, 2), (3, 3)),
            "addendum-bracketing-continued": ((4, 2), (5, 1), (5, 3), (6, 1), (6, 2), (6, 3)),
            "addendum-bracketing": ((5, 2),),
        },
        "linear": {
            "fragility-landscape": (
                *((0, c) for c in range(5)),
                (1, 0),
                (1, 4),
                (2, 0),
                (2, 4),
                (3, 0),
                (3, 4),
                (4, 0),
                (4, 1),
                (4, 3),
                (4, 4),
                *((5, c) for c in range(5)),
                *((6, c) for c in range(5)),
            ),
            "third-edition-addendum": (
                (1, 1),
                (1, 2),
                (1, 3),
                (2, 1),
                (2, 2),
                (2, 3),
                (3, 1),
                (3, 2),
                (3, 3),
                (4, 2),
            ),
        },
    },
    "nao": {
        "paper": {
            "fragility-landscape": (
                *((0, c) for c in range(5)),
                (1, 0),
                (1, 1),
                (1, 4),
                (2, 0),
                (2, 2),
                (2, 3),
                (2, 4),
                (3, 0),
                (3, 1),
                (3, 3),
                (3, 4),
                (4, 0),
                (4, 1),
                (4, 3),
                (4, 4),
                (5, 0),
                (5, 4),
                (6, 0),
                (6, 1),
                (6, 3),
                (6, 4),
            ),
            "third-edition-addendum": ((1, 3), (2, 1), (3, 2)),
            "addendum-bracketing": ((4, 2), (5, 2)),
            "addendum-bracketing-continued": ((5, 1), (5, 3), (6, 2)),
        },
        "linear": {
            "fragility-landscape": (
                *((0, c) for c in range(5)),
                (1, 0),
                (1, 4),
                (2, 0),
                (2, 4),
                (3, 4),
                (4, 0),
                (4, 2),
                (4, 3),
                (4, 4),
                *((5, c) for c in range(5)),
                *((6, c) for c in range(5)),
            ),
            "third-edition-addendum": (
                (1, 1),
                (1, 2),
                (1, 3),
                (2, 1),
                (2, 2),
                (2, 3),
                (3, 0),
                (3, 1),
                (3, 2),
                (3, 3),
                (4, 1),
            ),
        },
    },
}


def setting(world: str, learner: str, point: tuple[int, int]) -> dict | None:
    """The knob values of lattice point ``point`` (row rung, column rung) of ``learner`` in
    ``world``, or None where a rung is beyond its ladder's limit."""
    row, col = ROW_LADDERS[learner].value(point[0]), COL_LADDERS[learner].value(point[1])
    if row is None or col is None:
        return None
    found = dict(zip(KNOBS[learner], (row, col), strict=True))
    return {"eps_q": PAPER_EPS_Q[world], **found} if learner == "paper" else found


def learner_config(world: str, learner: str, knobs: dict, name: str = NAME):
    """``learner`` of ``world`` with ``knobs``, stored under ``name``."""
    w = te.WORLDS[world][1]
    if learner == "ppo":
        return PPOConfig(
            name=name,
            world=w,
            steps=PPO_STEPS,
            envs=PPO_ENVS,
            heldout_trials=HELDOUT_TRIALS,
            **knobs,
        )
    base = experiment2_in(w, name)
    make = linear_sarsa if learner == "linear" else net
    return named_variant(base, name, network=make(base, **knobs))


def valid(world: str, learner: str, point: tuple[int, int]) -> bool:
    """Whether ``point`` is a configuration (every rung within its ladder's limits)."""
    knobs = setting(world, learner, point)
    if knobs is None:
        return False
    try:
        learner_config(world, learner, knobs)
    except ValueError:
        return False
    return True


def _stored_under(world: str, learner: str, point: tuple[int, int]) -> str:
    for table, points in READ_FROM.get(world, {}).get(learner, {}).items():
        if tuple(point) in points:
            return table
    return NAME


def _cell(world, learner, point, stage, seeds, name=NAME) -> Cell:
    knobs = setting(world, learner, point)
    tag = ad.tag(knobs)
    suffix = "" if stage in ("grid", "judged") else f"/{stage}"
    key = f"{world}/{learner}/judged" if stage == "judged" else f"{world}/{learner}/{tag}{suffix}"
    return Cell(
        key,
        learner_config(world, learner, knobs, name),
        {
            "world": world,
            "learner": learner,
            "stage": stage,
            "row": int(point[0]),
            "col": int(point[1]),
            **knobs,
        },
        f"{learner} {tag} ({stage})",
        seeds=seeds,
    )


def grid_cells() -> list[Cell]:
    """The common grid: every learner's 9 x 5 points in every world, on :data:`GRID_SEEDS`."""
    return [
        _cell(w, learner, (r, c), "grid", GRID_SEEDS, _stored_under(w, learner, (r, c)))
        for w in WORLDS
        for learner in LEARNERS
        for r in range(GRID_ROWS)
        for c in range(GRID_COLS)
    ]


# ------------------------------------------------------------------------------------------
# The procedure (its source is part of the rules).
# ------------------------------------------------------------------------------------------


def searched(results, world: str, learner: str) -> dict[tuple[int, int], float]:
    """Every point of ``learner`` in ``world`` searched on the grid seeds (the grid, then the
    extensions in order), with its mean held-out success over them."""
    return {
        (c["row"], c["col"]): float(np.mean(results.score(c.key)))
        for c in results.cells
        if c["world"] == world
        and c["learner"] == learner
        and (c["stage"] == "grid" or c["stage"].startswith("extension"))
    }


def ranked(points: dict[tuple[int, int], float]) -> list[tuple[int, int]]:
    """The points best first (ties: the earlier searched)."""
    order = {p: i for i, p in enumerate(points)}
    return sorted(points, key=lambda p: (-points[p], order[p]))


def neighbours(point: tuple[int, int]) -> list[tuple[int, int]]:
    """A point's lattice neighbours: row up, row down, column up, column down."""
    r, c = point
    return [(r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)]


def extension(stage: int):
    """Extension stage ``stage`` (1, 2, ...): per world and learner, :data:`EXTENSION_POINTS`
    new points, the unsearched valid neighbours of the points in ranked order."""

    def cells(results) -> list[Cell]:
        found = []
        for world in WORLDS:
            for learner in LEARNERS:
                points = searched(results, world, learner)
                new = []
                for p in ranked(points):
                    for n in neighbours(p):
                        if len(new) < EXTENSION_POINTS and n not in points and n not in new:
                            if valid(world, learner, n):
                                new.append(n)
                found += [_cell(world, learner, n, f"extension-{stage}", GRID_SEEDS) for n in new]
        return found

    cells.__name__ = f"extension_{stage}"
    return cells


def bracketed(points: dict, world: str, learner: str, point: tuple[int, int]) -> bool:
    """Whether every lattice neighbour of ``point`` was searched or is beyond a limit."""
    return all(n in points or not valid(world, learner, n) for n in neighbours(point))


def candidates(results, world: str, learner: str) -> list[tuple[int, int]]:
    """The :data:`TOP_K` best bracketed points of ``learner`` in ``world``, best first."""
    points = searched(results, world, learner)
    return [p for p in ranked(points) if bracketed(points, world, learner, p)][:TOP_K]


def selection(results) -> list[Cell]:
    """The candidates of every learner and world, on :data:`SELECTION_SEEDS`."""
    return [
        _cell(world, learner, p, "selection", SELECTION_SEEDS)
        for world in WORLDS
        for learner in LEARNERS
        for p in candidates(results, world, learner)
    ]


def chosen(results, world: str, learner: str) -> tuple[int, int]:
    """The chosen point: the candidate with the best mean on the selection seeds (ties: the
    better ranked on the grid)."""
    found = [
        c
        for c in results.cells
        if c["world"] == world and c["learner"] == learner and c["stage"] == "selection"
    ]
    best = sorted(
        range(len(found)), key=lambda i: (-float(np.mean(results.score(found[i].key))), i)
    )[0]
    return found[best]["row"], found[best]["col"]


def judged(results) -> list[Cell]:
    """Every learner's chosen setting in every world, on :data:`SEEDS`."""
    return [
        _cell(world, learner, chosen(results, world, learner), "judged", SEEDS)
        for world in WORLDS
        for learner in LEARNERS
    ]


STAGES = (*(extension(s) for s in range(1, EXTENSION_STAGES + 1)), selection, judged)

DESIGN = Design(
    name=NAME,
    title="the equal contest: every learner searched alike on a common grid, judged afresh",
    cells=tuple(grid_cells()),
    seeds=SEEDS,
    measure="heldout",
    stages=STAGES,
    alpha=ALPHA,
)


# ------------------------------------------------------------------------------------------
# The verdicts (their source is part of the rules).
# ------------------------------------------------------------------------------------------


def holm(p) -> np.ndarray:
    """Holm's step-down adjusted p-values of a family, in the given order."""
    p = np.asarray(p, dtype=np.float64)
    order, adjusted, running = np.argsort(p, kind="stable"), np.empty(len(p)), 0.0
    for rank, k in enumerate(order):
        running = max(running, min(1.0, (len(p) - rank) * p[k]))
        adjusted[k] = running
    return adjusted


def judgement(pairs: dict) -> dict:
    """The verdicts of every world (``pairs``: ``{world: (linear, paper)}``, per-seed held-out
    success on the matched judged seeds): ``{world: {...}}`` with the lead (``lead``, ``low``,
    ``high``: mean and 95% interval of linear minus paper; ``p_lead``, ``lead_verdict``), the
    non-inferiority test (``p_noninferior``, ``p_inferior``, ``noninferiority``), the
    equivalence test (``p_tost``, ``equivalence``), ``failure_ratio`` and the means."""
    worlds = list(pairs)
    diffs = [np.asarray(pairs[w][0], float) - np.asarray(pairs[w][1], float) for w in worlds]
    for d in diffs:
        if d.ndim != 1 or len(d) < 2:
            raise ValueError(f"judgement needs matched series of 2 or more seeds, got {d!r}")
    lead = holm([sps.ttest_1samp(d, 0.0).pvalue for d in diffs])
    below = holm([sps.ttest_1samp(d, MARGIN, alternative="less").pvalue for d in diffs])
    above = holm([sps.ttest_1samp(d, MARGIN, alternative="greater").pvalue for d in diffs])
    tost = holm(
        [
            max(
                sps.ttest_1samp(d, -MARGIN, alternative="greater").pvalue,
                sps.ttest_1samp(d, MARGIN, alternative="less").pvalue,
            )
            for d in diffs
        ]
    )
    found = {}
    for i, (w, d) in enumerate(zip(worlds, diffs, strict=True)):
        linear, paper = (np.asarray(x, float) for x in pairs[w])
        ci = sps.ttest_1samp(d, 0.0).confidence_interval(1 - ALPHA)
        side = "the paper's learner ahead" if d.mean() < 0 else "linear SARSA ahead"
        if below[i] < ALPHA / 2:
            noninferiority = "non-inferior"
        elif above[i] < ALPHA / 2:
            noninferiority = "inferior by more than the margin"
        else:
            noninferiority = "undecided"
        found[w] = dict(
            linear=float(linear.mean()),
            paper=float(paper.mean()),
            lead=float(d.mean()),
            low=float(ci.low),
            high=float(ci.high),
            p_lead=float(lead[i]),
            lead_verdict=side if lead[i] < ALPHA else "no lead shown",
            p_noninferior=float(below[i]),
            p_inferior=float(above[i]),
            noninferiority=noninferiority,
            p_tost=float(tost[i]),
            equivalence="equivalent" if tost[i] < ALPHA else "equivalence not shown",
            failure_ratio=float((1 - paper.mean()) / (1 - linear.mean()))
            if linear.mean() < 1
            else float("inf"),
            seeds=len(d),
        )
    return found


#: The constants that are rules (in :func:`rules_text`).
RULES = (
    "WORLDS LEARNERS GRID_SEEDS SELECTION_SEEDS SEEDS GRID_ROWS GRID_COLS EXTENSION_STAGES "
    "EXTENSION_POINTS TOP_K ALPHA MARGIN PPO_STEPS PPO_ENVS PAPER_EPS_Q KNOBS READ_FROM"
).split()
#: The functions and classes whose source is part of the rules: the procedure and the verdicts.
PROCEDURE = (
    Ladder,
    setting,
    valid,
    searched,
    ranked,
    neighbours,
    extension,
    bracketed,
    candidates,
    selection,
    chosen,
    judged,
    holm,
    judgement,
)


def rules_text() -> str:
    """Every rule of the equal contest as canonical text: its constants, its ladders, its grid
    cells and the source of its procedure and verdicts."""
    constants = {n: globals()[n] for n in RULES}
    constants["ladders"] = {
        learner: [
            dataclasses.asdict(ROW_LADDERS[learner]),
            dataclasses.asdict(COL_LADDERS[learner]),
        ]
        for learner in LEARNERS
    }
    source = "".join(inspect.getsource(f) for f in PROCEDURE)
    constants["procedure"] = hashlib.sha256(source.encode()).hexdigest()
    return design_rules_text(DESIGN, json.loads(json.dumps(constants, default=list)))
