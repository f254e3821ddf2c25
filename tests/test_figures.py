"""Tests of docking.figures: every figure is written (png and pdf) from fresh and re-loaded
results; the receptive-field algebra; the trajectory sample shows failures."""

import dataclasses

import numpy as np
import pytest
from matplotlib.figure import Figure

from docking import figures
from docking.experiments import EXPERIMENT_1, EXPERIMENT_2, Curriculum, run_experiment
from docking.network import Network, NetworkConfig
from docking.store import load_result, save_result
from docking.world import ACTION_LETTERS, DockingEnv

TINY = dict(train_trials=4, test_trials=6, eval_every=2, eval_trials=2)


@pytest.fixture(scope="module")
def result1():
    return run_experiment(dataclasses.replace(EXPERIMENT_1, **TINY), seed=0, progress=False)


@pytest.fixture(scope="module")
def result2():
    curriculum = Curriculum(far_initial=EXPERIMENT_2.curriculum.far_initial, grow_trials=2)
    config = dataclasses.replace(EXPERIMENT_2, curriculum=curriculum, **TINY)
    return run_experiment(config, seed=0, progress=False)


@pytest.fixture(scope="module")
def loaded2(result2, tmp_path_factory):
    path = save_result(result2, tmp_path_factory.mktemp("results") / "seed0.npz")
    return load_result(path)


@pytest.fixture(scope="module")
def env():
    return DockingEnv(seed=0)


def _assert_written(fig, path):
    assert isinstance(fig, Figure)
    for suffix in (".png", ".pdf"):
        out = path.with_suffix(suffix)
        assert out.exists() and out.stat().st_size > 1000, out
    # The atomic writes leave no temporary files behind.
    assert not [p for p in path.parent.iterdir() if p.name.startswith(".")]


def test_fig2_scene(env, tmp_path):
    path = tmp_path / "fig2_scene.png"
    _assert_written(figures.fig2_scene(env, path), path)


def test_fig3(result1, env, tmp_path):
    path = tmp_path / "fig3"
    _assert_written(figures.fig3(result1, env, path), path)


def test_fig4_from_fresh_and_loaded_results(result2, loaded2, tmp_path):
    for name, result in (("fresh", result2), ("loaded", loaded2)):
        path = tmp_path / f"fig4_{name}.pdf"
        _assert_written(figures.fig4(result, path, n_samples=40), path)


def test_mean_winning_inputs_average_the_views_each_unit_wins():
    # Two hand-made feature units: one sees the left half of the image, one the right half;
    # action F is best for the left unit, action R for the right one.
    world = EXPERIMENT_1.world
    rows, cols = world.camera.input_shape
    W = np.zeros((2, rows * cols))
    W[0].reshape(rows, cols)[:, : cols // 2] = 1.0
    W[1].reshape(rows, cols)[:, cols // 2 :] = 1.0
    W /= np.linalg.norm(W, axis=1, keepdims=True)
    Q = np.zeros((4, 2))
    Q[ACTION_LETTERS.index("F"), 0] = 1.0
    Q[ACTION_LETTERS.index("R"), 1] = 1.0
    net = Network.from_weights(NetworkConfig(n_inputs=rows * cols, n_features=2), W, Q)
    action_mean, unit_mean, action_counts, unit_counts = figures.mean_winning_inputs(
        net, world, n=60, seed=1
    )
    assert action_mean.shape == (4, rows, cols) and unit_mean.shape == (2, rows, cols)
    assert unit_counts.sum() == 60 and action_counts.sum() == 60
    np.testing.assert_array_equal(
        action_counts[[ACTION_LETTERS.index("F"), ACTION_LETTERS.index("R")]], unit_counts
    )
    for j, side in ((0, slice(0, cols // 2)), (1, slice(cols // 2, cols))):
        if unit_counts[j]:  # the unit's mean view has more landmark on its own side
            other = slice(cols // 2, cols) if j == 0 else slice(0, cols // 2)
            assert unit_mean[j][:, side].sum() > unit_mean[j][:, other].sum()
    assert unit_counts.min() > 0  # the start region puts the landmark on both sides
    with pytest.raises(ValueError, match="n"):
        figures.mean_winning_inputs(net, world, n=0)


def test_fig5(result1, loaded2, tmp_path):
    for name, result in (("e1", result1), ("e2", loaded2)):
        path = tmp_path / f"fig5_{name}"
        _assert_written(figures.fig5(result, path, n=4), path)


def test_learning_curves_with_one_or_both_experiments(result1, result2, loaded2, tmp_path):
    for name, (r1, r2) in {
        "both": ([result1], [result2, loaded2]),
        "only1": ([result1], []),
        "only2": ([], [loaded2]),
    }.items():
        path = tmp_path / f"curves_{name}"
        _assert_written(figures.fig_learning_curves(r1, r2, path), path)
    with pytest.raises(ValueError):
        figures.fig_learning_curves([], [], tmp_path / "none")


def test_receptive_fields_are_rows_of_W_and_of_QW():
    rows, cols = 10, 32
    config = NetworkConfig(n_inputs=rows * cols, n_features=2, n_actions=4)
    W = np.zeros((2, rows * cols))
    W[0, 0] = 1.0  # top-left pixel
    W[1, 1 * cols + 5] = 1.0  # row 1, column 5 (row-major, as Network.prepare flattens)
    Q = np.array([[1.0, 0.0], [0.0, 2.0], [0.5, 0.5], [0.0, 0.0]])
    action_rf, feature_rf = figures.receptive_fields(Network.from_weights(config, W, Q))
    assert feature_rf.shape == (2, rows, cols) and action_rf.shape == (4, rows, cols)
    assert feature_rf[0, 0, 0] == 1.0 and feature_rf[1, 1, 5] == 1.0
    assert feature_rf.sum() == 2.0
    for i in range(4):  # RF_i = sum_j Q_ij W_j
        expected = sum(Q[i, j] * W[j] for j in range(2)).reshape(rows, cols)
        np.testing.assert_array_equal(action_rf[i], expected)
    assert action_rf[1, 1, 5] == 2.0 and action_rf[2, 0, 0] == 0.5
    with pytest.raises(ValueError):
        figures.receptive_fields(Network.from_weights(config, W, Q), shape=(8, 32))


def test_paper_action_order_is_L_R_F_B():
    assert [ACTION_LETTERS[i] for i in figures.PAPER_ACTION_ORDER] == list("LRFB")


def test_sample_trials_is_seeded_representative_and_shows_failures():
    success = np.array([True] * 95 + [False] * 5)
    chosen = figures.sample_trials(success, 10, seed=0)
    assert len(chosen) == len(set(chosen)) == 10
    assert np.sum(~success[chosen]) == 3  # round(10 * 5%) = 0 < 3: at least three failures
    np.testing.assert_array_equal(chosen, figures.sample_trials(success, 10, seed=0))
    many_fail = np.array([True] * 30 + [False] * 70)
    assert np.sum(~many_fail[figures.sample_trials(many_fail, 10, seed=1)]) == 7
    all_ok = np.ones(5, dtype=bool)
    assert len(figures.sample_trials(all_ok, 30, seed=0)) == 5


def test_view_poses_see_the_landmark_from_the_named_side(env):
    """The landmark is inside the crop at every example pose, and appears on the right of the
    image from the left of the landmark (and vice versa)."""
    cols = env.config.camera.input_shape[1]
    centre = {}
    for name, pose in figures.VIEW_POSES.items():
        assert env.landmark_in_crop(pose)
        obs = env.reset_to(pose).observation
        centre[name] = np.sum(obs.sum(axis=0) * np.arange(cols)) / obs.sum()
    assert centre["left"] > centre["front"] > centre["right"]
