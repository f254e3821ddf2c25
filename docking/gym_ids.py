"""The Gymnasium ids of :data:`docking.ENV_IDS`, registered when this module is imported
(``import docking.gym_ids``: Gymnasium 1.x has no plugin entry points), and what
``gymnasium.make`` builds for them: the adapter :class:`docking.gym.DockingGymEnv`, with its
arguments and actions checked here, and the conventions of reinforcement-learning libraries
such as Stable-Baselines3.

The adapter's code is part of the fingerprint of PPO's runs (:mod:`docking.study.ppo` builds it), so
what its code could hold lives in this module instead, which no run imports:

* a ``seed`` that is no integer (``seed=True``) and, in a world with continuous actions
  (``docking/Continuous-v0``), an action that is no vector of real numbers (strings, bools,
  complex numbers, which numpy would convert or truncate) are refused the way the discrete ids
  refuse them: a ``ValueError`` (or ``TypeError``) naming what was expected. A valid action
  reaches the adapter unchanged;
* ``reset(options=...)``: the environments take no options, so anything but ``None`` or an
  empty dict is refused, naming ``options``;
* ``info["is_success"]``: ``info["docked"]`` under the name Stable-Baselines3's success rates
  read (on every step, so on an episode's last one it is the episode's success);
* ``observation``: ``"grid"`` (the default, the ``(10, 32)`` rows of pixels the package's own
  learners read) or ``"flat"`` (the same pixels as one ``(320,)`` vector, row by row: the shape
  Stable-Baselines3's ``MlpPolicy`` and its ``check_env`` expect);
* a continuous world's ``Box`` action space is ``float32`` (the adapter's is ``float64``).
"""

from __future__ import annotations

import dataclasses

import gymnasium
import numpy as np
from gymnasium import spaces

from docking import ENV_IDS
from docking.gym import DockingGymEnv
from docking.scene import WorldConfig
from docking.validate import MAX_SEED, FieldTypeError, check_int

__all__ = ["OBSERVATIONS", "CheckedDockingGymEnv", "register"]

#: The layouts of ``make(..., observation=...)``: name -> what it is.
OBSERVATIONS = {
    "grid": "the (10, 32) rows of pixels",
    "flat": "the same pixels as one (320,) vector, row by row",
}


class CheckedDockingGymEnv(DockingGymEnv):
    """:class:`docking.gym.DockingGymEnv` with its arguments and continuous actions checked
    and the observation layout chosen (see the module docstring); the entry point of every
    registered id.

    Args:
      seed: As the adapter's (an int or ``None``), checked.
      observation: A name of :data:`OBSERVATIONS`.
      **kwargs: The adapter's ``render_mode`` and ``preset``, and fields of
        :class:`~docking.scene.WorldConfig`.
    """

    def __init__(self, seed: int | None = None, observation: str = "grid", **kwargs):
        if seed is not None:  # NumPy integers too, as reset(seed=...) takes them
            check_int("DockingGymEnv", "seed", seed, lo=0, hi=MAX_SEED)
        if not isinstance(observation, str) or observation not in OBSERVATIONS:
            raise ValueError(
                f"observation must be one of {', '.join(map(repr, OBSERVATIONS))}, "
                f"got {observation!r}"
            )
        _check_names(kwargs)
        super().__init__(seed=seed, **kwargs)
        self.observation = observation
        if observation == "flat":
            self.observation_space = spaces.flatten_space(self.observation_space)
        if self.config.continuous:
            box = self.action_space
            low, high = box.low.astype(np.float32), box.high.astype(np.float32)
            self.action_space = spaces.Box(low, high, dtype=np.float32)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode; ``seed`` reseeds the env first; ``options``: None or ``{}``."""
        if options is not None and not isinstance(options, dict):
            raise FieldTypeError(f"reset.options must be None or a dict, got {options!r}")
        if options:
            raise ValueError(
                f"reset.options must be empty: the docking environments take no options, got "
                f"{', '.join(map(repr, options))}"
            )
        obs, info = super().reset(seed=seed, options=options)
        return self._layout(obs), info

    def step(self, action):
        if self.config.continuous:
            _check_vector(action, self.config.action_names)
        obs, reward, terminated, truncated, info = super().step(action)
        return self._layout(obs), reward, terminated, truncated, info

    def _layout(self, obs: np.ndarray) -> np.ndarray:
        return obs.reshape(-1) if self.observation == "flat" else obs

    def _info(self) -> dict:
        info = super()._info()
        info["is_success"] = info["docked"]
        return info


def _check_names(kwargs: dict) -> None:
    """``TypeError`` naming what is neither an argument of the ids nor a field of
    :class:`~docking.scene.WorldConfig`."""
    fields = {f.name for f in dataclasses.fields(WorldConfig)}
    unknown = sorted(set(kwargs) - fields - {"preset", "render_mode"})
    if unknown:
        raise TypeError(
            f"the docking environments take the fields of WorldConfig "
            f"({', '.join(sorted(fields))}), preset, seed, render_mode and observation; got "
            f"unknown {', '.join(unknown)}"
        )


def _check_vector(action, names: tuple[str, ...]) -> None:
    """``ValueError`` unless ``action`` is ``len(names)`` real numbers (integers or floats,
    not bools, complex numbers or strings); the range is the adapter's to check."""
    try:
        kind = np.asarray(action).dtype.kind
    except (TypeError, ValueError):  # ragged nesting
        kind = "O"
    if kind not in "iuf":
        raise ValueError(
            f"action must be {len(names)} finite numbers in [-1, 1] ({', '.join(names)}), "
            f"got {action!r}"
        )


def register() -> None:
    """Register :data:`docking.ENV_IDS` with Gymnasium (each id not yet registered); the
    environments and their worlds are built only by ``gymnasium.make``. Done when this module
    is imported."""
    steps = WorldConfig.__dataclass_fields__["max_steps"].default  # the presets keep it
    for env_id, preset in ENV_IDS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(
                id=env_id,
                # the adapter with its seed and actions checked (this module)
                entry_point="docking.gym_ids:CheckedDockingGymEnv",
                kwargs={"preset": preset},
                max_episode_steps=steps,
                # Gymnasium 1.4's PassiveEnvChecker counts its first reset as checked before
                # it returns: after a refused first reset(seed='0') the next step fails inside
                # it (issue 52). check_env passes on every id (tests/test_gym.py).
                disable_env_checker=True,
            )


register()
