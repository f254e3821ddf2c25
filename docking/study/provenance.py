"""The study's provenance: which designs committed their rules before their runs
(:data:`RULES_COMMITS`, checked against the history by tests/test_provenance.py), the runs'
computed times against them (:func:`provenance_counts`, from the ledger's manifest), the
deviations from that order (:data:`DEVIATIONS`) and the choices made after results were seen
(:data:`CHOICES_AFTER_RESULTS`): the README's candid summary (:func:`candour_text`) and the
notebooks' tables of deviations.
"""

from __future__ import annotations

import collections
import dataclasses

from docking.study.designs.third_edition_report import OUTSIDE_COUNTS
from docking.study.report import md_table, utc

#: ``{design name: (the commit that added its rules, that commit's time)}``: what its runs'
#: computed times are compared with (tests/test_addendum.py checks each against the history).
RULES_COMMITS = {
    "third-edition-addendum": (
        "d1c52e9bf46ba23103503e7970b191404d74bc41",
        "2026-11-26T21:41:44+00:00",
    ),
    "addendum-bracketing": (
        "670c9e6773a9e2035b391bce4e358110d9ff574a",
        "2026-11-27T00:51:06+00:00",
    ),
    "addendum-bracketing-continued": (
        "b0c138ea24092af1c9a7dceb12989d1ec4b14fb1",
        "2026-11-27T03:51:50+00:00",
    ),
    "untested-revisited": (
        "52625147765c7d4dc7461dbebe4ae30eb3ce338f",
        "2026-11-27T00:57:05+00:00",
    ),
    "bracketing-replication": (
        "792adb7ac21e904685cd3b2080140ec9c2eb4ca8",
        "2026-11-28T05:05:02+00:00",
    ),
    "fragility-landscape": (
        "b4ecb82e559aaca53afe92a95b18a033ffc7c840",
        "2026-11-28T05:38:58+00:00",
    ),
    "equal-contest": (
        "319cc645556415be9688e341fd334c2fb70dbcda",
        "2026-11-29T04:50:05+00:00",
    ),
}


@dataclasses.dataclass(frozen=True)
class Deviation:
    """A departure from "rules before runs, code fixed while they run" in a design's
    history: what happened, the commit that shows it (None: no commit does) and the file it
    touched, and what it means for the design's verdicts."""

    design: str
    what: str
    commit: str | None
    path: str | None
    means: str


#: Every deviation known, listed in its design's notebook; tests/test_provenance.py checks
#: each commit against the history (that it exists, touched its file, and came after the
#: design's rules).
DEVIATIONS = (
    Deviation(
        "untested",
        "code changed after runs were seen: continuous PPO's actions clipped by the world, "
        "not inside the policy (its first runs stopped on NaN actions)",
        "fbd2835ed3689dc7e09575068460ac29c076fc6f",
        "docking/ppo.py",  # its path at that commit
        "every PPO run was re-keyed and computed again on the changed code; the judged "
        "comparisons of continuous actions read only those runs, but the change was made "
        "after seeing the first ones",
    ),
    Deviation(
        "third-edition",
        "runs on judged seeds before the rules: the Nao-like world's pose oracle ran on the "
        "judged seeds 3000-3004 before the third edition's rules were committed (a review's "
        "reading of the history, issue 42)",
        None,
        None,
        "the oracle is a yardstick (it fixes no verdict's arm), so no verdict was chosen on "
        "those runs; the ledger of that time kept no computed times, so the order cannot be "
        "recomputed from it",
    ),
    Deviation(
        "equal-contest",
        "rules amended after a run was seen (amendment 1): linear SARSA's eps_Q above 2 made a "
        "limit after its run at eps_Q 3 stopped (Q would have become non-finite), which stopped "
        "the contest; the rules named no outcome for a run that cannot finish",
        "32a998bf5c83327480e03c2067ed2aeda55e7b89",
        "rules/equal-contest.amendment-1.json",
        "committed before any run it changes: the 14 extension runs stored before it are ones the "
        "amended rules ask for too, and no selection or judged run existed; it moves linear "
        "SARSA's extension points from rungs that diverge to rungs that run, and counts eps_Q 1 "
        "as bracketed from above (the limit), which favours linear SARSA's search",
    ),
)


#: Choices made after earlier results had been seen, each with what it affects (the
#: candid summary's third part; issue 42).
CHOICES_AFTER_RESULTS = (
    (
        "the sideboard world's steps and its sideboard",
        "chosen while calibrating towards the paper's numbers (notebooks 03-04)",
    ),
    (
        "the floor scene",
        "chosen after the second edition had shown that it breaks the paper's learner; the "
        "Nao-like world builds on it, so the two are not independent worlds",
    ),
    (
        "the addendum's and the bracketing's knobs",
        "chosen after the contest had been seen to stop at the edge of its grids (rules "
        "committed before their own runs)",
    ),
    (
        "the bracketing's continuation",
        "its further budget chosen after the bracketing's runs had been seen to stop before "
        "the paper's learner's optimum; its walk is the bracketing's, and it judges on seeds "
        "no earlier run used (rules committed before its own runs)",
    ),
)


def candour_text(folder=None) -> str:
    """The candid summary's sentences: which claims hold by construction and which verdicts
    are limited by a measure's resolution (:data:`OUTSIDE_COUNTS`), which choices were made
    after earlier results were seen (:data:`CHOICES_AFTER_RESULTS`), the deviations from
    the rules' order (:data:`DEVIATIONS`), and where the ledger can prove that rules came
    before runs (:func:`provenance_text`, from the ledger in ``folder``)."""
    outside = "; ".join(f"{k}: {why}" for k, why in OUTSIDE_COUNTS.items())
    choices = "; ".join(f"{what}, {why}" for what, why in CHOICES_AFTER_RESULTS)
    deviations = "; ".join(f"{d.design}: {d.what}" for d in DEVIATIONS)
    return (
        f"**Read with care.** Outside every count of verdicts, as tests that could not fail "
        f"or could not see: {outside} (notebook 09 tests both again by rules that can fail). "
        f"Chosen after earlier results were seen: {choices}. Deviations from the rules' "
        f"order, listed in their notebooks: {deviations}. {provenance_text(folder)}"
    )


def provenance_counts(folder=None) -> tuple[dict[str, int], dict[str, int]]:
    """The ledger's runs per table, in two parts: ``(timed, untimed)``, the runs of the
    designs whose rules commit is recorded (:data:`RULES_COMMITS`), and the runs of every
    other table that carry no computed time (the ledger recorded none before issue 42)."""
    runs = _manifest_runs(folder)
    timed = collections.Counter(r["name"] for r in runs if r["name"] in RULES_COMMITS)
    untimed = collections.Counter(
        r["name"] for r in runs if r["name"] not in RULES_COMMITS and "computed_utc" not in r
    )
    return dict(timed), dict(untimed)


def provenance_text(folder=None) -> str:
    """Where "rules before runs" is proven by the ledger's run times and where it rests on
    the order of commits alone (:func:`provenance_counts`)."""
    timed, untimed = provenance_counts(folder)
    proven = ", ".join(f"{name} ({n:,})" for name, n in sorted(timed.items()))
    unproven = ", ".join(f"{name} ({n:,})" for name, n in sorted(untimed.items()))
    return (
        f"Rules before runs, proven by the ledger's run times (tests/test_provenance.py) for "
        f"{proven}; the runs of {unproven} carry no time (the ledger recorded none before "
        f"issue 42), so for their verdicts only the order of the commits speaks."
    )


def deviations_table(design: str) -> str:
    """The Markdown table of :data:`DEVIATIONS` of ``design`` (nothing: "none known")."""
    found = [d for d in DEVIATIONS if d.design == design]
    if not found:
        return "Deviations from the rules' order: none known."
    return md_table(
        ("deviation", "the commit", "what it means"),
        [(d.what, (d.commit or "none")[:7], d.means) for d in found],
    )


def computed_times(name: str, folder=None) -> list:
    """When each run of the ledger's table ``name`` was computed (UTC datetimes, sorted),
    from its manifest; a run stored before the time was recorded has none and is left out
    (compare the count with the runs')."""
    runs = _manifest_runs(folder)
    return sorted(utc(r["computed_utc"]) for r in runs if r["name"] == name and "computed_utc" in r)


def _manifest_runs(folder=None) -> list[dict]:
    """The run records of the ledger's manifest in ``folder`` (the ledger's by default), where
    the times runs were computed are kept; ValueError if there is no ledger."""
    from docking.study import ledger

    data = ledger.manifest(folder)
    if data is None:
        raise ValueError("no ledger: the times runs were computed are read from its manifest")
    return list(data["runs"].values())
