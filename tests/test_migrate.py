"""The migration (docking.study.migrate, ``python -m docking ledger migrate``): a real refactor of a
copy of the package (a keyed function split in two, a keyed module renamed) re-keys a tiny
ledger and its store without recomputing them, after recomputing a sample that covers every
table, kind of run and world; a change that alters a number migrates nothing and names the
runs that differ."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from docking.study import migrate

ROOT = Path(__file__).resolve().parents[1]

#: Builds a tiny store and ledger with the package on the path: two worlds, two kinds of run
#: (the paper's learner and a yardstick), a run kept whole, a table that keeps more.
BUILD = """
import dataclasses, sys
from pathlib import Path

from docking.study import ledger, store
from docking.study import kinds
from docking.study.design import yardstick_config
from docking.study.designs.builders import experiment2_in
from docking.presets import EXPERIMENT_1, FLOOR_WORLD

results, folder = Path(sys.argv[1]), Path(sys.argv[2])
small = dict(train_trials=4, test_trials=6, eval_every=4, eval_trials=1, heldout_trials=5)
tiny = dataclasses.replace(EXPERIMENT_1, name="tiny", **small)
floor = dataclasses.replace(experiment2_in(FLOOR_WORLD, "tiny-floor"), **small)
oracle = yardstick_config(tiny, "oracle", 5)
runs = [
    (tiny, 0, True, frozenset()),
    (tiny, 1, False, frozenset({"starts", "networks"})),
    (floor, 0, False, frozenset()),
    (oracle, 0, False, frozenset()),
]
for config, seed, *_ in runs:
    store.run_or_load(config, seed, results, progress=False)
store.run_or_load(tiny, 2, results, progress=False)  # in the store only: a seed no proof ran
ledger.update(runs, folder, results)
"""

#: Prints what this code finds: the ledger's check and whether the store serves every run
#: without computing (a runner that fails if asked to compute).
CHECK = """
import dataclasses, json, sys
from pathlib import Path

from docking.study import kinds, ledger
from docking.study.design import yardstick_config
from docking.study.designs.builders import experiment2_in
from docking.presets import EXPERIMENT_1, FLOOR_WORLD

results, folder = Path(sys.argv[1]), Path(sys.argv[2])
small = dict(train_trials=4, test_trials=6, eval_every=4, eval_trials=1, heldout_trials=5)
tiny = dataclasses.replace(EXPERIMENT_1, name="tiny", **small)
floor = dataclasses.replace(experiment2_in(FLOOR_WORLD, "tiny-floor"), **small)
oracle = yardstick_config(tiny, "oracle", 5)
checked = ledger.check_files(folder)
stored = [
    kinds.result_path(c, s, results).exists()
    for c, s in ((tiny, 0), (tiny, 1), (tiny, 2), (floor, 0), (oracle, 0))
]
print(json.dumps({"checked": checked, "stored": stored}))
"""


def _copy(tmp_path: Path) -> Path:
    """A copy of the package (``src/docking``) to refactor."""
    src = tmp_path / "src"
    shutil.copytree(ROOT / "docking", src / "docking", ignore=shutil.ignore_patterns("__pycache__"))
    return src


def _python(src: Path, *args, ledger_dir: Path | None = None, timeout: int = 900):
    env = {
        **os.environ,
        "PYTHONPATH": str(src),
        "DOCKING_LEDGER": str(ledger_dir) if ledger_dir else "off",
        "MUJOCO_GL": "egl",
        "PYOPENGL_PLATFORM": "egl",
    }
    env.pop("DOCKING_RESULTS", None)
    return subprocess.run(  # in src's folder: python -m puts the current folder first
        [sys.executable, *args],
        env=env,
        cwd=src.parent,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _split_exp(src: Path) -> None:
    """A keyed function split in two: ``arith.exp``'s body moves to ``_exp_body``, which
    ``exp`` calls (the same arithmetic)."""
    path = src / "docking" / "arith.py"
    text = path.read_text()
    assert text.count("def exp(x: np.ndarray) -> np.ndarray:") == 1
    text = text.replace("def exp(x: np.ndarray) -> np.ndarray:", "def _exp_body(x):")
    text += '\n\ndef exp(x: np.ndarray) -> np.ndarray:\n    """``exp``."""\n'
    text += "    return _exp_body(x)\n"
    path.write_text(text)


def _rename_region(src: Path) -> None:
    """A keyed module renamed: ``docking.region`` becomes ``docking.start_region``, every
    import of it rewritten."""
    package = src / "docking"
    (package / "region.py").rename(package / "start_region.py")
    found = 0
    for path in package.rglob("*.py"):
        text = path.read_text()
        new = re.sub(r"\bdocking\.region\b", "docking.start_region", text)
        if new != text:
            found += 1
            path.write_text(new)
    assert found >= 1


def _changed_number(src: Path) -> None:
    """A change that alters numbers: ``exp`` off by one part in a billion."""
    path = src / "docking" / "arith.py"
    text = path.read_text()
    old = "np.array([math.exp(v) for v in x.tolist()], dtype=np.float64)"
    assert text.count(old) == 1
    path.write_text(text.replace(old, f"(1 + 1e-9) * {old}"))


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A tiny ledger and store computed by the package as it is (a copy of it)."""
    base = tmp_path_factory.mktemp("migrate")
    src = _copy(base)
    out = _python(src, "-c", BUILD, str(base / "results"), str(base / "ledger"))
    assert out.returncode == 0, out.stderr[-3000:]
    return base


def _migrate(src: Path, folder: Path, results: Path, old: Path):
    """``ledger migrate`` by the package in ``src``, the battery's old code the one in ``old``."""
    return _python(
        src,
        "-m",
        "docking",
        "ledger",
        "migrate",
        "--results-dir",
        str(results),
        "--old",
        str(old),
        ledger_dir=folder,
    )


def _refused_then_migrated(src: Path, folder: Path, results: Path, old: Path):
    """The changed code in ``src`` refuses the ledger in ``folder``, naming the command that
    migrates it; ``ledger migrate`` (the battery's old code ``old``) then succeeds. Its
    output and the migrated manifest."""
    refused = _python(src, "-m", "docking", "ledger", "show", ledger_dir=folder)
    assert refused.returncode == 1 and "ledger migrate" in refused.stderr, refused.stderr
    out = _migrate(src, folder, results, old)
    assert out.returncode == 0, out.stderr[-3000:]
    return out, json.loads((folder / "manifest.json").read_text())


def _fresh(built: Path, tmp_path: Path) -> tuple[Path, Path, Path]:
    """A copy of the built package, ledger and store, to change."""
    for name in ("src", "ledger", "results"):
        shutil.copytree(built / name, tmp_path / name)
    return tmp_path / "src", tmp_path / "ledger", tmp_path / "results"


@pytest.mark.slow
def test_a_refactor_migrates_the_ledger_and_the_store_after_a_sample_equal_to_it(built, tmp_path):
    src, folder, results = _fresh(built, tmp_path)
    before = json.loads((folder / "manifest.json").read_text())
    _split_exp(src)
    _rename_region(src)
    # the refactored code refuses the ledger, naming the command that migrates it
    out, after = _refused_then_migrated(src, folder, results, built / "src")
    (migration,) = after["migrations"]
    assert migration["from"] == {"learner": before["fingerprints"]["learner"]}
    assert migration["to"] == {"learner": after["fingerprints"]["learner"]}
    assert migration["to"]["learner"] != migration["from"]["learner"]
    assert "docking.region" in migration["changed"]["learner"]
    assert "docking.start_region" in migration["changed"]["learner"]
    assert migration["moved"] == {"learner": 4}
    names = {(r["name"], r["seed"]) for r in migration["recomputed"]}
    assert {n for n, _ in names} == {"tiny", "tiny-floor", "yardsticks"}  # every table
    assert len(names) < 5  # a sample, not every run
    # every run kept its arrays, records and rows; only its key moved
    strip = ("whole", "sha256")
    old = sorted(
        json.dumps({k: v for k, v in r.items() if k not in strip}, sort_keys=True)
        for r in before["runs"].values()
    )
    new = sorted(
        json.dumps({k: v for k, v in r.items() if k not in strip}, sort_keys=True)
        for r in after["runs"].values()
    )
    assert old == new and set(before["runs"]).isdisjoint(after["runs"])
    # the store's run of seed 2 (the ledger holds none) is not moved: the proof never ran it
    assert "results store: 4 runs re-keyed, 0 keyed by this code already, 1 left" in out.stdout
    check = _python(src, "-c", CHECK, str(results), str(folder), ledger_dir=folder)
    assert check.returncode == 0, check.stderr[-3000:]
    found = json.loads(check.stdout)
    assert found == {
        "checked": {"runs": 4, "tables": 3, "whole": 1, "derived": 0},
        "stored": [True, True, False, True, True],
    }
    assert migration["covered"]["covered"]["learner"]["cases"] >= 4  # the battery ran
    assert migration["covered"]["sample"]["seeds"] == 2  # every seed of the ledger: 0 and 1
    assert migration["covered"]["sample"]["seed_list"] == [0, 1]
    # nothing left to migrate: the command says so and changes nothing
    again = _migrate(src, folder, results, built / "src")
    assert again.returncode == 0 and "nothing to migrate" in again.stdout
    assert json.loads((folder / "manifest.json").read_text()) == after


@pytest.mark.slow
def test_a_change_of_which_modules_are_keyed_migrates_by_each_codes_own_rule(built, tmp_path):
    """Which modules are keyed is code too (``fingerprint.UNKEYED_MODULES``): when it changes,
    the old code's fingerprint must be computed by the old code's rule, in its own process.
    This code's rule applied to the old files (what the battery did, until issue 60's
    validate.py was keyed) finds no old code that recorded the ledger, and refused."""
    src, folder, results = _fresh(built, tmp_path)
    path = src / "docking" / "study" / "fingerprint.py"
    text = path.read_text()
    old = 'UNKEYED_MODULES = frozenset({"docking.fileio"})'
    assert text.count(old) == 1
    path.write_text(
        text.replace(old, 'UNKEYED_MODULES = frozenset({"docking.fileio", "docking.validate"})')
    )
    # a derived table, keyed (as every derived entry) by the keys of the runs it read
    add = (
        "import sys, numpy as np; from docking.study import ledger; "
        "ledger.write_derived(sys.argv[1], 'feature-fidelity', {'k': {'x': np.zeros(2)}})"
    )
    added = _python(built / "src", "-c", add, str(folder), ledger_dir=folder)
    assert added.returncode == 0, added.stderr[-3000:]
    out, data = _refused_then_migrated(src, folder, results, built / "src")
    (migration,) = data["migrations"]
    assert "docking.validate" in migration["changed"]["learner"]
    assert migration["moved"] == {"learner": 4}
    # the derived table's entries name the runs' old keys: dropped, and said (the migration
    # of issue 60 dropped them from the manifest without a word, leaving their files)
    assert "derived tables dropped (feature-fidelity)" in out.stdout, out.stdout
    assert "ledger derive" in out.stdout
    assert "derived" not in data and not (folder / "derived" / "feature-fidelity.npz").exists()


@pytest.mark.slow
def test_a_change_that_alters_a_number_migrates_nothing_and_names_the_runs(built, tmp_path):
    src, folder, results = _fresh(built, tmp_path)
    manifest = (folder / "manifest.json").read_bytes()
    stored = sorted(p.relative_to(results) for p in results.rglob("*.npz"))
    _split_exp(src)
    _changed_number(src)
    out = _migrate(src, folder, results, built / "src")
    assert out.returncode == 1
    assert "nothing migrated: the battery's short runs differ" in out.stderr, out.stderr
    assert (folder / "manifest.json").read_bytes() == manifest
    assert sorted(p.relative_to(results) for p in results.rglob("*.npz")) == stored


#: A tiny ledger whose runs differ where the forged changes below aim: beta_a 2 and 10, seeds
#: below and at or above 7100, the sideboard and the floor world.
BUILD_WIDE = """
import dataclasses, sys
from pathlib import Path

from docking.study import ledger, store
from docking.study.designs.builders import experiment2_in
from docking.presets import EXPERIMENT_1, FLOOR_WORLD

results, folder = Path(sys.argv[1]), Path(sys.argv[2])
small = dict(train_trials=4, test_trials=0, eval_every=4, eval_trials=0, heldout_trials=4)
tiny = dataclasses.replace(EXPERIMENT_1, name="tiny", **small)
hot = dataclasses.replace(
    tiny, name="hot", network=dataclasses.replace(tiny.network, beta_a_train=10.0)
)
floor = dataclasses.replace(experiment2_in(FLOOR_WORLD, "tiny-floor"), **small)
runs = [(c, s, False, frozenset()) for c, s in ((tiny, 0), (tiny, 7105), (hot, 1), (floor, 2))]
for config, seed, *_ in runs:
    store.run_or_load(config, seed, results, progress=False)
ledger.update(runs, folder, results)
"""


@pytest.fixture(scope="module")
def built_wide(tmp_path_factory):
    base = tmp_path_factory.mktemp("migrate-wide")
    src = _copy(base)
    out = _python(src, "-c", BUILD_WIDE, str(base / "results"), str(base / "ledger"))
    assert out.returncode == 0, out.stderr[-3000:]
    return base


def _edit(src: Path, module: str, old: str, new: str) -> None:
    path = src / "docking" / module
    text = path.read_text()
    assert text.count(old) == 1, old
    path.write_text(text.replace(old, new))


#: Forged changes that alter some runs only, each refused with what it alters named:
#: ``(module, the line, the line with the change, what the refusal names)``.
FORGERIES = {
    # the laundering commit: only runs trained with beta_a in [5, 20)
    "beta_a": (
        "trial.py",
        '    beta_a = check_real("run_trial", "beta_a", beta_a, lo=0)\n',
        '    beta_a = check_real("run_trial", "beta_a", beta_a, lo=0)\n'
        "    if learn and 5 <= beta_a < 20:\n        beta_a = beta_a * 1.5\n",
        "network.beta_a_train = 10.0",
    ),
    "seeds": (
        "experiments.py",
        "    rngs = _streams(seed)\n    if config.before is None:",
        "    rngs = _streams(seed)\n    if seed >= 7100:\n        rngs = _streams(seed + 1)\n"
        "    if config.before is None:",
        "seed = 7105",
    ),
    "world": (
        "experiments.py",
        "    rngs = _streams(seed)\n    if config.before is None:",
        "    rngs = _streams(seed)\n    if config.world.scene == 'floor':\n"
        "        rngs = _streams(seed + 1)\n    if config.before is None:",
        'world.scene = "floor"',
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("forgery", sorted(FORGERIES))
def test_a_change_that_alters_only_some_runs_is_refused_naming_them(built_wide, tmp_path, forgery):
    """The battery runs every value of every field and every seed the ledger holds: a change
    aimed at one value, one seed range or one world is refused, naming it; nothing moves."""
    src, folder, results = _fresh(built_wide, tmp_path)
    manifest = (folder / "manifest.json").read_bytes()
    module, old, new, named = FORGERIES[forgery]
    _edit(src, module, old, new)
    out = _migrate(src, folder, results, built_wide / "src")
    assert out.returncode == 1, out.stdout + out.stderr
    says = " ".join(out.stderr.split())
    assert "nothing migrated: the battery's short runs differ" in says, says
    assert named in says, says
    assert (folder / "manifest.json").read_bytes() == manifest


@pytest.mark.slow
def test_a_split_function_still_migrates_the_wide_ledger(built_wide, tmp_path):
    src, folder, results = _fresh(built_wide, tmp_path)
    _split_exp(src)
    out = _migrate(src, folder, results, built_wide / "src")
    assert out.returncode == 0, out.stderr[-3000:]
    (migration,) = json.loads((folder / "manifest.json").read_text())["migrations"]
    assert migration["covered"]["sample"]["seeds"] == 4  # 0, 1, 2 and 7105
    assert migration["moved"] == {"learner": 4}


def test_the_sample_covers_every_table_kind_and_world_cheapest_first():
    def record(name, seed, seconds, world="a", policy=None, runner="learner"):
        return {
            "name": name,
            "seed": seed,
            "runner": runner,
            "wall_seconds": seconds,
            "config": {"world": {"w": world}, "policy": policy, "network": {}},
        }

    runs = {
        "k1": record("t1", 0, 50.0),
        "k2": record("t1", 1, 5.0),
        "k3": record("t2", 0, 9.0, world="b"),
        "k4": record("t2", 1, 1.0, world="b", policy="oracle"),
        "k5": record("t3", 0, 2.0, runner="ppo"),
        "k6": record("t2", 2, 1.0, world="a"),
    }
    data = {"runs": runs}
    chosen = migrate.sample(data, {"learner"})
    assert "k1" not in chosen and "k5" not in chosen  # dearer than k2; another runner
    covered = set().union(*(migrate._features(runs[k]) for k in chosen))
    wanted = set().union(*(migrate._features(r) for r in runs.values() if r["runner"] == "learner"))
    assert covered == wanted
    assert migrate.sample(data, {"ppo"}) == ["k5"]
    assert migrate.sample(data, set()) == []


def test_a_store_run_is_moved_only_along_a_chain_that_ends_at_this_code():
    chains = migrate._chains(
        [
            {"from": {"learner": "a"}, "to": {"learner": "b"}},
            {"from": {"learner": "b", "ppo": "x"}, "to": {"learner": "c", "ppo": "y"}},
        ]
    )
    assert chains == {"learner": {"a": "b", "b": "c"}, "ppo": {"x": "y"}}


def test_a_store_run_is_moved_only_if_the_proof_ran_its_seed_and_every_value_of_its_fields():
    """The laundering a proof over the ledger's runs cannot see (issue 60): a change that alters
    only a seed, or a field value, that the ledger never holds. A store run is moved only if a
    migration's sample recomputed its seed and each of its fields' values; a migration
    recorded without them (an older record) moves none."""
    from docking.study.battery import flat

    config = {"name": "t", "network": {"beta_a_train": 2.0, "eps_q": 0.1}, "train_trials": 8}
    values = {p: [v] for p, v in flat(config).items()}
    migrations = [
        {
            "from": {"learner": "a"},
            "to": {"learner": "b"},
            "covered": {"sample": {"values": {"learner": values}, "seed_list": [0, 1]}},
        },
        {"from": {"learner": "b"}, "to": {"learner": "c"}, "covered": {"sample": {}}},
    ]
    proofs = migrate._proofs(migrations)
    proof = proofs["learner"]["a"]
    assert migrate.covered_by(proof, config, 1)
    assert not migrate.covered_by(proof, config, 2)  # a seed it never ran
    other = {**config, "network": {"beta_a_train": 10.0, "eps_q": 0.1}}
    assert not migrate.covered_by(proof, other, 0)  # a beta_a it never ran
    assert not migrate.covered_by(proof, {**config, "pretrain_trials": 3}, 0)  # a new field
    assert proofs["learner"]["b"] is None
    assert not migrate.covered_by(proofs["learner"]["b"], config, 0)
