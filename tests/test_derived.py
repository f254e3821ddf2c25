"""Derived arrays in the committed ledger (issue 52): notebook 08's oracle-labelled success is
kept in the ledger, sealed, served to a fresh clone without computing, refused when edited,
caught by ``verify`` when forged and resealed, and never served to other code. Each test
builds its own tiny store and ledger."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from helpers import SEEDS, TINY

from docking.study import analysis, derived, ledger, ledger_rows, verify
from docking.study.cli import main
from docking.study.store import run_or_load

#: The labelled views of the tiny runs: two oracle trials (the notebook labels 300).
N_TRIALS = 2
#: The start views a tiny run's feature fidelity reads (the third edition reads 1500).
VIEWS = 30


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A tiny ledger (TINY seeds 0 and 1 in its table) and the oracle-labelled success of
    both runs committed beside it (``ledger derive`` from the store they were computed in)."""
    base = tmp_path_factory.mktemp("derived-ledger")
    results, folder = base / "results", base / "ledger"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DOCKING_LEDGER", "off")
        mp.setenv("DOCKING_RESULTS", str(results))
        runs = [run_or_load(TINY, s, results, progress=False) for s in SEEDS]
        ledger.update([(TINY, s, False, frozenset({"networks"})) for s in SEEDS], folder, results)
        values = [derived.oracle_labelled_success(r, N_TRIALS) for r in runs]
        for r in runs:
            derived.feature_fidelity(r, TINY.world, VIEWS, 1)
        ledger._read_manifest.cache_clear()
        written = derived.commit(folder, results)
        assert written == {"oracle-labelled-success": 2, "feature-fidelity": 2}
    return folder, values


@pytest.fixture
def copy(built, tmp_path, monkeypatch):
    """A copy of the tiny ledger that DOCKING_LEDGER names, an empty results store, and the
    values computed when it was built."""
    folder = tmp_path / "ledger"
    shutil.copytree(built[0], folder)
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))
    ledger._read_manifest.cache_clear()
    ledger._table.cache_clear()
    ledger._row_index.cache_clear()
    return folder, built[1]


def _runs():
    from docking.study.runs import load_run

    return [load_run(TINY, s) for s in SEEDS]


def _refuse_to_compute(monkeypatch):
    """Computing an entry (its held-out trials, which no key names) fails the test."""
    import docking.experiments

    def refuse(*args, **kwargs):
        raise AssertionError("computed, not read from the ledger")

    monkeypatch.setattr(docking.experiments, "heldout_trials", refuse)


def test_a_fresh_clone_is_served_the_committed_entries_without_computing(copy, monkeypatch):
    folder, values = copy
    _refuse_to_compute(monkeypatch)
    assert [derived.oracle_labelled_success(r, N_TRIALS) for r in _runs()] == values
    assert not (Path(folder).parent / "results" / "derived").exists()  # nothing was written


def test_another_question_of_the_same_runs_is_computed(copy, monkeypatch):
    """The ledger's key names the views (two oracle trials); other views are another key."""
    _refuse_to_compute(monkeypatch)
    with pytest.raises(AssertionError, match="computed, not read"):
        derived.oracle_labelled_success(_runs()[0], N_TRIALS + 1)


def test_an_entry_keyed_by_other_analysis_code_is_never_served(copy, monkeypatch):
    """The key names the functions that compute an entry by their sources: after an edit of
    one (here, oracle_labelled replaced by another function), the committed entries are
    computed again, and verify draws none."""
    folder, _ = copy
    real = analysis.oracle_labelled

    def oracle_labelled(net, labelled):  # an edit
        return real(net, labelled)

    monkeypatch.setattr(analysis, "oracle_labelled", oracle_labelled)
    assert derived.served(ledger.manifest(folder), "oracle-labelled-success") == []
    _refuse_to_compute(monkeypatch)
    with pytest.raises(AssertionError, match="computed, not read"):
        derived.oracle_labelled_success(_runs()[0], N_TRIALS)


def test_an_edit_elsewhere_in_analysis_leaves_the_entries_served(copy, monkeypatch, tmp_path):
    folder, values = copy
    edited = tmp_path / "analysis.py"
    edited.write_bytes(Path(analysis.__file__).read_bytes() + b"\n# an edit elsewhere\n")
    monkeypatch.setattr(analysis, "__file__", str(edited))
    assert len(derived.served(ledger.manifest(folder), "oracle-labelled-success")) == 2
    _refuse_to_compute(monkeypatch)
    assert [derived.oracle_labelled_success(r, N_TRIALS) for r in _runs()] == values


def test_verify_recomputes_the_entries_from_their_keys_and_finds_them_equal(copy):
    folder, _ = copy
    checks = verify.verify_derived(None, folder)
    assert sorted((c.name, c.run, c.seed, c.equal) for c in checks) == [
        (name, "tiny", s, True)
        for name in ("feature-fidelity", "oracle-labelled-success")
        for s in SEEDS
    ]
    assert len(verify.verify_derived(1, folder)) == 2  # one of each table


def test_the_feature_fidelity_is_served_without_rendering(copy, monkeypatch):
    """The third edition's measure reads the ledger's feature fidelity; rendering a start
    view (what computing it takes) fails the test."""
    import docking.world

    held = np.load(copy[0] / "derived" / "feature-fidelity.npz")["fidelity"]

    def refuse(*args, **kwargs):
        raise AssertionError("rendered, not read from the ledger")

    monkeypatch.setattr(docking.world, "DockingEnv", refuse)
    analysis.start_views.cache_clear()
    served = [derived.feature_fidelity(r, TINY.world, VIEWS, 1) for r in _runs()]
    assert sorted(served) == sorted(held.tolist()) and all(np.isfinite(served))


def _forge(folder: Path, change) -> None:
    """Change the success of every entry of the derived table, rewrite the file and put its
    SHA-256 in the manifest (nothing else)."""
    path = folder / "derived" / "oracle-labelled-success.npz"
    with np.load(path) as found:
        table = {k: found[k] for k in found.files}
    table["success"] = change(table["success"])
    path.write_bytes(ledger_rows.npz(table))
    manifest = folder / "manifest.json"
    data = json.loads(manifest.read_text())
    data["derived"]["oracle-labelled-success"] = hashlib.sha256(path.read_bytes()).hexdigest()
    manifest.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    ledger._read_manifest.cache_clear()
    ledger._table.cache_clear()
    ledger._row_index.cache_clear()


def _reseal(folder: Path) -> None:
    manifest = folder / "manifest.json"
    data = json.loads(manifest.read_text())
    data["seals"] = ledger.seals_of(data)
    manifest.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    ledger._read_manifest.cache_clear()


def test_a_forged_entry_is_refused_until_resealed_then_verify_names_it(copy, capsys):
    folder, values = copy
    _forge(folder, lambda success: 1.0 - success)
    assert main(["ledger", "show"]) == 1  # the derived table's digest is sealed
    assert "(derived) do not match their seal" in capsys.readouterr().err
    _reseal(folder)
    assert main(["ledger", "show"]) == 0  # a consistent forgery: no digest can catch it
    capsys.readouterr()
    served = [derived.oracle_labelled_success(r, N_TRIALS) for r in _runs()]
    assert served == [1.0 - v for v in values]  # what a reader would be served
    checks = verify.verify_derived(None, folder)
    bad = sorted((c.name, c.seed) for c in checks if not c.equal)
    assert len(checks) == 4 and bad == [("oracle-labelled-success", s) for s in SEEDS]


def test_the_verify_command_fails_on_a_forged_entry(copy, capsys):
    folder, _ = copy
    _forge(folder, lambda success: 1.0 - success)
    _reseal(folder)
    assert main(["verify", "--table", "tiny", "--processes", "1"]) == 0  # runs only
    capsys.readouterr()
    assert main(["verify", "--sample", "0", "--derived", "2", "--processes", "1"]) == 1
    out = capsys.readouterr().out
    assert "MISMATCH derived oracle-labelled-success of tiny seed" in out
    assert "2 of 4 recomputed derived entries equal the ledger" in out  # fidelity: not forged


def test_a_derived_table_that_is_not_a_regular_file_is_one_line(copy, capsys):
    folder, _ = copy
    path = folder / "derived" / "oracle-labelled-success.npz"
    path.unlink()
    path.symlink_to("/dev/zero")
    assert main(["ledger", "show"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "oracle-labelled-success" in err, err


def test_a_ledger_update_keeps_the_derived_tables(copy, tmp_path, monkeypatch):
    folder, values = copy
    results = tmp_path / "again"
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    for s in SEEDS:
        run_or_load(TINY, s, results, progress=False)
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    data = ledger.update(
        [(TINY, s, False, frozenset({"networks"})) for s in SEEDS], folder, results
    )
    assert set(data["derived"]) == {"oracle-labelled-success", "feature-fidelity"}
    assert ledger.check_files(folder)
    _refuse_to_compute(monkeypatch)
    assert [derived.oracle_labelled_success(r, N_TRIALS) for r in _runs()] == values


def test_commit_takes_only_entries_of_runs_the_ledger_holds(copy, tmp_path, monkeypatch):
    """An entry of a run the ledger does not hold (seed 9, computed in the store only) stays
    out of the ledger."""
    folder, _ = copy
    results = tmp_path / "results"
    monkeypatch.setenv("DOCKING_LEDGER", "off")
    run = run_or_load(TINY, 9, results, progress=False)
    derived.oracle_labelled_success(run, N_TRIALS)
    monkeypatch.setenv("DOCKING_LEDGER", str(folder))
    assert derived.commit(folder, results) == {"oracle-labelled-success": 2, "feature-fidelity": 2}


def test_a_derived_table_named_outside_the_ledger_is_refused(copy, capsys):
    """A manifest that names a derived table ``../../outside`` (its seal recomputed) is not
    a ledger manifest: one line, before any file is read (the reader would refuse a path out
    of the folder too)."""
    folder, _ = copy
    manifest = folder / "manifest.json"
    data = json.loads(manifest.read_text())
    data["derived"]["../../outside"] = data["derived"].pop("oracle-labelled-success")
    data["seals"] = ledger.seals_of(data)
    manifest.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    ledger._read_manifest.cache_clear()
    assert main(["ledger", "show"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "is not a ledger manifest" in err, err
    assert "outside" in err
