"""The addendum's bracketing: each SARSA learner's search continued until its optimum is
bracketed (issue 40), a second labelled analysis beside :mod:`docking.study.designs.addendum`.

**These rules were committed before any of its runs** and are not changed after seeing them
(their record, ``rules/addendum-bracketing.*``: the rules text pinned at the rules' commit,
this module's code, the addendum's rules and the gap rule's code as they were then;
tests/test_records.py holds the live rules to it and replays them on the ledger's runs).

Why: the addendum's search ran out of extension stages before the paper's learner's tuned
setting had all its neighbours evaluated (its tables say "at the edge: the search
stopped"); linear SARSA's tuned values were interior. The addendum's runs and tables stay as
they were run; this search starts where it stopped.

The rule, the same for both SARSA learners in each world of the addendum:

* A setting is *complete* when it has held-out success on every one of
  :data:`COMPARE_SEEDS` (the addendum's first 10 tuning seeds), from the addendum's runs
  where it ran that setting and seed, else from this design's. Settings are compared by
  their mean over these seeds: the same seeds for every setting (paired).
* Each stage (:data:`STAGES` at most): the *incumbent* is the complete setting with the
  best mean (ties: the first in the addendum's order of evaluation, then this design's);
  every neighbour of it on the addendum's ladders (one rung up or down one knob,
  :data:`docking.study.designs.addendum.LADDERS`) runs the seeds it lacks, while the learner's
  runs in this design stay within :data:`BUDGET`. A learner whose incumbent has every
  neighbour complete is *bracketed*: each tuned value is interior, or at a ladder's end
  (a stated limit, :data:`docking.study.designs.addendum.LIMITS`). The first incumbent is
  chosen by this rule too, among the addendum's complete settings (its round-2 finalists).
* The tuned setting is the last incumbent. If it differs from the addendum's tuned setting,
  it is judged on the addendum's judged seeds (:data:`docking.study.designs.addendum.SEEDS`,
  untouched by any tuning, on the same matched seeds); otherwise the
  addendum's judged runs stand.
* The gap rule is the addendum's (and the third edition's): linear SARSA minus the paper's
  learner, paired over the judged seeds, Student-t; *closed* if its 95% interval lies
  below :data:`docking.study.designs.addendum.GAP_CLOSED`, *remains* if above, else *undecided*.
* PPO's budget in steps: if the paper's learner's tuned setting changes in a world and its
  judged runs' mean training steps differ by more than :data:`STEPS_TOLERANCE` from the
  steps the addendum's PPO trained for, PPO (the addendum's setting) trains again for the
  new mean (:data:`docking.study.designs.addendum.PPO_ENVS` copies of the world).

Budgets: :data:`BUDGET` training runs per learner and world, the same for both learners
(a learner already bracketed uses fewer). This can only help a learner whose optimum the
addendum had not bracketed: the paper's learner. Cut: nothing beyond the addendum's cuts.
"""

from __future__ import annotations

import functools

import numpy as np

from docking.study.design import Cell, Design
from docking.study.designs import addendum as ad
from docking.study.designs.walk import Walk, scores_of

NAME = "addendum-bracketing"
#: The seeds every setting is compared on (the addendum's first 10 tuning seeds: every
#: round-2 finalist of the addendum has them).
COMPARE_SEEDS = ad.TUNING_SEEDS[:10]
#: Training runs per learner and world in this design, every stage included.
BUDGET = 100
STAGES = 5
#: How far the paper's learner's mean training steps may move from PPO's before PPO is
#: trained again (the acceptance of issue 40: PPO within 5%).
STEPS_TOLERANCE = 0.05


@functools.cache
def addendum():
    """The addendum's results (from the store, else the ledger)."""
    return ad.DESIGN.run(progress=False)


def _before(world: str, learner: str) -> dict:
    """The addendum's tuning runs of ``learner`` in ``world``, per setting."""
    return scores_of(addendum(), f"tune-{learner}", world, learner)


#: The walk (:class:`docking.study.designs.walk.Walk`): the addendum's tuning runs first, then
#: this design's cells (variant ``bracket-{learner}``).
WALK = Walk(NAME, "bracket", COMPARE_SEEDS, BUDGET, _before)
scores, tuned, _extend = WALK.scores, WALK.tuned, WALK.extend


def changed(own, world: str, learner: str) -> bool:
    """Whether the tuned setting differs from the addendum's."""
    return WALK.changed(own, world, learner, ad.TUNING.tuned(addendum(), world, learner))


def _judged(own) -> list[Cell]:
    """The tuned learners whose setting moved from the addendum's (the others' judged runs
    are the addendum's)."""
    return WALK.judged(own, only=functools.partial(changed, own))


def judged_key(own, world: str, learner: str) -> tuple:
    """Where the tuned learner's judged runs are: ``(results, key)``."""
    if changed(own, world, learner):
        return own, f"{world}/{learner}-bracketed"
    return addendum(), f"{world}/{learner}-tuned"


def judged_scores(own, world: str, learner: str) -> np.ndarray:
    results, key = judged_key(own, world, learner)
    return results.score(key)


def paper_steps(own, world: str) -> float:
    """The tuned paper learner's mean training steps over its judged runs."""
    results, key = judged_key(own, world, "paper")
    return float(np.mean(ad.training_steps(results, key)))


def ppo_steps(world: str) -> int:
    """The steps the addendum's PPO trained for in ``world``."""
    return int(addendum().cell(f"{world}/ppo-matched").config.steps)


def _ppo(own) -> list[Cell]:
    """PPO again where the tuned paper learner's training steps moved beyond
    :data:`STEPS_TOLERANCE` from those PPO was trained for."""
    found = []
    for world in ad.WORLDS:
        mean = paper_steps(own, world)
        if abs(ppo_steps(world) - mean) > STEPS_TOLERANCE * mean:
            found.append(ad.ppo_matched(world, mean, NAME))
    return found


def gaps(own):
    """The gap rule on the bracketed learners."""
    return WALK.gaps(functools.partial(judged_scores, own))


def replayed(results) -> dict:
    """What the rules reach beyond the walk, as data (its record's replay): the gap rule's
    verdicts (:func:`gaps`)."""
    return {"gaps": [g.as_data() for g in gaps(results)]}


DESIGN = Design(
    name=NAME,
    title="the addendum's search continued until each SARSA learner's optimum is bracketed",
    cells=(),
    seeds=ad.SEEDS,
    measure="heldout",
    stages=(*[_extend] * STAGES, _judged, _ppo),
    alpha=ad.ALPHA,
)


#: The constants that are rules (:func:`docking.study.designs.rules_data`).
RULES = "COMPARE_SEEDS BUDGET STAGES STEPS_TOLERANCE".split()
