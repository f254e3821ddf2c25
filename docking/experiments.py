"""The paper's two experiments (Sec. II-C, III), configured as data, run, saved and re-loaded.

* Experiment 1: starts close to the docking position, 4 feature units, the local rule,
  100 training trials, then greedy test trials from the same region.
  Paper: after about 25 rewarded trials the robot docks in 100% of trials.
* Experiment 2: 36 feature units, the non-local rule (Eq. 8), "Learning from Easy Missions":
  the start region grows during training until it reaches 1.5 m; 2000 training trials,
  then 725 test trials from the full region. Paper: 95% (690 of 725).

A run is determined by its :class:`ExperimentConfig` and seed, bit for bit: one
``numpy.random.SeedSequence(seed)`` is split into independent streams for the training world,
the test world, the network's initial weights, and the action choices in training and testing.
:mod:`docking.study.store` saves every run, keyed by what produced it, and re-uses it instead of
re-training.
"""

from __future__ import annotations

import dataclasses
import json
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from tqdm.auto import tqdm

from docking.camera import CameraConfig
from docking.network import Network, NetworkConfig
from docking.scene import Distractor, WorldConfig
from docking.trial import TrialRecord, run_trial
from docking.validate import (
    MAX_COUNT,
    MAX_SEED,
    check_bool,
    check_choice,
    check_instance,
    check_int,
    check_name,
    check_real,
    normalise,
)

if TYPE_CHECKING:  # the task itself needs OpenGL: imported where a run starts
    from docking.world import DockingEnv


@dataclasses.dataclass(frozen=True)
class Curriculum:
    """Learning from Easy Missions (Asada et al.; paper Sec. II-C): the far edge of the start
    trapezoid grows linearly from far_initial to the test region's far edge
    (world.start_far) over the first grow_trials training trials and stays there.
    grow_trials = 0 means no curriculum (far_initial is then unused).

    Attributes:
      far_initial: The start region's far edge in the first training trial (m).
      grow_trials: Training trials over which the far edge grows (0: no curriculum).
      far_final: Where the training region's far edge ends (m). None: at the
        test region's (world.start_far). A nearer value trains on a region nearer than
        the one tested (e.g. "near-only" training, grow_trials = 0).
    """

    far_initial: float
    grow_trials: int = 0
    far_final: float | None = None

    def __post_init__(self):
        owner = "Curriculum"
        normalise(
            self,
            far_initial=check_real(owner, "far_initial", self.far_initial, lo=0, lo_open=True),
            grow_trials=check_int(owner, "grow_trials", self.grow_trials, lo=0, hi=MAX_COUNT),
        )
        if self.far_final is not None:
            normalise(
                self, far_final=check_real(owner, "far_final", self.far_final, lo=0, lo_open=True)
            )

    def far_at(self, trial: int, test_far: float) -> float:
        """The far edge of the start region for training trial ``trial`` (0-based), for a test
        region whose far edge is ``test_far``."""
        final = test_far if self.far_final is None else self.far_final
        if self.grow_trials == 0 or trial >= self.grow_trials:
            return final
        return self.far_initial + (final - self.far_initial) * trial / self.grow_trials


#: What can act in a run (:attr:`ExperimentConfig.policy`): the learner, then the yardsticks
#: of :mod:`docking.policies`.
POLICIES = ("network", "oracle", "centroid", "forward", "random")

#: The first-stage rules of a two-stage learner (:attr:`ExperimentConfig.pretrain_rule`).
PRETRAIN_RULES = ("competitive", "som")


@dataclasses.dataclass(frozen=True)
class ExperimentConfig:
    """One experiment: the world, the network, the curriculum and the trial counts.

    Attributes:
      name: Names the results folder; a safe file-name component (letters, digits, .,
        _, -). Variants may share a name: results are keyed by the whole configuration.
      world: The world; its start_near/start_far are the test region.
      network: The network and its learning rule.
      curriculum: How the start region's far edge grows during training.
      train_trials: Training trials (beta_a = network.beta_a_train, learning on).
      test_trials: Final test trials (beta_a = network.beta_a_test, no learning) from the
        world's full start region (0: none, e.g. when held-out trials are the measure).
      eval_every: Every this many training trials the learning curve is measured ...
      eval_trials: ... with this many test trials from the full start region (0: no curve).
      bootstrap_on_truncation: SARSA target at the step limit; see run_trial.
      heldout_trials: After the test, this many more greedy trials from start poses and noise
        of streams used nowhere else (the study's held-out evaluation; 0: none).
      heldout_world: The world of the held-out trials (default world; e.g. one with a
        distractor that training never saw).
      pretrain_trials: Before SARSA, this many random-walk trials whose frames train W by
        winner-take-all competitive learning (no delta; the two-stage learner of the paper's
        Sec. IV). 0: none (the paper).
      pretrain_rate: The step rate of the pretraining rule (the winning unit's
        W_j += rate (I - W_j); a SOM's neighbourhood scales it).
      pretrain_rule: "competitive": plain winner-take-all
        (competitive_update); "som": Kohonen's
        self-organizing map (som_update), the units on a
        grid, the neighbourhood's width shrinking geometrically from half the grid's longer
        side to 0.5 units over the pretraining trials. See PRETRAIN_RULES.
      policy: What acts: "network", the paper's learner, trained; or a yardstick
        that needs no learning (policies): "oracle" (reads the true pose),
        "centroid" (the one-line pixel rule), "forward", "random". A yardstick
        run has no training (train_trials, pretrain_trials and eval_trials 0) and
        acts in the test and held-out trials, drawing from the streams a learner of the same
        seed draws from. See POLICIES. A world with continuous actions takes the oracle
        alone.
      before: Coping with change (the paper's Sec. IV): the network is first trained as a
        run of ``before`` with the same seed trains it (its pretraining and training trials;
        no test), then learns on here, in this configuration's world and with its rates,
        from this run's own streams (so its starts and noise are those of a fresh network's
        run of this configuration, trial for trial while their paths agree). None: a fresh
        network. ``before`` has this network's shape and no ``before`` of its own.
    """

    name: str
    world: WorldConfig
    network: NetworkConfig
    curriculum: Curriculum
    train_trials: int
    test_trials: int
    eval_every: int = 10
    eval_trials: int = 50
    bootstrap_on_truncation: bool = True
    heldout_trials: int = 0
    heldout_world: WorldConfig | None = None
    pretrain_trials: int = 0
    pretrain_rate: float = 0.05
    pretrain_rule: str = "competitive"
    policy: str = "network"
    before: ExperimentConfig | None = None

    def __post_init__(self):
        self._check_fields()
        self._check_policy()
        if self.before is not None:
            self._check_before()
        self._check_worlds()
        self._check_curriculum()
        self._check_network_shape()

    def _check_fields(self) -> None:
        """Every field of its type and in its range, normalised."""
        owner = "ExperimentConfig"
        normalise(
            self,
            name=check_name(owner, "name", self.name),
            world=check_instance(owner, "world", self.world, WorldConfig),
            network=check_instance(owner, "network", self.network, NetworkConfig),
            curriculum=check_instance(owner, "curriculum", self.curriculum, Curriculum),
            train_trials=check_int(owner, "train_trials", self.train_trials, lo=0, hi=MAX_COUNT),
            test_trials=check_int(owner, "test_trials", self.test_trials, lo=0, hi=MAX_COUNT),
            eval_every=check_int(owner, "eval_every", self.eval_every, lo=1, hi=MAX_COUNT),
            eval_trials=check_int(owner, "eval_trials", self.eval_trials, lo=0, hi=MAX_COUNT),
            bootstrap_on_truncation=check_bool(
                owner, "bootstrap_on_truncation", self.bootstrap_on_truncation
            ),
            heldout_trials=check_int(
                owner, "heldout_trials", self.heldout_trials, lo=0, hi=MAX_COUNT
            ),
            pretrain_trials=check_int(
                owner, "pretrain_trials", self.pretrain_trials, lo=0, hi=MAX_COUNT
            ),
            pretrain_rate=check_real(owner, "pretrain_rate", self.pretrain_rate, lo=0, hi=1),
            pretrain_rule=check_choice(owner, "pretrain_rule", self.pretrain_rule, PRETRAIN_RULES),
            policy=check_choice(owner, "policy", self.policy, POLICIES),
        )
        if self.heldout_world is not None:  # before anything reads it as a world
            check_instance(owner, "heldout_world", self.heldout_world, WorldConfig)

    def _check_policy(self) -> None:
        """The learner trains; a yardstick does not learn."""
        if self.policy == "network" and self.train_trials < 1:
            raise ValueError(
                f"ExperimentConfig.train_trials must be >= 1 for the learner (policy='network'), "
                f"got {self.train_trials}"
            )
        if self.policy != "network":
            learning = {
                name: getattr(self, name)
                for name in ("train_trials", "pretrain_trials", "eval_trials")
                if getattr(self, name)
            }
            if learning:
                raise ValueError(
                    f"ExperimentConfig: the yardstick policy={self.policy!r} does not learn; "
                    f"{', '.join(f'{k}={v}' for k, v in learning.items())} must be 0"
                )

    def _check_worlds(self) -> None:
        """Continuous actions take the oracle alone; the held-out world gives the network the
        same input shape."""
        owner = "ExperimentConfig"
        for w in (self.world, self.heldout_world):
            if w is not None and w.continuous and self.policy != "oracle":
                raise ValueError(
                    f"ExperimentConfig: a world with continuous actions (actions={w.actions!r}) "
                    f"takes policy='oracle' alone, got policy={self.policy!r}"
                )
        if self.heldout_world is not None:
            check_instance(owner, "heldout_world", self.heldout_world, WorldConfig)
            if self.heldout_world.camera.input_shape != self.world.camera.input_shape:
                raise ValueError(
                    "ExperimentConfig.heldout_world must give the network the same input shape"
                )

    def _check_curriculum(self) -> None:
        """The curriculum's far edges lie in the test region and the training region."""
        world, curriculum = self.world, self.curriculum
        if curriculum.far_final is not None and not (
            world.start_near < curriculum.far_final <= world.start_far
        ):
            raise ValueError(
                f"ExperimentConfig.curriculum.far_final must lie in the test region "
                f"({world.start_near:g}, {world.start_far:g}] m, got {curriculum.far_final:g}"
            )
        final = world.start_far if curriculum.far_final is None else curriculum.far_final
        if curriculum.grow_trials and not (world.start_near < curriculum.far_initial <= final):
            raise ValueError(
                f"ExperimentConfig.curriculum.far_initial must lie in the training region "
                f"({world.start_near:g}, {final:g}] m (world.start_near, the curriculum's "
                f"final far edge), got {curriculum.far_initial:g}"
            )

    def _check_network_shape(self) -> None:
        """The network has one action unit per action and one input per pixel."""
        world = self.world
        for what, w in (("world", world), ("heldout_world", self.heldout_world)):
            if w is not None and not w.continuous and w.n_actions != self.network.n_actions:
                raise ValueError(
                    f"ExperimentConfig.network.n_actions must equal the {w.n_actions} actions of "
                    f"{what}.actions={w.actions!r} ({', '.join(w.action_names)}), got "
                    f"{self.network.n_actions}"
                )
        rows, cols = world.camera.input_shape
        if rows * cols != self.network.n_inputs:
            raise ValueError(
                f"ExperimentConfig.network.n_inputs must equal the camera's {rows}x{cols} input "
                f"pixels ({rows * cols}), got {self.network.n_inputs}"
            )

    def _check_before(self) -> None:
        before = check_instance("ExperimentConfig", "before", self.before, ExperimentConfig)
        shape = ("n_inputs", "n_features", "n_actions", "feature_layer")
        problems = [
            f"before.network.{name} must equal network.{name}"
            for name in shape
            if getattr(before.network, name) != getattr(self.network, name)
        ]
        if before.before is not None:
            problems.append("before must have no before of its own")
        if "network" != self.policy or "network" != before.policy:
            problems.append("both must have policy='network'")
        if self.pretrain_trials:
            problems.append("pretrain_trials must be 0 (the network comes from before)")
        if problems:
            raise ValueError(f"ExperimentConfig.before: {'; '.join(problems)}")

    def to_dict(self) -> dict:
        """Every field, nested, as JSON-ready Python values (tuples become lists)."""
        return json.loads(json.dumps(dataclasses.asdict(self)))

    @classmethod
    def from_dict(cls, d: dict) -> ExperimentConfig:
        """The inverse of :meth:`to_dict`. A part that is not a mapping, an unknown field, or a
        missing field that has no default raises ``TypeError`` naming it; values are
        validated as always (``ValueError``)."""
        fields = _fields("ExperimentConfig", cls, d)
        heldout = fields.pop("heldout_world", None)
        before = fields.pop("before", None)
        return cls(
            before=None if before is None else cls.from_dict(before),
            world=_world_from_dict(fields.pop("world"), "ExperimentConfig.world"),
            heldout_world=None
            if heldout is None
            else _world_from_dict(heldout, "ExperimentConfig.heldout_world"),
            network=NetworkConfig(
                **_fields("ExperimentConfig.network", NetworkConfig, fields.pop("network"))
            ),
            curriculum=Curriculum(
                **_fields("ExperimentConfig.curriculum", Curriculum, fields.pop("curriculum"))
            ),
            **fields,
        )


def _fields(owner: str, cls, d) -> dict:
    """``d`` as keyword arguments of the dataclass ``cls``: a mapping with exactly the
    fields of ``cls`` that have no default, and no others, or ``TypeError`` naming them."""
    if not isinstance(d, dict):
        raise TypeError(f"{owner} must be a mapping of {cls.__name__}'s fields, got {d!r:.80}")
    names = {f.name for f in dataclasses.fields(cls)}
    required = {
        f.name
        for f in dataclasses.fields(cls)
        if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
    }
    unknown = sorted(set(d) - names, key=str)
    missing = sorted(required - set(d))
    if unknown or missing:
        parts = [f"unknown {', '.join(map(repr, unknown))}"] if unknown else []
        parts += [f"missing {', '.join(map(repr, missing))}"] if missing else []
        raise TypeError(f"{owner}: {'; '.join(parts)} (fields: {', '.join(sorted(names))})")
    return dict(d)


def _tuples(value):
    return tuple(value) if isinstance(value, list) else value


def _world_from_dict(d, owner: str) -> WorldConfig:
    world = _fields(owner, WorldConfig, d)
    camera = _fields(f"{owner}.camera", CameraConfig, world.pop("camera", {}))
    camera = {k: _tuples(v) for k, v in camera.items()}
    distractors = world.pop("distractors", ())
    if not isinstance(distractors, (list, tuple)):
        raise TypeError(f"{owner}.distractors must be a list, got {distractors!r:.80}")
    found = []
    for k, x in enumerate(distractors):
        x = _fields(f"{owner}.distractors[{k}]", Distractor, x)
        found.append(Distractor(x["shape"], _tuples(x["size"]), _tuples(x["position"])))
    return WorldConfig(camera=CameraConfig(**camera), distractors=tuple(found), **world)


# ------------------------------------------------------------------------------------------
# Records of many trials, stored flat (ragged arrays as values + offsets).
# ------------------------------------------------------------------------------------------


@dataclasses.dataclass
class TrialLog:
    """Many trials in flat arrays: per trial ``success``, ``steps``, ``start_far`` (the start
    region's far edge in force), and the concatenated ``poses`` (``steps + 1`` rows each),
    ``actions``, ``winners``, ``deltas`` (``steps`` rows each)."""

    success: np.ndarray
    steps: np.ndarray
    start_far: np.ndarray
    poses: np.ndarray
    actions: np.ndarray
    winners: np.ndarray
    deltas: np.ndarray

    @classmethod
    def from_records(cls, records: list[TrialRecord], start_far) -> TrialLog:
        """The log of ``records`` (none is allowed: an empty log)."""

        def joined(name, empty_shape, dtype):
            parts = [getattr(r, name) for r in records]
            return np.concatenate(parts) if parts else np.zeros(empty_shape, dtype=dtype)

        return cls(
            success=np.array([r.success for r in records], dtype=bool),
            steps=np.array([r.steps for r in records], dtype=np.int64),
            start_far=np.asarray(start_far, dtype=np.float64).reshape(-1),
            poses=joined("poses", (0, 3), np.float64),
            actions=joined("actions", (0,), np.int64),
            winners=joined("winners", (0,), np.int64),
            deltas=joined("deltas", (0,), np.float64),
        )

    def __len__(self) -> int:
        return len(self.success)

    def trial_poses(self, k: int) -> np.ndarray:
        """The ``(steps + 1, 3)`` poses of trial ``k``."""
        start = int(np.sum(self.steps[:k] + 1))
        return self.poses[start : start + self.steps[k] + 1]

    def trial_actions(self, k: int) -> np.ndarray:
        start = int(np.sum(self.steps[:k]))
        return self.actions[start : start + self.steps[k]]

    @property
    def starts(self) -> np.ndarray:
        """The start pose of every trial, ``(n, 3)``."""
        offsets = np.concatenate([[0], np.cumsum(self.steps + 1)[:-1]])
        return self.poses[offsets]

    @property
    def success_rate(self) -> float:
        """The fraction of trials that docked (NaN for an empty log)."""
        return float(np.mean(self.success)) if len(self.success) else float("nan")


@dataclasses.dataclass
class ExperimentResult:
    """Everything one seeded run produced."""

    config: ExperimentConfig
    seed: int
    network: Network
    train: TrialLog
    test: TrialLog
    curve_trials: np.ndarray  # training trials done at each learning-curve point
    curve_success: np.ndarray  # test success rate there
    curve_steps: np.ndarray  # mean actions of the successful test trials there
    curve_rewarded: np.ndarray  # rewarded training trials so far
    wall_time_train: float
    wall_time_test: float
    heldout: TrialLog | None = None  # config.heldout_trials greedy trials, if any

    @property
    def test_successes(self) -> int:
        return int(np.sum(self.test.success))

    @property
    def rewarded_until_mastery(self) -> int | None:
        """Rewarded training trials when the learning curve's test success first reached
        100% (None if it never did)."""
        hits = np.flatnonzero(self.curve_success >= 1.0)
        return int(self.curve_rewarded[hits[0]]) if len(hits) else None

    @property
    def trials_until_mastery(self) -> int | None:
        hits = np.flatnonzero(self.curve_success >= 1.0)
        return int(self.curve_trials[hits[0]]) if len(hits) else None


def _streams(seed: int) -> dict[str, np.random.Generator]:
    names = (
        "train_world",
        "test_world",
        "init",
        "train_actions",
        "test_actions",
        "eval_world",
        "eval_actions",
        "heldout_world",
        "heldout_actions",
        "pretrain_world",
        "pretrain_actions",
        "delta_shuffle",
    )
    # Child k of SeedSequence(seed) depends on k only, so streams added at the end leave the
    # earlier ones (and every run that does not use the new ones) unchanged.
    children = np.random.SeedSequence(seed).spawn(len(names))
    return {n: np.random.default_rng(c) for n, c in zip(names, children, strict=False)}


def initial_network(config: ExperimentConfig, seed: int) -> Network:
    """The network a run of (``config``, ``seed``) starts from, before any learning."""
    return Network(config.network, _streams(seed)["init"])


def evaluate(
    env: DockingEnv,
    net: Network,
    rng: np.random.Generator,
    n_trials: int,
    config: ExperimentConfig,
    on_trials: Callable[[int], None] | None = None,
) -> list[TrialRecord]:
    """``n_trials`` greedy test trials (beta_a = beta_a_test, no learning) of ``net``, or of
    the yardstick ``config.policy`` (drawing from ``rng`` if it is random); ``on_trials(1)``
    after each, if given."""
    found = []
    policy = None if config.policy == "network" else yardstick(config.policy, rng)
    for _ in range(n_trials):
        if policy is None:
            record = run_trial(
                env, net, rng, learn=False, bootstrap_on_truncation=config.bootstrap_on_truncation
            )
        else:
            record = policy_trial(env, policy)
        found.append(record)
        if on_trials is not None:
            on_trials(1)
    return found


def yardstick(name: str, rng: np.random.Generator):
    """The policy ``policy(observation, env) -> action`` of :mod:`docking.policies` that
    :data:`POLICIES` calls ``name`` (``"random"`` draws from ``rng``)."""
    from docking import policies

    check_choice("yardstick", "name", name, POLICIES[1:])
    if name == "random":
        return policies.RandomPolicy(rng)
    return {
        "oracle": policies.oracle,
        "centroid": policies.centroid_rule,
        "forward": policies.always_forward,
    }[name]


def policy_trial(env: DockingEnv, policy) -> TrialRecord:
    """One trial of a yardstick policy in the shape of a learner's :class:`TrialRecord`: no
    TD errors (0) and no winning feature unit (-1)."""
    from docking.policies import run_episode

    episode = run_episode(env, policy)
    steps = episode.steps
    # A continuous action is a vector; the log keeps action indices, -1 for "a vector" (the
    # poses show where each step went).
    actions = episode.actions if episode.actions.ndim == 1 else np.full(steps, -1, np.int64)
    rewards = np.zeros(steps, dtype=np.float64)
    rewards[-1] = float(episode.success)
    return TrialRecord(
        poses=np.asarray(episode.poses, dtype=np.float64),
        actions=actions,
        rewards=rewards,
        deltas=np.zeros(steps, dtype=np.float64),
        winners=np.full(steps, -1, dtype=np.int64),
        success=episode.success,
    )


def trials_in_run(config: ExperimentConfig) -> int:
    """How many trials a run of ``config`` executes (what a progress bar counts): the
    pretraining, training, learning-curve, test and held-out trials."""
    check_instance("trials_in_run", "config", config, ExperimentConfig)
    points = 1 + config.train_trials // config.eval_every if config.eval_trials else 0
    first = config.before
    return (
        (first.pretrain_trials + first.train_trials if first is not None else 0)
        + config.pretrain_trials
        + config.train_trials
        + points * config.eval_trials
        + config.test_trials
        + config.heldout_trials
    )


def pretrain_competitive(
    net: Network,
    env: DockingEnv,
    rng: np.random.Generator,
    n_trials: int,
    rate: float,
    rule: str = "competitive",
    on_trials: Callable[[int], None] | None = None,
) -> None:
    """The first stage of a two-stage learner (paper Sec. IV): train ``net.W`` without delta,
    on every frame of ``n_trials`` random-walk trials (uniformly random actions) in ``env``,
    by winner-take-all competitive learning (``rule="competitive"``,
    :meth:`Network.competitive_update`) or a self-organizing map (``rule="som"``,
    :meth:`Network.som_update`; the neighbourhood's width shrinks geometrically from half the
    grid's longer side to 0.5 over the trials)."""
    rule = check_choice("pretrain_competitive", "rule", rule, PRETRAIN_RULES)
    sigma_start = max(max(Network.som_grid(net.config.n_features)) / 2, 0.5)
    for k in range(n_trials):
        sigma = sigma_start * (0.5 / sigma_start) ** (k / max(n_trials - 1, 1))
        timestep = env.reset()
        while True:
            I = net.prepare(timestep.observation)
            if rule == "som":
                net.som_update(I, rate, sigma)
            else:
                net.competitive_update(I, rate)
            if timestep.last():
                break
            timestep = env.step(int(rng.integers(net.config.n_actions)))
        if on_trials is not None:
            on_trials(1)


class DeltaShuffle:
    """The permutation control's delta (:attr:`NetworkConfig.permute_delta`): called with each
    training step's TD error, it returns one drawn uniformly from the run's earlier training
    steps (the last ``window`` of them), then remembers the new one; 0 at the first step.
    The returned deltas have delta's distribution (its sign and size, as training goes) and
    no correlation with the current step's input or outcome."""

    def __init__(self, rng: np.random.Generator, window: int = 1000):
        self._rng = check_instance("DeltaShuffle", "rng", rng, np.random.Generator)
        self._window = check_int("DeltaShuffle", "window", window, lo=1, hi=MAX_COUNT)
        self._seen: list[float] = []
        self._next = 0  # where the next delta goes once the window is full

    def __call__(self, delta: float) -> float:
        seen = self._seen
        drawn = seen[int(self._rng.integers(len(seen)))] if seen else 0.0
        if len(seen) < self._window:
            seen.append(float(delta))
        else:
            seen[self._next] = float(delta)
            self._next = (self._next + 1) % self._window
        return drawn


def heldout_trials(
    config: ExperimentConfig,
    seed: int,
    net: Network,
    world: WorldConfig,
    on_trials: Callable[[int], None] | None = None,
) -> TrialLog:
    """``config.heldout_trials`` greedy trials of ``net`` in ``world`` from the held-out
    streams of ``seed``: start poses, step noise and action draws that training, the learning
    curve and the main test never use. One world generator draws both the start poses and
    every step's noise, so two runs of one seed share their first trial's start and draw from
    the same distributions after it, but their later trials are not paired (a trial that
    ends sooner draws fewer step noises). Compare such runs by their success rates, not
    trial by trial."""
    from docking.world import DockingEnv

    rngs = _streams(check_int("heldout_trials", "seed", seed, lo=0, hi=MAX_SEED))
    env = DockingEnv(
        check_instance("heldout_trials", "world", world, WorldConfig), rngs["heldout_world"]
    )
    found = evaluate(env, net, rngs["heldout_actions"], config.heldout_trials, config, on_trials)
    return TrialLog.from_records(found, [world.start_far] * len(found))


def run_experiment(
    config: ExperimentConfig,
    seed: int,
    progress: bool = True,
    on_trials: Callable[[int], None] | None = None,
) -> ExperimentResult:
    """Train and test one network; every random draw comes from ``seed`` (an int >= 0).

    ``progress``: tqdm bars of the training and test trials. ``on_trials(n)``, if given, is
    called as trials finish with how many just did (they add up to
    :func:`trials_in_run`), for a caller's own progress bar; it cannot change the run."""
    check_instance("run_experiment", "config", config, ExperimentConfig)
    seed = check_int("run_experiment", "seed", seed, lo=0, hi=MAX_SEED)
    rngs = _streams(seed)
    if config.before is None:
        net = Network(config.network, rngs["init"])
    else:  # coping with change: the network ``before`` trains, learning on here
        first = _streams(seed)
        trained = Network(config.before.network, first["init"])
        _train(config.before, seed, trained, first, progress, on_trials, curve=False)
        net = Network.from_weights(config.network, trained.W, trained.Q)
    t0 = time.perf_counter()
    train, curve = _train(config, seed, net, rngs, progress, on_trials)
    wall_train = time.perf_counter() - t0
    t0 = time.perf_counter()
    test, heldout = _test(config, seed, net, rngs, progress, on_trials)
    wall_test = time.perf_counter() - t0
    return ExperimentResult(
        config=config,
        seed=seed,
        network=net,
        train=train,
        test=test,
        curve_trials=np.array(curve["trials"], dtype=np.int64),
        curve_success=np.array(curve["success"], dtype=np.float64),
        curve_steps=np.array(curve["steps"], dtype=np.float64),
        curve_rewarded=np.array(curve["rewarded"], dtype=np.int64),
        wall_time_train=wall_train,
        wall_time_test=wall_test,
        heldout=heldout,
    )


def _train(
    config: ExperimentConfig,
    seed: int,
    net: Network,
    rngs: dict[str, np.random.Generator],
    progress: bool,
    on_trials: Callable[[int], None] | None,
    curve: bool = True,
) -> tuple[TrialLog, dict[str, list]]:
    """The pretraining (if any) and the SARSA training of ``net`` in place, with the learning
    curve (unless ``curve`` is False): ``(the training trials, the curve's columns)``."""
    from docking.world import DockingEnv

    _pretrain(config, net, rngs, on_trials)
    train_env = DockingEnv(config.world, seed=rngs["train_world"])
    eval_env = DockingEnv(config.world, seed=rngs["eval_world"]) if curve else None
    near = config.world.start_near
    shuffle = DeltaShuffle(rngs["delta_shuffle"]) if config.network.permute_delta else None
    records, fars = [], []
    points = {"trials": [], "success": [], "steps": [], "rewarded": []}
    rewarded = 0

    def measure(done: int) -> None:
        if eval_env is None or config.eval_trials == 0:
            return
        recs = evaluate(eval_env, net, rngs["eval_actions"], config.eval_trials, config, on_trials)
        ok = [r.steps for r in recs if r.success]
        point = (done, len(ok) / len(recs), float(np.mean(ok)) if ok else np.nan, rewarded)
        for name, value in zip(points, point, strict=True):
            points[name].append(value)

    measure(0)
    bar = tqdm(
        range(config.train_trials),
        desc=f"{config.name} seed {seed} train",
        disable=not progress,
        leave=False,
    )
    for k in bar:
        far = config.curriculum.far_at(k, config.world.start_far)
        train_env.set_start_region(near, far)
        rec = run_trial(
            train_env,
            net,
            rngs["train_actions"],
            learn=True,
            bootstrap_on_truncation=config.bootstrap_on_truncation,
            feature_delta=shuffle,
        )
        records.append(rec)
        fars.append(far)
        if on_trials is not None:
            on_trials(1)
        rewarded += rec.success
        if (k + 1) % config.eval_every == 0:
            measure(k + 1)
            if points["success"]:  # eval_trials = 0: no learning curve
                bar.set_postfix(rewarded=rewarded, test=f"{points['success'][-1]:.0%}")
    return TrialLog.from_records(records, fars), points


def _pretrain(
    config: ExperimentConfig,
    net: Network,
    rngs: dict[str, np.random.Generator],
    on_trials: Callable[[int], None] | None,
) -> None:
    """The first stage of a two-stage learner, if ``config`` has one (pretrain_competitive)."""
    from docking.world import DockingEnv

    if config.pretrain_trials:
        pretrain_competitive(
            net,
            DockingEnv(config.world, seed=rngs["pretrain_world"]),
            rngs["pretrain_actions"],
            config.pretrain_trials,
            config.pretrain_rate,
            config.pretrain_rule,
            on_trials,
        )


def _test(
    config: ExperimentConfig,
    seed: int,
    net: Network,
    rngs: dict[str, np.random.Generator],
    progress: bool,
    on_trials: Callable[[int], None] | None,
) -> tuple[TrialLog, TrialLog | None]:
    """The final test trials and the held-out trials (if any) of ``net``, or of the
    yardstick ``config.policy``: ``(test, held-out or None)``."""
    from docking.world import DockingEnv

    test_env = DockingEnv(config.world, seed=rngs["test_world"])
    records = []
    policy = None if config.policy == "network" else yardstick(config.policy, rngs["test_actions"])
    for _ in tqdm(
        range(config.test_trials),
        desc=f"{config.name} seed {seed} test",
        disable=not progress,
        leave=False,
    ):
        if policy is None:
            record = run_trial(
                test_env,
                net,
                rngs["test_actions"],
                learn=False,
                bootstrap_on_truncation=config.bootstrap_on_truncation,
            )
        else:
            record = policy_trial(test_env, policy)
        records.append(record)
        if on_trials is not None:
            on_trials(1)
    test = TrialLog.from_records(records, [config.world.start_far] * len(records))
    heldout = None
    if config.heldout_trials:
        world = config.heldout_world or config.world
        heldout = heldout_trials(config, seed, net, world, on_trials)
    return test, heldout
