"""Smoke tests of the benchmark's measurements (issue 9); the acceptance figures come from a
full run of ``python -m docking benchmark`` on an idle machine."""

from docking.study.cli.ledger import benchmark_module
from docking.world import WorldConfig

env_step_time, floor_time = benchmark_module().env_step_time, benchmark_module().floor_time


def test_env_step_and_floor_are_measured():
    step = env_step_time(WorldConfig(), steps=50, repeats=2)
    floor = floor_time(WorldConfig(), frames=50, repeats=2)
    assert step["n"] == 2 and 0 < step["min"] <= step["median"] < 0.1
    assert set(floor) == {"floor", "render", "physics", "preprocess"}
    assert all(0 < f["min"] <= f["median"] < 0.1 for f in floor.values())


def test_outside_a_clone_the_benchmark_says_where_it_is(tmp_path):
    """An installed package holds no benchmarks/ folder: python -m docking benchmark says so
    and exits 2, rather than failing on an import."""
    import os
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    import docking

    shutil.copytree(Path(docking.__file__).parent, tmp_path / "docking")
    done = subprocess.run(
        [sys.executable, "-m", "docking", "benchmark", "--quick"],
        env={**os.environ, "PYTHONPATH": str(tmp_path)},
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2, done.stderr
    assert "benchmarks/env_speed.py of the repository" in done.stderr
    assert "run it from a clone" in done.stderr


def test_the_benchmark_never_imports_the_command_line():
    """Issue 51: ``python -m docking benchmark`` imports the benchmark (benchmark_module), and
    the benchmark never imports the command line, so the two make no import circle; run on
    its own it reads its options itself."""
    import ast
    import subprocess
    import sys
    from pathlib import Path

    path = Path(benchmark_module().__file__)
    tree = ast.parse(path.read_text())
    imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert not {m for m in imported if m and m.startswith("docking.study.cli")}
    shown = subprocess.run(
        [sys.executable, str(path), "--help"], capture_output=True, text=True, timeout=120
    )
    assert shown.returncode == 0 and "--quick" in shown.stdout and "--seeds" in shown.stdout
