"""The report of Experiment 3 (:mod:`docking.study.designs.experiment3`, notebook 06): four
against six actions, from the cells' coordinates; the README's table of it.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.study.report import md_table
from docking.study.stats import Interval, difference_ci, removed_share_ci


@dataclasses.dataclass(frozen=True)
class Comparison:
    """Four against six actions in one task at one heading noise.

    Attributes:
      task, noise: The cell pair's task and heading noise (deg).
      four_key, six_key: The two cells' keys.
      four, six: Held-out success with four and with six actions (95% intervals for a rate
        over seeds and their trials, :func:`docking.study.stats.rate_ci`).
      gain: Six minus four actions (percentage points as fractions, 95% interval).
      removed: The share of the four-action learner's failures that are gone with six
        actions, ``1 - failures6 / failures4`` (95% interval, seeds of each resampled
        independently); None if the four-action learner never failed.
    """

    task: str
    noise: float
    four: Interval
    six: Interval
    gain: Interval
    removed: Interval | None
    four_key: str = ""
    six_key: str = ""

    @property
    def failure_ratio(self) -> Interval | None:
        """How many times as often six actions fail as four, ``failures6 / failures4``
        (``1 - removed``, with its interval)."""
        if self.removed is None:
            return None
        r = self.removed
        return Interval(1 - r.estimate, 1 - r.high, 1 - r.low, r.values, r.confidence)


def turning_comparisons(results) -> list[Comparison]:
    """One :class:`Comparison` per six-action core cell of an Experiment 3 design (coordinate
    ``actions == "turning"``) against its baseline, the four-action cell of the same task
    and noise, in the design's order; each arm's success with the interval for a rate
    (:func:`docking.study.claims.rate_interval`)."""
    from docking.study.claims import rate_interval

    found = []
    for c in results.cells:
        if c.coords.get("actions") != "turning" or not c.core:
            continue
        four, six = results.score(c.baseline), results.score(c.key)
        removed = None
        if np.mean(1 - four) > 0:
            removed = removed_share_ci(1 - six, 1 - four, paired=False)
        found.append(
            Comparison(
                c.coords["task"],
                c.coords["noise_deg"],
                rate_interval(results, c.baseline),
                rate_interval(results, c.key),
                difference_ci(six, four),
                removed,
                c.baseline,
                c.key,
            )
        )
    return found


def oracle_rates(oracle) -> dict[str, float]:
    """A yardstick design's held-out success per cell (``{cell key: rate}``, all seeds'
    trials pooled)."""
    return {c.key: float(np.mean(oracle.score(c.key))) for c in oracle.cells}


def turning_table(comparisons: list[Comparison], oracle: dict[str, float]) -> str:
    """The Markdown table of Experiment 3 from its :func:`turning_comparisons`: per task and
    noise, the oracle (``oracle``: its rate in each cell's world, by cell key) and the learner
    with four and six actions, six minus four, and how many times as often six actions fail
    as four."""
    rows = []
    for c in comparisons:
        o4, o6 = oracle[c.four_key], oracle[c.six_key]
        ratio = "no failures" if c.failure_ratio is None else c.failure_ratio.format(1.0, "x", 2)
        rows.append(
            (c.task, f"{c.noise:g}", f"{100 * o4:.1f}% / {100 * o6:.1f}%")
            + (c.four.format(unit="%"), c.six.format(unit="%"), c.gain.format(unit=" pp"), ratio)
        )
    header = ("task", "heading noise (deg)", "oracle, 4 / 6 actions", "learner, 4 actions")
    return md_table(header + ("learner, 6 actions", "6 minus 4", "failures, 6 / 4 actions"), rows)


def rotation_verdict(comparisons: list[Comparison], rule) -> tuple[str, Interval]:
    """The paper's rotation claim ("the reason for most of the unsuccessful trials") judged
    by the remedy it names, from Experiment 3's :func:`turning_comparisons`: in the paper's
    task at the lowest heading noise, the share of the four-action learner's held-out
    failures that are gone when the learner can turn, decided by ``rule`` (a
    :class:`docking.study.claims.Rule`); the verdict and the interval."""
    paper = [c for c in comparisons if c.task == "paper task"]
    found = min(paper, key=lambda c: c.noise)
    if found.removed is None:
        raise ValueError("the four-action learner never failed: nothing to remove")
    return rule.decide(found.removed), found.removed


def final_headings(results, key: str, n_seeds: int | None = None) -> np.ndarray:
    """``|yaw|`` (deg; 0 = facing the landmark's wall) at the end of every failed held-out
    trial of cell ``key``, its first ``n_seeds`` seeds (None: all) pooled."""
    out = [
        abs(np.degrees(log.trial_poses(k)[-1][2]))
        for log in results.logs[key][:n_seeds]
        for k in np.flatnonzero(~log.success)
    ]
    return np.array(out, dtype=np.float64)
