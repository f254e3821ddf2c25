"""Smoke tests of the benchmark's measurements (issue 9); the acceptance figures come from a
full run of ``python -m docking benchmark`` on an idle machine."""

from docking.benchmark import env_step_time, floor_time
from docking.world import WorldConfig


def test_env_step_and_floor_are_measured():
    step = env_step_time(WorldConfig(), steps=50, repeats=2)
    floor = floor_time(WorldConfig(), frames=50, repeats=2)
    assert step["n"] == 2 and 0 < step["min"] <= step["median"] < 0.1
    assert set(floor) == {"floor", "render", "physics", "preprocess"}
    assert all(0 < f["min"] <= f["median"] < 0.1 for f in floor.values())
