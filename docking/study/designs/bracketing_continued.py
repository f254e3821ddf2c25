"""The bracketing continued (issue 40), a third labelled analysis beside
:mod:`docking.study.designs.addendum` and :mod:`docking.study.designs.bracketing`, judged on fresh
seeds.

**These rules were committed before any of its runs** and are not changed after seeing them
(``tests/test_bracketing_continued.py`` pins them by a digest of :func:`rules_text`, which
covers this module's code, the bracketing's rules and the gap rule's code).

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

import dataclasses
import functools
import hashlib
import inspect
import itertools
import json
from pathlib import Path

import numpy as np

from docking.study.design import Cell, Design
from docking.study.design import rules_text as design_rules_text
from docking.study.designs import addendum as ad
from docking.study.designs import bracketing as br
from docking.study.designs.builders import experiment2_in, linear_sarsa, net, variant

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


def learner_config(world: str, learner: str, **setting):
    """The learner ``learner`` of ``world`` with ``setting``, named for this design."""
    base = experiment2_in(ad.WORLDS[world], NAME)
    make = linear_sarsa if learner == "linear" else net
    return variant(base, NAME, network=make(base, **setting))


def scores(own, world: str, learner: str) -> dict[tuple, dict[int, float]]:
    """Per setting, in the order evaluated (the addendum's, the bracketing's, then this
    design's): its held-out success on each seed it ran."""
    found = br.scores(bracketing(), world, learner)
    if own is None:
        return found
    for c in own.cells:
        if c.coords.get("variant") != f"continue-{learner}" or c["world"] != world:
            continue
        seeds = [r.seed for r in own.runs[c.key]]
        got = found.setdefault(br._setting(c.coords, learner), {})
        got.update(zip(seeds, map(float, own.score(c.key)), strict=True))
    return found


complete = br.complete
incumbent = br.incumbent
missing_neighbours = br.missing_neighbours


def runs_used(own, world: str, learner: str) -> int:
    """This design's walk's training runs for ``learner`` in ``world``."""
    if own is None:
        return 0
    return sum(
        len(own.runs[c.key])
        for c in own.cells
        if c.coords.get("variant") == f"continue-{learner}" and c["world"] == world
    )


def bracketed(own, world: str, learner: str) -> bool:
    """Whether the learner's incumbent has every neighbour complete."""
    found = scores(own, world, learner)
    return not missing_neighbours(found, incumbent(found))


def _extend(own) -> list[Cell]:
    cells = []
    for world, learner in itertools.product(ad.WORLDS, ad.LEARNERS):
        found = scores(own, world, learner)
        used = runs_used(own, world, learner)
        for setting, seeds in missing_neighbours(found, incumbent(found)):
            if used + len(seeds) <= BUDGET:
                used += len(seeds)
                cells.append(
                    Cell(
                        f"{world}/continue-{learner}/{ad.tag(setting)}",
                        learner_config(world, learner, **setting),
                        {"world": world, "variant": f"continue-{learner}", "learner": learner}
                        | setting,
                        f"{learner} {ad.tag(setting)}",
                        seeds=seeds,
                    )
                )
    return cells


def tuned(own, world: str, learner: str) -> dict:
    """The tuned setting: the last incumbent."""
    return incumbent(scores(own, world, learner))


def changed(own, world: str, learner: str) -> bool:
    """Whether the tuned setting differs from the addendum's."""
    return tuned(own, world, learner) != ad.TUNING.tuned(addendum(), world, learner)


def _judged(own) -> list[Cell]:
    return [
        Cell(
            f"{world}/{learner}-bracketed",
            learner_config(world, learner, **tuned(own, world, learner)),
            {"world": world, "variant": f"{learner}-bracketed", "learner": learner},
            f"{learner}, bracketed: {ad.tag(tuned(own, world, learner))}",
        )
        for world, learner in itertools.product(ad.WORLDS, ad.LEARNERS)
    ]


def judged_scores(own, world: str, learner: str) -> np.ndarray:
    return own.score(f"{world}/{learner}-bracketed")


def paper_steps(own, world: str) -> float:
    """The tuned paper learner's mean training steps over its judged runs here."""
    return float(np.mean(ad.training_steps(own, f"{world}/paper-bracketed")))


def _ppo(own) -> list[Cell]:
    cells = []
    for world in ad.WORLDS:
        steps = ad.PPO_ENVS * int(round(paper_steps(own, world) / ad.PPO_ENVS))
        config = ad.learner_config(
            world, "ppo", steps=steps, envs=ad.PPO_ENVS, **ad.PPO_SETTINGS[world]
        )
        cells.append(
            Cell(
                f"{world}/ppo-matched",
                dataclasses.replace(config, name=NAME),
                {"world": world, "variant": "ppo-matched", "learner": "ppo"},
                f"PPO at the paper learner's {steps} training steps",
            )
        )
    return cells


class _Judged:
    """The judged success of the tuned learners (``{world}/{learner}-tuned``): what the gap
    rule reads."""

    def __init__(self, own):
        self.own = own

    def score(self, key: str) -> np.ndarray:
        world, variant_name = key.split("/")
        return judged_scores(self.own, world, variant_name.removesuffix("-tuned"))


def gaps(own):
    """The gap rule on the tuned learners' fresh judged runs
    (:func:`docking.study.report.contest_gaps`)."""
    from docking.study import report

    return report.contest_gaps(_Judged(own), ad.WORLDS, ad.GAP_CLOSED)


DESIGN = Design(
    name=NAME,
    title="the bracketing's walk continued, then every tuned learner judged on fresh seeds",
    cells=(),
    seeds=SEEDS,
    measure="heldout",
    stages=(*[_extend] * STAGES, _judged, _ppo),
    alpha=ad.ALPHA,
)


def _code_digest() -> str:
    """SHA-256 of this module's tokens (without comments and docstrings), the bracketing's
    rules text and the gap rule's and its interval's source."""
    from docking.study import fingerprint, report, stats

    digest = hashlib.sha256()
    digest.update(fingerprint.code_tokens(Path(__file__).read_text(), __name__)[0].encode())
    digest.update(br.rules_text().encode())
    for function in (report.contest_gaps, report.paired_over_shared_seeds, stats.t_paired_ci):
        digest.update(inspect.getsource(function).encode())
    return digest.hexdigest()


#: The constants that are rules (in :func:`rules_text`).
RULES = "COMPARE_SEEDS SEEDS BUDGET STAGES".split()


def rules_text() -> str:
    """Every rule of the continued bracketing as canonical text: its constants and
    :func:`_code_digest`."""
    constants = {n: globals()[n] for n in RULES}
    constants["code"] = _code_digest()
    return design_rules_text(DESIGN, json.loads(json.dumps(constants, default=list)))
