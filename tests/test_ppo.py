"""The pixel-level bound (docking.study.ppo): its configuration, key, storage (the one store,
docking.study.store, through its runner "ppo") and streams."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from docking.presets import EXPERIMENT_2
from docking.study.kinds import PPO, CorruptResult, result_path, run_key, source_fingerprint
from docking.study.kinds import load_result as load
from docking.study.kinds import save_result as save
from docking.study.ppo import PPOConfig, result_arrays, run_ppo, trials_in_run
from docking.study.runs import load_run
from docking.study.store import run_or_load

TINY = PPOConfig(name="ppo-test", world=EXPERIMENT_2.world, steps=64, envs=2, heldout_trials=3)


@pytest.mark.parametrize(
    ("changes", "says"),
    [
        ({"steps": 0}, "PPOConfig.steps"),
        ({"learning_rate": 0.0}, "PPOConfig.learning_rate"),
        ({"hidden": ()}, "PPOConfig.hidden"),
        ({"hidden": (64, 0)}, "PPOConfig.hidden"),
        ({"mini_batches": 300}, "mini_batches"),
        ({"steps": 51}, "multiple of envs"),
        ({"envs": 0}, "PPOConfig.envs"),
        ({"name": "../x"}, "PPOConfig.name"),
        ({"world": "floor"}, "PPOConfig.world"),
    ],
)
def test_bad_configurations_are_clear_errors(changes, says):
    with pytest.raises((ValueError, TypeError), match=says.replace(".", r"\.")):
        dataclasses.replace(TINY, **changes)


def test_configuration_round_trips_and_refuses_unknown_fields():
    assert PPOConfig.from_dict(TINY.to_dict()) == TINY
    with pytest.raises(TypeError, match="no field nope"):
        PPOConfig.from_dict({**TINY.to_dict(), "nope": 1})


def test_key_covers_its_own_code_and_libraries():
    assert PPO.fingerprint() != source_fingerprint()
    assert run_key(TINY, 0) != run_key(TINY, 1)
    assert run_key(TINY, 0) != run_key(dataclasses.replace(TINY, steps=66), 0)


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ppo")
    reported = []
    result = run_or_load(TINY, 0, folder, progress=False, on_trials=reported.append)
    assert sum(reported) == trials_in_run(TINY) == 64 // 25 + 3
    return folder, result


@pytest.mark.slow
def test_a_run_is_repeatable_bit_for_bit_and_stored_under_its_key(tiny_run, tmp_path):
    folder, first = tiny_run
    again = run_or_load(TINY, 0, tmp_path, progress=False)
    for name in ("train_success", "train_steps"):
        np.testing.assert_array_equal(getattr(first, name), getattr(again, name))
    for field in dataclasses.fields(first.heldout):
        np.testing.assert_array_equal(
            getattr(first.heldout, field.name), getattr(again.heldout, field.name)
        )
    assert first.train_steps.sum() <= TINY.steps and len(first.heldout) == 3
    path = result_path(TINY, 0, folder)
    assert load(path, run_key(TINY, 0)).heldout_success == first.heldout_success
    with pytest.raises(CorruptResult, match="not"):
        load(path, run_key(TINY, 1))  # a file of another run is refused
    tampered = dataclasses.replace(first, train_steps=first.train_steps + 1)
    save(tampered, tmp_path / "t.npz")
    raw = dict(np.load(tmp_path / "t.npz"))
    raw["train.steps"] = first.train_steps  # arrays edited behind the meta record's back
    np.savez(tmp_path / "t.npz", **raw)
    with pytest.raises(CorruptResult, match="digest"):
        load(tmp_path / "t.npz", run_key(TINY, 0))


@pytest.mark.slow
def test_it_is_judged_on_the_learners_heldout_streams(tiny_run):
    """The first held-out trial starts where a learner's (or yardstick's) of the same seed does."""
    from docking.experiments import heldout_trials

    _, result = tiny_run
    yardstick = dataclasses.replace(
        EXPERIMENT_2,
        policy="forward",
        train_trials=0,
        eval_trials=0,
        test_trials=0,
        heldout_trials=1,
    )
    log = heldout_trials(yardstick, 0, None, EXPERIMENT_2.world)
    np.testing.assert_array_equal(log.trial_poses(0)[0], result.heldout.trial_poses(0)[0])


@pytest.mark.slow
def test_a_sweep_runs_ppo_jobs_beside_the_learners(tmp_path):
    """PPO runs go through the same sweep as the learner's: stored under their key, loaded
    on the next call instead of recomputed."""
    from docking.study.sweep import run_configs

    runs = run_configs({"ppo": TINY}, [1], tmp_path, workers=1, progress=False)
    (first,) = runs["ppo"]
    assert result_path(TINY, 1, tmp_path).exists() and len(first.heldout) == 3
    stamp = result_path(TINY, 1, tmp_path).stat().st_mtime_ns
    (again,) = run_configs({"ppo": TINY}, [1], tmp_path, workers=1, progress=False)["ppo"]
    assert result_path(TINY, 1, tmp_path).stat().st_mtime_ns == stamp
    np.testing.assert_array_equal(first.heldout.success, again.heldout.success)


def test_a_design_cell_may_be_the_pixel_level_bound_but_not_test_only():
    from docking.study.design import Cell

    cell = Cell("w/ppo", TINY, {"world": "w"}, seeds=(0, 1))
    assert cell.trained and cell.world == TINY.world
    with pytest.raises(ValueError, match="PPO cell cannot be test-only"):
        Cell("w/ppo-test", TINY, baseline="w/ppo", test_world=TINY.world)
    with pytest.raises(TypeError, match="config"):
        Cell("w/x", TINY.to_dict())


@pytest.mark.slow
def test_the_ledger_serves_a_ppo_run_and_refuses_one_of_other_code(tiny_run, tmp_path, monkeypatch):
    """A PPO run enters the ledger's results table (training episodes, held-out per-trial
    arrays); served from it bit for bit; per-step data is not kept; other code is refused."""
    import json

    from docking.study import ledger, ledger_rows
    from docking.study.sweep import run_configs

    folder, stored = tiny_run
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    data = ledger.update([(TINY, 0, False, frozenset())], tmp_path / "ledger", folder)
    assert set(data["runs"]) == {run_key(TINY, 0)}
    assert data["runs"][run_key(TINY, 0)]["runner"] == "ppo" and set(data["fingerprints"]) == {
        "ppo"
    }
    from docking.study.verify import verify

    (check,) = verify(None, workers=1, progress=False, folder=tmp_path / "ledger")
    assert check.ok and check.key == run_key(TINY, 0)  # --all recomputes the PPO run too
    monkeypatch.setenv("DOCKING_LEDGER", str(tmp_path / "ledger"))
    served = load_run(TINY, 0, tmp_path / "empty-store")
    np.testing.assert_array_equal(served.train_success, stored.train_success)
    np.testing.assert_array_equal(served.heldout.success, stored.heldout.success)
    np.testing.assert_array_equal(served.heldout.steps, stored.heldout.steps)
    with pytest.raises(ledger_rows.NotInLedger, match="path of trial 0"):
        served.heldout.trial_poses(0)
    monkeypatch.setattr("docking.study.ppo.run_ppo", lambda *a, **k: pytest.fail("recomputed"))
    (again,) = run_configs({"p": TINY}, [0], tmp_path / "s", workers=1, progress=False)["p"]
    assert again.heldout_success == stored.heldout_success
    manifest = tmp_path / "ledger" / "manifest.json"
    raw = json.loads(manifest.read_text())
    raw["fingerprints"]["ppo"] = "0" * 64  # as if docking.study.ppo had changed since
    manifest.write_text(json.dumps(raw))
    with pytest.raises(ledger.StaleLedger, match="ppo runs computed by other code"):
        load_run(TINY, 0, tmp_path / "empty-store")


@pytest.mark.slow
def test_continuous_actions_take_a_gaussian_policy_and_act_with_its_mean(monkeypatch):
    """A world with a step vector (the paper's future work): PPO learns a Gaussian policy
    from its samples as drawn (some beyond [-1, 1]) while the world gets them clipped, its
    greedy held-out actions are vectors in [-1, 1], and a run repeats bit for bit."""
    import gymnasium

    from docking.study.kinds import content_digest

    seen = {"drawn": [], "sent": []}
    clip = gymnasium.wrappers.ClipAction.action

    def action(self, a):
        seen["drawn"].append(np.array(a))
        seen["sent"].append(clip(self, a))
        return seen["sent"][-1]

    monkeypatch.setattr(gymnasium.wrappers.ClipAction, "action", action)
    world = dataclasses.replace(EXPERIMENT_2.world, actions="continuous")
    config = dataclasses.replace(TINY, world=world)
    first, again = run_ppo(config, 3, progress=False), run_ppo(config, 3, progress=False)
    drawn, sent = np.abs(seen["drawn"]), np.abs(seen["sent"])
    assert drawn.max() > 1 and sent.max() <= 1 and np.isfinite(drawn).all()
    assert content_digest(result_arrays(first)) == content_digest(result_arrays(again))
    assert len(first.heldout) == config.heldout_trials
    assert (first.heldout.actions == -1).all()  # the log's mark of a vector action
