"""The report of the untested claims (:mod:`docking.study.designs.untested`, notebook 08):
the claims of theirs that join the README's verdicts, and their sentence.
"""

from __future__ import annotations

from docking.study.designs.third_edition_report import claims_summary

#: The claims of the untested claims' design (notebook 08) that join the README's verdict
#: table: relocation and coping with change, the paper's claims of Sec. IV.
UNTESTED_IN_README = ("relocation", "coping")


def untested_summary(results) -> str:
    """The README's paragraph on the claims nobody had tested (notebook 08): the judged part
    of their design (``untested.part("judged")``'s ``results``), in :func:`claims_summary`'s
    sentences, under both decision rules."""
    from docking.study.claims import judge_family

    design = results.design
    decisions = judge_family(design.claims, results, alpha=design.alpha, per_claim=True)
    return (
        "**The claims nobody had tested** (notebook 08: fresh seeds, its own rules committed "
        "before the runs; relocation and coping among the claims below, continuous "
        "actions as the paper's future work). "
        + claims_summary(design.claims, decisions, design.alpha)
    )
