"""Claims as objects: which cells a claim compares, by which rule, and what that rule says.

A :class:`Claim` names the paper's words, the comparisons that test them (per world, cells
against their baselines) and one :class:`Rule`. The rule computes the statistic of a
comparison with its interval (:mod:`docking.study.stats`), decides it (``"supported"``,
``"not supported"``: the interval does not decide, ``"contradicted"``: it lies on the other
side) and renders its own wording, colour and band; notebooks, the README and the forest plot
all ask the rule, so a rule lives in one place.

Rules:

* :class:`Above`: the baseline minus the cell (percentage points of success) lies above a
  bound (0: the baseline is better).
* :class:`Equivalent`: the difference lies within +-margin (no effect), contradicted only if
  it lies wholly outside the margin.
* :class:`ShareAbove`: the share of the baseline's failures that are gone in the cell lies
  above a share (e.g. 0.5: "most").
* :class:`Gap`: a change costs a reference learner more than this one: ``(reference's
  baseline - reference) - (baseline - cell)`` lies above 0.

Each rule computes its interval by the first edition's percentile bootstrap
(``method="bootstrap"``), by Welch's Student-t (``method="t"``, the second edition's) or by
the paired Student-t over seeds (``method="paired"``, for arms that share each seed's
networks or held-out streams); ``tools/interval_coverage.py`` checks the intervals'
coverage. A family of claims is
judged together by :func:`judge_family`: a p-value per comparison, Holm's adjustment over
the family, and "at the bound" where a deciding interval ends within 1 pp of the rule's
bound. A comparison with no spread over seeds (a Student-t interval of no width) is decided
by the rules' convention (p = 0 where its estimate lies off the bound, the side it lies on),
and its tables say what it is (:func:`spread_words`: "identical in every trial", ...)
instead of a p-value.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping

import numpy as np

from docking.study.stats import (
    Interval,
    difference_ci,
    holm,
    rate_ci,
    removed_share_ci,
    t_difference_ci,
    t_interaction_ci,
    t_paired_ci,
    t_paired_interaction_ci,
    t_share_ci,
)

__all__ = [
    "AtMost",
    "SUPPORTED",
    "NOT_SUPPORTED",
    "CONTRADICTED",
    "VERDICT_COLOURS",
    "Above",
    "Claim",
    "Equivalent",
    "Rule",
    "ShareAbove",
    "design_verdicts",
    "judge_family",
    "one_family",
    "overall",
    "p_text",
    "rate_interval",
    "spread_words",
    "verdicts_table",
]

SUPPORTED, NOT_SUPPORTED, CONTRADICTED = "supported", "not supported", "contradicted"
AT_BOUND = "at the bound"
NOT_JUDGED = "not judged"

#: How near a deciding interval's end may come to a rule's bound before the verdict is "at
#: the bound" instead of decided (a fraction: 1 percentage point).
NEAR_BOUND = 0.01

#: The colour of each verdict in figures (matplotlib colours).
VERDICT_COLOURS = {
    SUPPORTED: "C2",
    NOT_SUPPORTED: "0.45",
    CONTRADICTED: "C3",
    AT_BOUND: "C1",
    NOT_JUDGED: "0.75",
}


class Rule:
    """How a comparison is measured and decided (subclasses below)."""

    #: Whether the statistic is a difference of success (pp) or a share of failures (%).
    unit = " pp"
    method = "bootstrap"

    def statistic(self, baseline: np.ndarray, cell: np.ndarray, seed: int = 0) -> Interval:
        """``baseline - cell`` of per-seed values, with its interval (bootstrap: seeds
        resampled per group; t: Welch; paired: Student-t on the per-seed differences, for arms
        that share each seed's networks or held-out streams)."""
        if self.method == "paired":
            return t_paired_ci(baseline, cell)
        if self.method == "t":
            return t_difference_ci(baseline, cell)
        return difference_ci(baseline, cell, seed=seed)

    def interval(self, results, pair: tuple[str, ...], measure, seed: int = 0) -> Interval:
        """The statistic of the comparison ``pair`` = ``(cell, baseline)``;
        ``measure(results, key)`` gives per-seed values."""
        key, baseline = pair[:2]
        return self.statistic(measure(results, baseline), measure(results, key), seed=seed)

    def bound(self) -> float:
        """The value the statistic is judged against."""
        return 0.0

    def p_side(self, ci: Interval) -> tuple[float, str]:
        """The p-value of the comparison and the verdict it would decide (Student-t
        intervals): two-sided against :meth:`bound`."""
        b = self.bound()
        return ci.p_value(b), SUPPORTED if ci.estimate > b else CONTRADICTED

    def near_bound(self, ci: Interval, verdict: str) -> bool:
        """Whether the end of ``ci`` that decides ``verdict`` lies within
        :data:`NEAR_BOUND` of the bound."""
        end = ci.low if verdict == SUPPORTED else ci.high
        return abs(end - self.bound()) < NEAR_BOUND

    def decide(self, ci: Interval) -> str:
        """Supported if ``ci`` lies above the bound, contradicted if below, else not
        supported."""
        b = self.bound()
        if ci.low > b:
            return SUPPORTED
        return CONTRADICTED if ci.high < b else NOT_SUPPORTED

    def describe(self) -> str:
        raise NotImplementedError

    def axis(self, what: str) -> str:
        """The statistic of ``what`` (the measure in words), for an axis."""
        return f"difference of {what}"

    @property
    def band(self) -> tuple[float, float] | None:
        """The band a figure shades for this rule (as fractions), or None."""
        return None


@dataclasses.dataclass(frozen=True)
class Above(Rule):
    """Supported if the interval of ``baseline - cell`` lies above ``bound``, contradicted if
    it lies below it."""

    at: float = 0.0
    method: str = "bootstrap"

    def bound(self) -> float:
        return self.at

    def describe(self) -> str:
        return f"supported if the 95% interval lies above {100 * self.at:g}"


@dataclasses.dataclass(frozen=True)
class Equivalent(Rule):
    """No effect, judged against a margin: supported if the interval of ``baseline - cell``
    lies within ``+-margin``, contradicted only if it lies wholly outside it (an effect
    larger than the margin), else not supported."""

    margin: float
    method: str = "paired"

    def decide(self, ci: Interval) -> str:
        if -self.margin <= ci.low and ci.high <= self.margin:
            return SUPPORTED
        return CONTRADICTED if ci.low > self.margin or ci.high < -self.margin else NOT_SUPPORTED

    def describe(self) -> str:
        return (
            f"supported if the interval lies within +-{100 * self.margin:.0f} pp, "
            f"contradicted if it lies wholly outside"
        )

    def equivalence_p(self, ci: Interval) -> float:
        """The p-value of equivalence: two one-sided Student-t tests against +-margin."""
        from scipy import stats

        lower = stats.t.sf((ci.estimate + self.margin) / ci.se, ci.df)
        upper = stats.t.cdf((ci.estimate - self.margin) / ci.se, ci.df)
        return float(max(lower, upper))

    def against_p(self, ci: Interval) -> float:
        """The p-value of an effect beyond the margin (one-sided, on the estimate's side):
        what contradicts "no effect" under this rule."""
        from scipy import stats

        return float(stats.t.sf((abs(ci.estimate) - self.margin) / ci.se, ci.df))

    def p_side(self, ci: Interval) -> tuple[float, str]:
        """Equivalence (two one-sided tests against +-margin) or an effect beyond it,
        whichever the data favour; the smaller p-value doubled (two tests per comparison)."""
        if ci.se == 0:
            inside = -self.margin < ci.estimate < self.margin
            return 0.0, SUPPORTED if inside else CONTRADICTED
        equivalence, against = self.equivalence_p(ci), self.against_p(ci)
        if equivalence <= against:
            return min(1.0, 2 * equivalence), SUPPORTED
        return min(1.0, 2 * against), CONTRADICTED

    def near_bound(self, ci: Interval, verdict: str) -> bool:
        ends = (abs(abs(ci.low) - self.margin), abs(abs(ci.high) - self.margin))
        return min(ends) < NEAR_BOUND

    @property
    def band(self) -> tuple[float, float]:
        return (-self.margin, self.margin)


@dataclasses.dataclass(frozen=True)
class ShareAbove(Rule):
    """The share of the baseline's failures gone in the cell (paired seeds), supported if
    its interval lies above ``share``, contradicted if below."""

    share: float
    method: str = "bootstrap"
    unit = "%"

    def bound(self) -> float:
        return self.share

    def statistic(self, baseline: np.ndarray, cell: np.ndarray, seed: int = 0) -> Interval:
        if self.method == "t":
            return t_share_ci(1 - cell, 1 - baseline)
        return removed_share_ci(1 - cell, 1 - baseline, paired=True, seed=seed)

    def describe(self) -> str:
        return f"supported if its interval lies above {self.share:.0%}"


@dataclasses.dataclass(frozen=True)
class Gap(Rule):
    """A change costs a reference learner more than this one: a comparison is
    ``(cell, baseline, reference_baseline, reference_cell)`` and the statistic is
    ``(mean(reference_baseline) - mean(reference_cell)) - (mean(baseline) - mean(cell))``
    (``method="t"``: Welch's t over four groups of seeds; ``"paired"``: the Student-t interval
    of the per-seed values, the four arms sharing each seed), supported if its interval lies
    above 0."""

    method: str = "t"

    def interval(self, results, pair: tuple[str, ...], measure, seed: int = 0) -> Interval:
        key, baseline, reference_baseline, reference_cell = pair
        arms = (
            measure(results, reference_baseline),
            measure(results, reference_cell),
            measure(results, baseline),
            measure(results, key),
        )
        if self.method == "paired":
            return t_paired_interaction_ci(*arms)
        return t_interaction_ci(*arms)

    def describe(self) -> str:
        return (
            "supported if the interval of (the reference's loss) - (this learner's loss) "
            "lies above 0"
        )


@dataclasses.dataclass(frozen=True)
class AtMost(Rule):
    """The cell's value is at most ``fraction`` of its baseline's (e.g. re-learning takes at
    most half the trials a fresh learner takes): supported if the paired interval of
    ``fraction * baseline - cell`` lies above 0, contradicted if below."""

    fraction: float
    method: str = "paired"

    def statistic(self, baseline: np.ndarray, cell: np.ndarray, seed: int = 0) -> Interval:
        return t_paired_ci(self.fraction * np.asarray(baseline), cell)

    def describe(self) -> str:
        return f"supported if the interval of {self.fraction:g} x baseline - cell lies above 0"

    def axis(self, what: str) -> str:
        return f"{self.fraction:g} x the baseline's {what} minus the cell's"


def measure_display(measure) -> tuple[str, int, str]:
    """How a claim's measure is shown: its unit's text, its decimals and its name on an axis
    (set by :func:`docking.study.designs.measures._unit`); a measure without them: no unit, three
    decimals, its function's name."""
    unit, digits = getattr(measure, "unit", ("", 3))
    return unit, digits, getattr(measure, "label", measure.__name__)


def success(results, key: str) -> np.ndarray:
    """Per seed, the measured success of cell ``key`` (the default measure of a claim)."""
    return results.score(key)


def rate_interval(results, key: str) -> Interval:
    """The measured success of cell ``key`` over its seeds, pooled over their trials, with
    the 95% interval for a rate (:func:`docking.study.stats.rate_ci`: in [0, 1], and of some width
    when every trial succeeds): what tables show of a success rate."""
    return rate_ci(results.score(key), [len(log.success) for log in results.logs[key]])


@dataclasses.dataclass(frozen=True)
class Claim:
    """A claim of the paper and how a design tests it.

    Attributes:
      key: Identifier (the cells' ``claim``).
      words: The paper's words.
      source: Where the paper says it.
      compares: What is compared, in words (the rule's wording follows it).
      rule: The :class:`Rule` of every comparison.
      cells: ``{world: comparisons}``: each a cell key (compared with the cell's baseline)
        or a tuple ``(cell, baseline, ...)`` (more keys for rules that need them,
        :class:`Gap`). In a world with several, the claim is supported there only if every
        comparison supports it, and contradicted if any contradicts it.
      measure: ``measure(results, key) -> per-seed values`` (default: measured success).
      judged: False for a finding that is reported with its numbers but is not a verdict
        (not in the family of :func:`judge_family`).
      min_baseline: A comparison is judged only where its baseline's mean measured success
        is at least this (e.g. rotation, judged only where the learner docks often enough
        for its failures to say something); elsewhere it is "not judged". None: always.
    """

    key: str
    words: str
    source: str
    compares: str
    rule: Rule
    cells: Mapping[str, tuple[str, ...]]
    measure: Callable = success
    judged: bool = True
    min_baseline: float | None = None

    def gated(self, results, entry) -> bool:
        """Whether comparison ``entry`` falls outside the claim's gate
        (:attr:`min_baseline`): its baseline docks less often than the gate asks."""
        if self.min_baseline is None:
            return False
        return float(np.mean(results.score(pair_of(results, entry)[1]))) < self.min_baseline

    @property
    def test(self) -> str:
        """How the claim is tested: the comparison, then the rule."""
        return f"{self.compares}: {self.rule.describe()}"

    def interval(self, results, entry, seed: int = 0) -> Interval:
        """The statistic of the comparison ``entry`` (a cell key, or a tuple, see
        :attr:`cells`) in ``results``."""
        return self.rule.interval(results, pair_of(results, entry), self.measure, seed=seed)

    def format(self, ci: Interval) -> str:
        """An interval of this claim's statistic as text: percentage points of success, a
        per cent share of failures, or (for a measure other than success) the raw
        difference in the measure's ``unit`` (its text and decimals; none: three decimals)."""
        if self.measure is not success:
            unit, digits, _ = measure_display(self.measure)
            return ci.format(scale=1.0, unit=unit, digits=digits)
        return ci.format(unit="%" if isinstance(self.rule, ShareAbove) else " pp")


def pair_of(results, entry) -> tuple[str, ...]:
    """A claim's comparison as ``(cell, baseline, ...)``: a bare cell key is compared with
    the cell's baseline."""
    if isinstance(entry, str):
        baseline = results.cell(entry).baseline
        if baseline is None:
            raise ValueError(f"cell {entry!r} has no baseline to be compared with")
        return (entry, baseline)
    return tuple(entry)


def overall(verdicts: dict[str, str]) -> str:
    """One verdict from the per-world verdicts ``{world: verdict}``: the common one;
    "supported only in the ... world" when the others are not supported; else each verdict
    with its worlds ("contradicted in floor; not supported in sideboard")."""
    values = set(verdicts.values())
    if len(values) == 1:
        return values.pop()
    if values == {SUPPORTED, NOT_SUPPORTED}:
        where = [w for w, v in verdicts.items() if v == SUPPORTED]
        return f"supported only in the {' and '.join(where)} world"
    groups: dict[str, list[str]] = {}
    for world, verdict in verdicts.items():
        groups.setdefault(verdict, []).append(world)
    return "; ".join(f"{v} in {' / '.join(ws)}" for v, ws in groups.items())


@dataclasses.dataclass(frozen=True)
class Decision:
    """One comparison of a family: its claim, world and cell, the interval, the p-value,
    Holm's adjusted p-value over the family, and the verdict."""

    claim: str
    world: str
    key: str
    interval: Interval
    p: float
    p_adjusted: float
    verdict: str


def judge_family(claims, results, alpha: float = 0.05, per_claim: bool = False) -> list[Decision]:
    """Judge every comparison of the ``judged`` claims: each rule's p-value (Student-t
    intervals), Holm's adjustment over all of them as one family, or with ``per_claim`` over
    each claim's own comparisons; a comparison whose adjusted p-value is below ``alpha`` gets
    the verdict its side decides, else "not supported"; a decided comparison whose deciding
    interval end lies within :data:`NEAR_BOUND` of the bound is "at the bound" instead. A
    comparison outside its claim's gate (:meth:`Claim.gated`) is "not judged" and leaves the
    family."""
    found, skipped = [], []
    for claim in claims:
        if not claim.judged:
            continue
        for world, keys in claim.cells.items():
            for entry in keys:
                ci = claim.interval(results, entry)
                p, side = claim.rule.p_side(ci)
                row = (claim, world, pair_of(results, entry)[0], ci, p, side)
                (skipped if claim.gated(results, entry) else found).append(row)
    groups = [[f for f in found if f[0] is c] for c in claims] if per_claim else [found]
    adjusted = {}
    for group in groups:
        if group:
            adjusted.update(zip(map(id, group), holm([f[4] for f in group]), strict=True))
    decisions = []
    for row in found + skipped:
        claim, world, key, ci, p, side = row
        if id(row) not in adjusted:
            decisions.append(Decision(claim.key, world, key, ci, p, float("nan"), NOT_JUDGED))
            continue
        p_adj = adjusted[id(row)]
        verdict = side if p_adj < alpha else NOT_SUPPORTED
        if verdict != NOT_SUPPORTED and claim.rule.near_bound(ci, verdict):
            verdict = AT_BOUND
        decisions.append(Decision(claim.key, world, key, ci, p, float(p_adj), verdict))
    rows = zip(found + skipped, decisions, strict=True)
    keyed = sorted(rows, key=lambda x: _position(claims, x[0]))
    return [d for _, d in keyed]


def _position(claims, row) -> tuple[int, int]:
    """A decision's place: its claim's, then its comparison's within the claim."""
    claim, world = row[0], row[1]
    return (list(claims).index(claim), list(claim.cells).index(world))


def one_family(claims, decisions: list[Decision], alpha: float) -> list[Decision]:
    """``decisions`` (:func:`judge_family`'s, within each claim or not) judged again as one
    family of every comparison, from their own p-values and intervals: what
    ``judge_family(claims, results, alpha)`` decides, without the results."""
    rules = {c.key: c.rule for c in claims}
    judged = [d for d in decisions if d.verdict != NOT_JUDGED]
    adjusted = dict(zip(map(id, judged), holm([d.p for d in judged]), strict=True))
    found = []
    for d in decisions:
        if id(d) not in adjusted:
            found.append(d)
            continue
        rule, p_adj = rules[d.claim], float(adjusted[id(d)])
        verdict = rule.p_side(d.interval)[1] if p_adj < alpha else NOT_SUPPORTED
        if verdict != NOT_SUPPORTED and rule.near_bound(d.interval, verdict):
            verdict = AT_BOUND
        found.append(dataclasses.replace(d, p_adjusted=p_adj, verdict=verdict))
    return found


def family_verdicts(claims, decisions: list[Decision]) -> dict[str, tuple[str, dict[str, str]]]:
    """Per judged claim: the overall verdict and the verdict per world, from the family's
    decisions (in a world: supported if every comparison is, contradicted if any is, at the
    bound if any is and none is contradicted, else not supported)."""
    out = {}
    for claim in claims:
        if not claim.judged:
            continue
        per_world = {}
        for world in claim.cells:
            found = [d.verdict for d in decisions if d.claim == claim.key and d.world == world]
            if all(v == SUPPORTED for v in found):
                per_world[world] = SUPPORTED
            elif CONTRADICTED in found:
                per_world[world] = CONTRADICTED
            elif all(v == NOT_JUDGED for v in found):
                per_world[world] = NOT_JUDGED
            elif AT_BOUND in found:
                per_world[world] = AT_BOUND
            else:
                per_world[world] = NOT_SUPPORTED
        out[claim.key] = (overall(per_world), per_world)
    return out


def markdown_cell(text: str) -> str:
    """``text`` for a cell of a Markdown table: its pipes escaped, so that one such as
    "|heading error|" does not split the row."""
    return text.replace("|", "\\|")


def _labels(results, world: str, entries) -> list[str]:
    """A label per comparison of one world: the world, and where the world has several
    comparisons, what tells them apart (the variant part of the cell keys that differ)."""
    if len(entries) == 1:
        return [world]
    pairs = [pair_of(results, e) for e in entries]
    differ = [i for i in range(len(pairs[0])) if len({p[i] for p in pairs}) > 1]
    return [f"{world}: {'/'.join(p[i].rsplit('/', 1)[-1] for i in differ)}" for p in pairs]


def claim_rows(claims, results, decisions) -> list:
    """Per claim, ``(claim, [(label, interval, verdict, Holm p), ...])``: a judged claim's
    comparisons with their decisions in ``decisions``, a finding's with ``"finding"`` (and
    no p); each labelled by its world."""
    found = []
    for claim in claims:
        rows = []
        for world, keys in claim.cells.items():
            for entry, label in zip(keys, _labels(results, world, keys), strict=True):
                ci, key = claim.interval(results, entry), pair_of(results, entry)[0]
                verdict, p = "finding", None
                if claim.judged:
                    (d,) = [
                        d
                        for d in decisions
                        if d.claim == claim.key and d.world == world and d.key == key
                    ]
                    verdict, p = d.verdict, d.p_adjusted
                rows.append((label, ci, verdict, p))
        found.append((claim, rows))
    return found


def p_text(p: float, alpha: float) -> str:
    """``p`` to two significant digits, or as many more as keep it on its side of
    ``alpha`` (0.04997 at 0.05 is "0.04997", not "0.05")."""
    for digits in range(2, 8):
        text = f"{p:.{digits}g}"
        if (float(text) < alpha) == (p < alpha):
            break
    return text


def spread_words(ci: Interval, identical: str | None = None) -> str | None:
    """What a table shows instead of the p-value of a Student-t interval with no spread over
    seeds (``se == 0``: its p-value, 0 or 1, is the rules' convention, which decides the
    comparison but is no evidence; "p 0" would read as certainty): "identical in every
    trial" or "identical in every seed" where the compared arms are (``identical``:
    ``"trial"`` or ``"seed"``), else "the same in every seed" (every seed's statistic
    equal). None for an interval with a spread, or not a Student-t interval."""
    if ci.se is None or ci.se > 0:
        return None
    if identical is not None:
        return f"identical in every {identical}"
    return "the same in every seed"


def _identical(claim: Claim, results, entry) -> str | None:
    """Whether the two arms of comparison ``entry`` are identical: ``"trial"`` (success,
    each seed's trial outcomes equal, where the results hold the trials), ``"seed"`` (the
    measure's per-seed values equal), or None (they differ, or more than two arms)."""
    pair = pair_of(results, entry)
    if len(pair) != 2:
        return None
    arms = [np.asarray(claim.measure(results, k)) for k in pair]
    if not np.array_equal(*arms):
        return None
    logs = getattr(results, "logs", None)
    if claim.measure is not success or logs is None or not all(k in logs for k in pair):
        return "seed"
    a, b = (logs[k] for k in pair)
    trials = len(a) == len(b) and all(
        np.array_equal(x.success, y.success) for x, y in zip(a, b, strict=True)
    )
    return "trial" if trials else "seed"


def _evidence(claim: Claim, results, entry, ci: Interval, p, alpha: float) -> str:
    """A judged comparison's p-value as its table shows it (", p 0.0012"), or what it is
    where it has no spread over seeds (:func:`spread_words`); nothing for a finding's."""
    if p is None or not np.isfinite(p):
        return ""
    words = (
        None if ci.se is None or ci.se > 0 else spread_words(ci, _identical(claim, results, entry))
    )
    return f", {words}" if words else f", p {p_text(p, alpha)}"


def _header(alpha: float) -> list[str]:
    return [
        f"| the paper's words (section) | compared | per comparison: 95% interval, Holm p -> "
        f"decision (Holm within the claim, {alpha:g}) | verdict | verdict, one family |",
        "|---|---|---|---|---|",
    ]


def verdicts_table(claims, results, per_claim, family, alpha: float, notes=None) -> str:
    """The verdict table of claims judged both ways: per claim, the paper's words and
    section, what is compared, each comparison's paired interval (95%, unadjusted) with its
    Holm-adjusted p-value (or, where it has no spread over seeds, :func:`spread_words`) and
    its decision under Holm within the claim (``per_claim``, the decision rule), and the
    verdict under one family of every comparison (``family``), at ``alpha``; a finding's
    intervals, not judged. ``notes``: ``{claim key: why}`` for a claim whose verdict is
    reported outside every count (e.g. a test that holds by construction): its verdicts
    carry the note."""
    within, overall_ = family_verdicts(claims, per_claim), family_verdicts(claims, family)
    lines = _header(alpha)
    for claim, rows in claim_rows(claims, results, per_claim):
        entries = [e for keys in claim.cells.values() for e in keys]  # claim_rows' order
        evidence = "<br>".join(
            f"{w}: {claim.format(ci)}{_evidence(claim, results, e, ci, p, alpha)} -> {v}"
            for (w, ci, v, p), e in zip(rows, entries, strict=True)
        )
        verdicts = (
            (within[claim.key][0], overall_[claim.key][0])
            if claim.judged
            else ("finding", "finding")
        )
        if notes and claim.key in notes:
            verdicts = tuple(f"{v}, {notes[claim.key]}: outside the counts" for v in verdicts)
        words, compares = markdown_cell(claim.words), markdown_cell(claim.compares)
        lines.append(
            f"| **{claim.key}**: {words} ({claim.source}) | {compares} | "
            f"{evidence} | {verdicts[0]} | {verdicts[1]} |"
        )
    return "\n".join(lines)


def design_verdicts(*judged, notes=None) -> str:
    """The verdict table (:func:`verdicts_table`) of one or more designs, under the sentence
    that names the decision rule: ``judged`` is ``results`` (every claim of its design) or
    ``(results, keys)`` (the claims named), each design's rows judged within its own claims
    and its own family; ``notes`` as :func:`verdicts_table`'s."""
    rows, alphas = [], set()
    for entry in judged:
        results, keys = entry if isinstance(entry, tuple) else (entry, None)
        design = results.design
        alphas.add(design.alpha)
        family = judge_family(design.claims, results, alpha=design.alpha)
        per = judge_family(design.claims, results, alpha=design.alpha, per_claim=True)
        claims = [c for c in design.claims if keys is None or c.key in keys]
        table = verdicts_table(claims, results, per, family, design.alpha, notes)
        rows += table.splitlines()[2:]
    if len(alphas) != 1:
        raise ValueError(f"design_verdicts: the designs judge at different levels {alphas}")
    (alpha,) = alphas
    return (
        "Decision rule, committed before the runs: Holm's adjustment within each claim over "
        f"its comparisons, at {alpha:g}, on paired Student-t intervals over seeds (p: the "
        "Holm-adjusted p-value); the last column judges the same comparisons as one family "
        "of their design's comparisons. A comparison with no spread over seeds shows what it "
        "is (identical in every trial, identical in every seed, the same in every seed) "
        "instead of a p-value; the committed rule decides it as before, by its convention for "
        "no spread (p = 0 where the estimate lies off the bound, on the side it lies on).\n\n"
        + "\n".join(_header(alpha) + rows)
    )
