"""A learner defined outside the package (tests/test_learners.py): SARSA on a few random
features of the pixels, registered as a kind of run of its own. Its module imports only
docking.study.learners (not followed for its key) and docking.scene, so its runs are keyed by this
file's code, docking.protocol's and docking.scene's (and what they import)."""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.scene import WorldConfig
from docking.study import learners


@dataclasses.dataclass(frozen=True)
class RandomFeatures:
    """SARSA(0) on ``features`` random projections of the 320 pixels, squashed by tanh."""

    name: str = "outside"
    world: WorldConfig = WorldConfig(start_near=0.58, start_far=0.8)
    heldout_trials: int = 3
    train_trials: int = 2
    features: int = 8
    alpha: float = 0.05
    epsilon: float = 0.2


def run(config, seed, progress=True, on_trials=None):
    rngs = learners.streams(seed)
    env, rng = learners.training_env(config.world, seed), rngs["train_actions"]
    n_actions = config.world.n_actions
    P = rngs["init"].normal(0.0, 1.0 / 18, (config.features, 320))
    w = np.zeros((n_actions, config.features))

    def phi(observation):
        return np.tanh(P @ np.asarray(observation, dtype=np.float64).ravel())

    def choose(x):
        if rng.random() < config.epsilon:
            return int(rng.integers(n_actions))
        return int(np.argmax(w @ x))

    steps = 0
    for _ in range(config.train_trials):
        timestep = env.reset()
        x = phi(timestep.observation)
        a = choose(x)
        while not timestep.last():
            timestep = env.step(a)
            steps += 1
            x2 = phi(timestep.observation)
            a2 = choose(x2)
            target = timestep.reward + 0.9 * timestep.discount * (w[a2] @ x2)
            w[a] += config.alpha * (target - w[a] @ x) * x
            x, a = x2, a2
        if on_trials is not None:
            on_trials(1)
    return learners.judge(
        config, seed, lambda o, _env: int(np.argmax(w @ phi(o))), steps, on_trials
    )


RUNNER = learners.register(RandomFeatures, run, name="random-features")
