"""The study's cells are valid, distinct runs with their baselines."""

import dataclasses

import pytest

from docking.experiments import EXPERIMENT_2
from docking.store import config_key
from docking.study import HELDOUT_TRIALS, STUDY_SEEDS, cells, control_cell


def test_cells_are_distinct_runs_judged_on_held_out_trials():
    all_cells = cells() + [control_cell(0.05)]
    keys = [c.key for c in all_cells]
    assert len(set(keys)) == len(keys)
    assert len({config_key(c.config) for c in all_cells}) == len(all_cells)
    by_key = {c.key: c for c in all_cells}
    for c in all_cells:
        assert c.config.heldout_trials == HELDOUT_TRIALS >= 500
        assert c.baseline is None or c.baseline in by_key
        if c.baseline:
            base = by_key[c.baseline].config
            assert c.config.world.scene == base.world.scene
    assert len(STUDY_SEEDS) >= 10


def test_the_paper_cell_trains_exactly_as_experiment_2():
    paper = {c.key: c for c in cells()}["paper"].config
    assert paper.network == EXPERIMENT_2.network and paper.world == EXPERIMENT_2.world
    assert paper.curriculum == EXPERIMENT_2.curriculum
    assert paper.train_trials == EXPERIMENT_2.train_trials


def test_variants_change_only_what_they_name():
    by_key = {c.key: c.config for c in cells()}
    paper = by_key["paper"]
    frozen = dataclasses.replace(by_key["frozen"], network=paper.network, eval_trials=50)
    assert frozen == paper  # only the network (and the skipped learning curve) differ
    assert by_key["frozen"].network.eps_w == 0
    assert by_key["local"].network.rule == "local"
    assert by_key["none"].curriculum.grow_trials == 0
    assert by_key["near-only"].curriculum.far_final == paper.curriculum.far_initial
    assert by_key["cup-test"].world == paper.world and by_key["cup-test"].heldout_world.distractors
    assert by_key["cup"].world.distractors and by_key["cup"].heldout_world is None
    # The effective gradient step eps_W / beta_s is kept.
    for k in ("beta-10", "beta-30"):
        n = by_key[k].network
        assert n.eps_w / n.beta_s == pytest.approx(paper.network.eps_w / paper.network.beta_s)
    assert by_key["floor/paper"].world.scene == "floor"
    assert control_cell(0.07).config.network.feature_delta == 0.07
