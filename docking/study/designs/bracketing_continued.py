"""The bracketing continued (issue 40), a third labelled analysis beside
:mod:`docking.study.designs.addendum` and :mod:`docking.study.designs.bracketing`, judged on fresh
seeds.

**These rules were committed before any of its runs** and are not changed after seeing them
(their record, ``rules/addendum-bracketing-continued.*``: the rules text pinned at the rules'
commit, this module's code, the bracketing's rules and the gap rule's code as they were then;
tests/test_records.py holds the live rules to it and replays them on the ledger's runs).

Why: the bracketing's search ran out of budget (100 runs per learner and world) before the
paper's learner's tuned setting had all its neighbours evaluated, in both worlds; its
tables say "at the edge: the search stopped" for beta_a_train and eps_w. Linear SARSA's
tuned setting was bracketed (every neighbour evaluated and worse) in both worlds. The
bracketing's rule was not at fault, its budget was: this design is the same walk with a
further budget. It was written after the bracketing's runs were seen (that is why it is a
new, labelled analysis), and it judges on seeds no earlier run has used.

The rule, the same for both SARSA learners in each world of the addendum:

* The walk is the bracketing's (:mod:`docking.study.designs.bracketing`), unchanged: settings are
  compared by their mean held-out success over :data:`COMPARE_SEEDS` (the same 10 tuning
  seeds for every setting), from the addendum's, the bracketing's and this design's runs;
  each stage (:data:`STAGES` at most) runs every ladder neighbour of the incumbent (the
  complete setting with the best mean; ties: the first evaluated) on the compared seeds it
  lacks, while the learner's runs in this design stay within :data:`BUDGET`. A learner whose
  incumbent has every neighbour complete is *bracketed*: each tuned value is interior or at
  a ladder's end (a stated limit, :data:`docking.study.designs.addendum.LIMITS`).
* The tuned setting is the last incumbent. **Both** tuned SARSA learners, changed or not,
  are judged on :data:`SEEDS`, fresh (no run of any earlier design used them), on matched
  seeds (each run its own seed's held-out stream; only the first start pose is shared): the
  addendum's judged seeds have had two judged looks already.
* The gap rule is the addendum's: linear SARSA minus the paper's learner, paired over the
  judged seeds, Student-t; *closed* if its 95% interval lies below
  :data:`docking.study.designs.addendum.GAP_CLOSED`, *remains* if above, else *undecided*.
* PPO (the addendum's setting per world) trains on the same fresh seeds for the tuned paper
  learner's mean training steps over its judged runs here, rounded to a multiple of
  :data:`docking.study.designs.addendum.PPO_ENVS`: PPO's budget in steps, matched again.

Budgets: at most :data:`BUDGET` further training runs per learner and world (the same for
both learners; a learner already bracketed uses none), plus the judged runs. Cut: nothing
beyond the addendum's cuts.
"""

from __future__ import annotations

import functools

import numpy as np

from docking.study.design import Cell, Design
from docking.study.designs import addendum as ad
from docking.study.designs import bracketing as br
from docking.study.designs.walk import Walk

NAME = "addendum-bracketing-continued"
#: The seeds every setting is compared on (the bracketing's).
COMPARE_SEEDS = br.COMPARE_SEEDS
#: Fresh judged seeds: no earlier design's run used them.
SEEDS = tuple(range(7000, 7010))
#: Further training runs per learner and world in this design's walk, every stage included.
BUDGET = 120
STAGES = 6


@functools.cache
def addendum():
    """The addendum's results (from the store, else the ledger)."""
    return br.addendum()


@functools.cache
def bracketing():
    """The bracketing's results (from the store, else the ledger)."""
    return br.DESIGN.run(progress=False)


def _before(world: str, learner: str) -> dict:
    """Every setting the addendum and the bracketing ran, in the order evaluated."""
    return br.scores(bracketing(), world, learner)


#: The walk (:class:`docking.study.designs.walk.Walk`): the addendum's and the bracketing's
#: runs first, then this design's cells (variant ``continue-{learner}``).
WALK = Walk(NAME, "continue", COMPARE_SEEDS, BUDGET, _before)
scores, tuned, _extend = WALK.scores, WALK.tuned, WALK.extend


def changed(own, world: str, learner: str) -> bool:
    """Whether the tuned setting differs from the addendum's."""
    return WALK.changed(own, world, learner, ad.TUNING.tuned(addendum(), world, learner))


def _judged(own) -> list[Cell]:
    """Every tuned learner, judged on this design's fresh seeds."""
    return WALK.judged(own)


def judged_scores(own, world: str, learner: str) -> np.ndarray:
    return own.score(f"{world}/{learner}-bracketed")


def paper_steps(own, world: str) -> float:
    """The tuned paper learner's mean training steps over its judged runs here."""
    return float(np.mean(ad.training_steps(own, f"{world}/paper-bracketed")))


def _ppo(own) -> list[Cell]:
    """PPO trained for the tuned paper learner's mean training steps here, in each world."""
    return [ad.ppo_matched(world, paper_steps(own, world), NAME) for world in ad.WORLDS]


def gaps(own):
    """The gap rule on the tuned learners' fresh judged runs."""
    return WALK.gaps(functools.partial(judged_scores, own))


def replayed(results) -> dict:
    """What the rules reach beyond the walk, as data (its record's replay): the gap rule's
    verdicts (:func:`gaps`)."""
    return {"gaps": [g.as_data() for g in gaps(results)]}


DESIGN = Design(
    name=NAME,
    title="the bracketing's walk continued, then every tuned learner judged on fresh seeds",
    cells=(),
    seeds=SEEDS,
    measure="heldout",
    stages=(*[_extend] * STAGES, _judged, _ppo),
    alpha=ad.ALPHA,
)


#: The constants that are rules (:func:`docking.study.designs.rules_data`).
RULES = "COMPARE_SEEDS SEEDS BUDGET STAGES".split()
