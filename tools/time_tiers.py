"""Time the Makefile's tiers on this checkout and record them in ``ledger/timings.json``.

Run it from a fresh clone (``git clone`` of the commit to measure), on a machine doing nothing
else::

    python3 tools/time_tiers.py --fresh         # make setup, check, report, test, docs, paper
    python3 tools/time_tiers.py --tiers check   # some of them

``report`` is ``python -m docking report`` from the committed ledger (not a Makefile target).
With ``--fresh``, every tier after ``setup`` starts from the clone as it was checked out, the
environment kept: ``git clean -fdx -e .venv`` (the results store, the executed notebooks,
the built site: every file git does not track) and ``git checkout -- .`` (the figures a tier
rewrote) run before it, untimed. So each time is a fresh clone's: ``report`` computes what
it caches, ``test`` finds no executed notebook, ``docs`` executes every notebook. Without
it the tiers run one after another in the checkout, each reusing what the ones before left
(``docs`` after ``test`` executes no notebook). ``--fresh`` refuses to run unless this
checkout's ``results/`` is empty or absent, so that a developer's store is never deleted.

Each tier is timed in wall-clock seconds and in the CPU seconds of its processes (user +
system of the waited-for children). Before the first tier and after the last,
``python -m docking benchmark --quick`` gives the CPU time of one environment step (minimum
and median over its repetitions), so that the times can be scaled to another machine. The
record (with the date, the commit, the number of cores, the Python version and whether the
tiers were fresh) is written to ``ledger/timings.json``; copy it into the checkout the clone
came from, where ``python -m docking report --readme README.md`` writes it into the README. A
tier that fails stops the measurement and nothing is written. Tiers already in the record
and not measured again are kept (each tier names its commit and date).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

#: In the order they run (with ``--fresh``, each from the clone as checked out).
TIERS = ("setup", "check", "report", "test", "docs", "paper")

#: The command of a tier that is not a Makefile target (its output is not kept).
COMMANDS = {"report": [".venv/bin/python", "-m", "docking", "report"]}

ROOT = Path(__file__).resolve().parent.parent


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed(command: list[str], quiet: bool = False) -> dict:
    """Run ``command`` in the checkout; its wall and CPU seconds (``RuntimeError`` if it fails).
    ``quiet``: its standard output is not shown."""
    cpu, wall = _children_cpu(), time.monotonic()
    done = subprocess.run(command, cwd=ROOT, stdout=subprocess.DEVNULL if quiet else None)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed (exit status {done.returncode})")
    return {"wall_s": round(time.monotonic() - wall, 1), "cpu_s": round(_children_cpu() - cpu, 1)}


def fresh() -> None:
    """The clone as checked out, its environment kept: every untracked file but ``.venv``
    removed (the results store, executed notebooks, built site) and tracked files restored."""
    subprocess.run(["git", "clean", "-fdxq", "-e", ".venv"], cwd=ROOT, check=True)
    subprocess.run(["git", "checkout", "-q", "--", "."], cwd=ROOT, check=True)


def step_time() -> dict:
    """``benchmark --quick``'s CPU milliseconds per environment step (min and median)."""
    code = (
        "import contextlib, io, json; from docking.study.cli.ledger import benchmark_module\n"
        "with contextlib.redirect_stdout(io.StringIO()): r = benchmark_module().run(quick=True)\n"
        "print(json.dumps(r['env_step']))"
    )
    out = subprocess.run(
        [str(ROOT / ".venv/bin/python"), "-c", code],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
        env={**os.environ, "MUJOCO_GL": "egl", "PYOPENGL_PLATFORM": "egl"},
    )
    step = json.loads(out.stdout.strip().splitlines()[-1])
    return {"min_ms": round(1e3 * step["min"], 3), "median_ms": round(1e3 * step["median"], 3)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tiers", nargs="+", choices=TIERS, default=list(TIERS))
    parser.add_argument(
        "--fresh",
        action="store_true",
        help="each tier after setup from the clone as checked out (git clean -fdx -e .venv)",
    )
    args = parser.parse_args(argv)
    stored = ROOT / "results"
    if args.fresh and stored.is_dir() and any(stored.iterdir()):
        parser.error(f"--fresh deletes untracked files, and {stored} is not empty: use a clone")
    commit = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=ROOT, check=True, capture_output=True, text=True
    ).stdout.strip()
    tiers, benchmarks = {}, []
    os.environ.update(MUJOCO_GL="egl", PYOPENGL_PLATFORM="egl")
    for tier in (t for t in TIERS if t in args.tiers):
        command = COMMANDS.get(tier, ["make", tier])
        if args.fresh and tier != "setup":
            fresh()
        print(f"--- {' '.join(command)}", flush=True)
        tiers[tier] = timed(command, quiet=tier in COMMANDS)
        print(f"--- {' '.join(command)}: {tiers[tier]}", flush=True)
        if tier == "setup" or not benchmarks:
            benchmarks.append(step_time())
    benchmarks.append(step_time())
    target = ROOT / "ledger" / "timings.json"
    # Tiers measured earlier (e.g. make setup before the last commit) are kept beside these.
    earlier = json.loads(target.read_text())["tiers"] if target.is_file() else {}
    today = datetime.date.today().isoformat()
    for timing in tiers.values():
        timing.update(commit=commit, date=today)
    record = {
        "date": today,
        "commit": commit,
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "fresh": bool(args.fresh),
        "step": {
            "min_ms": min(b["min_ms"] for b in benchmarks),
            "median_ms": sorted(b["median_ms"] for b in benchmarks)[len(benchmarks) // 2],
        },
        "tiers": {name: (earlier | tiers)[name] for name in TIERS if name in earlier | tiers},
    }
    target.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
    print(json.dumps(record, indent=1))
    print(f"written to {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
