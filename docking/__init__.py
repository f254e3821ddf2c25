"""docking: a reproduction of Kleesiek, Weber, Wermter & Engel (2011) on dm-control.

"Reward-Driven Learning of Sensorimotor Laws and Visual Features" (IEEE ICDL-EpiRob 2011):
a robot learns to dock from 32x10 camera pixels with a two-layer network (softmax feature
layer -> Q-value action layer) trained by SARSA, where the same TD error delta also trains
the visual features (Eq. 8).

The core, at this top level (``docking.core`` imports it in one line): ``world`` (the
dm-control scene, from ``assets/docking.xml``, and the ``dm_env`` task), ``render`` (offscreen
rendering), ``camera`` (the observation pipeline of Fig. 2), ``oracle`` (a pose-reading
reference policy), ``network`` (Eq. 1-16), ``trial`` (SARSA trials), ``experiments``
(Experiments 1 and 2); ``gym`` adapts the world to Gymnasium, and ``import docking.gym_ids``
registers its ids (:data:`ENV_IDS`). The study layer, the machinery of the study's many runs,
is the folder ``docking.study`` (the store and the ledger, ``designs``: every question the
package asks, as data, run by ``design``; the reports, ``figures``, the command line
``python -m docking``); docs/guide/package.md lists every module.

``import docking`` imports none of them: the names it gives (``docking.DockingEnv``,
``docking.Network``, ...) load their modules when first read, and ``docking.network`` works
without OpenGL. It does only what must precede any of the package's code: the rendering
defaults, Triton's library loaded before Mesa's (if Triton is installed), and the stat of each
of the package's files (the code the process is about to load).
"""

__version__ = "0.1.0"

import os as _os  # noqa: E402
import sys as _sys  # noqa: E402
import time as _time  # noqa: E402

# The rendering environment's defaults (MUJOCO_GL=egl, ...), before any module imports mujoco
# (docking.render does, and its code keys every run: the defaults are set here, for all).
from docking import glenv as _glenv  # noqa: E402, F401

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


# At import: every process that renders imports this package before it renders (the
# rendering modules' code keys every run, so they cannot do it themselves).
_load_triton_first()


def _sources_at_import() -> dict[str, tuple]:
    """``{file: (its os.stat_result, its SHA-256 or None)}`` of every ``.py`` file of the
    package as it is when ``docking`` is imported, before any of its code is loaded:
    :func:`docking.study.kinds.source_fingerprint` refuses to key runs with a file that has
    changed on disk since (the process would compute with the code it loaded, not the edited
    one). A file is read and hashed there, its stat compared with this one; here only stat is
    called, but a file modified in the last two seconds is hashed too, as an edit within one
    tick of the file system's clock can keep its times."""
    here = _os.path.realpath(_os.path.dirname(__file__))
    recent = _time.time_ns() - 2_000_000_000
    found = {}
    for folder, subfolders, names in _os.walk(here):
        subfolders[:] = [d for d in subfolders if d != "__pycache__"]
        for name in names:
            if not name.endswith(".py"):
                continue
            path = _os.path.join(folder, name)
            stat = _os.stat(path)
            digest = None
            if max(stat.st_mtime_ns, stat.st_ctime_ns) >= recent:
                import hashlib

                with open(path, "rb") as file:
                    digest = hashlib.sha256(file.read()).hexdigest()
            found[_os.path.relpath(path, here).replace(_os.sep, "/")] = (stat, digest)
    return found


_SOURCES_AT_IMPORT = _sources_at_import()

#: The Gymnasium ids ``import docking.gym_ids`` registers: ``{id: the preset world it starts
#: from}`` (:func:`docking.gym.preset_world`; None: the default ``WorldConfig``).
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


#: The names the package gives (read as ``docking.<name>``), each from the module that defines
#: it, imported when the name is first read: ``{name: (module, its name there)}``.
_LAZY = {
    "DockingEnv": ("docking.world", "DockingEnv"),
    "WorldConfig": ("docking.world", "WorldConfig"),
    "CameraConfig": ("docking.camera", "CameraConfig"),
    "Network": ("docking.network", "Network"),
    "NetworkConfig": ("docking.network", "NetworkConfig"),
    "run_trial": ("docking.trial", "run_trial"),
    "TrialRecord": ("docking.trial", "TrialRecord"),
    "oracle_action": ("docking.oracle", "oracle_action"),
    # what docking.gym.register() calls (its code keys PPO's runs, so it keeps the name)
    "_register_envs": ("docking.gym_ids", "register"),
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        module, attribute = _LAZY[name]
        return getattr(importlib.import_module(module), attribute)
    raise AttributeError(f"module 'docking' has no attribute {name!r}")
