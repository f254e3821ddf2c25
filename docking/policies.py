"""Yardsticks for the learner: policies that need no learning, and one loop that runs any.

A *policy* is a callable ``policy(observation, env) -> action``. The learner is judged against
these bounds (notebook 05):

* :func:`oracle` reads the robot's true pose (:mod:`docking.oracle`): what a perfect policy
  reaches with these steps, this noise and 25 actions;
* :func:`centroid_rule` reads the pixels like the learner, with one hand-written line: step
  towards the side of the image where the red is, forward when it is centred;
* :func:`always_forward` and :class:`RandomPolicy` show how much of the task the world gives
  away for free.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from docking.oracle import oracle_action, oracle_vector
from docking.scene import BACKWARD, FORWARD, LEFT, N_ACTIONS, RIGHT

if TYPE_CHECKING:
    from docking.world import DockingEnv

__all__ = [
    "Episode",
    "RandomPolicy",
    "always_forward",
    "centroid_offset",
    "centroid_rule",
    "evaluate_policy",
    "oracle",
    "run_episode",
    "run_oracle_trial",
]

#: Half-width of the centroid rule's dead band, in input columns (1 column = 5 camera pixels,
#: about 1.9 deg): within it the landmark counts as centred. Our choice, not tuned.
CENTROID_DEAD_BAND = 1.0


@dataclasses.dataclass(frozen=True)
class Episode:
    """One trial of a policy: ``success``, ``poses`` (start and after each action) and
    ``actions``."""

    success: bool
    poses: np.ndarray
    actions: np.ndarray

    @property
    def steps(self) -> int:
        return len(self.actions)


def run_episode(env: DockingEnv, policy) -> Episode:
    """Run one trial of ``env`` with ``policy(observation, env) -> action``."""
    timestep = env.reset()
    poses, actions = [env.pose], []
    while not timestep.last():
        action = policy(timestep.observation, env)
        actions.append(action)
        timestep = env.step(action)
        poses.append(env.pose)
    success = timestep.discount == 0.0 and timestep.reward > 0
    dtype = np.float64 if env.config.continuous else np.int64  # vectors or indices
    return Episode(bool(success), np.array(poses), np.array(actions, dtype=dtype))


def evaluate_policy(env: DockingEnv, policy, n_trials: int) -> list[Episode]:
    """``n_trials`` episodes of ``policy`` in ``env`` (whose seed decides the starts)."""
    if isinstance(n_trials, bool) or not isinstance(n_trials, (int, np.integer)) or n_trials < 1:
        raise ValueError(f"n_trials must be an integer >= 1, got {n_trials!r}")
    return [run_episode(env, policy) for _ in range(int(n_trials))]


def oracle(observation, env: DockingEnv):
    """The pose-reading oracle (:func:`docking.oracle.oracle_action`, or with continuous
    actions :func:`docking.oracle.oracle_vector`); ignores the pixels."""
    if env.config.continuous:
        return oracle_vector(env.pose, env.config)
    return oracle_action(env.pose, env.config)


def run_oracle_trial(env: DockingEnv) -> tuple[bool, int, np.ndarray]:
    """One trial of the oracle: ``(success, actions taken, poses)``; ``poses`` holds the
    start pose and the pose after every action."""
    episode = run_episode(env, oracle)
    return episode.success, episode.steps, episode.poses


def always_forward(observation, env=None) -> int:
    """Step forward, whatever the robot sees."""
    return FORWARD


class RandomPolicy:
    """Uniformly random actions of ``env``'s action set (the paper's four without an ``env``)
    from its own seeded generator."""

    def __init__(self, rng: np.random.Generator):
        if not isinstance(rng, np.random.Generator):
            raise ValueError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        self._rng = rng

    def __call__(self, observation, env=None) -> int:
        n = N_ACTIONS if env is None else env.config.n_actions
        return int(self._rng.integers(n))


def centroid_offset(images) -> np.ndarray:
    """Where the red lies across the image: the column of the red mass's centroid minus the
    image's central column (negative: left of centre), for one ``(rows, cols)`` image or a
    stack ``(..., rows, cols)``; NaN for an image with no red."""
    images = np.asarray(images, dtype=np.float64)
    cols = images.shape[-1]
    total = images.reshape(*images.shape[:-2], -1).sum(axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        # np.einsum, not @: numpy's own loop, the same on every CPU (docking.arith)
        columns = np.arange(cols, dtype=np.float64)
        centroid = np.einsum("...j,j->...", images.sum(axis=-2), columns) / total
    return centroid - (cols - 1) / 2


def centroid_rule(observation, env=None, dead_band: float = CENTROID_DEAD_BAND) -> int:
    """Step towards the red: LEFT if the red pixels' centroid lies left of the image's centre
    by more than ``dead_band`` columns, RIGHT if right, FORWARD if centred; BACKWARD if
    nothing red is seen (the landmark left the crop; stepping back brings it into view)."""
    image = np.asarray(observation, dtype=np.float64)
    if image.ndim != 2:
        raise ValueError(f"observation must be a 2-D image, got shape {image.shape}")
    if image.sum() <= 0:
        return BACKWARD
    offset = float(centroid_offset(image))
    if offset < -dead_band:
        return LEFT
    if offset > dead_band:
        return RIGHT
    return FORWARD
