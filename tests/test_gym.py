"""The Gymnasium adapter: the env checker, make, seeding, an async vector env, and the
conventions Stable-Baselines3 reads (``is_success``, a flat observation, float32 actions)."""

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import docking
import docking.gym
import docking.gym_ids  # noqa: F401  (registers the ids)
from docking.world import DockingEnv, WorldConfig


def test_check_env_passes():
    env = gymnasium.make(docking.gym.ENV_ID)
    check_env(env.unwrapped, skip_render_check=False)
    env.close()


def test_make_takes_world_fields_and_returns_spaces():
    env = gymnasium.make(docking.gym.ENV_ID, start_far=1.0, max_steps=3, seed=0)
    assert env.unwrapped.config == WorldConfig(start_far=1.0, max_steps=3)
    assert env.observation_space.shape == (10, 32)
    assert env.observation_space.dtype == np.float32
    assert env.action_space.n == 4
    obs, info = env.reset()
    assert obs in env.observation_space
    assert set(info) == {"pose", "docked", "is_success"}
    # Walking backwards never docks: the third action is a time-limit truncation.
    for k in range(3):
        obs, reward, terminated, truncated, info = env.step(1)
        assert reward == 0.0 and not terminated
        assert truncated == (k == 2)
    env.close()


def test_make_rejects_unknown_fields():
    with pytest.raises(TypeError, match="unknown nonsense") as refused:
        gymnasium.make("docking/Experiment2-v0", nonsense=1)
    assert "Docking-v0" not in str(refused.value)  # it named another id than the one made
    with pytest.raises(ValueError, match="WorldConfig.step_forward"):
        gymnasium.make(docking.gym.ENV_ID, step_forward=-1.0)


def test_docking_terminates_with_reward():
    env = gymnasium.make(docking.gym.ENV_ID, seed=0).unwrapped
    env.reset()
    config = env.config
    # Place the robot one forward step short of the dock's centre, facing it.
    env.dm_env.reset_to([-(config.dock_center + config.step_forward), 0.0, 0.0])
    _, reward, terminated, truncated, info = env.step(0)
    assert (reward, terminated, truncated, info["docked"]) == (1.0, True, False, True)
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(0)
    fresh = gymnasium.make(docking.gym.ENV_ID).unwrapped
    with pytest.raises(gymnasium.error.ResetNeeded):
        fresh.step(0)


def _episode(env, seed, actions):
    obs, _ = env.reset(seed=seed)
    observations = [obs]
    for a in actions:
        obs, _, terminated, truncated, _ = env.step(a)
        observations.append(obs)
        if terminated or truncated:
            break
    return np.stack(observations)


def test_same_seed_same_observations_and_matches_dm_env():
    actions = [0, 2, 0, 3, 1, 0, 0]
    env_a = gymnasium.make(docking.gym.ENV_ID)
    env_b = gymnasium.make(docking.gym.ENV_ID)
    first = _episode(env_a, 7, actions)
    np.testing.assert_array_equal(first, _episode(env_b, 7, actions))
    np.testing.assert_array_equal(first, _episode(env_a, 7, actions))  # reseeding again
    assert not np.array_equal(first[0], _episode(env_a, 8, actions)[0])

    # reset(seed=k) is the dm_env's DockingEnv(seed=k), through DockingEnv.reseed.
    dm = DockingEnv(WorldConfig(), seed=7)
    dm_obs = [dm.reset().observation]
    for a in actions[: len(first) - 1]:
        dm_obs.append(dm.step(a).observation)
    np.testing.assert_array_equal(first, np.stack(dm_obs))
    # The constructor's seed is the same as reset(seed=...).
    env_c = gymnasium.make(docking.gym.ENV_ID, seed=7)
    np.testing.assert_array_equal(env_c.reset()[0], first[0])


def test_reseed_replaces_the_generator():
    env = DockingEnv(WorldConfig(), seed=3)
    first = env.reset().observation
    env.reset()
    env.reseed(3)
    np.testing.assert_array_equal(env.reset().observation, first)
    env.reseed(np.random.default_rng(3))
    np.testing.assert_array_equal(env.reset().observation, first)
    with pytest.raises(ValueError, match="seed must be"):
        env.reseed("three")


def test_async_vector_env_with_spawn():
    envs = gymnasium.make_vec(
        docking.gym.ENV_ID,
        num_envs=2,
        vectorization_mode="async",
        vector_kwargs={"context": "spawn"},
    )
    try:
        obs, _ = envs.reset(seed=[1, 2])
        assert obs.shape == (2, 10, 32)
        for _ in range(3):
            obs, reward, terminated, truncated, _ = envs.step(np.array([0, 2]))
            assert obs.shape == (2, 10, 32) and reward.shape == (2,)
        single = gymnasium.make(docking.gym.ENV_ID)
        np.testing.assert_array_equal(single.reset(seed=2)[0], envs.reset(seed=[1, 2])[0][1])
    finally:
        envs.close()


# -- one id per task ------------------------------------------------------------------------


@pytest.mark.parametrize("env_id", sorted(docking.ENV_IDS))
def test_every_task_id_passes_check_env_and_has_its_step_limit(env_id):
    env = gymnasium.make(env_id, seed=0)
    try:
        world = docking.gym.preset_world(docking.ENV_IDS[env_id])
        assert env.unwrapped.config == world
        assert env.spec.max_episode_steps == world.max_steps == 25
        if world.continuous:  # a step vector
            assert env.action_space.shape == (world.n_actions,)
        else:
            assert env.action_space.n == world.n_actions
        check_env(env.unwrapped, skip_render_check=True)
    finally:
        env.close()


def test_the_ids_are_registered_by_importing_docking_gym_ids_alone():
    import subprocess
    import sys

    code = (
        "import gymnasium, docking.gym_ids\n"
        "env = gymnasium.make('docking/Experiment2-v0')\n"
        "print(env.unwrapped.config.start_far, env.spec.max_episode_steps)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["1.5", "25"]


def test_import_docking_imports_no_library_and_registers_nothing():
    """``import docking`` is the package's face (issue 61): it imports none of its modules but
    the rendering defaults (docking.glenv), nor Gymnasium, NumPy or MuJoCo, and registers no
    id; ``docking.gym.register()`` (which PPO's keyed code keeps) registers them all."""
    import subprocess
    import sys

    code = (
        "import sys, docking\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('docking', 'gymnasium', 'numpy', 'mujoco', 'dm_control')))\n"
        "import gymnasium\n"
        "print(sorted(i for i in gymnasium.registry if i.startswith('docking/')))\n"
        "import docking.gym\n"
        "docking.gym.register()\n"
        "print(sorted(i for i in gymnasium.registry if i.startswith('docking/')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    imported, before, after = out.stdout.splitlines()
    assert imported == str(["docking", "docking.glenv"])
    assert before == "[]" and after == str(sorted(docking.ENV_IDS))


def test_an_ids_world_fields_can_be_overridden():
    env = gymnasium.make("docking/Floor-v0", step_forward=0.08)
    assert env.unwrapped.config.scene == "floor" and env.unwrapped.config.step_forward == 0.08
    env.close()
    with pytest.raises(ValueError, match="no preset world"):
        docking.gym.DockingGymEnv(preset="moon")


def test_record_video_writes_an_episode(tmp_path):
    pytest.importorskip("moviepy", reason="the video extra: pip install docking[video]")
    from gymnasium.wrappers import RecordVideo

    env = RecordVideo(
        gymnasium.make("docking/Experiment1-v0", render_mode="rgb_array", seed=0),
        video_folder=str(tmp_path / "videos"),
        episode_trigger=lambda k: True,
        disable_logger=True,
    )
    env.reset(seed=0)
    done = False
    while not done:
        _, _, terminated, truncated, _ = env.step(0)
        done = terminated or truncated
    env.close()
    videos = list((tmp_path / "videos").glob("*.mp4"))
    assert len(videos) == 1 and videos[0].stat().st_size > 1000


def test_the_guide_names_every_id():
    """docs/guide/gymnasium.md's table has a row for each registered id (it once lacked
    Nao-v0 and Continuous-v0)."""
    from pathlib import Path

    guide = Path(__file__).resolve().parent.parent / "docs" / "guide" / "gymnasium.md"
    rows = [line for line in guide.read_text().splitlines() if line.startswith("| `docking/")]
    assert {i for i in docking.ENV_IDS if any(f"`{i}`" in row for row in rows)} == set(
        docking.ENV_IDS
    )


# -- the conventions of reinforcement-learning libraries (Stable-Baselines3) ------------------


def test_is_success_is_docked_on_the_last_step():
    env = gymnasium.make(docking.gym.ENV_ID, seed=0)
    _, info = env.reset()
    assert info["is_success"] is False
    config = env.unwrapped.config
    env.unwrapped.dm_env.reset_to([-(config.dock_center + config.step_forward), 0.0, 0.0])
    _, _, terminated, _, info = env.step(0)
    assert terminated and info["is_success"] is True and info["docked"] is True
    env.reset(seed=0)
    truncated = False
    while not truncated:  # walking backwards never docks: the time limit ends the episode
        _, _, terminated, truncated, info = env.step(1)
        assert not terminated
    assert info["is_success"] is False
    env.close()


@pytest.mark.parametrize("env_id", sorted(docking.ENV_IDS))
def test_the_flat_observation_is_the_grid_row_by_row(env_id):
    grid = gymnasium.make(env_id, seed=3)
    flat = gymnasium.make(env_id, seed=3, observation="flat")
    assert grid.observation_space.shape == (10, 32)  # the documented default is unchanged
    space = flat.observation_space
    assert (space.shape, space.dtype) == ((320,), np.float32)
    assert (space.low.min(), space.high.max()) == (0.0, 1.0)
    first, _ = flat.reset()
    np.testing.assert_array_equal(first, grid.reset()[0].reshape(320))
    action = grid.action_space.sample() if grid.unwrapped.config.continuous else 2
    np.testing.assert_array_equal(flat.step(action)[0], grid.step(action)[0].reshape(320))
    check_env(flat.unwrapped, skip_render_check=True)
    with pytest.raises(ValueError, match="observation must be one of 'grid', 'flat'"):
        gymnasium.make(env_id, observation="image")


def test_continuous_actions_are_float32():
    env = gymnasium.make("docking/Continuous-v0", seed=0)
    assert env.action_space.dtype == np.float32
    assert (env.action_space.low.tolist(), env.action_space.high.tolist()) == ([-1, -1], [1, 1])
    env.action_space.seed(0)
    env.reset(seed=0)
    action = env.action_space.sample()
    assert action.dtype == np.float32
    # The same episode as the adapter (float64 actions) given the same numbers.
    plain = docking.gym.DockingGymEnv(seed=0, preset="continuous")
    plain.reset(seed=0)
    np.testing.assert_array_equal(env.step(action)[0], plain.step(action.astype(np.float64))[0])


def test_a_refused_reset_leaves_the_env_usable():
    """Each refused reset names its argument; the next valid reset and step work (issue 52:
    after a refused reset(seed='0') the first step failed inside Gymnasium's passive env
    checker)."""
    env = gymnasium.make(docking.gym.ENV_ID)
    with pytest.raises(TypeError, match="reset.seed"):
        env.reset(seed="0")
    env.reset(seed=0)
    assert env.step(2)[0].shape == (10, 32)
    with pytest.raises(TypeError, match="reset.options must be None or a dict, got 'abc'"):
        env.reset(options="abc")
    with pytest.raises(ValueError, match="reset.options must be empty.*'start'"):
        env.reset(options={"start": [0, 0, 0]})
    env.reset(seed=0, options={})
    assert env.step(2)[0].shape == (10, 32)


@pytest.mark.parametrize("env_id", sorted(docking.ENV_IDS))
def test_stable_baselines3_check_env_warns_nothing_on_the_flat_observation(env_id):
    sb3_checker = pytest.importorskip(
        "stable_baselines3.common.env_checker", reason="Stable-Baselines3 is not installed"
    )
    import warnings

    env = gymnasium.make(env_id, observation="flat")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sb3_checker.check_env(env)
    assert [str(w.message) for w in caught] == []
    env.close()
