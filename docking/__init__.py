"""docking: a reproduction of Kleesiek, Weber, Wermter & Engel (2011) on dm-control.

"Reward-Driven Learning of Sensorimotor Laws and Visual Features" (IEEE ICDL-EpiRob 2011):
a robot learns to dock from 32x10 camera pixels with a two-layer network (softmax feature
layer -> Q-value action layer) trained by SARSA, where the same TD error delta also trains
the visual features (Eq. 8).

The core, at this top level (``docking.core`` imports it in one line): ``world`` (the
dm-control scene, from ``assets/docking.xml``, and the ``dm_env`` task), ``render`` (offscreen
rendering), ``camera`` (the observation pipeline of Fig. 2), ``oracle`` (a pose-reading
reference policy), ``network`` (Eq. 1-16), ``trial`` (SARSA trials), ``experiments``
(Experiments 1 and 2). The study layer, the machinery of the study's many runs, is the folder
``docking.study`` (the store and the ledger, ``designs``: every question the package asks, as
data, run by ``design``; the reports, ``figures``, the command line); docs/guide/package.md
lists every module. The world is imported lazily, so ``docking.network`` works without
OpenGL.
"""

__version__ = "0.1.0"

import os as _os  # noqa: E402
import signal as _signal  # noqa: E402
import sys as _sys  # noqa: E402

#: The command line's name in its messages (:data:`docking.study.cli.PROG`), here because
#: ``python -m docking`` may need it before the command line is imported.
_PROG = "python -m docking"


def _exit_on_ctrl_c(signum, frame):
    """Ctrl-C while ``python -m docking`` is importing: one line and status 130, nothing to
    undo. (A KeyboardInterrupt there is a traceback, or an ImportError when an extension
    module's initialisation meets it.)"""
    print(f"{_PROG}: interrupted", file=_sys.stderr, flush=True)
    _os._exit(130)


def _take_ctrl_c() -> bool:
    """Make Ctrl-C :func:`_exit_on_ctrl_c`, unless SIGINT is ignored (a shell's background
    job: it stays ignored, as Python leaves it); whether it did."""
    if _signal.getsignal(_signal.SIGINT) is _signal.SIG_IGN:
        return False
    _signal.signal(_signal.SIGINT, _exit_on_ctrl_c)
    return True


# ``python -m docking ...`` imports this package before docking.__main__, while argv[0] is
# still "-m": the handler then covers the imports below too (gymnasium and numpy, the larger
# part of the command's start). ``import docking`` anywhere else leaves Ctrl-C alone.
if _sys.argv[:1] == ["-m"] and "docking" in getattr(_sys, "orig_argv", ()):
    _take_ctrl_c()

# The rendering environment's defaults (MUJOCO_GL=egl, ...), before anything imports mujoco.
from docking import glenv as _glenv  # noqa: E402


def _check_opengl_platform() -> None:
    """:class:`docking.glenv.RenderingUnavailable` in one line, before dm-control's renderer
    fails with an ``ImportError`` on its first import, when ``PYOPENGL_PLATFORM`` names
    another platform than the ``MUJOCO_GL`` backend (egl or osmesa) it must match. (Here, not
    in :mod:`docking.glenv`, whose code keys every run.)"""
    backend = _os.environ.get("MUJOCO_GL", "")
    platform = _os.environ.get("PYOPENGL_PLATFORM", "")
    if backend in ("egl", "osmesa") and platform not in ("", backend):
        raise _glenv.RenderingUnavailable(
            f"PYOPENGL_PLATFORM={platform!r} does not match MUJOCO_GL={backend}: dm-control "
            f"renders with {backend} only if PYOPENGL_PLATFORM is unset or {backend!r}"
        )


#: A symbol every LLVM library exports (its C API): when it resolves in the process's global
#: scope, a library holding another LLVM that binds through that scope binds to this one.
_LLVM_SYMBOL = "LLVMContextCreate"


def _triton_library() -> str | None:
    """The path of Triton's compiler library (``triton/_C/libtriton*.so``, a copy of LLVM
    inside), or None if Triton is not installed or already imported. Imports nothing."""
    import importlib.machinery
    import importlib.util

    if "triton" in _sys.modules or not _sys.platform.startswith("linux"):
        return None
    try:
        spec = importlib.util.find_spec("triton")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    places = [_os.path.join(p, "_C") for p in spec.submodule_search_locations]
    library = importlib.machinery.PathFinder.find_spec("libtriton", places)
    return None if library is None else library.origin


def _load_triton_first() -> int | None:
    """Load Triton's compiler library, if Triton is installed, before rendering loads Mesa's
    LLVM; the ``dlopen`` mode it used (None if it loaded nothing).

    Mesa opens its llvmpipe driver (``swrast_dri.so``) with ``RTLD_GLOBAL``, which puts the
    system's ``libLLVM`` into the process's global symbol scope. libtriton exports the symbols
    of its own, newer LLVM and binds its references to them through the global scope first, so
    when it is loaded after Mesa (``torch.optim`` imports ``torch._dynamo``, which imports
    Triton) part of them bind to Mesa's LLVM, whose data structures differ, and its static
    initialisers crash the process (``llvm::DebugCounter::instance()``: issue 53). Loaded
    first, ``RTLD_LOCAL``, its references bind to itself, and the later ``import triton``
    finds it loaded. If an LLVM is already global here (``dm_control.mujoco`` was imported
    before ``docking``), it is loaded with ``RTLD_DEEPBIND``: its own symbols before the
    global scope's."""
    path = _triton_library()
    if path is None:
        return None
    import ctypes

    mode = _os.RTLD_NOW | _os.RTLD_LOCAL
    if hasattr(ctypes.CDLL(None), _LLVM_SYMBOL):
        mode |= getattr(_os, "RTLD_DEEPBIND", 0)
    try:
        ctypes.CDLL(path, mode=mode)
    except OSError:  # a broken install: ``import triton`` will say what is wrong
        return None
    return mode


_load_triton_first()


def _snapshot_sources() -> dict:
    """SHA-256 of every ``.py`` file of the package as it is when ``docking`` is imported:
    :mod:`docking.study.store` fingerprints this code, and refuses to key runs if a file has changed
    on disk since (the process would compute with the code it loaded, not the edited one)."""
    import hashlib
    from pathlib import Path

    here = Path(__file__).resolve().parent
    return {
        p.relative_to(here).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(here.rglob("*.py"))
        if "__pycache__" not in p.parts
    }


_SOURCES_AT_IMPORT = _snapshot_sources()

#: The Gymnasium ids ``import docking`` registers: ``{id: the preset world it starts from}``
#: (:func:`docking.gym.preset_world`; None: the default ``WorldConfig``).
ENV_IDS = {
    "docking/Docking-v0": None,
    "docking/Experiment1-v0": "experiment1",
    "docking/Experiment2-v0": "experiment2",
    "docking/Floor-v0": "floor",
    "docking/Turning-v0": "turning",
    "docking/Precision-v0": "precision",
    "docking/Nao-v0": "nao",
    "docking/Continuous-v0": "continuous",
}


def _register_envs() -> None:
    """Register :data:`ENV_IDS` with Gymnasium (if installed); the environments and their
    worlds are built only by ``gymnasium.make``."""
    try:
        import gymnasium
    except ImportError:  # pragma: no cover - gymnasium is a dependency
        return
    from docking.scene import WorldConfig

    steps = WorldConfig.__dataclass_fields__["max_steps"].default  # the presets keep it
    for env_id, preset in ENV_IDS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(
                id=env_id,
                # the adapter with its seed and actions checked (docking/gym_ids.py)
                entry_point="docking.gym_ids:CheckedDockingGymEnv",
                kwargs={"preset": preset},
                max_episode_steps=steps,
                # Gymnasium 1.4's PassiveEnvChecker counts its first reset as checked before
                # it returns: after a refused first reset(seed='0') the next step fails inside
                # it (issue 52). check_env passes on every id (tests/test_gym.py).
                disable_env_checker=True,
            )


_register_envs()

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
