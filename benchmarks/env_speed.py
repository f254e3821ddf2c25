"""Benchmark of the docking world against its floor, and of a full Experiment 2 seed.

A thin wrapper of :mod:`docking.benchmark` (also ``python -m docking benchmark``):

    python benchmarks/env_speed.py [--repeats 5] [--steps 2000] [--seeds 0 1] [--quick]
"""

from docking.benchmark import main

if __name__ == "__main__":
    main()
