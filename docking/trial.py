"""SARSA trials (Kleesiek et al. 2011, Sec. II-A): a :class:`~docking.network.Network` acting in
any ``dm_env.Environment``.

Environment contract: ``reset()`` returns a first ``TimeStep`` whose observation has
``net.config.n_inputs`` elements (the world's (10, 32) float32 image); ``step(action)`` takes an
int in ``[0, n_actions)``.  Docking ends the episode by *termination* (reward 1, discount 0);
running out of steps ends it by *truncation* (reward 0, discount 1).  An environment may have a
``pose`` attribute (``[x, y, yaw]``), which is then recorded after reset and after every action.

One step of the loop (on-policy SARSA, Eq. 6, with the network's learning rule Eq. 7-8)::

    s  = features(I),  a ~ Eq. (4),  v = Q[a] . s                     (Eq. 1-5)
    r, I' = env.step(a);  s' = features(I'),  a' ~ Eq. (4),  v' = Q[a'] . s'
    delta = r + gamma * discount * v' - v                             (Eq. 6)
    update(I, s, a, delta)                                            (Eq. 7, 8)
    I, a = I', a';  s, v recomputed from I' with the updated weights

The next action ``a'`` is chosen with the weights *before* the update (as in Sutton & Barto's
SARSA); the next ``s`` and ``v`` are recomputed after it, so that every ``delta`` and every
gradient uses the current weights.

End of an episode:

* termination (``discount == 0``): ``v' = 0``; no next action is sampled.
* truncation at the step limit (``discount > 0`` on the last step): by default the target
  bootstraps from ``v' = Q[a'] . s'`` (``a'`` sampled but never executed).  The step limit is
  not part of what the network sees, so treating the last state as worthless (``v' = 0``)
  would teach it that an arbitrary, possibly good, state has no value (Pardo et al. 2018,
  "Time Limits in Reinforcement Learning").  ``bootstrap_on_truncation=False`` uses
  ``v' = 0`` instead (the classic episodic treatment).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from docking import arith

from .network import Network
from .validate import FieldTypeError, check_bool, check_instance, check_real

__all__ = ["TrialRecord", "run_trial"]


@dataclass
class TrialRecord:
    """What happened in one trial of ``T`` actions.

    Attributes:
        poses: (T+1, 3) ``env.pose`` (``[x, y, yaw]``) at the start and after each action, or
            None if the environment has no ``pose`` attribute.
        actions: (T,) int, the executed action indices.
        rewards: (T,) float, the reward after each action.
        deltas: (T,) float, the TD error of Eq. (6) at each step (computed also when not
            learning).
        winners: (T,) int, index of the most active feature unit (argmax s) at each decision.
        success: True if the trial ended by termination (docking) with a positive reward.
    """

    poses: np.ndarray | None
    actions: np.ndarray
    rewards: np.ndarray
    deltas: np.ndarray
    winners: np.ndarray
    success: bool

    @property
    def steps(self) -> int:
        """Number of actions taken, T."""
        return int(self.actions.shape[0])


def run_trial(
    env,
    net: Network,
    rng: np.random.Generator,
    *,
    learn: bool,
    beta_a: float | None = None,
    bootstrap_on_truncation: bool = True,
    feature_delta: Callable[[float], float] | None = None,
) -> TrialRecord:
    """Run one episode of ``env`` with ``net`` choosing actions by Eq. (4); SARSA learning if
    ``learn`` (Eq. 6-8), otherwise the weights are left untouched.

    Args:
        env: a ``dm_env.Environment`` following the contract in the module docstring.
        net: the network; updated in place when ``learn`` is True.
        rng: the only source of randomness here (action sampling).
        learn: update ``net`` after every step.
        beta_a: action inverse temperature of Eq. (4); default ``net.config.beta_a_train``
            when learning, ``net.config.beta_a_test`` otherwise.
        bootstrap_on_truncation: at the step limit (truncation, discount > 0) use
            ``v' = Q[a'] . s'`` (True, default) or ``v' = 0`` (False); see the module docstring.
        feature_delta: the permutation control's source of the delta Eq. (8) uses
            (``net.config.permute_delta``; required there when learning): called with each
            learning step's delta, it returns the delta to use instead
            (:class:`docking.experiments.DeltaShuffle`).

    Returns:
        A :class:`TrialRecord`.
    """
    learn, bootstrap_on_truncation = _check_arguments(
        env, net, rng, learn, bootstrap_on_truncation, feature_delta
    )
    cfg = net.config
    if beta_a is None:
        beta_a = cfg.beta_a_train if learn else cfg.beta_a_test  # Eq. (4)
    beta_a = check_real("run_trial", "beta_a", beta_a, lo=0)
    log = _Log(hasattr(env, "pose"))
    ts = env.reset()
    log.pose(env)
    I = net.prepare(ts.observation)
    s = net.features(I)  # Eq. (1), (2)
    a = net.select_action(s, rng, beta_a)  # Eq. (3), (4)
    winner = int(s.argmax())  # the state the decision was based on
    while True:
        v = arith.dot(net.Q[a], s)  # Eq. (5), with the current weights
        log.act(a, winner)
        ts = env.step(a)
        log.pose(env)
        r, discount = float(ts.reward), float(ts.discount)
        following = _following(ts, net, rng, beta_a, bootstrap_on_truncation)
        delta = r + cfg.gamma * discount * following.v - v  # Eq. (6)
        log.outcome(r, delta)
        if learn:
            permuted = feature_delta(delta) if cfg.permute_delta else None
            net.update(I, s, a, delta, permuted)  # Eq. (7), (8)
        if ts.last():
            return log.record(success=discount == 0.0 and r > 0.0)
        I, a, winner = following.I, following.a, following.winner
        s = net.features(I) if learn else following.s  # current weights


class _Following(NamedTuple):
    """What follows a step (:func:`_following`): the next input, features, action and its
    winning unit, and the value ``v'`` of Eq. (6)."""

    I: np.ndarray | None
    s: np.ndarray | None
    a: int | None
    winner: int | None
    v: float


def _following(ts, net: Network, rng, beta_a: float, bootstrap_on_truncation: bool):
    """The next input, features, action (``a'``, drawn from ``rng`` by Eq. (4)) and ``v'``
    after the time step ``ts``: ``v' = 0`` and nothing drawn at termination, or at
    truncation unless ``bootstrap_on_truncation`` (see the module docstring)."""
    if ts.last() and (float(ts.discount) == 0.0 or not bootstrap_on_truncation):
        return _Following(None, None, None, None, 0.0)  # termination (or treated as one)
    I_next = net.prepare(ts.observation)
    s_next = net.features(I_next)
    a_next = net.select_action(s_next, rng, beta_a)
    return _Following(
        I_next, s_next, a_next, int(s_next.argmax()), arith.dot(net.Q[a_next], s_next)
    )


class _Log:
    """A trial's record as it happens (:class:`TrialRecord`)."""

    def __init__(self, has_pose: bool):
        self.has_pose = has_pose
        self.poses: list[np.ndarray] = []
        self.actions: list[int] = []
        self.rewards: list[float] = []
        self.deltas: list[float] = []
        self.winners: list[int] = []

    def pose(self, env) -> None:
        if self.has_pose:
            self.poses.append(np.array(env.pose, dtype=np.float64))

    def act(self, a: int, winner: int) -> None:
        self.winners.append(winner)
        self.actions.append(a)

    def outcome(self, r: float, delta: float) -> None:
        self.rewards.append(r)
        self.deltas.append(delta)

    def record(self, success: bool) -> TrialRecord:
        return TrialRecord(
            poses=np.array(self.poses) if self.has_pose else None,
            actions=np.array(self.actions, dtype=np.int64),
            rewards=np.array(self.rewards, dtype=np.float64),
            deltas=np.array(self.deltas, dtype=np.float64),
            winners=np.array(self.winners, dtype=np.int64),
            success=bool(success),
        )


def _check_arguments(env, net, rng, learn, bootstrap_on_truncation, feature_delta):
    """:func:`run_trial`'s arguments checked: ``(learn, bootstrap_on_truncation)`` as bools, or
    ``FieldTypeError``/``ValueError`` naming the bad one."""
    check_instance("run_trial", "net", net, Network)
    check_instance("run_trial", "rng", rng, np.random.Generator)
    learn = check_bool("run_trial", "learn", learn)
    bootstrap_on_truncation = check_bool(
        "run_trial", "bootstrap_on_truncation", bootstrap_on_truncation
    )
    if not (callable(getattr(env, "reset", None)) and callable(getattr(env, "step", None))):
        raise FieldTypeError(
            f"run_trial.env must be a dm_env.Environment (reset() and step()), got "
            f"{type(env).__name__}"
        )
    if learn and net.config.permute_delta and not callable(feature_delta):
        raise FieldTypeError(
            "run_trial.feature_delta must be a callable (the permuted delta) when learning with "
            f"NetworkConfig.permute_delta, got {feature_delta!r}"
        )
    return learn, bootstrap_on_truncation
