"""The yardstick policies and the episode loop."""

import numpy as np
import pytest

from docking.policies import (
    RandomPolicy,
    always_forward,
    centroid_rule,
    evaluate_policy,
    oracle,
    run_episode,
    run_oracle_trial,
)
from docking.world import BACKWARD, FORWARD, LEFT, RIGHT, DockingEnv, WorldConfig


def _image(column: int) -> np.ndarray:
    image = np.zeros((10, 32), dtype=np.float32)
    image[4:7, column - 1 : column + 2] = 1.0
    return image


def test_centroid_rule_steps_towards_the_red():
    assert centroid_rule(_image(4)) == LEFT
    assert centroid_rule(_image(28)) == RIGHT
    assert centroid_rule(_image(16)) == FORWARD and centroid_rule(_image(15)) == FORWARD
    assert centroid_rule(np.zeros((10, 32))) == BACKWARD
    with pytest.raises(ValueError, match="2-D"):
        centroid_rule(np.zeros(320))


def test_centroid_rule_reads_the_landmark_as_the_learner_must():
    # From the left of the landmark (+y) the landmark appears on the right of the image.
    env = DockingEnv(WorldConfig(step_noise_xy=0.0, step_noise_yaw_deg=0.0), seed=0)
    assert centroid_rule(env.reset_to([-0.9, 0.2, 0.0]).observation) == RIGHT
    assert centroid_rule(env.reset_to([-0.9, -0.2, 0.0]).observation) == LEFT
    assert centroid_rule(env.reset_to([-0.9, 0.0, 0.0]).observation) == FORWARD


def test_episodes_are_seeded_and_the_oracle_docks():
    a = evaluate_policy(DockingEnv(seed=4), oracle, 20)
    b = evaluate_policy(DockingEnv(seed=4), oracle, 20)
    assert [e.success for e in a] == [e.success for e in b]
    np.testing.assert_array_equal(a[3].poses, b[3].poses)
    assert np.mean([e.success for e in a]) >= 0.95
    for e in a:
        assert len(e.poses) == e.steps + 1 and e.steps <= 25
    ok, steps, poses = run_oracle_trial(DockingEnv(seed=4))
    assert ok == a[0].success and steps == a[0].steps
    np.testing.assert_array_equal(poses, a[0].poses)


def test_random_and_forward_policies():
    policy = RandomPolicy(np.random.default_rng(0))
    actions = [policy(None) for _ in range(400)]
    assert set(actions) == {0, 1, 2, 3}
    assert always_forward(None) == FORWARD
    episode = run_episode(DockingEnv(seed=1), always_forward)
    assert set(episode.actions.tolist()) == {FORWARD}
    with pytest.raises(ValueError, match="n_trials"):
        evaluate_policy(DockingEnv(seed=1), always_forward, 0)
    with pytest.raises(ValueError, match="rng"):
        RandomPolicy(0)
