"""docking: a reproduction of Kleesiek, Weber, Wermter & Engel (2011) on dm-control.

"Reward-Driven Learning of Sensorimotor Laws and Visual Features" (IEEE ICDL-EpiRob 2011):
a robot learns to dock from 32x10 camera pixels with a two-layer network (softmax feature
layer -> Q-value action layer) trained by SARSA, where the same TD error delta also trains
the visual features (Eq. 8).

Modules: ``world`` (the dm-control scene, from ``assets/docking.xml``, and the ``dm_env``
task), ``render`` (offscreen rendering), ``camera`` (the observation pipeline of Fig. 2),
``oracle`` (a pose-reading reference policy), ``network`` (Eq. 1-16), ``trial`` (SARSA
trials), ``experiments`` (Experiments 1 and 2), ``figures``, ``benchmark``.
The world is imported lazily, so ``docking.network`` works without OpenGL.
"""

__version__ = "0.1.0"

_LAZY = {
    "DockingEnv": "docking.world",
    "WorldConfig": "docking.world",
    "CameraConfig": "docking.camera",
    "Network": "docking.network",
    "NetworkConfig": "docking.network",
    "run_trial": "docking.trial",
    "TrialRecord": "docking.trial",
    "oracle_action": "docking.oracle",
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'docking' has no attribute {name!r}")
