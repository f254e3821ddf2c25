"""Bad input to ``python -m docking``, counted: a clear error, a traceback, silence or a hang.

Run from the checkout (``python3 tools/fuzz_cli.py``). Each case is a command line a user
could mistype, an environment variable set wrongly, a scheduler that never answers, or a
copy of the committed ledger damaged as an attacker or a bad merge would; a *clear error*
exits non-zero with a message and no Python traceback, a *traceback* shows one, *silent*
exits 0 (the bad input was accepted, or a damaged ledger served), a *hang* has not exited
after :data:`TIMEOUT` seconds. Nothing is computed: every case fails (or should fail) before
a run starts. Prints one line per case and the counts; exits 1 unless every case is a clear
error.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
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
]

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
    }
    return [
        (what, {"DOCKING_LEDGER": str(copy(f"l{i}", edit))})
        for i, (what, edit) in enumerate(cases.items())
    ]


def classify(args: list[str], extra_env: dict | None = None) -> tuple[str, str]:
    env = {**os.environ, "MUJOCO_GL": "egl", "PYOPENGL_PLATFORM": "egl", **(extra_env or {})}
    try:
        done = subprocess.run(
            [PYTHON, "-m", "docking", *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            timeout=TIMEOUT,
            env=env,
        )
    except subprocess.TimeoutExpired:
        return "hang", f"no exit after {TIMEOUT} s"
    text = (done.stderr or done.stdout).strip().splitlines()
    last = text[-1] if text else ""
    if "Traceback (most recent call last)" in done.stderr:
        return "traceback", last
    if done.returncode == 0:
        return "silent", last
    return "clear error", last


def main() -> int:
    counts: dict[str, int] = {}
    port = _silent_server()
    with tempfile.TemporaryDirectory() as tmp:
        results = str(Path(tmp) / "results")  # a damaged ledger must not fall back to computing
        cases = [(args, {}) for args in CASES]
        cases += [
            (
                ["run", "experiment1", "--seeds", "9999", "--scheduler", f"tcp://127.0.0.1:{port}"],
                {},
            ),
            (["ledger", "show"], {"DOCKING_LEDGER": "off"}),
            (["ledger", "show"], {"DOCKING_LEDGER": "ledgr"}),
            (["ledger", "show"], {"DOCKING_LEDGER": "/nonexistent/ledger"}),
            (["run", "experiment1", "--seeds", "0"], {"DOCKING_RESULTS": ""}),
        ]
        cases += [
            (
                ["run", "experiment1", "--seeds", "0-1", "--processes", "1"],
                {**env, "DOCKING_RESULTS": results, "what": what},
            )
            for what, env in _damaged_ledgers(Path(tmp))
        ]
        for args, env in cases:
            what = env.pop("what", "")
            kind, last = classify(args, env)
            counts[kind] = counts.get(kind, 0) + 1
            shown = " ".join(f"{k}={v!r}" for k, v in env.items() if k != "DOCKING_RESULTS")
            print(f"{kind:12s} {what + ': ' if what else ''}{shown} {' '.join(args)}")
            print(f"             {last[:150]}")
    print(", ".join(f"{k}: {v}" for k, v in sorted(counts.items())))
    return 0 if set(counts) == {"clear error"} else 1


if __name__ == "__main__":
    sys.exit(main())
