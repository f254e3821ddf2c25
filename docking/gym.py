"""The docking task as a Gymnasium environment, ``docking/Docking-v0``.

The ``dm_env`` :class:`~docking.world.DockingEnv` stays the primary API (the experiments use
it); this module adapts it for Gymnasium users and registers it on import::

    import gymnasium
    import docking.gym  # registers docking/Docking-v0

    env = gymnasium.make("docking/Docking-v0", start_far=1.0, seed=0)
    obs, info = env.reset(seed=1)            # obs: float32 (10, 32) in [0, 1]
    obs, reward, terminated, truncated, info = env.step(0)  # 0 F, 1 B, 2 L, 3 R

``gymnasium.make("docking.gym:docking/Docking-v0")`` imports and registers in one go. The
keyword arguments of ``make`` are the fields of :class:`~docking.world.WorldConfig` (``camera``
as a :class:`~docking.camera.CameraConfig` or a dict of its fields) plus ``seed`` and
``render_mode`` (``None`` or ``"rgb_array"``: an overview render of the room).

The mapping from ``dm_env`` time steps: docking gives reward 1 and ends the episode as
``terminated`` (dm_env discount 0); the ``max_steps``-th action without docking ends it as
``truncated`` (a time limit, dm_env discount 1). ``info`` carries the ground truth the learner
never reads: ``pose`` ``[x, y, yaw]`` and ``docked``.

Seeding: the wrapped env draws from the Gymnasium env's own ``np_random``, so
``reset(seed=k)`` reseeds it (through :meth:`DockingEnv.reseed`) and gives the same episode as
``DockingEnv(config, seed=k).reset()``. Vector envs: use ``gymnasium.make_vec(...,
vectorization_mode="async", vector_kwargs={"context": "spawn"})``; with the default fork
context the OpenGL (EGL) state of the parent hangs the children.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding

from docking.camera import CameraConfig
from docking.validate import MAX_SEED, check_int
from docking.world import DockingEnv, WorldConfig

#: The registered id.
ENV_ID = "docking/Docking-v0"


def _world_config(kwargs: dict[str, Any]) -> WorldConfig:
    names = {f.name for f in dataclasses.fields(WorldConfig)}
    unknown = sorted(set(kwargs) - names)
    if unknown:
        raise TypeError(
            f"{ENV_ID} takes the fields of WorldConfig ({', '.join(sorted(names))}), "
            f"seed and render_mode; got unknown {', '.join(unknown)}"
        )
    camera = kwargs.get("camera")
    if isinstance(camera, dict):
        kwargs = {**kwargs, "camera": CameraConfig(**camera)}
    elif camera is not None and not isinstance(camera, CameraConfig):
        raise TypeError(
            f"WorldConfig.camera must be a CameraConfig or a dict of its fields, got {camera!r}"
        )
    return WorldConfig(**kwargs)


class DockingGymEnv(gymnasium.Env):
    """Gymnasium adapter of :class:`~docking.world.DockingEnv` (see the module docstring).

    Args:
      seed: Seeds the env's ``np_random`` (an int or ``None``); ``reset(seed=...)`` reseeds.
      render_mode: ``None`` or ``"rgb_array"`` (``render()`` returns a 480x640 overview).
      **world: Fields of :class:`~docking.world.WorldConfig`.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 2}

    def __init__(self, seed: int | None = None, render_mode: str | None = None, **world):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be None or one of {self.metadata['render_modes']}, "
                f"got {render_mode!r}"
            )
        if seed is not None and not isinstance(seed, (int, np.integer)):
            raise TypeError(f"seed must be None or an int, got {seed!r}")
        self.render_mode = render_mode
        self.config = _world_config(world)
        if seed is not None:
            self._np_random, self._np_random_seed = seeding.np_random(int(seed))
        # One generator for both: the dm_env world draws from this env's np_random.
        self.dm_env = DockingEnv(self.config, seed=self.np_random)
        spec = self.dm_env.observation_spec()
        self.observation_space = spaces.Box(
            low=float(spec.minimum), high=float(spec.maximum), shape=spec.shape, dtype=spec.dtype
        )
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


gymnasium.register(id=ENV_ID, entry_point="docking.gym:DockingGymEnv")
