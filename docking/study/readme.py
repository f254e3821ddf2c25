"""The README's own blocks: its markers (each block written between ``<!-- NAME:start -->``
and ``<!-- NAME:end -->``, :func:`update_readme`), the detailed summary (:func:`summary_text`),
the first screen's figure's name and markers (its sentences and arrays are
:mod:`docking.study.answer`'s), the findings page's markers and the paragraph of times
(:func:`timings_text`). Each sentence's numbers come from its design's report
(``docking/study/designs/<design>_report.py``); ``python -m docking report --readme README.md``
writes them.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from docking.presets import HEADLINE_SEED
from docking.study.designs.paper_report import headline
from docking.study.designs.third_edition_report import contest_summary
from docking.study.report import _pct

if TYPE_CHECKING:  # runs are read here, never made
    from docking.experiments import ExperimentResult

#: The README's generated block lies between these lines.
README_START = "<!-- results:start -->"


README_END = "<!-- results:end -->"


#: The markers of the README's summary: what the runs show, in a few paragraphs (the detail is
#: on the findings page, :data:`FINDINGS_PAGE`).
SUMMARY_START = "<!-- summary:start -->"


SUMMARY_END = "<!-- summary:end -->"


def summary_text(
    results1: list[ExperimentResult],
    results2: list[ExperimentResult],
    comparisons: list | None = None,
    oracle: float | None = None,
    contest=None,
    claims: str | None = None,
    corrected: bool = False,
) -> str:
    """The README's detailed summary (``corrected``: the contest's finding is corrected by the
    addendum's, which follows it): what was reproduced, under what choices, what held up and
    what did not, in a few sentences whose numbers come from the runs: Experiments 1 and 2
    (``results1``, ``results2``) and, if given, Experiment 3's four-against-six comparisons
    (:func:`turning_comparisons`), the pose oracle's held-out success in the world of the
    first one's four-action cell (the paper's task and noise), the third edition's
    contest (its results, :func:`contest_summary`) and its claims' sentence
    (:func:`claims_summary`)."""
    text = [reproduced_text(results1, results2)]
    if comparisons:
        text.append(turning_text(comparisons, oracle))
    text.append(contest_summary(contest, corrected) if contest is not None else _FINDING_LEFT_OUT)
    if claims is not None:
        text.append(
            "**The paper's claims** (the third edition, notebook 07: fresh seeds, intervals "
            f"over matched seeds; the claims at a glance below, every interval and p-value on the "
            f"verdict table's page, docs/guide/verdicts.md). {claims}"
        )
    return "\n\n".join(text)


def reproduced_text(results1: list[ExperimentResult], results2: list[ExperimentResult]) -> str:
    """The paragraph on what was reproduced: Experiments 1 and 2 (``results1``, ``results2``)
    beside the paper's numbers, and the choices of the world they hold in."""
    h1, h2 = headline(results1), headline(results2)
    rate1 = np.array([r.test.success.mean() for r in results1])
    rate2 = np.array([r.test.success.mean() for r in results2])
    w = h2.config.world
    return (
        f"**Reproduced.** The paper's learner, trained from 32x10 pixels alone, docks in "
        f"{h1.test_successes}/{len(h1.test)} test trials of Experiment 1 (paper: 100%) and "
        f"{h2.test_successes}/{len(h2.test)} = {_pct(h2.test.success.mean())} of Experiment 2 "
        f"(paper: 95%, 690/725), headline seed {HEADLINE_SEED}. Over all seeds, "
        f"{int(np.sum(rate1 == 1))} of {len(results1)} networks reach 100% in Experiment 1, and"
        f" Experiment 2 averages {_pct(rate2.mean())} over {len(results2)} (min "
        f"{_pct(rate2.min())})."
        f" These numbers hold in a world whose step lengths ({100 * w.step_forward:.0f} cm "
        f"forward, {100 * w.step_side:.0f} cm sideways, about two of Nao's steps) and whose "
        f"{w.scene} that stops the robot at the dock were chosen while calibrating towards "
        "them (notebooks 03-04)."
    )


def turning_text(comparisons: list, oracle: float | None = None) -> str:
    """The paragraph on Experiment 3: the four-against-six comparisons
    (:func:`turning_comparisons`) and the pose oracle's held-out success in the world of the
    first one's four-action cell (the paper's task and noise; None: not said)."""
    gains = [c.gain.estimate for c in comparisons]
    four = comparisons[0]
    oracle_note = ""
    if oracle is not None:
        oracle_note = (
            f"; in the paper's own task and noise the pose oracle docks {_pct(oracle)} of "
            f"held-out trials and the four-action learner {_pct(four.four.estimate)}"
        )
    worse = sum(c.gain.high < 0 for c in comparisons)
    verdict = "Not supported" if worse == len(comparisons) else "Mixed"
    return (
        f"**{verdict}.** The paper names turning as the remedy for rotation, its main cause of "
        "failure; given turn actions, the learner docks less often "
        f"(95% interval below zero) in {worse} of Experiment 3's {len(comparisons)} cells; "
        f"six minus four actions ranges from {100 * min(gains):.1f} to "
        f"{100 * max(gains):.1f} percentage points{oracle_note} (notebook 06)."
    )


#: The summary's main finding when the third edition is left out of the report: where it is.
_FINDING_LEFT_OUT = (
    "**The main finding**: the study's third edition (notebooks 07 and 10), which this report left "
    "out (`--no-third-edition`)."
)


#: The markers of the README's table of the third edition's contest (notebook 10).
THIRD_EDITION_START = "<!-- third-edition:start -->"


THIRD_EDITION_END = "<!-- third-edition:end -->"


#: The markers of the README's table of Experiment 3 (notebook 06).
EXPERIMENT3_START = "<!-- experiment3:start -->"


EXPERIMENT3_END = "<!-- experiment3:end -->"


#: The markers of the README's paragraph of measured times.
TIMINGS_START = "<!-- timings:start -->"


TIMINGS_END = "<!-- timings:end -->"


#: What ``tools/time_tiers.py`` runs for a tier that is not a Makefile target.
COMMANDS = {"report": "python -m docking report"}


#: The order the README lists the tiers in (tools/time_tiers.py's, quickest first).
_TIER_ORDER = {
    name: k for k, name in enumerate(("setup", "check", "report", "test", "docs", "paper"))
}


def _tier_notes(measured: dict) -> dict[str, str]:
    """What the README says beside each tier's time of ``measured`` (time_tiers' record)."""
    names = {
        "setup": " (package downloads)",
        "docs": " (the site, executing the notebooks: none is executed yet in a fresh clone)",
        "report": " (from the committed ledger)",
    }
    if measured.get("fresh"):  # time_tiers --fresh: each tier from the clone as checked out
        names["test"] = " (no notebook executed before it)"
    elif "docs" in measured["tiers"] and "test" in measured["tiers"]:
        names["test"] = " (after `make docs` in the same clone)"
    return names


def timings_text(
    measured: dict | None, runs: int, run_seconds: float, ledger_bytes: int | None = None
) -> str:
    """The README's paragraph of times: ``measured`` is ``tools/time_tiers.py``'s record (None
    if the tiers were not timed), ``runs`` and ``run_seconds`` the ledger's runs and the sum
    of their wall times (the ledger manifest's), ``ledger_bytes`` its size
    (:func:`docking.study.ledger.size_bytes`; None: not said)."""
    per_run = run_seconds / max(runs, 1)
    size = ""
    if ledger_bytes is not None:
        size = (
            f" ({ledger_bytes / 2**20:.1f} MiB, compressed; a recompute under changed code "
            "rewrites it all, adding that much to the history)"
        )
    reproduce = (
        f"`make reproduce` computes the ledger's {runs} runs, whose recorded wall times add "
        f"up to {run_seconds / 3600:.1f} h of one process ({per_run:.0f} s per run on "
        "average; the embedded cluster runs one per core), then executes the notebooks and "
        f"writes the ledger{size}. A Dask cluster divides the computing by its number of "
        "cores (`--scheduler` on `design run`, `sweep`)."
    )
    if measured is None:
        return f"The tiers have not been timed on this commit's ledger. {reproduce}"
    names = _tier_notes(measured)
    top = measured["commit"]

    def where(t: dict) -> str:  # a tier kept from an earlier measurement names its commit
        return "" if t.get("commit", top) == top else f", on {t['commit'][:7]}"

    def took(t: dict) -> str:
        return f"{t['wall_s']:.0f} s" if t["wall_s"] < 60 else f"{t['wall_s'] / 60:.1f} min"

    tiers = "; ".join(
        f"`{COMMANDS.get(tier, f'make {tier}')}` {took(t)}{names.get(tier, '')}{where(t)}"
        for tier, t in sorted(
            measured["tiers"].items(), key=lambda item: _TIER_ORDER.get(item[0], 9)
        )
    )
    step = measured["step"]
    fresh = (
        ", each tier from the clone as checked out (its environment kept)"
        if measured.get("fresh")
        else ""
    )
    return (
        f"Measured by `tools/time_tiers.py` on {measured['date']} from a fresh clone (commit "
        f"{measured['commit'][:7]}){fresh} on a {measured['cores']}-core CPU-only machine, Python "
        f"{measured['python']}, where `python -m docking benchmark --quick` gives "
        f"{step['min_ms']:.2f} / {step['median_ms']:.2f} ms of CPU per environment step "
        f"(min / median; on a machine where it is twice that, expect twice the times): "
        f"{tiers}. {reproduce}"
    )


def replace_block(text: str, block: str, start: str = README_START, end: str = README_END) -> str:
    """``text`` with the lines between the markers ``start`` and ``end`` replaced by
    ``block``; ``ValueError`` unless each marker occurs once, in that order."""
    starts, ends = text.count(start), text.count(end)
    if starts != 1 or ends != 1 or text.index(start) > text.index(end):
        raise ValueError(
            f"the README must hold one {start!r} line followed by one {end!r} "
            f"line (found {starts} and {ends})"
        )
    head, rest = text.split(start, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{start}\n{block.strip()}\n{end}{tail}"


def update_readme(path, table: str, start: str = README_START, end: str = README_END) -> bool:
    """Write ``table`` into the README at ``path`` between the markers (atomically); whether
    the file changed."""

    from docking.fileio import atomic_write

    path = Path(path)
    text = path.read_text(encoding="utf-8")
    new = replace_block(text, table, start, end)
    if new == text:
        return False
    atomic_write(path, lambda f: f.write(new.encode("utf-8")))
    return True


#: The markers of the README's verdict table of the third edition (notebook 07).
VERDICTS_START = "<!-- verdicts:start -->"


VERDICTS_END = "<!-- verdicts:end -->"


#: The site's page of the full verdict table (beside the README, between the same markers);
#: the README shows the claims at a glance (:data:`CLAIMS_FIGURE`) and links it.
VERDICTS_PAGE = "docs/guide/verdicts.md"


CLAIMS_FIGURE = "verdicts_glance"


#: The first screen's figure, in the figures folder (written by ``report --readme``).
GLANCE_FIGURE = "glance"


#: The markers of the README's first screen: the figure and at most five sentences.
GLANCE_START = "<!-- glance:start -->"


GLANCE_END = "<!-- glance:end -->"


#: The site's page of what the runs show in detail: the detailed summary (between
#: :data:`DETAILS_START` and :data:`DETAILS_END`), the third edition's contest table and
#: Experiment 3's table, one link from the README.
FINDINGS_PAGE = "docs/guide/findings.md"


#: The markers of the findings page's section on the equal contest (the current finding):
#: its verdicts, the runs each learner spent and what it chose, its fragility tables.
EQUAL_START = "<!-- equal-contest:start -->"


EQUAL_END = "<!-- equal-contest:end -->"


DETAILS_START = "<!-- details:start -->"


DETAILS_END = "<!-- details:end -->"
