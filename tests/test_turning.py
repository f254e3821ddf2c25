"""Tests of the turning action set and precision docking (Experiment 3, issue 11)."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from docking.experiments import ExperimentConfig, TrialLog, run_experiment
from docking.gym import DockingGymEnv
from docking.oracle import oracle_action
from docking.presets import EXPERIMENT_2
from docking.study import analysis, arrays
from docking.study.designs import experiment3, experiment3_report
from docking.study.designs.builders import variant
from docking.world import (
    ACTION_LETTERS,
    FORWARD,
    LEFT,
    RIGHT,
    TURN_LEFT,
    TURN_RIGHT,
    DockingEnv,
    WorldConfig,
    heading_error,
    in_dock,
    in_region,
)

GOLDEN = Path(__file__).parent / "data" / "four_actions_golden.npz"

#: How far a noise-free turn may move the reference point (m): the servos rotate the body
#: about it, contacts aside.
TURN_POSITION_TOL = 0.002

TURNING = WorldConfig(actions="turning")
QUIET_TURNING = WorldConfig(actions="turning", step_noise_xy=0.0, step_noise_yaw_deg=0.0)


def test_four_actions_are_bit_identical_to_before_the_action_set():
    """A short Experiment 2 run of the default (paper) action set equals, array for array,
    the run that tests/data/four_actions_golden.npz recorded with the code before the action
    set became configurable (commit b51b74b; the script is in the file's docstring below)."""
    # Recorded by: EXPERIMENT_2 with train_trials=40, test_trials=20, eval_trials=0,
    # heldout_trials=10, name="golden"; run_experiment(config, 3); every TrialLog array of
    # train/test/heldout, then W and Q.
    config = dataclasses.replace(
        EXPERIMENT_2,
        name="golden",
        train_trials=40,
        test_trials=20,
        eval_trials=0,
        heldout_trials=10,
    )
    # Since the recording, the network's sums are exactly rounded (math.fsum, the same on
    # every Python) instead of the builtin sum(): every decision and pose is still equal bit
    # for bit; TD errors and weights differ in their last bits only.
    result = run_experiment(config, 3, progress=False)
    golden = np.load(GOLDEN)
    for part in ("train", "test", "heldout"):
        log = getattr(result, part)
        for field in ("success", "steps", "poses", "actions", "winners"):
            np.testing.assert_array_equal(getattr(log, field), golden[f"{part}_{field}"])
        np.testing.assert_allclose(log.deltas, golden[f"{part}_deltas"], rtol=0, atol=1e-14)
    np.testing.assert_allclose(result.network.W, golden["W"], rtol=0, atol=1e-14)
    np.testing.assert_allclose(result.network.Q, golden["Q"], rtol=0, atol=1e-14)


def test_action_sets_name_their_actions():
    paper, turning = WorldConfig(), TURNING
    assert paper.action_names == ("forward", "backward", "left", "right")
    assert paper.action_letters == ACTION_LETTERS == ("F", "B", "L", "R")
    assert turning.action_letters == ("F", "B", "L", "R", "TL", "TR")
    assert (paper.n_actions, turning.n_actions) == (4, 6)
    assert DockingEnv(paper, seed=0).action_spec().num_values == 4
    assert DockingEnv(turning, seed=0).action_spec().num_values == 6
    assert DockingGymEnv(actions="turning").action_space.n == 6
    with pytest.raises(ValueError, match="actions"):
        WorldConfig(actions="spin")
    with pytest.raises(ValueError, match="turn_deg"):
        WorldConfig(turn_deg=0.0)
    with pytest.raises(ValueError, match="dock_heading_deg"):
        WorldConfig(dock_heading_deg=-5.0)


def test_a_turn_is_refused_by_the_paper_world_and_taken_by_the_turning_world():
    env = DockingEnv(seed=0)
    env.reset()
    with pytest.raises(ValueError, match=r"0\.\.3 \(forward, backward, left, right\)"):
        env.step(TURN_LEFT)
    env = DockingEnv(TURNING, seed=0)
    env.reset()
    env.step(TURN_RIGHT)
    with pytest.raises(ValueError, match=r"0\.\.5"):
        env.step(6)


def test_network_must_have_an_action_unit_per_action():
    with pytest.raises(ValueError, match="n_actions must equal the 6 actions"):
        dataclasses.replace(EXPERIMENT_2, world=TURNING)
    config = dataclasses.replace(
        EXPERIMENT_2,
        world=TURNING,
        network=dataclasses.replace(EXPERIMENT_2.network, n_actions=6),
    )
    assert isinstance(config, ExperimentConfig)
    assert ExperimentConfig.from_dict(config.to_dict()) == config


@pytest.mark.parametrize("turn_deg", [10.0, 25.0])
@pytest.mark.parametrize("action,sign", [(TURN_LEFT, 1), (TURN_RIGHT, -1)])
def test_a_noise_free_turn_rotates_by_the_angle_in_place(turn_deg, action, sign):
    env = DockingEnv(dataclasses.replace(QUIET_TURNING, turn_deg=turn_deg), seed=0)
    start = np.array([-1.0, 0.1, 0.05])
    env.reset_to(start)
    env.step(action)
    end = env.pose
    assert end[2] - start[2] == pytest.approx(sign * np.radians(turn_deg), abs=1e-3)
    assert np.linalg.norm(end[:2] - start[:2]) <= TURN_POSITION_TOL


def test_heading_error_is_zero_facing_the_landmark():
    assert heading_error([-0.5, 0.0, 0.0]) == pytest.approx(0.0)
    # 10 cm to the left of the axis, the landmark lies to the robot's right
    bearing = np.arctan2(-0.1, 0.5)
    assert heading_error([-0.5, 0.1, bearing]) == pytest.approx(0.0, abs=1e-12)
    assert heading_error([-0.5, 0.1, 0.0]) == pytest.approx(-bearing)
    assert heading_error([-0.5, 0.0, np.radians(350)]) == pytest.approx(np.radians(-10))


def test_precision_docking_refuses_the_wrong_heading_and_accepts_the_right_one():
    precise = WorldConfig(dock_heading_deg=10.0)
    facing = [-0.48, 0.05, np.arctan2(-0.05, 0.48)]
    turned = [-0.48, 0.05, np.arctan2(-0.05, 0.48) + np.radians(15)]
    assert in_region(turned, precise) and not in_dock(turned, precise)
    assert in_dock(facing, precise)
    assert in_dock(turned, WorldConfig())  # the paper's task: the reference point alone
    # Through the environment: a forward step into the region turned 15 deg away does not
    # dock; turning back towards the landmark docks (mid-turn, once within the tolerance).
    env = DockingEnv(dataclasses.replace(QUIET_TURNING, dock_heading_deg=10.0), seed=0)
    env.reset_to([-0.62, 0.0, np.radians(15)])
    timestep = env.step(FORWARD)
    assert in_region(env.pose, env.config) and not env.docked
    assert timestep.mid() and timestep.reward == 0
    timestep = env.step(TURN_RIGHT)
    assert timestep.last() and timestep.reward == 1.0 and timestep.discount == 0.0
    assert abs(heading_error(env.pose)) <= np.radians(10.0) + 1e-9


def test_the_oracle_turns_only_with_turns():
    off = [-1.0, 0.0, np.radians(25)]
    assert oracle_action(off, WorldConfig()) in (FORWARD, LEFT, RIGHT)
    assert oracle_action(off, TURNING) == TURN_RIGHT
    assert oracle_action([-1.0, 0.0, np.radians(-25)], TURNING) == TURN_LEFT
    # within one turn of facing the landmark it walks
    assert oracle_action([-1.0, 0.0, np.radians(5)], TURNING) == FORWARD
    # precision: in the region with the heading outside the tolerance (but within one
    # turn... of 30 deg here) it turns
    wide = dataclasses.replace(TURNING, turn_deg=30.0, dock_heading_deg=10.0)
    assert oracle_action([-0.48, 0.0, np.radians(15)], wide) == TURN_RIGHT


def test_the_six_action_oracle_docks_in_the_hardest_cell():
    # The bound itself (every six-action cell >= 99% over 2500 held-out trials) is asserted
    # by notebook 06 on the oracle's runs; here one seed's 200 trials of the hardest cell.
    cell = experiment3.ORACLE.cell("6 actions, precision, 6 deg")
    result = run_experiment(dataclasses.replace(cell.config, heldout_trials=200), 0)
    assert len(result.heldout) == 200 and result.heldout.success_rate >= 0.98


def test_the_oracle_design_has_one_yardstick_cell_per_cell_of_the_grid():
    cells = experiment3.experiment3_cells()
    assert [c.key for c in experiment3.ORACLE.cells] == [c.key for c in cells]
    for oracle, cell in zip(experiment3.ORACLE.cells, cells, strict=True):
        assert oracle.config.policy == "oracle" and oracle.config.train_trials == 0
        assert oracle.config.world == cell.config.world


def test_experiment3_cells():
    found = experiment3.experiment3_cells()
    assert len(found) == 2 * len(experiment3.TASKS) * len(experiment3.NOISE_DEG)
    assert experiment3.LONGER_KEY not in {c.key for c in found}
    found = experiment3.experiment3_cells(full=True)
    longer = found[-1]
    assert longer.key == experiment3.LONGER_KEY
    six = next(c for c in found if c.key == "6 actions, paper task, 2 deg")
    assert longer.config.train_trials == 2 * six.config.train_trials
    assert longer.config.world == six.config.world and longer.baseline == six.baseline
    assert len({repr(c.config.to_dict()) for c in found}) == len(found)
    paper = variant(EXPERIMENT_2, "study-sideboard", True)  # the studies' paper runs
    first = found[0]
    assert first.key == "4 actions, paper task, 2 deg" and first.config == paper
    for c in found:
        w = c.config.world
        assert c.config.network.n_actions == w.n_actions
        assert (w.actions == "turning") == (c.baseline is not None)
        if c.baseline:
            base = next(b for b in found if b.key == c.baseline).config
            assert dataclasses.replace(base.world, actions="turning") == w
        assert c.config.heldout_trials == 500 and c.config.test_trials == 0


def test_failure_taxonomy_flags_a_wrong_heading_in_the_region():
    env = DockingEnv(dataclasses.replace(TURNING, dock_heading_deg=10.0), seed=0)
    yaw = np.radians(20)
    log = TrialLog(
        success=np.array([False, True]),
        steps=np.array([2, 2]),
        start_far=np.full(2, 1.5),
        poses=np.array(
            [(-0.62, 0, 0), (-0.48, 0, yaw), (-0.48, 0, yaw)]
            + [(-0.62, 0, 0), (-0.48, 0, yaw), (-0.48, 0, 0.0)]
        ),
        actions=np.array([FORWARD, TURN_LEFT, FORWARD, TURN_RIGHT]),
        winners=np.zeros(4, dtype=np.int64),
        deltas=np.zeros(4),
    )
    flags = analysis.failure_taxonomy(log, env)
    assert flags["heading_off_in_region"].tolist() == [True, False]
    # TL then TR counts as a reversal like L then R
    log.actions = np.array([FORWARD, TURN_LEFT, TURN_LEFT, TURN_RIGHT])
    flags = analysis.failure_taxonomy(log, env, min_reversals=1)
    assert flags["oscillating"].tolist() == [False, True]


def _synthetic(rates: dict[str, float], n: int = 200):
    """Experiment 3 results with held-out logs of the given success rates per cell key."""
    from docking.study.design import Results
    from docking.study.designs.builders import SEEDS

    def log(rate, seed):
        success = np.random.default_rng(seed).random(n) < rate
        return TrialLog(
            success=success,
            steps=np.ones(n, dtype=np.int64),
            start_far=np.full(n, 1.5),
            poses=np.tile([[-1.0, 0.0, 0.0], [-0.9, 0.0, 0.0]], (n, 1)),
            actions=np.zeros(n, dtype=np.int64),
            winners=np.zeros(n, dtype=np.int64),
            deltas=np.zeros(n),
        )

    found = experiment3.experiment3_cells()
    heldout = {c.key: [log(rates[c.key], s) for s in SEEDS] for c in found}
    return Results(experiment3.DESIGN, found, {}, heldout)


def test_experiment3_comparisons_table_and_verdict_on_synthetic_results():
    rates = {}
    for c in experiment3.experiment3_cells():
        four = c.key.startswith("4")
        rates[c.key] = 0.90 if four else (0.97 if "paper task" in c.key else 0.91)
    results = _synthetic(rates)
    found = experiment3_report.turning_comparisons(results)
    assert len(found) == len(experiment3.TASKS) * len(experiment3.NOISE_DEG)
    first = found[0]
    assert (first.task, first.noise) == ("paper task", 2.0)
    assert first.gain.estimate == pytest.approx(first.six.estimate - first.four.estimate)
    from docking.study.claims import rate_interval  # each arm's success: the interval for a rate

    assert (first.four, first.six) == tuple(
        rate_interval(results, k) for k in (first.four_key, first.six_key)
    )
    assert 0.5 < first.removed.estimate < 0.9 and first.removed.low > 0.5
    verdict, ci = experiment3_report.rotation_verdict(found, experiment3.ROTATION_RULE)
    assert verdict == "supported" and ci == first.removed
    # the precision rows remove few failures: their interval straddles 0 or lies low
    assert all(c.removed.estimate < 0.3 for c in found if c.task == "precision")
    oracle = {c.key: 1.0 for c in experiment3.experiment3_cells()}
    text = experiment3_report.turning_table(found, oracle)
    assert text.count("\n") == 1 + len(found) and "| paper task | 2 |" in text
    ratio = first.failure_ratio
    assert ratio.estimate == pytest.approx(1 - first.removed.estimate)
    assert ratio.low == pytest.approx(1 - first.removed.high)
    rates = {k: (0.9 if k.startswith("4") else 0.899) for k in rates}
    assert (
        experiment3_report.rotation_verdict(
            experiment3_report.turning_comparisons(_synthetic(rates)), experiment3.ROTATION_RULE
        )[0]
        == "contradicted"
    )


def test_failure_shares_pool_the_seeds_of_a_cell():
    rates = {c.key: 0.8 for c in experiment3.experiment3_cells()}
    results = _synthetic(rates, n=20)
    keys = ["4 actions, paper task, 2 deg"]
    shares, failures = analysis.failure_shares(results, keys)
    assert failures[0] == sum(int((~log.success).sum()) for log in results.logs[keys[0]])
    assert shares.shape == (1, len(arrays.FAILURE_CLASSES))
    assert np.all((shares >= 0) & (shares <= 1))


def test_experiment3_figures_draw_from_arrays():
    from matplotlib.figure import Figure

    from docking.study import figures

    noise = np.array([2.0, 4.0, 6.0])
    ci = np.tile([0.9, 0.85, 0.95], (2, 3, 1))
    series = {"4 actions": ci, "6 actions": ci - 0.1}
    seeds = {k: np.full((2, 3, 10), 0.9) for k in series}
    oracle = {k: np.ones((2, 3)) for k in series}
    fig = figures.fig_experiment3(noise, ["paper task", "precision"], series, seeds, oracle)
    assert isinstance(fig, Figure)
    with pytest.raises(ValueError, match="shape"):
        figures.fig_experiment3(noise, ["one"], series, seeds, oracle)
    shares = np.array([[0.5, np.nan], [0.2, 1.0]])
    assert isinstance(figures.fig_failure_matrix(["a", "b"], ["x", "y"], shares, [4, 0]), Figure)
    with pytest.raises(ValueError):
        figures.fig_failure_matrix(["a"], ["x", "y"], shares, [4])
    fields = np.random.default_rng(0).random((6, 10, 32))
    fig = figures.fig_action_fields(list("FBLRXY"), fields, fields, np.arange(6), "t")
    assert isinstance(fig, Figure)
    with pytest.raises(ValueError):
        figures.fig_action_fields(list("FBLR"), fields, fields, np.arange(6), "t")


def test_mean_inputs_at_given_poses():
    from docking.network import Network, NetworkConfig

    world = TURNING
    net = Network(NetworkConfig(n_actions=6), np.random.default_rng(0))
    poses = np.array([[-1.0, 0.0, 0.0], [-0.8, 0.1, 0.1], [-1.0, 0.0, 0.0]])
    found = analysis.mean_winning_inputs(net, world, poses=poses)
    assert found.action_counts.sum() == 3 and found.action_mean.shape[0] == 6
    env = DockingEnv(world, seed=0)
    views = [env.reset_to(p).observation for p in poses]
    i = [int(np.argmax(net.Q @ net.features(net.prepare(v)))) for v in views]
    chosen = [v for v, a in zip(views, i, strict=True) if a == i[0]]
    np.testing.assert_allclose(found.action_mean[i[0]], np.mean(chosen, axis=0))
    with pytest.raises(ValueError, match="poses"):
        analysis.mean_winning_inputs(net, world, poses=np.zeros((0, 3)))


def test_centroid_offset_of_stacks_and_final_headings():
    from docking.policies import centroid_offset

    images = np.zeros((3, 10, 32))
    images[0, :, 4] = 1  # red on the left
    images[1, :, 27] = 1  # on the right
    found = centroid_offset(images)
    assert found[0] == pytest.approx(4 - 15.5) and found[1] == pytest.approx(27 - 15.5)
    assert np.isnan(found[2])
    rates = {c.key: 0.5 for c in experiment3.experiment3_cells()}
    results = _synthetic(rates, n=10)
    key = "4 actions, paper task, 2 deg"
    headings = experiment3_report.final_headings(results, key)
    assert len(headings) == sum(int((~log.success).sum()) for log in results.logs[key])
    assert np.all(headings == 0)  # the synthetic trials end facing the wall


def test_fig4_follows_the_configured_action_set():
    from docking.network import Network
    from docking.study import figures
    from docking.study.arrays import MeanInputs, receptive_fields, strongest_units

    cell = next(c for c in experiment3.experiment3_cells() if c.key.startswith("6"))
    config = cell.config
    net = Network(config.network, np.random.default_rng(0))
    action_rf, feature_rf = receptive_fields(net, config.world.camera.input_shape)
    n_feat = config.network.n_features
    inputs = MeanInputs(
        action_rf, feature_rf, np.ones(6, dtype=np.int64), np.ones(n_feat, dtype=np.int64)
    )
    fig = figures.fig4(config, 0, action_rf, feature_rf, inputs, strongest_units(net.Q))
    titles = {ax.get_title() for ax in fig.axes}
    assert {"TL", "TR", "L", "R", "F", "B"} <= titles
    assert figures.action_order(config.world) == (2, 3, 0, 1, 4, 5)
    assert figures.action_order(WorldConfig()) == figures.PAPER_ACTION_ORDER
