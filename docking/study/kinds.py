"""The kinds of run, the key of each run and the file that holds it: what the results store
(:mod:`docking.study.store`) and the committed ledger (:mod:`docking.study.ledger`) both build
on, so that neither calls the other.

There are kinds of run, one :class:`Runner` each, looked up by the type of the configuration
(:func:`runner_for`): the paper's learner and its yardsticks (``"learner"``:
:class:`docking.experiments.ExperimentConfig`, :func:`docking.experiments.run_experiment`)
and the pixel-level bound (``"ppo"``: :class:`docking.study.ppo.PPOConfig`,
:func:`docking.study.ppo.run_ppo`); a learner from outside the package becomes a kind of run of
its own when it is registered (:func:`register`, through :func:`docking.study.learners.register`).
A runner names the module whose code computes its runs, the libraries whose versions enter its
keys, how a run is computed, which arrays it stores and how they are read back (the built-in
kinds' in :mod:`docking.study.layouts`); everything else here (keys, paths, saving, loading,
the checks) is one implementation for every kind.

A run is fully determined by its configuration, its seed and the code that computes it. Its
key is the SHA-256 of

* the configuration, every field, as canonical JSON (``config.to_dict()``);
* the *source fingerprint*: the code of the runner's root module (``docking.experiments`` for
  the learner, ``docking.study.ppo`` for PPO) and of every ``docking`` module its code imports,
  directly or indirectly (world, camera, network, trial, ...), read by
  :mod:`docking.study.fingerprint` as Python tokens without comments, docstrings, error
  messages and the validation, parsing and serialisation it names (so a reworded message or
  docstring re-keys nothing, a change to what computes a run does; the same on every Python),
  plus every file under ``docking/assets/``, plus the versions of the libraries whose
  arithmetic the runs depend on (MuJoCo, dm-control, NumPy, OpenCV; for PPO also skrl, JAX,
  Flax, Optax and Gymnasium). It is taken of the code this process *loaded*: if a
  fingerprinted file has changed on disk since ``docking`` was imported, keying a run raises
  :class:`StaleCode` (the run would be computed by the old code and stored under the new
  code's key);
* the *rendering stack* (:func:`docking.render.gl_stack`: the OpenGL version, renderer and
  vendor strings, e.g. Mesa's version and llvmpipe's), which draws every observation;

and the seed names the file: ``<results>/<config.name>/<key[:16]>/seed<k>.npz``
(:func:`result_path`; the folder also holds ``config.json``, the configuration in readable
form). Variants of one experiment therefore live side by side, and a code change makes every
run be recomputed without anyone deleting ``results/``.

Every file carries a SHA-256 *content digest* of its arrays (:func:`content_digest`; the
wall times in its meta record are not part of it). Loading validates a file
(:func:`load_result`): every member's size is checked against the configuration before it is
decompressed, every array present with the right shape and dtype, consistent lengths, poses,
TD errors and weights finite, the configuration round-trips, the key stored in the file equals
the key of its configuration under this code *and* the key asked for, and the digest matches
the arrays. Files are written by :func:`docking.fileio.atomic_write` (:func:`save_result`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import importlib.metadata
import io
import json
import os
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from docking.experiments import (
    ExperimentConfig,
    run_experiment,
    trials_in_run,
)
from docking.fileio import UnsafeFile, atomic_write, read_regular, remove_stale_temporaries
from docking.study import fingerprint, paths
from docking.study.layouts import (
    CorruptResult,
    learner_from_table,
    member_size,
    parse_learner,
    parse_ppo,
    ppo_from_table,
    result_arrays,
)
from docking.validate import MAX_SEED, check_int, check_name

__all__ = [
    "CorruptResult",
    "FORMAT_VERSION",
    "ForeignFile",
    "EXTRAS",
    "LEARNER",
    "MissingExtra",
    "RUNNERS",
    "Runner",
    "StaleCode",
    "built_in",
    "computed_utc",
    "config_json",
    "config_key",
    "content_digest",
    "is_valid",
    "load_result",
    "missing_extra",
    "module_digests",
    "register",
    "require_extra",
    "rendering_stack",
    "result_arrays",
    "result_path",
    "run_key",
    "runner_for",
    "runner_named",
    "save_result",
    "source_fingerprint",
]

#: Version of the file layout of the learner's runs written by :func:`save_result` (3: the
#: content digest); a PPO run's is :data:`docking.study.ppo.FORMAT_VERSION`.
FORMAT_VERSION = 3

#: The module whose code, with everything it imports from the package, computes results.
_ROOT_MODULE = "docking.experiments"

#: Libraries whose versions enter the key: their arithmetic decides the runs bit for bit.
_LIBRARIES = ("mujoco", "dm-control", "numpy", "opencv-python-headless")


class MissingExtra(ModuleNotFoundError):
    """A run must be computed by a kind of run whose optional dependencies are not installed:
    the message names the package's extra that installs them."""


#: Per kind of run, the modules of the optional dependencies its runs need to be computed and
#: the extra of the package that installs them (pyproject.toml's
#: [project.optional-dependencies]); reading its stored or published runs needs none of them.
EXTRAS = {"ppo": (("skrl", "jax", "flax", "optax"), "ppo")}


def missing_extra(runner_name: str) -> str | None:
    """If the optional dependencies of ``runner_name``'s runs are not installed, what is
    missing and the ``pip install`` line that installs them; else None."""
    import importlib.util

    modules, extra = EXTRAS.get(runner_name, ((), ""))
    absent = [m for m in modules if importlib.util.find_spec(m) is None]
    if not absent:
        return None
    return (
        f"the [{extra}] extra is not installed ({', '.join(absent)} missing): "
        f"pip install 'docking[{extra}]'"
    )


def require_extra(config) -> None:
    """:class:`MissingExtra` naming the extra if the runs of ``config``'s kind cannot be
    computed here (its optional dependencies are not installed)."""
    name = runner_for(config).name
    missing = missing_extra(name)
    if missing is not None:
        raise MissingExtra(
            f"a {name} run of {config.name!r} is neither stored nor in the ledger and must be "
            f"computed here: {missing}"
        )


class ForeignFile(CorruptResult):
    """A stored result's path holds what the store never writes (a FIFO, a device, a link out
    of its folder, a file beyond the size bound): refused, never read and never replaced."""


class StaleCode(RuntimeError):
    """The package's code on disk is not the code this process loaded: a run computed now
    would be stored under a key that does not describe it."""


# ------------------------------------------------------------------------------------------
# Keys.
# ------------------------------------------------------------------------------------------


def source_fingerprint(
    package_dir: Path | str | None = None,
    root: str = _ROOT_MODULE,
    libraries: tuple[str, ...] = _LIBRARIES,
) -> str:
    """SHA-256 of the code that computes results (see the module docstring).

    ``package_dir`` is the ``docking`` package folder to read (default: this package's, whose
    files must still be those this process imported, or :class:`StaleCode` is raised);
    ``root`` and ``libraries`` name another computation's code (e.g. :mod:`docking.study.ppo`'s)."""
    own = _OWN
    package_dir = Path(package_dir).resolve() if package_dir else own
    fingerprint, _, files = _fingerprint_parts(package_dir, root, tuple(libraries))
    if package_dir == own:
        changed = _changed_since_import(files)
        if changed:
            raise StaleCode(
                f"docking's code changed on disk after this process imported it "
                f"({', '.join('docking/' + f for f in changed)}): a run computed now would use "
                "the code in memory but be keyed by the code on disk. Restart the interpreter "
                "(in Jupyter: restart the kernel)."
            )
    return fingerprint


def _changed_since_import(files: dict[str, str]) -> list[str]:
    """The files of ``files`` (``{file: SHA-256 of the bytes read}``, this package's) that may
    not be those this process imported: as ``import docking`` found them
    (:data:`docking._SOURCES_AT_IMPORT`), a file hashed then has another digest, any other file
    another stat now (modification or change time, size or inode: its bytes read since are then
    not known to be those loaded), and a file it did not find is new."""
    import docking

    loaded = docking._SOURCES_AT_IMPORT
    changed = []
    for name, digest in sorted(files.items()):
        stat, loaded_digest = loaded.get(name, (None, None))
        if loaded_digest is not None:
            same = loaded_digest == digest
        else:
            try:
                now = os.stat(_OWN / name)
            except OSError:
                now = None
            same = None not in (stat, now) and _same_stat(stat, now)
        if not same:
            changed.append(name)
    return changed


def _same_stat(a: os.stat_result, b: os.stat_result) -> bool:
    """Whether ``a`` and ``b`` are the stat of one version of a file: its modification and
    change times (the change time moves with every write, and cannot be set back), size and
    inode."""
    fields = ("st_mtime_ns", "st_ctime_ns", "st_size", "st_ino")
    return all(getattr(a, f) == getattr(b, f) for f in fields)


def module_digests(
    package_dir: Path | str | None = None,
    root: str = _ROOT_MODULE,
    libraries: tuple[str, ...] = _LIBRARIES,
) -> dict[str, str]:
    """``{module: SHA-256 of its code}`` for every fingerprinted module of ``root``'s
    computation (the code as the fingerprint reads it), plus ``assets/...`` and
    ``library ...`` entries: what a ledger records, so that a mismatch can name what
    changed."""
    package_dir = Path(package_dir).resolve() if package_dir else _OWN
    parts = _fingerprint_parts(package_dir, root, tuple(libraries))
    return dict(parts[1])


#: The ``docking`` package folder this module was loaded from.
_OWN = Path(__file__).resolve().parents[1]


#: ``{(package folder, root, libraries): (stamp, parts)}``: :func:`_fingerprint_parts`'s
#: answers in this process, each with the stamp (:func:`_stamp`) of what it read.
_PARTS: dict[tuple, tuple[tuple, tuple]] = {}

#: A file modified less than this long before its fingerprint was computed (nanoseconds) is
#: not trusted to its stamp: an edit within one tick of the file system's clock keeps the
#: modification time, so such an answer is not cached (it is computed again next time).
_RACY_NS = 2_000_000_000


def _stamp(paths: tuple[Path, ...]) -> tuple:
    """``((path, mtime_ns, size), ...)`` of ``paths`` (``None`` for one that is gone)."""
    stamp = []
    for path in paths:
        try:
            found = os.stat(path)
        except OSError:
            stamp.append((path, None, None))
        else:
            stamp.append((path, found.st_mtime_ns, found.st_size))
    return tuple(stamp)


def _fingerprint_parts(
    package_dir: Path, root: str = _ROOT_MODULE, libraries: tuple = _LIBRARIES
) -> tuple[str, tuple, dict]:
    """(fingerprint, ((part, digest), ...), {file: SHA-256 of its bytes}), cached in this
    process by the stamp (modification time and size) of exactly what it read: every
    fingerprinted file, every file under ``assets/`` and the folders that hold them (a file
    added to or removed from one moves its folder's time). An edited file moves its stamp,
    so the fingerprint is computed again (tests/test_fingerprint_cache.py)."""
    key = (package_dir, root, libraries)
    cached = _PARTS.get(key)
    if cached is not None and _stamp(tuple(p for p, _, _ in cached[0])) == cached[0]:
        return cached[1]
    started = time.time_ns()
    parts = _compute_parts(package_dir, root, libraries)
    files = [package_dir / f for f in parts[2]]
    assets = package_dir / "assets"
    read = [*files, *(assets.rglob("*") if assets.is_dir() else ()), assets]
    read += sorted({p.parent for p in read} - set(read))
    stamp = _stamp(tuple(sorted(read)))
    if all(t is not None and t < started - _RACY_NS for _, t, _ in stamp):
        _PARTS[key] = (stamp, parts)
    else:
        _PARTS.pop(key, None)
    return parts


def _compute_parts(package_dir: Path, root: str, libraries: tuple) -> tuple[str, tuple, dict]:
    code, parts, files = fingerprint.walk(package_dir, root)
    digest = hashlib.sha256(f"code {code}\n".encode())
    assets = package_dir / "assets"
    if assets.is_dir():
        for path in sorted(p for p in assets.rglob("*") if p.is_file()):
            relative = path.relative_to(assets).as_posix()
            data = path.read_bytes()
            digest.update(f"asset {relative}\n".encode())
            digest.update(data)
            parts.append((f"assets/{relative}", hashlib.sha256(data).hexdigest()))
    for library in libraries:
        try:
            version = importlib.metadata.version(library)
        except importlib.metadata.PackageNotFoundError:
            version = "absent"
        digest.update(f"library {library} {version}\n".encode())
        parts.append((f"library {library}", version))
    return digest.hexdigest(), tuple(sorted(parts)), files


def rendering_stack() -> str:
    """The OpenGL stack that renders observations (:func:`docking.render.gl_stack`)."""
    from docking.render import gl_stack

    return gl_stack()


#: ``{id(config): (config, {form: its JSON})}``: :func:`config_json`'s answers for frozen,
#: hashable configurations (held, so that their ids stay theirs), at most :data:`_JSON_LIMIT`.
_JSON: dict[int, tuple[object, dict]] = {}
_JSON_LIMIT = 4096


def _frozen(config) -> bool:
    # A frozen dataclass whose every field hashes (no list or dict inside) cannot change.
    if not dataclasses.is_dataclass(config) or not config.__dataclass_params__.frozen:
        return False
    try:
        hash(config)
    except TypeError:
        return False
    return True


def config_json(config, compact: bool = True) -> str:
    """``config.to_dict()`` as JSON with sorted keys (``compact``: without spaces, the form a
    key hashes; else :func:`json.dumps`'s default separators, the ledger index's), cached
    for the configuration object while it is frozen and hashable (a configuration is
    immutable; one holding a list or dict is converted each time)."""
    entry = _JSON.get(id(config))
    if entry is None or entry[0] is not config:
        entry = (config, {})
        if _frozen(config):
            if len(_JSON) >= _JSON_LIMIT:
                _JSON.clear()
            _JSON[id(config)] = entry
    texts = entry[1]
    if compact not in texts:
        d = config.to_dict()
        texts[compact] = json.dumps(d, sort_keys=True, separators=(",", ":") if compact else None)
    return texts[compact]


def _canonical(config) -> str:
    return config_json(config)


def config_key(config, render: str | None = None, source: str | None = None) -> str:
    """SHA-256 of the canonical configuration, the source fingerprint of its runner's code and
    the rendering stack (the folder key); ``render`` names another stack than this process's
    (for the ledger), ``source`` another fingerprint than this code's (the key a run had
    before a migration, :mod:`docking.study.migrate`)."""
    runner = runner_for(config)
    text = (
        f"{runner.key_prefix}format {runner.format}\nconfig {_canonical(config)}"
        f"\nsource {runner.fingerprint() if source is None else source}"
        f"\nrender {rendering_stack() if render is None else render}"
    )
    return hashlib.sha256(text.encode()).hexdigest()


def run_key(config, seed: int, render: str | None = None, source: str | None = None) -> str:
    """The key of the run of (``config``, ``seed``): the configuration key and the seed."""
    seed = check_int("run_key", "seed", seed, lo=0, hi=MAX_SEED)
    return f"{config_key(config, render, source)}:seed{seed}"


def result_path(
    config, seed: int, results_dir: Path | str | None = None, key: str | None = None
) -> Path:
    """Where the run of (``config``, ``seed``) is stored (see the module docstring); ``key``,
    its :func:`run_key` if the caller has it (else it is computed)."""
    seed = check_int("result_path", "seed", seed, lo=0, hi=MAX_SEED)
    name = check_name(type(config).__name__, "name", config.name)  # a folder of the store
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    if key is None:
        key = run_key(config, seed)
    elif not key.endswith(f":seed{seed}"):
        raise ValueError(f"result_path: the key {key[:16]}... is not of seed {seed}")
    return root / name / key[:16] / f"seed{seed}.npz"


# ------------------------------------------------------------------------------------------
# Saving and loading.
# ------------------------------------------------------------------------------------------


def content_digest(arrays) -> str:
    """SHA-256 of a run's arrays: every array but ``meta``, by name, dtype, shape and bytes.

    ``arrays`` maps names to arrays (a dict, or an open ``.npz``). Two runs with equal digests
    are equal bit for bit in every array; the wall times (in ``meta``) are not covered."""
    digest = hashlib.sha256()
    names = arrays.files if hasattr(arrays, "files") else list(arrays)
    for name in sorted(n for n in names if n != "meta"):
        array = np.ascontiguousarray(arrays[name])
        digest.update(f"{name}\0{array.dtype.str}\0{array.shape}\0".encode())
        digest.update(array.tobytes())
    return digest.hexdigest()


def computed_utc() -> str:
    """Now, in UTC, to the second (ISO 8601): the time a run is stored as computed."""
    import datetime

    return datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")


def save_result(result, path: Path | str) -> Path:
    """Write ``result`` (a run of any :class:`Runner`) to ``path`` (compressed .npz)
    atomically; also ``config.json`` beside it (the configuration, readable). Returns
    ``path``."""
    path = Path(path)
    runner = runner_for(result.config)
    arrays = runner.arrays(result)
    meta = {
        "runner": runner.name,
        "format": runner.format,
        "key": run_key(result.config, result.seed),
        "digest": content_digest(arrays),
        "config": result.config.to_dict(),
        "seed": result.seed,
        "wall_time_train": float(result.wall_time_train),
        "wall_time_test": float(result.wall_time_test),
        # when it was computed (UTC), what a design's provenance test compares with the
        # commit of its rules (outside the content digest, as the wall times are)
        "computed_utc": computed_utc(),
    }
    arrays["meta"] = np.array(json.dumps(meta))
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    try:
        remove_stale_temporaries(path)
        atomic_write(path, lambda f: f.write(buffer.getvalue()))
        config_json = path.parent / "config.json"
        if not config_json.exists():
            text = json.dumps(meta["config"], indent=2, sort_keys=True) + "\n"
            remove_stale_temporaries(config_json)
            atomic_write(config_json, lambda f: f.write(text.encode()))
    except OSError as exc:
        raise OSError(
            exc.errno, f"cannot save the run in {str(path)!r}: {exc.strerror or exc}"
        ) from exc
    return path


#: The largest meta record a result file may hold (bytes, uncompressed).
_META_LIMIT = 1 << 20


#: The largest stored run :func:`load_result` reads (bytes on disk; a run holds a few MiB).
RESULT_LIMIT = 256 << 20


def load_result(
    path: Path | str,
    key: str | None = None,
    within: Path | str | None = None,
    source: str | None = None,
):
    """Read and validate a result written by :func:`save_result`, of any runner (the file's
    meta record names it; a file without one is the learner's) (see the module docstring);
    ``key``, if given, is the run key asked for (:func:`run_key`): a file holding another run
    is refused. The file must be a regular file of at most :data:`RESULT_LIMIT` bytes inside
    the folder ``within`` (default: its own folder), checked before it is read
    (:func:`docking.fileio.read_regular`). ``source``: the fingerprint its key must have been
    made with, if not this code's (a run before its migration). ``CorruptResult`` (naming the
    reason) if the file cannot be used."""
    path = Path(path)
    try:
        stamp = _file_stamp(path)
        raw = read_regular(path, RESULT_LIMIT, path.parent if within is None else within)
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            result = _parse(data, key, source)
    except CorruptResult:
        raise
    except UnsafeFile as exc:
        raise ForeignFile(str(exc)) from None
    except Exception as exc:  # unreadable: truncated, bit flips, not a zip, ...
        raise CorruptResult(f"{type(exc).__name__}: {exc}") from exc
    if source is None:
        _CHECKED.add((*stamp, key if key is not None else run_key(result.config, result.seed)))
    return result


#: ``(path, inode, mtime_ns, size, run key)`` of every file :func:`load_result` has read and
#: found valid in this process: a file unchanged since (an atomic write replaces the inode)
#: is not read again to learn that (:func:`is_valid`).
_CHECKED: set[tuple] = set()


def _file_stamp(path: Path) -> tuple:
    found = path.stat()
    return str(path.resolve()), found.st_ino, found.st_mtime_ns, found.st_size


def is_valid(path: Path | str, key: str) -> bool:
    """Whether ``path`` holds a valid run of ``key`` (:func:`load_result` would return it
    and not raise): read and checked once per process, while the file is unchanged."""
    path = Path(path)
    try:
        if (*_file_stamp(path), key) in _CHECKED:
            return True
        load_result(path, key)
    except (OSError, CorruptResult):
        return False
    return True


def _parse(data, asked: str | None, source: str | None = None):
    if "meta" not in data.files:
        raise CorruptResult("no 'meta' record")
    if member_size(data, "meta") > _META_LIMIT:
        raise CorruptResult(f"the meta record is larger than {_META_LIMIT} bytes")
    try:
        meta = json.loads(str(data["meta"]))
        runner = runner_named(meta.get("runner", LEARNER.name))
        config = runner.from_dict(meta["config"])
        seed = check_int("meta", "seed", meta["seed"], lo=0, hi=MAX_SEED)
        fmt, key, digest = meta["format"], meta["key"], meta["digest"]
        walls = float(meta["wall_time_train"]), float(meta["wall_time_test"])
    except (ValueError, TypeError, KeyError, AttributeError) as exc:
        raise CorruptResult(f"bad meta record: {type(exc).__name__}: {exc}") from exc
    if fmt != runner.format:
        raise CorruptResult(
            f"file format {fmt}, this package reads {runner.format} ({runner.name} runs)"
        )
    if config.to_dict() != meta["config"]:
        raise CorruptResult("the configuration does not round-trip")
    if key != run_key(config, seed, source=source):
        raise CorruptResult("made by other code or another configuration (key mismatch)")
    if asked is not None and key != asked:
        raise CorruptResult(
            f"holds the run {key[:16]}...:seed{seed} of {config.name!r}, not the run asked for "
            f"({asked[:16]}...:{asked.rpartition(':')[2]})"
        )
    result = runner.parse(data, config, seed, walls)
    # Every member has been size-checked and read: the digest covers them all (an extra
    # member changes it too).
    if content_digest(data) != digest:
        raise CorruptResult("the arrays do not match the file's content digest")
    return result


# ------------------------------------------------------------------------------------------
# The kinds of run.
# ------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Runner:
    """One kind of run: what computes it and what its key depends on.

    Attributes:
      name: The kind's name, recorded in every stored file and ledger record.
      config_type: The type of its configurations (:func:`runner_for` looks it up).
      root: The module whose code, with every ``docking`` module it imports, computes its
        runs (its source fingerprint's root).
      libraries: The libraries whose versions enter its keys.
      format: The version of its stored files' layout.
      key_prefix: What its keys' text starts with (keeps the keys of every kind apart).
      run: ``run(config, seed, progress=..., on_trials=...)`` computes a run.
      arrays: ``arrays(result)``: the arrays a stored run holds, by name (not ``meta``).
      parse: ``parse(data, config, seed, (wall_time_train, wall_time_test))``: the run of an
        open stored file whose meta record is checked; :class:`CorruptResult` if its arrays
        are not a run of ``config``.
      from_table: ``from_table(config, seed, row, logs, (wall_time_train,
        wall_time_test))``: the run of a row of a ledger's results table (``row``: its cells
        by column; ``logs``: its trial logs by part, None for a part the row holds none of;
        :func:`docking.study.ledger.read`).
      trials_in_run: ``trials_in_run(config)``: the trials a run reports to ``on_trials``.
      test_elsewhere: Whether a design cell may test its trained runs in another world.
    """

    name: str
    config_type: type
    root: str
    libraries: tuple[str, ...]
    format: int
    key_prefix: str
    run: Callable
    arrays: Callable
    parse: Callable
    from_table: Callable
    trials_in_run: Callable
    test_elsewhere: bool

    def from_dict(self, d: dict):
        """The configuration of the JSON-ready ``d`` (``config_type.from_dict``)."""
        return self.config_type.from_dict(d)

    def fingerprint(self) -> str:
        """The source fingerprint of this kind's runs (:func:`source_fingerprint`)."""
        return source_fingerprint(root=self.root, libraries=self.libraries)

    def module_digests(self, package_dir: Path | str | None = None) -> dict[str, str]:
        """:func:`module_digests` of this kind's computation."""
        return module_digests(package_dir, root=self.root, libraries=self.libraries)


#: The paper's learner and its yardsticks.
LEARNER = Runner(
    name="learner",
    config_type=ExperimentConfig,
    root=_ROOT_MODULE,
    libraries=_LIBRARIES,
    format=FORMAT_VERSION,
    key_prefix="",
    # looked up when called, so that a patched run_experiment is the one run
    run=lambda config, seed, **kwargs: run_experiment(config, seed, **kwargs),
    arrays=result_arrays,
    parse=parse_learner,
    from_table=learner_from_table,
    trials_in_run=trials_in_run,
    test_elsewhere=True,
)

#: Every kind of run, by its configuration's type (:func:`register` adds one; PPO's is added
#: when first asked for, :func:`_ppo_runner`).
RUNNERS: dict[type, Runner] = {LEARNER.config_type: LEARNER}
_BY_NAME: dict[str, Runner] = {LEARNER.name: LEARNER}
#: The module of the pixel-level bound, imported only when a PPO run is asked for: a run of
#: the paper's learner loads no PPO code (issue 43).
_PPO_MODULE = "docking.study.ppo"


def _ppo_runner() -> Runner:
    """The pixel-level bound's kind of run, PPO on the same pixels (made and added to
    :data:`RUNNERS` on first use)."""
    runner = _BY_NAME.get("ppo")
    if runner is not None:
        return runner
    from docking.study import ppo

    runner = Runner(
        name="ppo",
        config_type=ppo.PPOConfig,
        root=ppo.__name__,
        libraries=ppo.LIBRARIES,
        format=ppo.FORMAT_VERSION,
        key_prefix="ppo ",
        run=lambda config, seed, **kwargs: ppo.run_ppo(config, seed, **kwargs),
        arrays=ppo.result_arrays,
        parse=parse_ppo,
        from_table=ppo_from_table,
        trials_in_run=ppo.trials_in_run,
        test_elsewhere=False,
    )
    RUNNERS[runner.config_type], _BY_NAME[runner.name] = runner, runner
    return runner


def built_in() -> tuple[Runner, ...]:
    """The package's own kinds of run: the paper's learner and PPO."""
    return (LEARNER, _ppo_runner())


def __getattr__(name: str):
    """``kinds.PPO`` (the pixel-level bound's :class:`Runner`) and ``kinds.BUILT_IN``, made
    when first asked for (:func:`_ppo_runner`)."""
    if name == "PPO":
        return _ppo_runner()
    if name == "BUILT_IN":
        return built_in()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: Names of the runners adopted from a configuration's class (:func:`runner_for`).
_CARRIED: set[str] = set()
#: The environment variable naming modules to import for their learners (:func:`runner_named`).
LEARNERS_VARIABLE = "DOCKING_LEARNERS"
#: The attribute of a registered learner's configuration class that holds its runner.
RUNNER_ATTRIBUTE = "_docking_runner"


def register(runner: Runner) -> Runner:
    """Add a kind of run (:func:`docking.study.learners.register` makes one for a learner from
    outside the package). It replaces an earlier runner of its name or configuration type (a
    notebook cell run again defines the class anew), never a built-in one (``ValueError``).
    Returns ``runner``."""
    if not isinstance(runner, Runner):
        raise TypeError(f"register takes a Runner, got {runner!r:.80}")
    for own in built_in():
        if runner.name == own.name or runner.config_type is own.config_type:
            raise ValueError(f"{runner.name!r} would replace the built-in kind of run")
    for config_type, old in list(RUNNERS.items()):
        if old.name == runner.name or config_type is runner.config_type:
            del RUNNERS[config_type], _BY_NAME[old.name]
    RUNNERS[runner.config_type], _BY_NAME[runner.name] = runner, runner
    _CARRIED.discard(runner.name)
    return runner


def runner_for(config) -> Runner:
    """The :class:`Runner` of ``config``'s kind (by its exact type); ``TypeError`` naming
    the known configuration types for anything else.

    A registered learner's configuration class carries its runner (:data:`RUNNER_ATTRIBUTE`):
    where the class arrived by value (a Dask worker given a job of a learner defined in a
    notebook), that runner is adopted, unless this process registered one of its name."""
    if type(config).__module__ == _PPO_MODULE:
        _ppo_runner()
    runner = RUNNERS.get(type(config))
    carried = getattr(type(config), RUNNER_ATTRIBUTE, None)
    if runner is None and isinstance(carried, Runner) and carried.config_type is type(config):
        if carried.name not in _BY_NAME or carried.name in _CARRIED:
            runner = register(carried)
            _CARRIED.add(carried.name)
    if runner is None:
        known = " or ".join(r.config_type.__name__ for r in built_in())
        raise TypeError(
            f"a run's configuration must be a {known}, got {config!r:.80} (or the "
            "configuration of a learner registered with docking.study.learners.register)"
        )
    return runner


def runner_named(name: str) -> Runner:
    """The :class:`Runner` called ``name``; ``ValueError`` naming the known ones otherwise.
    A name not registered yet is looked up again after importing the modules that the
    environment variable :data:`LEARNERS_VARIABLE` names (comma-separated; a module that
    registers learners, e.g. for ``python -m docking verify`` of their runs)."""
    if name == "ppo":
        return _ppo_runner()
    runner = _BY_NAME.get(name) if isinstance(name, str) else None
    if runner is None and isinstance(name, str) and _import_learners():
        runner = _BY_NAME.get(name)
    if runner is None:
        built_in()  # the known names include PPO's, made on first use
        raise ValueError(
            f"no kind of run is called {name!r:.40}; known: {', '.join(_BY_NAME)} (a learner "
            f"from outside the package: import its module first, or name it in "
            f"{LEARNERS_VARIABLE})"
        )
    return runner


def _import_learners() -> bool:
    """Import the modules :data:`LEARNERS_VARIABLE` names; whether it names any."""
    import importlib

    names = [n.strip() for n in os.environ.get(LEARNERS_VARIABLE, "").split(",") if n.strip()]
    for name in names:
        importlib.import_module(name)
    return bool(names)
