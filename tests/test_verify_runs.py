"""The runs behind one number (issue 60): ``verify --design NAME --cells KEY --seeds SEEDS``
recomputes the runs of a design's cells (not a whole table), says first what that costs (from
the ledger's wall times of those runs), and catches a forgery of one of them that every
check reading the ledger passes; :func:`docking.study.report.verify_command` gives the
command beside a number."""

from __future__ import annotations

import hashlib
import json
import shlex
import shutil
import signal
from pathlib import Path

import numpy as np
import pytest

from docking.study import ledger, ledger_rows, verify
from docking.study.cli import main, parse
from docking.study.cli.ledger import Verify, _duration, _verify_plan
from docking.study.designs import equal_contest as ec
from docking.study.designs import replication as rp
from docking.study.report import verify_command
from docking.study.runs import load_run

REPO = Path(__file__).resolve().parent.parent
#: The number of the issue: the replication's floor-world paper's learner, five of its seeds
#: (the command's mechanics are tested on it).
DESIGN, CELL, SEEDS = rp.NAME, "floor/paper", tuple(range(7100, 7105))
#: The README's floor-world number now: the equal contest's judged paper's learner (a cell its
#: stages add) and five of its seeds (the forger edits the one of them with most failures).
NUMBER = (ec.NAME, "floor/paper/judged", tuple(range(7200, 7205)))


@pytest.fixture
def committed(monkeypatch):
    """The committed ledger (the unit tests' is off), its caches cleared."""
    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    _clear()


@pytest.fixture
def restore_sigterm():
    """main() installs a SIGTERM handler; put the test process's back."""
    handler = signal.getsignal(signal.SIGTERM)
    yield
    signal.signal(signal.SIGTERM, handler)


def _clear():
    ledger._read_manifest.cache_clear()
    ledger._table.cache_clear()
    ledger._row_index.cache_clear()


def _parsed(command: str) -> Verify:
    words = shlex.split(command)
    assert words[:3] == ["python", "-m", "docking"], command
    found = parse(words[3:])
    assert isinstance(found, Verify)
    return found


def test_the_command_beside_a_number_names_exactly_its_runs(committed):
    """The command verify_command gives parses to the runs of the cell and seeds asked for,
    each the ledger's run of the design's configuration, and its plan states their cost as the
    ledger records it."""
    command = verify_command(DESIGN, CELL, SEEDS)
    assert command == (
        "python -m docking verify --design bracketing-replication --cells floor/paper "
        "--seeds 7100-7104"
    )
    runs = _parsed(command)._design_runs()
    config = rp.DESIGN.cell(CELL).config
    assert [(cell, seed) for cell, _, seed in runs] == [(CELL, s) for s in SEEDS]
    assert all(found == config for _, found, _ in runs)
    data = ledger.manifest()
    keys = verify.named_runs(data, [(c, s) for _, c, s in runs])
    records = [data["runs"][k] for k in keys]
    assert [(r["name"], r["seed"]) for r in records] == [(DESIGN, s) for s in SEEDS]
    assert all(r["config"] == config.to_dict() for r in records)
    seconds = sum(r["wall_seconds"] for r in records)
    plan = _verify_plan(3, False, 2, None, (), runs)
    assert plan.startswith(
        "verify: recomputing the 5 runs behind cell floor/paper, seeds 7100-7104 "
        "(table bracketing-replication); "
    ), plan
    assert f"about {_duration(seconds / 2)} on 2 processes ({_duration(seconds)} of" in plan
    # every seed of the cell, and two cells by a pattern
    assert len(_parsed(verify_command(DESIGN, CELL))._design_runs()) == len(rp.SEEDS)
    both = _parsed(verify_command(DESIGN, "floor/*", [7100]))._design_runs()
    assert [c for c, _, _ in both] == ["floor/paper", "floor/linear", "floor/ppo"]


def test_a_stage_cell_is_named_and_resolved_from_the_ledger(committed):
    """A cell a stage adds (the bracketing continued's walk) is found by walking the stages on
    the ledger's runs, and its runs are the ledger's."""
    from docking.study.designs import bracketing_continued as bc

    every = _parsed(verify_command(bc.DESIGN.name))._design_runs()
    static = {c.key for c in bc.DESIGN.cells}
    staged = [(cell, config, seed) for cell, config, seed in every if cell not in static]
    assert staged, "the design's stages added no cell: the test cannot tell them apart"
    cell, _, seed = staged[-1]
    runs = _parsed(verify_command(bc.DESIGN.name, cell, [seed]))._design_runs()
    assert [(c, s) for c, _, s in runs] == [(cell, seed)]
    assert len(verify.named_runs(ledger.manifest(), [(runs[0][1], seed)])) == 1


@pytest.mark.parametrize(
    "args, says",
    [
        (["--design", DESIGN, "--cells", "floor/papr"], "has no cell matching 'floor/papr'"),
        (["--design", DESIGN, "--cells", CELL, "--seeds", "7000"], "no cell chosen runs seed 7000"),
        (["--design", DESIGN, "--cells", CELL, "--seeds", "7100,7100"], "must not repeat"),
        (["--cells", CELL], "--cells and --seeds choose runs of a design: name it"),
        (["--seeds", "7100"], "--cells and --seeds choose runs of a design: name it"),
        (["--design", DESIGN, "--table", DESIGN], "--table, --all and --design: give one"),
        (["--design", DESIGN, "--all"], "--table, --all and --design: give one"),
        (["--design", "replication"], "invalid choice"),
    ],
)
def test_verify_of_runs_no_design_has_is_one_line_before_any_work(
    args, says, committed, capsys, restore_sigterm
):
    try:
        status = main(["verify", *args])
    except SystemExit as exc:  # tyro refuses a choice as argparse does
        status = exc.code
    assert status == 2
    out = capsys.readouterr()
    assert says in out.err and "Traceback" not in out.err, out.err
    assert "recomputing" not in out.out  # refused before its plan


@pytest.mark.parametrize(
    "args, says",
    [
        (("../x",), "verify_command.design must be a safe file-name component"),
        ((DESIGN, ""), "verify_command.cells[0] must be a cell's key or pattern"),
        ((DESIGN, CELL, []), "verify_command.seeds is empty"),
        ((DESIGN, CELL, [-1]), "verify_command.seeds[] must be in"),
        ((DESIGN, CELL, "7100"), "verify_command.seeds must be integers"),
        ((DESIGN, CELL, [7100.0]), "verify_command.seeds[] must be an integer"),
    ],
)
def test_verify_command_refuses_what_no_command_could_name(args, says):
    with pytest.raises((ValueError, TypeError)) as found:
        verify_command(*args)
    assert says in str(found.value)


def test_verify_command_quotes_a_pattern_and_writes_seeds_as_ranges():
    assert verify_command("paper", ["floor/*", "a b"], [4, 0, 1, 2]) == (
        "python -m docking verify --design paper --cells 'floor/*' 'a b' --seeds 0-2,4"
    )
    assert verify_command("paper") == "python -m docking verify --design paper"


# A forgery resealed, and the five runs behind the number recomputed ---------------------------


def _forge(folder: Path, key: str, flips: int, table_name: str = ec.NAME) -> float:
    """The forgery of issue 60: in the table ``table_name``, the first ``flips`` failed
    held-out trials of run ``key`` made successes; the table rewritten, its SHA-256 put in the
    manifest's tables, the run's row digest taken from the forged table and the manifest
    resealed (a forger who can run the package). The run's forged held-out success."""
    path = folder / "tables" / f"{table_name}.npz"
    with np.load(path) as found:
        table = {k: found[k] for k in found.files}
    column = "heldout.success"
    row = table["key"].tolist().index(key)
    start = int(np.sum(np.maximum(table[column + ".count"][:row], 0)))
    cells = table[column][start : start + table[column + ".count"][row]]
    failed = np.flatnonzero(~cells)[:flips]
    assert len(failed) == flips, "too few failures to forge: choose another run"
    cells[failed] = True
    table[column][start : start + len(cells)] = cells
    path.write_bytes(ledger_rows.npz(table))
    manifest = folder / "manifest.json"
    data = json.loads(manifest.read_text())
    data["tables"][table_name] = hashlib.sha256(path.read_bytes()).hexdigest()
    for k, row_cells in ledger_rows.rows(ledger_rows.table_bytes(path.read_bytes())):
        data["runs"][k]["row"] = ledger_rows.row_digest(row_cells)
    data["seals"] = ledger.seals_of(data)
    manifest.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    _clear()
    return float(cells.mean())


@pytest.mark.slow
def test_verify_of_the_five_runs_behind_a_number_catches_one_forged_and_resealed(
    tmp_path, monkeypatch, capsys, restore_sigterm
):
    """On a copy of the committed ledger, the README's floor-world number (the equal contest's
    judged paper's learner): the forged run verified before the forgery equals the ledger; the
    forgery (one run's held-out successes raised, the table, its digest, the row digests and
    the seals rewritten) passes ledger show and is served, moving the number; verify of the
    cell's five named runs names that run, and only it."""
    design, cell, seeds = NUMBER
    copy = tmp_path / "ledger"
    shutil.copytree(REPO / "ledger", copy)
    monkeypatch.setenv("DOCKING_LEDGER", str(copy))
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))  # an empty store
    _clear()
    every = _parsed(verify_command(design, cell))._design_runs()  # the cell's runs, by the walk
    config = every[0][1]
    assert [s for _, _, s in every] == list(ec.SEEDS)
    forged = min(seeds, key=lambda s: load_run(config, s).heldout.success.mean())
    command = shlex.split(verify_command(design, cell, seeds))[3:] + ["--processes", "2"]
    one = shlex.split(verify_command(design, cell, [forged]))[3:] + ["--processes", "2"]

    def number() -> float:
        return float(np.mean([load_run(config, s).heldout.success.mean() for s in ec.SEEDS]))

    before = number()
    assert main(one) == 0  # the untouched copy: equal
    out = capsys.readouterr().out
    assert f"ok       {design} seed {forged}" in out and "1 of 1 recomputed runs equal" in out
    (key,) = verify.named_runs(ledger.manifest(), [(config, forged)])
    flips = 20
    rate = _forge(copy, key, flips=flips)
    assert main(["ledger", "show"]) == 0  # every check that reads the ledger passes it
    capsys.readouterr()
    assert load_run(config, forged).heldout.success.mean() == rate  # and it is served
    assert number() == pytest.approx(before + flips / 500 / len(ec.SEEDS))  # the number moved
    assert main(command) == 1
    out = capsys.readouterr().out
    assert out.splitlines()[0].startswith(f"verify: recomputing the 5 runs behind cell {cell}")
    lines = [line for line in out.splitlines() if f"{design} seed" in line]
    assert len(lines) == 5, out
    assert [line.split()[0] for line in lines] == [
        "MISMATCH" if s == forged else "ok" for s in seeds
    ], out
    assert f"MISMATCH {design} seed {forged}" in out
    assert "its table row (heldout.success) differ" in out
    assert "4 of 5 recomputed runs equal the ledger" in out
