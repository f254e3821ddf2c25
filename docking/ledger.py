"""The results ledger: the evidence of the notebooks, committed, verifiable, refused when stale.

Every run that a notebook, figure or README table uses is computed once (``make reproduce``)
and stored in the results store (:mod:`docking.store`, not committed). The ledger, in the
checkout's ``ledger/`` folder, is what of those runs is committed:

* ``ledger/manifest.json``: per kind of run (:class:`docking.store.Runner`: the learner's,
  PPO's) the source fingerprint of the code that computed its runs and the digest of every
  module of that code (so that a stale ledger can name what changed), the rendering stack,
  and one table of runs: per run its key (:func:`docking.store.run_key`), its runner, its
  name and seed,
  the SHA-256 *content digest* of the stored run's arrays (:func:`docking.store.content_digest`,
  the value ``python -m docking verify`` recomputes and compares) and the digest of its entry
  file.
* ``ledger/runs/<name>/<config key[:16]>/seed<k>.xz``: one *entry* per run, the parts of the
  run the analyses read and nothing else (of a PPO run: its training episodes and the
  per-trial arrays of its held-out trials); of a learner's run: per trial log its success of
  every trial, and the other per-trial arrays (steps, the far edge in force) if an analysis
  reads them; the learning curve, the wall times; the weights ``W`` and ``Q`` only for the
  runs whose network an analysis reads; per-step arrays (poses, actions, winning units, TD
  errors) only for the trials an analysis reads (for instance the failed held-out trials that
  the failure taxonomy classifies), or whole where an analysis reads them whole. Kept arrays
  keep their dtype and every bit, so an analysis computes from an entry exactly what it
  computes from the stored run. An entry is an xz stream of a small JSON index and the
  arrays' data bytes, each *shuffled* (byte 0 of every element, then byte 1, ...;
  :func:`_encode_entry`), which compresses this ledger's arrays about 15% smaller than
  ``np.savez_compressed`` does, and without a zip's and ``.npy``'s headers per array;
  lossless. ``W`` is kept as the bitwise XOR of its float64 bits with those of the run's
  random start
  (:func:`docking.experiments.initial_network` of its configuration and seed), which the
  reader recomputes: a frozen W (eps_W = 0) is all zero bits, a learned W shares its sign,
  exponent and leading mantissa bits with its start; lossless too.

What the analyses read is not written down by hand: ``make reproduce`` executes the
notebooks and the README report with ``DOCKING_TRACE`` naming a file, and every stored run
they load records there what is read of it (:class:`TracedResult`);
``python -m docking ledger update`` keeps exactly that. An entry that lacks something an
analysis reads raises :class:`NotInLedger`, naming the run, the array and the command that
recomputes; it never serves a substitute.

Loading (:func:`lookup`, used by :func:`load_run` when the store lacks a run) refuses a run
made by other code: if the source fingerprint of its runner is not this code's, every access
raises :class:`StaleLedger` naming the changed modules of that runner. A ledger rendered by
another OpenGL stack is served with a warning naming both stacks (``verify`` then shows
whether the runs still agree on this machine). ``DOCKING_LEDGER=off`` turns the ledger off
(every run is computed); ``DOCKING_LEDGER=/path`` reads another one.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
import warnings
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from docking import paths, ppo, store
from docking.experiments import ExperimentConfig, ExperimentResult, TrialLog, initial_network
from docking.fileio import atomic_write
from docking.network import Network
from docking.ppo import PPOConfig
from docking.store import Runner, runner_for, runner_named

__all__ = [
    "LEDGER_FORMAT",
    "CorruptLedger",
    "NotInLedger",
    "StaleLedger",
    "TracedResult",
    "holds",
    "ledger_dir",
    "lookup",
    "manifest",
    "trace",
    "update",
]

#: Version of the ledger's layout.
LEDGER_FORMAT = 5
# 5: one table of runs, each naming its runner, a fingerprint and module digests per runner,
# every entry under runs/; 4: W as its XOR with the run's random start, empty per-step arrays
# and the configuration left out of entries, a JSON index instead of a zip; 3: xz entries of
# byte-shuffled arrays, per-trial fields kept only if read
# (2: per-step fields kept per trial only if read so, "sliced"; PPO runs)

#: Per-step arrays of a trial log (the others hold one entry per trial).
STEP_FIELDS = ("poses", "actions", "winners", "deltas")
#: A per-step array that an entry keeps empty is left out of it; the reader puts this back.
_EMPTY_STEPS = {
    "poses": np.zeros((0, 3)),
    "actions": np.zeros(0, dtype=np.int64),
    "winners": np.zeros(0, dtype=np.int64),
    "deltas": np.zeros(0),
}
TRIAL_FIELDS = ("success", "steps", "start_far")
PARTS = ("train", "test", "heldout")

_RECOMPUTE = "make reproduce (recomputes the runs, then python -m docking ledger update)"


class StaleLedger(RuntimeError):
    """The ledger was computed by other code than this process runs."""


class NotInLedger(LookupError):
    """An analysis read a part of a run that its ledger entry does not keep."""


class CorruptLedger(StaleLedger):
    """A file of the ledger is not what the ledger's writer wrote: a manifest that is not one,
    a record that names another run's entry or a file outside the ledger, an entry that is
    not an entry, a wall time that is no time."""


#: What an error about a damaged ledger suggests.
_RESTORE = "check out the committed ledger again (git checkout -- ledger)"


# ------------------------------------------------------------------------------------------
# Where, and the manifest.
# ------------------------------------------------------------------------------------------


#: The values of ``DOCKING_LEDGER`` that turn the ledger off (in any case).
LEDGER_OFF = ("off", "0", "none", "false")


def ledger_off() -> bool:
    """Whether ``DOCKING_LEDGER`` turns the ledger off."""
    value = os.environ.get("DOCKING_LEDGER")
    return value is not None and value.strip().lower() in LEDGER_OFF


def ledger_dir() -> Path | None:
    """The ledger's folder: ``DOCKING_LEDGER`` if set (``off``, ``0``, ``none`` or ``false``:
    no ledger; otherwise the absolute path of an existing folder), else the checkout's
    ``ledger/`` (None for an installed package without one). Any other value of
    ``DOCKING_LEDGER`` (empty, a typo of ``off``, a relative path, a missing folder) is a
    ``ValueError`` naming it, never a silent "no ledger"."""
    value = os.environ.get("DOCKING_LEDGER")
    if value is not None:
        if ledger_off():
            return None
        usage = "set it to off or to the absolute path of a ledger folder, or unset it"
        if not value.strip():
            raise ValueError(f"DOCKING_LEDGER is set but empty; {usage}")
        path = Path(value).expanduser()
        if not path.is_absolute():
            raise ValueError(
                f"DOCKING_LEDGER={value!r} is neither off nor an absolute path; {usage}"
            )
        if not path.is_dir():
            raise ValueError(f"DOCKING_LEDGER={value!r} names no folder; {usage}")
        return path
    root = paths.checkout_root()
    return root / "ledger" if root is not None else None


def manifest(folder: Path | None = None) -> dict | None:
    """The ledger's manifest (None if there is no ledger), checked against this code:
    :class:`StaleLedger` if it was computed by other code."""
    folder = ledger_dir() if folder is None else Path(folder)
    data = _raw_manifest(folder)
    if data is not None:
        _check(folder, data)
    return data


#: The tiers' measured times (written by tools/time_tiers.py from a fresh clone).
TIMINGS_FILE = "timings.json"


def timings(folder: Path | None = None) -> dict | None:
    """The record of ``tools/time_tiers.py`` in the ledger's folder (None if there is none)."""
    folder = ledger_dir() if folder is None else Path(folder)
    if folder is None or not (folder / TIMINGS_FILE).is_file():
        return None
    return json.loads((folder / TIMINGS_FILE).read_text())


def size_bytes(folder: Path | None = None) -> int:
    """The bytes of every file of the ledger in ``folder`` (default :func:`ledger_dir`)."""
    folder = ledger_dir() if folder is None else Path(folder)
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


def computing_seconds(data: dict) -> tuple[int, float]:
    """The number of runs in a manifest (the learner's, the yardsticks' and PPO's) and the
    sum of their recorded wall times (seconds of one process each, training and testing)."""
    records = list(data["runs"].values())
    walls = [record.get("wall_seconds", float("nan")) for record in records]
    return len(walls), float(sum(walls))


def _raw_manifest(folder: Path | None) -> dict | None:
    if folder is None or not (folder / "manifest.json").is_file():
        return None
    path = (folder / "manifest.json").resolve()
    return _read_manifest(path, path.stat().st_mtime_ns)


@functools.lru_cache(maxsize=4)
def _read_manifest(path: Path, _mtime: int) -> dict:
    """The manifest at ``path``, each run's configuration put back into its record and the
    indexes by (configuration, seed) added; :class:`CorruptLedger` naming the file and what
    is wrong if it is not a manifest of this ledger format (one of another format is read as
    far as it can be: :func:`_check` refuses it, naming its format)."""
    try:
        data = json.loads(path.read_text())
    except (ValueError, UnicodeDecodeError) as exc:
        raise _not_a_manifest(path, f"not JSON ({exc})") from None
    if not isinstance(data, dict):
        raise _not_a_manifest(path, f"it holds a JSON {type(data).__name__}, not an object")
    if "format" not in data:
        raise _not_a_manifest(path, "it has no 'format'")
    ours = data.get("format") == LEDGER_FORMAT and data.get("store_format") == store.FORMAT_VERSION
    if ours:
        _check_manifest(path, data)
    configs = data.get("configs", {}) if isinstance(data.get("configs"), dict) else {}
    for record in _records(data):  # a run names its configuration in the table
        if isinstance(record.get("config"), str) and record["config"] in configs:
            record["config"] = configs[record["config"]]
    data["index"] = {
        _index_key(record["config"], record["seed"]): key
        for key, record in _records(data, keyed=True)
        if isinstance(record.get("config"), dict) and isinstance(record.get("seed"), int)
    }
    return data


def _records(data: dict, keyed: bool = False) -> list:
    """The records of ``data["runs"]`` that are dicts (with their keys if ``keyed``)."""
    table = data.get("runs", {})
    items = table.items() if isinstance(table, dict) else ()
    return [(k, r) if keyed else r for k, r in items if isinstance(r, dict)]


def _not_a_manifest(path: Path, what: str) -> CorruptLedger:
    return CorruptLedger(f"{path} is not a ledger manifest: {what}; {_RESTORE}")


def _check_manifest(path: Path, data: dict) -> None:
    """:class:`CorruptLedger` unless ``data`` has every field of a manifest of this format,
    of its type, and every run record its name, seed, entry, digests and configuration."""
    for name, kind in (
        ("fingerprints", dict),
        ("modules", dict),
        ("rendering_stack", str),
        ("runs", dict),
    ):
        if name not in data:
            raise _not_a_manifest(path, f"it has no {name!r}")
        if not isinstance(data[name], kind):
            raise _not_a_manifest(path, f"its {name!r} is not a {_TYPE_NAMES[kind]}")
    configs = data.get("configs", {})
    if not isinstance(configs, dict):
        raise _not_a_manifest(path, "its 'configs' is not an object")
    for name, fingerprint in data["fingerprints"].items():
        if not isinstance(fingerprint, str) or not isinstance(data["modules"].get(name), dict):
            raise _not_a_manifest(path, f"its runner {name!r:.40} has no fingerprint or modules")
    for key, record in data["runs"].items():
        problem = _record_problem(record, configs, data["fingerprints"])
        if problem:
            raise _not_a_manifest(path, f"the record of run {key[:24]!r} {problem}")


_TYPE_NAMES = {str: "string", dict: "JSON object", int: "integer"}


#: The wall times a record of each runner must have (others are checked where present).
_RECORD_TIMES = {"ppo": ("wall_time_train", "wall_time_test", "wall_seconds")}


def _record_problem(record, configs: dict, fingerprints: dict) -> str | None:
    """What is wrong with a manifest's run record (None if nothing)."""
    if not isinstance(record, dict):
        return "is not a JSON object"
    if record.get("runner") not in fingerprints:
        return f"names the runner {record.get('runner')!r:.40}, of no fingerprint in the manifest"
    for name in ("name", "file", "entry_digest", "digest"):
        if not isinstance(record.get(name), str):
            return f"has no {name!r} string"
    seed = record.get("seed")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        return f"has the seed {seed!r}, not an integer >= 0"
    config = record.get("config")
    if not (isinstance(config, dict) or (isinstance(config, str) and config in configs)):
        return f"names the configuration {config!r:.40}, which the manifest does not hold"
    required = _RECORD_TIMES.get(record["runner"], ())
    for name in ("wall_time_train", "wall_time_test", "wall_seconds"):
        if (name in required or name in record) and _seconds_problem(record.get(name)):
            return f"has {name} {record.get(name)!r}, not a time in seconds (finite, >= 0)"
    return None


def _seconds_problem(value) -> bool:
    """Whether ``value`` is not a wall time: a finite number >= 0."""
    return (
        isinstance(value, bool)
        or not isinstance(value, (int, float))
        or not np.isfinite(value)
        or value < 0
    )


def _index_key(config: dict, seed: int) -> str:
    return f"{json.dumps(config, sort_keys=True, separators=(',', ':'))}:seed{seed}"


def _check(folder: Path, data: dict, runners: Iterable[Runner] | None = None) -> None:
    """:class:`StaleLedger` unless ``data``'s runs of ``runners`` (default: of every runner
    the ledger holds runs of) were computed by this code; a warning (once) if by another
    rendering stack."""
    if data.get("format") != LEDGER_FORMAT or data.get("store_format") != store.FORMAT_VERSION:
        raise StaleLedger(
            f"the ledger in {folder} has format {data.get('format')}/{data.get('store_format')}"
            f", this package reads {LEDGER_FORMAT}/{store.FORMAT_VERSION}; recompute it: "
            f"{_RECOMPUTE}"
        )
    if runners is None:
        runners = [runner_named(name) for name in sorted(data["fingerprints"])]
    for runner in runners:
        if data["fingerprints"].get(runner.name) != runner.fingerprint():
            changed = _changed_modules(data["modules"].get(runner.name, {}), runner)
            raise StaleLedger(
                f"the ledger in {folder} holds {runner.name} runs computed by other code "
                f"(changed: {', '.join(changed) or 'the fingerprint'}); they are not used. "
                f"Recompute them: {_RECOMPUTE}"
            )
    stack = store.rendering_stack()
    if data["rendering_stack"] != stack and not data.get("warned"):
        data["warned"] = True
        warnings.warn(
            f"the ledger's runs were rendered by {data['rendering_stack']!r}, this machine "
            f"renders with {stack!r}; they are served as they were computed. `python -m "
            "docking verify --sample 3` shows whether runs still agree here.",
            RuntimeWarning,
            stacklevel=3,
        )


def holds(config: ExperimentConfig | PPOConfig, seed: int, check: bool = False) -> bool:
    """Whether the ledger holds the run of (``config``, ``seed``) (computed by any code; with
    ``check``, :class:`StaleLedger` if it holds it but its runner's code is not this code)."""
    found = _find(config, seed)
    if found is not None and check:
        folder, data, _ = found
        _check(folder, data, [runner_for(config)])
    return found is not None


def lookup(config: ExperimentConfig | PPOConfig, seed: int) -> ExperimentResult | None:
    """The ledger's entry for (``config``, ``seed``), of any runner: a :class:`LedgerResult`
    for the learner's, a ``docking.ppo.PPOResult`` for PPO's (whose held-out log keeps every
    per-trial array and no per-step one: reading one raises :class:`NotInLedger`); None if
    the ledger does not hold the run (or there is no ledger). :class:`StaleLedger` if it
    holds the run but its runner's code is not this code: its numbers are never served then."""
    runner = runner_for(config)
    found = _find(config, seed)
    if found is None:
        return None
    folder, data, key = found
    _check(folder, data, [runner])
    if key != store.run_key(config, seed, render=data["rendering_stack"]):
        raise StaleLedger(f"the ledger's key of {config.name!r} seed {seed} is not this code's")
    record = data["runs"][key]
    path = _entry_path(folder, record, key, config.name, seed)
    if record["runner"] != runner.name:
        raise CorruptLedger(
            f"the ledger's record of run {config.name!r} seed {seed} names the runner "
            f"{record['runner']!r}, not {runner.name!r}; {_RESTORE}"
        )
    arrays = _verified_arrays(path, record["entry_digest"])
    try:
        return _READERS[runner.name](arrays, config, key, seed, record, path)
    except (KeyError, ValueError, TypeError, IndexError) as exc:
        what = f"lacks {exc}" if isinstance(exc, KeyError) else f"is damaged ({exc})"
        raise CorruptLedger(f"the ledger entry {path} {what}; {_RESTORE}") from None


def _entry_path(folder: Path, record: dict, key: str, name: str, seed: int) -> Path:
    """The entry file of the manifest's ``record`` of run ``key`` (``name``, ``seed``):
    :class:`CorruptLedger` naming the record unless it is the run's own entry,
    ``runs/<name>/<key[:16]>/seed<k>.xz`` in the ledger's folder (an entry does not hold its
    key: where it lies names it; the reader checks its seed too)."""
    where = f"the ledger's record of run {name!r} seed {seed} (key {key[:16]})"
    root = Path(folder).resolve()
    try:
        path = (root / record["file"]).resolve()
    except (OSError, RuntimeError, ValueError) as exc:
        raise CorruptLedger(
            f"{where} names the entry {record['file']!r} ({exc}); {_RESTORE}"
        ) from None
    if not path.is_relative_to(root):
        raise CorruptLedger(
            f"{where} names the entry {record['file']!r}, outside the ledger folder {root}; "
            f"{_RESTORE}"
        )
    own = _entry_file(name, key, seed)
    if record["file"] != own or record["seed"] != seed or record["name"] != name:
        raise CorruptLedger(
            f"{where} names the entry {record['file']!r}, not the run's own {own!r}; {_RESTORE}"
        )
    return path


def _entry_file(name: str, key: str, seed: int) -> str:
    """Where in the ledger's folder the entry of run ``key`` (``name``, ``seed``) lies."""
    return f"runs/{name}/{key[:16]}/seed{seed}.xz"


def _find(config, seed: int) -> tuple[Path, dict, str] | None:
    """``(folder, manifest, run key)`` of the ledger's entry for (``config``, ``seed``);
    None if it holds none."""
    runner_for(config)  # TypeError for what is no run's configuration
    folder = ledger_dir()
    data = _raw_manifest(folder)
    if data is None:
        return None
    key = data["index"].get(_index_key(config.to_dict(), seed))
    return None if key is None else (folder, data, key)


def _changed_modules(theirs: dict, runner: Runner) -> list[str]:
    """The package modules (and libraries) of ``runner``'s computation whose digests differ
    from ``theirs`` (a manifest's record of that runner's modules)."""
    ours = runner.module_digests()
    return sorted(k for k in set(ours) | set(theirs) if ours.get(k) != theirs.get(k))


def _verified_arrays(path: Path, entry_digest: str) -> dict[str, np.ndarray]:
    """The arrays of the entry file ``path``, after checking its bytes against
    ``entry_digest`` (:class:`StaleLedger` if they differ)."""
    import lzma

    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise CorruptLedger(f"the ledger entry {path} is missing; {_RESTORE}") from None
    except OSError as exc:
        raise CorruptLedger(f"the ledger entry {path} cannot be read ({exc}); {_RESTORE}") from None
    if hashlib.sha256(raw).hexdigest() != entry_digest:
        raise StaleLedger(f"the ledger entry {path} does not match its digest in the manifest")
    try:
        return _decode_entry(raw)
    except (lzma.LZMAError, EOFError, ValueError, TypeError, KeyError, OverflowError) as exc:
        raise CorruptLedger(
            f"the ledger entry {path} matches its digest but is not a ledger entry "
            f"({type(exc).__name__}: {exc}); {_RESTORE}"
        ) from None


def _seconds(meta: dict, name: str, path: Path) -> float:
    """The wall time ``meta[name]`` (of the entry ``path`` or its record): a finite number
    of seconds >= 0, else :class:`CorruptLedger` (wall times are outside the digests)."""
    value = meta.get(name)
    if _seconds_problem(value):
        raise CorruptLedger(
            f"the ledger entry {path} (or its record) has {name} {value!r}, not a time in "
            f"seconds (finite, >= 0); {_RESTORE}"
        )
    return float(value)


def _ppo_entry(result: ppo.PPOResult, keep: dict) -> tuple[dict[str, np.ndarray], dict]:
    """The arrays of a PPO run's entry (its training episodes and its held-out per-trial
    arrays: what the analyses read of a PPO run) and what its record adds (its wall times)."""
    arrays = {"train.success": result.train_success, "train.steps": result.train_steps}
    for name in TRIAL_FIELDS:
        arrays[f"heldout.{name}"] = getattr(result.heldout, name)
    walls = {
        "wall_time_train": round(result.wall_time_train, 1),
        "wall_time_test": round(result.wall_time_test, 1),
    }
    return arrays, walls


def _read_ppo_entry(
    arrays: dict, config: PPOConfig, key: str, seed: int, record: dict, path: Path
) -> ppo.PPOResult:
    """The PPO run of the entry ``path`` (its ``arrays``) of the manifest's ``record``."""
    where = f"PPO run {config.name!r} seed {seed} (key {key[:16]}), heldout"
    names = [f"heldout.{name}" for name in TRIAL_FIELDS] + ["train.success", "train.steps"]
    if any(name not in arrays for name in names):
        absent = [name for name in names if name not in arrays]
        raise CorruptLedger(f"the ledger entry {path} lacks {', '.join(absent)}; {_RESTORE}")
    per_trial = {name: arrays[f"heldout.{name}"] for name in TRIAL_FIELDS}
    n = len(per_trial["success"])
    empty = {name: np.zeros(0, dtype=np.float32) for name in STEP_FIELDS}
    heldout = PartialTrialLog(where, per_trial, np.zeros(n, dtype=bool), empty, set(), None)
    return ppo.PPOResult(
        config=config,
        seed=seed,
        train_success=arrays["train.success"],
        train_steps=arrays["train.steps"],
        heldout=heldout,
        wall_time_train=_seconds(record, "wall_time_train", path),
        wall_time_test=_seconds(record, "wall_time_test", path),
    )


# ------------------------------------------------------------------------------------------
# Entries: reduced runs.
# ------------------------------------------------------------------------------------------


class PartialTrialLog(TrialLog):
    """A trial log of a ledger entry: the per-trial arrays in ``per_trial`` (success always;
    the others if an analysis read them); each per-step array either whole (if an analysis
    read it whole), or only for the trials in ``kept`` (if an analysis read it trial by
    trial: the fields in ``sliced``), or not at all. Reading an array or per-step data that
    is not kept raises :class:`NotInLedger`."""

    def __init__(
        self,
        where: str,
        per_trial: dict,
        kept: np.ndarray,
        steps: dict,
        whole: set,
        starts,
        sliced: set = frozenset(STEP_FIELDS),
    ):
        self._per_trial = dict(per_trial)
        self._where, self._kept, self._steps = where, kept, steps
        self._whole_fields, self._starts, self._sliced = whole, starts, sliced
        if "steps" in per_trial:  # kept whenever per-step data is
            n = np.asarray(per_trial["steps"], dtype=np.int64)
            self._all_offsets = np.concatenate([[0], np.cumsum(n)])
            self._kept_offsets = np.concatenate([[0], np.cumsum(np.where(kept, n, 0))])

    def _trial_field(self, name: str) -> np.ndarray:
        if name not in self._per_trial:
            raise self._missing(f"{name} of every trial")
        return self._per_trial[name]

    success = property(lambda self: self._trial_field("success"))
    steps = property(lambda self: self._trial_field("steps"))
    start_far = property(lambda self: self._trial_field("start_far"))

    def _missing(self, what: str) -> NotInLedger:
        return NotInLedger(
            f"{self._where}: {what} is not kept in the ledger (only what the notebooks read "
            f"is); compute the run: {_RECOMPUTE}"
        )

    def _whole(self, name: str) -> np.ndarray:
        if name not in self._whole_fields and not (self._kept.all() and name in self._sliced):
            raise self._missing(f"{name} of every trial")
        return self._steps[name]

    poses = property(lambda self: self._whole("poses"))
    actions = property(lambda self: self._whole("actions"))
    winners = property(lambda self: self._whole("winners"))
    deltas = property(lambda self: self._whole("deltas"))

    def _slice(self, name: str, k: int, extra: int) -> np.ndarray:
        k = int(k)
        length = int(self.steps[k]) + extra
        if name in self._whole_fields:
            start = int(self._all_offsets[k]) + extra * k
        elif self._kept[k] and name in self._sliced:
            before = int(np.count_nonzero(self._kept[:k]))  # kept trials before k
            start = int(self._kept_offsets[k]) + extra * before
        else:
            raise self._missing(f"{name} of trial {k}")
        return self._steps[name][start : start + length]

    def trial_poses(self, k: int) -> np.ndarray:
        return self._slice("poses", k, 1)

    def trial_actions(self, k: int) -> np.ndarray:
        return self._slice("actions", k, 0)

    @property
    def starts(self) -> np.ndarray:
        if self._starts is not None:
            return self._starts
        if "poses" in self._whole_fields or (self._kept.all() and "poses" in self._sliced):
            return TrialLog.starts.fget(self)
        raise self._missing("the start poses")


class LedgerResult(ExperimentResult):
    """A run read from its ledger entry: an ``ExperimentResult`` whose network, if the entry
    does not keep it, raises :class:`NotInLedger`."""

    def __init__(self, fields: dict, network: Network | None, where: str):
        self.__dict__.update(fields)
        self._network, self._where = network, where

    @property
    def network(self) -> Network:
        if self._network is None:
            raise NotInLedger(
                f"{self._where}: the weights W and Q are not kept in the ledger (only what "
                f"the notebooks read is); compute the run: {_RECOMPUTE}"
            )
        return self._network


def _read_learner_entry(
    arrays: dict, config: ExperimentConfig, key: str, seed: int, record: dict, path: Path
) -> LedgerResult:
    """The learner's run of the entry ``path`` (its ``arrays``) of the manifest's ``record``
    (run ``key``, ``seed``): :class:`CorruptLedger` if the entry holds another seed, lacks an
    array or has a wall time that is not one."""
    meta = json.loads(str(arrays.pop("meta")))
    if not isinstance(meta, dict) or meta.get("seed") != seed:
        found = meta.get("seed") if isinstance(meta, dict) else meta
        raise CorruptLedger(
            f"the ledger entry {path} holds the run of seed {found!r}, not of seed {seed} "
            f"that its record names; {_RESTORE}"
        )
    walls = {name: _seconds(meta, name, path) for name in ("wall_time_train", "wall_time_test")}
    where = f"run {config.name!r} seed {seed} (key {key[:16]})"
    logs = {}
    for part in PARTS:
        if f"{part}.success" not in arrays:
            logs[part] = None
            continue
        per_trial = {n: arrays[f"{part}.{n}"] for n in TRIAL_FIELDS if f"{part}.{n}" in arrays}
        kept = arrays[f"{part}.kept"]
        steps = {n: arrays.get(f"{part}.{n}", _EMPTY_STEPS[n]) for n in STEP_FIELDS}
        whole = {n for n, w in zip(STEP_FIELDS, arrays[f"{part}.whole"], strict=True) if w}
        starts = arrays.get(f"{part}.starts")
        sliced = {n for n, w in zip(STEP_FIELDS, arrays[f"{part}.sliced"], strict=True) if w}
        logs[part] = PartialTrialLog(
            f"{where}, {part}", per_trial, kept, steps, whole, starts, sliced
        )
    network = None
    if "W.xor" in arrays:
        W = _xor_start(arrays["W.xor"], config, seed)
        network = Network.from_weights(config.network, W, arrays["Q"])
    fields = {
        "config": config,
        "seed": seed,
        **logs,
        **{name: arrays[name] for name in arrays if name.startswith("curve_")},
        **walls,
    }
    return LedgerResult(fields, network, where)


def _learner_entry(result: ExperimentResult, keep: dict) -> tuple[dict[str, np.ndarray], dict]:
    """The arrays of the learner's ``result``'s entry (what ``keep``, a trace record, names;
    its seed and wall times in a ``meta`` record) and what its record adds (nothing)."""
    arrays = _entry_arrays(result, keep)
    meta = {  # the configuration and the key are the manifest's record's
        "seed": result.seed,
        "wall_time_train": result.wall_time_train,
        "wall_time_test": result.wall_time_test,
    }
    arrays["meta"] = np.array(json.dumps(meta, sort_keys=True))
    return arrays, {}


#: Per runner: what its entry keeps of a run, and the run an entry gives back.
_WRITERS = {"learner": _learner_entry, "ppo": _ppo_entry}
_READERS = {"learner": _read_learner_entry, "ppo": _read_ppo_entry}


def _entry_arrays(result: ExperimentResult, keep: dict) -> dict[str, np.ndarray]:
    """The arrays of the learner's ``result``'s entry: what ``keep`` (a trace record) names."""
    arrays = {
        name: getattr(result, name)
        for name in ("curve_trials", "curve_success", "curve_steps", "curve_rewarded")
    }
    if keep.get("network"):
        arrays["W.xor"] = _xor_start(result.network.W, result.config, result.seed)
        arrays["Q"] = result.network.Q
    for part in PARTS:
        log = getattr(result, part)
        if log is None:
            continue
        wanted = keep.get("parts", {}).get(part, {})
        whole = set(wanted.get("whole", ()))
        kept = np.zeros(len(log), dtype=bool)
        kept[np.asarray(wanted.get("trials", []), dtype=np.int64)] = True
        # Per trial: success always (it is the log's length), the number of steps if read or
        # if per-step data is kept (it locates each trial's), the far edge if read.
        per_trial = {"success"} | set(wanted.get("per_trial", ()))
        if whole or kept.any():
            per_trial.add("steps")
        for name in TRIAL_FIELDS:
            if name in per_trial:
                arrays[f"{part}.{name}"] = getattr(log, name)
        n_steps = np.asarray(log.steps)
        masks = {"poses": np.repeat(kept, n_steps + 1)}
        masks.update(dict.fromkeys(("actions", "winners", "deltas"), np.repeat(kept, n_steps)))
        # Per trial, only the fields an analysis read trial by trial (a failure's poses, say,
        # not its TD errors).
        sliced = set(wanted.get("fields", STEP_FIELDS)) if kept.any() else set()
        arrays[f"{part}.kept"] = kept
        arrays[f"{part}.whole"] = np.array([name in whole for name in STEP_FIELDS])
        arrays[f"{part}.sliced"] = np.array([name in sliced for name in STEP_FIELDS])
        for name in STEP_FIELDS:  # an empty one is left out (the reader puts it back)
            array = getattr(log, name)
            if name in whole and len(array):
                arrays[f"{part}.{name}"] = array
            elif name in sliced and masks[name].any():
                arrays[f"{part}.{name}"] = array[masks[name]]
        if wanted.get("starts") and "poses" not in whole and not kept.all():
            arrays[f"{part}.starts"] = log.starts
    return arrays


# ------------------------------------------------------------------------------------------
# Tracing what the analyses read.
# ------------------------------------------------------------------------------------------


def trace_file() -> Path | None:
    """The file named by ``DOCKING_TRACE`` (None: no tracing)."""
    value = os.environ.get("DOCKING_TRACE")
    return Path(value) if value else None


class _TracedLog(TrialLog):
    """A full trial log that records which per-trial arrays and which per-step data are
    read."""

    def __init__(self, log: TrialLog, note):
        self.__dict__.update({f.name: getattr(log, f.name) for f in dataclasses.fields(log)})
        object.__setattr__(self, "_note", note)

    def __getattribute__(self, name):
        if name in STEP_FIELDS:
            object.__getattribute__(self, "_note")("whole", name)
        elif name in TRIAL_FIELDS:
            object.__getattribute__(self, "_note")("per-trial", name)
        return object.__getattribute__(self, name)

    def trial_poses(self, k: int) -> np.ndarray:
        self._note("trial", int(k))
        self._note("field", "poses")
        return TrialLog.trial_poses(self._raw(), k)

    def trial_actions(self, k: int) -> np.ndarray:
        self._note("trial", int(k))
        self._note("field", "actions")
        return TrialLog.trial_actions(self._raw(), k)

    @property
    def starts(self) -> np.ndarray:
        self._note("starts", None)
        return self._raw().starts

    def _raw(self) -> TrialLog:
        d = object.__getattribute__(self, "__dict__")
        return TrialLog(**{f.name: d[f.name] for f in dataclasses.fields(TrialLog)})


class TracedResult(ExperimentResult):
    """A stored run that appends to the trace file what the analyses read of it: that it was
    loaded (and from where), its network, and per trial log the per-step data of which trials
    (or all of them), or the start poses. Each fact is written once per process."""

    def __init__(self, result: ExperimentResult, key: str, path: Path, source: Path):
        self.__dict__.update({f.name: getattr(result, f.name) for f in dataclasses.fields(result)})
        self._key, self._trace = key, path
        for part in PARTS:
            log = getattr(result, part)
            if log is not None:
                self.__dict__[part] = _TracedLog(log, functools.partial(self._note, part))
        self._note(None, "load", str(Path(source).resolve()))

    def __getattribute__(self, name):
        if name == "network":
            object.__getattribute__(self, "_note")(None, "network", None)
        return object.__getattribute__(self, name)

    def _note(self, part, kind, value) -> None:
        _write_fact(self._trace, self._key, part, kind, value)


#: The facts this process has written to the trace already.
_NOTED: set = set()


def _write_fact(trace_path: Path, key: str, part, kind: str, value) -> None:
    """Append one fact about run ``key`` to the trace file, once per process."""
    fact = (key, part, kind, value)
    if fact in _NOTED:
        return
    _NOTED.add(fact)
    line = json.dumps({"key": key, "part": part, "kind": kind, "value": value})
    with open(trace_path, "a") as f:
        f.write(line + "\n")


def trace(result: ExperimentResult, key: str, source: Path) -> ExperimentResult:
    """``result`` (loaded from the stored file ``source``) as a :class:`TracedResult` if
    ``DOCKING_TRACE`` names a file, else itself."""
    path = trace_file()
    return result if path is None else TracedResult(result, key, path, source)


def _trace_ppo(result: ppo.PPOResult, key: str, source: Path) -> ppo.PPOResult:
    """Record in the trace file (if any) that the PPO run ``key`` was loaded from ``source``
    (its ledger entry keeps what the analyses read of a PPO run: :func:`_ppo_entry`);
    ``result``."""
    path = trace_file()
    if path is not None:
        _write_fact(path, key, None, "load-ppo", str(Path(source).resolve()))
    return result


#: Per runner: how a run loaded from the store is traced.
_TRACERS = {"learner": trace, "ppo": _trace_ppo}


#: The kinds of a trace file's facts, and what each one's value is.
_TRACE_VALUES = {
    "load": str,
    "load-ppo": str,
    "network": type(None),
    "whole": STEP_FIELDS,
    "field": STEP_FIELDS,
    "per-trial": TRIAL_FIELDS,
    "starts": type(None),
    "trial": int,
}


def read_trace(lines: Iterable[str], source: str = "the trace") -> dict[str, dict]:
    """``{run key: what to keep}`` from the lines of trace files (a PPO run's record has
    ``"ppo": True``). A line that is not a fact of :func:`_write_fact` is a ``ValueError``
    naming ``source`` (the trace file) and its line number."""
    keep: dict[str, dict] = {}
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            record = _trace_fact(line)
        except ValueError as exc:
            raise ValueError(
                f"{source}, line {number}, is not a trace record ({exc}): {line.strip()[:80]!r}"
            ) from None
        entry = keep.setdefault(record["key"], {"network": False, "parts": {}})
        if record["kind"] in ("load", "load-ppo"):
            entry["path"] = record["value"]
            if record["kind"] == "load-ppo":
                entry["ppo"] = True
            continue
        if record["kind"] == "network":
            entry["network"] = True
            continue
        part = entry["parts"].setdefault(
            record["part"],
            {"whole": set(), "trials": set(), "fields": set(), "per_trial": set()},
        )
        if record["kind"] == "whole":
            part["whole"].add(record["value"])
        elif record["kind"] == "per-trial":
            part["per_trial"].add(record["value"])
        elif record["kind"] == "field":
            part["fields"].add(record["value"])
        elif record["kind"] == "starts":
            part["starts"] = True
        else:
            part["trials"].add(int(record["value"]))
    for entry in keep.values():
        for part in entry["parts"].values():
            part["trials"] = sorted(part["trials"])
            part["whole"] = sorted(part["whole"])
            part["fields"] = sorted(part["fields"])
            part["per_trial"] = sorted(part["per_trial"])
    return keep


def _trace_fact(line: str) -> dict:
    """One fact of a trace file (a JSON object of key, part, kind and value); ``ValueError``
    saying what is wrong with it."""
    try:
        record = json.loads(line)
    except ValueError as exc:
        raise ValueError(f"not JSON: {exc}") from None
    if not isinstance(record, dict):
        raise ValueError(f"a JSON {type(record).__name__}, not an object")
    absent = [name for name in ("key", "part", "kind", "value") if name not in record]
    if absent:
        raise ValueError(f"no {', '.join(map(repr, absent))}")
    kind, value = record["kind"], record["value"]
    if not isinstance(record["key"], str) or not record["key"]:
        raise ValueError(f"the key {record['key']!r} is not a run key")
    if kind not in _TRACE_VALUES:
        raise ValueError(f"the kind {kind!r} is not one of {', '.join(_TRACE_VALUES)}")
    if kind not in ("load", "load-ppo", "network") and record["part"] not in PARTS:
        raise ValueError(f"the part {record['part']!r} is not one of {', '.join(PARTS)}")
    wanted = _TRACE_VALUES[kind]
    if isinstance(wanted, tuple):
        ok = value in wanted
    elif wanted is int:
        ok = isinstance(value, int) and not isinstance(value, bool) and value >= 0
    else:
        ok = isinstance(value, wanted)
    if not ok:
        raise ValueError(f"the value {value!r:.60} does not fit the kind {kind!r}")
    return record


# ------------------------------------------------------------------------------------------
# Writing the ledger.
# ------------------------------------------------------------------------------------------


def update(keep: dict[str, dict], folder: Path | str | None = None) -> dict:
    """Write the ledger of the runs in ``keep`` (from :func:`read_trace`: run key -> where it
    is stored and what the analyses read of it) from their stored files, keeping of each what
    ``keep`` names; replaces the ledger's entries. Returns the manifest."""
    from docking.platform_info import numeric_platform

    folder = Path(folder) if folder is not None else ledger_dir()
    if folder is None:
        raise ValueError("no ledger folder: DOCKING_LEDGER is off and no folder was given")
    runs, files, runners = {}, {}, {}
    for key, wanted in sorted(keep.items()):
        if "path" not in wanted:
            raise ValueError(f"the trace names run {key[:16]} but not where it is stored")
        path = Path(wanted["path"])
        result = store.load_result(path, key)  # checks the file against the key and its digest
        with np.load(path, allow_pickle=False) as data:
            digest = store.content_digest(data)
        config, seed = result.config, result.seed
        runner = runner_for(config)
        runners[runner.name] = runner
        arrays, extra = _WRITERS[runner.name](result, wanted)
        relative = _entry_file(config.name, key, seed)
        files[relative] = _encode_entry(arrays)
        runs[key] = {
            "runner": runner.name,
            "name": config.name,
            "seed": seed,
            "digest": digest,
            "file": relative,
            "entry_digest": hashlib.sha256(files[relative]).hexdigest(),
            "config": config.to_dict(),
            **extra,
            "wall_seconds": round(result.wall_time_train + result.wall_time_test, 1),
        }
    data = {
        "format": LEDGER_FORMAT,
        "store_format": store.FORMAT_VERSION,
        "fingerprints": {name: runner.fingerprint() for name, runner in runners.items()},
        "modules": {name: runner.module_digests() for name, runner in runners.items()},
        "rendering_stack": store.rendering_stack(),
        "platform": numeric_platform(),
        "runs": runs,
    }
    # Each configuration once, in a table; a run names its entry (the seeds of a cell share
    # one). Reading the manifest puts the configurations back into the runs' records.
    data["configs"] = {}
    for record in runs.values():
        text = json.dumps(record["config"], sort_keys=True, separators=(",", ":"))
        ref = hashlib.sha256(text.encode()).hexdigest()[:16]
        data["configs"][ref], record["config"] = record["config"], ref
    folder.mkdir(parents=True, exist_ok=True)
    # (ppo/: where ledgers of format 4 kept PPO's entries)
    old = {p for kind in ("runs", "ppo") for p in folder.glob(f"{kind}/**/*") if p.is_file()}
    for relative, raw in files.items():
        target = folder / relative
        old.discard(target)
        if not target.exists() or target.read_bytes() != raw:
            atomic_write(target, lambda f, raw=raw: f.write(raw))
    for stale in old:
        stale.unlink()
    text = json.dumps(data, indent=1, sort_keys=True) + "\n"
    atomic_write(folder / "manifest.json", lambda f: f.write(text.encode()))
    _read_manifest.cache_clear()
    return _raw_manifest(folder)


def _xor_start(W: np.ndarray, config: ExperimentConfig, seed: int) -> np.ndarray:
    """Between a run's ``W`` (float64) and its entry's ``W.xor`` (uint64): the bitwise XOR
    with the run's random start W. Given ``W``, the XOR; given the XOR, ``W`` (every bit)."""
    start = np.ascontiguousarray(initial_network(config, seed).W, dtype=np.float64)
    W = np.ascontiguousarray(W)
    if W.dtype not in (np.float64, np.uint64) or W.shape != start.shape:
        raise ValueError(
            f"W of dtype {W.dtype} and shape {W.shape} does not match the run's start "
            f"(float64, {start.shape})"
        )
    bits = W.view(np.uint64) ^ start.view(np.uint64)
    return bits.view(np.float64) if W.dtype == np.uint64 else bits


def _shuffle_unit(dtype: np.dtype, size: int) -> int:
    """The bytes shuffled as one: an element's (its alignment: 8 for float64, 4 for a
    character of a str array), or 1 if the data does not divide into them."""
    unit = max(int(dtype.alignment), 1)
    return unit if size % unit == 0 else 1


def _encode_entry(arrays: dict) -> bytes:
    """The bytes of an entry file: an xz stream (preset 9) of a JSON index (each array's
    name, dtype, shape and memory order, by name; its length first, 8 bytes little-endian)
    followed by the arrays' data bytes, each shuffled by :func:`_shuffle_unit` (byte 0 of
    every element, then byte 1, ...: the sign-and-exponent bytes of floating-point numbers,
    nearly constant, end up together). Two-dimensional arrays are written column by column
    (a pose's x, y and yaw each together). The bytes, and so the entry's digest, depend on
    the arrays alone. Lossless; :func:`_decode_entry` reads it back."""
    import lzma

    index, chunks = [], []
    for name in sorted(arrays):
        array = np.asanyarray(arrays[name])
        fortran = array.ndim == 2
        data = np.frombuffer(
            (np.asfortranarray(array) if fortran else np.ascontiguousarray(array)).tobytes(
                order="F" if fortran else "C"
            ),
            np.uint8,
        )
        unit = _shuffle_unit(array.dtype, array.nbytes)
        chunks.append(data.reshape(-1, unit).T.tobytes())
        index.append([name, array.dtype.str, list(array.shape), fortran])
    head = json.dumps(index, separators=(",", ":")).encode()
    return lzma.compress(len(head).to_bytes(8, "little") + head + b"".join(chunks), preset=9)


def _decode_entry(raw: bytes) -> dict[str, np.ndarray]:
    """The arrays of an entry file's bytes (:func:`_encode_entry`), writable, each with the
    dtype, shape and every bit it was written with."""
    import lzma

    plain = lzma.decompress(raw)
    size = int.from_bytes(plain[:8], "little")
    offset = 8 + size
    arrays = {}
    for name, dtype, shape, fortran in json.loads(plain[8:offset]):
        dtype = np.dtype(dtype)
        nbytes = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
        data = np.frombuffer(plain, np.uint8, count=nbytes, offset=offset)
        offset += nbytes
        unit = _shuffle_unit(dtype, nbytes)
        flat = bytearray(data.reshape(unit, -1).T.tobytes())
        arrays[name] = np.frombuffer(flat, dtype=dtype).reshape(
            shape, order="F" if fortran else "C"
        )
    if offset != len(plain):
        raise ValueError(f"a ledger entry of {len(plain)} bytes holds {offset} bytes of arrays")
    return arrays


def load_run(
    config: ExperimentConfig | PPOConfig, seed: int, results_dir: Path | str | None = None
) -> ExperimentResult | ppo.PPOResult | None:
    """The run of (``config``, ``seed``) if it is stored: from the results store (checked
    against its key and digest; ``CorruptResult`` if the file there is bad), else from the
    committed ledger (:func:`lookup`; ``StaleLedger`` if the ledger holds the
    run but was computed by other code); None if neither holds it. Runs from the store are
    traced when ``DOCKING_TRACE`` is set (:func:`trace`). A ``docking.ppo.PPOConfig`` gives
    its ``PPOResult`` the same way."""
    runner = runner_for(config)
    path = store.result_path(config, seed, results_dir)
    if path.exists():
        key = store.run_key(config, seed)
        return _TRACERS[runner.name](store.load_result(path, key), key, path)
    return lookup(config, seed)
