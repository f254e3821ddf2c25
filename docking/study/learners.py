"""Bring your own learner: the learner protocol, and the registry that makes any learner a
kind of run like the paper's learner and PPO (stored, served from a ledger, verified,
entered into the contest, :mod:`docking.study.contest`). The guide:
docs/guide/bring_your_own_learner.md.

**The protocol.** A learner is two things.

* A *configuration*: a frozen dataclass of JSON-able fields (numbers, strings, booleans,
  tuples of them, a :class:`~docking.scene.WorldConfig`) with at least ``name`` (the results
  folder), ``world`` (the :class:`~docking.scene.WorldConfig` it trains and is judged in) and
  ``heldout_trials`` (how many greedy trials it is judged on); ``to_dict()`` and
  ``from_dict(d)`` (derived by :func:`register` when the class defines neither).
* A *run function* ``run(config, seed, progress=True, on_trials=None)``: train in
  ``config.world`` (a :class:`~docking.world.DockingEnv`, :func:`training_env`, or the
  Gymnasium env :class:`docking.gym.DockingGymEnv`), calling ``on_trials(n)`` as training
  trials finish; then return :func:`judge` of the greedy policy: a :class:`LearnerResult`
  of its held-out trials, drawn from the held-out streams of ``seed`` (so matched by seed
  with every other learner's run of ``seed``: the same first start pose, later ones following
  its own path), with its training steps and wall times.

The paper's learner and linear SARSA (:class:`~docking.experiments.ExperimentConfig`,
:func:`~docking.experiments.run_experiment`) and PPO (:class:`~docking.study.ppo.PPOConfig`,
:func:`~docking.study.ppo.run_ppo`) fit the protocol: configurations with ``name``, ``world``,
``heldout_trials``, ``to_dict``/``from_dict``; run functions of that signature, whose
results hold ``heldout`` (drawn from the same streams), the training and the wall times
(:func:`training_steps`). They are the package's built-in kinds of run (``"learner"``,
``"ppo"``: :func:`docking.study.kinds.built_in`); :func:`register` makes a kind of run of any
other.

**Keys.** A registered learner's runs are keyed as the built-in ones are
(:mod:`docking.study.store`): by the configuration (canonical JSON), the seed, the rendering stack,
the versions of the libraries (MuJoCo, dm-control, NumPy, OpenCV and those named at
registration), and the code: the learner's *own code* (:func:`own_code`: the tokens of the
module file that defines it, read as :mod:`docking.study.fingerprint` reads the package's, so a
comment or a docstring re-keys nothing; in a notebook cell or other code without a module
file, the tokens of the configuration class and the run function) and the tokens of every
``docking`` module that code imports and of :mod:`docking.protocol` (the worlds, the streams,
the held-out trials), with everything they import. This module and :mod:`docking.study.contest`
compute nothing a run stores and are not followed.

The own code is read when the learner is registered: it is the code this process runs.
A learner defined in a notebook, a script or code run with ``exec`` reaches a sweep's Dask
workers by value (cloudpickle), its runner with its class (:func:`docking.study.kinds.runner_for`
adopts it there); one defined in a module file reaches them by name, so the workers must
import that module, and every module of the user's own that its code imports
(:attr:`OwnCode.modules`). A sweep sees to it (:mod:`docking.study.sweep`): the embedded
cluster's workers get this process's import path, an existing cluster's workers are sent the
modules' files, and where a worker still cannot import one the sweep stops before any job,
naming it.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
import sys
import types
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np

from docking.experiments import TrialLog
from docking.protocol import (
    LearnerResult,
    heldout_env,
    heldout_log,
    judge,
    streams,
    training_env,
)
from docking.scene import WorldConfig
from docking.study import kinds, layouts
from docking.study.learner_run import _check_counts, _functions, _run
from docking.study.own_code import OwnCode
from docking.study.own_code import own_code as _own_code
from docking.validate import check_name

__all__ = [
    "CodeNotOnWorkers",
    "Learner",
    "LearnerResult",
    "LearnerRunner",
    "OwnCode",
    "heldout_env",
    "heldout_log",
    "judge",
    "own_code",
    "register",
    "registered",
    "runner",
    "streams",
    "training_env",
    "training_steps",
]

#: The version of the layout of a registered learner's stored runs (:func:`_arrays`).
FORMAT_VERSION = 1

#: ``docking`` modules a learner's code may import that are not followed for its key: they
#: compute nothing a run stores (the package's and the study layer's ``__init__``, this
#: registry, the contest).
NOT_FOLLOWED = frozenset(
    {"docking", "docking.study", "docking.study.learners", "docking.study.contest"}
)

#: The module every registered learner's runs are keyed by (the held-out judgement).
PROTOCOL_MODULE = "docking.protocol"
#: The module of what every registered learner's run executes around its run function (its
#: result checked against the held-out stream): keyed too.
RUN_MODULE = "docking.study.learner_run"


@runtime_checkable
class Learner(Protocol):
    """A learner's configuration (see the module docstring): what :func:`register` takes,
    and what the package's :class:`~docking.experiments.ExperimentConfig` and
    :class:`~docking.study.ppo.PPOConfig` are."""

    name: str
    world: WorldConfig
    heldout_trials: int

    def to_dict(self) -> dict: ...

    @classmethod
    def from_dict(cls, d: dict): ...


@dataclasses.dataclass(frozen=True)
class LearnerRunner(kinds.Runner):
    """The :class:`docking.study.kinds.Runner` of a registered learner: its runs are keyed by its
    own code (:attr:`code`) and the code of the ``docking`` modules of :attr:`roots`.

    Attributes:
      code: The learner's own code (:class:`OwnCode`).
      roots: :data:`PROTOCOL_MODULE` and the ``docking`` modules its code imports (each
        with every module it imports).
    """

    code: OwnCode | None = None
    roots: tuple[str, ...] = ()

    def module_digests(self, package_dir: Path | str | None = None) -> dict[str, str]:
        """``{part: digest}`` of what keys this learner's runs: ``"own code"``, every
        fingerprinted ``docking`` module of :attr:`roots`, the assets and the libraries'
        versions (what a ledger records, so that a mismatch names what changed)."""
        found = {"own code": self.code.digest}
        for root in self.roots:
            found.update(kinds.module_digests(package_dir, root=root, libraries=self.libraries))
        return dict(sorted(found.items()))

    def fingerprint(self) -> str:
        """The source fingerprint of this learner's runs: SHA-256 of :meth:`module_digests`
        (:class:`docking.study.kinds.StaleCode` if a ``docking`` file changed on disk since this
        process imported it)."""
        for root in self.roots:
            kinds.source_fingerprint(root=root, libraries=self.libraries)
        text = json.dumps(self.module_digests(), sort_keys=True)
        return hashlib.sha256(f"learner code {text}\n".encode()).hexdigest()


# ------------------------------------------------------------------------------------------
# Registration.
# ------------------------------------------------------------------------------------------


def register(
    config_type: type,
    run: Callable,
    *,
    name: str | None = None,
    libraries: tuple[str, ...] = (),
    trials: Callable | None = None,
    files: tuple = (),
) -> LearnerRunner:
    """Make the learner of ``config_type`` and ``run`` a kind of run (see the module
    docstring); returns its runner (it replaces an earlier registration of ``name``).

    Args:
      config_type: The configuration's class: a frozen dataclass with ``name``, ``world``
        and ``heldout_trials`` fields (``to_dict``/``from_dict`` are derived if it has
        neither).
      run: ``run(config, seed, progress=True, on_trials=None) -> LearnerResult``.
      name: The kind's name in stored files and ledgers (default: the class's name); not
        ``"learner"`` or ``"ppo"``.
      libraries: Distributions whose versions enter the keys besides MuJoCo's,
        dm-control's, NumPy's and OpenCV's (e.g. ``("scipy",)``).
      trials: ``trials(config)``: the trials a run reports to ``on_trials`` (default: its
        ``train_trials`` field, if any, plus ``heldout_trials``), what progress bars count.
      files: Data files the run reads (paths): keyed by their bytes, read now. A file it
        reads and does not declare is not keyed: an edit to it serves the old runs.

    Every argument is checked here, not in a run (:func:`_check_installed`,
    :func:`_check_defaults`: the default configuration's counts, ``trials`` of it)."""
    _check_config_type(config_type)
    _check_functions(run, trials)
    name = check_name("register", "name", config_type.__name__ if name is None else name)
    libraries = tuple(dict.fromkeys((*kinds._LIBRARIES, *_strings("libraries", libraries))))
    _check_installed(libraries)
    _serialisable(config_type)
    _check_defaults(config_type, trials)
    code = own_code(config_type, run, _checked_files(files))
    runner = _runner(name, config_type, run, libraries, trials, code)
    kinds.register(runner)
    setattr(config_type, kinds.RUNNER_ATTRIBUTE, runner)  # travels with a class sent by value
    return runner


def _runner(name: str, config_type: type, run: Callable, libraries, trials, code) -> LearnerRunner:
    """The kind of run of a learner whose arguments :func:`register` checked."""
    roots = (
        PROTOCOL_MODULE,
        RUN_MODULE,
        *sorted(set(code.imports) - {PROTOCOL_MODULE, RUN_MODULE}),
    )
    return LearnerRunner(
        name=name,
        config_type=config_type,
        root=PROTOCOL_MODULE,
        libraries=libraries,
        format=FORMAT_VERSION,
        key_prefix=f"learner {name} ",
        run=functools.partial(
            _run,
            run,
            files=_code_files(config_type, run),
            modules=code.keyed_names(config_type, run),
        ),
        arrays=_arrays,
        parse=_parse,
        from_table=_from_table,
        trials_in_run=_default_trials if trials is None else trials,
        test_elsewhere=False,
        code=code,
        roots=roots,
    )


def _from_table(config, seed: int, row: dict, logs: dict, walls) -> LearnerResult:
    """A registered learner's run of a ledger table's ``row``: its held-out trial log and its
    training steps where the row keeps them."""
    steps = row.get("train_steps")
    return LearnerResult(
        config=config,
        seed=seed,
        heldout=logs["heldout"],
        train_steps=None if steps is None else int(steps[0]),
        wall_time_train=walls[0],
        wall_time_test=walls[1],
    )


def _serialisable(config_type: type) -> None:
    """Give ``config_type`` ``to_dict``/``from_dict`` if it defines neither; ``TypeError`` if
    it defines one only."""
    own = [hasattr(config_type, m) for m in ("to_dict", "from_dict")]
    if own == [False, False]:
        config_type.to_dict = _to_dict
        config_type.from_dict = classmethod(_from_dict)
    elif own != [True, True]:
        raise TypeError(
            f"register: {config_type.__name__} must define both to_dict and "
            "from_dict, or neither (then both are derived)"
        )


def _checked_files(files) -> tuple:
    """``files`` (register's) as a tuple of paths; ``TypeError`` naming it otherwise."""
    if isinstance(files, str | Path) or not all(isinstance(f, str | Path) for f in files):
        raise TypeError(f"register: files must be a tuple of paths, got {files!r:.80}")
    return tuple(files)


def registered() -> dict[str, kinds.Runner]:
    """Every kind of run by name: the built-in ones and the registered learners."""
    kinds.built_in()  # PPO's runner is made on first use
    return {r.name: r for r in kinds.RUNNERS.values()}


def runner(config) -> kinds.Runner:
    """The kind of run of ``config`` (:func:`docking.study.kinds.runner_for`)."""
    return kinds.runner_for(config)


def training_steps(result) -> int | None:
    """The environment steps a run of any kind trained for: a registered learner's
    ``train_steps``; the paper's learner's pretraining and training trials' actions (None
    where a ledger's table does not keep them); PPO's budget."""
    if isinstance(result, LearnerResult):
        return result.train_steps
    train = getattr(result, "train", None)
    if isinstance(train, TrialLog):
        return int(np.sum(train.steps)) if train.steps is not None else None
    steps = getattr(result.config, "steps", None)  # PPO: the budget it trained for
    return int(steps) if steps is not None else None


def _strings(field: str, values) -> tuple[str, ...]:
    if isinstance(values, str) or not all(isinstance(v, str) for v in values):
        raise TypeError(f"register: {field} must be a tuple of names, got {values!r:.80}")
    return tuple(values)


def _check_config_type(config_type) -> None:
    if not (isinstance(config_type, type) and dataclasses.is_dataclass(config_type)):
        raise TypeError(f"register: the configuration must be a dataclass, got {config_type!r}")
    if not config_type.__dataclass_params__.frozen:
        raise TypeError(
            f"register: {config_type.__name__} must be frozen (@dataclass(frozen=True)): a "
            "run's key is taken of its configuration"
        )
    names = {f.name for f in dataclasses.fields(config_type)}
    missing = [n for n in ("name", "world", "heldout_trials") if n not in names]
    if missing:
        raise TypeError(
            f"register: {config_type.__name__} lacks the learner protocol's fields "
            f"{', '.join(missing)} (docking.study.learners)"
        )
    for own in kinds.built_in():
        if config_type is own.config_type:
            raise ValueError(f"register: {config_type.__name__} is a built-in kind of run")


def _check_functions(run, trials) -> None:
    """``TypeError`` unless ``run`` is a function and ``trials`` one or None."""
    if not isinstance(run, types.FunctionType):
        raise TypeError(f"register: run must be a function (def run(...)), got {run!r:.80}")
    if trials is not None and not callable(trials):
        raise TypeError(
            f"register: trials must be a function trials(config) -> the trials a run "
            f"reports, or None, got {trials!r:.80}"
        )


def _check_installed(libraries: tuple[str, ...]) -> None:
    """``ValueError`` naming the first of ``libraries`` that is no installed distribution
    (:func:`importlib.metadata.version` finds none: its version would be keyed as "absent",
    never its own), with the distribution of a module of that name where there is one
    (``sklearn``: ``scikit-learn``)."""
    import importlib.metadata

    for library in libraries:
        try:
            importlib.metadata.version(library)
        except (importlib.metadata.PackageNotFoundError, ValueError):
            found = importlib.metadata.packages_distributions().get(library)
            hint = (
                f"; the module {library} is distributed as {', '.join(sorted(set(found)))}"
                if found
                else ""
            )
            raise ValueError(
                f"register: libraries names {library!r}, which is no installed distribution "
                f"(importlib.metadata finds none){hint}: name distributions as pip does "
                "(e.g. 'scipy'), installed, so that their versions enter the runs' keys"
            ) from None


def _check_defaults(config_type, trials=None) -> None:
    """If every field has a default: the default configuration's counts (:data:`COUNTS`)
    are integers >= 0 (``ValueError``/``TypeError`` naming ``Class.field``), ``trials`` of
    it is one, and it round-trips through ``to_dict``/``from_dict`` as JSON."""
    try:
        config = config_type()
    except TypeError:  # a field without a default: checked when a run is keyed
        return
    check_name(config_type.__name__, "name", config.name)  # a folder of the results store
    _check_counts(config)
    if trials is not None:
        count = trials(config)
        if isinstance(count, bool | np.bool_) or not isinstance(count, int | np.integer):
            raise TypeError(
                f"register: trials(config) must be an integer, got {count!r:.80} for "
                f"{config_type.__name__}'s default configuration"
            )
        if count < 0:
            raise ValueError(
                f"register: trials(config) must be 0 or more, got {count} for "
                f"{config_type.__name__}'s default configuration"
            )
    d = config.to_dict()
    if config_type.from_dict(json.loads(json.dumps(d))) != config:
        raise ValueError(
            f"register: {config_type.__name__}'s default configuration does not round-trip "
            "through to_dict and from_dict"
        )


def _to_dict(self) -> dict:
    """Every field, nested, as JSON-ready values (tuples become lists)."""
    return json.loads(json.dumps(dataclasses.asdict(self)))


def _from_dict(cls, d: dict):
    """The configuration of ``d`` (:func:`_to_dict`'s inverse): a ``world`` (or any field
    whose default is a :class:`~docking.scene.WorldConfig`) is read back as one, lists as
    tuples."""
    from docking.experiments import _fields, _world_from_dict

    fields = _fields(cls.__name__, cls, d)
    for f in dataclasses.fields(cls):
        if f.name not in fields:
            continue
        value = fields[f.name]
        default = f.default if f.default is not dataclasses.MISSING else None
        if isinstance(value, dict) and (f.name == "world" or isinstance(default, WorldConfig)):
            fields[f.name] = _world_from_dict(value, f"{cls.__name__}.{f.name}")
        else:
            fields[f.name] = _tuples(value)
    return cls(**fields)


def _tuples(value):
    return tuple(_tuples(v) for v in value) if isinstance(value, list) else value


def _default_trials(config) -> int:
    _check_counts(config)  # the user's field named, before a sweep submits the run
    return int(getattr(config, "train_trials", 0)) + int(config.heldout_trials)


# ------------------------------------------------------------------------------------------
# Running and storing.
# ------------------------------------------------------------------------------------------


def _code_files(config_type: type, run: Callable) -> tuple[tuple[str, str], ...]:
    """``((qualified name, file), ...)`` of the learner's functions: ``run``, the
    configuration's methods and the functions and classes ``run``'s module holds."""
    objects = [run, config_type, *run.__globals__.values()]
    found = {
        f.__qualname__: f.__code__.co_filename
        for f in _functions(objects)
        if f.__module__ == run.__module__ or f.__module__ == config_type.__module__
    }
    return tuple(sorted(found.items()))


def _arrays(result: LearnerResult) -> dict[str, np.ndarray]:
    """The arrays a stored run of a registered learner holds (all but its ``meta``)."""
    arrays = {"train_steps": np.array([result.train_steps], dtype=np.int64)}
    for field in dataclasses.fields(TrialLog):
        arrays[f"heldout.{field.name}"] = getattr(result.heldout, field.name)
    return arrays


def _parse(data, config, seed: int, walls) -> LearnerResult:
    """A registered learner's run of the stored file ``data`` (its meta record checked)."""
    expected = {"meta", "train_steps"} | {f"heldout.{n}" for n in layouts.TRIAL_LOG_LAYOUT}
    layouts.expect_members(data, expected)
    steps = layouts.array(data, "train_steps", "i", 1, 8)
    if steps.shape != (1,) or steps[0] < 0:
        raise layouts.CorruptResult(f"train_steps must hold one count >= 0, got {steps!r:.80}")
    heldout = layouts.trial_log(data, "heldout", config.heldout_trials, config.world.max_steps)
    return LearnerResult(config, seed, heldout, int(steps[0]), *walls)


# ------------------------------------------------------------------------------------------
# The learner's own code.
# ------------------------------------------------------------------------------------------


def own_code(config_type: type, run: Callable, files=()) -> OwnCode:
    """The own code of the learner of ``config_type`` and ``run``, as its key reads it
    (:func:`docking.study.own_code.own_code`: what the class and the function reach, the
    modules of the user's own they import, the declared data ``files``), its ``docking``
    modules those of the package that are followed (not :data:`NOT_FOLLOWED`)."""
    code = _own_code(config_type, run, files)
    package = Path(kinds.__file__).resolve().parents[1]
    followed = sorted(m for m in code.imports if m not in NOT_FOLLOWED and _is_module(package, m))
    return dataclasses.replace(code, imports=tuple(followed))


def _is_module(package: Path, name: str) -> bool:
    """Whether ``name`` is a module of the ``docking`` package in ``package``."""
    if not name.startswith("docking."):
        return False
    relative = Path(*name.split(".")[1:])
    return (package / f"{relative}.py").is_file() or (package / relative / "__init__.py").is_file()


# ------------------------------------------------------------------------------------------
# The learner's code on a sweep's Dask workers (docking.study.sweep).
# ------------------------------------------------------------------------------------------


class CodeNotOnWorkers(RuntimeError):
    """A sweep's Dask workers cannot import a module of a registered learner's code
    (:attr:`docking.study.learners.OwnCode.modules`): raised before any job is submitted, in one
    line that names the module, its file, the worker's error and what to do."""


def modules_of(configs) -> dict[str, tuple[str, str]]:
    """``{module: (its file, the learner's name)}``: the modules of the user's own that a
    process must import to run ``configs`` (registered learners' :attr:`OwnCode.modules`; the
    built-in kinds need none)."""
    found: dict[str, tuple[str, str]] = {}
    for config in {type(c): c for c in configs}.values():
        runner = kinds.runner_for(config)
        for name, file in getattr(getattr(runner, "code", None), "modules", ()):
            found.setdefault(name, (file, runner.name))
    return found


def _module_root(name: str, file: str) -> Path | None:
    """The folder from which module ``name`` is imported as its file ``file`` (``/x`` for
    ``pkg.mod`` in ``/x/pkg/mod.py``); None if the file's path does not spell the name (a
    module loaded from a file under another name, which no import by name finds)."""
    path = Path(file)
    parts = name.split(".")
    tail = (
        [*parts, "__init__.py"] if path.name == "__init__.py" else [*parts[:-1], f"{parts[-1]}.py"]
    )
    if len(path.parts) <= len(tail) or list(path.parts[-len(tail) :]) != tail:
        return None
    return path.parents[len(tail) - 1]


def import_path(modules: Mapping[str, tuple[str, str]] | None = None) -> list[str]:
    """The folders the embedded cluster's workers import from before their own: this
    process's import path (``sys.path``, the current folder for ``""``), but the standard
    library's and site-packages' folders, which the workers (the same interpreter) have, and
    the folder each module of ``modules`` (:func:`modules_of`) is imported from by its name:
    so a worker imports what this process imports, wherever the script was started."""
    import sysconfig

    own = {
        Path(p).resolve()
        for key in ("stdlib", "platstdlib", "purelib", "platlib")
        if (p := sysconfig.get_paths().get(key))
    }
    roots = [_module_root(name, file) for name, (file, _) in sorted((modules or {}).items())]
    found: list[str] = []
    for entry in [*sys.path, *(str(r) for r in roots if r is not None)]:
        path = Path(entry or os.getcwd()).resolve()
        if not path.exists() or any(path == o or path.is_relative_to(o) for o in own):
            continue
        if str(path) not in found:
            found.append(str(path))
    return found


def ship_code(client, modules: Mapping[str, tuple[str, str]]) -> None:
    """Send the files of ``modules`` (:func:`modules_of`) to the scheduler of ``client``'s
    cluster (which unpickles the jobs it is given) and its workers, as plugins the scheduler
    keeps (a worker that joins later gets them too): each writes them under its local
    directory, laid out as their names say, puts that folder first on its import path and
    forgets any copy of them it imported before (a long-lived worker would run a learner's
    old code). A module whose file's path does not spell its name is not sent
    (:func:`check_imports` names it)."""
    import hashlib

    files: dict[str, bytes] = {}
    for name, (file, _) in sorted(modules.items()):
        root = _module_root(name, file)
        if root is not None:
            files[Path(file).relative_to(root).as_posix()] = Path(file).read_bytes()
    if not files:
        return
    digest = hashlib.sha256()
    for relative, data in sorted(files.items()):
        digest.update(f"{relative}\n{len(data)}\n".encode() + data)
    folder = f"docking-code-{digest.hexdigest()[:16]}"
    for plugin in _code_plugins(files, folder, tuple(sorted(modules))):
        client.register_plugin(plugin, name=folder)


def _code_plugins(files: dict[str, bytes], folder: str, names: tuple[str, ...]) -> tuple:
    """A ``distributed`` scheduler plugin and a worker plugin that run :func:`_receive_code`
    (classes made here, so that importing this module does not import distributed; they
    travel by value)."""
    from distributed.diagnostics.plugin import SchedulerPlugin, WorkerPlugin

    class ShipCodeToScheduler(SchedulerPlugin):
        async def start(self, scheduler):
            _receive_code(scheduler.local_directory, files, folder, names)

    class ShipCodeToWorkers(WorkerPlugin):
        def setup(self, worker):
            _receive_code(worker.local_directory, files, folder, names)

    return ShipCodeToScheduler(), ShipCodeToWorkers()


def _receive_code(local: str, files: dict[str, bytes], folder: str, names) -> None:
    """In a worker: write ``files`` (``{relative path: bytes}``) under ``local/folder``, put
    that folder first on the import path and forget the modules ``names`` imported before."""
    import importlib

    root = Path(local) / folder
    for relative, data in files.items():
        path = root / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    if str(root) in sys.path:
        sys.path.remove(str(root))
    sys.path.insert(0, str(root))
    for name in names:
        sys.modules.pop(name, None)
    importlib.invalidate_caches()


def _cannot_import(names) -> dict[str, str]:
    """In a worker: ``{module: its error}`` of the modules ``names`` it cannot import."""
    import importlib

    errors = {}
    for name in names:
        try:
            importlib.import_module(name)
        except (Exception, SystemExit) as exc:  # an ImportError, or what the module raised
            errors[name] = f"{type(exc).__name__}: {exc}"
    return errors


def check_imports(client, modules: Mapping[str, tuple[str, str]], embedded: bool) -> None:
    """The scheduler of ``client``'s cluster and every worker import the modules of
    ``modules`` (:func:`modules_of`); :class:`CodeNotOnWorkers` naming the first one
    cannot, its file, the error and what to do."""
    if not modules:
        return
    answers = {"scheduler": client.run_on_scheduler(_cannot_import, sorted(modules))}
    answers.update(sorted(client.run(_cannot_import, sorted(modules)).items()))
    for worker, errors in answers.items():
        for name, error in sorted(errors.items()):
            file, learner = modules[name]
            if _module_root(name, file) is None:
                advice = (
                    f"it was loaded from a file that is not named {name.rpartition('.')[2]}"
                    ".py, and a worker imports a learner's module by its name: save it as "
                    "such, in a folder on sys.path, or define the learner in the script "
                    "itself (its code then travels by value)"
                )
            elif embedded:
                advice = (
                    "the workers import from this process's import path (sys.path): import "
                    "the learner's modules by their names from a folder on it, or define the "
                    "learner in the script itself (its code then travels by value)"
                )
            else:
                advice = (
                    "its file was sent to the workers; install what it imports on the "
                    "workers' machines, in the workers' Python"
                )
            who = "the Dask scheduler" if worker == "scheduler" else f"the Dask worker {worker}"
            raise CodeNotOnWorkers(
                f"{who} cannot import {name} ({file}), a module of the learner {learner!r} "
                f"({error}); {advice}"
            )
