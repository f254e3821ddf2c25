"""Bring your own learner (issue 43, points 1-3): the learner protocol, a learner defined
outside the package (tests/outside_learner.py, modules written here) stored, served from a
ledger in a temporary folder and verified, keyed by its own code; the contest as a function;
the guide's example."""

from __future__ import annotations

import dataclasses
import importlib.metadata
import importlib.util
import inspect
import linecache
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import outside_learner as outside
import pytest
from helpers import TINY, user_scripts, without_extra

from docking import protocol
from docking.experiments import ExperimentConfig, run_experiment
from docking.policies import oracle
from docking.presets import EXPERIMENT_2
from docking.scene import WorldConfig
from docking.study import kinds, learners, ledger, store, verify
from docking.study.contest import CONTEST_BUDGET, Budget, Knob, Ladder, contest, small_budget
from docking.study.design import yardstick_config
from docking.study.ppo import PPOConfig, run_ppo
from docking.study.runs import load_run

ROOT = Path(__file__).resolve().parents[1]
GUIDE = ROOT / "docs" / "guide" / "bring_your_own_learner.md"
CONFIG = outside.RandomFeatures()


@pytest.fixture
def registry(monkeypatch):
    """The registry of kinds of run, restored after the test."""
    monkeypatch.setattr(kinds, "RUNNERS", dict(kinds.RUNNERS))
    monkeypatch.setattr(kinds, "_BY_NAME", dict(kinds._BY_NAME))
    monkeypatch.setattr(kinds, "_CARRIED", set(kinds._CARRIED))


# ------------------------------------------------------------------------------------------
# The protocol.
# ------------------------------------------------------------------------------------------


def test_the_built_in_learners_fit_the_protocol():
    """The paper's learner, linear SARSA and PPO: configurations of the protocol, run
    functions of its signature, and kinds of run beside the registered ones."""
    for config in (EXPERIMENT_2, PPOConfig(), CONFIG):
        assert isinstance(config, learners.Learner)
        assert type(config).from_dict(config.to_dict()) == config
    assert not isinstance(TINY.network, learners.Learner)
    for function in (run_experiment, run_ppo, outside.run):
        assert list(inspect.signature(function).parameters) == [
            "config",
            "seed",
            "progress",
            "on_trials",
        ]
    assert learners.runner(TINY) is kinds.LEARNER and learners.runner(PPOConfig()) is kinds.PPO
    assert learners.runner(CONFIG) is outside.RUNNER
    assert {"learner", "ppo", "random-features"} <= set(learners.registered())


def test_held_out_trials_are_the_published_learners_streams():
    """A learner's held-out trials are drawn as the paper's learner's (and PPO's) are: the
    oracle judged by the protocol equals the oracle yardstick run of the same seed, bit for
    bit."""
    yardstick = yardstick_config(TINY, "oracle", 4)
    for seed in (0, 7):
        expected = run_experiment(yardstick, seed, progress=False).heldout
        found = protocol.heldout_log(TINY.world, seed, 4, oracle)
        for field in dataclasses.fields(found):
            np.testing.assert_array_equal(getattr(found, field.name), getattr(expected, field.name))


def test_register_refuses_what_is_no_learner(registry):
    @dataclasses.dataclass
    class Mutable:
        name: str = "m"
        world: object = None
        heldout_trials: int = 1

    @dataclasses.dataclass(frozen=True)
    class NoWorld:
        name: str = "n"
        heldout_trials: int = 1

    with pytest.raises(TypeError, match="frozen"):
        learners.register(Mutable, outside.run)
    with pytest.raises(TypeError, match="lacks the learner protocol's fields world"):
        learners.register(NoWorld, outside.run)
    with pytest.raises(TypeError, match="must be a function"):
        learners.register(outside.RandomFeatures, print)
    with pytest.raises(ValueError, match="built-in"):
        learners.register(ExperimentConfig, outside.run)
    with pytest.raises(ValueError, match="built-in"):
        learners.register(outside.RandomFeatures, outside.run, name="ppo")


def test_register_refuses_a_library_that_is_no_installed_distribution(registry, monkeypatch):
    """Issue 60: a misspelt library was keyed as "absent", never as its version."""
    # the class carries the runner it was last registered with: put outside's back after
    monkeypatch.setattr(outside.RandomFeatures, kinds.RUNNER_ATTRIBUTE, outside.RUNNER)
    for library, says in (
        ("nosuchlib", "libraries names 'nosuchlib', which is no installed distribution"),
        ("scipyy", "libraries names 'scipyy', which is no installed distribution"),
        ("yaml", "the module yaml is distributed as PyYAML"),
    ):
        with pytest.raises(ValueError, match=re.escape(says)):
            learners.register(outside.RandomFeatures, outside.run, libraries=(library,))
    assert "random-features" in learners.registered()  # the earlier registration kept
    runner = learners.register(outside.RandomFeatures, outside.run, libraries=("scipy",))
    assert runner.module_digests()["library scipy"] == importlib.metadata.version("scipy")


def test_register_checks_trials_and_the_default_counts_at_registration(registry):
    """Issue 60: ``trials=5`` failed inside a run ('int' object is not callable), and a
    default configuration of -1 held-out trials failed later naming an internal field."""
    with pytest.raises(TypeError, match="register: trials must be a function trials"):
        learners.register(outside.RandomFeatures, outside.run, trials=5)
    with pytest.raises(ValueError, match=re.escape("register: trials(config) must be 0 or more")):
        learners.register(outside.RandomFeatures, outside.run, trials=lambda config: -1)
    with pytest.raises(TypeError, match=re.escape("register: trials(config) must be an integer")):
        learners.register(outside.RandomFeatures, outside.run, trials=lambda config: "5")
    for field, value, says in (
        ("heldout_trials", -1, "Negative.heldout_trials must be in [0, 1000000], got -1"),
        ("train_trials", 2.5, "Negative.train_trials must be an integer, got 2.5"),
    ):
        kind = dataclasses.make_dataclass(
            "Negative",
            [(field, type(value), value)],
            bases=(outside.RandomFeatures,),
            frozen=True,
        )
        with pytest.raises((ValueError, TypeError), match=re.escape(says)):
            learners.register(kind, outside.run)


def test_a_runs_counts_are_the_users_fields_before_it_runs(registry, monkeypatch):
    """A configuration registered with valid defaults, asked for -1 held-out trials: its
    trial count (what a sweep asks before submitting) names the user's field."""
    monkeypatch.setattr(outside.RandomFeatures, kinds.RUNNER_ATTRIBUTE, outside.RUNNER)
    runner = learners.register(outside.RandomFeatures, outside.run, name="counted")
    bad = dataclasses.replace(CONFIG, heldout_trials=-1)
    with pytest.raises(ValueError, match=re.escape("RandomFeatures.heldout_trials must be in")):
        runner.trials_in_run(bad)
    with pytest.raises(ValueError, match=re.escape("RandomFeatures.heldout_trials must be in")):
        runner.run(bad, 0, progress=False)


# ------------------------------------------------------------------------------------------
# Keys: its configuration, its own code, the docking modules it imports.
# ------------------------------------------------------------------------------------------

LEARNER_SOURCE = '''
"""A learner written to a file by a test."""
import dataclasses

from docking.study import learners
from docking.scene import WorldConfig


@dataclasses.dataclass(frozen=True)
class Edited:
    name: str = "edited"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 1
    alpha: float = 0.5


def run(config, seed, progress=True, on_trials=None):
    steps = 3  # three steps
    return learners.judge(config, seed, lambda o, env: 0, steps, on_trials)


RUNNER = learners.register(Edited, run)
'''


def _module(tmp_path: Path, name: str, source: str, monkeypatch):
    """The module ``name`` of ``source``, written to a file and imported (until the test
    ends)."""
    path = tmp_path / f"{name}.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, name, module)
    spec.loader.exec_module(module)
    return module


def test_the_key_follows_the_learners_own_code_in_a_module(tmp_path, registry, monkeypatch):
    def module(name, source):
        return _module(tmp_path, name, source, monkeypatch)

    first = module("edited_1", LEARNER_SOURCE)
    key = kinds.config_key(first.Edited())
    assert first.RUNNER.code.where == (str(tmp_path / "edited_1.py"),)
    assert first.RUNNER.roots == ("docking.protocol", "docking.study.learner_run", "docking.scene")
    assert "own code" in first.RUNNER.module_digests()
    assert kinds.config_key(first.Edited(alpha=0.25)) != key  # its configuration
    assert kinds.run_key(first.Edited(), 1) != kinds.run_key(first.Edited(), 2)  # the seed
    reworded = LEARNER_SOURCE.replace("# three steps", "# a comment, reworded").replace(
        '"""A learner written', '"""A docstring, reworded: a learner written'
    )
    second = module("edited_2", reworded)
    assert kinds.config_key(second.Edited()) == key
    changed = module("edited_3", LEARNER_SOURCE.replace("steps = 3", "steps = 4"))
    assert kinds.config_key(changed.Edited()) != key
    # a docking module its code uses enters the key with what it imports; one it imports
    # and never uses does not (issue 62: the key follows what the learner reaches)
    unused = LEARNER_SOURCE.replace(
        "import dataclasses\n", "import dataclasses\nimport docking.presets\n"
    )
    assert kinds.config_key(module("edited_4a", unused).Edited()) == key
    more = unused.replace("steps = 3  #", "steps = 3 + 0 * len(docking.presets.SEEDS)  #")
    other = module("edited_4", more)
    assert other.RUNNER.roots == (
        "docking.protocol",
        "docking.study.learner_run",
        "docking.presets",
        "docking.scene",
    )
    assert kinds.config_key(other.Edited()) != key
    # the learner's registry and the contest are not followed
    unfollowed = LEARNER_SOURCE.replace(
        "import dataclasses\n", "import dataclasses\nimport docking.study.contest\n"
    )
    assert module("edited_5", unfollowed).RUNNER.roots == first.RUNNER.roots


HELPED = """
import dataclasses

import {helper}
from docking.study import learners
from docking.scene import WorldConfig


@dataclasses.dataclass(frozen=True)
class Helped:
    name: str = "helped"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 1


def run(config, seed, progress=True, on_trials=None):
    return learners.judge(config, seed, lambda o, env: {helper}.ACTION, 3, on_trials)


RUNNER = learners.register(Helped, run)
"""


def test_the_key_follows_a_helper_module_of_the_users_transitively(tmp_path, registry, monkeypatch):
    """A module of the user's own that the learner's file imports, and one that module
    imports, are keyed by their code; a comment in one re-keys nothing. Each version lives
    in a folder of its own, under the same module names (names enter the key)."""

    def helped(tag: str, helper: str, deeper: str):
        folder = tmp_path / tag
        folder.mkdir()
        (folder / "helper.py").write_text(f"import deeper\n{helper}")
        (folder / "deeper.py").write_text(deeper)
        monkeypatch.syspath_prepend(str(folder))
        for name in ("helper", "deeper"):
            monkeypatch.delitem(sys.modules, name, raising=False)
        return _module(folder, "helped", HELPED.format(helper="helper"), monkeypatch)

    first = helped("a", "ACTION = 0\n", "X = 1\n")
    assert first.RUNNER.code.where[1:] == (
        str(tmp_path / "a" / "deeper.py"),
        str(tmp_path / "a" / "helper.py"),
    )
    key = kinds.config_key(first.Helped())
    assert kinds.config_key(helped("b", "ACTION = 0  # a comment\n", "X = 1\n").Helped()) == key
    assert kinds.config_key(helped("c", "ACTION = 1\n", "X = 1\n").Helped()) != key
    assert kinds.config_key(helped("d", "ACTION = 0\n", "X = 2\n").Helped()) != key


def test_a_helper_module_without_source_is_refused_naming_it(tmp_path, registry, monkeypatch):
    import py_compile

    monkeypatch.syspath_prepend(str(tmp_path))
    (tmp_path / "compiled_helper_src.py").write_text("ACTION = 0\n")
    py_compile.compile(
        str(tmp_path / "compiled_helper_src.py"), str(tmp_path / "compiled_helper.pyc")
    )
    (tmp_path / "compiled_helper_src.py").unlink()
    with pytest.raises(TypeError, match="imports compiled_helper, a module of your own with no"):
        _module(tmp_path, "helped_pyc", HELPED.format(helper="compiled_helper"), monkeypatch)


def test_a_learner_named_as_a_path_is_refused(registry):
    @dataclasses.dataclass(frozen=True)
    class Escaping:
        name: str = "../x"
        world: WorldConfig = WorldConfig()
        heldout_trials: int = 1

    with pytest.raises(ValueError, match="Escaping.name must be a safe file-name component"):
        learners.register(Escaping, outside.run)
    for name in ("../../../x", "/tmp/x", "a/b", ".."):
        with pytest.raises(ValueError, match="name must be a safe file-name component"):
            kinds.result_path(dataclasses.replace(CONFIG, name=name), 0, "/nonexistent")


CONTESTED = """
import dataclasses

import helper
from docking.study import learners
from docking.study.contest import Knob, Ladder, contest, small_budget
from docking.scene import WorldConfig


@dataclasses.dataclass(frozen=True)
class Helped:
    name: str = "helped"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 2
    k: int = 1
    j: int = 1


def run(config, seed, progress=True, on_trials=None):
    return learners.judge(config, seed, lambda o, env: helper.ACTION, 3, on_trials)


learners.register(Helped, run)
budget = small_budget(rows=1, cols=1, judged=2, heldout_trials=2)
k, j = Knob("k", Ladder((1,), 0, integer=True)), Knob("j", Ladder((1,), 0, integer=True))
found = contest(Helped(), k, j, budget, workers=1, progress=False)
print(sorted({s for sources in found.results.sources.values() for s in sources}))
"""


@pytest.mark.slow
def test_a_helper_edited_between_two_contests_is_recomputed(tmp_path):
    """The issue's case: a contest, then the helper module's constant changed, then the same
    contest: its runs are computed again (they were served stale), and unchanged, stored."""
    (tmp_path / "helper.py").write_text("ACTION = 0\n")
    (tmp_path / "contested.py").write_text(CONTESTED)
    env = {
        **os.environ,
        "PYTHONPATH": f"{tmp_path}{os.pathsep}{ROOT}",
        "DOCKING_RESULTS": str(tmp_path / "results"),
        "DOCKING_LEDGER": str(ROOT / "ledger"),
    }

    def sources() -> str:
        out = subprocess.run(
            [sys.executable, "contested.py"],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert out.returncode == 0, out.stderr[-3000:]
        return out.stdout.strip().splitlines()[-1]

    assert sources() == "['computed']"
    assert sources() == "['store']"
    (tmp_path / "helper.py").write_text("ACTION = 2\n")
    assert sources() == "['computed']"


FAILING = """
import dataclasses
import sys

from docking.study import learners
from docking.scene import WorldConfig
from docking.study.sweep import Job, run_jobs


@dataclasses.dataclass(frozen=True)
class Failing:
    name: str = "failing"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 1


def run(config, seed, progress=True, on_trials=None):
    return helper(seed)


def helper(seed):
    raise ZeroDivisionError(f"the learner's own error, seed {seed}")


learners.register(Failing, run)
run_jobs([Job(Failing(), 0)], sys.argv[1], workers=2, progress=False)
"""


@pytest.mark.slow
def test_a_learners_error_on_the_embedded_cluster_names_the_users_file_and_line(tmp_path):
    script = tmp_path / "failing.py"
    script.write_text(FAILING)
    lines = FAILING.splitlines()
    run_line = lines.index("    return helper(seed)") + 1
    raise_line = next(k for k, line in enumerate(lines) if "raise ZeroDivisionError" in line) + 1
    out = subprocess.run(
        [sys.executable, str(script), str(tmp_path / "results")],
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": str(ROOT), "DOCKING_LEDGER": "off"},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode != 0 and "the learner's own error, seed 0" in out.stderr
    assert "<dynamic-code>" not in out.stderr, out.stderr[-3000:]
    assert f'File "{script}", line {run_line}, in run' in out.stderr, out.stderr[-3000:]
    assert f'File "{script}", line {raise_line}, in helper' in out.stderr


def _started_elsewhere(tmp_path, script: Path, *args: str, timeout: float):
    """``script`` started from a folder of its own (neither the script's nor the clone's),
    with this clone alone on PYTHONPATH: its completed process, and how long it took."""
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir(exist_ok=True)
    start = time.monotonic()
    out = subprocess.run(
        [sys.executable, str(script), *args],
        cwd=elsewhere,
        env={**os.environ, "PYTHONPATH": str(ROOT), "DOCKING_LEDGER": "off"},
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    return out, time.monotonic() - start


@pytest.mark.slow
def test_a_scripts_learner_module_runs_on_the_embedded_cluster_from_another_folder(tmp_path):
    """Issue 62: a learner in a module beside the user's script, with a helper module of its
    own, the script saved outside the clone and started from a third folder. The embedded
    cluster's workers import both (they died of ModuleNotFoundError, and the sweep waited for
    them without a word until it was killed)."""
    script = user_scripts(tmp_path / "scripts")
    out, _ = _started_elsewhere(tmp_path, script, str(tmp_path / "results"), timeout=240)
    assert out.returncode == 0, out.stderr[-3000:]
    paths = [Path(line) for line in out.stdout.split()]
    assert [p.name for p in paths] == ["seed0.npz", "seed1.npz"], out.stdout
    assert all(p.is_file() and p.is_relative_to(tmp_path / "results") for p in paths)
    assert "ModuleNotFoundError" not in out.stderr, out.stderr[-3000:]


#: The user's learner module loaded from a file under another name (as plugin loaders do):
#: no import by its name finds it, in this process or a worker.
LOADS_IT = """
import importlib.util
import sys
from pathlib import Path

from docking.study.sweep import Job, run_jobs

path = Path(__file__).parent / "my-learner.py"
spec = importlib.util.spec_from_file_location("plugin_learner", path)
module = importlib.util.module_from_spec(spec)
sys.modules["plugin_learner"] = module
spec.loader.exec_module(module)
jobs = [Job(module.Steady(), seed) for seed in (0, 1)]
run_jobs(jobs, sys.argv[1], workers=2, progress=False)
"""


@pytest.mark.slow
def test_a_learner_module_no_worker_can_import_stops_the_sweep_at_once_in_one_line(tmp_path):
    folder = tmp_path / "scripts"
    user_scripts(folder)
    (folder / "user_learner.py").rename(folder / "my-learner.py")
    (folder / "loads_it.py").write_text(LOADS_IT)
    out, elapsed = _started_elsewhere(
        tmp_path, folder / "loads_it.py", str(tmp_path / "results"), timeout=120
    )
    assert out.returncode == 1 and elapsed < 30, (elapsed, out.stderr[-3000:])
    last = out.stderr.strip().splitlines()[-1]
    assert last.startswith("docking.study.learners.CodeNotOnWorkers: "), out.stderr[-3000:]
    assert "cannot import plugin_learner" in last and str(folder / "my-learner.py") in last
    assert "not named plugin_learner.py" in last and "save it as such" in last
    assert out.stderr.count("No module named") == 1  # in that line: no worker died of it
    assert not (tmp_path / "results" / "steady").exists()


DYING = """
import dataclasses
import os
import sys

from docking.scene import WorldConfig
from docking.study import learners
from docking.study.sweep import Job, run_jobs


@dataclasses.dataclass(frozen=True)
class Dying:
    name: str = "dying"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 1


def run(config, seed, progress=True, on_trials=None):
    os._exit(3)  # as a worker the kernel kills (out of memory) ends


learners.register(Dying, run)
run_jobs([Job(Dying(), 0)], sys.argv[1], workers=2, progress=False)
"""


@pytest.mark.slow
def test_a_sweep_whose_embedded_workers_all_end_stops_in_one_line(tmp_path):
    """A job that ends its worker, run again by Dask on the other one, which it ends too: the
    sweep says so and stops (it waited for workers that would never come)."""
    script = tmp_path / "dying.py"
    script.write_text(DYING)
    out, elapsed = _started_elsewhere(tmp_path, script, str(tmp_path / "results"), timeout=180)
    assert out.returncode == 1 and elapsed < 60, (elapsed, out.stderr[-3000:])
    last = out.stderr.strip().splitlines()[-1]
    assert last == (
        "RuntimeError: every Dask worker of the sweep has ended, 1 of its jobs unfinished "
        "(the workers' own messages are above)"
    ), out.stderr[-3000:]


CELL = """
import dataclasses

from docking.study import learners
from docking.scene import WorldConfig


@dataclasses.dataclass(frozen=True)
class InCell:
    name: str = "in-cell"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 1


def run(config, seed, progress=True, on_trials=None):
    steps = 3  # three steps
    return learners.judge(config, seed, lambda o, env: 0, steps, on_trials)


runner = learners.register(InCell, run)
"""


def _cell(source: str, name: str):
    """``source`` run as a notebook cell is (no module file; its source in linecache)."""
    linecache.cache[name] = (len(source), None, source.splitlines(keepends=True), name)
    namespace = {"__name__": "__main__"}
    exec(compile(source, name, "exec", dont_inherit=True), namespace)
    return namespace


def test_the_key_follows_the_learners_own_code_in_a_notebook_cell(registry):
    first = _cell(CELL, "<cell 1>")
    assert first["runner"].code.where == ("<cell 1>: InCell", "<cell 1>: run")
    key = kinds.config_key(first["InCell"]())
    reworded = _cell(CELL.replace("# three steps", "# reworded") + "\nx = 1\n", "<cell 2>")
    assert kinds.config_key(reworded["InCell"]()) == key  # a comment; code outside both
    changed = _cell(
        CELL.replace("heldout_trials: int = 1", "heldout_trials: int = 1\n    k: int = 2"),
        "<cell 3>",
    )
    assert kinds.config_key(changed["InCell"](k=2)) != key
    with pytest.raises(TypeError, match="cannot read the source of InCell"):
        exec(compile(CELL, "<no source>", "exec"), {"__name__": "__main__"})


# ------------------------------------------------------------------------------------------
# Stored, served from a ledger, verified.
# ------------------------------------------------------------------------------------------


def test_an_outside_learner_is_stored_and_loaded_not_recomputed(tmp_path, registry):
    computed = store.run_or_load(CONFIG, 0, tmp_path, progress=False)
    assert isinstance(computed, learners.LearnerResult)
    assert len(computed.heldout) == CONFIG.heldout_trials and computed.train_steps > 0
    assert computed.wall_time_train > 0 and computed.wall_time_test > 0
    path = kinds.result_path(CONFIG, 0, tmp_path)
    assert path == tmp_path / "outside" / kinds.config_key(CONFIG)[:16] / "seed0.npz"
    assert (path.parent / "config.json").exists()
    failing = dataclasses.replace(outside.RUNNER, run=lambda *a, **k: pytest.fail("recomputed"))
    kinds.register(failing)
    loaded = store.run_or_load(CONFIG, 0, tmp_path, progress=False)
    assert loaded.train_steps == computed.train_steps and loaded.config == CONFIG
    np.testing.assert_array_equal(loaded.heldout.poses, computed.heldout.poses)
    raw = dict(np.load(path))
    raw["train_steps"] = raw["train_steps"] + 1  # an array edited behind the digest's back
    np.savez(tmp_path / "edited.npz", **raw)
    with pytest.raises(kinds.CorruptResult, match="digest"):
        kinds.load_result(tmp_path / "edited.npz", kinds.run_key(CONFIG, 0))


def test_a_runs_result_is_checked(tmp_path, registry):
    def elsewhere(config, seed, progress=True, on_trials=None):
        return protocol.judge(config, seed + 1, lambda o, env: 0, 0)

    def too_few(config, seed, progress=True, on_trials=None):
        result = protocol.judge(config, seed, lambda o, env: 0, 0)
        result.heldout = protocol.heldout_log(config.world, seed, 1, lambda o, env: 0)
        return result

    for run, error, match in (
        (elsewhere, ValueError, "another configuration or seed"),
        (too_few, ValueError, "returned 1 held-out trials, its configuration asks for 3"),
        (lambda config, seed, **kw: None, TypeError, "not a LearnerResult"),
    ):
        kinds.register(dataclasses.replace(outside.RUNNER, run=_wrapped(run)))
        with pytest.raises(error, match=match):
            store.run_or_load(CONFIG, 0, tmp_path, progress=False)

    def other_stream(config, seed, progress=True, on_trials=None):
        result = protocol.judge(config, seed, lambda o, env: 0, 0)
        result.heldout = protocol.heldout_log(config.world, seed + 1, 3, lambda o, env: 0)
        return result

    kinds.register(dataclasses.replace(outside.RUNNER, run=_wrapped(other_stream)))
    with pytest.raises(ValueError, match="not drawn from the held-out stream of seed 0"):
        store.run_or_load(CONFIG, 0, tmp_path, progress=False)


def _wrapped(run):
    import functools

    return functools.partial(learners._run, run)


def test_a_learners_class_carries_its_runner_to_another_process(registry):
    """A Dask worker that receives a learner's class by value adopts its runner (simulated:
    the registry emptied); a class whose name this process registered otherwise is not."""
    del kinds.RUNNERS[outside.RandomFeatures], kinds._BY_NAME["random-features"]
    assert kinds.runner_for(CONFIG) is outside.RUNNER
    assert kinds.runner_named("random-features") is outside.RUNNER
    kinds.register(outside.RUNNER)  # registered here: no class carrying one of its name wins

    @dataclasses.dataclass(frozen=True)
    class Impostor(outside.RandomFeatures):
        pass

    Impostor._docking_runner = dataclasses.replace(outside.RUNNER, config_type=Impostor)
    with pytest.raises(TypeError, match="registered with docking.study.learners.register"):
        kinds.runner_for(Impostor())


@pytest.fixture
def learner_ledger(tmp_path, monkeypatch):
    """Two runs of the outside learner in a store, and a ledger of them in a temporary folder
    (seed 0 kept whole, seed 1 as a row of its table)."""
    results, folder = tmp_path / "results", tmp_path / "ledger"
    runs = [store.run_or_load(CONFIG, seed, results, progress=False) for seed in (0, 1)]
    data = ledger.update(
        [(CONFIG, 0, True, frozenset()), (CONFIG, 1, False, frozenset())], folder, results
    )
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    return runs, data, folder


def test_an_outside_learners_runs_are_served_from_a_ledger(learner_ledger, tmp_path, registry):
    runs, data, folder = learner_ledger
    assert data["fingerprints"] == {"random-features": outside.RUNNER.fingerprint()}
    assert data["modules"]["random-features"]["own code"] == outside.RUNNER.code.digest
    empty = tmp_path / "empty"
    for run in runs:
        served = load_run(CONFIG, run.seed, empty)
        assert isinstance(served, learners.LearnerResult)
        np.testing.assert_array_equal(served.heldout.success, run.heldout.success)
        np.testing.assert_array_equal(served.heldout.steps, run.heldout.steps)
        assert served.train_steps == run.train_steps
    assert load_run(CONFIG, 0, empty).heldout.poses is not None  # kept whole
    assert load_run(CONFIG, 1, empty).heldout.poses is None  # a row of its table
    assert load_run(CONFIG, 2, empty) is None
    # a ledger computed by the learner's earlier code is refused, naming its own code
    code = dataclasses.replace(outside.RUNNER.code, digest="0" * 64)
    kinds.register(dataclasses.replace(outside.RUNNER, code=code))
    with pytest.raises(ledger.StaleLedger, match="own code"):
        load_run(CONFIG, 1, empty)


def test_an_outside_learners_runs_are_verified(learner_ledger):
    _, data, folder = learner_ledger
    sampled = verify.chosen(ledger.manifest(folder), 1, "a commit")
    assert len(sampled) == 1 and data["runs"][sampled[0]]["runner"] == "random-features"
    checks = verify.verify(None, workers=1, progress=False, folder=folder)
    found = sorted((c.name, c.seed, c.ok) for c in checks)
    assert found == [("outside", 0, True), ("outside", 1, True)]


@pytest.mark.slow
def test_the_command_line_verifies_an_outside_learners_runs(learner_ledger):
    """``python -m docking verify`` imports the learner's module (DOCKING_LEARNERS) and
    recomputes its runs on the embedded Dask cluster, whose workers import it by name."""
    _, _, folder = learner_ledger
    env = {
        **os.environ,
        "DOCKING_LEARNERS": "outside_learner",
        "DOCKING_LEDGER": str(folder),
        "PYTHONPATH": str(Path(__file__).parent),
    }
    out = subprocess.run(
        [sys.executable, "-m", "docking", "verify", "--all"],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    assert "2 of 2 recomputed runs equal the ledger" in out.stdout
    without = {k: v for k, v in env.items() if k != "DOCKING_LEARNERS"}
    out = subprocess.run(
        [sys.executable, "-m", "docking", "verify", "--all"],
        capture_output=True,
        text=True,
        env=without,
        timeout=600,
    )
    assert out.returncode != 0 and "DOCKING_LEARNERS" in out.stderr


# ------------------------------------------------------------------------------------------
# The contest.
# ------------------------------------------------------------------------------------------


def _published_linear(world, **setting):
    """The equal contest's linear SARSA in ``world`` with ``setting``, under the name its
    ledger runs of that point hold (a grid point the ledger held before the contest keeps its
    table's name): what its search ran."""
    from docking.study.contest import WORLDS
    from docking.study.designs import equal_contest as ec

    world = next(k for k, found in WORLDS.items() if found == world)  # the world's key
    search, knobs = ec.SEARCH, ec.KNOBS["linear"]
    e = search.entrants["linear"]
    for r in range(-3, 13):
        for c in range(-3, 8):
            if (e.row.ladder.value(r), e.col.ladder.value(c)) == tuple(setting[k] for k in knobs):
                name = search._stored(world, "linear", (r, c))
                return ec.learner_config(world, "linear", name, **setting)
    raise AssertionError(f"{setting} is no point of the ladders")


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason=(
        "known, found when the equal contest's runs landed: the contest stores a grid point's "
        "grid-seed runs under the earlier table that held them (fragility-landscape) and its "
        "selection and judged runs under its own name, while a learner given as "
        "make(world, **setting) names its configuration once for every seed; so the contest "
        "of the published linear SARSA recomputes the 24 selection and judged runs of its "
        "floor-world point (10, 0.1) under the earlier name instead of reading them"
    ),
)
def test_the_contest_of_the_published_linear_sarsa_is_the_published_row(tmp_path, monkeypatch):
    """The package's linear SARSA entered with its published knobs and the contest's budget:
    every run is the ledger's (none computed), the chosen settings and the judged runs are the
    published ones, its lead over itself is 0 on every seed (no interval, no test)."""
    from docking.study.designs import equal_contest as ec
    from docking.study.designs import equal_contest_report as ecr

    monkeypatch.delenv("DOCKING_LEDGER")  # the committed ledger
    monkeypatch.setattr("docking.study.kinds.run_experiment", lambda *a, **k: pytest.fail("ran"))
    e = ec.SEARCH.entrants["linear"]
    found = contest(
        _published_linear, e.row, e.col, label="lin", results_dir=tmp_path, progress=False
    )
    assert {s for sources in found.results.sources.values() for s in sources} == {"ledger"}
    chosen = ecr.chosen(ec.DESIGN.read())
    for world in ec.WORLDS:
        assert found.chosen[world] == chosen[world, "linear"]
        np.testing.assert_array_equal(
            found.results.score(f"{world}/lin/judged"),
            found.published.score(f"{world}/linear/judged"),
        )
        same = found.verdicts[world, "linear"]
        assert same["lead"] == 0.0 and same.get("spread") is False
    assert "the same on every seed: no interval, no test" in found.table
    assert "| **lin, chosen (yours)** | 20 | 500 |" in found.table
    assert found.budget.is_the_contest and "**The equal contest's budget**" in found.table


def test_a_contest_budget_is_checked():
    from docking.study.designs import equal_contest as ec

    assert CONTEST_BUDGET.runs == ec.SEARCH.runs_per_learner() + len(ec.SEEDS) == 152
    assert CONTEST_BUDGET.is_the_contest
    assert CONTEST_BUDGET.describe().startswith("**The equal contest's budget**")
    small = small_budget()
    assert small.smaller and small.describe().startswith("**Not the contest: a smaller budget**")
    with pytest.raises(ValueError, match="Budget.judged must be in"):
        Budget(judged=1)
    with pytest.raises(ValueError, match="worlds"):
        Budget(worlds=("moon",))
    rows, cols = Knob("alpha", Ladder((1, 2, 5), -2)), Knob("epsilon", Ladder((1, 3), -2))
    with pytest.raises(ValueError, match="names a published learner"):
        contest(CONFIG, rows, cols, small, label="linear")

    @dataclasses.dataclass(frozen=True)
    class Unregistered:
        name: str = "unregistered"
        world: object = None
        heldout_trials: int = 1
        alpha: float = 0.1
        epsilon: float = 0.1

    with pytest.raises(TypeError, match="registered with docking.study.learners.register"):
        contest(Unregistered(), rows, cols, small)


def test_the_contest_reads_the_published_rows_and_never_computes_them(tmp_path):
    """With no ledger, the contest fails before it computes anything."""
    rows, cols = Knob("alpha", Ladder((1, 2, 5), -2)), Knob("epsilon", Ladder((1, 3), -2))
    with pytest.raises(LookupError, match="published contest's rows are read from"):
        contest(CONFIG, rows, cols, small_budget(), results_dir=tmp_path)
    assert not any(tmp_path.iterdir())


# ------------------------------------------------------------------------------------------
# The guide.
# ------------------------------------------------------------------------------------------


def _guide_example() -> str:
    (code,) = re.findall(r"```python\n(.*?)```", GUIDE.read_text(), re.S)
    return code


def test_the_guides_example_is_at_most_40_lines_of_a_new_kind_of_learner():
    code = _guide_example()
    assert len([line for line in code.splitlines() if line.strip()]) <= 40
    assert "learners.register(" in code and "contest(" in code and "small_budget(" in code
    assert "guide/bring_your_own_learner.md" in (ROOT / "docs" / "mkdocs.yml").read_text()


@pytest.mark.slow
def test_the_guides_example_run_as_a_script_from_another_folder_prints_its_table(tmp_path):
    """The guide's example saved as a script in a folder of its own and started from another
    (issue 62), by a Python without the [ppo] extra (issue 59): its learner runs on the
    embedded cluster's workers and it prints its table, every published row (PPO's too) read
    from the ledger, its verdicts against the equal contest's judged rows; run again, it reads
    its stored runs."""
    folder, elsewhere = tmp_path / "mine", tmp_path / "elsewhere"
    folder.mkdir()
    elsewhere.mkdir()
    (folder / "kmeans_contest.py").write_text(_guide_example())
    env = {
        **os.environ,
        "DOCKING_RESULTS": str(tmp_path / "results"),
        "DOCKING_LEDGER": str(ROOT / "ledger"),
    }
    python, env = without_extra(tmp_path, env)
    check = "import importlib.util as u; assert u.find_spec('skrl') is None"
    assert subprocess.run([*python, "-c", check], env=env).returncode == 0

    def table() -> str:
        out = subprocess.run(
            [*python, str(folder / "kmeans_contest.py")],
            cwd=elsewhere,
            env=env,
            capture_output=True,
            text=True,
            timeout=900,
        )
        assert out.returncode == 0, out.stderr[-3000:]
        return out.stdout

    first = table()
    assert first.startswith("**Not the contest: a smaller budget**")
    rows = [line for line in first.splitlines() if line.startswith("| ")]
    assert any(r.startswith("| **kmeans-q, chosen (yours)** | 3 | 20 |") for r in rows)
    assert any(r.startswith("| linear SARSA, chosen | 20 | 500 |") for r in rows)
    assert any(r.startswith("| pose oracle | 5 | 500 |") for r in rows)
    assert any(r.startswith("| sideboard | PPO |") for r in rows)  # read without the extra
    assert "(the equal contest's rules)" in first and "3000-3019" not in first
    assert "computed now" in first and "none read" in first
    assert "0 computed now" in table()
