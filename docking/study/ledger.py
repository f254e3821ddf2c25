"""The results ledger: the committed evidence, a results table per design (``ledger/``).

``tables/<name>.npz`` holds the runs stored under ``name``: per trial of each part
(``train``, ``test``, ``heldout``) ``success``, ``steps``, ``start_far``, each run's learning
curves, and what its design's ``keep`` adds (:attr:`docking.study.design.Design.keep`).
``whole/<name>/<key[:16]>/seed<k>.npz`` holds the runs a design names whole, and
``manifest.json`` every run's key, seed, configuration, content digest and wall times, the
fingerprint of the code that computed them and the SHA-256 of every file. The layout, for
any tool that opens ``.npz``: docs/guide/ledger.md.

What is checked, and where (docs/guide/ledger.md says what each check proves):

* a file is read only if it is a regular file inside the ledger's folder, of bounded size,
  and its bytes match the manifest's SHA-256 (:func:`_verified`); table names are plain
  names;
* each run's record holds its content digest (all its arrays) and its *row digest* (the
  arrays its table serves); each table's *seal* (:data:`SEALED`, :func:`_seals`) is the
  SHA-256 of its file's digest and of those fields of its runs, and the migrations are
  sealed too: an edit of any of them, the table's bytes included, is refused;
* :func:`check_files` (``python -m docking ledger show``) checks every file, every row of
  every table against its record's row digest, every whole run's arrays against its
  content digest, and every record's key against the key of its configuration and seed
  under this code.

The seal lives in the manifest beside what it seals, so it refuses an edit, not a forgery:
someone who rewrites a table and reseals the manifest passes every digest. Only recomputing
a run shows that the arrays a reader is served are its arrays (``python -m docking
verify``: every recomputed run is compared with its record's digest *and* with its table's
row).

A run read from a table is an ordinary result whose logs are
:class:`docking.study.ledger_rows.TableLog` objects (a table's rows are
:mod:`docking.study.ledger_rows`): what the table does not keep is ``None``. A ledger computed
by other code raises :class:`StaleLedger` naming the changed modules. ``DOCKING_LEDGER=off``
turns the ledger off (every run is computed); ``DOCKING_LEDGER=/path`` reads another one.
"""

from __future__ import annotations

import functools
import hashlib
import io
import json
import re
import warnings
import zipfile
from pathlib import Path

import numpy as np

from docking.fileio import UnsafeFile, atomic_write, read_regular
from docking.study import kinds, ledger_rows, paths
from docking.validate import NAME_PATTERN, check_name

__all__ = ["CorruptLedger", "StaleLedger", "holds", "read"]

LEDGER_FORMAT = 8  # the layout's version (8: row digests, tables' digests sealed)
TIMINGS_FILE = "timings.json"  # the tiers' measured times (tools/time_tiers.py)
_RECOMPUTE = "make reproduce (recomputes the runs, then python -m docking ledger update)"
_RESTORE = "check out the committed ledger again (git checkout -- ledger)"
#: What a table's seal covers of each of its runs' records (besides its key), with the
#: table file's SHA-256.
SEALED = ("digest", "row", "wall_time_train", "wall_time_test", "wall_seconds", "computed_utc")
#: Sealed too where a record has them (records written before them are sealed as they were;
#: ``sha256``: a whole run's file).
SEALED_IF_PRESENT = ("rules_sha256", "sha256")
#: The seal of the manifest's migrations (not a table's name: table names are plain names).
MIGRATIONS_SEAL = "(migrations)"
#: The seal of the manifest's derived tables (``derived``: ``{name: SHA-256 of
#: derived/<name>.npz}``, arrays computed from runs, :mod:`docking.study.derived`).
DERIVED_SEAL = "(derived)"
#: The largest manifest, results table or whole run read (bytes on disk), and the most a
#: table's arrays may hold decompressed.
MANIFEST_LIMIT = 64 << 20
FILE_LIMIT = 256 << 20
#: A run's key: the SHA-256 of its configuration and code, and its seed.
KEY_PATTERN = re.compile(r"[0-9a-f]{64}:seed(0|[1-9][0-9]*)")


class StaleLedger(RuntimeError):
    """The ledger was computed by other code (or its files do not match the manifest)."""


class CorruptLedger(StaleLedger):
    """A ledger file is damaged or not a ledger file."""


def manifest(folder: Path | None = None) -> dict | None:
    """The ledger's manifest (None if none), checked against this code (:class:`StaleLedger`
    if computed by other code)."""
    data = _stored_manifest(paths.ledger_dir() if folder is None else Path(folder))
    for name in sorted(data["fingerprints"]) if data else ():
        _check(data, kinds.runner_named(name))
    return data


def _stored_manifest(folder: Path | None) -> dict | None:
    """The manifest in ``folder`` as read (cached until the file changes); None if none."""
    if folder is None or not (folder / "manifest.json").exists():
        return None
    path = Path(folder).resolve() / "manifest.json"
    return _read_manifest(path, path.stat().st_mtime_ns)


@functools.lru_cache(maxsize=4)
def _read_manifest(path: Path, _mtime: int) -> dict:
    """The manifest at ``path``, its layout, names and seals checked (not its code)."""
    try:
        raw = read_regular(path, MANIFEST_LIMIT, path.parent)
    except (OSError, UnsafeFile) as exc:
        raise CorruptLedger(f"the ledger's manifest cannot be read ({exc}); {_RESTORE}") from None
    try:
        data = json.loads(raw)
        if data["format"] != LEDGER_FORMAT or data["store_format"] != kinds.FORMAT_VERSION:
            raise StaleLedger(
                f"the ledger in {path.parent} has format {data['format']}/"
                f"{data['store_format']}, this package reads {LEDGER_FORMAT}/"
                f"{kinds.FORMAT_VERSION}; "
                + (
                    f"upgrade it once: python tools/upgrade_ledger.py {path.parent}"
                    if data["format"] == LEDGER_FORMAT - 1
                    else f"recompute it: {_RECOMPUTE}"
                )
            )
        _check_names(data)
        data["index"] = {_index(r["config"], r["seed"]): k for k, r in data["runs"].items()}
        seals = data["seals"]
        _check_derived_names(data.get("derived", {}))
        found = seals_of(data)
    except (ValueError, KeyError, TypeError, AttributeError, AssertionError) as exc:
        raise CorruptLedger(f"{path} is not a ledger manifest ({exc!r:.300}); {_RESTORE}") from None
    broken = sorted(n for n in set(seals) | set(found) if seals.get(n) != found.get(n))
    if broken:
        raise CorruptLedger(
            f"{path}: the files, digests or wall times of {', '.join(map(str, broken))[:200]} "
            f"do not match their seal (the manifest or a table was edited); {_RESTORE}"
        )
    data["folder"] = path.parent
    return data


def _check_names(data: dict) -> None:
    """AssertionError unless every table and run of the manifest ``data`` is named as the
    ledger names them (plain table names, run keys of their seeds, each whole run in its own
    file), its seed and wall times are numbers; replaces each record's configuration reference
    by the configuration."""
    for name, sha256 in data["tables"].items():
        assert isinstance(name, str) and NAME_PATTERN.fullmatch(name), f"table name {name!r:.80}"
        assert isinstance(sha256, str) and len(sha256) == 64, f"table {name}: its digest"
    for key, record in data["runs"].items():
        record["config"] = data["configs"][record["config"]]
        seed, walls = record["seed"], [record[f"wall_time_{p}"] for p in ("train", "test")]
        assert isinstance(key, str) and KEY_PATTERN.fullmatch(key), f"run key {key!r:.80}"
        assert isinstance(seed, int) and key.endswith(f":seed{seed}"), (
            f"run {key[:16]}: seed {seed!r}"
        )
        assert record["name"] in data["tables"], f"run {key[:16]}: no table {record['name']!r}"
        assert record["runner"] in data["fingerprints"], f"run {key[:16]}: its runner"
        assert all(np.isfinite(w) and w >= 0 for w in walls), f"run {key[:16]}: {walls}"
        own = f"whole/{record['name']}/{key[:16]}/seed{seed}.npz"
        assert record.get("whole") in (None, own), f"run {key[:16]}: not its own file"


def _check_derived_names(derived) -> None:
    """AssertionError unless the manifest's ``derived`` is ``{plain name: SHA-256}``."""
    assert isinstance(derived, dict), "derived: not a mapping"
    for name, sha256 in derived.items():
        assert isinstance(name, str) and NAME_PATTERN.fullmatch(name), f"derived {name!r:.80}"
        assert isinstance(sha256, str) and len(sha256) == 64, f"derived {name}: its digest"


def _index(config: dict, seed: int) -> str:
    return f"{json.dumps(config, sort_keys=True)}:seed{seed}"


def _seals(runs: dict, tables: dict | None = None, migrations=None, derived=None) -> dict[str, str]:
    """``{table: its seal}`` of the run records ``runs`` (``{key: record}``) and the tables'
    digests ``tables`` (``{table: SHA-256 of its file}``): the SHA-256 of the table's digest
    and of the :data:`SEALED` fields of its runs, in the order of their keys; with
    ``migrations`` (the manifest's), their seal under :data:`MIGRATIONS_SEAL`; with
    ``derived`` (``{name: SHA-256 of its file}``), theirs under :data:`DERIVED_SEAL`."""
    rows: dict[str, list] = {}
    for key in sorted(runs):
        record = runs[key]
        fields = [record.get(f) for f in SEALED]
        fields += [record[f] for f in SEALED_IF_PRESENT if f in record]
        rows.setdefault(str(record["name"]), []).append([key, *fields])
    seals = {
        name: _sha256_json([(tables or {}).get(name), found])
        for name, found in sorted(rows.items())
    }
    for name in set(tables or ()) - set(seals):  # a table of no run
        seals[name] = _sha256_json([tables[name], []])
    if migrations:
        seals[MIGRATIONS_SEAL] = _sha256_json(migrations)
    if derived:
        seals[DERIVED_SEAL] = _sha256_json(derived)
    return dict(sorted(seals.items()))


def seals_of(data: dict) -> dict[str, str]:
    """The seals of the manifest ``data`` as written (:func:`_seals` of its runs, tables,
    migrations and derived tables): what :func:`update` writes, and what a forger recomputes
    after an edit (a seal refuses an edit, not a forgery: ``verify`` recomputes)."""
    return _seals(data["runs"], data["tables"], data.get("migrations", []), data.get("derived", {}))


def _sha256_json(value) -> str:
    return hashlib.sha256(json.dumps(value, allow_nan=False, sort_keys=True).encode()).hexdigest()


#: The optional dependencies of each kind of run (:data:`docking.study.kinds.EXTRAS`).
EXTRAS = kinds.EXTRAS
missing_extra = kinds.missing_extra


def _only_libraries_absent(data: dict, runner: kinds.Runner) -> bool:
    """Whether ``runner``'s code is the code that computed the ledger's runs and only
    libraries that are not installed here (its extra's) differ from the ledger's record."""
    ours, theirs = runner.module_digests(), data["modules"].get(runner.name, {})
    differ = {k for k in set(ours) | set(theirs) if ours.get(k) != theirs.get(k)}
    return all(k.startswith("library ") and ours.get(k) == "absent" for k in differ)


def _served_source(data: dict, runner: kinds.Runner) -> str | None:
    """The fingerprint to key ``runner``'s runs by when reading the ledger: None (this
    process's) normally; the ledger's own where the runner's extra is not installed and only
    its absent libraries differ (the runs are read as published, never computed here)."""
    if kinds.missing_extra(runner.name) is not None and _only_libraries_absent(data, runner):
        return data["fingerprints"][runner.name]
    return None


def _check(data: dict, runner: kinds.Runner) -> None:
    """:class:`StaleLedger` unless ``runner``'s runs were computed by this code (first, if
    the extra its runs need is not installed, saying so); a warning (once) if by another
    rendering stack."""
    if _served_source(data, runner) is not None:
        return  # read as published; computing one needs the extra (kinds.MissingExtra)
    if data["fingerprints"].get(runner.name) != runner.fingerprint():
        ours, theirs = runner.module_digests(), data["modules"].get(runner.name, {})
        changed = sorted(k for k in set(ours) | set(theirs) if ours.get(k) != theirs.get(k))
        raise StaleLedger(
            f"the ledger in {data['folder']} holds {runner.name} runs computed by other code "
            f"(changed: {', '.join(changed) or 'the fingerprint'}); they are not used. If "
            f"the change computes the same numbers, python -m docking ledger migrate "
            f"re-keys them after recomputing a sample; else recompute them: {_RECOMPUTE}"
        )
    if data["rendering_stack"] != kinds.rendering_stack() and not data.get("warned"):
        data["warned"] = True
        warnings.warn(
            f"the ledger's runs were rendered by {data['rendering_stack']!r}, this machine by "
            f"{kinds.rendering_stack()!r}; `python -m docking verify` shows whether they agree",
            RuntimeWarning,
            stacklevel=3,
        )


def timings(folder: Path | None = None) -> dict | None:
    """The record of ``tools/time_tiers.py`` in the ledger's folder (None if there is none)."""
    path = Path(folder or paths.ledger_dir() or ".") / TIMINGS_FILE
    return json.loads(path.read_text()) if path.is_file() else None


def size_bytes(folder: Path | None = None) -> int:
    """The bytes of every file of the ledger in ``folder`` (default :func:`paths.ledger_dir`)."""
    return sum(
        p.stat().st_size for p in Path(folder or paths.ledger_dir()).rglob("*") if p.is_file()
    )


def _find(config, seed: int) -> tuple[dict, str] | None:
    kinds.runner_for(config)  # TypeError for what is no run's configuration
    data = _stored_manifest(paths.ledger_dir())
    key = (
        data["index"].get(f"{kinds.config_json(config, compact=False)}:seed{seed}")
        if data
        else None
    )
    return None if key is None else (data, key)


def holds(config, seed: int, check: bool = False) -> bool:
    """Whether the ledger holds the run of (``config``, ``seed``); with ``check``,
    :class:`StaleLedger` if it does but its runner's code is not this code."""
    found = _find(config, seed)
    if found is not None and check:
        _check(found[0], kinds.runner_for(config))
    return found is not None


def _verified(path: Path, sha256: str, folder: Path | None = None) -> bytes:
    """The bytes of the ledger file ``path``: a regular file of at most :data:`FILE_LIMIT`
    bytes inside the ledger's ``folder`` (default: the folder two levels up, the ledger's for
    a table), checked against its manifest digest."""
    folder = path.parent.parent if folder is None else folder
    try:
        raw = read_regular(path, FILE_LIMIT, folder)
    except (OSError, UnsafeFile) as exc:
        raise CorruptLedger(f"the ledger file {path} cannot be read ({exc}); {_RESTORE}") from None
    if hashlib.sha256(raw).hexdigest() != sha256:
        raise CorruptLedger(f"the ledger file {path} does not match its digest; {_RESTORE}")
    return raw


@functools.lru_cache(maxsize=8)
def _table(path: Path, sha256: str) -> dict[str, np.ndarray]:
    """The columns of the results table ``path`` (checked against ``sha256``)."""
    raw = _verified(path, sha256)
    if not zipfile.is_zipfile(io.BytesIO(raw)):  # np.load would call it pickled data
        raise CorruptLedger(f"the ledger table {path} is not an .npz (zip) file; {_RESTORE}")
    try:
        table = ledger_rows.table_bytes(raw)
        keys = table["key"].tolist()
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
        raise CorruptLedger(
            f"the ledger table {path} is not readable ({exc}); {_RESTORE}"
        ) from None
    if len(set(keys)) != len(keys):
        raise CorruptLedger(f"the ledger table {path} holds a run twice; {_RESTORE}")
    return table


@functools.lru_cache(maxsize=8)
def _row_index(path: Path, sha256: str) -> dict[str, int]:
    """``{run key: its row}`` of the results table ``path`` (:func:`_table`, which holds
    each key once)."""
    return {key: row for row, key in enumerate(_table(path, sha256)["key"].tolist())}


def table_rows(data: dict, name: str) -> dict[str, dict[str, np.ndarray]]:
    """``{run key: its row's cells}`` of the results table ``name`` of the ledger whose
    manifest is ``data`` (the file checked against its digest, each row against its
    record's row digest: :class:`CorruptLedger` naming the first that differs)."""
    path = data["folder"] / "tables" / f"{name}.npz"
    rows = dict(ledger_rows.rows(_table(path, data["tables"][name])))
    named = {k for k, r in data["runs"].items() if r["name"] == name}
    if set(rows) != named:
        raise CorruptLedger(
            f"the ledger table {path} does not hold the runs the manifest names of it "
            f"({len(rows)} in the table, {len(named)} named); {_RESTORE}"
        )
    for key, cells in rows.items():
        if ledger_rows.row_digest(cells) != data["runs"][key]["row"]:
            raise CorruptLedger(
                f"the ledger table {path}: the row of {name!r} seed {data['runs'][key]['seed']} "
                f"is not the row its record names (row digest); {_RESTORE}"
            )
    return rows


def _served_row(data: dict, name: str, key: str) -> dict[str, np.ndarray]:
    """The row of run ``key`` of table ``name``, checked against its record's row digest."""
    path = data["folder"] / "tables" / f"{name}.npz"
    table = _table(path, data["tables"][name])
    row = _row_index(path, data["tables"][name]).get(key)
    if row is None:
        raise CorruptLedger(
            f"the ledger table {path} does not hold the run of {name!r} seed "
            f"{data['runs'][key]['seed']} that the manifest names; {_RESTORE}"
        )
    got = {n: ledger_rows.cell(table, n, row) for n in table if n + ".count" in table}
    got = {n: a for n, a in got.items() if a is not None}
    if ledger_rows.row_digest(got) != data["runs"][key]["row"]:
        raise CorruptLedger(
            f"the ledger table {path}: the row of {name!r} seed {data['runs'][key]['seed']} "
            f"is not the row its record names (row digest); {_RESTORE}"
        )
    return got


def read(config, seed: int, key: str | None = None):
    """The run of (``config``, ``seed``) as the ledger holds it (whole, or from its results
    table, its row checked against its record), or None if it holds none.
    :class:`StaleLedger` if it holds it but was computed by other code. (The store is asked
    first, by :func:`docking.study.runs.locate`, which passes the run's ``key`` under this
    code and rendering stack, so that it is not computed twice.)"""
    found = _find(config, seed)
    if found is None:
        return None
    (data, held), runner = found, kinds.runner_for(config)
    _check(data, runner)
    record = data["runs"][held]
    source = _served_source(data, runner)
    if key is None or data["rendering_stack"] != kinds.rendering_stack() or source is not None:
        key = kinds.run_key(config, seed, render=data["rendering_stack"], source=source)
    if held != key:
        raise StaleLedger(f"the ledger's key of {config.name!r} seed {seed} is not this code's")
    if record.get("whole"):
        whole = data["folder"] / record["whole"]
        raw = _verified(whole, record["sha256"], data["folder"])
        try:
            result = kinds.load_result(whole, key, within=data["folder"])
        except kinds.CorruptResult as exc:
            raise CorruptLedger(f"the ledger file {record['whole']}: {exc}; {_RESTORE}") from None
        _check_content(raw, record, whole)
        return result
    got = _served_row(data, config.name, key)
    return _from_row(
        config, seed, runner, got, (record["wall_time_train"], record["wall_time_test"])
    )


def _from_row(config, seed: int, runner: kinds.Runner, got: dict, walls) -> object:
    """The run of (``config``, ``seed``) read from its table row ``got``, by its kind's
    :attr:`~docking.study.kinds.Runner.from_table`."""
    logs = {p: ledger_rows.log(got, p, f"{config.name!r} seed {seed}") for p in ledger_rows.PARTS}
    return runner.from_table(config, seed, got, logs, walls)


def _check_content(raw: bytes, record: dict, path: Path) -> None:
    """:class:`CorruptLedger` unless the arrays of the whole run ``raw`` (a ledger file's
    bytes) have the content digest its ``record`` says."""
    with np.load(io.BytesIO(raw), allow_pickle=False) as arrays:
        digest = kinds.content_digest(arrays)
    if digest != record["digest"]:
        raise CorruptLedger(
            f"the manifest's content digest of {path} is not its arrays' digest; {_RESTORE}"
        )


def check_files(folder: Path | str | None = None) -> dict[str, int] | None:
    """Check the ledger in ``folder`` (default :func:`paths.ledger_dir`) as a whole: its
    manifest (format, names, this code, the seals), every results table and whole run
    against its SHA-256, every table's rows against its runs' records (the runs it names and
    each row's digest), each whole run's arrays against its content digest, and each run's
    key against the key of its configuration and seed under this code.
    :class:`CorruptLedger` (or :class:`StaleLedger`) naming the first that fails; None if
    there is no manifest; else what was checked: ``{"runs", "tables", "whole", "derived"}``
    counts (``derived``: the derived tables, each against its sealed SHA-256)."""
    data = manifest(Path(folder) if folder is not None else paths.ledger_dir())
    if data is None:
        return None
    for name in sorted(data["tables"]):
        table_rows(data, name)
    for name in sorted(data.get("derived", {})):
        derived_table(data, name)
    whole = [r for r in data["runs"].values() if r.get("whole")]
    for record in whole:
        path = data["folder"] / record["whole"]
        _check_content(_verified(path, record["sha256"], data["folder"]), record, path)
    _check_keys(data)
    counts = {"runs": len(data["runs"]), "tables": len(data["tables"]), "whole": len(whole)}
    return {**counts, "derived": len(data.get("derived", {}))}


def _check_keys(data: dict) -> None:
    """:class:`CorruptLedger` unless every run's key is the key of its record's configuration
    and seed under this code and the ledger's rendering stack (a record moved to another
    run's key is caught here, without recomputing)."""
    keys: dict[str, str] = {}
    for key, record in data["runs"].items():
        runner = kinds.runner_named(record["runner"])
        text = json.dumps(record["config"], sort_keys=True)
        if text not in keys:
            keys[text] = kinds.config_key(
                runner.from_dict(record["config"]),
                data["rendering_stack"],
                source=_served_source(data, runner),
            )
        if key != f"{keys[text]}:seed{record['seed']}":
            raise CorruptLedger(
                f"the ledger's run {key[:16]}... of {record['name']!r} seed {record['seed']}: its "
                f"key is not the key of its configuration and seed; {_RESTORE}"
            )


#: The results tables that several designs' runs share
#: (:func:`docking.study.design.yardstick_config` names its runs so): :func:`update` with ``only``
#: adds a design's new runs of them to the ledger's table, keeping its rows, instead of refusing to
#: replace it whole.
SHARED_TABLES = frozenset({"yardsticks"})


def update(runs, folder: Path | str | None = None, results_dir=None, only=None, rules=None) -> dict:
    """Write the ledger of ``runs`` (``(config, seed, whole, keep)`` each: keep the stored
    file whole; what the table keeps) from the results store, replacing the ledger's files;
    returns the manifest.

    ``only``: the names of the tables ``runs`` replace (or add); every other table of the
    ledger in ``folder``, its runs, configurations and whole runs, is kept as it is, after
    checking it against its manifest and this code (:class:`StaleLedger` otherwise). So one
    design's runs enter the ledger without the results store holding every other's.

    A run of a table outside ``only`` is refused, unless the table is one that designs
    share (:data:`SHARED_TABLES`) and the ledger holds it: then the run is added to its rows
    (one the table holds already is left as it is).

    ``rules``: ``{table name: the SHA-256 of its design's rules}``
    (:func:`docking.study.designs.rules_digest`), recorded (and sealed) with each of its runs
    computed here, so that the ledger shows which rules each run was judged by."""
    from docking.study.platform_info import numeric_platform

    folder = Path(folder) if folder is not None else paths.ledger_dir()
    if folder is None:
        raise ValueError("no ledger folder: DOCKING_LEDGER is off and no folder was given")
    records, files, tables, runners, configs, kept = {}, {}, {}, {}, {}, {}
    if only is not None:
        kept, tables = _kept_and_shared(folder, only, runs)
        records, files, configs = kept["runs"], kept["files"], kept["configs"]
        runners = {name: kinds.runner_named(name) for name in kept["runners"]}
    for config, seed, whole, keep in runs:
        if only is not None and config.name not in only and kinds.run_key(config, seed) in records:
            continue  # a shared table's run the ledger holds already
        key, arrays, record = _record(config, seed, results_dir)
        runner = runners.setdefault(kinds.runner_for(config).name, kinds.runner_for(config))
        configs[record["config"]] = config.to_dict()
        records[key] = {"runner": runner.name, **record}
        if rules and rules.get(config.name):
            records[key]["rules_sha256"] = rules[config.name]
        if whole:
            records[key]["whole"] = name = f"whole/{config.name}/{key[:16]}/seed{seed}.npz"
            files[name] = ledger_rows.npz(arrays)
            records[key]["sha256"] = hashlib.sha256(files[name]).hexdigest()
        tables.setdefault(config.name, []).append((key, ledger_rows.row(arrays, frozenset(keep))))
    for name, found in tables.items():
        files[f"tables/{name}.npz"] = ledger_rows.npz(
            ledger_rows.columns(sorted(found, key=lambda r: r[0]))
        )
        for key, cells in ledger_rows.rows(ledger_rows.table_bytes(files[f"tables/{name}.npz"])):
            records[key]["row"] = ledger_rows.row_digest(cells)  # what the table serves of the run
    platform = kept["platform"] if only is not None else numeric_platform()
    migrations = kept["migrations"] if only is not None else _migrations_of(folder)
    data = _manifest(files, records, runners, configs, platform, migrations, _derived_of(folder))
    if only is not None:
        platforms = _table_platforms(kept, only, tables, numeric_platform())
        if platforms:
            data["table_platforms"] = platforms
    _replace_files(folder, files)
    text = json.dumps(data, indent=1, sort_keys=True) + "\n"
    atomic_write(folder / "manifest.json", lambda f: f.write(text.encode()))
    _read_manifest.cache_clear()
    return manifest(folder)


def _kept_and_shared(folder: Path, only, runs) -> tuple[dict, dict]:
    """What :func:`update` with ``only`` keeps of the ledger in ``folder`` (:func:`_kept`,
    the shared tables it extends taken out of its files) and the rows of each shared table
    that ``runs`` add to; ValueError for runs of a table it would replace whole."""
    kept = _kept(folder, frozenset(only))
    # a run of another table that the ledger holds already (a design reading an earlier
    # design's runs under their own names) is left as it is, not written again
    held = kept["runs"]
    outside = sorted(
        {c.name for c, s, *_ in runs if c.name not in only and kinds.run_key(c, s) not in held}
    )
    if set(outside) - SHARED_TABLES or not {f"tables/{n}.npz" for n in outside} <= set(
        kept["files"]
    ):
        raise ValueError(
            f"runs of the tables {', '.join(outside)} would replace those tables whole: "
            f"name them too, or write the whole ledger"
        )
    # a table designs share: extended, its rows kept as they are
    tables = {
        n: ledger_rows.rows(ledger_rows.table_bytes(kept["files"].pop(f"tables/{n}.npz")))
        for n in outside
    }
    return kept, tables


def _table_platforms(kept: dict, only, tables, here: dict) -> dict:
    """Where each table's runs were computed, as :func:`update` with ``only`` records it:
    the kept tables' as they were, the written tables' ``here``, and an extended shared
    table's every platform its runs came from (a list where there are several)."""
    platforms = {n: p for n, p in kept["platforms"].items() if n not in only}
    for n in tables:
        before = platforms.get(n, kept["platform"]) if n not in only else here
        before = before if isinstance(before, list) else [before]
        found = before if here in before else [*before, here]
        platforms[n] = found[0] if len(found) == 1 else found
    return dict(sorted(platforms.items()))


def _derived_of(folder: Path) -> dict:
    """The derived tables of the ledger in ``folder`` (``{name: SHA-256}``), each file checked
    against its digest; none if it has no readable manifest."""
    try:
        data = _stored_manifest(folder)
    except StaleLedger:
        return {}
    derived = dict(data.get("derived", {})) if data else {}
    for name, sha256 in derived.items():
        _verified(folder / "derived" / f"{name}.npz", sha256, folder)
    return derived


def derived_table(data: dict, name: str) -> tuple[dict[str, int], dict[str, np.ndarray]] | None:
    """The derived table ``name`` of the ledger whose manifest is ``data`` (its file checked
    against its sealed digest): ``({whole key: row}, {array name: its rows stacked})``, or
    None if the ledger has none of that name."""
    sha256 = data.get("derived", {}).get(name)
    if sha256 is None:
        return None
    path = data["folder"] / "derived" / f"{name}.npz"
    table = _table(path, sha256)
    if "key" not in table:
        raise CorruptLedger(f"the derived table {path} holds no keys; {_RESTORE}")
    return _row_index(path, sha256), table


def write_derived(folder: Path | str, name: str, entries: dict[str, dict]) -> dict:
    """Write the derived table ``name`` (``entries``: ``{whole key: arrays}``, every entry the
    same array names and shapes) into the ledger in ``folder``, replacing one of that name,
    and seal it in the manifest (written atomically); returns the manifest."""
    folder = Path(folder)
    check_name("write_derived", "name", name)
    data = manifest(folder)
    if data is None:
        raise ValueError(f"no ledger in {folder} to add to (it has no manifest.json)")
    keys = sorted(entries)
    if not keys:
        raise ValueError(f"derived {name!r}: no entries to write")
    fields = sorted(entries[keys[0]])
    for key in keys:
        if sorted(entries[key]) != fields or "key" in fields:
            raise ValueError(f"derived {name!r}: entries differ in their arrays ({fields})")
    columns = {"key": np.array(keys)}
    columns.update({f: np.stack([np.asarray(entries[k][f]) for k in keys]) for f in fields})
    raw = ledger_rows.npz(columns)
    atomic_write(folder / "derived" / f"{name}.npz", lambda f: f.write(raw))
    text = json.loads((folder / "manifest.json").read_text())
    text["derived"] = {**text.get("derived", {}), name: hashlib.sha256(raw).hexdigest()}
    text["seals"] = seals_of(text)
    out = json.dumps(text, indent=1, sort_keys=True) + "\n"
    atomic_write(folder / "manifest.json", lambda f: f.write(out.encode()))
    _read_manifest.cache_clear()
    return manifest(folder)


def _migrations_of(folder: Path) -> list:
    """The migrations recorded by the ledger in ``folder`` (none if it has no readable
    manifest): a ledger written anew keeps the history of its runs' keys."""
    try:
        data = _stored_manifest(folder)
    except StaleLedger:
        return []
    return list(data.get("migrations", [])) if data else []


def _manifest(
    files: dict,
    records: dict,
    runners: dict,
    configs: dict,
    platform: dict,
    migrations: list = (),
    derived: dict | None = None,
) -> dict:
    """The manifest of a ledger's ``files`` (its tables among them) and run ``records``, the
    runs computed by ``runners`` from ``configs`` on ``platform`` (the ledger's), with the
    ``migrations`` its runs' keys went through and its ``derived`` tables (kept as they are:
    an entry whose key names no run of the ledger is never asked for)."""
    table_names = {p[len("tables/") : -len(".npz")] for p in files if p.startswith("tables/")}
    tables = {n: hashlib.sha256(files[f"tables/{n}.npz"]).hexdigest() for n in sorted(table_names)}
    found = {
        "format": LEDGER_FORMAT,
        "store_format": kinds.FORMAT_VERSION,
        "fingerprints": {name: r.fingerprint() for name, r in runners.items()},
        "modules": {name: r.module_digests() for name, r in runners.items()},
        "rendering_stack": kinds.rendering_stack(),
        "platform": platform,
        "configs": configs,
        "tables": tables,
        "runs": records,
        "seals": _seals(records, tables, list(migrations), derived),
    }
    if migrations:
        found["migrations"] = list(migrations)
    if derived:
        found["derived"] = dict(derived)
    return found


def _config_ref(config: dict) -> str:
    """How a run's record names its configuration (``config``, JSON-ready) in the manifest's
    ``configs``."""
    return hashlib.sha256(json.dumps(config, sort_keys=True).encode()).hexdigest()[:16]


def _record(config, seed: int, results_dir) -> tuple[str, dict, dict]:
    """A stored run as the ledger takes it: its key, its arrays (the file checked against the
    key and its content digest) and its record, but for its runner's name."""
    key, path = kinds.run_key(config, seed), kinds.result_path(config, seed, results_dir)
    result = kinds.load_result(path, key)  # checks the file against the key and digest
    with np.load(path, allow_pickle=False) as stored:
        arrays = {k: stored[k] for k in stored.files}
    computed = json.loads(str(arrays["meta"])).get("computed_utc")
    walls = float(result.wall_time_train), float(result.wall_time_test)
    record = {
        "name": config.name,
        "seed": seed,
        "config": _config_ref(config.to_dict()),
        "digest": kinds.content_digest(arrays),
        "wall_time_train": walls[0],
        "wall_time_test": walls[1],
        "wall_seconds": round(sum(walls), 1),
    }
    if computed is not None:  # runs stored before the time was recorded have none
        record["computed_utc"] = computed
    return key, arrays, record


def _kept(folder: Path, replaced: frozenset) -> dict:
    """What :func:`update` with ``only=replaced`` keeps of the ledger in ``folder``: the
    records, configurations and files (bytes, checked against the manifest) of every table
    not in ``replaced``, and the runners that computed them."""
    data = manifest(folder)  # StaleLedger if another code computed it
    if data is None:
        raise ValueError(f"no ledger in {folder} to add to (it has no manifest.json)")
    runs, files, configs, runners = {}, {}, {}, set()
    for name, sha256 in data["tables"].items():
        if name not in replaced:
            files[f"tables/{name}.npz"] = _verified(
                folder / "tables" / f"{name}.npz", sha256, folder
            )
    refs = {json.dumps(c, sort_keys=True): ref for ref, c in data["configs"].items()}
    for key, record in data["runs"].items():
        if record["name"] in replaced:
            continue
        kept = {k: v for k, v in record.items()}
        ref = refs[json.dumps(record["config"], sort_keys=True)]
        kept["config"], configs[ref] = ref, record["config"]
        if "whole" in record:
            files[record["whole"]] = _verified(folder / record["whole"], record["sha256"], folder)
        runs[key] = kept
        runners.add(record["runner"])
    platform, platforms = data["platform"], data.get("table_platforms", {})
    return dict(
        migrations=list(data.get("migrations", [])),
        runs=runs,
        files=files,
        configs=configs,
        runners=runners,
        platform=platform,
        platforms={n: p for n, p in platforms.items() if n not in replaced},
    )


def _replace_files(folder: Path, files: dict[str, bytes]) -> None:
    """Write ``files`` (``{path in folder: bytes}``), each atomically and only if it changed,
    and delete the tables and whole runs the ledger no longer holds (and emptied folders)."""
    old = {p for kind in ("tables", "whole") for p in [folder / kind, *folder.glob(f"{kind}/**/*")]}
    for relative, raw in files.items():
        old.discard(folder / relative)
        if not _holds(folder / relative, raw):
            atomic_write(folder / relative, lambda f, raw=raw: f.write(raw))
    for stale in sorted(old, reverse=True):  # a folder's files before the folder
        if stale.is_file():
            stale.unlink()
        elif stale.is_dir() and not any(stale.iterdir()):
            stale.rmdir()


def _holds(path: Path, raw: bytes) -> bool:
    """Whether ``path`` is a regular file holding ``raw`` (anything else is replaced)."""
    try:
        return read_regular(path, len(raw), path.parent) == raw
    except (OSError, UnsafeFile):
        return False
