"""What a registered learner's run executes around its own run function
(:mod:`docking.study.learners`): the result checked (its configuration, its seed, its held-out
trials drawn from the held-out stream of the seed, as many as asked for) and, for code sent by
value to a Dask worker, its functions' files restored (so that a traceback names the user's
file). Every registered learner's runs are keyed by this module's code, as by
:mod:`docking.protocol`'s: it runs inside every run.
"""

from __future__ import annotations

import functools
import importlib.metadata
import sys
import sysconfig
import time
import types
from collections.abc import Callable
from pathlib import Path

import numpy as np

from docking.protocol import LearnerResult, heldout_env
from docking.validate import MAX_COUNT, MAX_SEED, check_int

#: The count fields of a learner's configuration: the protocol's and the default trials'.
COUNTS = ("heldout_trials", "train_trials")


def _check_counts(config) -> None:
    """``ValueError``/``TypeError`` naming ``Class.field`` unless each count field
    (:data:`COUNTS`) of ``config`` is an integer in ``[0, MAX_COUNT]``."""
    for field in COUNTS:
        if hasattr(config, field):
            check_int(type(config).__name__, field, getattr(config, field), lo=0, hi=MAX_COUNT)


def _installed_folders() -> tuple[Path, ...]:
    import site

    folders = {
        Path(p).resolve()
        for key, p in sysconfig.get_paths().items()
        if key in ("stdlib", "platstdlib", "purelib", "platlib") and p
    }
    for base in {sys.prefix, sys.base_prefix, sys.exec_prefix}:
        folders.add(Path(base).resolve() / "lib")
    for p in [*getattr(site, "getsitepackages", list)(), site.getusersitepackages()]:
        folders.add(Path(p).resolve())
    return tuple(sorted(folders))


@functools.cache
def _distributed_paths() -> frozenset[Path]:
    """What the installed distributions put on the import path, by their own file lists
    (``RECORD``): each one's top-level packages and modules, wherever its folder is (a
    ``PYTHONPATH`` entry, a ``.pth`` line, ``pip install --target``), not only under this
    Python's site folders. An editable install lists only its ``.pth`` and finder, so the
    source it points to is not among them. Read once per process."""
    found = set()
    for dist in importlib.metadata.distributions():
        tops = {f.parts[0] for f in dist.files or () if f.parts}
        for top in tops:
            if top in ("..", ".") or top.endswith((".dist-info", ".egg-info", ".data")):
                continue
            path = Path(dist.locate_file(top))
            if path.exists():
                found.add(path.resolve())
    return frozenset(found)


_DOCKING = Path(__file__).resolve().parents[1]


def is_users_file(path: Path | str) -> bool:
    """Whether a module loaded from ``path`` is the user's own: a file outside the standard
    library's, the installed distributions' (their site folders and what their file lists
    name, :func:`_distributed_paths`) and ``docking``'s folders."""
    path = Path(path).resolve()
    theirs = {*_installed_folders(), *_distributed_paths(), _DOCKING}
    return not any(p in theirs for p in (path, *path.parents))


def unkeyed_modules(before, keyed) -> list[tuple[str, str]]:
    """``[(module, its file)]`` of the modules of the user's own loaded since ``before`` (the
    names ``sys.modules`` held) that ``keyed`` (the modules a learner's key covers) does not
    cover."""
    found = []
    for name in sorted(set(sys.modules) - set(before)):
        path = getattr(sys.modules.get(name), "__file__", None)
        if name in keyed or not path or name.partition(".")[0] == "docking":
            continue
        if is_users_file(path):
            found.append((name, str(path)))
    return found


def _run(
    run: Callable,
    config,
    seed: int,
    progress: bool = True,
    on_trials=None,
    files=None,
    modules: tuple[str, ...] | None = None,
):
    """A registered learner's run: ``run``'s result, checked (its configuration and seed,
    its held-out trials drawn from the held-out stream of ``seed``, as many as the
    configuration asks for), its training time filled in if ``run`` left it out.
    ``files``: :func:`_code_files` of the learner, taken where it was registered; a copy of
    its code sent by value (to a Dask worker) gets its files back, so that a traceback from
    it names the user's file and line (cloudpickle names them ``<dynamic-code>``).
    ``modules``: the modules of the user's own its key covers; a run that loads another is
    refused (its key cannot have seen that code), so it is never stored."""
    if files:
        _restore_files([run, type(config), *run.__globals__.values()], dict(files))
    seed = check_int(type(config).__name__, "seed", seed, lo=0, hi=MAX_SEED)
    _check_counts(config)
    before = set(sys.modules)
    t0 = time.perf_counter()
    result = run(config, seed, progress=progress, on_trials=on_trials)
    elapsed = time.perf_counter() - t0
    what = f"the run of {type(config).__name__} {config.name!r} seed {seed}"
    unkeyed = unkeyed_modules(before, modules or ()) if modules is not None else []
    if unkeyed:
        name, path = unkeyed[0]
        raise RuntimeError(
            f"{what} loaded {name} ({path}), a module of your own that its key does not cover "
            "(imported while it ran, e.g. by importlib): the run is not stored. Import it at "
            "the top of the learner's module (or of a module it imports)"
        )
    if not isinstance(result, LearnerResult):
        raise TypeError(f"{what} returned {type(result).__name__}, not a LearnerResult (judge)")
    if result.config != config or result.seed != seed:
        raise ValueError(f"{what} returned the result of another configuration or seed")
    n = len(result.heldout)
    if n != config.heldout_trials:
        raise ValueError(
            f"{what} returned {n} held-out trials, its configuration asks for "
            f"{config.heldout_trials}"
        )
    if n and not np.array_equal(result.heldout.starts[0], _first_heldout_start(config, seed)):
        raise ValueError(
            f"{what}: its held-out trials are not drawn from the held-out stream of seed {seed} "
            "(judge them with docking.study.learners.judge)"
        )
    if result.wall_time_train is None:
        result.wall_time_train = max(elapsed - result.wall_time_test, 0.0)
    return result


#: What cloudpickle names the file of code it sends by value.
_DYNAMIC = "<dynamic-code>"


def _functions(objects) -> list:
    """The functions among ``objects`` and the functions of the classes among them."""
    found = []
    for obj in objects:
        if isinstance(obj, types.FunctionType):
            found.append(obj)
        elif isinstance(obj, type):
            found += [f for f in vars(obj).values() if isinstance(f, types.FunctionType)]
    return found


def _restore_files(objects, files: dict[str, str]) -> None:
    """Give each function among ``objects`` whose code cloudpickle renamed
    ``<dynamic-code>`` its file back (``files``: :func:`_code_files`), nested code included."""

    def renamed(code: types.CodeType, file: str) -> types.CodeType:
        consts = tuple(
            renamed(c, file) if isinstance(c, types.CodeType) else c for c in code.co_consts
        )
        return code.replace(co_filename=file, co_consts=consts)

    for function in _functions(objects):
        file = files.get(function.__qualname__)
        if file is not None and function.__code__.co_filename == _DYNAMIC:
            function.__code__ = renamed(function.__code__, file)


def _first_heldout_start(config, seed: int) -> np.ndarray:
    """The first start pose of the held-out stream of ``seed`` in ``config.world``."""
    env = heldout_env(config.world, seed)
    env.reset()
    return env.pose
