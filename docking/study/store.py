"""The results store: a folder of runs (``results/``, or ``DOCKING_RESULTS``), each saved in
the file its key names (:func:`docking.study.kinds.result_path`).

Three things happen here, and only here: a stored run is *found* (:func:`find`: the file read
and checked against its key and content digest, :func:`docking.study.kinds.load_result`), a run
is *computed and stored* (:func:`compute`: by its runner, saved atomically, the folder checked
for writability and free space first), and both in one for a user who wants a run without the
ledger (:func:`run_or_load`). Which of the store, the committed ledger
(:mod:`docking.study.ledger`) or a computation gives a run is decided in one place,
:func:`docking.study.runs.locate`; the store never reads the ledger, and the ledger never the
store (both build on :mod:`docking.study.kinds`).

A file that is not a valid run of its key is a warning that names the file and the reason
(:func:`run_or_load`, :func:`docking.study.runs.locate`); the run is then computed again and
replaces it. Temporary files of killed writers are cleaned up before the next write.
"""

from __future__ import annotations

import hashlib
import io
import os
import shutil
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from docking.fileio import UnsafeFile, atomic_write, read_regular, remove_stale_temporaries
from docking.study import kinds, paths
from docking.study.kinds import CorruptResult, ForeignFile, module_digests, source_fingerprint

#: ``source_fingerprint`` and ``module_digests`` (:mod:`docking.study.kinds`): the code the
#: store's keys name, here too, where a reader of the store looks for them.
__all__ = [
    "check_inside",
    "check_writable",
    "compute",
    "derived",
    "code_line",
    "derived_key",
    "find",
    "module_digests",
    "run_or_load",
    "source_fingerprint",
]

#: Free space the results folder must have before a run starts (a stored run is < 2 MiB).
_MIN_FREE = 16 << 20


def check_writable(results_dir: Path | str | None = None) -> Path:
    """Make sure the results folder exists and a file can be written there; ``PermissionError``
    (an ``OSError``) naming the path otherwise. Returns the folder."""
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    try:
        root.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".write-test.", suffix=".tmp", dir=root)
        os.close(fd)
        os.unlink(probe)
        free = shutil.disk_usage(root).free
        if free < _MIN_FREE:
            raise OSError(f"only {free // 2**20} MiB free, a run needs up to {_MIN_FREE >> 20}")
    except OSError as exc:
        raise PermissionError(
            f"the results folder {str(root)!r} is not writable ({type(exc).__name__}: {exc}); "
            "choose another with DOCKING_RESULTS or results_dir="
        ) from exc
    return root


def check_inside(path: Path | str, root: Path | str | None = None) -> Path:
    """``path``, a file of the results store ``root`` (default: the folder three levels up,
    as :func:`docking.study.kinds.result_path` and :func:`derived` name files:
    ``<root>/<name>/<key>/seed<k>.npz``), if the folder that holds it lies inside ``root``
    with every link resolved (``root`` itself may be a link). A folder of the store that is a
    symbolic link leading out of it is :class:`~docking.study.kinds.ForeignFile` naming the
    link, before anything there is read, removed or written."""
    path = Path(path)
    root = path.parents[2] if root is None else Path(root)
    inside = root.resolve()
    if path.parent.resolve().is_relative_to(inside):
        return path
    link = next(
        (f for f in (root / p for p in _prefixes(path.parent.relative_to(root))) if f.is_symlink()),
        path.parent,
    )
    raise ForeignFile(
        f"{link} is a link to {link.resolve()}, outside the results store {inside}: nothing "
        "there is read or written; remove the link, or name that folder as the store "
        "(DOCKING_RESULTS, --results-dir)"
    )


def _prefixes(relative: Path) -> list[Path]:
    """``a``, ``a/b``, ``a/b/c`` of ``a/b/c``."""
    parts = relative.parts
    return [Path(*parts[: k + 1]) for k in range(len(parts))]


def find(config, seed: int, path: Path, key: str):
    """The run of (``config``, ``seed``) stored at ``path`` (its file read and checked against
    ``key`` and its content digest), or None if the store holds no file there.
    :class:`~docking.study.kinds.CorruptResult` naming the reason if the file there is not a
    valid run of ``key``; :class:`~docking.study.kinds.ForeignFile` if it is nothing the store
    writes (refused, never read, never replaced: remove it to compute the run again), or if
    its folder is a link out of the store (:func:`check_inside`)."""
    del config, seed  # named by ``key`` and ``path``; passed so that a call says which run
    check_inside(path)
    remove_stale_temporaries(path)  # of writers killed during an earlier save
    if not path.exists():
        return None
    try:
        return kinds.load_result(path, key)
    except ForeignFile as exc:
        raise ForeignFile(f"{exc}; remove it to compute the run again") from None


def compute(
    config, seed: int, path: Path, progress: bool = True, on_trials=None, again: bool = False
):
    """Compute the run of (``config``, ``seed``) with its runner and store it at ``path``
    (replacing whatever is there); the run. ``on_trials(n)``: called as its trials finish.

    Unless ``again``, a valid file of this very run already at ``path`` is read instead: an
    earlier attempt of the same job stored it (a sweep's job that Dask runs again after its
    worker was lost once the run was stored, or another sweep's), and a stored run is never
    computed twice."""
    check_inside(path)  # never written through a link out of the store
    if not again and path.exists():
        try:
            return kinds.load_result(path, kinds.run_key(config, seed))
        except CorruptResult:
            pass  # not this run: computed and replaced below (ForeignFile is raised)
    check_writable(path.parent)
    result = kinds.runner_for(config).run(config, seed, progress=progress, on_trials=on_trials)
    kinds.save_result(result, path)
    return result


def run_or_load(
    config,
    seed: int,
    results_dir: Path | str | None = None,
    force: bool = False,
    progress: bool = True,
    on_trials=None,
):
    """The run of (``config``, ``seed``), of any runner, from the store alone: loaded if a
    valid file with its key is there, otherwise computed by its runner and saved (a bad file is
    a warning, then replaced). ``on_trials(n)``: called as the computed run's trials finish
    (its progress). ``force`` recomputes and replaces whatever is stored. The ledger is not
    consulted: :func:`docking.study.runs.locate` asks the store, then the ledger."""
    path = kinds.result_path(config, seed, results_dir)
    if not force:
        try:
            found = find(config, seed, path, kinds.run_key(config, seed))
        except ForeignFile:
            raise
        except CorruptResult as exc:
            warnings.warn(
                f"ignoring the stored result {path}: {exc}; recomputing it",
                RuntimeWarning,
                stacklevel=2,
            )
        else:
            if found is not None:
                return found
    return compute(config, seed, path, progress=progress, on_trials=on_trials, again=True)


def derived_key(key: str, code: tuple = ()) -> str:
    """The whole key of :func:`derived` arrays: ``key`` and, per item of ``code``, a line
    ``code <name> <SHA-256>`` (:func:`code_line`)."""
    for item in code:
        key += "\n" + code_line(item)
    return key


def code_line(item) -> str:
    """``code <name> <SHA-256>`` of ``item``: a module by its file (any edit of it changes the
    line), a function by its source (``inspect.getsource``: an edit elsewhere in its module
    does not)."""
    import inspect

    if inspect.ismodule(item):
        source = Path(item.__file__).read_bytes()
        return f"code {item.__name__} {hashlib.sha256(source).hexdigest()}"
    source = inspect.getsource(item).encode()
    return f"code {item.__module__}.{item.__qualname__} {hashlib.sha256(source).hexdigest()}"


#: Bytes a file of :func:`derived` arrays may hold.
_DERIVED_LIMIT = 64 << 20


def derived(
    name: str,
    key: str,
    compute: Callable[[], dict[str, np.ndarray]],
    results_dir: Path | str | None = None,
    code: tuple = (),
    elsewhere: Callable[[str], dict[str, np.ndarray] | None] | None = None,
) -> dict[str, np.ndarray]:
    """Arrays computed from runs (e.g. rendered start views read by a run's network), kept
    in the results store beside the runs, keyed as runs are: ``key`` is the text of
    everything they depend on, which names the run keys (:func:`docking.study.kinds.run_key`:
    configuration, the code's fingerprint, the rendering stack, seed) and the computation's
    own arguments; ``code``, the modules or functions that compute them outside the runs'
    fingerprinted code (e.g. :mod:`docking.study.analysis`), enter it by the SHA-256 of their
    files or sources (:func:`code_line`), so an edit of theirs computes the arrays again. The
    file
    ``<results>/derived/<name>/<SHA-256 of key>.npz`` holds the key too; it is used only if
    that is this key (else, or if it is unreadable, the arrays are computed and replace it).
    A store that cannot be written is not an error: the arrays are returned, not kept.
    ``elsewhere(key)``: asked (with the whole key, the code's lines in it) when the store holds
    no file of this key, before computing: its arrays, if it returns any, are returned (the
    committed ledger's, :mod:`docking.study.derived`; the store never reads the ledger)."""
    key = derived_key(key, code)
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    path = root / "derived" / name / f"{hashlib.sha256(key.encode()).hexdigest()[:32]}.npz"
    check_inside(path, root)
    try:
        raw = read_regular(path, _DERIVED_LIMIT, path.parent)
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            if str(data["key"]) == key:
                return {k: data[k] for k in data.files if k != "key"}
    except (OSError, UnsafeFile, ValueError, KeyError):
        pass  # none, unreadable or another key's: computed below
    found = elsewhere(key) if elsewhere is not None else None
    if found is not None:
        return found
    arrays = compute()
    if "key" in arrays:
        raise ValueError("derived: 'key' is the name the file keeps its key under")
    buffer = io.BytesIO()
    np.savez(buffer, key=np.array(key), **arrays)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, lambda f: f.write(buffer.getvalue()))
    except OSError:
        pass
    return arrays


def derived_entries(name: str, results_dir: Path | str | None = None) -> dict[str, dict]:
    """``{whole key: arrays}`` of every readable :func:`derived` file of ``name`` in the
    results store (one that cannot be read, or whose name is not its key's, is left out)."""
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    found = {}
    check_inside(root / "derived" / name / "-", root)
    for path in sorted((root / "derived" / name).glob("*.npz")):
        try:
            raw = read_regular(path, _DERIVED_LIMIT, path.parent)
            with np.load(io.BytesIO(raw), allow_pickle=False) as data:
                arrays = {k: data[k] for k in data.files}
        except (OSError, UnsafeFile, ValueError):
            continue
        key = str(arrays.pop("key", ""))
        if path.stem == hashlib.sha256(key.encode()).hexdigest()[:32]:
            found[key] = arrays
    return found
