"""The results ledger (issue 16) and the store's checks of what it serves (issue 17)."""

import dataclasses
import io
import json
import os
import shutil
import subprocess
import sys
import textwrap
import time
import zipfile

import numpy as np
import pytest
from helpers import SEEDS, TINY

from docking.experiments import run_experiment
from docking.study import arrays, kinds, ledger, ledger_rows, store, verify
from docking.study.kinds import (
    CorruptResult,
    StaleCode,
    content_digest,
    load_result,
    result_path,
    run_key,
    save_result,
)
from docking.study.runs import load_run
from docking.study.store import run_or_load

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(store.__file__)))


KEEP = frozenset({"paths", "starts"})


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A store of two tiny runs and the ledger written from it: seed 0 kept whole, seed 1 as
    rows of the results table, with its failed trials' paths."""
    base = tmp_path_factory.mktemp("ledger")
    results, folder = base / "results", base / "ledger"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        for s in SEEDS:
            run_or_load(TINY, s, results, progress=False)
    data = ledger.update([(TINY, 0, True, KEEP), (TINY, 1, False, KEEP)], folder, results)
    full = [load_result(result_path(TINY, s, results)) for s in SEEDS]
    return folder, data, full, results


def _served(monkeypatch, folder, seed, config=TINY):
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    return load_run(config, seed, "/nonexistent-store")


#: TINY with at most two actions per trial: most trials fail, so the table keeps paths.
SHORT = dataclasses.replace(TINY, world=dataclasses.replace(TINY.world, max_steps=2))


@pytest.fixture(scope="module")
def short_built(tmp_path_factory):
    base = tmp_path_factory.mktemp("ledger-short")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        stored = run_or_load(SHORT, 1, base / "results", progress=False)
    ledger.update(
        [(SHORT, 1, False, KEEP | {"ends", "lengths"})], base / "ledger", base / "results"
    )
    return base / "ledger", stored


def test_a_whole_run_is_served_bit_for_bit(built, monkeypatch):
    folder, data, full, _ = built
    served = _served(monkeypatch, folder, 0)
    assert (
        kinds.content_digest(kinds.result_arrays(served))
        == data["runs"][run_key(TINY, 0)]["digest"]
    )


def test_a_table_run_serves_its_per_trial_arrays_and_none_of_the_rest(short_built, monkeypatch):
    folder, stored = short_built
    served = _served(monkeypatch, folder, 1, SHORT)
    for part in ("test", "heldout"):
        starts = getattr(served, part).starts
        assert starts.tobytes() == getattr(stored, part).starts.tobytes()
    for part in ("train", "test", "heldout"):
        for name in ("success", "steps", "start_far"):
            a, b = getattr(getattr(served, part), name), getattr(getattr(stored, part), name)
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes()
    for name in ("curve_trials", "curve_success", "curve_steps", "curve_rewarded"):
        assert getattr(served, name).tobytes() == getattr(stored, name).tobytes()
    # The paths of the failed test and held-out trials, and nothing else
    failures = 0
    for part in ("test", "heldout"):
        log, whole = getattr(served, part), getattr(stored, part)
        failed = np.flatnonzero(~whole.success)
        failures += failed.size
        for k in failed:
            assert log.trial_poses(k).tobytes() == whole.trial_poses(k).tobytes()
            assert log.trial_actions(k).tobytes() == whole.trial_actions(k).tobytes()
        docked = np.flatnonzero(whole.success)
        if docked.size:
            with pytest.raises(ledger_rows.NotInLedger, match="path of trial"):
                log.trial_poses(docked[0])
    assert failures, "the tiny run must fail some trials for this test to mean anything"
    # What the table does not keep is absent (None), not a substitute
    assert served.network is None
    for part in ("train", "test", "heldout"):
        log = getattr(served, part)
        assert log.poses is None and log.actions is None and log.deltas is None
        assert log.winners is None  # not asked for
    with pytest.raises(ledger_rows.NotInLedger, match="'tiny' seed 1.*whole"):
        served.test.trial_poses(int(np.flatnonzero(stored.test.success)[0]))


def test_a_table_keeps_the_final_poses_it_is_asked_for(short_built, built, monkeypatch):
    folder, stored = short_built
    served = _served(monkeypatch, folder, 1, SHORT)
    for part in ("test", "heldout"):
        whole = getattr(stored, part)
        ends = arrays.final_poses(getattr(served, part))
        assert ends.tobytes() == arrays.final_poses(whole).tobytes()
        assert (
            ends.tobytes()
            == np.array([whole.trial_poses(k)[-1] for k in range(len(whole))]).tobytes()
        )
        lengths = arrays.path_lengths(getattr(served, part))
        walked = [
            np.sum(np.linalg.norm(np.diff(whole.trial_poses(k)[:, :2], axis=0), axis=1))
            for k in range(len(whole))
        ]
        assert np.allclose(lengths, walked, rtol=0, atol=1e-12)
        assert lengths.tobytes() == arrays.path_lengths(whole).tobytes()
    without = _served(monkeypatch, built[0], 1)  # a table not asked for them
    with pytest.raises(ledger_rows.NotInLedger, match="final poses"):
        arrays.final_poses(without.heldout)
    with pytest.raises(ledger_rows.NotInLedger, match="path lengths"):
        arrays.path_lengths(without.heldout)


def test_an_update_writes_the_same_bytes_again(built, tmp_path):
    folder, _, _, results = built
    again = tmp_path / "ledger"
    ledger.update([(TINY, 0, True, KEEP), (TINY, 1, False, KEEP)], again, results)
    files = sorted(p.relative_to(folder) for p in folder.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(again) for p in again.rglob("*") if p.is_file())
    for f in files:
        if f.name != "manifest.json":  # (it records this machine's platform)
            assert (folder / f).read_bytes() == (again / f).read_bytes(), f


def test_an_update_removes_the_files_of_runs_it_no_longer_keeps(built, tmp_path):
    folder, _, _, results = built
    copy = tmp_path / "ledger"
    shutil.copytree(folder, copy)
    ledger.update([(TINY, 1, False, KEEP)], copy, results)
    assert not (copy / "whole").exists()  # seed 0 was whole: its file and folders go
    assert sorted(p.name for p in copy.glob("tables/*")) == ["tiny.npz"]


def test_the_tables_open_in_plain_numpy(built):
    folder, *_ = built
    (table,) = folder.glob("tables/*.npz")
    with np.load(table, allow_pickle=False) as columns:
        assert list(columns["key"]) == sorted(run_key(TINY, s) for s in SEEDS)
        assert columns["heldout.success.count"].tolist() == [TINY.heldout_trials] * 2


def test_the_manifest_records_each_runs_digest(built):
    folder, data, full, results = built
    for s in SEEDS:
        record = data["runs"][run_key(TINY, s)]
        with np.load(result_path(TINY, s, results)) as f:
            assert record["digest"] == content_digest(f)
        assert record["seed"] == s and record["name"] == "tiny"


def test_sweeps_do_not_recompute_what_the_ledger_holds(built, monkeypatch, tmp_path):
    from docking.study.sweep import run_configs

    folder, *_ = built
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    monkeypatch.setattr(kinds, "run_experiment", _refuse)
    found = run_configs({"tiny": TINY}, SEEDS, tmp_path, workers=1, progress=False)
    assert [r.seed for r in found["tiny"]] == list(SEEDS)
    assert not any(tmp_path.rglob("*.npz"))


def _refuse(*args, **kwargs):
    raise AssertionError("a run the ledger holds was recomputed")


@pytest.mark.parametrize("where", ["tables/tiny.npz", "manifest.json"])
def test_a_tampered_file_is_refused(built, monkeypatch, tmp_path, where):
    folder, *_ = built
    copy = tmp_path / "ledger"
    shutil.copytree(folder, copy)
    (copy / where).write_bytes((copy / where).read_bytes()[:-10] + b"0123456789")
    with pytest.raises(ledger.StaleLedger):
        _served(monkeypatch, copy, 1)
    whole = next(copy.glob("whole/**/seed0.npz"))
    whole.write_bytes(whole.read_bytes()[:-10] + b"0123456789")
    with pytest.raises(ledger.StaleLedger):
        _served(monkeypatch, copy, 0)


def test_a_ledger_of_another_layout_is_refused(built, monkeypatch, tmp_path):
    folder, *_ = built
    copy = tmp_path / "ledger"
    shutil.copytree(folder, copy)
    data = json.loads((copy / "manifest.json").read_text())
    data["format"] = 5
    (copy / "manifest.json").write_text(json.dumps(data))
    with pytest.raises(ledger.StaleLedger, match="format 5"):
        _served(monkeypatch, copy, 1)


def test_verify_passes_on_the_ledger_and_fails_on_a_wrong_digest(built, tmp_path):
    folder, *_ = built
    checks = verify.verify(None, workers=1, progress=False, folder=folder)
    assert len(checks) == 2 and all(c.ok for c in checks)
    copy = tmp_path / "ledger"
    shutil.copytree(folder, copy)
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["runs"][run_key(TINY, 1)]["digest"] = "0" * 64
    (copy / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ledger.CorruptLedger, match="do not match their seal"):  # an edit
        verify.verify(None, workers=1, progress=False, folder=copy)
    # A manifest consistent with itself (its seals follow the digest), wrong about a run:
    # only recomputing the run shows it.
    manifest["seals"] = ledger.seals_of(manifest)
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
        from docking.study import ledger
        from docking.study.runs import load_run
        from docking.presets import EXPERIMENT_1
        config = dataclasses.replace(EXPERIMENT_1, name="tiny", train_trials=4, test_trials=6,
                                     eval_every=4, eval_trials=1, heldout_trials=5)
        assert ledger.holds(config, 0)
        try:
            load_run(config, 0, "/nonexistent-store")
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
        from docking.study import kinds
        kinds.source_fingerprint()  # fine: the code on disk is the code loaded
        world = pathlib.Path({str(root / "docking" / "world.py")!r})
        world.write_text(world.read_text() + "\\n_EDITED = 1\\n")
        try:
            kinds.source_fingerprint()
        except kinds.StaleCode as exc:
            print("STALE", exc)
        """
    found = _python(code, root)
    assert found.returncode == 0, found.stderr
    assert "STALE" in found.stdout and "docking/world.py" in found.stdout
    assert issubclass(StaleCode, RuntimeError)


@pytest.mark.slow
def test_code_rewritten_in_place_after_import_cannot_key_runs(tmp_path):
    """``import docking`` records each file's stat and hashes only a file modified in the last
    two seconds (issue 61: it hashed every file); an older one is hashed when a fingerprint is
    first read, and is refused if its stat has moved since the import. Here a file is rewritten
    after the import with the same size and its modification time set back: its change time
    has moved (a check of the modification time and size alone would key runs with it)."""
    root = _copied_package(tmp_path)
    time.sleep(2.5)  # the copy is older than the two seconds import docking hashes
    code = f"""
        import os, pathlib, docking
        from docking.study import kinds
        world = pathlib.Path({str(root / "docking" / "world.py")!r})
        print("HASHED" if docking._SOURCES_AT_IMPORT["world.py"][1] else "STAT")
        kinds.source_fingerprint()  # fine: hashed now, its stat that of the import
        before = os.stat(world)
        text = world.read_bytes()
        world.write_bytes(text[:-1] + b" ")  # the last newline a space: the same size
        os.utime(world, ns=(before.st_atime_ns, before.st_mtime_ns))
        assert os.stat(world).st_size == before.st_size
        try:
            kinds.source_fingerprint()
        except kinds.StaleCode as exc:
            print("STALE", exc)
        """
    found = _python(code, root)
    assert found.returncode == 0, found.stderr
    assert found.stdout.startswith("STAT\n"), found.stdout
    assert "STALE" in found.stdout and "docking/world.py" in found.stdout


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
    stack = kinds.rendering_stack()
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
    from docking.study import paths

    monkeypatch.setenv("DOCKING_RESULTS", "")
    with pytest.raises(ValueError, match="DOCKING_RESULTS is set but empty"):
        paths.results_dir()


@pytest.mark.slow
def test_a_test_only_cell_is_stored_as_the_run_it_equals(tmp_path, monkeypatch):
    """A baseline's networks tested in another world are stored under the key of the run
    with that held-out world, bit for bit what computing that run gives (so ``verify`` can
    check them), and loaded, not recomputed, the next time."""
    from docking.study.design import tested_in

    monkeypatch.setenv("DOCKING_LEDGER", "off")
    other = dataclasses.replace(TINY.world, step_noise_yaw_deg=0.0)
    base = run_or_load(TINY, 0, tmp_path, progress=False)
    derived = tested_in(base, other, tmp_path)
    config = dataclasses.replace(TINY, heldout_world=other)
    assert derived.config == config and result_path(config, 0, tmp_path).exists()
    full = run_experiment(config, 0, progress=False)
    save_result(full, tmp_path / "full.npz")
    with np.load(tmp_path / "full.npz") as a, np.load(result_path(config, 0, tmp_path)) as b:
        assert content_digest(a) == content_digest(b)
    monkeypatch.setattr("docking.study.design.heldout_trials", _refuse)
    again = tested_in(base, other, tmp_path)
    np.testing.assert_array_equal(again.heldout.success, derived.heldout.success)


def test_one_table_keeps_networks_of_different_shapes(tmp_path, monkeypatch):
    """A design's networks may differ in shape (Experiment 1's 4 feature units beside 36):
    one table keeps both, and each is served back bit for bit in its configuration's shape;
    so are the test and held-out steps' winning units (not the training steps')."""
    wide = dataclasses.replace(TINY, network=dataclasses.replace(TINY.network, n_features=9))
    assert wide.network.n_features != TINY.network.n_features and wide.name == TINY.name
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    stored = [run_or_load(c, 0, tmp_path / "results", progress=False) for c in (TINY, wide)]
    keep = frozenset({"networks", "winners"})
    ledger.update(
        [(TINY, 0, False, keep), (wide, 0, False, keep)], tmp_path / "ledger", tmp_path / "results"
    )
    for config, whole in zip((TINY, wide), stored, strict=True):
        served = _served(monkeypatch, tmp_path / "ledger", 0, config).network
        assert served.W.shape == whole.network.W.shape and served.Q.shape == whole.network.Q.shape
        assert served.W.tobytes() == whole.network.W.tobytes()
        assert served.Q.tobytes() == whole.network.Q.tobytes()
        run = _served(monkeypatch, tmp_path / "ledger", 0, config)
        assert run.test.winners.tobytes() == whole.test.winners.tobytes()
        assert run.heldout.winners.tobytes() == whole.heldout.winners.tobytes()
        assert run.train.winners is None and run.train.success.size == len(whole.train)


def test_a_table_without_training_trials_serves_the_rest_and_no_training_log(
    built, tmp_path, monkeypatch
):
    """``no-train`` leaves each training trial's outcome out of the table: the held-out
    trials and the learning curve are served as before, the training trials refused."""
    folder, _, full, results = built
    ledger.update(
        [(TINY, 1, False, frozenset({ledger_rows.NO_TRAIN}))], tmp_path / "ledger", results
    )
    with zipfile.ZipFile(tmp_path / "ledger" / "tables" / f"{TINY.name}.npz") as z:
        assert not [n for n in z.namelist() if n.startswith("train.")]
    served = _served(monkeypatch, tmp_path / "ledger", 1)
    assert served.heldout.success.tobytes() == full[1].heldout.success.tobytes()
    assert served.curve_success.tobytes() == full[1].curve_success.tobytes()
    assert served.train is None


def test_an_update_of_one_table_keeps_every_other_as_it_was(built, tmp_path, monkeypatch):
    """``update(..., only=...)`` adds a design's table without the store holding the rest:
    the other tables, whole runs and records stay byte for byte, and both are served."""
    folder, _, full, results = built
    copy, other = tmp_path / "ledger", dataclasses.replace(TINY, name="added")
    shutil.copytree(folder, copy)
    with monkeypatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        added = run_or_load(other, 0, results, progress=False)
    before = json.loads((copy / "manifest.json").read_text())
    ledger.update([(other, 0, False, KEEP)], copy, results, only={"added"})
    after = json.loads((copy / "manifest.json").read_text())
    assert {k: after["runs"][k] for k in before["runs"]} == before["runs"]
    assert after["platform"] == before["platform"] and set(after["table_platforms"]) == {"added"}
    for f in folder.rglob("*.npz"):
        assert (copy / f.relative_to(folder)).read_bytes() == f.read_bytes(), f
    assert _served(monkeypatch, copy, 0).network.W.tobytes() == full[0].network.W.tobytes()
    served = _served(monkeypatch, copy, 0, other)
    assert np.array_equal(served.heldout.success, added.heldout.success)
    # a run of another table the ledger holds already is left as it is (a design reading an
    # earlier design's runs under their names); one it does not hold is refused
    held = ledger.update(
        [(other, 0, False, KEEP), (TINY, 1, False, KEEP)], copy, results, only={"added"}
    )
    assert held["runs"] == ledger.manifest(copy)["runs"] and len(held["runs"]) == len(after["runs"])
    for f in folder.rglob("*.npz"):
        assert (copy / f.relative_to(folder)).read_bytes() == f.read_bytes(), f
    with monkeypatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        run_or_load(TINY, 9, results, progress=False)
    with pytest.raises(ValueError, match="tiny"):  # a run outside the named tables
        ledger.update([(TINY, 9, False, KEEP)], copy, results, only={"added"})
    (copy / "tables" / "tiny.npz").write_bytes(b"damaged")
    with pytest.raises(ledger.CorruptLedger, match="digest"):  # what it keeps is checked
        ledger.update([(other, 0, False, KEEP)], copy, results, only={"added"})


def test_a_shared_tables_new_runs_are_added_to_its_rows(built, tmp_path, monkeypatch):
    """A design's new runs of a table that designs share (the yardsticks) join its rows under
    ``only``: the rows it held stay as they were, the table is the one a whole write of all
    its runs gives, and the new run is served."""
    _, _, full, results = built
    monkeypatch.setattr(ledger, "SHARED_TABLES", frozenset({TINY.name}))
    other = dataclasses.replace(TINY, name="added")
    with monkeypatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        run_or_load(other, 0, results, progress=False)
    grown, whole = tmp_path / "grown", tmp_path / "whole"
    before = ledger.update([(TINY, 1, False, KEEP)], grown, results)
    runs = [(other, 0, False, KEEP), (TINY, 0, False, KEEP), (TINY, 1, False, KEEP)]
    after = ledger.update(runs, grown, results, only={"added"})
    ledger.update([(TINY, 0, False, KEEP), (TINY, 1, False, KEEP)], whole, results)
    table = f"tables/{TINY.name}.npz"
    assert (grown / table).read_bytes() == (whole / table).read_bytes()
    assert {k: after["runs"][k] for k in before["runs"]} == before["runs"]
    assert len(after["runs"]) == 3
    served = _served(monkeypatch, grown, 0)
    assert served.heldout.success.tobytes() == full[0].heldout.success.tobytes()
    monkeypatch.setattr(ledger, "SHARED_TABLES", frozenset())
    with monkeypatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        run_or_load(TINY, 2, results, progress=False)
    with pytest.raises(ValueError, match="replace those tables whole"):  # not shared: refused
        ledger.update([*runs, (TINY, 2, False, KEEP)], grown, results, only={"added"})


# Issue 61: every kind of run decodes its own table rows (Runner.from_table); the ledger
# has no switch on the kind.


def _committed_table_run(runner_name: str):
    """The configuration and seed of one run of ``runner_name`` that the committed ledger
    keeps as a table row."""
    data = ledger.manifest()
    record = next(
        r
        for r in data["runs"].values()
        if r.get("runner", "learner") == runner_name and not r.get("whole")
    )
    runner = kinds.runner_named(runner_name)
    return runner, runner.from_dict(record["config"]), record["seed"]


@pytest.mark.parametrize("name", ["learner", "ppo"])
def test_each_kind_decodes_its_own_table_rows(name, monkeypatch):
    """``ledger.read`` of a table row returns what the run's kind's ``from_table`` makes of
    it: a runner with another ``from_table`` is served that, for the learner as for PPO."""
    monkeypatch.setenv("DOCKING_LEDGER", ROOT + "/ledger")
    runner, config, seed = _committed_table_run(name)
    served = ledger.read(config, seed)
    assert served.heldout is not None and len(served.heldout) == config.heldout_trials
    seen = []

    def own(*args):
        seen.append(args)
        return "decoded by its kind"

    monkeypatch.setitem(kinds.RUNNERS, type(config), dataclasses.replace(runner, from_table=own))
    assert ledger.read(config, seed) == "decoded by its kind"
    (config_seen, seed_seen, row, logs, walls) = seen[0]
    assert (config_seen, seed_seen) == (config, seed) and set(logs) == set(ledger_rows.PARTS)
    assert np.array_equal(logs["heldout"].success, served.heldout.success)


def test_the_ledger_names_no_kind_of_run():
    """The ledger reads every kind's rows through the same ``Runner.from_table``: its code
    names no kind (no ``runner.name ==`` switch, no import of PPO's module)."""
    import inspect

    source = inspect.getsource(ledger)
    assert "runner.name ==" not in source and "from docking.study import ppo" not in source
    assert "ppo." not in source and "PPOResult" not in source
