"""Run (or load) a part of the study's third edition, niced, on the embedded Dask cluster.

The edition's runs take hours; its parts can be run one after another (each a sub-design of
the same cells, so the runs are the design's own, stored under the same keys):

* ``contest``: the contest worlds' untuned learners, yardsticks and tuning (with the
  design's stages: round 2 of the successive halving, then the tuned learners);
* ``rest``: every other cell (the path, the verdicts' variants, rotation and turning,
  Experiment 1), without stages.

Usage: ``python tools/run_third_edition.py contest|rest [--workers 2]``.
"""

from __future__ import annotations

import argparse
import os

from docking.study.designs import third_edition as te


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("part", choices=("contest", "rest"))
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    os.nice(10)
    design = te.part(args.part)
    results = design.run(workers=args.workers)
    print(f"{args.part}: {len(results.cells)} cells")


if __name__ == "__main__":
    main()
