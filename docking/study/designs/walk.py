"""The walk to a bracketed optimum, written once and parameterised: what the next walk design
takes its walk from.

The addendum's bracketing (:mod:`docking.study.designs.bracketing`) and its continuation
(:mod:`docking.study.designs.bracketing_continued`) both walk by it. Their rules, and the code
of their walks as committed before their runs, are kept as records (``rules/``); replayed on
the ledger's runs, this walk gives the cells theirs gave (tests/test_records.py). A new walk
design builds a :class:`Walk` too:

* a setting is *complete* when it has held-out success on every one of the compared seeds,
  from the runs before the design (:attr:`Walk.before`) or the design's own; settings are
  compared by their mean over those seeds (the same seeds for every setting: paired);
* each stage, the *incumbent* is the complete setting with the best mean (ties: the first
  evaluated), and every neighbour of it on the addendum's ladders
  (:func:`docking.study.designs.addendum.neighbours`) runs the compared seeds it lacks, while
  the learner's runs in the design stay within the budget;
* a learner whose incumbent has every neighbour complete is *bracketed*; the tuned setting is
  the last incumbent.

How the tuned learners are judged (on which seeds, against what) is each design's own rule.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable

import numpy as np

from docking.study.design import Cell
from docking.study.designs import addendum as ad
from docking.study.designs.builders import experiment2_in, linear_sarsa, net, variant

__all__ = ["Judged", "Walk", "scores_of"]


def scores_of(results, variant_name: str, world: str, learner: str) -> dict[tuple, dict]:
    """Per setting of ``learner`` (a tuple of ``(knob, value)``) in ``world``, in the order of
    ``results``' cells of variant ``variant_name``: its held-out success on each seed it ran."""
    found: dict[tuple, dict[int, float]] = {}
    for c in results.cells:
        if c.coords.get("variant") != variant_name or c["world"] != world:
            continue
        seeds = [r.seed for r in results.runs[c.key]]
        got = found.setdefault(tuple((k, c.coords[k]) for k in ad.KNOBS[learner]), {})
        got.update(zip(seeds, map(float, results.score(c.key)), strict=True))
    return found


@dataclasses.dataclass(frozen=True)
class Walk:
    """One walk design's walk (the module docstring).

    Attributes:
      name: The design's name (its cells' configurations are named so).
      variant: Its cells' variant, per learner ``f"{variant}-{learner}"`` (their keys
        ``f"{world}/{variant}-{learner}/{tag}"``).
      compare_seeds: The seeds every setting is compared on.
      budget: Training runs per learner and world in the design, every stage included.
      before: ``before(world, learner)``: the scores of every setting evaluated before the
        design (:func:`scores_of` of the earlier designs' results), in the order evaluated.
      worlds, learners: Where and whom it walks (the addendum's).
    """

    name: str
    variant: str
    compare_seeds: tuple[int, ...]
    budget: int
    before: Callable[[str, str], dict]
    worlds: tuple[str, ...] = tuple(ad.WORLDS)
    learners: tuple[str, ...] = ad.LEARNERS

    def learner_config(self, world: str, learner: str, **setting):
        """The learner ``learner`` of ``world`` with ``setting``, named for the design."""
        base = experiment2_in(ad.WORLDS[world], self.name)
        make = linear_sarsa if learner == "linear" else net
        return variant(base, self.name, network=make(base, **setting))

    def scores(self, own, world: str, learner: str) -> dict[tuple, dict[int, float]]:
        """Per setting, in the order evaluated (before the design, then its own cells): its
        held-out success on each seed it ran."""
        found = {s: dict(got) for s, got in self.before(world, learner).items()}
        if own is not None:
            mine = scores_of(own, f"{self.variant}-{learner}", world, learner)
            for setting, got in mine.items():
                found.setdefault(setting, {}).update(got)
        return found

    def complete(self, found: dict[tuple, dict[int, float]]) -> dict[tuple, float]:
        """The complete settings' means over the compared seeds, in the order evaluated."""
        return {
            s: float(np.mean([got[seed] for seed in self.compare_seeds]))
            for s, got in found.items()
            if all(seed in got for seed in self.compare_seeds)
        }

    def incumbent(self, found) -> dict:
        """The complete setting with the best mean (ties: the first evaluated)."""
        means = self.complete(found)
        order = list(means)
        best = max(range(len(order)), key=lambda i: (means[order[i]], -i))
        return dict(order[best])

    def missing_neighbours(self, found, setting: dict) -> list[tuple[dict, tuple[int, ...]]]:
        """Each neighbour of ``setting`` on the ladders with the compared seeds it lacks."""
        seeds = self.compare_seeds
        return [
            (other, tuple(s for s in seeds if s not in found.get(tuple(other.items()), {})))
            for other, limit in ad.neighbours(setting)
            if limit is None and not all(s in found.get(tuple(other.items()), {}) for s in seeds)
        ]

    def runs_used(self, own, world: str, learner: str) -> int:
        """The design's walk's training runs for ``learner`` in ``world``."""
        if own is None:
            return 0
        return sum(
            len(own.runs[c.key])
            for c in own.cells
            if c.coords.get("variant") == f"{self.variant}-{learner}" and c["world"] == world
        )

    def bracketed(self, own, world: str, learner: str) -> bool:
        """Whether the learner's incumbent has every neighbour complete."""
        found = self.scores(own, world, learner)
        return not self.missing_neighbours(found, self.incumbent(found))

    def tuned(self, own, world: str, learner: str) -> dict:
        """The tuned setting: the last incumbent."""
        return self.incumbent(self.scores(own, world, learner))

    def changed(self, own, world: str, learner: str, before: dict) -> bool:
        """Whether the tuned setting differs from ``before`` (an earlier search's)."""
        return self.tuned(own, world, learner) != before

    def judged(self, own, only: Callable[[str, str], bool] | None = None) -> list[Cell]:
        """The tuned learners' cells (``{world}/{learner}-bracketed``, the design's seeds),
        those ``only(world, learner)`` keeps (None: every one)."""
        return [
            Cell(
                f"{world}/{learner}-bracketed",
                self.learner_config(world, learner, **self.tuned(own, world, learner)),
                {"world": world, "variant": f"{learner}-bracketed", "learner": learner},
                f"{learner}, bracketed: {ad.tag(self.tuned(own, world, learner))}",
            )
            for world, learner in itertools.product(self.worlds, self.learners)
            if only is None or only(world, learner)
        ]

    def gaps(self, scores: Callable[[str, str], np.ndarray]) -> list:
        """The gap rule (:func:`docking.study.report.contest_gaps`, the addendum's bound) on
        the tuned learners whose judged success ``scores(world, learner)`` gives."""
        from docking.study import report

        return report.contest_gaps(Judged(scores), self.worlds, ad.GAP_CLOSED)

    def extend(self, own) -> list[Cell]:
        """One stage of the walk (a design's stage function): the cells that run each
        incumbent's missing neighbours on the seeds they lack, within the budget."""
        cells = []
        for world, learner in itertools.product(self.worlds, self.learners):
            found = self.scores(own, world, learner)
            used = self.runs_used(own, world, learner)
            for setting, seeds in self.missing_neighbours(found, self.incumbent(found)):
                if used + len(seeds) <= self.budget:
                    used += len(seeds)
                    cells.append(
                        Cell(
                            f"{world}/{self.variant}-{learner}/{ad.tag(setting)}",
                            self.learner_config(world, learner, **setting),
                            {"world": world, "variant": f"{self.variant}-{learner}"}
                            | {"learner": learner}
                            | setting,
                            f"{learner} {ad.tag(setting)}",
                            seeds=seeds,
                        )
                    )
        return cells


class Judged:
    """The judged success of a walk's tuned learners as the gap rule reads it (cells
    ``{world}/{learner}-tuned``), wherever their runs are: ``scores(world, learner)``."""

    def __init__(self, scores: Callable[[str, str], np.ndarray]):
        self.scores = scores

    def score(self, key: str) -> np.ndarray:
        world, variant_name = key.split("/")
        return self.scores(world, variant_name.removesuffix("-tuned"))
