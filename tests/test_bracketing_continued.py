"""The bracketing continued (docking.designs.bracketing_continued): its rules, pinned
before its runs, and its judged seeds, fresh."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from docking.designs import bracketing as br
from docking.designs import bracketing_continued as bc

REPO = Path(__file__).resolve().parents[1]
#: The SHA-256 of rules_text() when the rules were committed, before any of its runs.
RULES_DIGEST = "0cbf59c64e30ae0423858268f0e5a7404f26b340fe772a75ca72fc26450976e4"


def test_rules_are_the_committed_ones():
    assert hashlib.sha256(bc.rules_text().encode()).hexdigest() == RULES_DIGEST


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
