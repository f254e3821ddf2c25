"""Benchmark: environment steps per second; the code lives in :mod:`docking.benchmark`.

python benchmarks/env_speed.py [--steps N]   (the same as: python -m docking benchmark)
"""

from docking.benchmark import main

if __name__ == "__main__":
    raise SystemExit(main())
