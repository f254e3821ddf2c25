"""Run one test many times in a row while busy loops keep every core loaded; print the count
that passed.

The test that once failed only under load (issue 41): on a busy machine a heartbeat of the
embedded Dask cluster's worker could reach the scheduler after the worker had unregistered,
and distributed printed ``WARNING:distributed.scheduler:Received heartbeat from unregistered
worker ...`` on the user's terminal as the cluster closed. Usage (not part of CI)::

    MUJOCO_GL=egl PYOPENGL_PLATFORM=egl .venv/bin/python tools/load_flaky.py [--runs 20]
        [--busy 2] [--test tests/test_fuzz_defects.py::...]

Exits 0 only if every run passed; the output of a failed run is printed.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
TEST = "tests/test_fuzz_defects.py::test_a_failed_job_on_dask_prints_only_the_clear_message"


def _spin() -> None:  # a busy loop at normal priority, until terminated
    while True:
        pass


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=20, help="times to run the test (20)")
    parser.add_argument("--busy", type=int, default=2, help="busy-loop processes (2)")
    parser.add_argument("--test", default=TEST, help="the pytest node id")
    args = parser.parse_args()
    if args.runs < 1 or args.busy < 0:
        parser.error("--runs must be >= 1 and --busy >= 0")

    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    env.setdefault("MUJOCO_GL", "egl")
    env.setdefault("PYOPENGL_PLATFORM", "egl")
    pytest = [sys.executable, "-m", "pytest", args.test, "-q", "-p", "no:cacheprovider", "-x"]
    loads = [multiprocessing.Process(target=_spin, daemon=True) for _ in range(args.busy)]
    for p in loads:
        p.start()
    passed = 0
    try:
        for k in range(1, args.runs + 1):
            start = time.monotonic()
            out = subprocess.run(pytest, cwd=REPO, env=env, capture_output=True, text=True)
            seconds = time.monotonic() - start
            ok = out.returncode == 0
            passed += ok
            print(
                f"run {k}/{args.runs}: {'passed' if ok else 'FAILED'} ({seconds:.0f} s)", flush=True
            )
            if not ok:
                print(out.stdout[-4000:], out.stderr[-2000:], sep="\n", flush=True)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
    finally:
        for p in loads:
            p.terminate()
        for p in loads:
            p.join()
    print(f"{passed}/{args.runs} passed under {args.busy} busy loops: {args.test}")
    return 0 if passed == args.runs else 1


if __name__ == "__main__":
    sys.exit(main())
