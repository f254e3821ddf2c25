"""Keys that cannot miss what a run executes (issue 60): each kind of run (the paper's learner
in every variant the ledger holds, PPO, a registered learner) runs short under a profiler that
records every function called, and every ``docking`` function it calls must live in a module
its key covers (:meth:`docking.study.kinds.Runner.module_digests`). A module that computes a
run's numbers and is not keyed would let an edit there serve stale runs."""

from __future__ import annotations

import collections
import json
import sys
from pathlib import Path

import pytest

import docking
from docking.study import battery, kinds, ledger, migrate

PACKAGE = Path(docking.__file__).resolve().parent


def _module(filename: str) -> str | None:
    """The ``docking`` module a code object's file is, or None outside the package."""
    try:
        relative = Path(filename).resolve().relative_to(PACKAGE)
    except ValueError:
        return None
    parts = relative.with_suffix("").parts
    return ".".join(("docking", *parts)).removesuffix(".__init__")


def executed(fn, entry) -> dict[str, set[str]]:
    """``{docking module: the functions it ran}`` while ``fn()`` runs (``entry``: the runner's
    own dispatch, a pass-through left out)."""
    seen: dict[str, set[str]] = collections.defaultdict(set)
    skip = getattr(entry, "__code__", None)

    def profile(frame, event, arg):
        # the import system probing a package for a name (``from docking import x`` asks
        # ``docking.__getattr__``) resolves a module; it computes nothing
        caller = frame.f_back.f_code.co_filename if frame.f_back else ""
        if event == "call" and frame.f_code is not skip and not caller.startswith("<frozen"):
            module = _module(frame.f_code.co_filename)
            if module is not None:
                seen[module].add(frame.f_code.co_qualname)

    sys.setprofile(profile)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return dict(seen)


def outside_key(runner, config, seed: int = 0) -> dict[str, set[str]]:
    """The ``docking`` modules a short run of ``config`` executes that its key does not cover,
    with their functions."""
    keyed = {m for m in runner.module_digests() if m.startswith("docking")}
    ran = executed(lambda: runner.run(config, seed, progress=False), runner.run)
    return {m: f for m, f in ran.items() if m not in keyed}


def _ledger_kinds(runner_name: str) -> list[tuple[str, dict]]:
    """One configuration per kind of run the ledger holds (:func:`migrate._kind`), the
    cheapest, run short (:func:`battery.short`)."""
    data = ledger._stored_manifest(Path(__file__).resolve().parents[1] / "ledger")
    found: dict[str, tuple[float, dict]] = {}
    for record in data["runs"].values():
        if record["runner"] != runner_name:
            continue
        kind = migrate._kind(record)
        if kind not in found or record["wall_seconds"] < found[kind][0]:
            found[kind] = (record["wall_seconds"], record["config"])
    return [(k, battery.short(runner_name, c)) for k, (_, c) in sorted(found.items())]


@pytest.mark.slow
@pytest.mark.parametrize("kind", [k for k, _ in _ledger_kinds("learner")])
def test_every_kind_of_the_learners_runs_executes_only_keyed_code(kind):
    config = dict(_ledger_kinds("learner"))[kind]
    runner = kinds.runner_named("learner")
    assert outside_key(runner, runner.from_dict(config)) == {}


@pytest.mark.slow
def test_ppo_executes_only_keyed_code():
    pytest.importorskip("skrl")
    ((_, config),) = _ledger_kinds("ppo")
    runner = kinds.runner_named("ppo")
    assert outside_key(runner, runner.from_dict(config)) == {}


@pytest.mark.slow
def test_a_registered_learner_executes_only_keyed_code():
    sys.path.insert(0, str(Path(__file__).parent))
    try:
        import outside_learner
    finally:
        sys.path.pop(0)
    # the runner its module registered on import (registering the class again here, under
    # another name, changed the registry and the class's runner for every later test)
    runner = outside_learner.RUNNER
    found = outside_key(runner, outside_learner.RandomFeatures())
    assert found == {}


def test_the_profiler_sees_a_module_outside_the_key():
    """The check can fail: a run whose code calls into an unkeyed module is caught."""
    runner = kinds.runner_named("learner")

    def fake_run(config, seed, progress=False):
        from docking.study import paths

        return paths.results_dir()

    probe = type(
        "Probe", (), {"run": staticmethod(fake_run), "module_digests": runner.module_digests}
    )
    found = outside_key(probe, None)
    assert "docking.study.paths" in found, json.dumps({k: sorted(v) for k, v in found.items()})
