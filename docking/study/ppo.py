"""The pixel-level bound: PPO from a maintained library on the package's Gymnasium env.

What the paper's learner should be compared with in a world is not only what reads the true
pose (the oracle) but what a generic learner makes of the same 32x10 pixels. This module
trains PPO (skrl 2.1 on JAX, CPU) on :class:`docking.gym.DockingGymEnv` of a world, the
observation flattened to its 320 pixels, for :attr:`PPOConfig.steps` environment steps from
the world's full start region (no curriculum), and then judges its greedy policy (the most
probable action) on the **same held-out streams** as the paper's learner of the same seed
(:func:`docking.experiments.heldout_trials`: the start poses and step noise of stream
``heldout_world``), so that its held-out success is comparable with theirs.

Choices, named: the networks are two-layer tanh MLPs of :attr:`PPOConfig.hidden` units for
the policy and for the value; every PPO setting is skrl 2.1.1's default (``PPO_CFG``),
written out in :class:`PPOConfig` so that the key records it; PPO collects its experience
from :attr:`PPOConfig.envs` copies of the world at once (a Gymnasium ``SyncVectorEnv``, each
copy reset in the step that ends its episode), so that one update learns from
``envs x rollouts`` steps: skrl's JAX agent spends about 20 ms of bookkeeping per agent step
and per update whatever the batch, which with one env would make the 50,000 steps of the
paper's budget cost about 20 CPU minutes per run; the budget counts the steps of all copies;
the entropy bonus stays at
skrl's default 0 (skrl's JAX categorical model does not compute an entropy). In a world with
continuous actions (the paper's future work) the policy is a Gaussian of learned mean and
state-free log standard deviation (starting at 1); its samples are clipped to [-1, 1] on their
way to the world (``gymnasium.wrappers.ClipAction``) but learned from as drawn (clipped
samples, whose log-probability far from the mean can make PPO's ratio overflow, stopped
a run of the untested claims' design on NaN actions); the greedy action is the mean,
clipped. skrl draws from a global seed (``skrl.utils.set_seed``: Python's, NumPy's and
JAX's), which is set from ``SeedSequence([PPO_STREAM, seed])``, as is the training env's
seed; the held-out streams are children of ``SeedSequence(seed)``, so training never sees them.

Runs are stored by the one results store (:mod:`docking.study.store`, whose runner ``"ppo"`` is
this module's): under ``<results>/<config.name>/<key[:16]>/seed<k>.npz``, keyed by the
configuration, the code of this module and everything it imports, the versions of
:data:`LIBRARIES` (skrl, JAX, Flax, Optax and Gymnasium beside the learner's), the rendering
stack and the seed, with a content digest checked on load against the key asked for.
"""

from __future__ import annotations

import dataclasses
import json
import os
import time

import gymnasium
import numpy as np

from docking.experiments import TrialLog, _streams, policy_trial
from docking.scene import WorldConfig
from docking.validate import (
    MAX_COUNT,
    MAX_SEED,
    check_instance,
    check_int,
    check_int_tuple,
    check_name,
    check_real,
    normalise,
)

__all__ = [
    "PPOConfig",
    "PPOResult",
    "result_arrays",
    "run_ppo",
    "trials_in_run",
]

#: Version of the stored file's layout (:func:`result_arrays`; read by :mod:`docking.study.store`).
FORMAT_VERSION = 1

#: The first word of the training seeds' SeedSequence (disjoint from every learner stream).
PPO_STREAM = 0x70706F

#: Libraries whose versions enter the key, beyond those of the learner's runs.
LIBRARIES = (
    "mujoco",
    "dm-control",
    "numpy",
    "opencv-python-headless",
    "gymnasium",
    "skrl",
    "jax",
    "jaxlib",
    "flax",
    "optax",
)


@dataclasses.dataclass(frozen=True)
class PPOConfig:
    """One PPO run: the world, the budget, the networks and skrl's PPO settings.

    Attributes:
      name: The results folder (a file-name component).
      world: The world PPO trains and is judged in.
      steps: Environment steps of training, summed over the ``envs`` copies (2000 trials x
        25 actions at most: 50,000); a multiple of ``envs``.
      envs: Copies of the world that PPO steps at once (one agent step steps all of them).
      heldout_trials: Greedy trials on the held-out streams after training.
      hidden: Units of the hidden tanh layers of the policy and of the value network.
      rollouts, learning_epochs, mini_batches, discount_factor, gae_lambda, learning_rate,
        grad_norm_clip, ratio_clip, value_clip, value_loss_scale: skrl 2.1.1's ``PPO_CFG``
        (its defaults).
    """

    name: str = "ppo"
    world: WorldConfig = dataclasses.field(default_factory=WorldConfig)
    steps: int = 50_000
    envs: int = 16
    heldout_trials: int = 500
    hidden: tuple[int, ...] = (64, 64)
    rollouts: int = 16
    learning_epochs: int = 8
    mini_batches: int = 2
    discount_factor: float = 0.99
    gae_lambda: float = 0.95
    learning_rate: float = 1e-3
    grad_norm_clip: float = 0.5
    ratio_clip: float = 0.2
    value_clip: float = 0.2
    value_loss_scale: float = 2.5

    def __post_init__(self):
        owner = "PPOConfig"
        hidden = self.hidden
        if not isinstance(hidden, (tuple, list)) or not 1 <= len(hidden) <= 4:
            raise ValueError(f"PPOConfig.hidden must be 1 to 4 layer widths, got {hidden!r}")
        normalise(
            self,
            name=check_name(owner, "name", self.name),
            world=check_instance(owner, "world", self.world, WorldConfig),
            steps=check_int(owner, "steps", self.steps, lo=1, hi=100 * MAX_COUNT),
            envs=check_int(owner, "envs", self.envs, lo=1, hi=256),
            heldout_trials=check_int(
                owner, "heldout_trials", self.heldout_trials, lo=0, hi=MAX_COUNT
            ),
            hidden=check_int_tuple(owner, "hidden", tuple(hidden), len(hidden), lo=1, hi=4096),
            rollouts=check_int(owner, "rollouts", self.rollouts, lo=1, hi=4096),
            learning_epochs=check_int(owner, "learning_epochs", self.learning_epochs, lo=1, hi=100),
            mini_batches=check_int(owner, "mini_batches", self.mini_batches, lo=1, hi=4096),
            discount_factor=check_real(owner, "discount_factor", self.discount_factor, lo=0, hi=1),
            gae_lambda=check_real(owner, "gae_lambda", self.gae_lambda, lo=0, hi=1),
            learning_rate=check_real(
                owner, "learning_rate", self.learning_rate, lo=0, hi=1, lo_open=True
            ),
            grad_norm_clip=check_real(owner, "grad_norm_clip", self.grad_norm_clip, lo=0, hi=1e3),
            ratio_clip=check_real(owner, "ratio_clip", self.ratio_clip, lo=0, hi=1),
            value_clip=check_real(owner, "value_clip", self.value_clip, lo=0, hi=1e3),
            value_loss_scale=check_real(
                owner, "value_loss_scale", self.value_loss_scale, lo=0, hi=1e3
            ),
        )
        if self.steps % self.envs:
            raise ValueError(
                f"PPOConfig.steps ({self.steps}) must be a multiple of envs ({self.envs}): the "
                "budget counts the steps of every copy of the world"
            )
        if self.mini_batches > self.rollouts * self.envs:
            raise ValueError(
                f"PPOConfig.mini_batches ({self.mini_batches}) must not exceed rollouts x "
                f"envs ({self.rollouts * self.envs})"
            )

    def to_dict(self) -> dict:
        """Every field, nested, as JSON-ready values."""
        return json.loads(json.dumps(dataclasses.asdict(self)))

    @classmethod
    def from_dict(cls, d: dict) -> PPOConfig:
        """The inverse of :meth:`to_dict` (``TypeError`` for unknown or missing fields)."""
        from docking.experiments import _world_from_dict

        if not isinstance(d, dict):
            raise TypeError(f"PPOConfig.from_dict needs a dict, got {d!r:.80}")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names)
        if unknown:
            raise TypeError(f"PPOConfig has no field {', '.join(unknown)}")
        fields = dict(d)
        if "world" in fields:
            fields["world"] = _world_from_dict(fields["world"], "PPOConfig.world")
        if "hidden" in fields:
            fields["hidden"] = tuple(fields["hidden"])
        return cls(**fields)


@dataclasses.dataclass
class PPOResult:
    """A PPO run: its training episodes' outcomes and its greedy held-out trials.

    ``train_success`` and ``train_steps`` hold one entry per training episode, in order (an
    episode cut off by the step budget is not counted); ``heldout`` is the log of the greedy
    held-out trials (no TD errors: 0; no feature unit: -1)."""

    config: PPOConfig
    seed: int
    train_success: np.ndarray
    train_steps: np.ndarray
    heldout: TrialLog
    wall_time_train: float
    wall_time_test: float

    @property
    def heldout_success(self) -> float:
        return float(np.mean(self.heldout.success)) if len(self.heldout) else float("nan")


# ------------------------------------------------------------------------------------------
# Running.
# ------------------------------------------------------------------------------------------


def _training_seeds(seed: int) -> tuple[int, int]:
    """(skrl's global seed, the training env's seed) of run ``seed``."""
    words = np.random.SeedSequence([PPO_STREAM, seed]).generate_state(2, dtype=np.uint32)
    return int(words[0]), int(words[1])


def _quiet_jax() -> None:
    # One CPU thread per process (a sweep runs one process per core), before JAX starts.
    os.environ.setdefault("JAX_PLATFORMS", "cpu")
    os.environ.setdefault(
        "XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1"
    )


def _models(config: PPOConfig, observation_space, action_space, device):
    """The policy (categorical, or Gaussian with continuous actions) and the value network
    of ``config``, their parameters initialised from skrl's global key (policy first)."""
    trunk = _trunk(config.hidden)
    policy = _gaussian_policy(trunk) if config.world.continuous else _categorical_policy(trunk)
    models = {
        "policy": policy(observation_space, action_space, device),
        "value": _value(trunk)(observation_space, action_space, device),
    }
    for role, model in models.items():
        model.init_state_dict(role=role)
    return models


def _trunk(hidden: tuple[int, ...]):
    """The hidden layers every network shares the shape of: tanh of a dense layer per width
    of ``hidden`` (each network has its own parameters)."""
    import flax.linen as nn

    def trunk(x):
        for width in hidden:
            x = nn.tanh(nn.Dense(width)(x))
        return x

    return trunk


def _categorical_policy(trunk):
    """Discrete actions: a categorical policy of the logits of a dense layer on ``trunk``."""
    import flax.linen as nn
    from skrl.models.jax import CategoricalMixin, Model

    class Policy(CategoricalMixin, Model):
        def __init__(self, observation_space, action_space, device=None, **kwargs):
            Model.__init__(
                self,
                observation_space=observation_space,
                action_space=action_space,
                device=device,
                **kwargs,
            )
            CategoricalMixin.__init__(self, unnormalized_log_prob=True)

        @nn.compact
        def __call__(self, inputs, role):
            return nn.Dense(self.num_actions)(trunk(inputs["observations"])), {}

    return Policy


def _gaussian_policy(trunk):
    """Continuous actions: a Gaussian of learned mean (a dense layer on ``trunk``) and
    state-free log std, its samples learned from unclipped (the world's wrapper clips them)."""
    import flax.linen as nn
    import jax.numpy as jnp
    from skrl.models.jax import GaussianMixin, Model

    class VectorPolicy(GaussianMixin, Model):
        def __init__(self, observation_space, action_space, device=None, **kwargs):
            Model.__init__(
                self,
                observation_space=observation_space,
                action_space=action_space,
                device=device,
                **kwargs,
            )
            GaussianMixin.__init__(self, clip_actions=False)

        @nn.compact
        def __call__(self, inputs, role):
            mean = nn.Dense(self.num_actions)(trunk(inputs["observations"]))
            log_std = self.param("log_std", lambda _: jnp.zeros(self.num_actions))
            return mean, {"log_std": log_std}

    return VectorPolicy


def _value(trunk):
    """The value network: one dense unit on ``trunk``."""
    import flax.linen as nn
    from skrl.models.jax import DeterministicMixin, Model

    class Value(DeterministicMixin, Model):
        def __init__(self, observation_space, action_space, device=None, **kwargs):
            Model.__init__(
                self,
                observation_space=observation_space,
                action_space=action_space,
                device=device,
                **kwargs,
            )
            DeterministicMixin.__init__(self)

        @nn.compact
        def __call__(self, inputs, role):
            return nn.Dense(1)(trunk(inputs["observations"])), {}

    return Value


class _EpisodeLog(gymnasium.Wrapper):
    """Records every finished episode's success and length into the lists given, and calls
    ``on_steps(1)`` after each step (if given)."""

    def __init__(self, env, success: list, steps: list, on_steps=None):
        super().__init__(env)
        self._success, self._steps, self._n = success, steps, 0
        self._on_steps = on_steps

    def reset(self, **kwargs):
        self._n = 0
        return self.env.reset(**kwargs)

    def step(self, action):
        out = self.env.step(action)
        self._n += 1
        if self._on_steps is not None:
            self._on_steps(1)
        if out[2] or out[3]:  # terminated (docked) or truncated (out of actions)
            self._success.append(bool(out[2]))
            self._steps.append(self._n)
        return out


def trials_in_run(config: PPOConfig) -> int:
    """The trials a run of ``config`` reports to ``on_trials``: its training budget in trials
    of the world's ``max_steps`` actions, then its held-out trials."""
    check_instance("trials_in_run", "config", config, PPOConfig)
    return config.steps // config.world.max_steps + config.heldout_trials


class _TrialBudget:
    """Turns environment steps into trials of ``max_steps`` actions for ``on_trials``."""

    def __init__(self, on_trials, max_steps: int, total: int):
        self.on_trials, self.max_steps, self.left, self.steps = on_trials, max_steps, total, 0

    def __call__(self, n: int) -> None:
        self.steps += n
        done = min(self.steps // self.max_steps, self.left)
        if done:
            self.steps -= done * self.max_steps
            self.left -= done
            self.on_trials(done)


def run_ppo(
    config: PPOConfig, seed: int, progress: bool | None = None, on_trials=None
) -> PPOResult:
    """Train PPO in ``config.world`` and judge it greedily on the held-out streams of
    ``seed`` (see the module docstring). ``progress``: skrl's bar over the training steps
    (None: shown on a terminal only); ``on_trials(n)``: called as training uses up trials of
    ``max_steps`` actions and as held-out trials finish (:func:`trials_in_run` in all), for
    a caller's own bar."""
    check_instance("run_ppo", "config", config, PPOConfig)
    seed = check_int("run_ppo", "seed", seed, lo=0, hi=MAX_SEED)
    _quiet_jax()
    # Everything the run imports, imported here, before the seeds are set (as it always was):
    # whatever an import does happens before the first draw. The helpers import them again.
    import logging
    import tempfile  # noqa: F401

    import jax  # noqa: F401
    import jax.numpy as jnp  # noqa: F401
    import skrl
    from skrl.agents.jax.ppo import PPO, PPO_CFG  # noqa: F401
    from skrl.envs.wrappers.jax import wrap_env  # noqa: F401
    from skrl.memories.jax import RandomMemory  # noqa: F401
    from skrl.trainers.jax import SequentialTrainer  # noqa: F401
    from skrl.utils import set_seed

    from docking.gym import DockingGymEnv  # noqa: F401
    from docking.world import DockingEnv  # noqa: F401

    skrl.logger.setLevel(logging.ERROR)
    global_seed, env_seed = _training_seeds(seed)
    set_seed(global_seed)
    success, steps = [], []
    budget = None
    if on_trials is not None:
        budget = _TrialBudget(
            on_trials, config.world.max_steps, config.steps // config.world.max_steps
        )
    env = _training_env(config, env_seed, success, steps, budget)
    models = _models(config, env.observation_space, env.action_space, env.device)
    t0 = time.perf_counter()
    _train(config, env, models, progress)
    wall_train = time.perf_counter() - t0

    t0 = time.perf_counter()
    heldout = _judge(config, seed, _greedy(config, models), on_trials)
    return PPOResult(
        config=config,
        seed=seed,
        train_success=np.array(success, dtype=bool),
        train_steps=np.array(steps, dtype=np.int64),
        heldout=heldout,
        wall_time_train=wall_train,
        wall_time_test=time.perf_counter() - t0,
    )


def _training_env(config: PPOConfig, env_seed: int, success: list, steps: list, budget):
    """The ``config.envs`` copies of the world PPO trains in, as skrl's wrapper of a
    Gymnasium ``SyncVectorEnv``: copy ``k`` seeded ``env_seed + k``, each logging its finished
    episodes into ``success`` and ``steps`` and its steps into ``budget`` (if any)."""
    from skrl.envs.wrappers.jax import wrap_env

    from docking.gym import DockingGymEnv

    def make(k: int):
        def env():
            one = _EpisodeLog(
                DockingGymEnv(seed=env_seed + k, **_world_kwargs(config.world)),
                success,
                steps,
                budget,
            )
            if config.world.continuous:  # the world takes [-1, 1]; PPO learns the raw sample
                one = gymnasium.wrappers.ClipAction(one)
            return gymnasium.wrappers.FlattenObservation(one)

        return env

    # Same-step autoreset: a finished copy is reset within the step that ends its episode,
    # as skrl's wrapper assumes (with next-step autoreset, every episode would add a step
    # whose action is ignored).
    env = gymnasium.vector.SyncVectorEnv(
        [make(k) for k in range(config.envs)],
        autoreset_mode=gymnasium.vector.AutoresetMode.SAME_STEP,
    )
    return wrap_env(env, wrapper="gymnasium")


#: The fields of :class:`PPOConfig` that are skrl's ``PPO_CFG`` settings.
_PPO_SETTINGS = (
    "rollouts",
    "learning_epochs",
    "mini_batches",
    "discount_factor",
    "gae_lambda",
    "learning_rate",
    "grad_norm_clip",
    "ratio_clip",
    "value_clip",
    "value_loss_scale",
)


def _train(config: PPOConfig, env, models: dict, progress: bool | None) -> None:
    """Train ``models`` by skrl's PPO with ``config``'s settings in ``env`` for
    ``config.steps`` environment steps (skrl writes nothing: a scratch folder, both
    intervals 0)."""
    import tempfile

    from skrl.agents.jax.ppo import PPO, PPO_CFG
    from skrl.memories.jax import RandomMemory
    from skrl.trainers.jax import SequentialTrainer

    memory = RandomMemory(memory_size=config.rollouts, num_envs=env.num_envs, device=env.device)
    settings = {name: getattr(config, name) for name in _PPO_SETTINGS}
    cfg = PPO_CFG(**settings)
    with tempfile.TemporaryDirectory() as scratch:
        cfg.experiment.directory = scratch  # skrl writes nothing with both intervals 0
        cfg.experiment.write_interval = 0
        cfg.experiment.checkpoint_interval = 0
        agent = PPO(
            models=models,
            memory=memory,
            observation_space=env.observation_space,
            action_space=env.action_space,
            device=env.device,
            cfg=cfg,
        )
        trainer = SequentialTrainer(
            cfg={
                "timesteps": config.steps // config.envs,  # agent steps: all copies each
                "headless": True,
                "disable_progressbar": None if progress is None else not progress,
                "close_environment_at_exit": False,
            },
            env=env,
            agents=agent,
        )
        trainer.train()


def _greedy(config: PPOConfig, models: dict):
    """The trained policy's greedy action for an observation, as a policy of
    :func:`docking.experiments.policy_trial`."""
    import jax
    import jax.numpy as jnp

    policy = models["policy"]
    params = policy.state_dict.params
    logits = jax.jit(lambda x: policy.apply(params, {"observations": x}, "policy")[0])

    def greedy(observation, _env):
        """The most probable action: the largest logit, or the Gaussian's mean (clipped)."""
        x = jnp.asarray(np.asarray(observation, dtype=np.float32).reshape(1, -1))
        out = np.asarray(logits(x))[0]
        if config.world.continuous:
            return np.clip(out.astype(np.float64), -1.0, 1.0)
        return int(np.argmax(out))

    return greedy


def _judge(config: PPOConfig, seed: int, greedy, on_trials) -> TrialLog:
    """The log of ``config.heldout_trials`` trials of ``greedy`` on the held-out streams of
    ``seed``."""
    from docking.world import DockingEnv

    heldout_env = DockingEnv(config.world, _streams(seed)["heldout_world"])
    records = []
    for _ in range(config.heldout_trials):
        records.append(policy_trial(heldout_env, greedy))
        if on_trials is not None:
            on_trials(1)
    return TrialLog.from_records(records, [config.world.start_far] * len(records))


def _world_kwargs(world: WorldConfig) -> dict:
    return {f.name: getattr(world, f.name) for f in dataclasses.fields(WorldConfig)}


# ------------------------------------------------------------------------------------------
# Storing.
# ------------------------------------------------------------------------------------------


def result_arrays(result: PPOResult) -> dict[str, np.ndarray]:
    """The arrays a stored PPO run holds (all but its ``meta`` record), by name."""
    arrays = {"train.success": result.train_success, "train.steps": result.train_steps}
    for field in dataclasses.fields(TrialLog):
        arrays[f"heldout.{field.name}"] = getattr(result.heldout, field.name)
    return arrays
