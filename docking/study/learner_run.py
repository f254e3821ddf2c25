"""What a registered learner's run executes around its own run function
(:mod:`docking.study.learners`): the result checked (its configuration, its seed, its held-out
trials drawn from the held-out stream of the seed, as many as asked for) and, for code sent by
value to a Dask worker, its functions' files restored (so that a traceback names the user's
file). Every registered learner's runs are keyed by this module's code, as by
:mod:`docking.protocol`'s: it runs inside every run.
"""

from __future__ import annotations

import time
import types
from collections.abc import Callable

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


def _run(run: Callable, config, seed: int, progress: bool = True, on_trials=None, files=None):
    """A registered learner's run: ``run``'s result, checked (its configuration and seed,
    its held-out trials drawn from the held-out stream of ``seed``, as many as the
    configuration asks for), its training time filled in if ``run`` left it out.
    ``files``: :func:`_code_files` of the learner, taken where it was registered; a copy of
    its code sent by value (to a Dask worker) gets its files back, so that a traceback from
    it names the user's file and line (cloudpickle names them ``<dynamic-code>``)."""
    if files:
        _restore_files([run, type(config), *run.__globals__.values()], dict(files))
    seed = check_int(type(config).__name__, "seed", seed, lo=0, hi=MAX_SEED)
    _check_counts(config)
    t0 = time.perf_counter()
    result = run(config, seed, progress=progress, on_trials=on_trials)
    elapsed = time.perf_counter() - t0
    what = f"the run of {type(config).__name__} {config.name!r} seed {seed}"
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
