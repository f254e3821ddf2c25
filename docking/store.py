"""The results store: every run saved under a key of what produced it.

A run of :func:`docking.experiments.run_experiment` is fully determined by its configuration,
its seed and the code that computes it. Its key is the SHA-256 of

* the configuration, every field, as canonical JSON (:meth:`ExperimentConfig.to_dict`);
* the *source fingerprint*: the code of ``docking.experiments`` and of every ``docking``
  module it imports, directly or indirectly (world, camera, network, trial, ...), read as
  Python syntax trees without docstrings and comments (so prose edits do not invalidate
  results, any code change does), plus every file under ``docking/assets/``, plus the
  versions of the libraries whose arithmetic the runs depend on (MuJoCo, dm-control, NumPy,
  OpenCV);

and the seed names the file: ``<results>/<config.name>/<key[:16]>/seed<k>.npz`` (the folder
also holds ``config.json``, the configuration in readable form). Variants of one experiment
therefore live side by side, and a code change makes every run be recomputed without anyone
deleting ``results/``.

Loading validates a file (every array present with the right shape and dtype, consistent
lengths, the configuration round-trips, the key matches). :func:`run_or_load` treats any
failure as a warning that names the file and the reason, recomputes the run and replaces the
file. Files are written by :func:`docking.fileio.atomic_write`; temporary files of killed
writers are cleaned up before the next write. The results folder is checked for writability
before a run starts.
"""

from __future__ import annotations

import ast
import dataclasses
import functools
import hashlib
import importlib.metadata
import io
import json
import os
import tempfile
import warnings
from pathlib import Path

import numpy as np

from docking import paths
from docking.experiments import ExperimentConfig, ExperimentResult, TrialLog, run_experiment
from docking.fileio import atomic_write, remove_stale_temporaries
from docking.network import Network
from docking.validate import check_instance, check_int

__all__ = [
    "CorruptResult",
    "FORMAT_VERSION",
    "check_writable",
    "load_result",
    "result_path",
    "run_key",
    "run_or_load",
    "run_seeds",
    "save_result",
    "source_fingerprint",
]

#: Version of the file layout written by :func:`save_result`.
FORMAT_VERSION = 2

#: The module whose code, with everything it imports from the package, computes results.
_ROOT_MODULE = "docking.experiments"

#: Libraries whose versions enter the key: their arithmetic decides the runs bit for bit.
_LIBRARIES = ("mujoco", "dm-control", "numpy", "opencv-python-headless")


class CorruptResult(ValueError):
    """A saved result that cannot be used: unreadable, incomplete or inconsistent."""


# ------------------------------------------------------------------------------------------
# Keys.
# ------------------------------------------------------------------------------------------


def _code_of(source: str) -> str:
    """The syntax tree of Python ``source`` without docstrings, as a string."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if (
                body
                and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)
            ):
                node.body = body[1:] or [ast.Pass()]
    return ast.dump(tree, annotate_fields=False)


def _imported_package_modules(tree: ast.AST, module: str) -> set[str]:
    """Names of the ``docking`` modules that ``module``'s syntax tree imports."""
    found = set()
    package = module.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:  # relative import
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([base] if base else []))
            names = [base] + [f"{base}.{alias.name}" for alias in node.names]
        else:
            continue
        found.update(name for name in names if name.startswith("docking."))
    return found  # names that are not modules (``docking.world.DockingEnv``) find no file


def _module_file(name: str, package_dir: Path) -> Path | None:
    relative = Path(*name.split(".")[1:])
    for candidate in (package_dir / f"{relative}.py", package_dir / relative / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def source_fingerprint(package_dir: Path | str | None = None) -> str:
    """SHA-256 of the code that computes results (see the module docstring).

    ``package_dir`` is the ``docking`` package folder to read (default: this package's)."""
    package_dir = (Path(package_dir) if package_dir else Path(__file__).parent).resolve()
    # Cached by the files' sizes and modification times, so an edit is always seen.
    stamp = tuple(
        (str(p), st.st_mtime_ns, st.st_size)
        for p in sorted(package_dir.rglob("*"))
        if "__pycache__" not in p.parts and p.is_file() and (st := p.stat())
    )
    return _source_fingerprint(package_dir, stamp)


@functools.lru_cache(maxsize=8)
def _source_fingerprint(package_dir: Path, stamp: tuple) -> str:
    digest = hashlib.sha256()
    seen, queue = set(), [_ROOT_MODULE]
    while queue:
        name = queue.pop()
        if name in seen:
            continue
        seen.add(name)
        path = _module_file(name, package_dir)
        if path is None:
            continue
        source = path.read_text(encoding="utf-8")
        queue.extend(_imported_package_modules(ast.parse(source), name))
        digest.update(f"module {name}\n{_code_of(source)}\n".encode())
    assets = package_dir / "assets"
    if assets.is_dir():
        for path in sorted(p for p in assets.rglob("*") if p.is_file()):
            digest.update(f"asset {path.relative_to(assets).as_posix()}\n".encode())
            digest.update(path.read_bytes())
    for library in _LIBRARIES:
        try:
            version = importlib.metadata.version(library)
        except importlib.metadata.PackageNotFoundError:
            version = "absent"
        digest.update(f"library {library} {version}\n".encode())
    return digest.hexdigest()


def _canonical(config: ExperimentConfig) -> str:
    return json.dumps(config.to_dict(), sort_keys=True, separators=(",", ":"))


def config_key(config: ExperimentConfig) -> str:
    """SHA-256 of the canonical configuration and the source fingerprint (the folder key)."""
    check_instance("config_key", "config", config, ExperimentConfig)
    text = f"format {FORMAT_VERSION}\nconfig {_canonical(config)}\nsource {source_fingerprint()}"
    return hashlib.sha256(text.encode()).hexdigest()


def run_key(config: ExperimentConfig, seed: int) -> str:
    """The key of the run of (``config``, ``seed``): the configuration key and the seed."""
    seed = check_int("run_key", "seed", seed, lo=0)
    return f"{config_key(config)}:seed{seed}"


def result_path(config: ExperimentConfig, seed: int, results_dir: Path | str | None = None) -> Path:
    """Where the run of (``config``, ``seed``) is stored (see the module docstring)."""
    seed = check_int("result_path", "seed", seed, lo=0)
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    return root / config.name / config_key(config)[:16] / f"seed{seed}.npz"


# ------------------------------------------------------------------------------------------
# Saving and loading.
# ------------------------------------------------------------------------------------------


def save_result(result: ExperimentResult, path: Path | str) -> Path:
    """Write ``result`` to ``path`` (compressed .npz) atomically; also ``config.json`` beside
    it (the configuration, readable). Returns ``path``."""
    path = Path(path)
    meta = {
        "format": FORMAT_VERSION,
        "key": run_key(result.config, result.seed),
        "config": result.config.to_dict(),
        "seed": result.seed,
        "wall_time_train": float(result.wall_time_train),
        "wall_time_test": float(result.wall_time_test),
    }
    arrays = {
        "meta": np.array(json.dumps(meta)),
        "W": result.network.W,
        "Q": result.network.Q,
        "curve_trials": result.curve_trials,
        "curve_success": result.curve_success,
        "curve_steps": result.curve_steps,
        "curve_rewarded": result.curve_rewarded,
    }
    for part in ("train", "test", "heldout"):
        log = getattr(result, part)
        for field in dataclasses.fields(TrialLog) if log is not None else ():
            arrays[f"{part}.{field.name}"] = getattr(log, field.name)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    remove_stale_temporaries(path)
    atomic_write(path, lambda f: f.write(buffer.getvalue()))
    config_json = path.parent / "config.json"
    if not config_json.exists():
        text = json.dumps(meta["config"], indent=2, sort_keys=True) + "\n"
        remove_stale_temporaries(config_json)
        atomic_write(config_json, lambda f: f.write(text.encode()))
    return path


#: dtype kind and number of dimensions of every array in a result file.
_TRIAL_LOG_LAYOUT = {
    "success": ("b", 1),
    "steps": ("i", 1),
    "start_far": ("f", 1),
    "poses": ("f", 2),
    "actions": ("i", 1),
    "winners": ("i", 1),
    "deltas": ("f", 1),
}
_CURVE_LAYOUT = {
    "curve_trials": ("i", 1),
    "curve_success": ("f", 1),
    "curve_steps": ("f", 1),
    "curve_rewarded": ("i", 1),
}


def _array(data, name: str, kind: str, ndim: int) -> np.ndarray:
    if name not in data.files:
        raise CorruptResult(f"array {name!r} is missing")
    array = data[name]
    if array.dtype.kind != kind or array.ndim != ndim:
        raise CorruptResult(
            f"array {name!r} has dtype {array.dtype} and {array.ndim} dimensions, expected "
            f"kind {kind!r} and {ndim}"
        )
    return array


def _trial_log(data, part: str, expected_trials: int) -> TrialLog:
    fields = {
        name: _array(data, f"{part}.{name}", kind, ndim)
        for name, (kind, ndim) in _TRIAL_LOG_LAYOUT.items()
    }
    log = TrialLog(**fields)
    n = len(log.success)
    if n != expected_trials:
        raise CorruptResult(f"{part} holds {n} trials, the configuration {expected_trials}")
    if len(log.steps) != n or len(log.start_far) != n:
        raise CorruptResult(f"{part}: per-trial arrays of different lengths")
    if np.any(log.steps < 1):
        raise CorruptResult(f"{part}: a trial with no action")
    actions = int(np.sum(log.steps))
    if log.poses.shape != (actions + n, 3):
        raise CorruptResult(
            f"{part}.poses has shape {log.poses.shape}, expected ({actions + n}, 3)"
        )
    for name in ("actions", "winners", "deltas"):
        if len(fields[name]) != actions:
            raise CorruptResult(
                f"{part}.{name} holds {len(fields[name])} steps, expected {actions}"
            )
    return log


def load_result(path: Path | str) -> ExperimentResult:
    """Read and validate a result written by :func:`save_result`; ``CorruptResult`` (naming
    the reason) if the file cannot be used."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            return _parse(data)
    except CorruptResult:
        raise
    except Exception as exc:  # unreadable: truncated, bit flips, not a zip, ...
        raise CorruptResult(f"{type(exc).__name__}: {exc}") from exc


def _parse(data) -> ExperimentResult:
    if "meta" not in data.files:
        raise CorruptResult("no 'meta' record")
    try:
        meta = json.loads(str(data["meta"]))
        config = ExperimentConfig.from_dict(meta["config"])
        seed = check_int("meta", "seed", meta["seed"], lo=0)
        fmt, key = meta["format"], meta["key"]
        walls = float(meta["wall_time_train"]), float(meta["wall_time_test"])
    except (ValueError, TypeError, KeyError, AttributeError) as exc:
        raise CorruptResult(f"bad meta record: {type(exc).__name__}: {exc}") from exc
    if fmt != FORMAT_VERSION:
        raise CorruptResult(f"file format {fmt}, this package reads {FORMAT_VERSION}")
    if config.to_dict() != meta["config"]:
        raise CorruptResult("the configuration does not round-trip")
    if key != run_key(config, seed):
        raise CorruptResult("made by other code or another configuration (key mismatch)")
    net = config.network
    W = _array(data, "W", "f", 2)
    Q = _array(data, "Q", "f", 2)
    if W.shape != (net.n_features, net.n_inputs) or Q.shape != (net.n_actions, net.n_features):
        raise CorruptResult(f"W {W.shape} or Q {Q.shape} do not fit the network")
    curve = {name: _array(data, name, kind, ndim) for name, (kind, ndim) in _CURVE_LAYOUT.items()}
    points = 1 + config.train_trials // config.eval_every if config.eval_trials else 0
    if any(len(v) != points for v in curve.values()):
        raise CorruptResult(f"learning-curve arrays must hold {points} points")
    try:
        network = Network.from_weights(config.network, W, Q)
    except ValueError as exc:
        raise CorruptResult(str(exc)) from exc
    return ExperimentResult(
        config=config,
        seed=seed,
        network=network,
        train=_trial_log(data, "train", config.train_trials),
        test=_trial_log(data, "test", config.test_trials),
        heldout=(
            _trial_log(data, "heldout", config.heldout_trials) if config.heldout_trials else None
        ),
        **curve,
        wall_time_train=walls[0],
        wall_time_test=walls[1],
    )


def check_writable(results_dir: Path | str | None = None) -> Path:
    """Make sure the results folder exists and a file can be written there; ``PermissionError``
    (an ``OSError``) naming the path otherwise. Returns the folder."""
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    try:
        root.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".write-test.", suffix=".tmp", dir=root)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise PermissionError(
            f"the results folder {str(root)!r} is not writable ({type(exc).__name__}: {exc}); "
            "choose another with DOCKING_RESULTS or results_dir="
        ) from exc
    return root


def run_or_load(
    config: ExperimentConfig,
    seed: int,
    results_dir: Path | str | None = None,
    force: bool = False,
    progress: bool = True,
) -> ExperimentResult:
    """The run of (``config``, ``seed``): loaded from the store if a valid file with its key
    is there, otherwise computed and saved (a bad file is a warning, then replaced).
    ``force`` recomputes and replaces whatever is stored."""
    path = result_path(config, seed, results_dir)
    remove_stale_temporaries(path)  # of writers killed during an earlier save
    if path.exists() and not force:
        try:
            return load_result(path)
        except CorruptResult as exc:
            warnings.warn(
                f"ignoring the stored result {path}: {exc}; recomputing it",
                RuntimeWarning,
                stacklevel=2,
            )
    check_writable(path.parent)
    result = run_experiment(config, seed, progress=progress)
    save_result(result, path)
    return result


def _run_or_load_job(args) -> str:
    config, seed, results_dir, force = args
    run_or_load(config, seed, results_dir, force=force, progress=False)
    return str(result_path(config, seed, results_dir))


def run_seeds(
    config: ExperimentConfig,
    seeds,
    results_dir: Path | str | None = None,
    force: bool = False,
    processes: int | None = None,
    progress: bool = True,
) -> list[ExperimentResult]:
    """Run (or load) ``config`` for every seed, several seeds at once in worker processes
    (one per core by default; each renders with its own OpenGL context)."""
    from tqdm.auto import tqdm

    seeds = [check_int("run_seeds", "seeds[]", s, lo=0) for s in seeds]
    check_writable(results_dir)
    processes = processes or min(len(seeds), os.cpu_count() or 1)
    jobs = [(config, s, results_dir, force) for s in seeds]
    if processes <= 1:
        paths_ = [_run_or_load_job(j) for j in tqdm(jobs, desc=config.name, disable=not progress)]
    else:
        import multiprocessing

        with multiprocessing.get_context("spawn").Pool(processes) as pool:
            paths_ = list(
                tqdm(
                    pool.imap(_run_or_load_job, jobs),
                    total=len(jobs),
                    desc=f"{config.name}, {len(seeds)} seeds",
                    disable=not progress,
                )
            )
    return [load_result(p) for p in paths_]
