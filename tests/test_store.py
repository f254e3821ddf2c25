"""The results store (issue #7): keys, validation, fault injection, atomic writes."""

import dataclasses
import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
import zipfile

import numpy as np
import pytest

import docking
from docking.experiments import ExperimentConfig, run_experiment
from docking.fileio import atomic_write, remove_stale_temporaries
from docking.network import NetworkConfig
from docking.presets import EXPERIMENT_1
from docking.study import kinds
from docking.study.kinds import (
    CorruptResult,
    load_result,
    result_path,
    save_result,
    source_fingerprint,
)
from docking.study.store import check_writable, run_or_load
from docking.study.sweep import run_configs

TINY = dataclasses.replace(EXPERIMENT_1, train_trials=3, test_trials=2, eval_every=3, eval_trials=1)
SEED = 7


@pytest.fixture(scope="module")
def reference():
    """The run every recovered file must reproduce, bit for bit."""
    return run_experiment(TINY, SEED, progress=False)


@pytest.fixture
def stored(tmp_path, reference):
    path = save_result(reference, result_path(TINY, SEED, tmp_path))
    return tmp_path, path


def _assert_same_run(a, b):
    np.testing.assert_array_equal(a.network.W, b.network.W)
    np.testing.assert_array_equal(a.network.Q, b.network.Q)
    np.testing.assert_array_equal(a.train.poses, b.train.poses)
    np.testing.assert_array_equal(a.test.actions, b.test.actions)


def _rewrite(path, change):
    """Rewrite the .npz at ``path`` as a valid zip whose contents ``change(dict)`` altered."""
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    change(arrays)
    atomic_write(path, lambda f: np.savez_compressed(f, **arrays))


def _edit_meta(edit):
    def change(arrays):
        meta = json.loads(str(arrays["meta"]))
        edit(meta)
        arrays["meta"] = np.array(json.dumps(meta))

    return change


def _flip_byte(path):
    raw = bytearray(path.read_bytes())
    raw[len(raw) // 3] ^= 0xFF
    path.write_bytes(bytes(raw))


CORRUPTIONS = {
    "zero bytes": lambda p: p.write_bytes(b""),
    "half a file": lambda p: p.write_bytes(p.read_bytes()[: p.stat().st_size // 2]),
    "a flipped byte": _flip_byte,
    "bad meta JSON": lambda p: _rewrite(p, lambda a: a.update(meta=np.array("{not json"))),
    "a missing key": lambda p: _rewrite(p, lambda a: a.pop("test.deltas")),
    "an unknown config field": lambda p: _rewrite(
        p, _edit_meta(lambda m: m["config"]["network"].update(colour="red"))
    ),
    "a truncated array": lambda p: _rewrite(
        p, lambda a: a.update({"train.actions": a["train.actions"][:-1]})
    ),
}


@pytest.mark.parametrize("kind", list(CORRUPTIONS))
def test_a_corrupt_file_is_a_warning_and_a_recomputed_run(stored, reference, kind):
    results_dir, path = stored
    CORRUPTIONS[kind](path)
    with pytest.raises(CorruptResult):
        load_result(path)
    with pytest.warns(RuntimeWarning, match=rf"{path.name}.*recomputing"):
        recovered = run_or_load(TINY, SEED, results_dir=results_dir, progress=False)
    _assert_same_run(recovered, reference)
    _assert_same_run(load_result(path), reference)  # the bad file was replaced


def test_a_checked_file_is_not_read_again_until_it_is_replaced(stored, monkeypatch):
    """``is_valid`` reads a file once per process; an atomic rewrite (a new file) is read
    again, and a corrupt one found invalid."""
    _, path = stored
    key = kinds.run_key(TINY, SEED)
    assert kinds.is_valid(path, key) and not kinds.is_valid(path, "0" * 64 + ":seed7")
    reads = []
    monkeypatch.setattr(kinds, "_parse", lambda data, asked: reads.append(asked))
    assert kinds.is_valid(path, key) and reads == []
    monkeypatch.undo()
    _rewrite(path, lambda a: a.update({"train.actions": a["train.actions"][:-1]}))
    assert not kinds.is_valid(path, key)
    assert not kinds.is_valid(path.with_name("seed8.npz"), key)  # no file


def test_a_file_of_another_configuration_or_code_is_refused(stored):
    _, path = stored
    _rewrite(path, _edit_meta(lambda m: m.update(key="0" * 64 + ":seed7")))
    with pytest.raises(CorruptResult, match="key"):
        load_result(path)


def test_variants_of_one_name_live_side_by_side(tmp_path):
    variant = dataclasses.replace(TINY, world=dataclasses.replace(TINY.world, step_forward=0.08))
    assert variant.name == TINY.name
    a = result_path(TINY, SEED, tmp_path)
    b = result_path(variant, SEED, tmp_path)
    assert a != b and a.parent.parent == b.parent.parent
    run_or_load(TINY, SEED, results_dir=tmp_path, progress=False)
    run_or_load(variant, SEED, results_dir=tmp_path, progress=False)
    assert load_result(a).config == TINY and load_result(b).config == variant
    assert json.loads((a.parent / "config.json").read_text()) == TINY.to_dict()


def _copy_package(tmp_path):
    src = os.path.dirname(docking.__file__)
    dst = tmp_path / "docking"
    shutil.copytree(src, dst, ignore=shutil.ignore_patterns("__pycache__"))
    return dst


@pytest.mark.slow
def test_the_fingerprint_is_the_same_in_every_process():
    """Worker processes (a sweep on a cluster) must compute the parent's key: the
    fingerprint may not depend on the per-process hash seed of str (set iteration order)."""
    import os
    import subprocess
    import sys

    code = "from docking.study.kinds import source_fingerprint; print(source_fingerprint())"
    prints = {
        subprocess.run(
            [sys.executable, "-c", code],
            env={**os.environ, "PYTHONHASHSEED": str(seed)},
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        for seed in (1, 2, 3)
    }
    assert prints == {source_fingerprint()}


def test_a_code_change_in_trial_py_changes_the_fingerprint(tmp_path):
    package = _copy_package(tmp_path)
    before = source_fingerprint(package)
    assert before == source_fingerprint()  # the copy is the same code
    trial = package / "trial.py"
    source = trial.read_text()
    # Prose (docstrings, comments, layout) does not change what a run computes ...
    trial.write_text(source.replace('"""SARSA trials', '"""Trials of SARSA', 1) + "\n# note\n")
    assert source_fingerprint(package) == before
    # ... code does.
    changed = source.replace("r + cfg.gamma * discount", "r + 0.5 * cfg.gamma * discount", 1)
    assert changed != source
    trial.write_text(changed)
    assert source_fingerprint(package) != before
    # So do the modules trial.py imports (network.py), and the scene's assets.
    trial.write_text(source)
    network = package / "network.py"
    network.write_text(network.read_text() + "\n_UNUSED = 1\n")
    assert source_fingerprint(package) != before


def test_a_code_change_invalidates_the_cache(stored, reference, monkeypatch):
    results_dir, path = stored
    assert run_or_load(TINY, SEED, results_dir=results_dir, progress=False)  # loads
    monkeypatch.setattr(kinds, "source_fingerprint", lambda package_dir=None, **_: "other code")
    new_path = result_path(TINY, SEED, results_dir)
    assert new_path != path  # another key: the old file is never returned for the new code
    calls = []
    real = kinds.run_experiment
    monkeypatch.setattr(kinds, "run_experiment", lambda *a, **k: calls.append(1) or real(*a, **k))
    _assert_same_run(run_or_load(TINY, SEED, results_dir=results_dir, progress=False), reference)
    assert calls == [1] and new_path.exists()


def test_an_unwritable_results_folder_fails_before_the_run(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    calls = []
    monkeypatch.setattr(kinds, "run_experiment", lambda *a, **k: calls.append(1))
    with pytest.raises(PermissionError, match="a-file"):
        run_or_load(TINY, SEED, results_dir=blocker / "results", progress=False)
    with pytest.raises(PermissionError, match="a-file"):
        run_configs({"t": TINY}, [0, 1], results_dir=blocker / "results", progress=False)
    assert calls == []


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write into a read-only folder")
def test_a_read_only_results_folder_fails_before_the_run(tmp_path):
    folder = tmp_path / "results"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        with pytest.raises(PermissionError, match="not writable"):
            check_writable(folder)
    finally:
        folder.chmod(0o755)


_KILLED_WRITER = textwrap.dedent(
    """
    import sys, time
    from docking.fileio import atomic_write
    data = open(sys.argv[2], "rb").read()
    def write(f):
        f.write(data[: len(data) // 2])
        f.flush()
        print("half written", flush=True)
        time.sleep(60)
        f.write(data[len(data) // 2 :])
    atomic_write(sys.argv[1], write)
    """
)


def test_kill_9_during_a_save_leaves_a_loadable_target_and_no_stray_temp(stored, reference):
    results_dir, path = stored
    good = path.read_bytes()
    source = path.parent / "source.bin"
    source.write_bytes(good)
    writer = subprocess.Popen(
        [sys.executable, "-c", _KILLED_WRITER, str(path), str(source)],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert writer.stdout.readline().strip() == "half written"
        os.kill(writer.pid, signal.SIGKILL)
    finally:
        writer.wait(timeout=30)
    source.unlink()
    strays = [p for p in path.parent.iterdir() if p.name.endswith(".tmp")]
    assert len(strays) == 1 and strays[0].name.startswith(f".{path.name}.{writer.pid}.")
    assert path.read_bytes() == good  # the target was never touched
    _assert_same_run(run_or_load(TINY, SEED, results_dir=results_dir, progress=False), reference)
    assert not [p for p in path.parent.iterdir() if p.name.endswith(".tmp")]


def test_stale_temporaries_of_live_writers_are_kept(tmp_path):
    target = tmp_path / "x.npz"
    mine = tmp_path / f".x.npz.{os.getpid()}.abc.tmp"
    mine.write_bytes(b"")
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    theirs = tmp_path / f".x.npz.{dead.pid}.abc.tmp"
    theirs.write_bytes(b"")
    other_target = tmp_path / f".y.npz.{dead.pid}.abc.tmp"
    other_target.write_bytes(b"")
    assert remove_stale_temporaries(target) == [theirs]
    assert mine.exists() and other_target.exists()


def test_numpy_integers_in_a_config_are_saved_as_plain_ints(tmp_path):
    config = dataclasses.replace(
        TINY, network=dataclasses.replace(TINY.network, n_features=np.int64(3))
    )
    assert type(config.network.n_features) is int
    result = run_or_load(config, np.int64(2), results_dir=tmp_path, progress=False)
    assert result.config.network.n_features == 3 and result.seed == 2


def test_no_learning_curve_with_eval_trials_0(tmp_path):
    config = dataclasses.replace(TINY, eval_trials=0)
    result = run_or_load(config, 1, results_dir=tmp_path, progress=False)
    assert len(result.curve_trials) == 0 and len(result.test) == config.test_trials
    assert load_result(result_path(config, 1, tmp_path)).curve_success.shape == (0,)


@pytest.mark.parametrize("name", ["../x", "/tmp/x", "a/b", "..", ".hidden", "", "x" * 101, "a b"])
def test_a_name_cannot_leave_the_results_folder(name):
    with pytest.raises(ValueError, match="ExperimentConfig.name"):
        dataclasses.replace(TINY, name=name)


def test_a_result_file_is_a_zip_with_the_documented_arrays(stored):
    _, path = stored
    with zipfile.ZipFile(path) as z:
        names = {n.removesuffix(".npy") for n in z.namelist()}
    assert {"meta", "W", "Q", "train.poses", "test.success", "curve_success"} <= names


def test_config_round_trips_through_json():
    for config in (TINY, dataclasses.replace(TINY, network=NetworkConfig(n_features=5))):
        assert ExperimentConfig.from_dict(json.loads(json.dumps(config.to_dict()))) == config


def test_run_or_load_is_quick_to_load(stored):
    results_dir, _ = stored
    t0 = time.perf_counter()
    run_or_load(TINY, SEED, results_dir=results_dir, progress=False)
    assert time.perf_counter() - t0 < 5


def test_a_run_without_a_final_test_saves_and_loads(tmp_path):
    config = dataclasses.replace(TINY, test_trials=0, heldout_trials=2)
    result = run_or_load(config, 1, results_dir=tmp_path, progress=False)
    assert len(result.test) == 0 and result.test.poses.shape == (0, 3)
    assert len(result.heldout) == 2
    loaded = load_result(result_path(config, 1, tmp_path))
    assert len(loaded.test) == 0 and np.isnan(loaded.test.success_rate)


def test_presets_and_designs_are_outside_the_fingerprint():
    """A seed list or a preset is data: editing it must not re-key the stored runs."""
    modules = kinds.module_digests()
    assert "docking.experiments" in modules and "docking.scene" in modules
    assert not any(
        name.startswith(("docking.presets", "docking.study.designs")) for name in modules
    )


def test_derived_arrays_are_kept_and_served_only_to_their_key(tmp_path):
    """Arrays computed from runs (issue 52: the rendered start views behind the fidelity
    measure) are kept in the store under their key's digest, served again only for that very
    key, and computed again when the file holds another key or cannot be read."""
    from docking.study.store import derived

    calls = []

    def compute(value=1.0):
        calls.append(value)
        return {"a": np.full(3, value)}

    key = "mean_winning_inputs\nrun abc:seed0\nviews 10"
    first = derived("thing", key, compute, tmp_path)
    again = derived("thing", key, compute, tmp_path)
    assert len(calls) == 1 and np.array_equal(first["a"], again["a"])
    (path,) = (tmp_path / "derived" / "thing").glob("*.npz")
    # another key (the code's fingerprint moved): its own file, computed
    derived("thing", key.replace("abc", "abd"), lambda: compute(2.0), tmp_path)
    assert calls == [1.0, 2.0]
    # the file of this key holding another key's arrays is refused and replaced
    np.savez(path, key=np.array("another key"), a=np.full(3, 9.0))
    assert np.array_equal(derived("thing", key, compute, tmp_path)["a"], np.full(3, 1.0))
    assert calls == [1.0, 2.0, 1.0]
    path.write_bytes(b"not a zip")
    derived("thing", key, compute, tmp_path)
    assert len(calls) == 4
    assert derived("thing", key, compute, tmp_path)["a"].tolist() == [1.0] * 3 and len(calls) == 4


def test_derived_arrays_are_computed_again_when_their_code_changes(tmp_path):
    """A module named in ``code`` enters the key by its file's digest: edited, the arrays
    are computed again (a cache that never invalidates would serve the old code's)."""
    import types

    from docking.study.store import derived

    source = tmp_path / "helper.py"
    source.write_text("X = 1\n")
    module = types.ModuleType("helper")
    module.__file__ = str(source)
    calls = []

    def compute():
        calls.append(1)
        return {"a": np.zeros(2)}

    derived("thing", "k", compute, tmp_path / "store", code=(module,))
    derived("thing", "k", compute, tmp_path / "store", code=(module,))
    assert len(calls) == 1
    source.write_text("X = 2\n")
    derived("thing", "k", compute, tmp_path / "store", code=(module,))
    assert len(calls) == 2


# A folder of the store that is a link out of it (issue 60) ------------------------------------


def _linked_out(store, outside, depth: int):
    """Move the folder ``depth`` levels below ``store`` on the path of (TINY, SEED)'s file
    (1: its configuration's name, 2: its key) to ``outside`` and leave a symbolic link to it
    in its place; the link."""
    path = result_path(TINY, SEED, store)
    folder = store.joinpath(*path.relative_to(store).parts[:depth])
    outside.parent.mkdir(parents=True, exist_ok=True)
    shutil.move(folder, outside)
    folder.symlink_to(outside, target_is_directory=True)
    return folder


@pytest.mark.parametrize("depth", [1, 2], ids=["name", "key"])
@pytest.mark.parametrize("held", [True, False], ids=["a run there", "empty"])
def test_a_store_folder_linked_out_of_the_store_is_refused_naming_it(
    stored, tmp_path, depth, held, monkeypatch
):
    """A folder of the store that is a link leading out of it was read (its run served) and
    written through: refused before anything there is read, removed or written, with one line
    naming the link, whether it holds the run or nothing yet."""
    from docking.study.runs import load_run, locate
    from docking.study.store import compute

    monkeypatch.setenv("DOCKING_LEDGER", "off")
    store, path = stored
    if not held:
        path.unlink()
    outside = tmp_path.parent / f"{tmp_path.name}-outside" / "folder"
    link = _linked_out(store, outside, depth)
    there = sorted(p.name for p in outside.rglob("*"))
    says = f"{link} is a link to {outside.resolve()}, outside the results store"
    for call in (
        lambda: locate(TINY, SEED, store),
        lambda: load_run(TINY, SEED, store),
        lambda: run_or_load(TINY, SEED, store, progress=False),
        lambda: compute(TINY, SEED, result_path(TINY, SEED, store), progress=False),
    ):
        with pytest.raises(kinds.ForeignFile) as refused:
            call()
        assert str(refused.value).startswith(says) and "\n" not in str(refused.value)
    assert sorted(p.name for p in outside.rglob("*")) == there  # nothing written there


def test_links_inside_the_store_and_a_linked_store_are_read(stored, tmp_path, reference):
    """What the refusal must not catch: the store's own folder a link (DOCKING_RESULTS naming
    a link to it), and a folder of the store linked to another folder inside it."""
    store, _ = stored
    linked = tmp_path.parent / f"{tmp_path.name}-store-link"
    linked.symlink_to(store, target_is_directory=True)
    _assert_same_run(run_or_load(TINY, SEED, linked, progress=False), reference)
    _linked_out(store, store / "elsewhere" / "tiny", 1)
    _assert_same_run(run_or_load(TINY, SEED, store, progress=False), reference)


def test_the_command_line_refuses_a_store_folder_linked_out_in_one_line(
    tmp_path, monkeypatch, capsys
):
    """run, its store's folder of experiment1 a link out of the store (holding nothing yet):
    one line naming the link, exit 2, nothing computed or written there."""
    from docking.study.cli import main

    monkeypatch.setenv("DOCKING_LEDGER", "off")
    store, outside = tmp_path / "store", tmp_path / "outside"
    store.mkdir()
    outside.mkdir()
    (store / "experiment1").symlink_to(outside, target_is_directory=True)
    handler = signal.getsignal(signal.SIGTERM)
    try:
        status = main(
            ["run", "experiment1", "--seeds", str(SEED), "--train-trials", "3", "--test-trials"]
            + ["2", "--eval-every", "3", "--eval-trials", "1", "--processes", "1"]
            + ["--results-dir", str(store)]
        )
    finally:
        signal.signal(signal.SIGTERM, handler)
    err = capsys.readouterr().err.strip()
    assert status == 2 and len(err.splitlines()) == 1, err
    assert f"{store / 'experiment1'} is a link to {outside.resolve()}" in err
    assert not list(outside.iterdir())


def test_derived_arrays_in_a_folder_linked_out_of_the_store_are_refused(tmp_path):
    from docking.study.store import derived, derived_entries

    store, outside = tmp_path / "store", tmp_path / "outside"
    (store / "derived").mkdir(parents=True)
    outside.mkdir()
    (store / "derived" / "thing").symlink_to(outside, target_is_directory=True)
    for call in (
        lambda: derived("thing", "k", lambda: {"x": np.zeros(2)}, store),
        lambda: derived_entries("thing", store),
    ):
        with pytest.raises(kinds.ForeignFile, match="is a link to .* outside the results store"):
            call()
    assert not list(outside.iterdir())


def test_migrating_a_store_leaves_a_folder_linked_out_of_it_unread(stored, tmp_path):
    """ledger migrate's pass over a results store neither reads nor moves the runs of a folder
    that is a link out of the store (counted left)."""
    from docking.study.migrate import migrate_store

    store, _ = stored
    assert migrate_store(store, tmp_path / "no-ledger") == {"moved": 0, "current": 1, "left": 0}
    _linked_out(store, tmp_path.parent / f"{tmp_path.name}-outside" / "tiny", 1)
    assert migrate_store(store, tmp_path / "no-ledger") == {"moved": 0, "current": 0, "left": 1}
