"""The bracketing continued (docking.study.designs.bracketing_continued): its rules, pinned
before its runs, and its judged seeds, fresh."""

from __future__ import annotations

import json
from pathlib import Path

from docking.study.designs import bracketing as br
from docking.study.designs import bracketing_continued as bc

REPO = Path(__file__).resolve().parents[1]


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
    assert type(bc.WALK) is type(br.WALK)  # the one walk (docking.study.designs.walk)
    assert bc.WALK.compare_seeds == br.WALK.compare_seeds
