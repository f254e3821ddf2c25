"""The study's cells are valid, distinct runs with their baselines."""

import dataclasses

import numpy as np
import pytest

from docking.experiments import EXPERIMENT_1, EXPERIMENT_2, heldout_trials, run_experiment
from docking.store import config_key
from docking.study import HELDOUT_TRIALS, STUDY_SEEDS, cells, control_cell


def test_cells_are_distinct_runs_judged_on_held_out_trials():
    all_cells = cells(full=True) + [control_cell(0.05)]
    keys = [c.key for c in all_cells]
    assert len(set(keys)) == len(keys)
    trained = [c for c in all_cells if c.test_world is None]
    assert len({config_key(c.config) for c in trained}) == len(trained)
    by_key = {c.key: c for c in all_cells}
    for c in all_cells:
        assert c.config.heldout_trials == HELDOUT_TRIALS >= 500
        assert c.baseline is None or c.baseline in by_key
        if c.baseline:
            assert c.config.world.scene == by_key[c.baseline].config.world.scene
        if c.test_world is not None:  # a test-only cell judges its baseline's networks
            assert c.config == by_key[c.baseline].config
    assert len(STUDY_SEEDS) >= 10
    core = {c.key for c in cells()}
    assert {"paper", "frozen", "none", "near-only", "no-yaw-noise", "cup-test"} <= core
    assert {"floor/paper", "floor/frozen", "floor/none", "exp1/frozen"} <= core


def test_the_paper_cell_trains_exactly_as_experiment_2():
    paper = {c.key: c for c in cells()}["paper"].config
    assert paper.network == EXPERIMENT_2.network and paper.world == EXPERIMENT_2.world
    assert paper.curriculum == EXPERIMENT_2.curriculum
    assert paper.train_trials == EXPERIMENT_2.train_trials


def test_variants_change_only_what_they_name():
    by_key = {c.key: c for c in cells(full=True)}
    paper = by_key["paper"].config
    frozen = dataclasses.replace(by_key["frozen"].config, network=paper.network, eval_trials=50)
    assert frozen == paper  # only the network (and the skipped learning curve) differ
    assert by_key["frozen"].config.network.eps_w == 0
    assert by_key["local"].config.network.rule == "local"
    assert by_key["none"].config.curriculum.grow_trials == 0
    assert by_key["near-only"].config.curriculum.far_final == paper.curriculum.far_initial
    assert by_key["cup-test"].test_world.distractors and not paper.world.distractors
    assert by_key["no-yaw-noise"].test_world.step_noise_yaw_deg == 0
    assert by_key["cup"].config.world.distractors
    for k in ("beta-10", "beta-30"):
        n = by_key[k].config.network
        assert n.eps_w / n.beta_s == pytest.approx(paper.network.eps_w / paper.network.beta_s)
    assert by_key["floor/paper"].config.world.scene == "floor"
    assert control_cell(0.07).config.network.feature_delta == 0.07


def test_held_out_trials_are_paired_across_worlds():
    config = dataclasses.replace(
        EXPERIMENT_1, train_trials=2, test_trials=1, eval_trials=0, heldout_trials=4
    )
    result = run_experiment(config, 5, progress=False)
    again = heldout_trials(config, 5, result.network, config.world)
    np.testing.assert_array_equal(again.poses, result.heldout.poses)
    quiet = dataclasses.replace(config.world, step_noise_yaw_deg=0.0)
    paired = heldout_trials(config, 5, result.network, quiet)
    np.testing.assert_array_equal(paired.starts, result.heldout.starts)  # the same starts
    assert not np.array_equal(paired.poses, result.heldout.poses)  # but other headings
