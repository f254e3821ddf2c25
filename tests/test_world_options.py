"""The world options, network layer and runner phase that issues 30 and 31 added: the camera's
height, the landmark's shape, the room and its placement (relocation), continuous actions,
the forced single winner, and a network that learns on after a change (``before``)."""

from __future__ import annotations

import dataclasses
import hashlib

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import docking.gym_ids  # noqa: F401  (registers the Gymnasium ids)
from docking.experiments import ExperimentConfig, policy_trial, run_experiment, trials_in_run
from docking.network import Network, NetworkConfig
from docking.policies import evaluate_policy, oracle
from docking.presets import EXPERIMENT_2, NAO_WORLD, RELOCATIONS
from docking.scene import FORWARD, LEFT, TURN_LEFT, WorldConfig
from docking.world import DockingEnv, footprints, make_model, make_model_xml
from tests.helpers import TINY

#: sha256 of the default worlds' MJCF before these options existed (commit 77ffa64): the
#: options leave the home scene as it was, byte for byte.
HOME_XML = {
    "sideboard": "e0a5fff58cb4",
    "floor": "389beb078e25",
}


@pytest.mark.parametrize("scene", sorted(HOME_XML))
def test_the_home_scene_is_unchanged_byte_for_byte(scene):
    xml = make_model_xml(WorldConfig(scene=scene))
    assert hashlib.sha256(xml.encode()).hexdigest()[:12] == HOME_XML[scene]


def test_camera_height_moves_the_eye_alone():
    model = make_model(WorldConfig(camera_height=0.527))
    home = make_model(WorldConfig())
    assert model.cam("eye").pos[2] == pytest.approx(0.527)
    np.testing.assert_array_equal(model.cam("eye").pos[:2], home.cam("eye").pos[:2])
    with pytest.raises(ValueError, match="camera_height"):
        WorldConfig(camera_height=5.0)


def test_the_slab_shape_has_no_post_and_is_seen():
    config = WorldConfig(landmark_shape="slab")
    model = make_model(config)
    names = {model.geom(i).name for i in range(model.ngeom)}
    assert "landmark_slab" in names and "landmark_post" not in names
    assert "landmark_post" not in footprints(config)
    env, home = DockingEnv(config, seed=0), DockingEnv(seed=0)
    assert env.physics.landmark_corners().shape == (8, 3)
    pose = [-1.0, 0.0, 0.0]
    seen, at_home = env.reset_to(pose).observation, home.reset_to(pose).observation
    assert 0 < seen.sum() < at_home.sum()
    with pytest.raises(ValueError, match="landmark_shape"):
        WorldConfig(landmark_shape="star")


@pytest.mark.parametrize("name", sorted(RELOCATIONS))
def test_a_relocated_landmark_sees_the_same_and_the_oracle_docks(name):
    # The landmark keeps its frame: the same pose gives the same view where no furniture is
    # in the way, and the pose oracle docks as at home (no furniture in the walking region).
    world = RELOCATIONS[name]
    env, home = DockingEnv(world, seed=0), DockingEnv(seed=0)
    for pose in ([-1.0, 0.0, 0.0], [-0.7, 0.1, 0.1]):
        np.testing.assert_array_equal(
            env.reset_to(pose).observation, home.reset_to(pose).observation
        )
    episodes = evaluate_policy(DockingEnv(world, seed=1), oracle, 100)
    assert np.mean([e.success for e in episodes]) >= 0.99


def test_the_room_moves_and_the_landmark_stays():
    moved = make_model(RELOCATIONS["another wall"])
    home = make_model(WorldConfig())
    for name in ("landmark_slab", "landmark_post", "sideboard", "dock"):
        np.testing.assert_array_equal(moved.geom(name).pos, home.geom(name).pos)
    assert moved.body("room").pos[:2].tolist() == [-1.75, 1.375]
    second = make_model(WorldConfig(room="second"))
    names = {second.body(i).name for i in range(second.nbody)}
    assert "second_bookcase" in names and "sofa" not in names
    with pytest.raises(ValueError, match="room"):
        WorldConfig(room="attic")


def test_a_continuous_step_of_one_is_the_discrete_step():
    # The same noise draws: a component of +-1 is the discrete step, bit for bit.
    cases = [("continuous", [1.0, 0.0], FORWARD), ("continuous", [0.0, 1.0], LEFT)]
    cases += [("continuous-turning", [0.0, 0.0, 1.0], TURN_LEFT)]
    for actions, vector, index in cases:
        discrete = "turning" if actions == "continuous-turning" else "paper"
        a = DockingEnv(WorldConfig(actions=actions), seed=3)
        b = DockingEnv(WorldConfig(actions=discrete), seed=3)
        a.reset(), b.reset()
        a.step(vector), b.step(index)
        np.testing.assert_array_equal(a.pose, b.pose)


@pytest.mark.parametrize("action", [[2.0, 0.0], [0.0], [np.nan, 0.0], "f", 1])
def test_a_bad_continuous_action_raises(action):
    env = DockingEnv(WorldConfig(actions="continuous"), seed=0)
    env.reset()
    with pytest.raises(ValueError, match="in \\[-1, 1\\]"):
        env.step(action)


def test_the_continuous_oracle_docks_in_fewer_actions():
    world = EXPERIMENT_2.world
    steps = {}
    for actions in ("paper", "continuous"):
        env = DockingEnv(dataclasses.replace(world, actions=actions), seed=2)
        episodes = evaluate_policy(env, oracle, 40)
        assert np.mean([e.success for e in episodes]) >= 0.95
        steps[actions] = np.mean([e.steps for e in episodes])
        record = policy_trial(env, oracle)
        assert record.actions.dtype == np.int64
        assert (record.actions == -1).all() == (actions == "continuous")
    assert steps["continuous"] < steps["paper"]


@pytest.mark.parametrize("env_id", ["docking/Continuous-v0", "docking/Nao-v0"])
def test_the_new_gymnasium_ids_pass_check_env(env_id):
    env = gymnasium.make(env_id, seed=0)
    check_env(env.unwrapped, skip_render_check=True)
    if env_id == "docking/Continuous-v0":
        assert isinstance(env.action_space, gymnasium.spaces.Box)
        assert env.action_space.shape == (2,)
        turning = gymnasium.make(env_id, actions="continuous-turning")
        assert turning.action_space.shape == (3,)


def test_the_nao_world_is_its_specification():
    model = make_model(NAO_WORLD)
    assert model.cam("eye").pos[2] == pytest.approx(0.527)
    assert model.cam("eye").fovy[0] == pytest.approx(36.8)
    assert (NAO_WORLD.step_forward, NAO_WORLD.step_side) == (0.08, 0.072)
    assert NAO_WORLD.scene == "floor" and NAO_WORLD.max_steps == 25


def test_a_continuous_world_takes_the_oracle_alone():
    world = dataclasses.replace(EXPERIMENT_2.world, actions="continuous")
    with pytest.raises(ValueError, match="continuous actions"):
        dataclasses.replace(EXPERIMENT_2, world=world)
    yardstick = dataclasses.replace(
        EXPERIMENT_2, world=world, policy="oracle", train_trials=0, eval_trials=0
    )
    assert ExperimentConfig.from_dict(yardstick.to_dict()) == yardstick


def test_the_forced_single_winner_is_one_hot_and_follows_eq_8():
    rng = np.random.default_rng(0)
    I = rng.random(320)
    I /= np.linalg.norm(I)
    for rule, moves in (("nonlocal", False), ("local", True)):
        config = NetworkConfig(n_features=36, feature_layer="winner", rule=rule, q_init=0.5)
        net = Network(config, np.random.default_rng(1))
        s = net.features(I)
        winner = int(np.argmax(net.W @ I))
        assert s.sum() == 1.0 and s[winner] == 1.0
        before = net.W.copy()
        net.update(I, s, 0, 0.5)
        changed = np.flatnonzero(np.abs(net.W - before).max(axis=1) > 1e-12)
        # Eq. (8) with a one-hot s: the bracket of the non-local rule is 0; the local rule
        # moves the winner's row alone (the others are renormalised: rounding only).
        assert changed.tolist() == ([winner] if moves else [])


def test_a_network_learns_on_after_a_change():
    first = TINY
    frozen = dataclasses.replace(TINY.network, eps_q=0.0, eps_w=0.0)
    changed = dataclasses.replace(
        TINY,
        world=dataclasses.replace(TINY.world, step_forward=0.12),
        network=frozen,
        train_trials=2,
        heldout_trials=0,
        before=first,
    )
    assert trials_in_run(changed) == first.train_trials + trials_in_run(
        dataclasses.replace(changed, before=None)
    )
    # With the rates at 0 after the change, the network ends as the first run's ended (W's
    # rows are renormalised after every step: rounding only).
    result = run_experiment(changed, seed=1, progress=False)
    trained = run_experiment(first, seed=1, progress=False).network
    np.testing.assert_allclose(result.network.W, trained.W, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(result.network.Q, trained.Q)
    # The same change from a fresh network trains another one.
    fresh = run_experiment(dataclasses.replace(changed, before=None), seed=1, progress=False)
    assert not np.array_equal(fresh.network.W, trained.W)
    assert ExperimentConfig.from_dict(changed.to_dict()) == changed
    with pytest.raises(ValueError, match="n_features"):
        dataclasses.replace(
            changed, before=dataclasses.replace(first, network=NetworkConfig(n_features=36))
        )
