"""The README's own blocks: its markers (each block written between ``<!-- NAME:start -->``
and ``<!-- NAME:end -->``, :func:`update_readme`), the detailed summary (:func:`summary_text`),
the first screen (its figure's arrays, :func:`glance_data`, and its sentences,
:func:`glance_text`) and the paragraph of times (:func:`timings_text`). Each sentence's
numbers come from its design's report (``docking/study/designs/<design>_report.py``);
``python -m docking report --readme README.md`` writes them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from docking.experiments import ExperimentResult
from docking.presets import HEADLINE_SEED
from docking.study.designs.paper_report import headline
from docking.study.designs.third_edition_report import claim_groups, contest_summary
from docking.study.report import _pct, contest_gaps

#: The README's generated block lies between these lines.
README_START = "<!-- results:start -->"


README_END = "<!-- results:end -->"


#: The markers of the README's summary, its first screen.
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
    h1, h2 = headline(results1), headline(results2)
    rate1 = np.array([r.test.success.mean() for r in results1])
    rate2 = np.array([r.test.success.mean() for r in results2])
    w = h2.config.world
    text = [
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
        "them (notebooks 03-04).",
    ]
    if comparisons:
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
        text.append(
            f"**{verdict}.** The paper blames most failures on uncorrected rotation and "
            "names turning as the remedy; given turn actions, the learner docks less often "
            f"(95% interval below zero) in {worse} of Experiment 3's {len(comparisons)} cells; "
            f"six minus four actions ranges from {100 * min(gains):.1f} to "
            f"{100 * max(gains):.1f} percentage points{oracle_note} (notebook 06)."
        )
    text.append(contest_summary(contest, corrected) if contest is not None else _FINDING_LEFT_OUT)
    if claims is not None:
        text.append(
            "**The paper's claims** (the third edition, notebook 07: fresh seeds, intervals "
            f"over matched seeds; the claims at a glance below, every interval and p-value on the "
            f"verdict table's page, docs/guide/verdicts.md). {claims}"
        )
    return "\n\n".join(text)


#: The summary's main finding when the third edition is left out of the report: where it is.
_FINDING_LEFT_OUT = (
    "**The main finding**: the study's third edition (notebook 07), which this report left "
    "out (`--no-third-edition`)."
)


#: The markers of the README's table of the third edition's contest (notebook 07).
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
            f" ({ledger_bytes / 2**20:.1f} MiB; its tables and whole runs are compressed "
            "already, and a full recompute under changed code rewrites every one of them, so it "
            "adds about that much to the repository's history)"
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
    names = {
        "setup": " (package downloads)",
        "docs": " (the site, executing the notebooks: none is executed yet in a fresh clone)",
        "report": " (from the committed ledger)",
    }
    top = measured["commit"]

    def where(t: dict) -> str:  # a tier kept from an earlier measurement names its commit
        return "" if t.get("commit", top) == top else f", on {t['commit'][:7]}"

    def took(t: dict) -> str:
        return f"{t['wall_s']:.0f} s" if t["wall_s"] < 60 else f"{t['wall_s'] / 60:.1f} min"

    tiers = "; ".join(
        f"`{COMMANDS.get(tier, f'make {tier}')}` {took(t)}{names.get(tier, '')}{where(t)}"
        for tier, t in measured["tiers"].items()
    )
    step = measured["step"]
    return (
        f"Measured by `tools/time_tiers.py` on {measured['date']} from a fresh clone (commit "
        f"{measured['commit'][:7]}) on a {measured['cores']}-core CPU-only machine, Python "
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


#: The learners of the first screen's figure: ``(variant in the addendum, in the contest,
#: label)``; the sideboard world is not in the addendum and shows the contest's.
GLANCE_LEARNERS = (
    ("paper-tuned", "paper-tuned", "the paper's learner, tuned"),
    ("linear-tuned", "linear-tuned", "linear SARSA on the same pixels, tuned"),
    ("ppo-matched", "ppo-tuned", "PPO on the same pixels"),
)


#: The yardsticks of the first screen's figure: ``(variant in the contest, label)``.
GLANCE_YARDSTICKS = (
    ("oracle", "pose oracle (reads the true pose)"),
    ("centroid", "centroid rule (one line of code)"),
    ("random", "random actions"),
)


#: The worlds' labels under the first screen's figure (and how their learners were tuned).
GLANCE_WORLDS = {
    "sideboard": "sideboard world (calibrated)",
    "floor": "floor world",
    "nao": "Nao-like world",
}


def glance_data(contest, added) -> tuple[list, list, dict, dict]:
    """The first screen's figure's arrays (:func:`docking.study.figures.fig_glance`): per world of
    the contest, each learner's per-seed held-out success (the addendum's where it ran, the
    contest's in the sideboard world) and the yardsticks' means."""
    keys = {c.key for c in added.cells} if added is not None else set()
    worlds, learners = [], [label for *_, label in GLANCE_LEARNERS]
    seeds, yardsticks = {}, {}
    for world, label in GLANCE_WORLDS.items():
        bracketed = f"{world}/paper-tuned" in keys
        name = f"{label}\n({'tuned on the same knobs' if bracketed else 'contest tuning'})"
        worlds.append(name)
        for in_addendum, in_contest, label in GLANCE_LEARNERS:
            if bracketed:
                seeds[name, label] = added.score(f"{world}/{in_addendum}")
            else:
                seeds[name, label] = contest.score(f"{world}/{in_contest}")
        for variant, label in GLANCE_YARDSTICKS:
            yardsticks[name, label] = float(np.mean(contest.score(f"{world}/{variant}")))
    return worlds, learners, seeds, yardsticks


#: The first screen's figure, in the figures folder (written by ``report --readme``).
GLANCE_FIGURE = "glance"


#: The markers of the README's first screen: the figure and at most five sentences.
GLANCE_START = "<!-- glance:start -->"


GLANCE_END = "<!-- glance:end -->"


def _revisited_clause(rows, verdict: str) -> str:
    """The first screen's words on relocation and coping revisited (``rows``:
    :func:`revisited_rows`, None: not in): where each claim got ``verdict``."""
    if rows is None:
        return ""
    worlds = {}
    for (claim, world), got in rows["verdict"].items():
        if got == verdict:
            worlds.setdefault(claim, []).append(world)
    found = []
    for claim, places in worlds.items():
        if claim == "relocation-height":
            found.append(
                f"relocation{' fails' if verdict == 'contradicted' else ''}, a landmark "
                + " or ".join(
                    f"{100 * rows['height']:.0f} cm {p.removeprefix('sideboard ')} taking "
                    f"success from {_pct(rows['places'][p]['home'].estimate)} to "
                    f"{_pct(rows['places'][p]['there'].estimate)}"
                    for p in places
                )
            )
        else:
            found.append(
                f"coping after the {_and(places)} change" + ("s" if len(places) > 1 else "")
            )
    lead = "; so is " if verdict == "supported" else "; "
    return f"{lead}{_and(found)} (notebook 09)" if found else ""


def _and(words) -> str:
    """``words`` as English: "a", "a and b", "a, b and c"."""
    words = list(words)
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def _main_finding(contest, added, worlds, where: str, gaps: dict, unbracketed) -> str:
    """The first screen's sentence on the main finding: the contest's (``added`` None) or
    the addendum's walk's, with the contest's gaps it corrects."""
    worlds_text = "the *floor world* and the *Nao-like world*"
    if added is None:
        return (
            f"**The main finding:** in {worlds_text}, *linear SARSA* (one Q-value per pixel, no "
            f"feature layer) docks more often than the paper's learner, both tuned alike: "
            f"{where} (notebook 07)."
        )
    before = {g.world: g for g in contest_gaps(contest, worlds, 0.05)}
    was = " and ".join(f"{100 * before[k].interval.estimate:.0f}" for k in worlds)
    how = (
        "tuned alike to bracketed optima"
        if not unbracketed
        else f"tuned on the same knobs (the paper's learner's {_and(unbracketed)} left at "
        "the edge of the search)"
    )
    verdicts = {g.verdict for g in gaps.values()}
    close = "docks within 5 pp of" if verdicts == {"closed"} else "closes part of its gap to"
    return (
        f"**The main finding, corrected:** {how}, the paper's learner {close} *linear "
        f"SARSA* (no feature layer) in {worlds_text}: {where}; our earlier gaps of {was} pp "
        "were too strong (notebook 07)."
    )


def glance_text(
    results1,
    results2,
    comparisons,
    contest,
    added,
    claims,
    decisions,
    tuned=None,
    unbracketed=(),
    revisited=None,
) -> str:
    """The README's first screen under its figure: at most five plain sentences, every
    number from the runs, every term defined where it first appears. ``added``: the
    addendum's results (None: the contest's finding); ``tuned``: ``{world: the paper
    learner's tuned exploration temperature}`` in the addendum; ``unbracketed``: the knobs
    of the paper's learner whose tuned value the search left at the edge of what it tried;
    ``revisited``: :func:`revisited_rows` of relocation and coping revisited (None: not in)."""
    from docking.study.claims import rate_interval

    h2 = headline(results2)
    e1 = np.mean([r.test.success.mean() for r in results1])
    e2 = np.mean([r.test.success.mean() for r in results2])
    groups = claim_groups(claims, decisions)
    judged = sum(len(v) for v in groups.values())
    held = groups.get("supported wherever judged", []) + groups.get(
        "supported in some worlds only", []
    )
    against = groups.get("contradicted in at least one world", [])
    worse = sum(c.gain.high < 0 for c in comparisons) if comparisons else 0
    source = added if added is not None else contest
    worlds = [w for w in ("floor", "nao") if f"{w}/paper-tuned" in {c.key for c in source.cells}]
    gaps = {g.world: g for g in contest_gaps(source, worlds, 0.05)}
    w = h2.config.world
    lines = [
        f"**Reproduced, under our choices.** From 32x10 camera pixels alone, the paper's "
        f"learner docks in {_pct(e1)} and {_pct(e2)} of Experiments 1 and 2's test trials "
        f"(paper: 100%, 95%) in the *sideboard world*, its {100 * w.step_forward:.0f} cm steps "
        "and sideboard chosen while calibrating (notebooks 03-04).",
        f"**What held up:** {len(held)} of the paper's {judged} claims judged on fresh seeds "
        "are supported in at least one world (notebook 07)"
        + _revisited_clause(revisited, "supported")
        + ".",
        f"**What did not:** {len(against)} are contradicted somewhere; turn actions lower "
        f"success in {worse} of {len(comparisons) if comparisons else 0} settings (notebook 06)"
        + _revisited_clause(revisited, "contradicted")
        + ".",
    ]
    paper = {k: rate_interval(source, f"{k}/paper-tuned").estimate for k in worlds}
    linear = {k: rate_interval(source, f"{k}/linear-tuned").estimate for k in worlds}
    where = " and ".join(f"{_pct(paper[k])} against {_pct(linear[k])}" for k in worlds)
    lines.append(_main_finding(contest, added, worlds, where, gaps, unbracketed))
    return "\n".join(f"{k + 1}. {line}" for k, line in enumerate(lines))
