"""A results table of the ledger (:mod:`docking.study.ledger`), as arrays: what a table keeps
of a run (its row, :func:`row`, as a design's ``keep`` asks), a table's columns of many rows
(:func:`columns`) and its ``.npz`` bytes (:func:`npz`: the same arrays, the same bytes), its
rows read back (:func:`table_bytes`, :func:`rows`), a row's digest (:func:`row_digest`), a
part's trial log read from a row (:class:`TableLog`: what the table does not keep is None, and
asking for it raises :class:`NotInLedger`) and a row compared with a recomputed run
(:func:`row_differences`). The ledger's files, manifest and checks are
:mod:`docking.study.ledger`'s.
"""

from __future__ import annotations

import dataclasses
import io
import zipfile

import numpy as np

from docking.experiments import TrialLog
from docking.study import kinds

__all__ = [
    "EVERYTHING",
    "NO_TRAIN",
    "NotInLedger",
    "PARTS",
    "STEPS",
    "TableLog",
    "columns",
    "npz",
    "row",
    "row_differences",
    "row_digest",
    "rows",
    "table_bytes",
]


PARTS = ("train", "test", "heldout")


STEPS = ("poses", "actions", "winners", "deltas")  # a trial log's per-step arrays


NO_TRAIN = "no-train"


#: Everything a table can keep of a run (``Design.keep``): a recomputed run's row with all
#: of it holds every column any table row can have (:func:`row_differences`).
EVERYTHING = frozenset({"starts", "ends", "lengths", "paths", "winners", "networks"})


UNPACKED_LIMIT = 1 << 30


class NotInLedger(LookupError):
    """An analysis asked a table run for what its table does not keep."""


@dataclasses.dataclass
class TableLog(TrialLog):
    """A trial log read from a results table. ``poses``, ``actions`` and ``deltas`` are
    None (``winners`` too unless kept); ``start_poses``, ``ends`` and ``lengths`` are the
    kept per-trial columns (None if not kept); ``paths`` maps a failed trial to its kept
    ``(poses, actions)``."""

    start_poses: np.ndarray | None = None
    ends: np.ndarray | None = None
    lengths: np.ndarray | None = None
    paths: dict = dataclasses.field(default_factory=dict)
    what: str = "a run"

    @property
    def starts(self) -> np.ndarray:
        return self.require(self.start_poses, "the trials' start poses")

    def trial_poses(self, k: int) -> np.ndarray:
        return self.require(self.paths.get(int(k), (None,))[0], f"the path of trial {k}")

    def trial_actions(self, k: int) -> np.ndarray:
        return self.require(self.paths.get(int(k), (None, None))[1], f"the path of trial {k}")

    def require(self, value, what: str):
        """``value`` (a kept column), or :class:`NotInLedger` naming ``what`` if it is None."""
        if value is None:
            raise NotInLedger(
                f"the ledger's table of {self.what} does not keep {what}: keep it in its "
                "design (`keep`, or the run in `whole`; then python -m docking ledger "
                "update), or compute it (DOCKING_LEDGER=off)"
            )
        return value


def row(arrays: dict, keep: frozenset) -> dict[str, np.ndarray]:
    """What a table keeps of a run's stored ``arrays`` as ``keep`` asks (module docstring)."""
    from docking.study.arrays import final_poses, path_lengths

    row, parts = {}, PARTS[1:] if NO_TRAIN in keep else PARTS
    for name, array in arrays.items():
        part, _, field = name.rpartition(".")
        if name == "meta" or (part == "train" and (NO_TRAIN in keep or field == "winners")):
            continue
        if field in STEPS and not (field == "winners" and "winners" in keep):
            continue
        if name in ("W", "Q") and "networks" not in keep:
            continue
        row[name] = np.ravel(array) if name in ("W", "Q") else np.atleast_1d(array)
    for part in (p for p in parts if f"{p}.poses" in arrays):
        log = TrialLog(**{f.name: arrays[f"{part}.{f.name}"] for f in dataclasses.fields(TrialLog)})
        if "starts" in keep:  # a part of no trials has no start pose: an empty column
            row[f"{part}.starts"] = log.starts if len(log.success) else np.zeros((0, 3))
        if "ends" in keep and part != "train":
            row[f"{part}.ends"] = final_poses(log)
        if "lengths" in keep and part != "train":
            row[f"{part}.lengths"] = path_lengths(log)
        if "paths" in keep and part != "train":  # the failed trials' poses and actions
            failed = row[f"{part}.path.trial"] = np.flatnonzero(~log.success)
            for f, empty in (("poses", np.zeros((0, 3))), ("actions", np.zeros(0, np.int64))):
                paths = [getattr(log, f"trial_{f}")(k) for k in failed]
                row[f"{part}.path.{f}"] = np.concatenate(paths) if paths else empty
    return row


def columns(runs: list[tuple[str, dict]]) -> dict[str, np.ndarray]:
    """The results table of ``runs`` (``(key, its row)`` each, :func:`row`)."""
    table, rows = {"key": np.array([key for key, _ in runs])}, [row for _, row in runs]
    for name in sorted({n for row in rows for n in row}):
        found = [row.get(name) for row in rows]
        table[name] = np.concatenate([a for a in found if a is not None])
        table[name + ".count"] = np.array([-1 if a is None else len(a) for a in found])
    return table


def npz(arrays: dict[str, np.ndarray]) -> bytes:
    """``arrays`` as an ``.npz`` of LZMA-compressed members with fixed timestamps (the same
    arrays, the same bytes)."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_LZMA) as archive:
        for name, array in arrays.items():
            info = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_LZMA
            with archive.open(info, "w") as f:
                np.lib.format.write_array(f, np.asanyarray(array), allow_pickle=False)
    return buffer.getvalue()


def table_bytes(raw: bytes) -> dict[str, np.ndarray]:
    """The columns of a results table's (verified) bytes: a zip of ``.npy`` members holding
    at most :data:`UNPACKED_LIMIT` bytes decompressed (checked before decompressing)."""
    with zipfile.ZipFile(io.BytesIO(raw)) as archive:
        unpacked = sum(info.file_size for info in archive.infolist())
    if unpacked > UNPACKED_LIMIT:
        raise ValueError(
            f"its arrays would decompress to {unpacked} bytes, at most {UNPACKED_LIMIT}"
        )
    with np.load(io.BytesIO(raw), allow_pickle=False) as found:
        return {k: found[k] for k in found.files}


def rows(table: dict[str, np.ndarray]) -> list[tuple[str, dict]]:
    """The rows of a results table's columns ``table``, as :func:`columns` took them: per
    run, its key and ``{column: its cells}`` (the columns it has none of left out)."""
    names = [n for n in table if n + ".count" in table]
    offsets = {
        n: np.concatenate([[0], np.cumsum(np.maximum(table[n + ".count"], 0))]) for n in names
    }
    found = []
    for row, key in enumerate(table["key"].tolist()):
        cells = {}
        for n in names:
            count = int(table[n + ".count"][row])
            if count >= 0:
                start = int(offsets[n][row])
                cells[n] = table[n][start : start + count]
        found.append((key, cells))
    return found


def row_digest(cells: dict[str, np.ndarray]) -> str:
    """The digest of a table row's cells (``{column: its cells}``, :func:`rows`): what the
    table serves of a run, by name, dtype, shape and bytes
    (:func:`docking.study.kinds.content_digest`)."""
    return kinds.content_digest(cells)


def cell(table: dict, name: str, row: int) -> np.ndarray | None:
    """Run number ``row``'s rows of column ``name`` (None if it has none)."""
    counts = table[name + ".count"]
    start = int(np.sum(np.maximum(counts[:row], 0)))
    return table[name][start : start + counts[row]] if counts[row] >= 0 else None


def log(got: dict, part: str, what: str) -> TableLog | None:
    """A run's log of ``part`` from its table columns ``got`` (None if they have none), with
    the paths of the failed trials where the table keeps them."""
    if f"{part}.start_far" not in got:
        return None
    kept, failed = {}, got.get(f"{part}.path.trial", ())
    if len(failed):
        steps = got[f"{part}.steps"][failed]
        poses = np.split(got[f"{part}.path.poses"], np.cumsum(steps + 1)[:-1])
        actions = np.split(got[f"{part}.path.actions"], np.cumsum(steps)[:-1])
        kept = {int(k): path for k, *path in zip(failed, poses, actions, strict=True)}
    columns = {f: got.get(f"{part}.{f}") for f in ("success", "steps", "start_far", "winners")}
    return TableLog(
        **columns,
        poses=None,
        actions=None,
        deltas=None,
        start_poses=got.get(f"{part}.starts"),
        ends=got.get(f"{part}.ends"),
        lengths=got.get(f"{part}.lengths"),
        paths=kept,
        what=what,
    )


def row_differences(arrays: dict, cells: dict) -> list[str]:
    """The columns of a table row ``cells`` (:func:`rows`) that are not what the run's
    ``arrays`` (as stored, or recomputed) give: each column's cells compared bit for bit, in
    the table's dtype. A column the arrays cannot give counts as different (a part of no
    trials gives its derived columns empty, as the tables have always kept them)."""
    computed = row(arrays, EVERYTHING)
    differ = []
    for name, cell in sorted(cells.items()):
        mine = computed.get(name)
        if mine is None or np.shape(mine) != cell.shape:
            differ.append(name)
            continue
        ours = np.ascontiguousarray(np.asarray(mine).astype(cell.dtype, copy=False))
        if ours.tobytes() != np.ascontiguousarray(cell).tobytes():
            differ.append(name)
    return differ
