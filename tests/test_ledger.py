"""The results ledger (issue 16) and the store's checks of what it serves (issue 17)."""

import dataclasses
import io
import json
import os
import shutil
import subprocess
import sys
import textwrap
import zipfile

import numpy as np
import pytest
from helpers import SEEDS, TINY

from docking import ledger, store, verify
from docking.experiments import run_experiment
from docking.ledger import load_run
from docking.store import (
    CorruptResult,
    StaleCode,
    content_digest,
    load_result,
    result_path,
    run_key,
    run_or_load,
    save_result,
)

ROOT = os.path.dirname(os.path.dirname(store.__file__))


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A store of two tiny runs, read under tracing as an analysis would (the network of
    seed 0, one test trial's poses, the training start poses and far edges, every held-out
    action of seed 1), and the ledger written from that trace."""
    base = tmp_path_factory.mktemp("ledger")
    results, trace, folder = base / "results", base / "trace.jsonl", base / "ledger"
    env = {"DOCKING_TRACE": str(trace), "DOCKING_LEDGER": "off"}
    with pytest.MonkeyPatch.context() as mp:
        for name, value in env.items():
            mp.setenv(name, value)
        runs = [run_or_load(TINY, s, results, progress=False) for s in SEEDS]  # computes
        runs = [load_run(TINY, s, results) for s in SEEDS]  # loads, traced
        assert all(isinstance(r, ledger.TracedResult) for r in runs)
        read = [runs[0].network.W, runs[0].test.trial_poses(2), runs[0].train.starts]
        read.append(runs[0].train.start_far)
        read.append(runs[1].heldout.actions)
    keep = ledger.read_trace(trace.read_text().splitlines())
    assert set(keep) == {run_key(TINY, s) for s in SEEDS}
    data = ledger.update(keep, folder)
    full = [load_result(result_path(TINY, s, results)) for s in SEEDS]
    return folder, data, full, results


def _served(monkeypatch, folder, seed):
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    monkeypatch.delenv("DOCKING_TRACE", raising=False)
    return load_run(TINY, seed, "/nonexistent-store")


def test_the_ledger_serves_what_was_read_bit_for_bit(built, monkeypatch):
    folder, data, full, _ = built
    a, b = (_served(monkeypatch, folder, s) for s in SEEDS)
    assert isinstance(a, ledger.LedgerResult) and isinstance(b, ledger.LedgerResult)
    # Per-trial arrays: success always; the others where read, or (steps) where a trial's
    # per-step data is kept (the test poses of seed 0, the held-out actions of seed 1).
    kept = {(0, "train", "start_far"), (0, "test", "steps"), (1, "heldout", "steps")}
    for seed, served, stored in zip(SEEDS, (a, b), full, strict=True):
        for part in ("train", "test", "heldout"):
            for name in ("success", "steps", "start_far"):
                if name == "success" or (seed, part, name) in kept:
                    np.testing.assert_array_equal(
                        getattr(getattr(served, part), name), getattr(getattr(stored, part), name)
                    )
                else:
                    with pytest.raises(ledger.NotInLedger, match=f"{name} of every trial"):
                        getattr(getattr(served, part), name)
        np.testing.assert_array_equal(served.curve_success, stored.curve_success)
        assert served.test.success_rate == stored.test.success_rate
    np.testing.assert_array_equal(a.network.W, full[0].network.W)
    np.testing.assert_array_equal(a.network.Q, full[0].network.Q)
    np.testing.assert_array_equal(a.test.trial_poses(2), full[0].test.trial_poses(2))
    with pytest.raises(ledger.NotInLedger, match="actions of trial 2"):
        a.test.trial_actions(2)  # its poses were read, not its actions: only they are kept
    np.testing.assert_array_equal(a.train.starts, full[0].train.starts)
    np.testing.assert_array_equal(b.heldout.actions, full[1].heldout.actions)
    # What no analysis read is not there, and saying so is an error, never a substitute.
    with pytest.raises(ledger.NotInLedger, match="W and Q are not kept"):
        _ = b.network
    with pytest.raises(ledger.NotInLedger, match="poses of trial 1"):
        a.test.trial_poses(1)
    with pytest.raises(ledger.NotInLedger, match="deltas of every trial"):
        _ = a.train.deltas


def test_the_manifest_records_each_runs_digest(built):
    folder, data, full, results = built
    for s in SEEDS:
        record = data["runs"][run_key(TINY, s)]
        with np.load(result_path(TINY, s, results)) as f:
            assert record["digest"] == content_digest(f)
        assert record["seed"] == s and record["name"] == "tiny"


def test_sweeps_do_not_recompute_what_the_ledger_holds(built, monkeypatch, tmp_path):
    from docking.sweep import run_configs

    folder, *_ = built
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    monkeypatch.setattr(store, "run_experiment", _refuse)
    found = run_configs({"tiny": TINY}, SEEDS, tmp_path, workers=1, progress=False)
    assert [r.seed for r in found["tiny"]] == list(SEEDS)
    assert not any(tmp_path.rglob("*.npz"))


def _refuse(*args, **kwargs):
    raise AssertionError("a run the ledger holds was recomputed")


def test_a_tampered_entry_is_refused(built, monkeypatch, tmp_path):
    folder, *_ = built
    copy = tmp_path / "ledger"
    shutil.copytree(folder, copy)
    entry = next(copy.glob("runs/**/seed0.xz"))
    entry.write_bytes(entry.read_bytes()[:-10] + b"0123456789")
    with pytest.raises(ledger.StaleLedger, match="does not match its digest"):
        _served(monkeypatch, copy, 0)


def test_a_ledger_of_another_layout_is_refused(built, monkeypatch, tmp_path):
    folder, *_ = built
    copy = tmp_path / "ledger"
    shutil.copytree(folder, copy)
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["format"] = ledger.LEDGER_FORMAT - 1
    (copy / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ledger.StaleLedger, match="has format .* recompute it: make reproduce"):
        _served(monkeypatch, copy, 0)


def test_W_is_kept_as_its_xor_with_the_runs_random_start(built):
    """A frozen W costs nothing but its zeros; a learned one comes back to the bit."""
    from docking.experiments import initial_network

    folder, *_ = built
    (entry,) = [p for p in folder.rglob("*.xz") if "W.xor" in ledger._decode_entry(p.read_bytes())]
    arrays = ledger._decode_entry(entry.read_bytes())
    assert "W" not in arrays and arrays["W.xor"].dtype == np.uint64
    start = initial_network(TINY, 0).W
    assert not np.any(ledger._xor_start(start, TINY, 0))  # W at its start: all zero bits
    rng = np.random.default_rng(0)
    learned = start + 1e-3 * rng.standard_normal(start.shape)
    back = ledger._xor_start(ledger._xor_start(learned, TINY, 0), TINY, 0)
    assert back.dtype == np.float64 and back.tobytes() == learned.tobytes()
    with pytest.raises(ValueError, match="does not match"):
        ledger._xor_start(learned[:, :3], TINY, 0)


def test_the_manifest_holds_each_configuration_once(built):
    folder, *_ = built
    raw = json.loads((folder / "manifest.json").read_text())
    assert len(raw["configs"]) == 1  # two seeds of one configuration
    (ref,) = raw["configs"]
    assert all(record["config"] == ref for record in raw["runs"].values())
    served = ledger.manifest(folder)  # reading puts the configuration back into each record
    assert all(record["config"] == TINY.to_dict() for record in served["runs"].values())


@pytest.mark.slow
def test_verify_passes_on_the_ledger_and_fails_on_a_wrong_digest(built, tmp_path):
    folder, *_ = built
    checks = verify.verify(None, workers=1, progress=False, folder=folder)
    assert len(checks) == 2 and all(c.ok for c in checks)
    copy = tmp_path / "ledger"
    shutil.copytree(folder, copy)
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["runs"][run_key(TINY, 1)]["digest"] = "0" * 64
    (copy / "manifest.json").write_text(json.dumps(manifest))
    checks = verify.verify(None, workers=1, progress=False, folder=copy)
    assert [c.ok for c in sorted(checks, key=lambda c: c.seed)] == [True, False]


def test_verify_draws_its_sample_from_the_commit():
    runs = {f"k{i}": {"runner": "learner", "name": "x", "seed": i} for i in range(20)}
    runs.update({"p": {"runner": "learner", "name": "experiment2", "seed": 0}})
    runs.update({"q": {"runner": "ppo", "name": "ppo", "seed": 0}})  # only in --all
    data = {"runs": runs}
    a, b = verify.chosen(data, 3, "commit-a"), verify.chosen(data, 3, "commit-b")
    assert a[0] == b[0] == "p" and len(a) == len(b) == 4
    assert a != b and a == verify.chosen(data, 3, "commit-a")
    assert "q" not in verify.chosen(data, 30, "c")
    assert len(verify.chosen(data, None, "c")) == 22


def _copied_package(tmp_path):
    dst = tmp_path / "pkg"
    shutil.copytree(
        os.path.join(ROOT, "docking"), dst / "docking", ignore=shutil.ignore_patterns("__pycache__")
    )
    return dst


def _python(code, root, **env):
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        env={**os.environ, "PYTHONPATH": str(root), **env},
        capture_output=True,
        text=True,
        timeout=300,
        cwd=root,  # python -c puts the working directory first on sys.path
    )


@pytest.mark.slow
def test_a_ledger_from_other_code_is_refused_naming_the_module(built, tmp_path):
    folder, *_ = built
    root = _copied_package(tmp_path)
    network = root / "docking" / "network.py"
    network.write_text(network.read_text().replace("MAX_RATE = 100.0", "MAX_RATE = 99.0"))
    code = """
        import dataclasses
        from docking import ledger
        from docking.presets import EXPERIMENT_1
        config = dataclasses.replace(EXPERIMENT_1, name="tiny", train_trials=4, test_trials=6,
                                     eval_every=4, eval_trials=1, heldout_trials=5)
        assert ledger.holds(config, 0)
        try:
            ledger.lookup(config, 0)
        except ledger.StaleLedger as exc:
            print("REFUSED", exc)
        else:
            print("SERVED")
        """
    found = _python(code, root, DOCKING_LEDGER=str(folder))
    assert found.returncode == 0, found.stderr
    assert "REFUSED" in found.stdout and "docking.network" in found.stdout
    assert "make reproduce" in found.stdout
    # The unchanged package serves it.
    found = _python(code, ROOT, DOCKING_LEDGER=str(folder))
    assert "SERVED" in found.stdout, found.stdout + found.stderr


@pytest.mark.slow
def test_code_edited_after_import_cannot_key_runs(tmp_path):
    root = _copied_package(tmp_path)
    code = f"""
        import pathlib
        from docking import store
        store.source_fingerprint()  # fine: the code on disk is the code loaded
        world = pathlib.Path({str(root / "docking" / "world.py")!r})
        world.write_text(world.read_text() + "\\n_EDITED = 1\\n")
        try:
            store.source_fingerprint()
        except store.StaleCode as exc:
            print("STALE", exc)
        """
    found = _python(code, root)
    assert found.returncode == 0, found.stderr
    assert "STALE" in found.stdout and "docking/world.py" in found.stdout
    assert issubclass(StaleCode, RuntimeError)


# ------------------------------------------------------------------------------------------
# What the store serves (issue 17: no silent wrong result).
# ------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory):
    results = tmp_path_factory.mktemp("store")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        for s in SEEDS:
            run_or_load(TINY, s, results, progress=False)
    return results


def test_a_valid_file_of_another_run_is_not_served(two_runs, tmp_path, monkeypatch):
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    results = tmp_path / "results"
    shutil.copytree(two_runs, results)
    shutil.copy(result_path(TINY, 1, results), result_path(TINY, 0, results))
    with pytest.raises(CorruptResult, match="not the run asked for"):
        load_result(result_path(TINY, 0, results), run_key(TINY, 0))
    with pytest.warns(RuntimeWarning, match="not the run asked for"):
        again = run_or_load(TINY, 0, results, progress=False)
    assert again.seed == 0
    assert load_result(result_path(TINY, 0, results), run_key(TINY, 0)).seed == 0


def _rewrite(path, change):
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    change(arrays)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    path.write_bytes(buffer.getvalue())


@pytest.mark.parametrize(
    "change, reason",
    [
        (lambda a: a.__setitem__("test.success", ~a["test.success"]), "content digest"),
        (lambda a: a["Q"].__setitem__((0, 0), 1e308), "content digest"),
        (lambda a: a["test.poses"].__setitem__((0, 0), np.nan), "non-finite"),
        (lambda a: a.__setitem__("extra", np.zeros(3)), "unexpected or missing"),
    ],
)
def test_arrays_edited_inside_a_file_are_refused(two_runs, tmp_path, change, reason):
    path = tmp_path / "seed0.npz"
    shutil.copy(result_path(TINY, 0, two_runs), path)
    _rewrite(path, change)
    with pytest.raises(CorruptResult, match=reason):
        load_result(path, run_key(TINY, 0))


@pytest.mark.slow
def test_sizes_are_checked_before_decompression(two_runs, tmp_path):
    path = tmp_path / "seed0.npz"
    shutil.copy(result_path(TINY, 0, two_runs), path)
    with np.load(path) as data:
        arrays = {name: data[name] for name in data.files}
    # W as an array of 200 MB of zeros: a few hundred kB compressed.
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name, array in arrays.items():
            member = io.BytesIO()
            if name == "W":
                array = np.zeros((4, 25_000_000 // 4), dtype=np.float64)
            np.lib.format.write_array(member, array)
            zf.writestr(f"{name}.npy", member.getvalue())
    assert path.stat().st_size < 2**20
    with pytest.raises(CorruptResult, match="would decompress to"):
        load_result(path, run_key(TINY, 0))


def test_the_rendering_stack_is_part_of_the_key():
    stack = store.rendering_stack()
    assert "Mesa" in stack or "GL" in stack
    assert run_key(TINY, 0) != run_key(TINY, 0, render="another stack")
    assert run_key(TINY, 0) == run_key(TINY, 0, render=stack)


def test_a_saved_file_digest_covers_every_array(two_runs):
    result = run_experiment(TINY, 0, progress=False)
    path = result_path(TINY, 0, two_runs)
    with np.load(path) as data:
        meta = json.loads(str(data["meta"]))
        assert meta["digest"] == content_digest(data)
    again = two_runs / "again.npz"
    save_result(result, again)
    with np.load(again) as data:
        assert content_digest(data) == meta["digest"]  # same run: same arrays, bit for bit


def test_a_nearly_full_disk_is_refused_before_a_run_naming_the_folder(tmp_path, monkeypatch):
    import collections
    import shutil as shutil_

    usage = collections.namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil_, "disk_usage", lambda path: usage(10**9, 10**9 - 2**20, 2**20))
    with pytest.raises(PermissionError, match=str(tmp_path)):
        store.check_writable(tmp_path)
    with pytest.raises(PermissionError, match="MiB free"):
        run_or_load(TINY, 0, tmp_path, progress=False)


def test_an_empty_results_variable_is_refused(monkeypatch):
    from docking import paths

    monkeypatch.setenv("DOCKING_RESULTS", "")
    with pytest.raises(ValueError, match="DOCKING_RESULTS is set but empty"):
        paths.results_dir()


@pytest.mark.slow
def test_a_test_only_cell_is_stored_as_the_run_it_equals(tmp_path, monkeypatch):
    """A baseline's networks tested in another world are stored under the key of the run
    with that held-out world, bit for bit what computing that run gives (so ``verify`` can
    check them), and loaded, not recomputed, the next time."""
    from docking.design import tested_in

    monkeypatch.setenv("DOCKING_LEDGER", "off")
    monkeypatch.delenv("DOCKING_TRACE", raising=False)
    other = dataclasses.replace(TINY.world, step_noise_yaw_deg=0.0)
    base = run_or_load(TINY, 0, tmp_path, progress=False)
    derived = tested_in(base, other, tmp_path)
    config = dataclasses.replace(TINY, heldout_world=other)
    assert derived.config == config and result_path(config, 0, tmp_path).exists()
    full = run_experiment(config, 0, progress=False)
    save_result(full, tmp_path / "full.npz")
    with np.load(tmp_path / "full.npz") as a, np.load(result_path(config, 0, tmp_path)) as b:
        assert content_digest(a) == content_digest(b)
    monkeypatch.setattr("docking.design.heldout_trials", _refuse)
    again = tested_in(base, other, tmp_path)
    np.testing.assert_array_equal(again.heldout.success, derived.heldout.success)


def test_an_entry_gives_back_every_array_to_the_bit():
    rng = np.random.default_rng(0)
    arrays = {
        "meta": np.array('{"seed": 3}'),
        "poses": rng.standard_normal((17, 3)),
        "success": rng.random(9) > 0.5,
        "actions": np.arange(5),
        "empty": np.zeros((0, 3)),
        "bits": rng.integers(0, 2**63, (4, 5), dtype=np.uint64),
    }
    raw = ledger._encode_entry(arrays)
    assert raw == ledger._encode_entry(dict(reversed(arrays.items())))  # order-free bytes
    back = ledger._decode_entry(raw)
    assert sorted(back) == sorted(arrays)
    for name, array in arrays.items():
        assert back[name].dtype == array.dtype and back[name].shape == array.shape
        assert back[name].tobytes() == array.tobytes() and back[name].flags.writeable
