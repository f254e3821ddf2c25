"""Tests of the experiment runner (issue #4): curriculum, configs, seeding, saving."""

import dataclasses
import os

import numpy as np
import pytest

from docking.experiments import (
    Curriculum,
    DeltaShuffle,
    ExperimentConfig,
    initial_network,
    run_experiment,
    trials_in_run,
)
from docking.presets import EXPERIMENT_1, EXPERIMENT_2
from docking.study.kinds import load_result, result_path, save_result
from docking.study.store import run_or_load

TINY = dataclasses.replace(EXPERIMENT_1, train_trials=4, test_trials=3, eval_every=2, eval_trials=2)


@pytest.fixture(scope="module")
def tiny_result():
    return run_experiment(TINY, seed=3, progress=False)


def test_curriculum_grows_linearly_then_holds():
    c = Curriculum(far_initial=0.7, grow_trials=1400)
    assert c.far_at(0, 1.5) == 0.7
    assert c.far_at(700, 1.5) == pytest.approx(1.1)
    assert c.far_at(1400, 1.5) == 1.5 and c.far_at(1999, 1.5) == 1.5
    assert Curriculum(1.0).far_at(5, 1.2) == 1.2  # no curriculum: always the test region
    with pytest.raises(ValueError, match="far_initial"):
        Curriculum(far_initial=-1.0)
    with pytest.raises(ValueError, match="grow_trials"):
        Curriculum(0.7, grow_trials=-1)


def test_experiment_configs_match_the_paper():
    assert EXPERIMENT_1.network.n_features == 4 and EXPERIMENT_1.network.rule == "local"
    assert EXPERIMENT_1.train_trials == 100
    assert EXPERIMENT_2.network.n_features == 36 and EXPERIMENT_2.network.rule == "nonlocal"
    assert EXPERIMENT_2.train_trials == 2000 and EXPERIMENT_2.test_trials == 725
    assert EXPERIMENT_2.world.start_far == 1.5
    assert EXPERIMENT_2.curriculum.far_initial < EXPERIMENT_2.world.start_far
    for config in (EXPERIMENT_1, EXPERIMENT_2):
        assert config.network.beta_s == 100 and config.network.gamma == 0.9
        assert config.network.beta_a_train == 2 and config.network.beta_a_test == 100
        assert config.world.max_steps == 25


def test_bad_experiment_config_raises():
    with pytest.raises(ValueError, match="far_initial"):  # grows from beyond the test region
        dataclasses.replace(EXPERIMENT_1, curriculum=Curriculum(0.9, grow_trials=10))
    with pytest.raises(ValueError, match="train_trials"):
        dataclasses.replace(EXPERIMENT_1, train_trials=0)


def test_config_survives_a_round_trip_through_a_dict():
    for config in (EXPERIMENT_1, EXPERIMENT_2):
        assert ExperimentConfig.from_dict(config.to_dict()) == config


def test_same_seed_same_run_bit_for_bit(tiny_result):
    again = run_experiment(TINY, seed=3, progress=False)
    np.testing.assert_array_equal(again.network.W, tiny_result.network.W)
    np.testing.assert_array_equal(again.network.Q, tiny_result.network.Q)
    np.testing.assert_array_equal(again.train.poses, tiny_result.train.poses)
    np.testing.assert_array_equal(again.test.actions, tiny_result.test.actions)
    np.testing.assert_array_equal(again.curve_success, tiny_result.curve_success)
    other = run_experiment(TINY, seed=4, progress=False)
    assert not np.array_equal(other.train.poses[:1], tiny_result.train.poses[:1])


def test_the_record_is_complete(tiny_result):
    r = tiny_result
    assert len(r.train) == TINY.train_trials and len(r.test) == TINY.test_trials
    assert len(r.train.poses) == int(np.sum(r.train.steps + 1))
    assert len(r.train.actions) == int(np.sum(r.train.steps))
    for k in range(len(r.train)):
        poses = r.train.trial_poses(k)
        assert len(poses) == r.train.steps[k] + 1
        np.testing.assert_array_equal(poses[0], r.train.starts[k])
    np.testing.assert_array_equal(r.curve_trials, [0, 2, 4])
    assert r.curve_rewarded[-1] <= int(r.train.success.sum())
    assert r.wall_time_train > 0 and r.wall_time_test > 0
    # The learning run starts from initial_network(config, seed).
    # (docking.study.analysis.feature_change compares them; tests/test_analysis.py tests it.)
    assert initial_network(TINY, 3).W.shape == r.network.W.shape


def test_save_load_round_trip(tiny_result, tmp_path):
    path = save_result(tiny_result, tmp_path / "x" / "seed3.npz")
    loaded = load_result(path)
    assert loaded.config == TINY and loaded.seed == 3
    np.testing.assert_array_equal(loaded.network.W, tiny_result.network.W)
    for part in ("train", "test"):
        for field in dataclasses.fields(type(tiny_result.train)):
            np.testing.assert_array_equal(
                getattr(getattr(loaded, part), field.name),
                getattr(getattr(tiny_result, part), field.name),
            )
    assert loaded.rewarded_until_mastery == tiny_result.rewarded_until_mastery
    assert not list(path.parent.glob("*.tmp"))  # the temporary file was renamed away
    umask = os.umask(0)
    os.umask(umask)
    assert (path.stat().st_mode & 0o777) == 0o666 & ~umask  # an ordinary file


def test_run_or_load_reuses_and_keeps_variants_side_by_side(tmp_path):
    first = run_or_load(TINY, 5, results_dir=tmp_path, progress=False)
    path = result_path(TINY, 5, tmp_path)
    stamp = path.stat().st_mtime_ns
    again = run_or_load(TINY, 5, results_dir=tmp_path, progress=False)
    assert path.stat().st_mtime_ns == stamp  # loaded, not re-trained
    np.testing.assert_array_equal(again.network.W, first.network.W)
    # A variant with the same name lives beside the original; neither overwrites the other.
    changed = dataclasses.replace(TINY, test_trials=4)
    rerun = run_or_load(changed, 5, results_dir=tmp_path, progress=False)
    assert len(rerun.test) == 4
    assert result_path(changed, 5, tmp_path) != path
    assert path.stat().st_mtime_ns == stamp
    assert len(run_or_load(TINY, 5, results_dir=tmp_path, progress=False).test) == 3
    assert path.stat().st_mtime_ns == stamp


def test_near_only_curriculum_trains_nearer_than_it_tests():
    c = Curriculum(far_initial=0.7, grow_trials=0, far_final=0.7)
    assert c.far_at(0, 1.5) == 0.7 and c.far_at(1999, 1.5) == 0.7
    grow = Curriculum(far_initial=0.7, grow_trials=10, far_final=1.0)
    assert grow.far_at(5, 1.5) == pytest.approx(0.85) and grow.far_at(10, 1.5) == 1.0
    with pytest.raises(ValueError, match="far_final"):
        dataclasses.replace(EXPERIMENT_2, curriculum=Curriculum(0.7, far_final=1.6))
    config = dataclasses.replace(TINY, curriculum=Curriculum(0.6, far_final=0.6))
    result = run_experiment(config, seed=1, progress=False)
    assert np.all(result.train.start_far == 0.6)
    assert np.all(-result.train.starts[:, 0] <= 0.6 + 1e-9)


def test_heldout_trials_use_their_own_streams_and_change_nothing_else(tiny_result, tmp_path):
    from docking.world import Distractor

    world = dataclasses.replace(TINY.world, distractors=(Distractor.cup(),))
    config = dataclasses.replace(TINY, heldout_trials=5, heldout_world=world)
    result = run_experiment(config, seed=3, progress=False)
    np.testing.assert_array_equal(result.network.W, tiny_result.network.W)
    np.testing.assert_array_equal(result.test.poses, tiny_result.test.poses)
    assert len(result.heldout) == 5
    assert not np.array_equal(result.heldout.starts[:2], result.test.starts[:2])
    path = save_result(result, tmp_path / "r.npz")
    loaded = load_result(path)
    np.testing.assert_array_equal(loaded.heldout.poses, result.heldout.poses)
    assert loaded.config.heldout_world == world
    assert tiny_result.heldout is None


def test_two_stage_pretraining_moves_w_without_delta():
    config = dataclasses.replace(
        TINY,
        network=dataclasses.replace(TINY.network, eps_w=0.0),
        pretrain_trials=3,
        pretrain_rate=0.2,
    )
    result = run_experiment(config, seed=3, progress=False)
    start = initial_network(config, 3).W
    moved = np.flatnonzero(np.abs(result.network.W - start).max(axis=1) > 1e-6)
    assert len(moved) >= 1  # the winners moved towards the frames, SARSA left W alone
    np.testing.assert_allclose(np.linalg.norm(result.network.W, axis=1), 1.0)
    assert result.network.W.min() >= 0


# -- from_dict, the permutation control, the SOM stage --------------------------------------


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: {**d, "extra": 1}, "unknown 'extra'"),
        (lambda d: {k: v for k, v in d.items() if k != "world"}, "missing 'world'"),
        (lambda d: {**d, "network": [1, 2]}, "ExperimentConfig.network must be a mapping"),
        (lambda d: {**d, "world": {**d["world"], "camera": 3}}, "world.camera must be a mapping"),
        (lambda d: {**d, "curriculum": {"grow_trials": 3}}, "missing 'far_initial'"),
        (
            lambda d: {**d, "world": {**d["world"], "distractors": [{"shape": "box"}]}},
            r"distractors\[0\]: missing 'position', 'size'",
        ),
    ],
)
def test_from_dict_names_what_is_wrong_with_a_type_error(change, message):
    with pytest.raises(TypeError, match=message):
        ExperimentConfig.from_dict(change(EXPERIMENT_2.to_dict()))


def test_from_dict_inverts_to_dict_with_every_option():
    from docking.world import Distractor

    config = dataclasses.replace(
        EXPERIMENT_2,
        heldout_world=dataclasses.replace(EXPERIMENT_2.world, distractors=(Distractor.cup(),)),
        network=dataclasses.replace(EXPERIMENT_2.network, permute_delta=True),
        pretrain_rule="som",
        pretrain_trials=3,
    )
    assert ExperimentConfig.from_dict(config.to_dict()) == config
    with pytest.raises(ValueError, match="pretrain_rule"):
        dataclasses.replace(config, pretrain_rule="kohonen")


def test_the_delta_shuffle_returns_earlier_deltas_of_its_window():
    shuffle = DeltaShuffle(np.random.default_rng(0), window=3)
    assert shuffle(1.0) == 0.0  # nothing earlier
    assert shuffle(2.0) == 1.0
    drawn = [shuffle(float(k)) for k in range(3, 200)]
    for k, value in zip(range(3, 200), drawn, strict=True):
        assert value in {k - 3.0, k - 2.0, k - 1.0} or (k == 3 and value in {1.0, 2.0})
    assert len(set(drawn[-60:])) > 30  # draws, not a fixed lag


def test_a_permutation_run_differs_from_the_papers_and_repeats_bit_for_bit():
    permuted = dataclasses.replace(
        TINY, network=dataclasses.replace(TINY.network, permute_delta=True)
    )
    a = run_experiment(permuted, seed=3, progress=False)
    b = run_experiment(permuted, seed=3, progress=False)
    plain = run_experiment(TINY, seed=3, progress=False)
    np.testing.assert_array_equal(a.network.W, b.network.W)
    np.testing.assert_array_equal(a.train.deltas, b.train.deltas)
    assert not np.array_equal(a.network.W, plain.network.W)


def test_som_pretraining_moves_w_and_leaves_the_other_streams_alone():
    som = dataclasses.replace(TINY, pretrain_trials=2, pretrain_rule="som")
    competitive = dataclasses.replace(TINY, pretrain_trials=2)
    a = run_experiment(som, seed=5, progress=False)
    b = run_experiment(competitive, seed=5, progress=False)
    start = initial_network(TINY, 5)
    assert not np.array_equal(a.network.W, b.network.W)
    # The pretraining frames come from their own streams: the first training start is the same.
    np.testing.assert_array_equal(a.train.starts[0], b.train.starts[0])
    assert not np.array_equal(a.network.W, start.W)


def test_on_trials_counts_every_trial_of_a_run_and_changes_nothing():
    config = dataclasses.replace(TINY, pretrain_trials=2, heldout_trials=3)
    counted = []
    a = run_experiment(config, seed=4, progress=False, on_trials=counted.append)
    b = run_experiment(config, seed=4, progress=False)
    assert set(counted) == {1}
    assert sum(counted) == trials_in_run(config) == 2 + 4 + 3 * 2 + 3 + 3
    np.testing.assert_array_equal(a.network.W, b.network.W)
    np.testing.assert_array_equal(a.heldout.success, b.heldout.success)


# -- yardstick runs: a policy that does not learn, through the same runner and store ----------


@pytest.mark.parametrize("policy", ["oracle", "centroid", "forward", "random"])
def test_a_yardstick_run_is_stored_and_loaded_like_a_learners(policy, tmp_path):
    config = dataclasses.replace(
        EXPERIMENT_2, policy=policy, train_trials=0, eval_trials=0, test_trials=4, heldout_trials=3
    )
    result = run_experiment(config, seed=2, progress=False)
    assert len(result.train) == 0 and len(result.curve_trials) == 0
    assert len(result.test) == 4 and len(result.heldout) == 3
    assert (result.heldout.winners == -1).all() and (result.heldout.deltas == 0).all()
    back = load_result(save_result(result, tmp_path / "run.npz"))
    np.testing.assert_array_equal(back.heldout.poses, result.heldout.poses)
    again = run_experiment(config, seed=2, progress=False)
    np.testing.assert_array_equal(again.test.actions, result.test.actions)


def test_a_yardstick_starts_where_the_learner_of_its_seed_starts():
    learner = dataclasses.replace(
        EXPERIMENT_2, train_trials=2, eval_trials=0, test_trials=2, heldout_trials=2
    )
    oracle = dataclasses.replace(learner, policy="oracle", train_trials=0)
    a = run_experiment(learner, seed=6, progress=False)
    b = run_experiment(oracle, seed=6, progress=False)
    np.testing.assert_array_equal(a.test.starts[0], b.test.starts[0])
    np.testing.assert_array_equal(a.heldout.starts[0], b.heldout.starts[0])
    assert b.heldout.success.all()  # the oracle docks from Experiment 2's region


def test_a_yardstick_does_not_learn_and_a_learner_does():
    with pytest.raises(ValueError, match="policy='oracle' does not learn; train_trials=5"):
        dataclasses.replace(EXPERIMENT_2, policy="oracle", train_trials=5, eval_trials=0)
    with pytest.raises(ValueError, match="train_trials must be >= 1 for the learner"):
        dataclasses.replace(EXPERIMENT_2, train_trials=0)
    with pytest.raises(ValueError, match="policy"):
        dataclasses.replace(EXPERIMENT_2, policy="ppo", train_trials=0, eval_trials=0)
