"""The rules of the claims nobody had tested (docking.designs.untested), pinned before their
runs; the relocations' and changes' effect on the views, measured before any run."""

from __future__ import annotations

import dataclasses
import hashlib
from pathlib import Path

import numpy as np
import pytest
from helpers import unknown_cells, unquoted

from docking.designs import third_edition, untested

#: The SHA-256 of rules_text() when the rules were committed, before any of their runs (last
#: amended, still before any run, to give the relocation claim's label the statistic's sign).
RULES_DIGEST = "3005101fcff8df0bc100cf3b38165abdbec3ca0d89e8cc98f02421cc587c4bd3"

PAPER = Path(__file__).resolve().parents[2] / "shared" / "paper.md"


def test_rules_are_the_committed_ones():
    assert hashlib.sha256(untested.rules_text().encode()).hexdigest() == RULES_DIGEST


def test_seeds_are_fresh():
    used = set(third_edition.SEEDS) | set(third_edition.TUNING_SEEDS) | set(range(10))
    assert not used & set(untested.SEEDS)


def test_comparisons_name_cells_of_the_design():
    assert unknown_cells(untested.DESIGN) == []


def test_coping_starts_from_the_home_networks_and_shares_their_runs():
    home = untested.DESIGN.cell("home/paper").config
    for change in untested.CHANGES:
        relearn = untested.DESIGN.cell(f"{change}/paper-relearn").config
        fresh = untested.DESIGN.cell(f"{change}/paper-fresh").config
        assert relearn.before == home and dataclasses.replace(relearn, before=None) == fresh


def test_population_holds_eps_w_over_beta_s():
    base = untested.DESIGN.cell("sideboard/paper").config.network
    for beta in untested.BETAS:
        n = untested.DESIGN.cell(f"sideboard/beta{beta:g}").config.network
        assert n.beta_s == beta and n.eps_w / n.beta_s == pytest.approx(base.eps_w / base.beta_s)


@pytest.mark.skipif(not PAPER.exists(), reason="the paper's text (shared/paper.md) is not here")
def test_claims_quote_the_paper():
    assert unquoted(untested.CLAIMS, PAPER.read_text(), skip=("mechanism", "coping-linear")) == []


@pytest.mark.slow
def test_relocations_change_no_view_and_the_changes_do():
    """The fact the rules file states, measured: the robot's 32x10 views at 100 start poses
    are the same in every relocated place, and differ under each change of coping."""
    from docking.world import DockingEnv

    home = DockingEnv(untested.DESIGN.cell("home/paper").config.world, seed=0)
    poses = [home.sample_start_pose() for _ in range(100)]

    def views(world):
        env = DockingEnv(world, seed=0)
        return np.array([np.asarray(env.reset_to(p).observation) for p in poses])

    at_home = views(home.config)
    for place in ("along the wall", "another wall", "second room"):
        cell = untested.DESIGN.cell(f"{place}/paper")
        assert np.array_equal(views(cell.test_world), at_home), place
    for change, world in untested.CHANGES.items():
        if change != "actuator":  # a step length changes no view
            assert (views(world) != at_home).any(axis=(1, 2)).mean() > 0.9, change
