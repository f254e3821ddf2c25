"""The bracketing continued (docking.study.designs.bracketing_continued): its rules, pinned
before its runs, and its judged seeds, fresh."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pinned
import pytest

from docking.study import provenance
from docking.study.designs import addendum as ad
from docking.study.designs import bracketing as br
from docking.study.designs import bracketing_continued as bc

REPO = Path(__file__).resolve().parents[1]
#: The SHA-256 of rules_text() when the rules were committed, before any of its runs.
RULES_DIGEST = "0cbf59c64e30ae0423858268f0e5a7404f26b340fe772a75ca72fc26450976e4"
#: The SHA-256 of rules_text() since the study layer moved into docking/study/ (issue 51): the
#: same rules, its, the bracketing's and the addendum's import statements naming the moved modules
#: (:func:`test_the_rules_moved_unchanged` proves it from the history).
MOVED_DIGEST = "c0c673327c58876088519f3e1ea3bc33b2559b8f27a79e7cabd647e22430356a"


def test_rules_are_the_committed_ones():
    """The rules as committed: their digest since the move, which is the digest pinned at the
    rules' commit with only import statements changed (:func:`test_the_rules_moved_unchanged`)."""
    assert hashlib.sha256(bc.rules_text().encode()).hexdigest() == MOVED_DIGEST


def test_the_rules_moved_unchanged():
    """Which proof holds: the digest at the rules' commit, from the history (tests/pinned.py).
    The rules now, with this module's, the bracketing's and the addendum's tokens and the judging
    functions' source read as at the rules' commit, have :data:`RULES_DIGEST`; the three modules
    differ from then only in import statements; the judging functions' text is the same but for
    ``report.paired_over_shared_seeds``'s import of ``t_paired_ci`` (the bracketing's and the
    addendum's rules, part of these, by the same proof)."""
    if not pinned.history():
        pytest.skip("a shallow clone (or no git): the history that pinned the rules is not here")
    commit = provenance.RULES_COMMITS[bc.NAME][0]
    read = pinned.check_moved(bc.rules_text, commit, [bc, br, ad], RULES_DIGEST)
    assert sorted(read["functions"]) == [
        "docking.study.report.contest_gaps",
        "docking.study.report.paired_over_shared_seeds",
        "docking.study.stats.t_paired_ci",
    ]
    assert pinned.changed_functions(read) == {"docking.study.report.paired_over_shared_seeds"}


def test_the_judged_seeds_are_fresh():
    """No run of another design in the committed ledger used the judged seeds, and they are
    not the seeds settings are compared on."""
    runs = json.loads((REPO / "ledger" / "manifest.json").read_text())["runs"]
    used = {r["seed"] for r in runs.values() if r["name"] != bc.NAME}
    assert used and not used & set(bc.SEEDS)
    assert not set(bc.SEEDS) & set(bc.COMPARE_SEEDS)


def test_the_walk_is_the_bracketings():
    """The same compared seeds and the same incumbent and neighbour functions: only the
    budget, the stages and the judged seeds are this design's."""
    assert bc.COMPARE_SEEDS == br.COMPARE_SEEDS
    assert bc.incumbent is br.incumbent and bc.missing_neighbours is br.missing_neighbours
