"""Claims as objects: which cells a claim compares, by which rule, and what that rule says.

A :class:`Claim` names the paper's words, the comparisons that test them (per world, cells
against their baselines) and one :class:`Rule`. The rule computes the statistic of a
comparison with its interval (:mod:`docking.stats`), decides it (``"supported"``,
``"not supported"``: the interval does not decide, ``"contradicted"``: it lies on the other
side) and renders its own wording, colour and band; notebooks, the README and the forest plot
all ask the rule, so a rule lives in one place.

Rules:

* :class:`Above`: the baseline minus the cell (percentage points of success) lies above a
  bound (0: the baseline is better).
* :class:`Within`: the difference lies within +-margin (no effect), contradicted if it
  excludes 0.
* :class:`ShareAbove`: the share of the baseline's failures that are gone in the cell lies
  above a share (e.g. 0.5: "most").
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from docking.stats import Interval, difference_ci, removed_share_ci

__all__ = [
    "SUPPORTED",
    "NOT_SUPPORTED",
    "CONTRADICTED",
    "VERDICT_COLOURS",
    "Above",
    "Claim",
    "Rule",
    "ShareAbove",
    "Within",
    "overall",
]

SUPPORTED, NOT_SUPPORTED, CONTRADICTED = "supported", "not supported", "contradicted"

#: The colour of each verdict in figures (matplotlib colours).
VERDICT_COLOURS = {SUPPORTED: "C2", NOT_SUPPORTED: "0.45", CONTRADICTED: "C3"}


class Rule:
    """How a comparison is measured and decided (subclasses below)."""

    #: Whether the statistic is a difference of success (pp) or a share of failures (%).
    unit = " pp"

    def statistic(self, baseline: np.ndarray, cell: np.ndarray, seed: int = 0) -> Interval:
        """``baseline - cell`` of per-seed success, with its bootstrap interval (seeds
        resampled per group)."""
        return difference_ci(baseline, cell, seed=seed)

    def decide(self, ci: Interval) -> str:
        raise NotImplementedError

    def describe(self) -> str:
        raise NotImplementedError

    @property
    def band(self) -> tuple[float, float] | None:
        """The band a figure shades for this rule (as fractions), or None."""
        return None


@dataclasses.dataclass(frozen=True)
class Above(Rule):
    """Supported if the interval of ``baseline - cell`` lies above ``bound``, contradicted if
    it lies below it."""

    bound: float = 0.0

    def decide(self, ci: Interval) -> str:
        if ci.low > self.bound:
            return SUPPORTED
        return CONTRADICTED if ci.high < self.bound else NOT_SUPPORTED

    def describe(self) -> str:
        return f"supported if the 95% interval lies above {100 * self.bound:g}"


@dataclasses.dataclass(frozen=True)
class Within(Rule):
    """No effect: supported if the interval of ``baseline - cell`` lies within
    ``+-margin``, contradicted if it excludes 0."""

    margin: float

    def decide(self, ci: Interval) -> str:
        if -self.margin <= ci.low and ci.high <= self.margin:
            return SUPPORTED
        return CONTRADICTED if ci.low > 0 or ci.high < 0 else NOT_SUPPORTED

    def describe(self) -> str:
        return f"supported if the interval lies within +-{100 * self.margin:.0f} pp"

    @property
    def band(self) -> tuple[float, float]:
        return (-self.margin, self.margin)


@dataclasses.dataclass(frozen=True)
class ShareAbove(Rule):
    """The share of the baseline's failures gone in the cell (paired seeds), supported if
    its interval lies above ``share``, contradicted if below."""

    share: float
    unit = "%"

    def statistic(self, baseline: np.ndarray, cell: np.ndarray, seed: int = 0) -> Interval:
        return removed_share_ci(1 - cell, 1 - baseline, paired=True, seed=seed)

    def decide(self, ci: Interval) -> str:
        if ci.low > self.share:
            return SUPPORTED
        return CONTRADICTED if ci.high < self.share else NOT_SUPPORTED

    def describe(self) -> str:
        return f"supported if its interval lies above {self.share:.0%}"


@dataclasses.dataclass(frozen=True)
class Claim:
    """A claim of the paper and how a design tests it.

    Attributes:
      key: Identifier (the cells' ``claim``).
      words: The paper's words.
      source: Where the paper says it.
      compares: What is compared, in words (the rule's wording follows it).
      rule: The :class:`Rule` of every comparison.
      cells: ``{world: (cell keys)}``: the comparisons (each cell against its baseline). In
        a world with several, the claim is supported there only if every comparison
        supports it, and contradicted if any contradicts it.
    """

    key: str
    words: str
    source: str
    compares: str
    rule: Rule
    cells: Mapping[str, tuple[str, ...]]

    @property
    def test(self) -> str:
        """How the claim is tested: the comparison, then the rule."""
        return f"{self.compares}: {self.rule.describe()}"

    def interval(self, results, key: str, seed: int = 0) -> Interval:
        """The statistic of cell ``key`` against its baseline in ``results``."""
        baseline = results.cell(key).baseline
        return self.rule.statistic(results.score(baseline), results.score(key), seed=seed)

    def evidence(self, results, key: str) -> str:
        """The comparison's number with its interval, as text."""
        ci = self.interval(results, key)
        if isinstance(self.rule, ShareAbove):
            return f"{ci.format(unit='%')} of the failures go"
        return f"{ci.format(unit=' pp')} vs {key}"

    def verdict(self, results) -> tuple[str, dict[str, str], list[str]]:
        """The overall verdict, the verdict per world, and the evidence (per comparison)."""
        per_world, evidence = {}, []
        for world, keys in self.cells.items():
            found = [self.rule.decide(self.interval(results, key)) for key in keys]
            if all(v == SUPPORTED for v in found):
                per_world[world] = SUPPORTED
            elif CONTRADICTED in found:
                per_world[world] = CONTRADICTED
            else:
                per_world[world] = NOT_SUPPORTED
            evidence += [f"{world}: {self.evidence(results, key)}" for key in keys]
        return overall(per_world), per_world, evidence

    def row(self, results) -> str:
        """The claim's row of a verdict table (Markdown)."""
        verdict, _, evidence = self.verdict(results)
        return f"| {self.words} ({self.source}) | {verdict} | {'; '.join(evidence)} |"


def overall(verdicts: dict[str, str]) -> str:
    """One verdict from the per-world verdicts ``{world: verdict}``: the common one, or
    "supported only in the ... world" when they differ."""
    values = set(verdicts.values())
    if len(values) == 1:
        return values.pop()
    where = [w for w, v in verdicts.items() if v == SUPPORTED]
    if where:
        return f"supported only in the {' and '.join(where)} world"
    return "; ".join(f"{v} ({w} world)" for w, v in verdicts.items())


def verdict_table(claims, results) -> str:
    """The Markdown table of ``claims``, their verdicts and the numbers behind them."""
    header = "| claim, in the paper's words | verdict | the number (95% interval) |\n|---|---|---|"
    return header + "\n" + "\n".join(c.row(results) for c in claims)


def claim_of(claims, key: str) -> Claim:
    """The claim ``key`` of ``claims``."""
    for c in claims:
        if c.key == key:
            return c
    raise KeyError(f"no claim {key!r} ({', '.join(c.key for c in claims)})")
