"""The replication (docking.study.designs.replication): its rules, pinned before its runs; its
seeds, fresh; its cells, the bracketing continued's; its verdicts, rules that can fail."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from docking.study.designs import replication as rp

REPO = Path(__file__).resolve().parents[1]


def test_no_other_run_of_the_ledger_uses_its_seeds():
    runs = json.loads((REPO / "ledger" / "manifest.json").read_text())["runs"]
    used = {r["seed"] for r in runs.values() if r["name"] != rp.NAME}
    assert used and not used & set(rp.SEEDS)
    assert len(rp.SEEDS) >= 20


@pytest.mark.slow
def test_its_cells_are_the_bracketing_continueds_judged_cells_renamed(monkeypatch):
    """Each cell's configuration, renamed, is the one the bracketing continued judged: the
    tuned settings and PPO's matched steps as committed there (read from its ledger)."""
    from docking.study.designs import bracketing_continued as bc

    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))

    own = bc.DESIGN.run(progress=False)
    for cell in rp.DESIGN.cells:
        world, learner = cell["world"], cell["learner"]
        key = f"{world}/ppo-matched" if learner == "ppo" else f"{world}/{learner}-bracketed"
        assert dataclasses.replace(cell.config, name=bc.NAME) == own.cell(key).config, key
        if learner != "ppo":
            assert rp.TUNED[world][learner] == bc.tuned(own, world, learner)


def test_the_gap_rule_says_closed_remains_and_undecided():
    paper = np.full(20, 0.9)
    jitter = np.tile([-0.01, 0.01], 10)
    assert rp.gap_verdict(paper + 0.01 + jitter, paper) == "closed"
    assert rp.gap_verdict(paper + 0.09 + jitter, paper) == "remains"
    assert rp.gap_verdict(paper + 0.05 + 5 * jitter, paper) == "undecided"
    mean, low, high = rp.gap_interval(paper + 0.02 + jitter, paper)
    assert low < mean < high and mean == pytest.approx(0.02)


def test_the_leads_are_holm_adjusted_over_the_worlds():
    rng = np.random.default_rng(0)
    paper = rng.uniform(0.9, 0.95, 20)
    clear = paper - 0.03 + rng.normal(0, 0.005, 20)
    none = paper + rng.normal(0, 0.02, 20)
    found = rp.lead_verdicts({"floor": (clear, paper), "nao": (none, paper)})
    assert found["floor"][0] == "paper ahead"
    assert found["nao"][0] == "no lead shown"
    # Holm: the larger p-value is never adjusted below its own
    raw = [__import__("scipy").stats.ttest_1samp(x - paper, 0).pvalue for x in (clear, none)]
    assert found["nao"][1] >= raw[1] and found["floor"][1] == pytest.approx(2 * raw[0])


def test_the_wording_says_replicated_only_where_both_agree():
    assert rp.wording("closed", "closed", "paper ahead", "paper ahead") == (
        "closed, replicated",
        "paper ahead, replicated",
    )
    gap, lead = rp.wording("closed", "undecided", "paper ahead", "no lead shown")
    assert "not replicated" in gap and "not replicated" in lead
    assert rp.first_lead(-0.035, -0.003) == "paper ahead"
    assert rp.first_lead(-0.01, 0.02) == "no lead shown"


def test_no_text_calls_the_held_out_streams_of_two_learners_paired():
    """Each learner's run of a seed draws its own held-out trials from that seed's generator:
    the seeds are matched, the streams are not paired (only the first start pose is shared).
    No page, docstring or notebook says otherwise (the archived editions excepted)."""
    import re

    pattern = re.compile(r"paired\s+held-out|held-out\s+streams,?\s+paired|paired\s+streams", re.I)
    found = []
    for folder in ("docking", "notebooks", "docs", "tools", "tests"):
        for path in sorted((REPO / folder).rglob("*")):
            if path.suffix in (".py", ".md") and path != Path(__file__):
                found += [f"{path.name}: {m.group(0)}" for m in pattern.finditer(path.read_text())]
    for name in ("README.md", "CONTRIBUTING.md"):
        found += [f"{name}: {m.group(0)}" for m in pattern.finditer((REPO / name).read_text())]
    assert not found, found
