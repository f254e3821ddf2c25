"""Pre-registered rules kept as records (issue 61, docking.study.records): each design's
record is the rules text whose digest its tests pinned at the rules' commit; its procedure's
verbatim copy is the code that digest covered; the live design states the same constants, cells
and claims; replayed on the committed ledger's runs, the live code walks the cells and reaches
the verdicts the record holds; and the rules' commit came before the design's first run."""

from __future__ import annotations

import copy
import hashlib
import json
from pathlib import Path

import pytest

from docking.study import fingerprint, provenance, records, report
from docking.study.designs import replay, rules_data

ROOT = Path(__file__).resolve().parents[1]

#: Each pre-registered design's rules digest, pinned by its tests at the rules' commit.
PINNED = {
    "third-edition": "cd2a0602b296679342c67a9afe926c24a0baa8901a6f55c48a4e2fbac2984ac4",
    "untested": "9c3e3a99b36d5f6f16eef28e8ef64bc9a7751bcb46b6b99a23932784e66c52b7",
    "fragility-landscape": "1e457a7d4dd78ecef8eb4de75b91126021a8c63dfacfb4740d533a4c9b89ac9c",
    "third-edition-addendum": "7809d4840d852585f603d398a8a24f8c31a1c635af7b71396390d747cd9728b9",
    "addendum-bracketing": "061f85bf9f2da895b0038717c06fc814a98c213ab4f01bd8f64c1c14b1978077",
    "addendum-bracketing-continued": (
        "0cbf59c64e30ae0423858268f0e5a7404f26b340fe772a75ca72fc26450976e4"
    ),
    "untested-revisited": "580a6f6e3a0dfcf48976abdfd065c7cb93e73cc70325192beb9f0925c49d0f6b",
    "bracketing-replication": "4aacdf6f66bdac36460b5e0ed4941a87ab22c8b2cd894c912704c27a484cf15e",
    "equal-contest": "b1de72d16f0eeccc43a727f11c3de0f02b8503dfc2de6d5cbfad4cecae00f145",
}
#: Where a rules digest covered code: the constant that held that code's digest.
CODE = {
    "third-edition-addendum": "code",
    "addendum-bracketing": "code",
    "addendum-bracketing-continued": "code",
    "untested-revisited": "code",
    "bracketing-replication": "verdicts",
    "equal-contest": "procedure",
}
#: The third edition's erratum to one label (its rule's margin is symmetric): now, committed.
ERRATUM = (
    "the paper's networks without a red cup minus with one never seen in training",
    "the paper's networks with a red cup never seen minus without",
)


@pytest.mark.parametrize("name", sorted(PINNED))
def test_the_record_is_the_rules_text_pinned_at_the_rules_commit(name):
    assert records.digest(name) == PINNED[name]


def _code_digest(name: str) -> str:
    """The digest the rules text held of its code, recomputed from the verbatim copy as the
    design computed it at its rules' commit."""
    parts = records.parts(name)
    if name == "bracketing-replication":  # its verdict functions' source
        return hashlib.sha256("".join(t for _, _, t in parts).encode()).hexdigest()
    if name == "equal-contest":  # its procedure's source
        return hashlib.sha256(records.procedure(name).encode()).hexdigest()
    digest = hashlib.sha256()
    (module, text) = next((w, t) for k, w, t in parts if k == "module")
    digest.update(fingerprint.code_tokens(text, module)[0].encode())
    before = {"addendum-bracketing": "third-edition-addendum"}
    before["addendum-bracketing-continued"] = "addendum-bracketing"
    if name in before:  # the rules it continues, as committed
        digest.update(records.text(before[name]).encode())
    for kind, _, text in parts:
        if kind == "function":
            digest.update(text.encode())
    if name == "untested-revisited":
        from docking.study.claims import NEAR_BOUND

        digest.update(repr(NEAR_BOUND).encode())
    return digest.hexdigest()


@pytest.mark.parametrize("name", sorted(CODE))
def test_the_verbatim_copy_is_the_code_the_rules_pinned(name):
    assert _code_digest(name) == records.data(name)["constants"][CODE[name]]


def test_a_changed_verbatim_copy_is_caught(monkeypatch):
    text = records.procedure("third-edition-addendum")
    assert "GAP_CLOSED = 0.05" in text
    monkeypatch.setattr(records, "procedure", lambda n: text.replace("0.05", "0.06", 1))
    assert (
        _code_digest("third-edition-addendum")
        != records.data("third-edition-addendum")["constants"]["code"]
    )


def _recorded(name: str) -> dict:
    data = records.amended(name)  # the record with its amendments (the equal contest's one)
    data["constants"].pop(CODE.get(name, ""), None)
    if name == "third-edition":
        return json.loads(json.dumps(data).replace(json.dumps(ERRATUM[1]), json.dumps(ERRATUM[0])))
    return data


@pytest.mark.parametrize("name", sorted(PINNED))
def test_the_live_design_states_the_recorded_rules(name):
    """Its constants, cells and claims are the record's with its amendments (the third
    edition's with its one erratum, a label; the equal contest's with its amendment 1): the
    code that states them is free to change otherwise."""
    assert rules_data(name) == _recorded(name)


def test_a_changed_constant_is_not_the_record(monkeypatch):
    from docking.study.designs import replication as rp

    monkeypatch.setattr(rp, "GAP_CLOSED", 0.06)
    assert rules_data("bracketing-replication") != _recorded("bracketing-replication")


def _canonical(value) -> str:
    return json.dumps(value, sort_keys=True)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(PINNED))
def test_the_live_procedure_replays_the_recorded_cells_and_verdicts(name, monkeypatch):
    """Replayed on the committed ledger's runs (never computed), the live code walks the
    cells its record's replay holds and reaches the same decisions and verdicts."""
    monkeypatch.setenv("DOCKING_LEDGER", str(ROOT / "ledger"))
    assert _canonical(replay(name)) == _canonical(records.replay(name))


@pytest.mark.slow
def test_the_replay_fails_when_a_score_or_a_rule_is_altered(monkeypatch, tmp_path):
    """The replay test can fail: with one ledger score altered (a run's held-out trials read
    back with its failures made successes) the replication's verdicts differ from the
    record's; with
    a rule altered (the live gap rule's bound) they differ too."""
    from docking.study import design
    from docking.study.designs import replication as rp

    monkeypatch.setenv("DOCKING_LEDGER", str(ROOT / "ledger"))
    recorded = records.replay("bracketing-replication")
    loaded = design._loaded

    def forged(d, cells, results_dir=None):
        found = loaded(d, cells, results_dir)
        if "floor/paper" in found:
            run = copy.deepcopy(found["floor/paper"][0])
            assert not run.heldout.success.all()
            run.heldout.success[:] = True
            found["floor/paper"] = [run, *found["floor/paper"][1:]]
        return found

    monkeypatch.setattr(design, "_loaded", forged)
    assert _canonical(replay("bracketing-replication")) != _canonical(recorded)
    monkeypatch.setattr(design, "_loaded", loaded)
    assert _canonical(replay("bracketing-replication")) == _canonical(recorded)
    rule = rp.gap_verdict
    monkeypatch.setattr(rp, "gap_verdict", lambda linear, paper: rule(linear, paper, bound=0.01))
    assert _canonical(replay("bracketing-replication")) != _canonical(recorded)


@pytest.mark.parametrize("name", sorted(provenance.RULES_COMMITS))
def test_the_rules_commit_came_before_the_designs_first_run(name):
    runs = json.loads((ROOT / "ledger" / "manifest.json").read_text())["runs"].values()
    times = [report.utc(r["computed_utc"]) for r in runs if r["name"] == name]
    assert times and min(times) > report.utc(provenance.RULES_COMMITS[name][1])
    ours = [r.get("rules_sha256") for r in runs if r["name"] == name and r.get("rules_sha256")]
    assert set(ours) <= {records.in_force_digest(name)}


def test_the_rules_in_force_are_the_record_and_its_amendments():
    """Without an amendment the digest in force is the record's; with one it is another (the
    equal contest's), and it moves if the amendment's file does."""
    assert records.in_force_digest("bracketing-replication") == records.digest(
        "bracketing-replication"
    )
    assert records.in_force_digest("equal-contest") != records.digest("equal-contest")
