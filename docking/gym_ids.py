"""What ``gymnasium.make`` builds for the ids of :data:`docking.ENV_IDS`: the adapter
:class:`docking.gym.DockingGymEnv`, with its arguments and actions checked here.

The adapter's code is part of the fingerprint of PPO's runs (:mod:`docking.ppo` builds it), so
checks that its code could hold live in this module instead, which no run imports: a
``seed`` that is no integer (``seed=True``) and, in a world with continuous actions
(``docking/Continuous-v0``), an action that is no vector of real numbers (strings, bools,
complex numbers, which numpy would convert or truncate) are refused the way the discrete ids
refuse them: a ``ValueError`` (or ``TypeError``) naming what was expected. A valid action
reaches the adapter unchanged.
"""

from __future__ import annotations

import numpy as np

from docking.gym import DockingGymEnv
from docking.validate import MAX_SEED, check_int

__all__ = ["CheckedDockingGymEnv"]


class CheckedDockingGymEnv(DockingGymEnv):
    """:class:`docking.gym.DockingGymEnv` with its ``seed`` and continuous actions checked
    (see the module docstring); the entry point of every registered id."""

    def __init__(self, seed: int | None = None, **kwargs):
        if seed is not None:  # NumPy integers too, as reset(seed=...) takes them
            check_int("DockingGymEnv", "seed", seed, lo=0, hi=MAX_SEED)
        super().__init__(seed=seed, **kwargs)

    def step(self, action):
        if self.config.continuous:
            _check_vector(action, self.config.action_names)
        return super().step(action)


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
