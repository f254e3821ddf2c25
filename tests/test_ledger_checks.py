"""The ledger's checks say what they checked (issue 41): a run's digest and wall times in the
manifest are sealed, a whole run's digest is compared with its arrays, ``ledger show`` checks
every file it summarises, and ``run`` names a ledger it cannot use before it computes. Each
test builds its own tiny store and ledger."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import SEEDS, TINY, tool

from docking.presets import EXPERIMENT_1
from docking.study import ledger, ledger_rows, verify
from docking.study.cli import main
from docking.study.cli.ledger import _verify_plan
from docking.study.kinds import result_path, run_key
from docking.study.runs import load_run
from docking.study.store import run_or_load

REPO = Path(__file__).resolve().parent.parent
#: What ``run experiment1`` with these options computes: :data:`SMALL`.
SMALL_ARGS = ["--train-trials", "4", "--test-trials", "3", "--eval-every", "2"]
SMALL_ARGS += ["--eval-trials", "2", "--processes", "1"]
SMALL = dataclasses.replace(
    EXPERIMENT_1, train_trials=4, test_trials=3, eval_every=2, eval_trials=2
)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A ledger of tiny runs: seed 0 whole, seed 1 in its table only; and SMALL seed 0 (what
    ``run experiment1 --seeds 0`` with SMALL_ARGS asks for) in its table."""
    base = tmp_path_factory.mktemp("checked-ledger")
    results, folder = base / "results", base / "ledger"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        for s in SEEDS:
            run_or_load(TINY, s, results, progress=False)
        run_or_load(SMALL, 0, results, progress=False)
    runs = [(TINY, 0, True, frozenset()), (TINY, 1, False, frozenset())]
    ledger.update([*runs, (SMALL, 0, False, frozenset())], folder, results)
    return folder


@pytest.fixture
def copy(built, tmp_path, monkeypatch):
    """A copy of the tiny ledger that DOCKING_LEDGER names."""
    folder = tmp_path / "ledger"
    shutil.copytree(built, folder)
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    ledger._read_manifest.cache_clear()
    ledger._table.cache_clear()
    return folder


@pytest.fixture
def restore_sigterm():
    handler = signal.getsignal(signal.SIGTERM)
    yield
    signal.signal(signal.SIGTERM, handler)


def _edit(folder: Path, change, reseal: bool = False) -> None:
    """Edit the manifest in ``folder``; with ``reseal``, its seals follow the edit (a manifest
    consistent with itself, but not with the ledger's files)."""
    path = folder / "manifest.json"
    data = json.loads(path.read_text())
    change(data)
    if reseal:
        data["seals"] = ledger.seals_of(data)
    path.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    ledger._read_manifest.cache_clear()


def _record(data, seed, config=TINY):
    return data["runs"][run_key(config, seed)]


# A run's digest and wall times ---------------------------------------------------------------


@pytest.mark.parametrize("seed", SEEDS, ids=["whole", "table"])
@pytest.mark.parametrize(
    "field, value",
    [("digest", "0" * 64), ("wall_time_train", 91.43), ("wall_seconds", 0.0)],
)
def test_an_edited_digest_or_wall_time_is_refused(copy, seed, field, value):
    _edit(copy, lambda d: _record(d, seed).update({field: value}))
    with pytest.raises(ledger.CorruptLedger, match="tiny do not match their seal"):
        load_run(TINY, seed, "/nonexistent-store")


def test_a_whole_runs_digest_is_compared_with_its_arrays(copy):
    """Edited with its seal: the seal holds, the whole run's arrays do not."""
    _edit(copy, lambda d: _record(d, 0).update(digest="0" * 64), reseal=True)
    with pytest.raises(ledger.CorruptLedger, match="is not its arrays' digest"):
        load_run(TINY, 0, "/nonexistent-store")
    with pytest.raises(ledger.CorruptLedger, match="is not its arrays' digest"):
        ledger.check_files(copy)


def test_a_format_7_ledger_is_refused_and_the_tool_upgrades_it(copy):
    """Format 7 (no row digests, the tables' digests unsealed) is refused, naming the tool;
    the tool checks it as format 7 did and writes format 8 without recomputing a run."""
    upgrade = tool("upgrade_ledger")

    def as_7(data):
        for record in data["runs"].values():
            del record["row"]
        data["format"] = 7
        data["seals"] = upgrade._seals_7(data["runs"])

    _edit(copy, as_7)
    with pytest.raises(ledger.StaleLedger, match="tools/upgrade_ledger.py"):
        ledger.manifest(copy)
    out = subprocess.run(
        [sys.executable, str(REPO / "tools" / "upgrade_ledger.py"), str(copy)],
        env={**os.environ, "PYTHONPATH": str(REPO)},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    ledger._read_manifest.cache_clear()
    assert ledger.check_files(copy) == {"runs": 3, "tables": 2, "whole": 1, "derived": 0}
    assert load_run(TINY, 1, "/nonexistent-store").seed == 1


def test_the_upgrade_refuses_a_format_7_ledger_edited_after_its_seal(copy):
    upgrade = tool("upgrade_ledger")

    def as_7_edited(data):
        for record in data["runs"].values():
            del record["row"]
        data["format"] = 7
        data["seals"] = upgrade._seals_7(data["runs"])
        _record(data, 1)["wall_time_train"] = 1.0

    _edit(copy, as_7_edited)
    with pytest.raises(SystemExit, match="do not match their format-7 seals"):
        upgrade.upgrade(copy)


def test_wall_times_served_are_the_sealed_ones(copy, built):
    data = json.loads((built / "manifest.json").read_text())
    served = load_run(TINY, 1, "/nonexistent-store")
    assert served.wall_time_train == _record(data, 1)["wall_time_train"]


# ledger show checks what it summarises --------------------------------------------------------


def _flip(path: Path) -> None:
    raw = bytearray(path.read_bytes())
    raw[len(raw) // 2] ^= 0x01
    path.write_bytes(bytes(raw))


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


@pytest.mark.parametrize("damage", [_flip, _truncate, Path.unlink], ids=["flip", "cut", "gone"])
@pytest.mark.parametrize("which", ["table", "whole"])
def test_ledger_show_refuses_a_damaged_file(copy, damage, which, capsys, restore_sigterm):
    data = json.loads((copy / "manifest.json").read_text())
    path = copy / ("tables/tiny.npz" if which == "table" else _record(data, 0)["whole"])
    damage(path)
    assert main(["ledger", "show"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(path) in err, err


def test_ledger_show_refuses_a_table_that_holds_other_runs(copy, capsys, restore_sigterm):
    """A table of the other name's runs, with its digest: refused by its seal; resealed,
    every byte checks, its runs do not."""
    other = (copy / "tables" / "experiment1.npz").read_bytes()
    (copy / "tables" / "tiny.npz").write_bytes(other)

    def edit(data):
        data["tables"]["tiny"] = hashlib.sha256(other).hexdigest()

    _edit(copy, edit)
    assert main(["ledger", "show"]) == 1
    assert "tiny do not match their seal" in capsys.readouterr().err
    _edit(copy, lambda data: None, reseal=True)
    assert main(["ledger", "show"]) == 1
    assert "does not hold the runs the manifest names" in capsys.readouterr().err


# A forger's edits (issue 49): what each check catches ----------------------------------------


def _forge_table(folder: Path, seed: int, column: str, change) -> None:
    """Change ``column`` of run ``seed``'s row of the tiny table, rewrite the table and put its
    SHA-256 in the manifest (the issue's forgery; nothing else)."""
    path = folder / "tables" / "tiny.npz"
    with np.load(path) as found:
        table = {k: found[k] for k in found.files}
    row = table["key"].tolist().index(run_key(TINY, seed))
    start = int(np.sum(np.maximum(table[column + ".count"][:row], 0)))
    cells = table[column][start : start + table[column + ".count"][row]]
    table[column][start : start + len(cells)] = change(cells)
    path.write_bytes(ledger_rows.npz(table))

    def edit(data):
        data["tables"]["tiny"] = hashlib.sha256(path.read_bytes()).hexdigest()

    _edit(folder, edit)
    ledger._table.cache_clear()


def _reseal_rows(folder: Path) -> None:
    """What a forger who can run the package does next: every record's row digest taken from
    the forged table, and the seals recomputed."""

    def edit(data):
        rows = ledger_rows.rows(
            ledger_rows.table_bytes((folder / "tables" / "tiny.npz").read_bytes())
        )
        for key, cells in rows:
            data["runs"][key]["row"] = ledger_rows.row_digest(cells)

    _edit(folder, edit, reseal=True)


def test_a_forged_table_is_refused_by_ledger_show_until_resealed_then_verify_names_it(
    copy, capsys, restore_sigterm
):
    _forge_table(copy, 1, "test.success", lambda cells: ~cells)
    assert main(["ledger", "show"]) == 1  # the table's digest is sealed with its runs
    assert "tiny do not match their seal" in capsys.readouterr().err
    _edit(copy, lambda data: None, reseal=True)
    assert main(["ledger", "show"]) == 1  # the row is not the row its record names
    assert "the row of 'tiny' seed 1 is not the row its record names" in capsys.readouterr().err
    _reseal_rows(copy)
    assert main(["ledger", "show"]) == 0  # a consistent forgery: no digest can catch it
    capsys.readouterr()
    checks = verify.verify(tables=("tiny",), workers=1, progress=False, folder=copy)
    bad = [c for c in checks if not c.ok]
    assert [(c.seed, c.columns) for c in bad] == [(1, ("test.success",))]
    assert bad[0].digest == bad[0].ledger_digest  # the record's digest was never touched


def test_two_records_swapped_and_resealed_are_refused_by_ledger_show(copy, capsys, restore_sigterm):
    def swap(data):
        a, b = run_key(TINY, 0), run_key(TINY, 1)
        data["runs"][a], data["runs"][b] = data["runs"][b], data["runs"][a]

    _edit(copy, swap, reseal=True)
    assert main(["ledger", "show"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "seed" in err, err


def test_a_record_given_another_runs_configuration_is_refused_by_ledger_show(
    copy, capsys, restore_sigterm
):
    """The configurations of two runs of one seed swapped, resealed: each record's key is no
    longer the key of its configuration (checked without recomputing)."""

    def swap(data):
        a, b = _record(data, 0), _record(data, 0, SMALL)
        a["config"], b["config"] = b["config"], a["config"]

    _edit(copy, swap, reseal=True)
    assert main(["ledger", "show"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "is not the key of its configuration and seed" in err


def test_a_swap_of_rows_and_digests_resealed_is_caught_by_verify(copy):
    """Two runs' rows swapped in the table and their records' digests with them, resealed:
    every digest agrees with every file; recomputing shows both runs differ."""
    path = copy / "tables" / "tiny.npz"
    table = ledger_rows.table_bytes(path.read_bytes())
    rows = dict(ledger_rows.rows(table))
    a, b = run_key(TINY, 0), run_key(TINY, 1)
    rows[a], rows[b] = rows[b], rows[a]
    path.write_bytes(ledger_rows.npz(ledger_rows.columns(sorted(rows.items()))))

    def edit(data):
        data["tables"]["tiny"] = hashlib.sha256(path.read_bytes()).hexdigest()
        ra, rb = data["runs"][a], data["runs"][b]
        ra["row"], rb["row"] = ledger_rows.row_digest(rows[a]), ledger_rows.row_digest(rows[b])
        ra.pop("whole"), ra.pop("sha256")  # a whole run's file would give it away
        ra["digest"], rb["digest"] = rb["digest"], ra["digest"]

    _edit(copy, edit, reseal=True)
    ledger._table.cache_clear()
    assert ledger.check_files(copy)  # consistent
    checks = {
        c.seed: c for c in verify.verify(tables=("tiny",), workers=1, progress=False, folder=copy)
    }
    assert not checks[0].ok and not checks[1].ok
    assert "its record's content digest" in checks[0].differences()


@pytest.mark.parametrize("name", ["../../outside", "/etc/passwd", "a/b", ".hidden", "..", ""])
def test_a_table_name_that_is_not_a_plain_name_is_refused(copy, name, capsys, restore_sigterm):
    def edit(data):
        data["tables"][name] = data["tables"].pop("tiny")
        for record in data["runs"].values():
            if record["name"] == "tiny":
                record["name"] = name

    _edit(copy, edit, reseal=True)
    assert main(["ledger", "show"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "table name" in err, err


def _fifo(path: Path) -> None:
    path.unlink()
    os.mkfifo(path)


def _to_dev_zero(path: Path) -> None:
    path.unlink()
    path.symlink_to("/dev/zero")


def _to_outside(path: Path) -> None:
    outside = path.parent.parent.parent / "outside.npz"
    outside.write_bytes(path.read_bytes())
    path.unlink()
    path.symlink_to(outside)


@pytest.mark.parametrize("make", [_fifo, _to_dev_zero, _to_outside], ids=["fifo", "zero", "out"])
@pytest.mark.parametrize(
    "command", [["ledger", "show"], pytest.param(["report"], marks=pytest.mark.slow)]
)
def test_a_table_that_is_not_a_regular_file_of_the_ledger_is_one_line(
    copy, make, command, tmp_path, restore_sigterm
):
    """In the tiny ledger for ``ledger show``; in a copy of the committed ledger for
    ``report`` (which reads the paper's tables)."""
    folder, table = copy, "tiny"
    if command == ["report"]:
        folder, table = tmp_path / "committed", "experiment1"
        shutil.copytree(REPO / "ledger", folder)
    make(folder / "tables" / f"{table}.npz")
    out = subprocess.run(
        [sys.executable, "-m", "docking", *command],
        env={**os.environ, "PYTHONPATH": str(REPO), "DOCKING_LEDGER": str(folder)},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 1, out.stderr[-2000:]
    err = out.stderr.strip()
    assert len(err.splitlines()) == 1 and "not read" in err, err


@pytest.mark.parametrize("make", [_fifo, _to_dev_zero], ids=["fifo", "zero"])
def test_a_manifest_that_is_not_a_regular_file_is_one_line(copy, make, capsys, restore_sigterm):
    make(copy / "manifest.json")
    assert main(["ledger", "show"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "not read" in err, err


def test_a_stored_result_that_is_a_fifo_is_one_line_and_no_hang(tmp_path):
    results = tmp_path / "results"
    path = result_path(SMALL, 0, results)
    path.parent.mkdir(parents=True)
    os.mkfifo(path)
    out = subprocess.run(
        [sys.executable, "-m", "docking", "run", "experiment1", "--seeds", "0", *SMALL_ARGS],
        env={**os.environ, "PYTHONPATH": str(REPO), "DOCKING_RESULTS": str(results)},
        capture_output=True,
        text=True,
        timeout=300,
    )
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert any("is a FIFO (named pipe), not a regular file: not read" in line for line in lines)
    assert len(lines) == 1, out.stderr


def test_ledger_show_says_what_it_checked(copy, capsys, restore_sigterm):
    assert main(["ledger", "show"]) == 0
    out = capsys.readouterr().out
    checked = " ".join(out[out.index("\nchecked: ") :].split())  # its last lines, wrapped
    assert "the 2 tables and 1 whole runs against their SHA-256" in checked
    assert "only by recomputing" in checked


# run names a ledger it cannot use before it computes ------------------------------------------


def _run(args, monkeypatch, tmp_path):
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))
    return main(["run", "experiment1", *args, *SMALL_ARGS])


@pytest.mark.parametrize("kind", ["no manifest", "not a ledger", "no folder"])
def test_run_says_the_ledger_is_unusable_before_it_computes(
    kind, copy, tmp_path, monkeypatch, capsys, restore_sigterm
):
    if kind == "no manifest":
        (copy / "manifest.json").unlink()
        says = f"{copy} is not a ledger (it has no manifest.json)"
    elif kind == "not a ledger":
        monkeypatch.setenv("DOCKING_LEDGER", "/etc")
        says = "/etc is not a ledger (it has no manifest.json)"
    else:
        monkeypatch.delenv("DOCKING_LEDGER")
        monkeypatch.setattr("docking.study.paths.checkout_root", lambda: tmp_path / "clone")
        says = f"the ledger folder {tmp_path / 'clone' / 'ledger'} does not exist"
    assert _run(["--seeds", "0"], monkeypatch, tmp_path) == 0
    captured = capsys.readouterr()
    notes = [line for line in captured.err.splitlines() if line.startswith("python -m docking")]
    assert notes == [f"python -m docking: note: {says}: no run is read from it; computing 1 runs"]
    assert "seeds 0: computed now" in captured.out


def test_run_reads_a_usable_ledger_without_a_note(copy, tmp_path, monkeypatch, capsys):
    assert _run(["--seeds", "0"], monkeypatch, tmp_path) == 0
    captured = capsys.readouterr()
    assert "note" not in captured.err and "read from the committed ledger" in captured.out
    assert not result_path(SMALL, 0, tmp_path / "results").exists()


@pytest.mark.parametrize("what", ["the run's table", "another table"])
def test_run_refuses_a_damaged_ledger_before_it_computes(
    what, copy, tmp_path, monkeypatch, capsys, restore_sigterm
):
    _flip(copy / "tables" / ("experiment1.npz" if what == "the run's table" else "tiny.npz"))
    assert _run(["--seeds", "0,1"], monkeypatch, tmp_path) == 1  # seed 1 is not in the ledger
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "does not match its digest" in err, err
    assert not result_path(SMALL, 1, tmp_path / "results").exists()  # nothing computed


# verify says what it will recompute, capped ---------------------------------------------------


def test_verify_caps_its_sample_and_says_how_long_before_it_starts(copy):
    line = _verify_plan(10**12, False, 2)
    assert "2 of the 2 others the ledger holds (--sample 1000000000000 capped at 2)" in line
    assert line.startswith("verify: recomputing 3 runs: the 1 of experiment1 and experiment2")
    assert "about " in line and "of the runs' wall times in the ledger" in line
    assert "capped" not in _verify_plan(1, False, 2)


def _log_arrays(part: str, n_trials: int) -> dict[str, np.ndarray]:
    """The stored arrays of a trial log ``part`` of ``n_trials`` two-step trials."""
    steps = np.full(n_trials, 2, dtype=np.int64)
    return {
        f"{part}.success": np.zeros(n_trials, dtype=bool),
        f"{part}.steps": steps,
        f"{part}.start_far": np.full(n_trials, 1.5),
        f"{part}.poses": np.arange(9.0 * n_trials).reshape(3 * n_trials, 3),
        f"{part}.actions": np.zeros(2 * n_trials, dtype=np.int64),
        f"{part}.winners": np.zeros(2 * n_trials, dtype=np.int64),
        f"{part}.deltas": np.zeros(2 * n_trials),
    }


def test_a_part_of_no_trials_matches_its_empty_columns_and_only_those():
    """A table written before ledger format 8 keeps the derived columns of a part of no trials
    empty (``test.ends`` of a yardstick run of no test trials); the recomputed run gives none:
    the row is the run's. An emptied column of a part with trials is still caught."""
    arrays = {**_log_arrays("test", 0), **_log_arrays("heldout", 2)}
    cells = ledger_rows.row(arrays, frozenset({"ends", "lengths", "paths"}))
    cells |= {
        "test.ends": np.zeros((0, 3)),
        "test.lengths": np.zeros(0),
        "test.path.trial": np.zeros(0, dtype=np.int64),
        "test.path.poses": np.zeros((0, 3)),
        "test.path.actions": np.zeros(0, dtype=np.int64),
    }
    assert ledger_rows.row_differences(arrays, cells) == []
    emptied = cells | {"heldout.ends": np.zeros((0, 3)), "heldout.lengths": np.zeros(0)}
    assert ledger_rows.row_differences(arrays, emptied) == ["heldout.ends", "heldout.lengths"]
    assert ledger_rows.row_differences(arrays, cells | {"test.ends": np.zeros((1, 3))}) == [
        "test.ends"
    ]
