"""The equal contest (issue 59): every learner selected by one procedure, with the same number
of runs on a common grid, judged on fresh seeds, and its verdict named as the test it is.

**These rules were committed before any of its runs** and are not changed after seeing them
(their record, ``rules/equal-contest.*``: the rules text pinned by digest at the rules' commit
and its procedure's source as it was then; tests/test_equal_contest.py and
tests/test_records.py hold the live rules to it and replay them on the ledger's runs).

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
   above 1, fewer than one rollout) is a limit, never searched; so is linear SARSA's eps_Q
   above 2 (:data:`LMS_LIMIT`, amendment 1 below).
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

**Amendment 1** (``rules/equal-contest.amendment-1.json``, committed after one run was seen,
before any run it changes): the first extension stage asked for linear SARSA at eps_Q 3, and
that run stopped (Eq. (7)'s update would have made Q non-finite; nothing was stored), which
would stop the whole contest. The rules named no outcome for a run that cannot finish. The
amendment makes eps_Q above 2 a limit of linear SARSA's ladder (the normalised LMS bound: its
input has unit length), of the same kind as the rules' other limits; no other learner's ladder
changes. The 14 extension runs computed before it are all ones the amended rules ask for too.
Its effect: linear SARSA's extension points go to rungs that can run, and eps_Q 1 counts as
bracketed from above.

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
import functools
import json

from docking.study.design import rules_text as design_rules_text
from docking.study.designs import search
from docking.study.designs import third_edition as te
from docking.study.designs.builders import HELDOUT_TRIALS, experiment2_in, linear_sarsa, net
from docking.study.designs.builders import variant as named_variant
from docking.study.designs.search import Entrant, Knob, Ladder, Search
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


#: Rows: rungs 0-8 are the grid. beta_a 1, 2, 5, ..., 500; PPO's learning rate 1e-5 ... 5e-3.
ROW_LADDERS = {
    "paper": Ladder((1, 2, 5), 0),
    "linear": Ladder((1, 2, 5), 0),
    "ppo": Ladder((1, 2, 5), -5),
}
#: Linear SARSA's eps_Q above this is a limit (amendment 1, rules/equal-contest.amendment-1.json,
#: committed before any run it changes): with unit-length input (``normalize_input``) Eq. (7)
#: on linear SARSA is the normalised LMS rule, which overshoots its target and diverges for a
#: step above 2; at eps_Q 3 the network refused an update that would make Q non-finite, and
#: the run stopped with nothing stored.
LMS_LIMIT = 2.0
#: Columns: rungs 0-4 are the grid. eps_W 0.05 ... 5; eps_Q 0.01 ... 1 (at most
#: :data:`LMS_LIMIT`); rollouts 8 ... 128 (at most 256: 16 copies x 512 rollouts make XLA's
#: compile of the update take minutes).
COL_LADDERS = {
    "paper": Ladder((5, 15), -2),
    "linear": Ladder((1, 3), -2, upper=LMS_LIMIT),
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


def learner_config(world: str, learner: str, name: str = NAME, **knobs):
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


def _entrant(learner: str) -> Entrant:
    row, col = KNOBS[learner]
    return Entrant(
        functools.partial(_make, learner),
        Knob(row, ROW_LADDERS[learner]),
        Knob(col, COL_LADDERS[learner]),
        {w: {"eps_q": q} for w, q in PAPER_EPS_Q.items()} if learner == "paper" else {},
    )


def _make(learner: str, world: str, name: str, **knobs):
    return learner_config(world, learner, name, **knobs)


#: The procedure (:class:`docking.study.designs.search.Search`) with this design's constants.
SEARCH = Search(
    name=NAME,
    worlds=WORLDS,
    entrants={learner: _entrant(learner) for learner in LEARNERS},
    grid_seeds=GRID_SEEDS,
    selection_seeds=SELECTION_SEEDS,
    judged_seeds=SEEDS,
    rows=GRID_ROWS,
    cols=GRID_COLS,
    extension_stages=EXTENSION_STAGES,
    extension_points=EXTENSION_POINTS,
    top_k=TOP_K,
    stored_under=READ_FROM,
)

DESIGN = SEARCH.design(
    "the equal contest: every learner searched alike on a common grid, judged afresh", ALPHA
)


def judgement(pairs: dict) -> dict:
    """The verdicts of every world (``pairs``: ``{world: (linear, paper)}``, per-seed held-out
    success on the matched judged seeds), by :func:`docking.study.designs.search.judgement` at
    :data:`MARGIN` and :data:`ALPHA`, Holm over the worlds."""
    return search.judgement(pairs, MARGIN, ALPHA, ("linear SARSA", "the paper's learner"))


def judged(results) -> dict[str, dict]:
    """``{world: {learner: per-seed held-out success on the judged seeds}}``."""
    return {
        w: {learner: results.score(f"{w}/{learner}/judged") for learner in LEARNERS} for w in WORLDS
    }


def verdicts(results) -> dict[str, dict]:
    """Per world, the rules' verdicts of linear SARSA minus the paper's learner
    (:func:`judgement`)."""
    found = judged(results)
    return judgement({w: (found[w]["linear"], found[w]["paper"]) for w in WORLDS})


def chosen(results) -> dict[tuple[str, str], dict]:
    """``{(world, learner): the chosen setting (its knobs)}``."""
    return {
        (w, learner): SEARCH.setting(w, learner, SEARCH.chosen(results, w, learner))
        for w in WORLDS
        for learner in LEARNERS
    }


def replayed(results) -> dict:
    """What the rules reach beyond the cells, as data (its record's replay): every
    learner's chosen setting per world, the verdicts and their margin."""
    picked = {f"{w}/{learner}": s for (w, learner), s in chosen(results).items()}
    return {"chosen": picked, "verdicts": verdicts(results), "margin": MARGIN}


#: The constants that are rules (in :func:`rules_data`).
RULES = (
    "WORLDS LEARNERS GRID_SEEDS SELECTION_SEEDS SEEDS GRID_ROWS GRID_COLS EXTENSION_STAGES "
    "EXTENSION_POINTS TOP_K ALPHA MARGIN PPO_STEPS PPO_ENVS PAPER_EPS_Q KNOBS READ_FROM"
).split()


def rules_data() -> dict:
    """The rules of the equal contest as data: its constants, its ladders and its grid cells
    (:func:`docking.study.design.rules_text`'s form, parsed). Its procedure is
    :mod:`docking.study.designs.search`'s, checked against the procedure as committed (the
    module at the rules' commit, whose blocks the record's verbatim copy holds, with its
    amendment) by replaying both on the ledger's runs (tests/test_equal_contest.py)."""
    constants = {n: globals()[n] for n in RULES}
    constants["ladders"] = {
        learner: [
            dataclasses.asdict(ROW_LADDERS[learner]),
            dataclasses.asdict(COL_LADDERS[learner]),
        ]
        for learner in LEARNERS
    }
    return json.loads(design_rules_text(DESIGN, json.loads(json.dumps(constants, default=list))))
