"""Tests of docking.study.analysis: every function returns the arrays it promises, on hand-made
networks and trials whose answers are known."""

import dataclasses
import re

import numpy as np
import pytest

from docking.experiments import TrialLog, initial_network, run_experiment
from docking.network import Network, NetworkConfig
from docking.presets import EXPERIMENT_1
from docking.scene import scene_facts
from docking.study import analysis, arrays
from docking.world import ACTION_LETTERS, DockingEnv, WorldConfig

TINY = dict(train_trials=4, test_trials=6, eval_every=2, eval_trials=2)
L, R, F, B = (ACTION_LETTERS.index(c) for c in "LRFB")


@pytest.fixture(scope="module")
def env():
    return DockingEnv(seed=0)


@pytest.fixture(scope="module")
def result1():
    return run_experiment(dataclasses.replace(EXPERIMENT_1, **TINY), seed=0, progress=False)


def _half_image_network(world: WorldConfig) -> Network:
    """Two feature units: unit 0 sees the left half of the image, unit 1 the right half;
    action F is best for unit 0, action R for unit 1."""
    rows, cols = world.camera.input_shape
    W = np.zeros((2, rows * cols))
    W[0].reshape(rows, cols)[:, : cols // 2] = 1.0
    W[1].reshape(rows, cols)[:, cols // 2 :] = 1.0
    W /= np.linalg.norm(W, axis=1, keepdims=True)
    Q = np.zeros((4, 2))
    Q[F, 0] = 1.0
    Q[R, 1] = 1.0
    return Network.from_weights(NetworkConfig(n_inputs=rows * cols, n_features=2), W, Q)


# -- weights --------------------------------------------------------------------------------


def test_receptive_fields_are_rows_of_W_and_of_QW():
    rows, cols = 10, 32
    config = NetworkConfig(n_inputs=rows * cols, n_features=2, n_actions=4)
    W = np.zeros((2, rows * cols))
    W[0, 0] = 1.0  # top-left pixel
    W[1, 1 * cols + 5] = 1.0  # row 1, column 5 (row-major, as Network.prepare flattens)
    Q = np.array([[1.0, 0.0], [0.0, 2.0], [0.5, 0.5], [0.0, 0.0]])
    action_rf, feature_rf = arrays.receptive_fields(Network.from_weights(config, W, Q))
    assert feature_rf.shape == (2, rows, cols) and action_rf.shape == (4, rows, cols)
    assert feature_rf[0, 0, 0] == 1.0 and feature_rf[1, 1, 5] == 1.0
    assert feature_rf.sum() == 2.0
    for i in range(4):  # RF_i = sum_j Q_ij W_j
        expected = sum(Q[i, j] * W[j] for j in range(2)).reshape(rows, cols)
        np.testing.assert_array_equal(action_rf[i], expected)
    assert action_rf[1, 1, 5] == 2.0 and action_rf[2, 0, 0] == 0.5
    with pytest.raises(ValueError):
        arrays.receptive_fields(Network.from_weights(config, W, Q), shape=(8, 32))


def test_best_actions_and_unused_units():
    Q = np.array([[0.1, 0.0, 0.0], [0.7, 0.0, 0.2], [0.2, 0.0, 0.5], [0.0, 0.0, 0.1]])
    np.testing.assert_array_equal(arrays.best_actions(Q), [1, -1, 2])


def test_strongest_units_frame_the_largest_weight_of_L_R_F():
    Q = np.zeros((4, 3))
    Q[L] = [0.1, 0.9, 0.2]
    Q[R] = [0.0, 0.3, 0.4]
    Q[F] = [0.0, 0.8, 0.1]
    Q[B] = [5.0, 0.0, 0.0]  # B is not framed
    assert arrays.strongest_units(Q) == {1: ["L", "F"], 2: ["R"]}
    Q[R] = 0.0  # no unit votes for R: nothing framed for it
    assert arrays.strongest_units(Q) == {1: ["L", "F"]}


def test_feature_change_is_the_cosine_to_the_initial_weights(result1):
    change = analysis.feature_change(result1)
    start = initial_network(result1.config, result1.seed).W
    assert change.shape == (result1.config.network.n_features,)
    for j in range(len(change)):
        w0, w1 = start[j], result1.network.W[j]
        cosine = w0 @ w1 / (np.linalg.norm(w0) * np.linalg.norm(w1))
        assert change[j] == pytest.approx(cosine, abs=1e-12)
    unchanged = dataclasses.replace(result1, network=initial_network(result1.config, 0))
    np.testing.assert_allclose(analysis.feature_change(unchanged), 1.0)


# -- decisions ------------------------------------------------------------------------------


def test_decide_and_decisions():
    world = WorldConfig()
    net = _half_image_network(world)
    rows, cols = world.camera.input_shape
    left, right = np.zeros((rows, cols)), np.zeros((rows, cols))
    left[:, 2] = 1.0
    right[:, cols - 3] = 1.0
    winner, activation, action = arrays.decide(net, left)
    assert (winner, action) == (0, F) and activation > 0.99  # beta_s = 100: a clear winner
    assert arrays.decide(net, right)[::2] == (1, R)
    d = arrays.decisions(net, np.stack([left, right, left]))
    np.testing.assert_array_equal(d.winners, [0, 1, 0])
    np.testing.assert_array_equal(d.actions, [F, R, F])
    assert d.activations.shape == (3,) and d.winners.dtype == np.int64
    assert len(arrays.decisions(net, []).winners) == 0


# -- views ----------------------------------------------------------------------------------


def test_view_poses_see_the_landmark_from_the_named_side(env):
    """The landmark is inside the crop at every example pose, and appears on the right of the
    image from the left of the landmark (and vice versa)."""
    views = analysis.example_views(env)
    cols = env.config.camera.input_shape[1]
    assert views.names == ("left", "front", "right")
    np.testing.assert_array_equal(views.poses, list(arrays.VIEW_POSES.values()))
    cam = env.config.camera
    assert views.frames.shape == (3, cam.height, cam.width, 3)
    assert views.inputs.shape == (3,) + cam.input_shape
    centre = {}
    for name, pose, obs in zip(views.names, views.poses, views.inputs, strict=True):
        assert env.landmark_in_crop(pose)
        centre[name] = np.sum(obs.sum(axis=0) * np.arange(cols)) / obs.sum()
        # the input is the one the environment gives at that pose
        np.testing.assert_array_equal(obs, env.reset_to(pose).observation)
    assert centre["left"] > centre["front"] > centre["right"]
    with pytest.raises(ValueError, match="three views"):
        analysis.example_views(env, {"a": (-0.7, 0, 0)})


def test_overview_is_an_rgb_render_with_the_dock_drawn(env):
    image = analysis.overview(env, arrays.VIEW_POSES["front"], size=(160, 120))
    assert image.shape == (120, 160, 3) and image.dtype == np.uint8
    yellow = (image[..., 0] > 200) & (image[..., 1] > 180) & (image[..., 2] < 120)
    assert yellow.any()  # the virtual docking region is drawn in overview renders
    np.testing.assert_array_equal(env.pose[:2], arrays.VIEW_POSES["front"][:2])


def test_mean_winning_inputs_average_the_views_each_unit_wins():
    world = EXPERIMENT_1.world
    rows, cols = world.camera.input_shape
    net = _half_image_network(world)
    m = analysis.mean_winning_inputs(net, world, n=60, seed=1)
    assert m.action_mean.shape == (4, rows, cols) and m.unit_mean.shape == (2, rows, cols)
    assert m.unit_counts.sum() == 60 and m.action_counts.sum() == 60
    np.testing.assert_array_equal(m.action_counts[[F, R]], m.unit_counts)
    assert m.unit_counts.min() > 0  # the start region puts the landmark on both sides
    for j, side, other in ((0, slice(0, cols // 2), slice(cols // 2, cols)), (1,) + (None,) * 2):
        if side is None:
            side, other = slice(cols // 2, cols), slice(0, cols // 2)
        # the unit's mean view has more landmark on its own side
        assert m.unit_mean[j][:, side].sum() > m.unit_mean[j][:, other].sum()
    # An action never chosen has a zero mean, not NaN.
    assert np.all(m.action_mean[L] == 0) and np.all(np.isfinite(m.action_mean))
    with pytest.raises(ValueError, match="n"):
        analysis.mean_winning_inputs(net, world, n=0)


# -- trials ---------------------------------------------------------------------------------


def test_sample_trials_is_seeded_representative_and_shows_failures():
    success = np.array([True] * 95 + [False] * 5)
    chosen = arrays.sample_trials(success, 10, seed=0)
    assert len(chosen) == len(set(chosen)) == 10
    assert np.all(np.diff(chosen) > 0)
    assert np.sum(~success[chosen]) == 3  # round(10 * 5%) = 0 < 3: at least three failures
    np.testing.assert_array_equal(chosen, arrays.sample_trials(success, 10, seed=0))
    many_fail = np.array([True] * 30 + [False] * 70)
    assert np.sum(~many_fail[arrays.sample_trials(many_fail, 10, seed=1)]) == 7
    all_ok = np.ones(5, dtype=bool)
    assert len(arrays.sample_trials(all_ok, 30, seed=0)) == 5


def _log(trials) -> TrialLog:
    """A TrialLog from ``[(poses, actions, success)]``."""
    return TrialLog(
        success=np.array([t[2] for t in trials], dtype=bool),
        steps=np.array([len(t[1]) for t in trials], dtype=np.int64),
        start_far=np.full(len(trials), 1.5),
        poses=np.concatenate([np.asarray(t[0], dtype=np.float64) for t in trials]),
        actions=np.concatenate([np.asarray(t[1], dtype=np.int64) for t in trials]),
        winners=np.zeros(sum(len(t[1]) for t in trials), dtype=np.int64),
        deltas=np.zeros(sum(len(t[1]) for t in trials)),
    )


def test_trajectory_sample_returns_the_chosen_paths():
    trials = [
        ([(-1.0, 0, 0), (-0.9, 0, 0)], [F], k % 3 != 0) for k in range(9)
    ]  # trials 0, 3, 6 fail
    log = _log(trials)
    sample = arrays.trajectory_sample(log, n=4, seed=2)
    np.testing.assert_array_equal(sample.indices, arrays.sample_trials(log.success, 4, 2))
    assert (sample.n_trials, sample.n_docked) == (9, 6)
    for k, path, ok in zip(sample.indices, sample.paths, sample.success, strict=True):
        np.testing.assert_array_equal(path, log.trial_poses(k))
        assert ok == log.success[k]


def test_failure_taxonomy_classifies_hand_made_trials(env):
    cfg = env.config
    assert cfg.max_steps == 25 and cfg.dock_center == 0.48 and cfg.dock_width == 0.20
    contact_x = -0.35 - scene_facts().robot_radius  # the sideboard's front is at x = -0.35
    T = cfg.max_steps
    yaw15 = np.radians(15)
    trials = {
        # docked from straight ahead: no class
        "clean": ([(-0.8, 0, 0), (-0.65, 0, 0), (-0.48, 0, 0)], [F, F], True),
        # the heading drifts to 15 deg (and back): heading_drift only
        "drift": ([(-0.8, 0, 0), (-0.8, 0, yaw15), (-0.7, 0, 0.0)], [F, F], False),
        # a step far to the side: the landmark leaves the crop
        "lost": ([(-0.8, 0, 0), (-0.8, 0.6, 0), (-0.75, 0.0, 0)], [L, R], False),
        # walks backwards: ends farther from the dock than it started
        "farther": ([(-0.7, 0, 0), (-0.85, 0, 0)], [B], False),
        # L R L R: three immediate reversals
        "oscillating": (
            [(-0.7, 0, 0), (-0.7, 0.1, 0), (-0.7, 0, 0), (-0.7, 0.1, 0), (-0.7, 0.0, 0)],
            [L, R, L, R],
            False,
        ),
        # the step limit ends it 6 cm before the docking region (x = -0.58; the region spans
        # -0.52..-0.44)
        "timed_out_near": (
            [(-0.7, 0, 0)] + [(-0.58, 0, 0)] * T,
            [B, F] * (T // 2) + [F] * (T % 2),
            False,
        ),
        # pressed against the sideboard 15 cm beside the dock's centre line (the region is
        # 10 cm to either side)
        "pressed": ([(-0.6, 0.15, 0), (contact_x, 0.15, 0)], [F], False),
    }
    flags = analysis.failure_taxonomy(_log(list(trials.values())), env)
    assert set(flags) == set(arrays.FAILURE_CLASSES)
    names = list(trials)
    table = {name: {c for c in flags if flags[c][k]} for k, name in enumerate(names)}
    assert table["clean"] == set()
    assert table["drift"] == {"heading_drift"}
    assert table["lost"] == {"landmark_lost"}  # one L-R reversal is not oscillating
    assert table["farther"] == {"ended_farther"}
    assert table["oscillating"] == {"oscillating"}
    assert table["timed_out_near"] == {"timed_out_near"}  # B F B F are not sidesteps
    assert table["pressed"] == {"pressed_beside_dock"}
    # The thresholds are parameters: a 20 deg limit does not flag the 15 deg drift, a 1 cm
    # "near" does not flag a robot 6 cm from the region, 4 reversals are not 3.
    strict = analysis.failure_taxonomy(
        _log(list(trials.values())), env, heading_deg=20, near_m=0.01, min_reversals=4
    )
    assert not strict["heading_drift"].any()
    assert not strict["timed_out_near"].any()
    assert not strict["oscillating"].any()
    with pytest.raises(ValueError):
        analysis.failure_taxonomy(_log(list(trials.values())), env, heading_deg=0)


def test_floor_plan_names_the_sideboard():
    plan = analysis.floor_plan(WorldConfig())
    assert set(plan) == {"sideboard", "landmark_slab", "landmark_post", "dock"}
    x0, y0, x1, y1 = plan["sideboard"]
    assert x0 == pytest.approx(-0.35) and x0 < 0 < x1 and y0 == -y1
    dock = plan["dock"]
    assert dock[0] == pytest.approx(-0.52) and dock[2] == pytest.approx(-0.44)


# -- learning curves ------------------------------------------------------------------------


def test_mean_curve_uses_the_shared_points_and_ignores_nan():
    xs = [np.array([0, 10, 20, 30]), np.array([0, 10, 20])]
    ys = [np.array([0.0, 0.5, np.nan, 1.0]), np.array([0.2, 0.7, np.nan])]
    points, mean = arrays.mean_curve(xs, ys)
    np.testing.assert_array_equal(points, [0, 10, 20])
    np.testing.assert_allclose(mean[:2], [0.1, 0.6])
    assert np.isnan(mean[2])  # no value in any run stays NaN
    _, m = arrays.mean_curve(
        [np.array([0, 10]), np.array([0, 10])], [np.array([1.0, np.nan]), np.array([0.0, 0.4])]
    )
    np.testing.assert_allclose(m, [0.5, 0.4])


def test_learning_curves_of_several_seeds(result1):
    other = run_experiment(result1.config, seed=1, progress=False)
    curves = arrays.learning_curves([result1, other])
    assert curves.seeds == (0, 1) and curves.config == result1.config
    np.testing.assert_array_equal(curves.mean_trials, result1.curve_trials)
    np.testing.assert_allclose(
        curves.mean_success, (result1.curve_success + other.curve_success) / 2
    )
    np.testing.assert_array_equal(
        curves.final_success, [r.test.success_rate for r in (result1, other)]
    )
    np.testing.assert_array_equal(curves.final_trials, [TINY["train_trials"]] * 2)
    np.testing.assert_array_equal(curves.rewarded[1], other.curve_rewarded)
    assert len(curves.start_far) == 2 and len(curves.start_far[0]) == TINY["train_trials"]
    with pytest.raises(ValueError):
        arrays.learning_curves([])
    different = dataclasses.replace(result1, config=dataclasses.replace(result1.config, name="x"))
    with pytest.raises(ValueError, match="one configuration"):
        arrays.learning_curves([result1, different])


def test_floor_plan_and_taxonomy_of_the_floor_scene():
    from docking.experiments import TrialLog
    from docking.presets import FLOOR_WORLD
    from docking.study.analysis import failure_taxonomy, floor_plan
    from docking.world import DockingEnv

    plan = floor_plan(FLOOR_WORLD)
    assert "sideboard" not in plan and {"landmark_slab", "dock"} <= set(plan)
    # A trial that ended pressed against the landmark's front, beside the region.
    end_x = plan["landmark_slab"][0] - 0.10
    poses = np.array([[-1.0, 0.2, 0.0], [end_x, 0.2, 0.0]])
    log = TrialLog(
        success=np.array([False]),
        steps=np.array([1]),
        start_far=np.array([1.5]),
        poses=poses,
        actions=np.array([0]),
        winners=np.array([0]),
        deltas=np.array([0.0]),
    )
    flags = failure_taxonomy(log, DockingEnv(FLOOR_WORLD, seed=0))
    assert flags["pressed_beside_dock"][0] and not flags["heading_drift"][0]


def test_winner_change_counts_views_whose_winner_or_action_moved():
    from docking.network import Network, NetworkConfig
    from docking.study.arrays import winner_change

    config = NetworkConfig(n_inputs=4, n_features=2, n_actions=2)
    W0 = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    W1 = np.array([[0, 0, 1.0, 0], [0, 1.0, 0, 0]])  # unit 0 now reads input 2
    Q = np.array([[1.0, 0.0], [0.0, 1.0]])  # unit 0 -> action 0, unit 1 -> action 1
    start, end = Network.from_weights(config, W0, Q), Network.from_weights(config, W1, Q)
    views = np.array([[1.0, 0.1, 0, 0], [0, 1.0, 0, 0], [0, 0.2, 1.0, 0], [0, 1.0, 0.1, 0]])
    # view 0: unit 0 -> unit 1; view 2: unit 1 -> unit 0; views 1, 3 unchanged.
    assert winner_change(start, end, views) == (0.5, 0.5)
    assert winner_change(end, end, views) == (0.0, 0.0)


def test_start_views_are_seeded_start_observations():
    from docking.study.analysis import start_views
    from docking.world import WorldConfig

    views = start_views(WorldConfig(), 4, seed=3)
    assert views.shape == (4, 10, 32) and views.dtype == np.float32
    assert np.all(views.sum(axis=(1, 2)) > 0)  # the landmark is in every start view
    np.testing.assert_array_equal(views, start_views(WorldConfig(), 4, seed=3))
    with pytest.raises(ValueError, match="n must be"):
        start_views(WorldConfig(), 0, seed=3)


def test_rewarded_share_counts_the_far_training_trials():
    from types import SimpleNamespace

    trials = [
        ([(-1.2, 0, 0), (-1.0, 0, 0)], [F], True),
        ([(-0.8, 0, 0), (-0.6, 0, 0)], [F], False),
        ([(-0.7, 0, 0), (-0.5, 0, 0)], [F], True),
    ]
    run = SimpleNamespace(train=_log(trials), config=SimpleNamespace(world=WorldConfig()))
    np.testing.assert_allclose(arrays.rewarded_share([run]), [2 / 3])
    # Below half the start region's near edge every trial counts, without reading starts.
    starts_unread = SimpleNamespace(success=run.train.success)
    np.testing.assert_allclose(
        arrays.rewarded_share([SimpleNamespace(train=starts_unread, config=run.config)]),
        [2 / 3],
    )
    np.testing.assert_allclose(arrays.rewarded_share([run], beyond=0.75), [0.5])
    assert np.isnan(arrays.rewarded_share([run], beyond=2.0)[0])


def test_the_failure_taxonomy_of_chosen_trials_reads_only_their_poses():
    result = run_experiment(
        dataclasses.replace(EXPERIMENT_1, train_trials=3, test_trials=6, eval_trials=0),
        1,
        progress=False,
    )
    log = result.test
    env = DockingEnv(EXPERIMENT_1.world, seed=0)
    every = analysis.failure_taxonomy(log, env)
    some = analysis.failure_taxonomy(log, env, trials=[1, 4])
    for name in arrays.FAILURE_CLASSES:
        np.testing.assert_array_equal(some[name][[1, 4]], every[name][[1, 4]])
        assert not some[name][[0, 2, 3, 5]].any()
    with pytest.raises(ValueError, match="must index the log's 6 trials"):
        analysis.failure_taxonomy(log, env, trials=[6])


@pytest.mark.parametrize("scene", ["sideboard", "floor"])
def test_the_taxonomys_crop_check_is_landmark_in_crop_bit_for_bit(scene):
    # failure_taxonomy's landmark_lost looks the geoms and the camera up once; it must give
    # what DockingEnv.landmark_in_crop(pose, margin=0) gives, to the bit, from any pose
    # (near the crop's edges too), and leave the robot where it stood.
    from docking.presets import FLOOR_WORLD

    world = WorldConfig() if scene == "sideboard" else FLOOR_WORLD
    env = DockingEnv(world, seed=0)
    rng = np.random.default_rng(5)
    n = 600
    poses = np.column_stack(
        [rng.uniform(-2.0, -0.3, n), rng.uniform(-0.8, 0.8, n), rng.uniform(-0.9, 0.9, n)]
    )
    before = env.pose
    check = analysis._CropCheck(env)
    inside = []
    for pose in poses:
        ours = check.uv(pose)
        env.physics.place(pose)
        theirs = env.physics.project(env.physics.landmark_corners(), "eye", world.camera)
        assert ours.tobytes() == theirs.tobytes()
        inside.append(env.landmark_in_crop(pose, margin=0))
        assert check(pose) == inside[-1]
    assert 0.1 < np.mean(inside) < 0.9  # both outcomes are tried
    env.physics.place(before)
    assert analysis.landmark_lost(env, poses) == (not all(inside))
    assert analysis.landmark_lost(env, poses[np.array(inside)]) is False
    np.testing.assert_array_equal(env.pose, before)


def test_the_oracle_labelled_q_gives_each_unit_its_views_most_frequent_action():
    """Three units, each the direction of a group of views; the oracle acts 2, 3 and 0 on
    the groups, once otherwise on the first: Q's labels and the partition's purity."""
    config = NetworkConfig(n_features=4, n_inputs=320)
    W = np.zeros((4, 320))
    W[0, :10], W[1, 10:20], W[2, 20:30], W[3, 300:] = 1.0, 1.0, 1.0, 1.0
    W /= np.linalg.norm(W, axis=1, keepdims=True)
    Q = np.zeros((4, 4))
    Q[1, 3] = 1.0  # unit 3 wins no view: it keeps its own best action (1)
    net = Network.from_weights(config, W, Q)
    views = np.zeros((7, 320))
    for i, group in enumerate((0, 0, 0, 1, 1, 2, 2)):
        views[i, 10 * group : 10 * group + 10] = 1.0 + i
    actions = np.array([2, 2, 1, 3, 3, 0, 0])
    labelled = arrays.OracleViews(views, actions)
    assert list(analysis.winners(net, views)) == [0, 0, 0, 1, 1, 2, 2]
    labelled_net = analysis.oracle_labelled(net, labelled)
    assert list(labelled_net.Q.argmax(axis=0)) == [2, 3, 0, 1]
    assert np.array_equal(labelled_net.W, net.W)
    assert analysis.partition_purity(net, labelled) == pytest.approx(6 / 7)


def test_landscape_puts_each_settings_mean_and_runs_on_its_grid_point():
    scores = {(2.0, 0.05): [0.3, 0.5], (100.0, 0.5): [0.9], (7.0, 0.5): [1.0], (2.0, 5.0): []}
    grid = arrays.landscape(scores, [2.0, 100.0], [0.05, 0.5, 5.0])
    assert grid.mean[0, 0] == pytest.approx(0.4) and grid.n[0, 0] == 2
    assert grid.mean[1, 1] == pytest.approx(0.9) and grid.n[1, 1] == 1
    assert np.isnan(grid.mean[0, 2]) and grid.n[0, 2] == 0  # no runs: blank
    assert int(grid.n.sum()) == 3  # the off-grid setting (7, 0.5) is left out


def test_share_near_best_counts_the_settings_within_the_margin():
    assert arrays.share_near_best([0.95, 0.91, 0.89, 0.3]) == (2, 4)
    assert arrays.share_near_best([0.5]) == (1, 1)
    assert arrays.share_near_best([]) == (0, 0)


def test_centroid_rows_weigh_each_row_by_its_intensity():
    views = np.zeros((3, 10, 32))
    views[0, 2, :] = 1.0  # all in row 2
    views[1, 4, 0], views[1, 6, 0] = 1.0, 3.0  # (4 + 18) / 4
    found = arrays.centroid_rows(views)
    assert found[0] == pytest.approx(2.0) and found[1] == pytest.approx(5.5)
    assert np.isnan(found[2])  # an empty view has no centroid


def test_view_shift_is_zero_in_the_same_world_and_signed_by_the_landmarks_move():
    from docking.study.designs import revisited as rv

    assert np.all(analysis.view_shift(rv._HOME, rv._HOME, n=5) == 0)
    places = rv.places()
    higher, lower = (analysis.view_shift(rv._HOME, places[p], n=5) for p in sorted(places))
    assert len(lower) == len(higher) == 5
    assert np.all(np.sign(lower) == -np.sign(higher)) and np.all(lower != 0)


# -- a trial log's columns, sample efficiency, the oracle's views (issue 61) -----------------


def test_actions_and_heading_error_of_the_docked_trials():
    """The mean actions of the docked trials, and their mean |heading error| at the end
    (0 for a robot facing the landmark from straight in front of it); NaN if none docked."""
    ahead = [(-1.0, 0, 0), (-0.9, 0, 0), (-0.8, 0, 0)]
    tilted = [(-1.0, 0, 0), (-0.8, 0, np.radians(10))]
    log = _log([(ahead, [F, F], True), (tilted, [F], True), (ahead, [L, R], False)])
    assert arrays.actions_per_docking(log) == 1.5
    assert arrays.docked_heading_error_deg(log) == pytest.approx(5.0)
    failed = _log([(ahead, [L, R], False)])
    assert np.isnan(arrays.actions_per_docking(failed))
    assert np.isnan(arrays.docked_heading_error_deg(failed))


def test_trials_to_level_reads_each_runs_learning_curve():
    from types import SimpleNamespace

    def run(success):
        return SimpleNamespace(
            curve_trials=np.array([0, 100, 200]),
            curve_success=np.array(success),
            config=SimpleNamespace(name="x"),
            seed=0,
        )

    found = arrays.trials_to_level([run([0.2, 0.95, 1.0]), run([0.0, 0.5, 0.8])], 0.9)
    np.testing.assert_array_equal(found[:1], [100.0])
    assert np.isnan(found[1])
    with pytest.raises(ValueError):
        arrays.trials_to_level([run([0.1, 0.2, 0.3])], 0.0)


def test_oracle_views_are_the_oracle_trials_views_and_actions():
    """Every view of the pose oracle's trials (observations as the network's flat input)
    with the oracle's action there, read-only; the same again from the same stream."""
    from docking.oracle import oracle_action

    world = WorldConfig()
    found = analysis.oracle_views(world, 2, 0)
    assert found.views.shape == (len(found.actions), int(np.prod(world.camera.input_shape)))
    assert not found.views.flags.writeable and not found.actions.flags.writeable
    env = DockingEnv(world, seed=0)
    step = env.reset()
    assert np.array_equal(found.views[0], np.asarray(step.observation, dtype=float).ravel())
    assert found.actions[0] == oracle_action(env.pose, world)


def test_every_function_of_arrays_and_analysis_is_tested_by_name():
    """CONTRIBUTING's recipe for a figure: each function that computes a figure's arrays has
    a test; a new one without one fails here."""
    from pathlib import Path

    tests = "".join(p.read_text() for p in Path(__file__).parent.glob("test_*.py"))
    untested = [
        f"{module.__name__}.{name}"
        for module in (arrays, analysis)
        for name in module.__all__
        if callable(getattr(module, name))
        and not isinstance(getattr(module, name), type)
        and not re.search(rf"\b{name}\(", tests)
    ]
    assert not untested, untested
