"""Defects found by fuzzing the command line and the ledger's files: bad input is a clear
one-line error (``python -m docking: error: ...``, a non-zero exit), never a traceback, a
silent wrong result or a hang. Each test builds its own tiny store and ledger."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from helpers import SEEDS, TINY

from docking.study import ledger, paths
from docking.study.cli import main
from docking.study.kinds import run_key
from docking.study.progress import PROGRESS_LINE
from docking.study.runs import load_run
from docking.study.store import run_or_load
from docking.study.sweep import jobs_for, parse_seeds, run_jobs

REPO = Path(__file__).resolve().parent.parent
TINY_ARGS = ["--train-trials", "4", "--test-trials", "3", "--eval-every", "2", "--eval-trials", "2"]


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A ledger of two tiny runs (seeds 0 and 1) as rows of its results table."""
    base = tmp_path_factory.mktemp("fuzz-ledger")
    results, folder = base / "results", base / "ledger"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        for s in SEEDS:
            run_or_load(TINY, s, results, progress=False)
    ledger.update([(TINY, s, True, frozenset()) for s in SEEDS], folder, results)
    return folder


@pytest.fixture
def copy(built, tmp_path, monkeypatch):
    """A copy of the tiny ledger that DOCKING_LEDGER names."""
    folder = tmp_path / "ledger"
    shutil.copytree(built, folder)
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    ledger._read_manifest.cache_clear()
    return folder


@pytest.fixture
def restore_sigterm():
    """main() installs a SIGTERM handler; put the test process's back."""
    handler = signal.getsignal(signal.SIGTERM)
    yield
    signal.signal(signal.SIGTERM, handler)


def _served(seed):
    return load_run(TINY, seed, "/nonexistent-store")


def _edit_manifest(folder, change, reseal: bool = False):
    """Edit the manifest in ``folder``; with ``reseal``, its seals follow the edit (a forger
    who can run the package: the checks past the seals must catch it)."""
    path = folder / "manifest.json"
    data = json.loads(path.read_text())
    change(data)
    if reseal:
        data["seals"] = ledger.seals_of(data)
    path.write_text(json.dumps(data))
    ledger._read_manifest.cache_clear()


def _record(data, seed):
    return data["runs"][run_key(TINY, seed)]


def _one_error_line(err: str) -> str:
    """The one line of ``err`` (a command's stderr) but a sweep's progress lines
    (:data:`docking.study.progress.PROGRESS_LINE`: where stderr is not a terminal, the runs it
    computes and each run finished), checked to be the command's message."""
    lines = [line for line in err.strip().splitlines() if not PROGRESS_LINE.fullmatch(line)]
    assert "Traceback" not in err, err
    assert len(lines) == 1 and lines[0].startswith("python -m docking: error: "), err
    return lines[0]


# 1, 2. A record that points at another seed's file, or outside the ledger folder ----------


def test_a_record_pointing_at_another_seeds_file_is_refused(copy):
    def point_0_at_1(data):
        _record(data, 0).update(whole=_record(data, 1)["whole"], sha256=_record(data, 1)["sha256"])

    _edit_manifest(copy, point_0_at_1)
    with pytest.raises(ledger.CorruptLedger, match="not its own file"):
        _served(0)


def test_another_seeds_file_copied_into_place_is_refused(copy):
    data = json.loads((copy / "manifest.json").read_text())
    other = (copy / _record(data, 1)["whole"]).read_bytes()
    (copy / _record(data, 0)["whole"]).write_bytes(other)
    new = hashlib.sha256(other).hexdigest()
    _edit_manifest(copy, lambda d: _record(d, 0).update(sha256=new))
    with pytest.raises(ledger.CorruptLedger, match="tiny do not match their seal"):
        _served(0)  # a whole file's digest is sealed
    _edit_manifest(copy, lambda d: None, reseal=True)
    with pytest.raises(ledger.CorruptLedger, match="not the run asked for"):
        _served(0)


def test_a_file_outside_the_ledger_folder_is_refused(copy, tmp_path):
    data = json.loads((copy / "manifest.json").read_text())
    outside = tmp_path / "elsewhere" / "x.npz"
    outside.parent.mkdir()
    shutil.copy(copy / _record(data, 0)["whole"], outside)  # the right bytes, the wrong place
    relative = os.path.relpath(outside, copy)
    _edit_manifest(copy, lambda d: _record(d, 0).update(whole=relative))
    with pytest.raises(ledger.CorruptLedger, match="not its own file"):
        _served(0)


# 3. Seeds separated by spaces ---------------------------------------------------------------


def test_seeds_separated_by_spaces_are_separate_seeds():
    assert parse_seeds("1 2") == [1, 2]
    assert parse_seeds(" 1  2,5 ") == [1, 2, 5]
    assert parse_seeds("0-2 7") == [0, 1, 2, 7]
    # the forms accepted before still mean what they meant
    assert parse_seeds("0-4") == [0, 1, 2, 3, 4]
    assert parse_seeds("0,3,5") == [0, 3, 5]
    assert parse_seeds("0-2, 10-11") == [0, 1, 2, 10, 11]
    assert parse_seeds("0 - 2") == [0, 1, 2]
    for bad in ("", " ", "1,,2", "1,", "1 1", "1 -", "1.5 2"):
        with pytest.raises(ValueError, match="seeds"):
            parse_seeds(bad)


# 4. Wall times outside the digests ----------------------------------------------------------


@pytest.mark.parametrize("value", [-12345.0, float("nan"), "12"])
def test_an_edited_wall_time_in_the_manifest_is_refused(copy, value):
    _edit_manifest(copy, lambda d: _record(d, 0).update(wall_time_train=value))
    with pytest.raises(ledger.CorruptLedger, match="is not a ledger manifest"):
        ledger.manifest(copy)


# 5, 6. Scheduler addresses ------------------------------------------------------------------


@pytest.mark.parametrize(
    "address, says",
    [
        ("tls://127.0.0.1:1", "tls:// schedulers need a security configuration"),
        ("tcp://127.0.0.1:" + "9" * 30, "port must be 1-65535"),
        ("tcp://127.0.0.1:0", "port must be 1-65535"),
        ("tcp://127.0.0.1:65536", "port must be 1-65535"),
        ("tcp://" + "a" * 300 + ":8786", "too long"),
    ],
)
def test_bad_scheduler_addresses_are_refused_before_any_work(address, says, tmp_path):
    with pytest.raises(ValueError, match=says):
        run_jobs(jobs_for([TINY], [0]), tmp_path, scheduler=address, progress=False)
    assert not any(tmp_path.iterdir())


def test_a_tls_scheduler_without_security_is_a_clear_cli_error(
    tmp_path, monkeypatch, capsys, restore_sigterm
):
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))
    args = ["run", "experiment1", "--seeds", "0", "--scheduler", "tls://127.0.0.1:1"]
    assert main(args) == 2
    assert "security configuration" in _one_error_line(capsys.readouterr().err)


# 7. A manifest that is not one --------------------------------------------------------------


@pytest.mark.parametrize(
    "text, says",
    [
        ("[]", "TypeError"),
        ("{not json", "JSONDecodeError"),
        ("", "JSONDecodeError"),
        (lambda d: d.pop("fingerprints"), "KeyError..fingerprints"),
        (lambda d: _record(d, 1).update(runner="nope"), "its runner"),
        (lambda d: d["runs"].update(k=3), "TypeError"),
        (lambda d: _record(d, 1).update(seed=-1), "seed -1"),
        (lambda d: _record(d, 1).pop("config"), "KeyError..config"),
    ],
)
def test_a_manifest_that_is_not_one_is_a_clear_error(copy, text, says, capsys, restore_sigterm):
    if callable(text):
        _edit_manifest(copy, text)
    else:
        (copy / "manifest.json").write_text(text)
    with pytest.raises(ledger.CorruptLedger, match=says) as error:
        ledger.manifest(copy)
    assert "manifest.json is not a ledger manifest" in str(error.value)
    assert "git checkout -- ledger" in str(error.value)
    assert main(["ledger", "show"]) == 1
    line = _one_error_line(capsys.readouterr().err)
    assert "manifest.json is not a ledger manifest" in line


# 8. A table that is not an npz ------------------------------------------------------------


def test_a_table_that_is_not_an_npz_is_a_clear_error(copy):
    raw = b"not an npz at all"
    (copy / "tables" / "tiny.npz").write_bytes(raw)

    def edit(data):
        data["tables"].update(tiny=hashlib.sha256(raw).hexdigest())
        _record(data, 1).pop("whole")  # seed 1 is then read from the table

    _edit_manifest(copy, edit, reseal=True)
    with pytest.raises(ledger.CorruptLedger, match=r"tiny.npz is not an .npz \(zip\) file") as e:
        load_run(TINY, 1, "/nonexistent-store")
    assert "pickled" not in str(e.value)  # numpy's word for bytes that are no zip


# 9. A failed job on the embedded cluster ----------------------------------------------------


def _cli(args, tmp_path, timeout, **env):
    return subprocess.run(
        [sys.executable, "-m", "docking", *args],
        cwd=tmp_path,
        env={
            **os.environ,
            "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
            "DOCKING_RESULTS": str(tmp_path / "results"),
            "DOCKING_LEDGER": "off",
            **env,
        },
        capture_output=True,
        text=True,
        timeout=timeout,
    )


@pytest.mark.slow
def test_a_failed_job_on_dask_prints_only_the_clear_message(tmp_path):
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "experiment1").write_text("a file where the runs' folder goes")
    args = ["run", "experiment1", "--seeds", "0,1", "--processes", "2", *TINY_ARGS]
    out = _cli(args, tmp_path, timeout=300)
    assert out.returncode == 1
    assert "Compute Failed" not in out.stderr
    assert "is not writable" in _one_error_line(out.stderr)


# 11. A scheduler that accepts and never answers ---------------------------------------------


@pytest.mark.slow
def test_a_scheduler_that_never_answers_is_a_clear_error_in_bounded_time(tmp_path):
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    server.settimeout(0.2)
    port = server.getsockname()[1]
    stop, accepted = threading.Event(), []

    def accept() -> None:
        while not stop.is_set():
            try:
                accepted.append(server.accept()[0])  # and never a byte back
            except (TimeoutError, OSError):
                continue

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        start = time.monotonic()
        args = ["run", "experiment1", "--seeds", "0", "--scheduler", f"tcp://127.0.0.1:{port}"]
        out = _cli([*args, *TINY_ARGS], tmp_path, timeout=120)
        elapsed = time.monotonic() - start
    finally:
        stop.set()
        thread.join(timeout=5)
        for conn in accepted:
            conn.close()
        server.close()
    assert accepted, "the command never connected"
    assert out.returncode == 1 and elapsed < 60, (elapsed, out.stderr)
    assert "cannot reach a Dask scheduler" in _one_error_line(out.stderr)


# 12, 13. DOCKING_LEDGER ---------------------------------------------------------------------


def test_ledger_show_says_the_ledger_is_switched_off(monkeypatch, capsys, restore_sigterm):
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    assert main(["ledger", "show"]) == 2
    line = _one_error_line(capsys.readouterr().err)
    assert "switched off by DOCKING_LEDGER=off" in line and "None" not in line


@pytest.mark.parametrize(
    "value, says",
    [
        ("of", "DOCKING_LEDGER='of' is neither off nor an absolute path"),
        ("ledger", "DOCKING_LEDGER='ledger' is neither off nor an absolute path"),
        ("", "DOCKING_LEDGER is set but empty"),
        ("/nonexistent/ledger", "DOCKING_LEDGER='/nonexistent/ledger' names no folder"),
    ],
)
def test_a_bad_ledger_variable_is_a_clear_error(value, says, monkeypatch, capsys, restore_sigterm):
    monkeypatch.setenv("DOCKING_LEDGER", value)
    with pytest.raises(ValueError, match=says):
        paths.ledger_dir()
    assert main(["ledger", "show"]) == 2
    assert says in _one_error_line(capsys.readouterr().err)


def test_the_ledger_variable_accepts_off_and_absolute_folders(monkeypatch, tmp_path):
    for off in ("off", "OFF", "0", "none", "false"):
        monkeypatch.setenv("DOCKING_LEDGER", off)
        assert paths.ledger_dir() is None and paths.ledger_off()
    monkeypatch.setenv("DOCKING_LEDGER", str(tmp_path))
    assert paths.ledger_dir() == tmp_path and not paths.ledger_off()
    monkeypatch.delenv("DOCKING_LEDGER")
    assert paths.ledger_dir() == REPO / "ledger"


# 14. An empty --results-dir -----------------------------------------------------------------


@pytest.mark.parametrize(
    "args",
    [
        ["run", "experiment1", "--seeds", "0", "--results-dir", ""],
        ["sweep", "experiment1", "--seeds", "0", "--results-dir="],
        ["figures", "--folder", " "],
    ],
)
def test_an_empty_results_dir_is_refused(args, tmp_path, monkeypatch, capsys, restore_sigterm):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("docking.study.sweep.run_jobs", _refuse)
    assert main(args) == 2
    assert "is empty; name a folder" in _one_error_line(capsys.readouterr().err)
    assert not any(tmp_path.iterdir())


def _refuse(*args, **kwargs):
    raise AssertionError("a command ran with an empty folder option")
