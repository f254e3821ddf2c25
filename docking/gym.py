"""The docking task as Gymnasium environments, one id per task (:data:`docking.ENV_IDS`,
registered by ``import docking.gym_ids``): an adapter of the ``dm_env``
:class:`~docking.world.DockingEnv`, which stays the primary API. The ids, the keyword
arguments of ``make``, the mapping of ``dm_env`` time steps to ``terminated`` and
``truncated``, seeding and vector environments: docs/guide/gymnasium.md.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding

from docking.camera import CameraConfig
from docking.scene import WorldConfig
from docking.validate import MAX_SEED, check_int

#: The id of the default world (see :data:`docking.ENV_IDS` for every id).
ENV_ID = "docking/Docking-v0"


def preset_world(name: str | None) -> WorldConfig:
    """The world of a registered id's ``preset`` (:data:`docking.ENV_IDS`)."""
    from docking.presets import EXPERIMENT_1, EXPERIMENT_2, FLOOR_WORLD, NAO_WORLD

    worlds = {
        None: WorldConfig(),
        "experiment1": EXPERIMENT_1.world,
        "experiment2": EXPERIMENT_2.world,
        "floor": FLOOR_WORLD,
        # Experiment 3's worlds at the paper's 2 deg (docking.study.designs.experiment3.world).
        "turning": dataclasses.replace(EXPERIMENT_2.world, actions="turning"),
        "precision": dataclasses.replace(
            EXPERIMENT_2.world, actions="turning", dock_heading_deg=10.0
        ),
        "nao": NAO_WORLD,
        # The paper's future work (Sec. V): a step vector instead of four steps.
        "continuous": dataclasses.replace(EXPERIMENT_2.world, actions="continuous"),
    }
    if name not in worlds:
        raise ValueError(f"no preset world {name!r}; the presets are {', '.join(map(str, worlds))}")
    return worlds[name]


def _world_config(kwargs: dict[str, Any], preset: str | None = None) -> WorldConfig:
    names = {f.name for f in dataclasses.fields(WorldConfig)}
    unknown = sorted(set(kwargs) - names)
    if unknown:
        raise TypeError(
            f"the docking environments take the fields of WorldConfig "
            f"({', '.join(sorted(names))}), preset, seed and render_mode; got unknown "
            f"{', '.join(unknown)}"
        )
    camera = kwargs.get("camera")
    if isinstance(camera, dict):
        kwargs = {**kwargs, "camera": CameraConfig(**camera)}
    elif camera is not None and not isinstance(camera, CameraConfig):
        raise TypeError(
            f"WorldConfig.camera must be a CameraConfig or a dict of its fields, got {camera!r}"
        )
    return dataclasses.replace(preset_world(preset), **kwargs)


class DockingGymEnv(gymnasium.Env):
    """Gymnasium adapter of :class:`~docking.world.DockingEnv` (see the module docstring).

    Args:
      seed: Seeds the env's ``np_random`` (an int or ``None``); ``reset(seed=...)`` reseeds.
      render_mode: ``None`` or ``"rgb_array"`` (``render()`` returns a 480x640 overview).
      preset: The world to start from (:func:`preset_world`; None: ``WorldConfig()``).
      **world: Fields of :class:`~docking.scene.WorldConfig` that override the preset's.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 2}

    def __init__(
        self,
        seed: int | None = None,
        render_mode: str | None = None,
        preset: str | None = None,
        **world,
    ):
        from docking.world import DockingEnv

        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be None or one of {self.metadata['render_modes']}, "
                f"got {render_mode!r}"
            )
        if seed is not None and not isinstance(seed, (int, np.integer)):
            raise TypeError(f"seed must be None or an int, got {seed!r}")
        self.render_mode = render_mode
        self.config = _world_config(world, preset)
        if seed is not None:
            self._np_random, self._np_random_seed = seeding.np_random(int(seed))
        # One generator for both: the dm_env world draws from this env's np_random.
        self.dm_env = DockingEnv(self.config, seed=self.np_random)
        spec = self.dm_env.observation_spec()
        self.observation_space = spaces.Box(
            low=float(spec.minimum), high=float(spec.maximum), shape=spec.shape, dtype=spec.dtype
        )
        if self.config.continuous:  # a step vector: forward, sideways (and a turn)
            n = self.config.n_actions
            self.action_space = spaces.Box(-1.0, 1.0, shape=(n,), dtype=np.float64)
        else:
            self.action_space = spaces.Discrete(self.config.n_actions)
        self._needs_reset = True

    def _info(self) -> dict[str, Any]:
        return {"pose": self.dm_env.pose, "docked": self.dm_env.docked}

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode; ``seed`` reseeds the env first (``options`` is unused)."""
        if seed is not None:  # NumPy integers too, as the constructor takes them
            seed = check_int("reset", "seed", seed, lo=0, hi=MAX_SEED)
        super().reset(seed=seed)
        if seed is not None:
            self.dm_env.reseed(self.np_random)
        timestep = self.dm_env.reset()
        self._needs_reset = False
        return timestep.observation, self._info()

    def step(self, action):
        if self._needs_reset:
            raise gymnasium.error.ResetNeeded(
                "call reset() before step(), and again after an episode ends"
            )
        timestep = self.dm_env.step(action)
        terminated = bool(timestep.last() and timestep.discount == 0.0)
        truncated = bool(timestep.last() and not terminated)
        self._needs_reset = terminated or truncated
        return timestep.observation, float(timestep.reward), terminated, truncated, self._info()

    def render(self):
        """An RGB overview of the room with the robot and the docking region (``rgb_array``)."""
        if self.render_mode == "rgb_array":
            return self.dm_env.render_view("overview")
        return None


def register() -> None:
    """Register every id of :data:`docking.ENV_IDS` (done by ``import docking.gym_ids``)."""
    import docking

    docking._register_envs()
