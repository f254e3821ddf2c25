"""Benchmark of the docking world against its floor, and of a full Experiment 2 seed.

A thin wrapper of ``python -m docking benchmark`` (:mod:`docking.benchmark`), with its options:

    python benchmarks/env_speed.py [--repeats 5] [--steps 2000] [--seeds 0-1] [--quick]
"""

import sys

from docking.cli import main

if __name__ == "__main__":
    raise SystemExit(main(["benchmark", *sys.argv[1:]]))
