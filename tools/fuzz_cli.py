"""Bad input to ``python -m docking``, counted per class: clear / traceback / silent / hang /
recovered.

Run from the checkout (``python3 tools/fuzz_cli.py [CLASS ...]``; a few minutes). Each case
is a command line a user could mistype, an environment variable set wrongly, a scheduler
that never answers, a copy of the committed ledger damaged as an attacker or a bad merge
would, a Ctrl-C, or a request that once never ended. A case either expects an error or an
honest result (a text its output must hold):

* *clear*: an expected error: a non-zero exit with a message and no Python traceback (for a
  Ctrl-C: exit 130 and the one line ``python -m docking: interrupted``);
* *traceback*: a Python traceback (or death by a signal);
* *silent*: exit 0 where an error was due (bad input accepted, a damaged ledger served), or
  an honest result's text missing (a computation that does not say why), or files left in
  the system's temporary folder;
* *hang*: no exit (or no answer) after :data:`TIMEOUT` seconds;
* *recovered*: the honest result: exit 0 with its text (the help at a clamped width, a run
  that names the missing ledger before it computes, ``verify`` saying what it will do, a run
  without test trials saying so, a sweep that leaves its temporary folder empty).

Nothing long is computed: the damaged-ledger cases fail before a run starts, the cases that
recover compute a run of a few trials. Prints one line per case and the counts per class;
exits 1 if any case is silent, a traceback or a hang.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PYTHON = str(ROOT / ".venv/bin/python") if (ROOT / ".venv/bin/python").exists() else sys.executable

CASES = [
    ["run", "experiment3"],
    ["run", "experiment1", "--seeds", "-1"],
    ["run", "experiment1", "--seeds", "3-1"],
    ["run", "experiment1", "--seeds", "a"],
    ["run", "experiment1", "--seeds", "0,0"],
    ["run", "experiment1", "--world.scene", "flor"],
    ["run", "experiment1", "--network.rule", "global"],
    ["run", "experiment1", "--network.eps-w", "-1"],
    ["run", "experiment1", "--network.eps-w", "nan"],
    ["run", "experiment1", "--train-trials", "0.5"],
    ["run", "experiment1", "--world.camera.tilt-deg", "400"],
    ["run", "experiment1", "--policy", "greedy"],
    ["run", "experiment1", "--processes", "0"],
    ["run", "experiment1", "--seeds", "9999", "--results-dir", "/proc/nope"],
    ["design", "run", "nope"],
    ["design", "run", "study", "--seeds", "x"],
    ["design", "run", "study", "--scheduler", "localhost"],
    ["sweep", "--seeds", "9999", "--scheduler", "tcp://127.0.0.1:1"],
    ["run", "experiment1", "--seeds", "9999", "--scheduler", "tcp://127.0.0.1:1"],
    ["sweep", "--grid", "network.eps_w"],
    ["sweep", "--grid", "nope=1,2"],
    ["verify", "--sample", "-3"],
    ["ledger", "frobnicate"],
    ["figures", "fig9"],
    ["benchmark", "--steps", "0"],
    [
        "report",
        "--readme",
        "/nonexistent/README.md",
        "--no-study",
        "--no-experiment3",
        "--no-second-edition",
    ],
    ["nope"],
    ["run", "experiment1", "--seeds", "9999", "--scheduler", "tls://127.0.0.1:1"],
    ["run", "experiment1", "--seeds", "9999", "--scheduler", "tcp://127.0.0.1:" + "9" * 30],
    ["run", "experiment1", "--seeds", "1 x"],
    ["run", "experiment1", "--seeds", "0", "--results-dir", ""],
    # issue 60: an option given twice (argparse kept the last without a word); the runs of a
    # design's cells that the design does not have
    ["run", "experiment1", "--seeds", "9999", "--seeds", "9998"],
    ["run", "experiment1", "--seeds=9999", "--seeds", "9998"],
    ["run", "experiment1", "--seeds", "9999", "--train_trials", "3", "--train-trials", "4"],
    ["report", "--no-experiment3", "--experiment3"],
    ["report", "--figures-dir", ""],
    ["verify", "--design", "nope"],
    ["verify", "--design", "bracketing-replication", "--cells", "floor/papr"],
    ["verify", "--design", "bracketing-replication", "--cells", "floor/paper", "--seeds", "7000"],
    ["verify", "--cells", "floor/paper"],
    ["verify", "--design", "paper", "--table", "experiment1"],
]

#: Seeds and grids (issue 41): other digits, underscores, repeated grid values.
SEEDS_AND_GRIDS = [
    ["run", "experiment1", "--seeds", "1_0"],
    ["run", "experiment1", "--seeds", "\u0661"],
    ["run", "experiment1", "--seeds", "\u0663-5"],
    ["run", "experiment1", "--seeds", "\uff11"],
    ["run", "experiment1", "--seeds", "+1"],
    ["run", "experiment1", "--seeds", "1e3"],
    ["run", "experiment1", "--seeds", "0-1_0"],
    ["sweep", "experiment1", "--seeds", "9999", "--grid", "network.eps_w=0,0.0"],
    ["sweep", "experiment1", "--seeds", "9999", "--grid", "network.eps_w=0.05,0.05"],
    ["sweep", "experiment1", "--seeds", "9999", "--grid", "network.eps_w=0", "network.eps-w=1"],
    ["sweep", "experiment1", "--seeds", "9999", "--grid", "world.heading_hold=true,yes"],
    ["benchmark", "--seeds", "\u0661"],
]

#: Every number of the command line (issue 52), read as seeds are: ``(option, value)``. Each
#: case is a run of a few trials (:data:`TINY`, then the option), so that a value accepted
#: where an error was due is a run computed in seconds, counted silent.
NUMBERS = [
    ("--train-trials", "1_0"),
    ("--train-trials", "\u0661\u0660"),  # Arabic-Indic 10
    ("--test-trials", "\uff13"),  # a full-width 3
    ("--network.eps-w", "1_0"),
    ("--network.eps-w", "0.0_5"),
    ("--network.eps-w", "\u0660.\u0660\u0665"),  # Arabic-Indic 0.05
    ("--world.start-near", "\u0660.6"),
    ("--processes", "1_0"),
]
#: ``--grid`` entries of issue 52: a number with an underscore, a grid of 8 million
#: configurations (refused before any is built).
_VALUES = ",".join(str(k) for k in range(1, 201))
GRIDS = [
    ["train_trials=1_0,20"],
    ["network.eps_w=0.0_5"],
    [f"train_trials={_VALUES}", f"test_trials={_VALUES}", f"heldout_trials={_VALUES}"],
]

#: A run of a few trials (seconds): what the cases that recover compute.
TINY = ["--train-trials", "4", "--test-trials", "3", "--eval-every", "2", "--eval-trials", "2"]
TINY += ["--processes", "1"]

#: Seconds after which a case counts as a hang.
TIMEOUT = 120


def _silent_server() -> int:
    """A TCP server on 127.0.0.1 that accepts connections and never answers; its port."""
    server = socket.create_server(("127.0.0.1", 0))
    held = []

    def serve():
        while True:
            held.append(server.accept()[0])

    threading.Thread(target=serve, daemon=True).start()
    return server.getsockname()[1]


#: Run in the package's Python (:func:`_in_package`): Experiment 1's table with one run's
#: test success set to False, rewritten; prints the table's new SHA-256.
_FORGE = """
import hashlib, sys
from pathlib import Path
import numpy as np
from docking.study import ledger_rows
path, key = Path(sys.argv[1]) / "experiment1.npz", sys.argv[2]
with np.load(path) as found:
    table = {k: found[k] for k in found.files}
row, column = table["key"].tolist().index(key), "test.success"
start = int(np.sum(np.maximum(table[column + ".count"][:row], 0)))
table[column][start : start + table[column + ".count"][row]] = False
path.write_bytes(ledger_rows.npz(table))
print(hashlib.sha256(path.read_bytes()).hexdigest())
"""
#: The seals of the manifest read from stdin, as the package computes them (a forger who can
#: run the package reseals the manifest after an edit).
_SEALS = """
import json, sys
from docking.study import ledger
print(json.dumps(ledger.seals_of(json.load(sys.stdin))))
"""
#: A stored result of Experiment 1 seed 0 (with the tiny options) made a FIFO in the store
#: argv[1].
_FIFO_RESULT = """
import dataclasses, os, sys
from docking.presets import EXPERIMENT_1
from docking.study.kinds import result_path
config = dataclasses.replace(
    EXPERIMENT_1, train_trials=4, test_trials=3, eval_every=2, eval_trials=2
)
path = result_path(config, 0, sys.argv[1])
path.parent.mkdir(parents=True)
os.mkfifo(path)
"""


#: The results store argv[1] whose folder of Experiment 1's runs is a link to the folder
#: argv[2], outside the store (issue 60: it was read and written through).
_LINKED_OUT = """
import os, sys
from pathlib import Path
store, outside = Path(sys.argv[1]), Path(sys.argv[2])
store.mkdir(parents=True)
outside.mkdir(parents=True)
os.symlink(outside, store / "experiment1")
"""


def _in_package(code: str, *args, stdin: str | None = None) -> str:
    """Run ``code`` in the package's Python (:data:`PYTHON`) with ``args``; its output."""
    out = subprocess.run(
        [PYTHON, "-c", code, *map(str, args)],
        input=stdin,
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT), "MUJOCO_GL": "egl"},
        check=True,
    )
    return out.stdout.strip()


def _damaged_ledgers(tmp: Path) -> list[tuple[str, dict]]:
    """``(what, environment)`` cases: copies of the committed ledger, each damaged once."""
    source = ROOT / "ledger"
    manifest = json.loads((source / "manifest.json").read_text())
    whole = {(r["name"], r["seed"]): (k, r) for k, r in manifest["runs"].items() if r.get("whole")}
    # The runs the ledger keeps whole: the cases damage Experiment 1's seed 0 (which the
    # command below reads), or point it at Experiment 2's.
    (k0, r0), (_, r1) = whole[("experiment1", 0)], whole[("experiment2", 0)]

    def copy(name: str, edit) -> Path:
        folder = tmp / name
        shutil.copytree(source, folder)
        data = json.loads(json.dumps(manifest))
        text = edit(data, folder)
        (folder / "manifest.json").write_text(text if text is not None else json.dumps(data))
        return folder

    def other_seeds_entry(data, folder):
        data["runs"][k0].update(whole=r1["whole"], sha256=r1["sha256"])

    def outside(data, folder):
        data["runs"][k0]["whole"] = "../../../../../tmp/x.npz"

    def wall_time(data, folder):
        data["runs"][k0]["wall_time_train"] = -12345

    def not_xz(data, folder):
        (folder / r0["whole"]).write_bytes(b"not an npz")

    def not_xz_digest_matching(data, folder):
        (folder / r0["whole"]).write_bytes(b"not an npz")
        data["runs"][k0]["sha256"] = hashlib.sha256(b"not an npz").hexdigest()

    def missing_fingerprint(data, folder):
        del data["fingerprints"]

    def table_not_npz(data, folder):  # the table of Experiment 1's other seeds
        (folder / "tables" / "experiment1.npz").write_bytes(b"not an npz")
        data["tables"]["experiment1"] = hashlib.sha256(b"not an npz").hexdigest()

    table_run = next(
        k for k, r in manifest["runs"].items() if r["name"] == "experiment1" and r["seed"] == 1
    )

    def edit(key, **fields):
        return lambda data, folder: data["runs"][key].update(fields)

    # issue 49: a forged table (Experiment 1 seed 1's test success set to False, the table
    # rewritten and its SHA-256 put in the manifest), then resealed, records swapped and
    # resealed, a table named outside the folder, tables that are not regular files
    def forged_table(data, folder, reseal=False):
        data["tables"]["experiment1"] = _in_package(_FORGE, folder / "tables", table_run)
        if reseal:
            data["seals"] = json.loads(_in_package(_SEALS, stdin=json.dumps(data)))

    def swapped(data, folder):
        data["runs"][k0], data["runs"][table_run] = data["runs"][table_run], data["runs"][k0]
        data["seals"] = json.loads(_in_package(_SEALS, stdin=json.dumps(data)))

    def named_outside(data, folder):
        data["tables"]["../../outside"] = data["tables"].pop("experiment1")

    def table_as(kind, relative="tables/experiment1.npz"):
        def apply(data, folder):
            path = folder / relative
            path.unlink()
            if kind == "fifo":
                os.mkfifo(path)
            elif kind == "zero":
                path.symlink_to("/dev/zero")
            else:
                outside = folder.parent / f"{folder.name}-outside.npz"
                shutil.copy(source / relative, outside)
                path.symlink_to(outside)

        return apply

    # issue 52: the derived table (notebook 08's oracle-labelled success) damaged, forged with
    # its SHA-256 updated (not resealed), or a link to /dev/zero
    derived_path = "derived/oracle-labelled-success.npz"

    def derived_forged(data, folder):
        path = folder / derived_path
        raw = path.read_bytes()
        path.write_bytes(raw[:-1] + bytes([raw[-1] ^ 1]))
        data["derived"]["oracle-labelled-success"] = hashlib.sha256(path.read_bytes()).hexdigest()

    def damage(relative, how):
        def apply(data, folder):
            path = folder / relative
            raw = path.read_bytes()
            if how == "flip":
                path.write_bytes(
                    raw[: len(raw) // 2]
                    + bytes([raw[len(raw) // 2] ^ 1])
                    + raw[len(raw) // 2 + 1 :]
                )
            elif how == "cut":
                path.write_bytes(raw[: len(raw) // 2])
            else:
                path.unlink()

        return apply

    cases = {
        "a record points at another run's whole file": other_seeds_entry,
        "a record's file outside the ledger": outside,
        "a negative wall time": wall_time,
        "a whole run that is not an npz": not_xz,
        "a whole run that is not an npz, its digest matching": not_xz_digest_matching,
        "no fingerprints": missing_fingerprint,
        "a results table that is not an npz, its digest matching": table_not_npz,
        "a manifest holding []": lambda data, folder: "[]",
        "a manifest that is not JSON": lambda data, folder: "{nope",
        # issue 41: the digests and wall times outside every file, the files themselves
        "a whole run's digest edited": edit(k0, digest="0" * 64),
        "a table run's digest edited": edit(table_run, digest="0" * 64),
        "a table run's wall time edited (+90 s)": edit(
            table_run, wall_time_train=manifest["runs"][table_run]["wall_time_train"] + 90
        ),
        "a whole run's wall seconds edited": edit(k0, wall_seconds=1.0),
        "a run's computation time edited": edit(
            table_run, computed_utc="2020-01-01T00:00:00+00:00"
        ),
        "the seals removed": lambda data, folder: data.pop("seals") and None,
        "a results table bit-flipped": damage("tables/experiment1.npz", "flip"),
        "a results table truncated": damage("tables/experiment1.npz", "cut"),
        "a results table deleted": damage("tables/experiment1.npz", "gone"),
        "another results table bit-flipped": damage("tables/experiment2.npz", "flip"),
        "another results table deleted": damage("tables/yardsticks.npz", "gone"),
        "a whole run bit-flipped": damage(r0["whole"], "flip"),
        "a whole run truncated": damage(r0["whole"], "cut"),
        "a whole run deleted": damage(r0["whole"], "gone"),
        "another whole run bit-flipped": damage(r1["whole"], "flip"),
        "another whole run truncated": damage(r1["whole"], "cut"),
        "a table forged, its SHA-256 updated": forged_table,
        "a table forged, its SHA-256 updated and resealed": lambda d, f: forged_table(d, f, True),
        "two records swapped, resealed": swapped,
        "a table named ../../outside": named_outside,
        "a table that is a FIFO": table_as("fifo"),
        "a table that is a link to /dev/zero": table_as("zero"),
        "a table that is a link out of the ledger": table_as("out"),
        "a derived table bit-flipped": damage(derived_path, "flip"),
        "a derived table deleted": damage(derived_path, "gone"),
        "a derived table forged, its SHA-256 updated": derived_forged,
        "a derived table that is a link to /dev/zero": table_as("zero", derived_path),
    }
    return [
        (what, {"DOCKING_LEDGER": str(copy(f"l{i}", edit))})
        for i, (what, edit) in enumerate(cases.items())
    ]


def _env(extra: dict | None) -> dict:
    return {
        **os.environ,
        "MUJOCO_GL": "egl",
        "PYOPENGL_PLATFORM": "egl",
        "PYTHONPATH": str(ROOT),
        **(extra or {}),
    }


def classify(args: list[str], extra_env: dict | None = None, expect: str | None = None):
    """``(kind, what it said)`` of one command line (see the module docstring): ``expect``
    None if an error is due, else the text an honest result holds."""
    try:
        done = subprocess.run(
            [PYTHON, "-m", "docking", *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=TIMEOUT,
            env=_env(extra_env),
        )
    except subprocess.TimeoutExpired:
        return "hang", f"no exit after {TIMEOUT} s"
    text = (done.stderr or done.stdout).strip().splitlines()
    last = text[-1] if text else ""
    if "Traceback (most recent call last)" in done.stderr or done.returncode < 0:
        return "traceback", last
    if done.returncode != 0:
        return "clear", last
    if expect is None:
        return "silent", last
    found = expect in done.stdout + done.stderr
    return ("recovered", expect) if found else ("silent", f"no {expect!r}: {last}")


def interrupt(args: list[str], after: float, signum: int = signal.SIGINT, extra_env=None):
    """A command sent ``signum`` after ``after`` seconds, as a terminal sends Ctrl-C to its
    foreground job (the whole process group): clear if it exits 130 (143 for SIGTERM) with at
    most one line on stderr, no traceback and no process left."""
    import psutil

    proc = subprocess.Popen(
        [PYTHON, "-m", "docking", *args],
        cwd=ROOT,
        env=_env(extra_env),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        # SIGINT at its default, as a terminal's foreground job has it, even where this tool
        # runs with SIGINT ignored (a script's background job): python -m docking keeps an
        # inherited SIG_IGN, as Python does.
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    time.sleep(after)
    if proc.poll() is not None:  # the case is wrong, not the command: say so
        return "silent", f"exited {proc.returncode} before the signal; make the case longer"
    try:
        family = [psutil.Process(proc.pid), *psutil.Process(proc.pid).children(recursive=True)]
    except psutil.NoSuchProcess:
        family = []
    os.killpg(proc.pid, signum)
    try:
        _, err = proc.communicate(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return "hang", f"no exit {TIMEOUT} s after signal {signum}"
    _, alive = psutil.wait_procs(family, timeout=20)
    lines = err.strip().splitlines()
    last = lines[-1] if lines else ""
    if "Traceback (most recent call last)" in err or proc.returncode < 0:
        return "traceback", last or f"died by signal {-proc.returncode}"
    if alive:
        return "silent", f"left {len(alive)} processes running"
    if proc.returncode == 128 + signum and len(lines) <= 1:
        return "clear", last or "(quiet)"
    return "silent", f"exit {proc.returncode}: {last}"


def first_line(args: list[str], expect: str, extra_env=None):
    """A command that starts a long computation: recovered if its first line of output,
    within :data:`TIMEOUT` seconds, holds ``expect`` (then it is stopped); a hang if no line
    comes."""
    proc = subprocess.Popen(
        [PYTHON, "-m", "docking", *args],
        cwd=ROOT,
        env=_env(extra_env),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    found: list[str] = []
    reader = threading.Thread(target=lambda: found.append(proc.stdout.readline()), daemon=True)
    reader.start()
    reader.join(TIMEOUT)
    os.killpg(proc.pid, signal.SIGTERM)
    proc.wait(timeout=60)
    if not found:
        return "hang", f"no line after {TIMEOUT} s"
    line = found[0].strip()
    if "Traceback" in line:
        return "traceback", line
    return ("recovered", line) if expect in line else ("silent", line)


def leaves_nothing(args: list[str], extra_env: dict, scratch: Path):
    """A command run with ``scratch`` as the system's temporary folder (``TMPDIR``): recovered
    if it exits 0 and leaves ``scratch`` empty (its temporary files under a folder of its
    own, removed); silent if it leaves something there."""
    scratch.mkdir(parents=True, exist_ok=True)
    kind, said = classify(args, {**extra_env, "TMPDIR": str(scratch)}, expect="")
    if kind != "recovered":  # an error where none was due is no clear one
        return ("silent" if kind == "clear" else kind), said
    left = sorted(p.name for p in scratch.iterdir())
    return ("silent", f"left {', '.join(left)} in TMPDIR") if left else ("recovered", "nothing")


def _migration_of(change: str, tmp: Path):
    """``ledger migrate`` of a tiny ledger (beta_a 2 and 10, seeds below and at 7100 or more,
    two worlds) by a copy of the package with ``change`` applied (tests/test_migrate.py's
    forgeries, or ``"split"``: a keyed function split in two, which changes no number): clear
    if a forgery is refused naming what it alters; recovered if the split migrates."""
    import shutil

    sys.path.insert(0, str(ROOT / "tests"))
    import test_migrate as tm

    base = tmp / "migrate-base"
    if not base.exists():
        src = tm._copy(base)
        built = tm._python(src, "-c", tm.BUILD_WIDE, str(base / "results"), str(base / "ledger"))
        if built.returncode != 0:
            return "traceback", built.stderr.strip().splitlines()[-1]
    work = tmp / f"migrate-{change}"
    shutil.rmtree(work, ignore_errors=True)
    src, folder, results = tm._fresh(base, work)
    if change == "split":
        tm._split_exp(src)
    else:
        tm._edit(src, *tm.FORGERIES[change][:3])
    done = tm._migrate(src, folder, results, base / "src")
    said = " ".join(done.stderr.split()) or done.stdout.strip().splitlines()[-1]
    if "Traceback" in done.stderr:
        return "traceback", said[-200:]
    if change == "split":
        return ("recovered", "migrated") if done.returncode == 0 else ("silent", said[-200:])
    named = tm.FORGERIES[change][3]
    if done.returncode == 1 and named in said:
        return "clear", said[said.index("what only") :][:150]
    return "silent", f"not refused naming {named!r}: {said[-150:]}"


def cases(tmp: Path) -> dict[str, list]:
    """``{class: [(label, runner, arguments)]}``; a runner returns ``(kind, what it said)``."""
    port = _silent_server()
    results = str(tmp / "results")  # a damaged ledger must not fall back to computing
    stores = iter(range(10**6))

    def fresh() -> dict:  # an empty store of its own: the case computes what it asks for
        return {"DOCKING_RESULTS": str(tmp / f"fresh{next(stores)}"), "DOCKING_LEDGER": "off"}

    def cli(args, env=None, expect=None, label=""):
        shown = " ".join(f"{k}={v!r}" for k, v in (env or {}).items() if k != "DOCKING_RESULTS")
        return (label or f"{shown} {' '.join(args)}".strip(), classify, (args, env, expect))

    found: dict[str, list] = {}
    found["command line"] = [cli(args) for args in CASES] + [
        cli(["run", "experiment1", "--seeds", "9999", "--scheduler", f"tcp://127.0.0.1:{port}"]),
    ]
    found["seeds and grids"] = [cli(args) for args in SEEDS_AND_GRIDS]
    run0 = ["run", "experiment1", "--seeds", "0", *TINY]
    found["numbers, grid sizes, no tests, scratch"] = [
        *(cli([*run0, option, value], fresh()) for option, value in NUMBERS),
        *(
            cli(
                ["sweep", "experiment1", "--seeds", "0", *TINY, "--grid", *grid],
                fresh(),
                label=f"sweep --grid {' '.join(grid)[:60]}",
            )
            for grid in GRIDS
        ),
        cli(
            ["sweep", "experiment1", "--seeds", "0-9999", "--grid", "network.eps_w=0,0.05"],
            fresh(),
        ),
        cli([*run0, "--test-trials", "0"], fresh(), expect="no test trials (--test-trials 0)"),
        (
            "sweep on the embedded cluster: its scratch under its own folder",
            leaves_nothing,
            (
                ["sweep", "experiment1", "--seeds", "0,1", *TINY, "--processes", "2"],
                fresh(),
                tmp / "scratch",
            ),
        ),
    ]
    found["environment variables"] = [
        cli(["ledger", "show"], {"DOCKING_LEDGER": "off"}),
        cli(["ledger", "show"], {"DOCKING_LEDGER": "ledgr"}),
        cli(["ledger", "show"], {"DOCKING_LEDGER": "/nonexistent/ledger"}),
        cli(["ledger", "show"], {"DOCKING_LEDGER": ""}),
        cli(["ledger", "show"], {"DOCKING_LEDGER": "/etc"}),
        cli(["run", "experiment1", "--seeds", "0"], {"DOCKING_RESULTS": ""}),
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY], {**fresh(), "DOCKING_RESULTS": "/proc/x"}
        ),
        *(
            cli(["ledger", "show"], {"MUJOCO_GL": value})
            for value in ("bogus", "", "EGL", "osmesa")
        ),
        # issue 52: a platform that does not match MUJOCO_GL=egl
        cli(["ledger", "show"], {"PYOPENGL_PLATFORM": "bogus"}),
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY],
            {**fresh(), "PYOPENGL_PLATFORM": "osmesa"},
        ),
        *(
            cli(["run", "--help"], {"COLUMNS": value}, expect="--seeds")
            for value in ("5", "2", "1", "0", "-3", "abc", "40")
        ),
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY],
            {**fresh(), "DOCKING_LEDGER": "/etc"},
            expect="note: /etc is not a ledger",
        ),
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY],
            {**fresh(), "DOCKING_LEDGER": "/"},
            expect="note: / is not a ledger",
        ),
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY],
            {**fresh(), "DOCKING_LEDGER": str(tmp)},
            expect=f"note: {tmp} is not a ledger",
        ),
    ]
    fifo_store = tmp / "fifo-store"
    _in_package(_FIFO_RESULT, fifo_store)
    found["a stored result that is a FIFO"] = [
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY],
            {"DOCKING_RESULTS": str(fifo_store), "DOCKING_LEDGER": "off"},
            label="run, its stored result a FIFO",
        )
    ]
    linked_store = tmp / "linked-store"
    _in_package(_LINKED_OUT, linked_store, tmp / "outside-the-store")
    found["a store folder linked out of the store"] = [
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY],
            {"DOCKING_RESULTS": str(linked_store), "DOCKING_LEDGER": "off"},
            label="run, its store's experiment1 folder a link out of the store",
        )
    ]
    found["damaged ledgers: run"], found["damaged ledgers: ledger show"] = [], []
    for what, env in _damaged_ledgers(tmp):
        found["damaged ledgers: run"].append(
            # seed 9999 makes the command compute: the whole ledger is checked first
            cli(
                ["run", "experiment1", "--seeds", "0-1,9999", "--processes", "1"],
                {**env, "DOCKING_RESULTS": results},
                label=what,
            )
        )
        found["damaged ledgers: ledger show"].append(cli(["ledger", "show"], env, label=what))
    no_manifest = tmp / "no-manifest"
    shutil.copytree(ROOT / "ledger", no_manifest)
    (no_manifest / "manifest.json").unlink()
    found["damaged ledgers: run"].append(
        cli(
            ["run", "experiment1", "--seeds", "0", *TINY],
            {**fresh(), "DOCKING_LEDGER": str(no_manifest)},
            expect=f"note: {no_manifest} is not a ledger",
            label="the manifest deleted",
        )
    )
    found["damaged ledgers: ledger show"].append(
        cli(["ledger", "show"], {"DOCKING_LEDGER": str(no_manifest)}, label="the manifest deleted")
    )
    slow = ["--train-trials", "5000"]  # minutes: still running when the signal comes
    found["signals"] = [
        (f"Ctrl-C {what}", interrupt, (args, after, signal.SIGINT, fresh()))
        for what, args, after in [
            ("while importing", ["run", "experiment1", "--seeds", "0", *TINY], 0.8),
            ("while parsing", ["run", "experiment1", "--seeds", "0", *TINY[-2:], *slow], 2.5),
            ("during run", ["run", "experiment1", "--seeds", "0", "--processes", "1", *slow], 8),
            (
                "during sweep",
                ["sweep", "experiment1", "--seeds", "0,1", "--processes", "2", *slow],
                15,
            ),
            (
                "during sweep, later",
                ["sweep", "experiment1", "--seeds", "0,1", "--processes", "2", *slow],
                40,
            ),
        ]
    ] + [
        (
            "SIGTERM during sweep",
            interrupt,
            (
                ["sweep", "experiment1", "--seeds", "0,1", "--processes", "2", *slow],
                15,
                signal.SIGTERM,
                fresh(),
            ),
        ),
    ]
    found["laundering"] = [  # issue 60: a migration that would re-key changed results
        ("migrate after beta_a in [5, 20) altered", _migration_of, ("beta_a", tmp)),
        ("migrate after seeds >= 7100 altered", _migration_of, ("seeds", tmp)),
        ("migrate after the floor world altered", _migration_of, ("world", tmp)),
        ("migrate after a split function (no number changed)", _migration_of, ("split", tmp)),
    ]
    found["hangs"] = [
        (
            "verify --sample 1000000000000",
            first_line,
            (["verify", "--sample", "1000000000000"], "capped at", None),
        ),
        (
            "verify --all --processes 2",
            first_line,
            (["verify", "--all", "--processes", "2"], "every run of the ledger", None),
        ),
        (  # issue 60: the runs behind one number, their cost said first
            "verify --design bracketing-replication --cells floor/paper --seeds 7100-7104",
            first_line,
            (
                [
                    "verify",
                    "--design",
                    "bracketing-replication",
                    "--cells",
                    "floor/paper",
                    "--seeds",
                    "7100-7104",
                ],
                "the 5 runs behind cell floor/paper, seeds 7100-7104",
                None,
            ),
        ),
        cli(["run", "--help"], {"COLUMNS": "5"}, expect="--seeds"),
        cli(["sweep", "--help"], {"COLUMNS": "1"}, expect="--grid"),
        cli(["design", "run", "--help"], {"COLUMNS": "2"}, expect="--seeds"),
        cli(["run", "experiment1", "--seeds", "9999", "--scheduler", f"tcp://127.0.0.1:{port}"]),
    ]
    return found


KINDS = ("clear", "traceback", "silent", "hang", "recovered")


def main() -> int:
    wanted = set(sys.argv[1:])
    totals: dict[str, dict[str, int]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, found in cases(Path(tmp)).items():
            if wanted and name not in wanted:
                continue
            counts = totals.setdefault(name, dict.fromkeys(KINDS, 0))
            print(f"== {name}", flush=True)
            for label, runner, arguments in found:
                kind, said = runner(*arguments)
                counts[kind] += 1
                print(f"{kind:9s} {label}\n          {said[:150]}", flush=True)
    print("\nclass: clear / traceback / silent / hang / recovered")
    for name, counts in totals.items():
        print(f"{name}: " + " / ".join(str(counts[k]) for k in KINDS))
    bad = sum(c[k] for c in totals.values() for k in ("traceback", "silent", "hang"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
