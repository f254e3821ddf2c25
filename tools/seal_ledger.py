"""Seal a ledger written before its runs' digests and wall times were sealed (issue 41).

The manifest's per-table seals (:data:`docking.ledger.SEALED`, :func:`docking.ledger._seals`)
cover what no file of the ledger holds: each run's content digest and wall times. A ledger
written by ``python -m docking ledger update`` carries them; this adds them to an older one,
once its history shows it unedited (``git log -p ledger/manifest.json``): it checks every
table and whole run against its SHA-256 and this code's fingerprints first, then writes the
manifest again with the seals added and nothing else changed. Usage::

    .venv/bin/python tools/seal_ledger.py [FOLDER]   # default: the checkout's ledger/
"""

from __future__ import annotations

import json
import shutil
import sys
import tempfile
from pathlib import Path

from docking import ledger, paths
from docking.fileio import atomic_write


def seal(folder: Path) -> dict[str, str]:
    """Add the seals to the manifest in ``folder``; the seals."""
    path = folder / "manifest.json"
    raw = json.loads(path.read_text())
    if "seals" in raw:
        raise SystemExit(f"{path} is sealed already")
    seals = ledger._seals(raw["runs"])
    sealed = {**raw, "seals": seals}
    with tempfile.TemporaryDirectory(prefix="docking-seal-") as scratch:
        check = Path(scratch) / "ledger"  # the ledger as it will be, checked first
        shutil.copytree(folder, check)
        (check / "manifest.json").write_text(json.dumps(sealed, indent=1, sort_keys=True) + "\n")
        ledger._read_manifest.cache_clear()
        ledger.check_files(check)  # every file, this code, the seals
    ledger._read_manifest.cache_clear()
    text = json.dumps(sealed, indent=1, sort_keys=True) + "\n"
    atomic_write(path, lambda f: f.write(text.encode()))
    return seals


def main() -> int:
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else paths.ledger_dir()
    if folder is None:
        raise SystemExit("no ledger folder: name one")
    seals = seal(folder.resolve())
    print(f"{folder}: sealed the runs of {len(seals)} tables ({', '.join(seals)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
