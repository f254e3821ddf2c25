"""The rules of the claims nobody had tested (docking.study.designs.untested), pinned before their
runs; the relocations' and changes' effect on the views, measured before any run."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from helpers import unknown_cells, unquoted

from docking.study.designs import third_edition, untested

PAPER = Path(__file__).resolve().parents[2] / "shared" / "paper.md"


def test_seeds_are_fresh():
    used = set(third_edition.SEEDS) | set(third_edition.TUNING_SEEDS) | set(range(10))
    assert not used & set(untested.SEEDS)


def test_comparisons_name_cells_of_the_design():
    assert unknown_cells(untested.DESIGN) == []


def test_its_parts_split_the_cells_and_the_judged_part_holds_the_judged_claims():
    judged, findings = untested.part("judged"), untested.part("findings")
    keys = [c.key for c in judged.cells] + [c.key for c in findings.cells]
    assert sorted(keys) == sorted(c.key for c in untested.DESIGN.cells)
    assert unknown_cells(judged) == [] and findings.claims == ()
    assert {c.key for c in untested.DESIGN.claims if c.judged} <= {c.key for c in judged.claims}
    with pytest.raises(ValueError, match="judged"):
        untested.part("all")


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


def test_ambiguous_views_are_poses_with_one_input_and_different_oracle_actions():
    """Each group of ambiguous start views re-renders to one input byte for byte, and the
    pose oracle acts differently on its poses."""
    from docking.oracle import oracle_action
    from docking.presets import EXPERIMENT_2
    from docking.study.analysis import ambiguous_views
    from docking.world import DockingEnv

    world = EXPERIMENT_2.world
    found = ambiguous_views(world, n=300)
    assert found.views == 300 and found.ambiguous <= found.shared <= found.views
    assert found.groups and found.ambiguous == sum(len(g) for g in found.groups)
    env = DockingEnv(world, seed=1)
    for poses in found.groups:
        inputs = {env.reset_to(p).observation.tobytes() for p in poses}
        assert len(inputs) == 1 and len({oracle_action(p, world) for p in poses}) > 1
    env.close()
    with pytest.raises(ValueError, match="n >= 2"):
        ambiguous_views(world, n=1)


def test_weight_mass_moves_onto_the_landmark_when_W_draws_it():
    """At W's random start the shares are the parts' areas; with every unit's weights set to
    the mean landmark view it wins, the landmark's share rises and the distractor's falls."""
    from docking.experiments import initial_network
    from docking.presets import EXPERIMENT_2
    from docking.study.analysis import mean_winning_inputs, weight_mass
    from docking.study.arrays import MASS_PARTS
    from docking.study.designs.builders import with_cup

    world = with_cup(EXPERIMENT_2.world)
    net = initial_network(EXPERIMENT_2, 0)
    start = weight_mass(net, world, n=150, min_views=3)
    assert start.shape == (len(MASS_PARTS),) and abs(start.sum() - 1) < 1e-12
    assert (start >= 0).all() and start[2] > start[0]  # mostly background
    views = mean_winning_inputs(net, EXPERIMENT_2.world, n=150, seed=0)
    drawn = net.W.copy()
    won = views.unit_counts > 0
    drawn[won] = views.unit_mean[won].reshape(int(won.sum()), -1) + 1e-6
    net.W[:] = drawn
    learned = weight_mass(net, world, n=150, min_views=3)
    assert learned[0] > 2 * start[0] and learned[1] < start[1]
    with pytest.raises(ValueError, match="distractor"):
        weight_mass(net, EXPERIMENT_2.world, n=10)


def test_a_measures_statistic_is_shown_in_its_unit():
    from docking.study.stats import Interval

    shown = {c.key: c.format(Interval(45.0, 34.5, 55.5, ())) for c in untested.CLAIMS}
    assert shown["coping"] == "45 trials [34, 56]"  # trials, whole
    assert shown["continuous-path"] == "45.000 m [34.500, 55.500]"
    assert shown["relocation"] == "4500.0 pp [3450.0, 5550.0]"  # a success difference


def test_a_measure_without_a_unit_is_shown_raw_under_its_name():
    from docking.study.claims import measure_display

    def walked(results, key):
        return results

    assert measure_display(walked) == ("", 3, "walked")
    assert measure_display(untested.regain_trials)[:2] == (" trials", 0)
