"""One kind of run (issue point 4): every run, the learner's or PPO's, goes through one
registry of runners (docking.study.kinds.runner_for), one store and one ledger."""

from __future__ import annotations

import collections
import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import TINY

from docking.experiments import ExperimentConfig, TrialLog, run_experiment
from docking.presets import EXPERIMENT_2
from docking.study import kinds, ledger, ledger_rows, runs, store, sweep
from docking.study.ppo import PPOConfig, PPOResult
from docking.study.runs import load_run

PPO_TINY = PPOConfig(name="ppo-tiny", world=EXPERIMENT_2.world, steps=64, envs=2, heldout_trials=2)
PACKAGE = Path(store.__file__).resolve().parents[1]


def _ppo_result(seed: int = 0) -> PPOResult:
    """A PPO run built by hand (a real one needs JAX and minutes): two training episodes and
    two held-out trials of 2 and 1 actions."""
    heldout = TrialLog(
        success=np.array([True, False]),
        steps=np.array([2, 1], dtype=np.int64),
        start_far=np.array([1.5, 1.5]),
        poses=np.arange(15, dtype=np.float64).reshape(5, 3) / 10,
        actions=np.array([0, 1, 2], dtype=np.int64),
        winners=np.full(3, -1, dtype=np.int64),
        deltas=np.zeros(3),
    )
    return PPOResult(
        config=PPO_TINY,
        seed=seed,
        train_success=np.array([False, True]),
        train_steps=np.array([25, 7], dtype=np.int64),
        heldout=heldout,
        wall_time_train=1.5,
        wall_time_test=0.5,
    )


def test_an_unknown_configuration_type_is_a_clear_type_error():
    with pytest.raises(TypeError, match="ExperimentConfig or PPOConfig, got"):
        kinds.runner_for({"name": "not a config"})
    with pytest.raises(TypeError, match="ExperimentConfig or PPOConfig"):
        kinds.run_key(TINY.to_dict(), 0)
    assert kinds.runner_for(TINY) is kinds.LEARNER and kinds.runner_for(PPO_TINY) is kinds.PPO
    with pytest.raises(ValueError, match="no kind of run is called 'nope'"):
        kinds.runner_named("nope")


def test_no_code_path_is_chosen_by_isinstance_on_the_kind_of_run():
    """The kind of run is looked up (runner_for), never tested with isinstance."""
    kinds = re.compile(r"isinstance\(.*(PPOConfig|ExperimentConfig|CONFIG_TYPES|PPOResult)")
    found = [
        f"{path.name}:{number}: {line.strip()}"
        for path in sorted(PACKAGE.rglob("*.py"))
        for number, line in enumerate(path.read_text().splitlines(), 1)
        if "isinstance" in line and kinds.search(line)
    ]
    assert found == []


def _assert_same(a, b):
    for name, array in kinds.runner_for(a.config).arrays(a).items():
        np.testing.assert_array_equal(array, kinds.runner_for(b.config).arrays(b)[name])
        assert array.dtype == kinds.runner_for(b.config).arrays(b)[name].dtype


def test_both_kinds_round_trip_through_the_one_store(tmp_path):
    learner = run_experiment(TINY, 0, progress=False)
    for result in (learner, _ppo_result()):
        config = result.config
        path = kinds.result_path(config, 0, tmp_path)
        assert path == tmp_path / config.name / kinds.run_key(config, 0)[:16] / "seed0.npz"
        kinds.save_result(result, path)
        loaded = kinds.load_result(path, kinds.run_key(config, 0))
        assert type(loaded) is type(result) and loaded.config == config
        _assert_same(loaded, result)
        assert (path.parent / "config.json").exists()
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            assert meta["runner"] == kinds.runner_for(config).name
            assert meta["digest"] == kinds.content_digest(data)
        with pytest.raises(kinds.CorruptResult, match="not the run asked for"):
            kinds.load_result(path, kinds.run_key(config, 1))  # the key check
        raw = dict(np.load(path))
        name = next(n for n in raw if n != "meta" and raw[n].size and raw[n].dtype.kind == "i")
        raw[name] = raw[name] + 1  # arrays edited behind the meta record's back
        np.savez(tmp_path / "t.npz", **raw)
        with pytest.raises(kinds.CorruptResult):
            kinds.load_result(tmp_path / "t.npz", kinds.run_key(config, 0))
    # the keys of the two kinds never meet
    assert kinds.run_key(TINY, 0) != kinds.run_key(PPO_TINY, 0)


def test_a_stored_ppo_run_is_loaded_not_recomputed(tmp_path, monkeypatch):
    result = _ppo_result(3)
    kinds.save_result(result, kinds.result_path(PPO_TINY, 3, tmp_path))
    monkeypatch.setattr("docking.study.ppo.run_ppo", lambda *a, **k: pytest.fail("recomputed"))
    _assert_same(store.run_or_load(PPO_TINY, 3, tmp_path, progress=False), result)


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    """A store of a learner's run and a PPO run, and the ledger written from it (both as rows
    of their results tables)."""
    base = tmp_path_factory.mktemp("both")
    results, folder = base / "results", base / "ledger"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        learner = store.run_or_load(TINY, 0, results, progress=False)
        ppo_run = _ppo_result()
        kinds.save_result(ppo_run, kinds.result_path(PPO_TINY, 0, results))
    runs = [(TINY, 0, False, frozenset()), (PPO_TINY, 0, False, frozenset())]
    data = ledger.update(runs, folder, results)
    return folder, data, learner, ppo_run


def test_the_ledger_holds_both_kinds_in_one_table(both, monkeypatch, tmp_path):
    folder, data, learner, ppo_run = both
    keys = {"learner": kinds.run_key(TINY, 0), "ppo": kinds.run_key(PPO_TINY, 0)}
    assert set(data["runs"]) == set(keys.values()) and "ppo_runs" not in data
    assert {data["runs"][k]["runner"] for k in keys.values()} == set(keys)
    assert data["fingerprints"] == {n: kinds.runner_named(n).fingerprint() for n in keys}
    assert (
        "docking.study.ppo" in data["modules"]["ppo"]
        and "docking.study.ppo" not in data["modules"]["learner"]
    )
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    empty = tmp_path / "empty-store"
    served = load_run(TINY, 0, empty)
    np.testing.assert_array_equal(served.test.success, learner.test.success)
    served = load_run(PPO_TINY, 0, empty)
    assert isinstance(served, PPOResult) and served.wall_time_train == 1.5
    np.testing.assert_array_equal(served.train_steps, ppo_run.train_steps)
    np.testing.assert_array_equal(served.heldout.success, ppo_run.heldout.success)
    with pytest.raises(ledger_rows.NotInLedger, match="path of trial 0"):
        served.heldout.trial_poses(0)
    assert ledger.holds(PPO_TINY, 0, check=True) and not ledger.holds(PPO_TINY, 1)


@pytest.mark.parametrize(
    ("stale", "module", "config", "fresh"),
    [("ppo", "docking.study.ppo", PPO_TINY, TINY), ("learner", "docking.network", TINY, PPO_TINY)],
)
def test_a_stale_run_names_the_changed_modules_of_its_runner(
    both, monkeypatch, tmp_path, stale, module, config, fresh
):
    folder, *_ = both
    copy = tmp_path / "ledger"
    import shutil

    shutil.copytree(folder, copy)
    data = json.loads((copy / "manifest.json").read_text())
    data["fingerprints"][stale] = "0" * 64  # as if that runner's code had changed since
    data["modules"][stale][module] = "0" * 64
    (copy / "manifest.json").write_text(json.dumps(data))
    ledger._read_manifest.cache_clear()
    monkeypatch.setenv("DOCKING_LEDGER", str(copy))
    with pytest.raises(ledger.StaleLedger, match=rf"{stale} runs computed by other code.*{module}"):
        load_run(config, 0, tmp_path / "empty-store")
    with pytest.raises(ledger.StaleLedger, match=module):
        ledger.holds(config, 0, check=True)
    assert load_run(fresh, 0, tmp_path / "empty-store").seed == 0  # the other runner's: served
    with pytest.raises(ledger.StaleLedger, match=module):
        ledger.manifest(copy)  # the ledger as a whole holds a stale run


# One path from a command to its stored run (issue 51).

#: The modules a configuration's path is counted through.
WATCHED = ("docking.study.store", "docking.study.ledger")


def _entries(call) -> dict[tuple[str, int], collections.Counter]:
    """Run ``call()`` under a profiler: per (configuration name, seed) of a run, how many
    times its configuration entered each module of :data:`WATCHED` from another module (a
    call into it with the configuration among its arguments, or an argument that holds it:
    a job, a run)."""
    found: dict = collections.defaultdict(collections.Counter)

    def profile(frame, event, arg):
        if event != "call":
            return
        module = frame.f_globals.get("__name__")
        if module not in WATCHED or frame.f_back is None:
            return
        if frame.f_back.f_globals.get("__name__") == module:
            return
        args = frame.f_locals
        seed = args.get("seed")
        for value in list(args.values()):
            config = (
                value if isinstance(value, ExperimentConfig) else getattr(value, "config", None)
            )
            if isinstance(config, ExperimentConfig):
                found[config.name, seed][module] += 1
                return

    sys.setprofile(profile)
    try:
        call()
    finally:
        sys.setprofile(None)
    return found


def test_a_commands_configuration_enters_the_store_and_the_ledger_once_each(
    tmp_path, monkeypatch, capsys
):
    """``python -m docking run`` of two seeds (in this process): each job is located once
    (:func:`docking.study.runs.locate`), and its configuration enters the store once (to store
    the run computed, or to read the stored one) and the ledger at most once (when the store
    holds no file of it), whichever of the three places its run comes from."""
    from docking.study import cli

    results, folder = tmp_path / "results", tmp_path / "ledger"
    args = ["run", "experiment1", "--seeds", "0,1", "--processes", "1", "--name", "tiny-run"]
    args += ["--train-trials", "2", "--test-trials", "1", "--eval-every", "2"]
    args += ["--eval-trials", "1", "--results-dir"]
    calls = []
    real = runs.locate
    monkeypatch.setattr(runs, "locate", lambda *a, **k: calls.append(a[:2]) or real(*a, **k))
    monkeypatch.setattr(sweep, "locate", runs.locate)

    monkeypatch.setenv("DOCKING_LEDGER", "off")
    computed = _entries(lambda: cli.main([*args, str(results)]))
    assert "seeds 0-1: computed now" in capsys.readouterr().out
    stored = _entries(lambda: cli.main([*args, str(results)]))
    assert "seeds 0-1: loaded from the results store" in capsys.readouterr().out
    config = cli.parse([*args, str(results)]).experiment
    ledger.update([(config, s, False, frozenset()) for s in (0, 1)], folder, results)
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    served = _entries(lambda: cli.main([*args, str(tmp_path / "empty")]))
    assert "seeds 0-1: read from the committed ledger" in capsys.readouterr().out

    assert len(calls) == 6 and sorted(s for _, s in calls) == [0, 0, 0, 1, 1, 1]  # once a job
    jobs = [("tiny-run", 0), ("tiny-run", 1)]
    once = {"docking.study.store": 1, "docking.study.ledger": 1}
    assert {job: dict(computed[job]) for job in jobs} == dict.fromkeys(jobs, once)
    assert {job: dict(stored[job]) for job in jobs} == dict.fromkeys(
        jobs, {"docking.study.store": 1}
    )
    assert {job: dict(served[job]) for job in jobs} == dict.fromkeys(
        jobs, {"docking.study.ledger": 1}
    )


def test_the_store_and_the_ledger_do_not_import_each_other():
    """Neither module imports the other (the import contract's row ``ledger | store`` keeps it
    for every import, a function's own included)."""
    for module, other in ((ledger, "store"), (store, "ledger")):
        imports = [
            line
            for line in Path(module.__file__).read_text().splitlines()
            if line.strip().startswith(("from docking", "import docking"))
        ]
        assert imports and not [line for line in imports if re.search(rf"\b{other}\b", line)]
