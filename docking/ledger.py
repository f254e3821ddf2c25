"""The results ledger: the committed evidence of the notebooks, a results table per design.

Every run is computed once (``make reproduce``) into the results store (:mod:`docking.store`,
not committed). The ledger, the checkout's ``ledger/`` folder, is what of them is committed,
in formats any numpy opens (``np.load``; zip archives of ``.npy`` arrays, LZMA-compressed):

* ``tables/<name>.npz``: the results table of the runs stored under ``name`` (a
  configuration's name, e.g. ``experiment3``): per trial of each part (``train``, ``test``,
  ``heldout``) its ``success``, ``steps`` and ``start_far``; the learning curves; each run's
  other per-run arrays. A column ``A`` is every run's ``A`` end to end, ``A.count`` says how
  many rows each run has (-1: the run has no ``A``), ``key`` names the runs in order. What
  a design's ``Design.keep`` asks for besides: the path of every failed test or held-out
  trial (``"paths"``: ``<part>.path.run``, ``.trial``, ``.steps``, ``.poses``,
  ``.actions``, what the failure taxonomy reads), every trial's start pose (``"starts"``),
  each run's ``W`` and ``Q`` (``"networks"``), the test and held-out steps' winning units
  (``"winners"``), each test and held-out trial's final pose (``"ends"``) and the distance
  walked (``"lengths"``).
* ``whole/<name>/<key[:16]>/seed<k>.npz``: the few runs kept whole (``Design.whole``: those
  whose weights or trajectories a figure draws), the stored file itself.
* ``manifest.json``: per kind of run (:class:`docking.store.Runner`) the source fingerprint
  of the code that computed its runs and the digests of its modules; per run its key,
  runner, name, seed, content digest (:func:`docking.store.content_digest`, what ``python
  -m docking verify`` recomputes) and wall time; the SHA-256 of every file.

A run read from a table is the run with what the table does not keep (its network, its
per-step arrays) replaced by :class:`NotKept`, which raises :class:`NotInLedger` on any use:
an analysis never gets a substitute. A ledger computed by other code (another fingerprint)
raises :class:`StaleLedger` naming the changed modules. ``DOCKING_LEDGER=off`` turns the
ledger off (every run is computed); ``DOCKING_LEDGER=/path`` reads another one.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import io
import json
import os
import warnings
import zipfile
from pathlib import Path

import numpy as np

from docking import paths, ppo, store
from docking.experiments import ExperimentResult, TrialLog
from docking.fileio import atomic_write
from docking.network import Network

__all__ = [
    "CorruptLedger",
    "NotInLedger",
    "NotKept",
    "StaleLedger",
    "final_poses",
    "holds",
    "path_lengths",
    "load_run",
]

#: Version of the ledger's layout.
LEDGER_FORMAT = 6
PARTS = ("train", "test", "heldout")
#: A trial log's per-step arrays and a run's weights: kept in whole runs, and in a table
#: only as a design's ``keep`` asks.
STEP_FIELDS = ("poses", "actions", "winners", "deltas")
NETWORK = ("W", "Q")
#: A design's ``keep`` with this: its table leaves out each training trial's outcome (a
#: design none of whose analyses reads them; its learning curves are per-run arrays, kept).
NO_TRAIN = "no-train"
_RECOMPUTE = "make reproduce (recomputes the runs, then python -m docking ledger update)"
_RESTORE = "check out the committed ledger again (git checkout -- ledger)"
#: The values of ``DOCKING_LEDGER`` that turn the ledger off (in any case).
LEDGER_OFF = ("off", "0", "none", "false")
#: The tiers' measured times (written by tools/time_tiers.py from a fresh clone).
TIMINGS_FILE = "timings.json"


class StaleLedger(RuntimeError):
    """The ledger was computed by other code (or its files do not match the manifest)."""


class NotInLedger(LookupError):
    """An analysis read what the ledger's table does not keep of a run."""


class CorruptLedger(StaleLedger):
    """A ledger file is damaged or not a ledger file."""


class NotKept:
    """What a results table does not keep of a run (its network, a per-step array): every
    use raises :class:`NotInLedger` naming it and what to do."""

    def __init__(self, what: str):
        self._what = what

    def _refuse(self, *_args, **_kwargs):
        raise NotInLedger(
            f"the ledger keeps only the results table of {self._what.split(': ')[0]}, not "
            f"{self._what.split(': ')[-1]}: an analysis that reads it needs the whole run "
            "(name it in its design's `whole`, then python -m docking ledger update), or "
            "compute it (DOCKING_LEDGER=off)"
        )

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        self._refuse()

    __array__ = __len__ = __getitem__ = __iter__ = __bool__ = __float__ = __int__ = _refuse
    __eq__ = __ne__ = __lt__ = __le__ = __gt__ = __ge__ = __add__ = __sub__ = __mul__ = _refuse
    __truediv__ = __matmul__ = __neg__ = __abs__ = _refuse
    __hash__ = None

    def __repr__(self) -> str:
        return f"NotKept({self._what!r})"


@dataclasses.dataclass
class TableLog(TrialLog):
    """A trial log from a results table: per-trial arrays, the per-step ones
    :class:`NotKept`, and the paths (poses, actions) of the trials in ``paths``."""

    paths: dict = dataclasses.field(default_factory=dict)
    start_poses: np.ndarray | None = None
    end_poses: np.ndarray | None = None
    lengths: np.ndarray | None = None
    what: str = "a run"

    @property
    def starts(self) -> np.ndarray:
        if self.start_poses is None:
            NotKept(f"{self.what}: the trials' start poses")._refuse()
        return self.start_poses

    @property
    def ends(self) -> np.ndarray:
        if self.end_poses is None:
            NotKept(f"{self.what}: the trials' final poses")._refuse()
        return self.end_poses

    def trial_poses(self, k: int) -> np.ndarray:
        return self._path(k)[0]

    def trial_actions(self, k: int) -> np.ndarray:
        return self._path(k)[1]

    def _path(self, k: int):
        if int(k) not in self.paths:
            NotKept(f"{self.what}: the path of trial {k}")._refuse()
        return self.paths[int(k)]


def ledger_off() -> bool:
    """Whether ``DOCKING_LEDGER`` turns the ledger off."""
    value = os.environ.get("DOCKING_LEDGER")
    return value is not None and value.strip().lower() in LEDGER_OFF


def ledger_dir() -> Path | None:
    """The ledger's folder: ``DOCKING_LEDGER`` if set (``off``: none; else the absolute path
    of an existing folder, any other value a ``ValueError`` naming it), else the checkout's
    ``ledger/`` (None for an installed package without one)."""
    value = os.environ.get("DOCKING_LEDGER")
    if value is None:
        root = paths.checkout_root()
        return root / "ledger" if root is not None else None
    if ledger_off():
        return None
    usage = "set it to off or to the absolute path of a ledger folder, or unset it"
    path = Path(value).expanduser()
    if not value.strip():
        raise ValueError(f"DOCKING_LEDGER is set but empty; {usage}")
    if not path.is_absolute():
        raise ValueError(f"DOCKING_LEDGER={value!r} is neither off nor an absolute path; {usage}")
    if not path.is_dir():
        raise ValueError(f"DOCKING_LEDGER={value!r} names no folder; {usage}")
    return path


def manifest(folder: Path | None = None) -> dict | None:
    """The ledger's manifest (None if there is none), checked against this code
    (:class:`StaleLedger` if computed by other code)."""
    data = _stored_manifest(ledger_dir() if folder is None else Path(folder))
    if data is None:
        return None
    for name in sorted(data["fingerprints"]):
        _check(data, store.runner_named(name))
    return data


def _stored_manifest(folder: Path | None) -> dict | None:
    """The manifest in ``folder`` as read (cached until the file changes), unchecked against
    this code; None if there is none."""
    if folder is None or not (folder / "manifest.json").is_file():
        return None
    path = (folder / "manifest.json").resolve()
    return _read_manifest(path, path.stat().st_mtime_ns)


@functools.lru_cache(maxsize=4)
def _read_manifest(path: Path, _mtime: int) -> dict:
    try:
        data = json.loads(path.read_text())
        if data["format"] != LEDGER_FORMAT or data["store_format"] != store.FORMAT_VERSION:
            raise StaleLedger(
                f"the ledger in {path.parent} has format {data['format']}/"
                f"{data['store_format']}, this package reads {LEDGER_FORMAT}/"
                f"{store.FORMAT_VERSION}; recompute it: {_RECOMPUTE}"
            )
        for key, record in data["runs"].items():
            record["config"] = data["configs"][record["config"]]
            seed, walls = record["seed"], [record[f"wall_time_{p}"] for p in ("train", "test")]
            assert isinstance(seed, int) and seed >= 0, f"run {key[:16]}: seed {seed!r}"
            assert record["runner"] in data["fingerprints"], f"run {key[:16]}: its runner"
            assert all(np.isfinite(w) and w >= 0 for w in walls), f"run {key[:16]}: {walls}"
            own = f"whole/{record['name']}/{key[:16]}/seed{seed}.npz"
            assert record.get("whole") in (None, own), f"run {key[:16]}: not its own file"
        data["index"] = {_index(r["config"], r["seed"]): k for k, r in data["runs"].items()}
    except (ValueError, KeyError, TypeError, AttributeError, AssertionError) as exc:
        raise CorruptLedger(f"{path} is not a ledger manifest ({exc!r}); {_RESTORE}") from None
    data["folder"] = path.parent
    return data


def _index(config: dict, seed: int) -> str:
    return f"{json.dumps(config, sort_keys=True)}:seed{seed}"


def _check(data: dict, runner: store.Runner) -> None:
    """:class:`StaleLedger` unless ``runner``'s runs were computed by this code; a warning
    (once) if by another rendering stack."""
    if data["fingerprints"].get(runner.name) != runner.fingerprint():
        ours, theirs = runner.module_digests(), data["modules"].get(runner.name, {})
        changed = sorted(k for k in set(ours) | set(theirs) if ours.get(k) != theirs.get(k))
        raise StaleLedger(
            f"the ledger in {data['folder']} holds {runner.name} runs computed by other code "
            f"(changed: {', '.join(changed) or 'the fingerprint'}); they are not used. "
            f"Recompute them: {_RECOMPUTE}"
        )
    if data["rendering_stack"] != store.rendering_stack() and not data.get("warned"):
        data["warned"] = True
        warnings.warn(
            f"the ledger's runs were rendered by {data['rendering_stack']!r}, this machine by "
            f"{store.rendering_stack()!r}; `python -m docking verify` shows whether they agree",
            RuntimeWarning,
            stacklevel=3,
        )


def timings(folder: Path | None = None) -> dict | None:
    """The record of ``tools/time_tiers.py`` in the ledger's folder (None if there is none)."""
    folder = ledger_dir() if folder is None else Path(folder)
    found = folder is not None and (folder / TIMINGS_FILE).is_file()
    return json.loads((folder / TIMINGS_FILE).read_text()) if found else None


def size_bytes(folder: Path | None = None) -> int:
    """The bytes of every file of the ledger in ``folder`` (default :func:`ledger_dir`)."""
    folder = ledger_dir() if folder is None else Path(folder)
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


def computing_seconds(data: dict) -> tuple[int, float]:
    """The number of runs in a manifest and the sum of their wall times (seconds)."""
    return len(data["runs"]), float(sum(r["wall_seconds"] for r in data["runs"].values()))


def _find(config, seed: int) -> tuple[dict, str] | None:
    store.runner_for(config)  # TypeError for what is no run's configuration
    data = _stored_manifest(ledger_dir())
    if data is None:
        return None
    key = data["index"].get(_index(config.to_dict(), seed))
    return None if key is None else (data, key)


def holds(config, seed: int, check: bool = False) -> bool:
    """Whether the ledger holds the run of (``config``, ``seed``); with ``check``,
    :class:`StaleLedger` if it does but its runner's code is not this code."""
    found = _find(config, seed)
    if found is not None and check:
        _check(found[0], store.runner_for(config))
    return found is not None


def _verified(path: Path, sha256: str) -> bytes:
    """The bytes of the ledger file ``path``, checked against its manifest digest."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise CorruptLedger(f"the ledger file {path} cannot be read ({exc}); {_RESTORE}") from None
    if hashlib.sha256(raw).hexdigest() != sha256:
        raise CorruptLedger(f"the ledger file {path} does not match its digest; {_RESTORE}")
    return raw


@functools.lru_cache(maxsize=8)
def _table(path: Path, sha256: str) -> dict[str, np.ndarray]:
    """The columns of the results table ``path`` (checked against ``sha256``)."""
    try:
        with np.load(io.BytesIO(_verified(path, sha256)), allow_pickle=False) as found:
            return {k: found[k] for k in found.files}
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise CorruptLedger(
            f"the ledger table {path} is not readable ({exc}); {_RESTORE}"
        ) from None


def load_run(config, seed: int, results_dir: Path | str | None = None):
    """The run of (``config``, ``seed``): from the results store if it holds it (checked
    against its key and digest), else from the ledger (whole, or from its results table),
    else None. :class:`StaleLedger` if the ledger holds it but was computed by other code."""
    path = store.result_path(config, seed, results_dir)
    if path.exists():
        return store.load_result(path, store.run_key(config, seed))
    found = _find(config, seed)
    if found is None:
        return None
    data, key = found
    runner = store.runner_for(config)
    _check(data, runner)
    record = data["runs"][key]
    if key != store.run_key(config, seed, render=data["rendering_stack"]):
        raise StaleLedger(f"the ledger's key of {config.name!r} seed {seed} is not this code's")
    if record.get("whole"):
        _verified(data["folder"] / record["whole"], record["sha256"])
        try:
            return store.load_result(data["folder"] / record["whole"], key)
        except store.CorruptResult as exc:
            raise CorruptLedger(f"the ledger file {record['whole']}: {exc}; {_RESTORE}") from None
    table = _table(data["folder"] / f"tables/{config.name}.npz", data["tables"][config.name])
    rows = list(table["key"]).index(key)
    what = f"run {config.name!r} seed {seed}"
    arrays = _rows(table, rows)
    logs = {p: _log(table, arrays, rows, p, what) for p in PARTS if f"{p}.start_far" in arrays}
    walls = record["wall_time_train"], record["wall_time_test"]
    if runner is store.PPO:
        train = [
            arrays[f"train.{f}"] if f"train.{f}" in arrays else NotKept(f"{what}: its training")
            for f in ("success", "steps")
        ]
        return ppo.PPOResult(config, seed, *train, logs["heldout"], *walls)
    curves = {k: arrays[k] for k in ("curve_trials", "curve_success", "curve_steps")}
    return ExperimentResult(
        config=config,
        seed=seed,
        network=(
            Network.from_weights(
                config.network,
                arrays["W"].reshape(config.network.n_features, -1),
                arrays["Q"].reshape(config.network.n_actions, -1),
            )
            if "W" in arrays
            else NotKept(f"{what}: its network")
        ),
        train=logs["train"] if "train" in logs else NotKept(f"{what}: its training trials"),
        test=logs["test"],
        **curves,
        curve_rewarded=arrays["curve_rewarded"],
        wall_time_train=walls[0],
        wall_time_test=walls[1],
        heldout=logs.get("heldout"),
    )


def _rows(table: dict, run: int) -> dict[str, np.ndarray]:
    """Run number ``run``'s arrays in ``table`` (those it has)."""
    out = {}
    for name in (n for n in table if n + ".count" in table):
        counts = table[name + ".count"]
        if counts[run] >= 0:
            start = int(np.sum(np.maximum(counts[:run], 0)))
            out[name] = table[name][start : start + counts[run]]
    return out


def _log(table: dict, arrays: dict, run: int, part: str, what: str) -> TableLog:
    """Run number ``run``'s log of ``part`` from the table (its ``arrays``), with the paths
    the table keeps of its trials."""
    kept = {}
    if f"{part}.path.run" in table:
        runs, trials, steps = (table[f"{part}.path.{c}"] for c in ("run", "trial", "steps"))
        pose_at = np.concatenate([[0], np.cumsum(steps + 1)])
        action_at = np.concatenate([[0], np.cumsum(steps)])
        for i in np.flatnonzero(runs == run):
            kept[int(trials[i])] = (
                table[f"{part}.path.poses"][pose_at[i] : pose_at[i + 1]],
                table[f"{part}.path.actions"][action_at[i] : action_at[i + 1]],
            )
    absent = {f: NotKept(f"{what}: the {part} trials' {f}") for f in STEP_FIELDS}
    if f"{part}.winners" in arrays:
        absent["winners"] = arrays[f"{part}.winners"]
    per_trial = {f: arrays[f"{part}.{f}"] for f in ("success", "steps", "start_far")}
    starts, ends = arrays.get(f"{part}.starts"), arrays.get(f"{part}.ends")
    return TableLog(
        **per_trial,
        **absent,
        paths=kept,
        start_poses=starts,
        end_poses=ends,
        lengths=arrays.get(f"{part}.lengths"),
        what=what,
    )


# ------------------------------------------------------------------------------------------
# Writing.
# ------------------------------------------------------------------------------------------


def _npz(arrays: dict[str, np.ndarray]) -> bytes:
    """``arrays`` as an ``.npz`` (LZMA-compressed members, fixed timestamps: the same arrays
    give the same bytes)."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_LZMA) as archive:
        for name, array in arrays.items():
            info = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_LZMA
            with archive.open(info, "w") as f:
                np.lib.format.write_array(f, np.asanyarray(array), allow_pickle=False)
    return buffer.getvalue()


def _row(arrays: dict, keep: frozenset) -> dict[str, np.ndarray]:
    """What a table keeps of a run's stored ``arrays``: every per-trial and per-run array;
    with ``"starts"`` each trial's start pose, ``"networks"`` W and Q (flat; read back in
    the configuration's shapes), ``"winners"`` the test
    and held-out steps' winning units; with :data:`NO_TRAIN` no training trial; never
    ``meta`` or another per-step array."""
    row = {}
    for name, array in arrays.items():
        field = name.rpartition(".")[2]
        if name == "meta" or (name in NETWORK and "networks" not in keep):
            continue
        if name.startswith("train.") and NO_TRAIN in keep:
            continue
        if field in STEP_FIELDS and not (field == "winners" and "winners" in keep):
            continue
        if field == "winners" and name.startswith("train."):
            continue
        # W and Q flat: a design's networks differ in shape (Experiment 1 has 4 units)
        row[name] = np.ravel(array) if name in NETWORK else np.atleast_1d(array)
    for part in PARTS:
        if part == "train" and NO_TRAIN in keep:
            continue
        if "starts" in keep and f"{part}.poses" in arrays:
            row[f"{part}.starts"] = _stored_log(arrays, part).starts
        if "ends" in keep and part != "train" and f"{part}.poses" in arrays:
            row[f"{part}.ends"] = final_poses(_stored_log(arrays, part))
        if "lengths" in keep and part != "train" and f"{part}.poses" in arrays:
            row[f"{part}.lengths"] = path_lengths(_stored_log(arrays, part))
    return row


def final_poses(log: TrialLog) -> np.ndarray:
    """The final pose of every trial of ``log``, ``(n, 3)`` (a table's kept ones, else read
    from its poses)."""
    if isinstance(log, TableLog):
        return log.ends
    return log.poses[np.cumsum(log.steps + 1) - 1] if len(log) else np.zeros((0, 3))


def path_lengths(log: TrialLog) -> np.ndarray:
    """The distance the reference point walked in each trial of ``log`` (m; the sum of its
    steps' displacements): a table's kept ones, else read from its poses."""
    if isinstance(log, TableLog):
        if log.lengths is None:
            NotKept(f"{log.what}: the trials' path lengths")._refuse()
        return log.lengths
    steps = np.linalg.norm(np.diff(log.poses[:, :2], axis=0), axis=1)
    ends = np.cumsum(log.steps + 1)
    walked = np.concatenate([[0.0], np.cumsum(steps)])
    return walked[ends - 1] - walked[ends - 1 - log.steps]


def _stored_log(arrays: dict, part: str) -> TrialLog:
    """The trial log of ``part`` in a stored run's ``arrays`` (its own slicing of trials)."""
    return TrialLog(**{f.name: arrays[f"{part}.{f.name}"] for f in dataclasses.fields(TrialLog)})


def _columns(runs: list[tuple[str, dict, frozenset]]) -> dict[str, np.ndarray]:
    """The results table of ``runs`` (``(key, stored arrays, what to keep)`` each)."""
    table = {"key": np.array([key for key, _, _ in runs])}
    rows = [_row(arrays, keep) for _, arrays, keep in runs]
    for name in sorted({n for row in rows for n in row}):
        found = [row.get(name) for row in rows]
        table[name] = np.concatenate([a for a in found if a is not None])
        table[name + ".count"] = np.array([-1 if a is None else len(a) for a in found])
    for part in ("test", "heldout"):
        kept = {c: [] for c in ("run", "trial", "steps", "poses", "actions")}
        for i, (_, arrays, keep) in enumerate(runs):
            if "paths" not in keep or f"{part}.success" not in arrays:
                continue
            log = _stored_log(arrays, part)
            for k in np.flatnonzero(~log.success):
                kept["run"].append(i)
                kept["trial"].append(k)
                kept["steps"].append(log.steps[k])
                kept["poses"].append(log.trial_poses(k))
                kept["actions"].append(log.trial_actions(k))
        if kept["run"]:
            table.update({f"{part}.path.{c}": np.array(kept[c]) for c in ("run", "trial", "steps")})
            table[f"{part}.path.poses"] = np.concatenate(kept["poses"])
            table[f"{part}.path.actions"] = np.concatenate(kept["actions"])
    return table


def update(runs, folder: Path | str | None = None, results_dir=None) -> dict:
    """Write the ledger of ``runs`` (``(config, seed, whole, keep)`` each) from the results
    store, replacing the ledger's files; returns the manifest. ``whole``: keep the run's
    stored file; ``keep``: what its table keeps (:attr:`docking.design.Design.keep`)."""
    from docking.platform_info import numeric_platform

    folder = Path(folder) if folder is not None else ledger_dir()
    if folder is None:
        raise ValueError("no ledger folder: DOCKING_LEDGER is off and no folder was given")
    records, files, tables, runners = {}, {}, {}, {}
    for config, seed, whole, keep in runs:
        key = store.run_key(config, seed)
        path = store.result_path(config, seed, results_dir)
        result = store.load_result(path, key)  # checks the file against the key and digest
        runner = runners.setdefault(store.runner_for(config).name, store.runner_for(config))
        with np.load(path, allow_pickle=False) as stored:
            arrays = {k: stored[k] for k in stored.files}
        record = {
            "runner": runner.name,
            "name": config.name,
            "seed": seed,
            "config": config.to_dict(),
            "digest": store.content_digest(arrays),
            "wall_time_train": float(result.wall_time_train),
            "wall_time_test": float(result.wall_time_test),
            "wall_seconds": round(result.wall_time_train + result.wall_time_test, 1),
        }
        if whole:
            record["whole"] = f"whole/{config.name}/{key[:16]}/seed{seed}.npz"
            files[record["whole"]] = _npz(arrays)
            record["sha256"] = hashlib.sha256(files[record["whole"]]).hexdigest()
        records[key] = record
        tables.setdefault(config.name, []).append((key, arrays, frozenset(keep)))
    for name, found in tables.items():
        files[f"tables/{name}.npz"] = _npz(_columns(sorted(found, key=lambda r: r[0])))
    configs = {}
    for record in records.values():
        text = json.dumps(record["config"], sort_keys=True)
        ref = hashlib.sha256(text.encode()).hexdigest()[:16]
        configs[ref], record["config"] = record["config"], ref
    data = {
        "format": LEDGER_FORMAT,
        "store_format": store.FORMAT_VERSION,
        "fingerprints": {name: r.fingerprint() for name, r in runners.items()},
        "modules": {name: r.module_digests() for name, r in runners.items()},
        "rendering_stack": store.rendering_stack(),
        "platform": numeric_platform(),
        "configs": configs,
        "tables": {n: hashlib.sha256(files[f"tables/{n}.npz"]).hexdigest() for n in tables},
        "runs": records,
    }
    _replace_files(folder, files)
    text = json.dumps(data, indent=1, sort_keys=True) + "\n"
    atomic_write(folder / "manifest.json", lambda f: f.write(text.encode()))
    _read_manifest.cache_clear()
    return manifest(folder)


def _replace_files(folder: Path, files: dict[str, bytes]) -> None:
    """Write ``files`` (``{path relative to folder: bytes}``) into the ledger ``folder``, each
    atomically and only if it changed, and delete the tables and whole runs it no longer
    holds (and empty folders)."""
    kinds = ("runs", "ppo", "tables", "whole")  # (runs/, ppo/: earlier formats' entries)
    old = {p for kind in kinds for p in [folder / kind, *folder.glob(f"{kind}/**/*")]}
    for relative, raw in files.items():
        old.discard(folder / relative)
        if not (folder / relative).exists() or (folder / relative).read_bytes() != raw:
            atomic_write(folder / relative, lambda f, raw=raw: f.write(raw))
    for stale in (p for p in old if p.is_file()):
        stale.unlink()
    for empty in sorted((p for p in old if p.is_dir()), reverse=True):
        if not any(empty.iterdir()):
            empty.rmdir()
