"""Benchmark: environment steps per second (render + physics + preprocessing).

Runs random actions in `DockingEnv` with the default world and prints steps/s overall and the
time spent in each part of a step. Target (issue #2): at least 1000 steps/s on a 2-core
CPU-only machine with MUJOCO_GL=egl (Mesa llvmpipe).

    python -m docking benchmark [--steps N]
"""

from __future__ import annotations

import argparse
import time


def main(argv=None) -> int:
    """Run the benchmark with command-line arguments ``argv`` (default ``sys.argv[1:]``)."""
    parser = argparse.ArgumentParser(
        prog="python -m docking benchmark", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--steps", type=int, default=5000, help="timed steps (default 5000)")
    args = parser.parse_args(argv)
    if args.steps < 1:
        parser.error(f"--steps must be >= 1, got {args.steps}")

    import numpy as np

    from docking.camera import preprocess
    from docking.world import DockingEnv

    env = DockingEnv(seed=0)
    rng = np.random.default_rng(1)
    env.reset()
    for _ in range(200):  # warm up the GL context and caches
        env.step(int(rng.integers(4)))
    start = time.perf_counter()
    for _ in range(args.steps):
        env.step(int(rng.integers(4)))
    total = time.perf_counter() - start

    n = 1000
    t0 = time.perf_counter()
    for _ in range(n):
        frame = env.render_camera()
    t_render = (time.perf_counter() - t0) / n
    t0 = time.perf_counter()
    for _ in range(n):
        preprocess(frame, env.config.camera)
    t_pre = (time.perf_counter() - t0) / n
    target = env.physics.data.ctrl[:3].copy()
    t0 = time.perf_counter()
    for _ in range(n):
        env.physics.walk_to(target)
    t_phys = (time.perf_counter() - t0) / n

    print(
        f"environment steps/s (render + physics + preprocessing, incl. resets): "
        f"{args.steps / total:.0f}"
    )
    print(
        f"  per step: {1e3 * total / args.steps:.3f} ms; render {1e3 * t_render:.3f} ms, "
        f"physics {1e3 * t_phys:.3f} ms, preprocessing {1e3 * t_pre:.3f} ms"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
