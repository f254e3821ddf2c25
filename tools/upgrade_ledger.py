"""Upgrade a ledger of format 7 to format 8 (issue 49), once, without recomputing a run.

Format 8 adds to every run's record its *row digest* (the digest of the arrays its results
table serves of it, :func:`docking.study.ledger_rows.row_digest`), and seals each table's file
digest with its runs' records (:func:`docking.study.ledger._seals`), so that a table rewritten
and named anew in the manifest is refused unless the manifest is resealed. This reads a format-7
manifest, checks it as format 7 did (every table and whole run against its SHA-256, the
format-7 seals of the runs' digests and wall times), computes each row digest from the table
as committed, and writes the manifest again with the rows, the new seals and format 8;
nothing else changes. Run it only on a ledger whose history shows it unedited (``git log -p
ledger/``): it seals what it finds. Usage::

    .venv/bin/python tools/upgrade_ledger.py [FOLDER]   # default: the checkout's ledger/
"""

from __future__ import annotations

import hashlib
import json
import shutil
import sys
import tempfile
from pathlib import Path

from docking.fileio import atomic_write
from docking.study import ledger, ledger_rows, paths

#: Format 7's sealed fields (its seal: the SHA-256 of these per run, in key order, per table).
SEALED_7 = ("digest", "wall_time_train", "wall_time_test", "wall_seconds", "computed_utc")


def _seals_7(runs: dict) -> dict[str, str]:
    rows: dict[str, list] = {}
    for key in sorted(runs):
        record = runs[key]
        fields = [record.get(f) for f in SEALED_7]
        fields += [record["rules_sha256"]] if "rules_sha256" in record else []
        rows.setdefault(str(record["name"]), []).append([key, *fields])
    return {
        name: hashlib.sha256(json.dumps(found, allow_nan=False).encode()).hexdigest()
        for name, found in sorted(rows.items())
    }


def upgraded(folder: Path) -> dict:
    """The format-8 manifest of the format-7 ledger in ``folder`` (checked as format 7)."""
    raw = json.loads((folder / "manifest.json").read_text())
    if raw.get("format") != 7:
        raise SystemExit(f"{folder} has format {raw.get('format')}, not 7: nothing to upgrade")
    if raw.get("seals") != _seals_7(raw["runs"]):
        raise SystemExit(f"{folder}: the runs do not match their format-7 seals; not upgraded")
    for name, sha256 in raw["tables"].items():
        path = folder / "tables" / f"{name}.npz"
        table = ledger_rows.table_bytes(ledger._verified(path, sha256, folder))
        for key, cells in ledger_rows.rows(table):
            raw["runs"][key]["row"] = ledger_rows.row_digest(cells)
    for key, record in raw["runs"].items():
        if "row" not in record:
            raise SystemExit(f"run {key[:16]} of {record['name']} is in no table; not upgraded")
        if record.get("whole"):
            ledger._verified(folder / record["whole"], record["sha256"], folder)
    raw["format"] = ledger.LEDGER_FORMAT
    raw["seals"] = ledger._seals(raw["runs"], raw["tables"], raw.get("migrations", []))
    return raw


def upgrade(folder: Path) -> dict:
    """Upgrade the ledger in ``folder`` in place, checked as format 8 first; its manifest."""
    data = upgraded(folder)
    text = json.dumps(data, indent=1, sort_keys=True) + "\n"
    with tempfile.TemporaryDirectory(prefix="docking-upgrade-") as scratch:
        check = Path(scratch) / "ledger"  # the ledger as it will be, checked first
        shutil.copytree(folder, check)
        (check / "manifest.json").write_text(text)
        ledger._read_manifest.cache_clear()
        ledger.check_files(check)  # every file, every row, every key, the seals
    ledger._read_manifest.cache_clear()
    atomic_write(folder / "manifest.json", lambda f: f.write(text.encode()))
    return data


def main() -> int:
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else paths.ledger_dir()
    if folder is None:
        raise SystemExit("no ledger folder: name one")
    data = upgrade(folder.resolve())
    print(
        f"{folder}: format 8, {len(data['runs'])} runs' rows sealed in {len(data['tables'])} tables"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
