"""The third edition's rules: the equivalence rule judged against its margin."""

import dataclasses

import numpy as np
import pytest

from docking.study import claims
from docking.study.designs import third_edition_report
from docking.study.stats import Interval


def _ci(low, high):
    return Interval((low + high) / 2, low, high, (), se=(high - low) / 4, df=9)


def test_equivalence_is_contradicted_only_outside_its_margin():
    rule = claims.Equivalent(0.02)
    assert rule.decide(_ci(-0.01, 0.015)) == claims.SUPPORTED
    assert rule.decide(_ci(0.023, 0.069)) == claims.CONTRADICTED  # wholly beyond +2 pp
    assert rule.decide(_ci(0.005, 0.03)) == claims.NOT_SUPPORTED  # excludes 0, not the margin
    p, side = rule.p_side(_ci(0.04, 0.08))
    assert side == claims.CONTRADICTED and p < 0.05


def test_a_paired_rule_uses_the_per_seed_differences():
    base = np.array([0.9, 0.8, 0.95, 0.7, 0.85, 0.75, 0.9, 0.8, 0.92, 0.88])
    cell = base - 0.03 + np.linspace(-0.005, 0.005, 10)
    paired = claims.Above(0.0, method="paired").statistic(base, cell)
    welch = claims.Above(0.0, method="t").statistic(base, cell)
    assert paired.low > 0 > welch.low  # the same seeds' arms: pairing decides
    assert claims.Above(0.0, method="paired").decide(paired) == claims.SUPPORTED


class _Results:
    """Per-seed scores by cell key, with baselines: what the claims read of a design's
    results."""

    def __init__(self, scores, baselines):
        self._scores, self._baselines = scores, baselines

    def score(self, key):
        return np.asarray(self._scores[key], dtype=float)

    def cell(self, key):
        return type("C", (), {"baseline": self._baselines.get(key)})()


def _seeds(mean, n=10, spread=0.01):
    return mean + np.linspace(-spread, spread, n)


def test_a_paired_gap_uses_each_seeds_four_arms():
    rng = np.random.default_rng(1)
    level = rng.uniform(0.5, 0.95, 10)  # seeds differ a lot; their arms move together
    arms = {"cell": level - 0.01, "paper": level, "ref": level, "ref-cell": level - 0.05}
    results = _Results(arms, {})
    entry = ("cell", "paper", "ref", "ref-cell")
    paired = claims.Gap(method="paired").interval(results, entry, claims.success)
    welch = claims.Gap(method="t").interval(results, entry, claims.success)
    assert abs(paired.estimate - 0.04) < 1e-12 and abs(welch.estimate - 0.04) < 1e-12
    assert paired.low > 0 > welch.low


def test_holm_per_claim_and_one_family_and_the_gate():
    scores = {"a": _seeds(0.9), "a0": _seeds(0.86), "b": _seeds(0.9), "b0": _seeds(0.7)}
    scores.update({"c": _seeds(0.5, spread=0.1), "c0": _seeds(0.5, spread=0.1) - 0.02})
    results = _Results(scores, {"a0": "a", "b0": "b", "c0": "c"})
    rule = claims.Above(0.0, method="paired")
    one = claims.Claim("one", "w", "s", "x", rule, {"w1": ("a0",), "w2": ("b0",)})
    gated = claims.Claim("gated", "w", "s", "x", rule, {"w": ("c0",)}, min_baseline=0.8)
    two = claims.Claim("two", "w", "s", "x", rule, {"w1": ("b0",)})
    per = claims.judge_family([one, gated, two], results, per_claim=True)
    family = claims.judge_family([one, gated, two], results)
    assert [d.claim for d in per] == ["one", "one", "gated", "two"]
    assert per[-1].p_adjusted == per[-1].p  # alone in its claim: no adjustment
    assert family[-1].p_adjusted > per[-1].p  # one family of three comparisons
    per = per[:3]
    assert per[-1].verdict == claims.NOT_JUDGED and np.isnan(per[-1].p_adjusted)
    # Holm over the claim's two comparisons, not over a family that excludes the gated one
    p = sorted(d.p for d in per[:2])
    assert sorted(d.p_adjusted for d in per[:2]) == [2 * p[0], max(2 * p[0], p[1])]
    verdicts = claims.family_verdicts([one, gated], per)
    assert verdicts["gated"] == (claims.NOT_JUDGED, {"w": claims.NOT_JUDGED})


def test_the_verdict_table_and_figure_show_both_decisions_and_the_findings():
    from docking.study import figures

    scores = {"a": _seeds(0.9), "a0": _seeds(0.8), "b": _seeds(0.9), "b0": _seeds(0.9)}
    results = _Results(scores, {"a0": "a", "b0": "b"})
    rule = claims.Above(0.0, method="paired")
    one = claims.Claim("one", "the first words", "Sec. I", "a minus a0", rule, {"w1": ("a0",)})
    two = claims.Claim("two", "more words", "Sec. II", "b minus b0", rule, {"w1": ("b0",)})
    finding = claims.Claim("f", "(finding) could", "Sec. V", "a minus b0", rule, {"w": ("b0",)})
    finding = dataclasses.replace(finding, judged=False)
    found = [one, two, finding]
    per = claims.judge_family(found, results, per_claim=True)
    family = claims.judge_family(found, results)
    table = claims.verdicts_table(found, results, per, family, 0.05).splitlines()
    assert len(table) == 2 + 3  # header, rule, a row per claim
    # each judged comparison with its Holm-adjusted p-value, a finding without one; one
    # that is 10 pp in every seed (no spread) says so instead of "p 0", decided as before
    assert per[0].p_adjusted == 0 and per[0].verdict == claims.SUPPORTED
    same = "w1: 10.0 pp [10.0, 10.0], the same in every seed -> supported | supported |"
    assert same in table[2] and ", p 0 " not in "\n".join(table)
    # equal arms: p 1 by the convention, "identical in every seed" in the table
    assert per[1].p_adjusted == 1 and per[1].verdict == claims.NOT_SUPPORTED
    equal = "w1: 0.0 pp [0.0, 0.0], identical in every seed -> not supported | not supported |"
    assert equal in table[3]
    assert "w: 0.0 pp [0.0, 0.0] -> finding | finding | finding |" in table[4]
    panels = third_edition_report.verdict_panels(found, results, per)
    assert [len(p["rows"]) for p in panels] == [1, 1, 1]
    assert panels[0]["rows"][0][2] == claims.SUPPORTED and panels[0]["scale"] == 100.0
    assert "not judged" in panels[2]["title"]
    fig = figures.fig_verdicts(panels)
    assert len(fig.axes) == 3
    with pytest.raises(ValueError, match="at least one panel"):
        figures.fig_verdicts([])


def test_the_claims_sentence_counts_and_names_each_group():

    scores = {"a": _seeds(0.9), "a0": _seeds(0.8), "b": _seeds(0.9), "b0": _seeds(0.9)}
    scores.update({"c": _seeds(0.8), "c0": _seeds(0.9)})
    results = _Results(scores, {"a0": "a", "b0": "b", "c0": "c"})
    rule = claims.Above(0.0, method="paired")
    found = [
        claims.Claim("good", "w", "s", "x", rule, {"w1": ("a0",)}),
        claims.Claim("some", "w", "s", "x", rule, {"w1": ("a0",), "w2": ("b0",)}),
        claims.Claim("none", "w", "s", "x", rule, {"w1": ("b0",)}),
        claims.Claim("against", "w", "s", "x", rule, {"w1": ("c0",)}),
        dataclasses.replace(claims.Claim("f", "w", "s", "x", rule, {"w": ("a0",)}), judged=False),
    ]
    decisions = claims.judge_family(found, results, per_claim=True)
    text = third_edition_report.claims_summary(found, decisions)
    assert text == (
        "Of the paper's 4 claims judged, by the decision rule committed before the runs (Holm "
        "within each claim): 1 supported wherever judged (good); 1 supported in some worlds "
        "only (some); 1 not supported in any world (none); 1 contradicted in at least one "
        "world (against); and 1 finding, measured, not judged (f). Judged as one family of "
        "all 5 comparisons instead, the counts are the same."
    )


def test_a_pipe_in_a_claims_words_does_not_split_its_table_row():
    results = _Results({"a": _seeds(0.9), "a0": _seeds(0.8)}, {"a0": "a"})
    rule = claims.Above(0.0, method="paired")
    one = claims.Claim("one", "w", "s", "|heading error| at docking", rule, {"w1": ("a0",)})
    per = claims.judge_family([one], results, per_claim=True)
    header, _, row = claims.verdicts_table([one], results, per, per, 0.05).splitlines()
    assert row.replace("\\|", "").count("|") == header.count("|")


def test_one_verdict_table_of_two_designs_keeps_each_designs_family():
    """Rows of a second design join the first's table, each judged in its own design; only
    the claims named join; designs judged at another level are refused."""
    import types

    rule = claims.Above(0.0, method="paired")
    scores = {"a": _seeds(0.9), "a0": _seeds(0.8), "b": _seeds(0.9), "b0": _seeds(0.85)}

    def judged(name, found, alpha=0.05):
        results = _Results(scores, {"a0": "a", "b0": "b"})
        results.design = types.SimpleNamespace(name=name, claims=tuple(found), alpha=alpha)
        return results

    one = claims.Claim("one", "w", "s", "x", rule, {"w1": ("a0",)})
    two = claims.Claim("two", "w", "s", "x", rule, {"w1": ("b0",)})
    three = claims.Claim("three", "w", "s", "x", rule, {"w1": ("a0",)})
    text = claims.design_verdicts(judged("d1", [one]), (judged("d2", [two, three]), ("two",)))
    table = text.split("\n\n")[1].splitlines()
    assert len(table) == 2 + 2 and "**one**" in table[2] and "**two**" in table[3]
    assert "Holm's adjustment within each claim" in text
    with pytest.raises(ValueError, match="different levels"):
        claims.design_verdicts(judged("d1", [one]), judged("d3", [one], alpha=0.01))


def test_a_design_with_claims_needs_the_level_of_their_verdicts():
    from helpers import TINY

    from docking.study.design import Cell, Design

    one = claims.Claim("one", "w", "s", "x", claims.Above(0.0), {"w1": ("a",)})
    cells = (Cell("a", TINY, {"v": "a"}),)
    with pytest.raises(ValueError, match="has claims: give the level"):
        Design(name="no-level", title="t", cells=cells, seeds=(0,), claims=(one,))
    assert Design(name="level", title="t", cells=cells, seeds=(0,), claims=(one,), alpha=0.05)


def test_several_comparisons_of_one_world_are_labelled_by_what_tells_them_apart():

    scores = {k: _seeds(0.8) for k in ("w/paper", "w/units144", "w/units576", "v/paper")}
    scores["v/units144"] = _seeds(0.9)
    results = _Results(scores, {})
    entries = {
        "w": (("w/paper", "w/units144"), ("w/paper", "w/units576")),
        "v": (("v/paper", "v/units144"),),
    }
    finding = claims.Claim("m", "w", "s", "x", claims.Above(0.0, method="paired"), entries)
    finding = dataclasses.replace(finding, judged=False)
    (panel,) = third_edition_report.verdict_panels([finding], results, [])
    assert [r[0] for r in panel["rows"]] == ["w: units144", "w: units576", "v"]


def test_a_p_value_is_never_shown_on_the_other_side_of_the_level():
    assert claims.p_text(0.0499711, 0.05) == "0.04997"  # not "0.05", which is not below it
    assert claims.p_text(0.0500001, 0.05) == "0.05"  # not below: "0.05" says so
    assert claims.p_text(0.0012345, 0.05) == "0.0012"
    assert claims.p_text(8.2e-06, 0.05) == "8.2e-06"


class _Logged(_Results):
    """:class:`_Results` with each seed's trial outcomes (``logs``), from which the scores
    come, and its cells."""

    def __init__(self, outcomes, baselines):
        self.logs = {
            k: [type("Log", (), {"success": np.asarray(o, dtype=bool)})() for o in seeds]
            for k, seeds in outcomes.items()
        }
        scores = {k: [np.mean(log.success) for log in v] for k, v in self.logs.items()}
        super().__init__(scores, baselines)
        self.cells = [type("C", (), {"key": k})() for k in outcomes]


def test_a_comparison_without_spread_says_identical_in_every_trial_or_seed_never_p_0():
    """Arms whose every trial ends alike: "identical in every trial"; arms whose seeds dock
    equally often in other trials: "identical in every seed"; the committed convention
    (p = 0) still decides them, in both decision rules."""
    rng = np.random.default_rng(3)
    home = [rng.random(50) < 0.9 for _ in range(10)]
    shuffled = [rng.permutation(o) for o in home]  # the same count, other trials
    outcomes = {"home": home, "same": [o.copy() for o in home], "moved": shuffled}
    outcomes["worse"] = [o & (rng.random(50) < 0.8) for o in home]
    results = _Logged(outcomes, {"same": "home", "moved": "home", "worse": "home"})
    rule = claims.Equivalent(0.02)
    relocation = claims.Claim(
        "relocation", "w", "s", "x", rule, {"a": ("same",), "b": ("moved",), "c": ("worse",)}
    )
    per = claims.judge_family([relocation], results, per_claim=True)
    family = claims.judge_family([relocation], results)
    assert [d.p for d in per[:2]] == [0.0, 0.0]  # the convention, kept
    assert [d.verdict for d in per[:2]] == [claims.SUPPORTED] * 2
    assert [d.verdict for d in family] == [d.verdict for d in per]
    (row,) = claims.verdicts_table([relocation], results, per, family, 0.05).splitlines()[2:]
    assert "a: 0.0 pp [0.0, 0.0], identical in every trial -> supported" in row
    assert "b: 0.0 pp [0.0, 0.0], identical in every seed -> supported" in row
    assert f"c: {claims.Claim.format(relocation, per[2].interval)}, p " in row
    assert ", p 0 " not in row and ", p 0<" not in row


def test_spread_words_only_for_a_t_interval_without_spread():
    assert claims.spread_words(Interval(0.1, 0.05, 0.15, (), se=0.02, df=9)) is None
    assert claims.spread_words(Interval(0.1, 0.05, 0.15, ())) is None  # a bootstrap's
    point = Interval(0.0, 0.0, 0.0, (0.0, 0.0), se=0.0, df=1)
    assert claims.spread_words(point, "trial") == "identical in every trial"
    assert claims.spread_words(point) == "the same in every seed"


def _close_call():
    """Scores where one comparison ("a0", p = 0.034 alone) is decided within its claim and
    not in one family of four (Holm doubles it), beside two clear ones and a null one."""
    z = np.linspace(-1, 1, 10) / np.linspace(-1, 1, 10).std(ddof=1)
    scores = {"a": _seeds(1.0), "b": _seeds(0.9), "b0": _seeds(0.8), "c": _seeds(0.9)}
    scores.update({"a0": _seeds(1.0) - (0.3 + 0.38 * z), "c0": _seeds(0.7)})
    scores.update({"d": _seeds(0.8, spread=0.05), "d0": _seeds(0.8, spread=0.02)})
    return _Results(scores, {"a0": "a", "b0": "b", "c0": "c", "d0": "d"})


def test_one_family_from_the_decisions_is_judge_familys_one_family():
    """The one-family verdicts recomputed from the per-claim decisions (what the README's
    count needs, without the results) are judge_family's own, gate and bound included."""
    results = _close_call()
    rule = claims.Above(0.0, method="paired")
    found = [
        claims.Claim("close", "w", "s", "x", rule, {"w1": ("a0",)}),
        claims.Claim("clear", "w", "s", "x", rule, {"w1": ("b0",), "w2": ("c0",)}),
        claims.Claim("gated", "w", "s", "x", rule, {"w": ("c0",)}, min_baseline=0.95),
        claims.Claim("null", "w", "s", "x", claims.Equivalent(0.01), {"w1": ("d0",)}),
    ]
    per = claims.judge_family(found, results, per_claim=True)
    family = claims.judge_family(found, results)
    again = claims.one_family(found, per, 0.05)
    assert [d.verdict for d in again] == [d.verdict for d in family]
    assert [d.p_adjusted for d in again] == pytest.approx(
        [d.p_adjusted for d in family], nan_ok=True
    )
    assert [d.verdict for d in per] != [d.verdict for d in family]  # the rules differ here
    assert claims.NOT_JUDGED in [d.verdict for d in again]


def test_the_claims_sentence_counts_under_both_decision_rules_where_they_differ():

    results = _close_call()
    rule = claims.Above(0.0, method="paired")
    found = [
        claims.Claim("close", "w", "s", "x", rule, {"w1": ("a0",)}),
        claims.Claim("clear", "w", "s", "x", rule, {"w1": ("b0",), "w2": ("c0",)}),
        claims.Claim("null", "w", "s", "x", rule, {"w1": ("d0",)}),
    ]
    per = claims.judge_family(found, results, per_claim=True)
    family = claims.judge_family(found, results)
    assert per[0].p_adjusted < 0.05 < family[0].p_adjusted  # Holm over 4 undecides "close"
    text = third_edition_report.claims_summary(found, per)
    assert text == (
        "Of the paper's 3 claims judged, by the decision rule committed before the runs (Holm "
        "within each claim): 2 supported wherever judged (close, clear); 1 not supported in "
        "any world (null). Judged as one family of all 4 comparisons instead (the verdict "
        "table's last column): 1 supported wherever judged (clear); 2 not supported in any "
        "world (close, null)."
    )


def test_rate_tables_show_an_interval_for_a_rate():
    """The contest table and a design's summary show each cell's success with the interval
    for a rate: seeds at 100% are not "[100.0, 100.0]"; a drop the same in every seed has no
    p-value in the path table."""
    import types

    from docking.study import design

    outcomes = {"w/oracle": [np.ones(500)] * 10, "w/paper": [np.arange(500) < 450] * 4}
    outcomes["w/paper"] += [np.arange(500) < 400] * 6
    results = _Logged(outcomes, {})
    table = third_edition_report.contest_table(results, {"w": "the w world"})
    assert "| pose oracle | 10 | 100.0% [99.9, 100.0] |" in table
    assert "[100.0, 100.0]" not in table
    paper = claims.rate_interval(results, "w/paper")
    assert f"| the paper's learner, untuned | 10 | {paper.format(unit='%')} |" in table
    results.design = types.SimpleNamespace(measure="heldout", report=None, claims=())
    results.cells = [type("C", (), {"key": k, "label": k})() for k in outcomes]
    text = design.summary(results)
    assert "| w/oracle | 100.0% [99.9, 100.0] (seeds: 10) |" in text
    drop = Interval(0.0, 0.0, 0.0, (0.0, 0.0, 0.0), se=0.0, df=2)
    step = third_edition_report.PathStep("a", "b", drop, 1.0, "does not break", 0.05)
    assert "| identical in every seed | does not break |" in third_edition_report.path_table(
        [step], {"b": "x"}
    )
