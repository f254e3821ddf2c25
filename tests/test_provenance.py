"""Rules before runs, provable from the ledger: for every design whose rules commit is
recorded (:data:`docking.study.provenance.RULES_COMMITS`), the commit is the one the history holds,
and every run of its ledger table was computed after it."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from helpers import old_path

from docking.study import provenance, report
from docking.study.designs import MODULES

ROOT = Path(__file__).resolve().parents[1]


def _manifest_runs(name: str) -> list[dict]:
    runs = json.loads((ROOT / "ledger" / "manifest.json").read_text())["runs"].values()
    return [r for r in runs if r["name"] == name]


def early(runs, rules_time) -> list:
    """The seeds of ``runs`` (ledger records) without a time or computed before the rules."""
    return [
        r["seed"]
        for r in runs
        if "computed_utc" not in r or report.utc(r["computed_utc"]) <= rules_time
    ]


@pytest.mark.parametrize("name", sorted(provenance.RULES_COMMITS))
def test_the_rules_commit_is_the_one_history_holds(name):
    shallow = subprocess.run(
        ["git", "rev-parse", "--is-shallow-repository"], capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()
    if shallow != "false":
        pytest.skip("a shallow clone (or no git): the history that added the rules is not here")
    module = MODULES[name]  # added before issue 51 (docking/designs/) or since (docking/study/)
    places = [old_path(module), module.replace(".", "/") + ".py"]
    git = ["git", "log", "--diff-filter=A", "--format=%H %cI", "--", *places]
    log = subprocess.run(git, capture_output=True, text=True, check=True, cwd=ROOT).stdout
    assert log.split() == list(provenance.RULES_COMMITS[name])


@pytest.mark.parametrize("name", sorted(provenance.RULES_COMMITS))
def test_every_run_was_computed_after_its_rules_commit(name):
    runs = _manifest_runs(name)
    assert runs, f"the ledger holds no run of {name}"
    assert early(runs, report.utc(provenance.RULES_COMMITS[name][1])) == []


def test_a_run_older_than_its_rules_or_without_a_time_is_caught():
    import datetime

    rules = report.utc("2026-11-27T00:00:00+00:00")
    later = (rules + datetime.timedelta(seconds=1)).isoformat()
    runs = [{"seed": 1, "computed_utc": "2026-01-01T00:00:00+00:00"}, {"seed": 2}]
    runs.append({"seed": 3, "computed_utc": later})
    assert early(runs, rules) == [1, 2]


def _history() -> bool:
    shallow = subprocess.run(
        ["git", "rev-parse", "--is-shallow-repository"], capture_output=True, text=True, cwd=ROOT
    ).stdout.strip()
    return shallow == "false"


@pytest.mark.parametrize("deviation", [d for d in provenance.DEVIATIONS if d.commit], ids=str)
def test_each_deviation_is_the_history_s(deviation):
    """A listed deviation's commit exists, touched the file named, and came after the
    commit that added its design's rules."""
    if not _history():
        pytest.skip("a shallow clone (or no git): the history is not here")
    git = ["git", "show", "--name-only", "--format=%cI", deviation.commit]
    shown = subprocess.run(git, capture_output=True, text=True, check=True, cwd=ROOT).stdout
    when, *paths = [line for line in shown.splitlines() if line]
    assert deviation.path in paths
    module = MODULES[deviation.design]  # where it was added: before issue 51 or since
    places = [old_path(module), module.replace(".", "/") + ".py"]
    added = ["git", "log", "--diff-filter=A", "--format=%cI", "--", *places]
    rules = subprocess.run(added, capture_output=True, text=True, check=True, cwd=ROOT).stdout
    assert report.utc(when) > report.utc(rules.split()[-1])


def test_every_deviation_names_a_design_and_is_shown_in_its_table():
    for d in provenance.DEVIATIONS:
        assert d.design in MODULES
        assert d.what in provenance.deviations_table(d.design)
    assert "none known" in provenance.deviations_table("paper")


#: The designs whose every ledger run records the rules it was judged by (the designs whose
#: runs were written after the ledger began recording them; the earlier ones' runs record
#: their computed time at most).
RULES_RECORDED = (
    "addendum-bracketing",
    "addendum-bracketing-continued",
    "untested-revisited",
    "bracketing-replication",
    "fragility-landscape",
    "equal-contest",
)


@pytest.mark.parametrize("name", RULES_RECORDED)
def test_every_run_carries_the_digest_of_its_designs_recorded_rules(name):
    """Every run records the digest of its design's rules as committed before the runs: its
    record's (tests/test_records.py holds the record to the digest pinned then), which is what
    the ledger records for new runs too (:func:`rules_digest`)."""
    from docking.study import records
    from docking.study.designs import rules_digest

    runs = _manifest_runs(name)
    assert runs and {r.get("rules_sha256") for r in runs} == {records.in_force_digest(name)}
    assert rules_digest(name) == records.in_force_digest(name)


def test_a_run_with_other_rules_breaks_its_tables_seal():
    from docking.study import ledger

    records = {"k1": {"name": "t", "digest": "d", "rules_sha256": "a"}}
    sealed = ledger._seals(records)
    records["k1"]["rules_sha256"] = "b"
    assert ledger._seals(records) != sealed
    del records["k1"]["rules_sha256"]  # a record from before the field: sealed as it was
    assert ledger._seals(records) == ledger._seals({"k1": {"name": "t", "digest": "d"}})


def test_the_summary_says_where_rules_before_runs_is_proven_and_where_not():
    """provenance.provenance_text: the designs whose runs' times prove their rules came first,
    and every other table whose runs carry no time, with their counts from the manifest."""
    folder = ROOT / "ledger"
    timed, untimed = provenance.provenance_counts(folder)
    assert set(timed) == set(provenance.RULES_COMMITS)
    for name, n in timed.items():
        assert n == len(_manifest_runs(name))
    for name, n in untimed.items():
        assert name not in timed
        assert n == sum("computed_utc" not in r for r in _manifest_runs(name)) > 0
    text = provenance.provenance_text(folder)
    assert all(f"{name} ({n:,})" in text for name, n in {**timed, **untimed}.items())
    assert text in provenance.candour_text(folder)
