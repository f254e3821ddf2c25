"""Benchmark of the docking world against its floor, and of a full Experiment 2 seed.

One run reports:

* env steps/s: ``DockingEnv.step`` with random actions (resets included);
* the floor, measured in the same process: one bare ``mujoco.Renderer`` frame of the same
  scene with the same geom selection and the same size as the robot's camera renders (the
  crop band, group 2, headlight only) + the bare ``mj_step`` calls of one action +
  ``preprocess`` of the band; and the ratio env step / floor;
* the CPU time (``time.process_time``) of a full Experiment 2 seed and its env steps;
* the speed-up of two processes over one on two seeds: the wall time of the seeds run one
  after the other in one process over that of the seeds run at once, one per process (2.00x
  at best on two cores; below 1.00x the two processes took longer than one).

``--quick`` (a smoke test, and the step time ``tools/time_tiers.py`` records) shortens every
part: fewer, shorter repetitions and a 40-trial Experiment 2 without its learning curve.

The machine may be shared: every measurement is repeated, the minimum and the median are
reported, and CPU time is preferred over wall time wherever one process is measured.

    python -m docking benchmark [--repeats 5] [--steps 2000] [--seeds 0-1] [--quick]
    python benchmarks/env_speed.py [the same options]

It lives in the repository, beside the package and not in it (issue 43): it measures the
package, it computes nothing the package's results need. ``python -m docking benchmark``
runs it from a clone.
"""

from __future__ import annotations

import contextlib
import dataclasses
import multiprocessing
import os
import time

import numpy as np

# Imported first: it sets MUJOCO_GL before MuJoCo is imported.
from docking.world import DockingEnv, make_model  # isort: skip
import mujoco  # noqa: E402

from docking.camera import preprocess_band  # noqa: E402
from docking.experiments import ExperimentConfig, run_experiment  # noqa: E402
from docking.presets import EXPERIMENT_2  # noqa: E402
from docking.world import _EYE_GROUP  # noqa: E402


def _stats(values) -> dict:
    values = np.asarray(values, dtype=np.float64)
    return {"min": float(values.min()), "median": float(np.median(values)), "n": len(values)}


def env_step_time(config, steps: int, repeats: int, seed: int = 0) -> dict:
    """CPU seconds per ``DockingEnv.step`` with uniformly random actions (with resets)."""
    env = DockingEnv(config, seed=seed)
    rng = np.random.default_rng(seed)
    env.reset()
    for _ in range(200):  # warm up
        env.step(int(rng.integers(4)))
    times = []
    for _ in range(repeats):
        actions = rng.integers(4, size=steps)
        t0 = time.process_time()
        for a in actions:
            env.step(int(a))
        times.append((time.process_time() - t0) / steps)
    return _stats(times)


def floor_time(config, frames: int, repeats: int) -> dict:
    """CPU seconds of the floor of one env step: a bare ``mujoco.Renderer`` frame of the
    crop band's size with the camera's geom group and no lights but the headlight, the bare
    ``mj_step`` calls of one action, and ``preprocess_band``."""
    env = DockingEnv(config, seed=0)
    model = make_model(config)
    model.light_active[:] = 0
    data = mujoco.MjData(model)
    env.reset()
    data.qpos[:] = env.physics.data.qpos
    data.ctrl[:] = env.physics.data.ctrl
    mujoco.mj_forward(model, data)
    x0, y0, x1, y1 = config.camera.crop
    renderer = mujoco.Renderer(model, height=y1 - y0, width=x1 - x0)
    option = mujoco.MjvOption()
    option.geomgroup[:] = 0
    option.geomgroup[_EYE_GROUP] = 1
    n_physics = env.physics._n_move + env.physics._n_settle
    cam = config.camera

    def one():
        for _ in range(n_physics):
            mujoco.mj_step(model, data)
        renderer.update_scene(data, camera="eye", scene_option=option)
        preprocess_band(renderer.render(), cam)

    for _ in range(100):
        one()
    times = {"floor": [], "render": [], "physics": [], "preprocess": []}
    band = renderer.render()
    for _ in range(repeats):
        t0 = time.process_time()
        for _ in range(frames):
            one()
        times["floor"].append((time.process_time() - t0) / frames)
        t0 = time.process_time()
        for _ in range(frames):
            renderer.update_scene(data, camera="eye", scene_option=option)
            renderer.render()
        times["render"].append((time.process_time() - t0) / frames)
        t0 = time.process_time()
        for _ in range(frames):
            for _ in range(n_physics):
                mujoco.mj_step(model, data)
        times["physics"].append((time.process_time() - t0) / frames)
        t0 = time.process_time()
        for _ in range(frames):
            preprocess_band(band, cam)
        times["preprocess"].append((time.process_time() - t0) / frames)
    renderer.close()
    return {k: _stats(v) for k, v in times.items()}


@contextlib.contextmanager
def _counting_steps():
    """Count ``DockingEnv.step`` and ``reset_to`` calls in this process."""
    counts = {"steps": 0, "resets": 0}
    step, reset_to = DockingEnv.step, DockingEnv.reset_to

    def counted_step(self, action):
        counts["steps"] += not self._needs_reset
        return step(self, action)

    def counted_reset_to(self, pose):
        counts["resets"] += 1
        return reset_to(self, pose)

    DockingEnv.step, DockingEnv.reset_to = counted_step, counted_reset_to
    try:
        yield counts
    finally:
        DockingEnv.step, DockingEnv.reset_to = step, reset_to


def _run_seeds(args) -> dict:
    """Worker: run ``config`` for each seed in turn; CPU and wall time of each."""
    config, seeds = args
    out = []
    for seed in seeds:
        with _counting_steps() as counts:
            c0, w0 = time.process_time(), time.perf_counter()
            result = run_experiment(config, seed, progress=False)
            cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        out.append(
            {
                "seed": seed,
                "cpu": cpu,
                "wall": wall,
                "steps": counts["steps"],
                "resets": counts["resets"],
                "test_success": result.test.success_rate,
            }
        )
    return out


def experiment_times(config: ExperimentConfig, seeds) -> dict:
    """Run the seeds one after the other in one worker process, then each in its own worker
    process at the same time: per-seed CPU times and the speed-up of the parallel run (the
    serial wall time over the parallel one). The workers are started once, before either
    (their start-up, imports and GL context, is not part of a run)."""
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(len(seeds)) as pool:
        pool.map(_noop, range(len(seeds)), chunksize=1)
        w0 = time.perf_counter()
        serial = pool.apply(_run_seeds, ((config, list(seeds)),))
        serial_wall = time.perf_counter() - w0
        w0 = time.perf_counter()
        jobs = [(config, [s]) for s in seeds]
        parallel = [r for rs in pool.map(_run_seeds, jobs, chunksize=1) for r in rs]
        parallel_wall = time.perf_counter() - w0
        pool.close()
        pool.join()
    return {
        "serial": serial,
        "serial_wall": serial_wall,
        "parallel": parallel,
        "parallel_wall": parallel_wall,
        "speedup": serial_wall / parallel_wall,
    }


def _noop(*_):
    import docking.world  # noqa: F401

    time.sleep(0.2)  # every worker takes one: each has started before the runs
    return None


#: ``repeats`` and ``steps`` by default, and with ``quick``.
DEFAULTS = {"repeats": 5, "steps": 2000}
QUICK = {"repeats": 3, "steps": 500}


def run(
    repeats: int | None = None, steps: int | None = None, seeds=(0, 1), quick: bool = False
) -> dict:
    """Run the benchmark and print its report (``python -m docking benchmark``); returns the
    figures as a dict. ``repeats`` repetitions of ``steps`` environment steps for the step
    and floor timings (default :data:`DEFAULTS`, with ``quick`` :data:`QUICK`); Experiment 2
    for each of ``seeds`` (``quick``: 30 training and 10 test trials without the learning
    curve, a smoke test)."""
    chosen = QUICK if quick else DEFAULTS
    repeats = chosen["repeats"] if repeats is None else repeats
    steps = chosen["steps"] if steps is None else steps
    for name, value, lo, hi in (("repeats", repeats, 1, 1000), ("steps", steps, 1, 1_000_000)):
        if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
            raise ValueError(f"--{name} must be an integer in [{lo}, {hi}], got {value!r}")
    seeds = tuple(seeds)
    if not seeds or any(not 0 <= s <= 2**32 - 1 for s in seeds):
        raise ValueError(f"--seeds must be in [0, {2**32 - 1}], got {list(seeds)}")
    config = EXPERIMENT_2
    if quick:
        config = dataclasses.replace(config, train_trials=30, test_trials=10, eval_trials=0)
    world = config.world

    step = env_step_time(world, steps, repeats)
    floor = floor_time(world, steps, repeats)
    ratio = step["median"] / floor["floor"]["median"]
    ms = 1e3
    print(f"CPU time per step, {repeats} repetitions of {steps} (min / median):")
    print(
        f"  env step  {ms * step['min']:.3f} / {ms * step['median']:.3f} ms "
        f"({1 / step['median']:.0f} steps/s)"
    )
    print(
        f"  floor     {ms * floor['floor']['min']:.3f} / {ms * floor['floor']['median']:.3f} ms"
        f"  = render {ms * floor['render']['median']:.3f} + physics "
        f"{ms * floor['physics']['median']:.3f} + preprocess "
        f"{ms * floor['preprocess']['median']:.3f} (medians)"
    )
    print(f"  time ratio env step / floor (medians): {ratio:.2f} (1.00: nothing above the floor)")

    runs = experiment_times(config, list(seeds))
    cpus = [r["cpu"] for r in runs["serial"]]
    cpu = _stats(cpus)
    r0 = runs["serial"][0]
    curve = " + learning curve" if config.eval_trials else ""
    print(
        f"{config.name} ({config.train_trials} training{curve} + "
        f"{config.test_trials} test trials), one process, seeds {list(seeds)} in turn:"
    )
    for r in runs["serial"]:
        print(
            f"  seed {r['seed']}: {r['cpu']:.1f} s CPU ({r['wall']:.1f} s wall), "
            f"{r['steps']} env steps + {r['resets']} resets, test {r['test_success']:.1%}"
        )
    print(f"  CPU time per seed (min / median): {cpu['min']:.1f} / {cpu['median']:.1f} s")
    print(
        f"{len(seeds)} processes at once, one seed each: {runs['parallel_wall']:.1f} s of wall "
        "time (CPU per seed: " + ", ".join(f"{r['cpu']:.1f} s" for r in runs["parallel"]) + ")"
    )
    best = min(len(seeds), os.cpu_count() or 1)
    print(
        f"  speed-up over one process ({runs['serial_wall']:.1f} s / "
        f"{runs['parallel_wall']:.1f} s of wall time): {runs['speedup']:.2f}x (at best "
        f"{best}.00x; below 1.00x slower)"
    )
    return {
        "env_step": step,
        "floor": floor,
        "ratio": ratio,
        "experiment": runs,
        "seed_cpu": cpu,
        "seed_steps": r0["steps"],
    }


def main(argv=None) -> int:
    """``python benchmarks/env_speed.py [--repeats N] [--steps N] [--seeds 0-1] [--quick]``:
    :func:`run` with the options of ``python -m docking benchmark`` (which imports this module;
    this one never imports the command line)."""
    import argparse

    from docking.study.sweep import parse_seeds

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n", 1)[0])
    parser.add_argument("--repeats", type=int, default=None, help="repetitions of each timing")
    parser.add_argument("--steps", type=int, default=None, help="environment steps per repetition")
    parser.add_argument("--seeds", default="0-1", help="seeds of the Experiment 2 runs")
    parser.add_argument("--quick", action="store_true", help="a smoke test of about 10 s")
    args = parser.parse_args(argv)
    try:
        run(args.repeats, args.steps, parse_seeds(args.seeds), args.quick)
    except ValueError as exc:
        parser.error(str(exc))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
