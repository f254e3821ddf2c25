"""What any learner's run computes with: its worlds, its streams and its judgement on the
held-out trials (the computing half of the learner protocol; :mod:`docking.study.learners` is the
other half, the registration, and docs/guide/bring_your_own_learner.md the guide).

A run of any learner, the paper's, PPO or one from outside the package, is judged the same
way: after training, its greedy policy acts in ``world`` from the start poses and step noise
of the *held-out* stream of its seed (child ``heldout_world`` of
``numpy.random.SeedSequence(seed)``, :func:`streams`), which no training and no other test
draws from. So a learner's run of seed ``k`` meets the same first held-out start pose as the
paper's learner's and PPO's runs of seed ``k`` (later trials are paired only while their paths
agree: a trial that ends sooner draws fewer step noises) and its held-out success is compared
with theirs seed by seed, as the third edition's contest compares them.

This module is keyed: a learner registered from outside the package
(:func:`docking.study.learners.register`) has its runs keyed by this module's code and every
``docking`` module it imports (the world, the camera, the streams of
:mod:`docking.experiments`), besides the learner's own code.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from docking.experiments import TrialLog, _streams, policy_trial
from docking.scene import WorldConfig
from docking.validate import MAX_COUNT, MAX_SEED, check_instance, check_int

if TYPE_CHECKING:  # the task needs OpenGL: imported where an environment is made
    from docking.world import DockingEnv

__all__ = [
    "LearnerResult",
    "heldout_env",
    "heldout_log",
    "judge",
    "streams",
    "training_env",
]


@dataclasses.dataclass
class LearnerResult:
    """A run of a learner registered with :func:`docking.study.learners.register`.

    Attributes:
      config: The learner's configuration.
      seed: The run's seed.
      heldout: The greedy held-out trials (:func:`heldout_log`: the held-out streams of
        ``seed``, ``config.heldout_trials`` of them, in ``config.world``).
      train_steps: The environment steps the learner trained for (its budget used).
      wall_time_train: Seconds of training (None: filled in by the runner, the run's time
        minus ``wall_time_test``).
      wall_time_test: Seconds of the held-out trials.
    """

    config: Any
    seed: int
    heldout: TrialLog
    train_steps: int
    wall_time_train: float | None = None
    wall_time_test: float = 0.0

    @property
    def heldout_success(self) -> float:
        """The share of held-out trials that docked."""
        return self.heldout.success_rate


def streams(seed: int) -> dict[str, np.random.Generator]:
    """The independent random streams of run ``seed``, fresh (the same for every learner):
    ``train_world``, ``train_actions``, ``init``, ..., ``heldout_world`` (the held-out
    trials' starts and noise: :func:`heldout_env`) and ``heldout_actions``. A learner may
    draw from any of them but ``heldout_world``; :func:`judge` draws that one."""
    return _streams(check_int("streams", "seed", seed, lo=0, hi=MAX_SEED))


def training_env(world: WorldConfig, seed: int) -> DockingEnv:
    """A :class:`docking.world.DockingEnv` of ``world`` whose start poses and step noise come
    from the ``train_world`` stream of ``seed`` (the paper's learner's training stream)."""
    from docking.world import DockingEnv

    check_instance("training_env", "world", world, WorldConfig)
    return DockingEnv(world, seed=streams(seed)["train_world"])


def heldout_env(world: WorldConfig, seed: int) -> DockingEnv:
    """A :class:`docking.world.DockingEnv` of ``world`` on the held-out stream of ``seed``:
    the one every learner's held-out trials are drawn from."""
    from docking.world import DockingEnv

    check_instance("heldout_env", "world", world, WorldConfig)
    return DockingEnv(world, seed=streams(seed)["heldout_world"])


def heldout_log(
    world: WorldConfig,
    seed: int,
    n_trials: int,
    policy: Callable,
    on_trials: Callable[[int], None] | None = None,
) -> TrialLog:
    """``n_trials`` trials of ``policy(observation, env) -> action`` (greedy: no learning)
    in ``world`` on the held-out stream of ``seed``, logged as the paper's learner's and PPO's
    held-out trials are (no TD errors: 0; no winning unit: -1); ``on_trials(1)`` after each."""
    n_trials = check_int("heldout_log", "n_trials", n_trials, lo=0, hi=MAX_COUNT)
    env = heldout_env(world, seed)
    records = []
    for _ in range(n_trials):
        records.append(policy_trial(env, _yours(policy)))
        if on_trials is not None:
            on_trials(1)
    return TrialLog.from_records(records, [world.start_far] * len(records))


def _yours(policy: Callable) -> Callable:
    """``policy`` with each action it returns checked as the world's step checks it, before
    the step: a bad one is an error that says the policy returned it (the step's own says
    only "action must be ...")."""
    from docking.world import _check_action, _check_vector_action

    def checked(observation, env):
        action = policy(observation, env)
        check = _check_vector_action if env.config.continuous else _check_action
        try:
            check(action, env.config.action_names)
        except ValueError as exc:
            raise ValueError(f"your policy returned {action!r:.80}: {exc}") from None
        return action

    return checked


def judge(
    config,
    seed: int,
    policy: Callable,
    train_steps: int,
    on_trials: Callable[[int], None] | None = None,
) -> LearnerResult:
    """The end of a learner's run: its trained ``policy(observation, env) -> action`` judged
    on ``config.heldout_trials`` held-out trials of ``config.world`` (:func:`heldout_log`),
    timed, with the ``train_steps`` environment steps it trained for: the run's
    :class:`LearnerResult`."""
    t0 = time.perf_counter()
    log = heldout_log(config.world, seed, config.heldout_trials, policy, on_trials)
    train_steps = check_int("judge", "train_steps", train_steps, lo=0)
    return LearnerResult(
        config=config,
        seed=seed,
        heldout=log,
        train_steps=train_steps,
        wall_time_test=time.perf_counter() - t0,
    )
