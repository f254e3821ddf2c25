"""Bad input to ``python -m docking``, counted: a clear error, a traceback, or silence.

Run from the checkout (``python3 tools/fuzz_cli.py``). Each case is a command line a user
could mistype; a *clear error* exits non-zero with a message and no Python traceback, a
*traceback* shows one, *silent* exits 0 (the bad input was accepted). Nothing is computed:
every case fails (or should fail) before a run starts. Prints one line per case and the
counts; exits 1 unless every case is a clear error.
"""

from __future__ import annotations

import os
import subprocess
import sys
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
]


def classify(args: list[str]) -> tuple[str, str]:
    env = {**os.environ, "MUJOCO_GL": "egl", "PYOPENGL_PLATFORM": "egl"}
    done = subprocess.run(
        [PYTHON, "-m", "docking", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    text = (done.stderr or done.stdout).strip().splitlines()
    last = text[-1] if text else ""
    if "Traceback (most recent call last)" in done.stderr:
        return "traceback", last
    if done.returncode == 0:
        return "silent", last
    return "clear error", last


def main() -> int:
    counts: dict[str, int] = {}
    for args in CASES:
        kind, last = classify(args)
        counts[kind] = counts.get(kind, 0) + 1
        print(f"{kind:12s} {' '.join(args)}\n             {last[:150]}")
    print(", ".join(f"{k}: {v}" for k, v in sorted(counts.items())))
    return 0 if set(counts) == {"clear error"} else 1


if __name__ == "__main__":
    sys.exit(main())
