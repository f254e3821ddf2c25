"""The command line says what it did (issue 44): a run's line names its options, a trial count
that cuts the curriculum short is a warning, an experiment's --help shows its common options,
the benchmark names its ratios, ``ledger show`` is a short table, and an installed package
says where it writes and which extra it misses. Real processes wherever the CLI is run."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import without_extra

REPO = Path(__file__).resolve().parent.parent
TINY = ["--train-trials", "4", "--test-trials", "3", "--eval-every", "2", "--eval-trials", "2"]


def _env(tmp_path, **extra):
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
        "DOCKING_RESULTS": str(tmp_path / "results"),
        "DOCKING_FIGURES": str(tmp_path / "figures"),
        "COLUMNS": "90",
        **extra,
    }


def _cli(args, tmp_path, timeout=300, env=None):
    return subprocess.run(
        [sys.executable, "-m", "docking", *args],
        cwd=tmp_path,
        env=env or _env(tmp_path),
        capture_output=True,
        text=True,
        timeout=timeout,
    )


# ------------------------------------------------------------------------------------------
# run: its line, the curriculum's warning, its help.
# ------------------------------------------------------------------------------------------


def test_a_runs_label_names_the_options_that_differ_from_its_preset():
    from docking.presets import EXPERIMENT_1, EXPERIMENT_2
    from docking.study.cli.runs import _label

    assert _label(EXPERIMENT_2) == "experiment2"
    network = dataclasses.replace(EXPERIMENT_2.network, eps_w=0.0)
    changed = dataclasses.replace(EXPERIMENT_2, train_trials=100, network=network)
    assert _label(changed) == "experiment2 (--network.eps-w 0.0, --train-trials 100)"
    world = dataclasses.replace(EXPERIMENT_1.world, heading_hold=True, room_shift=(0.1, 0, 0))
    renamed = dataclasses.replace(EXPERIMENT_1, name="mine", world=world)
    assert _label(renamed) == (
        "mine (experiment1 --name mine, --world.heading-hold, --world.room-shift 0.1 0.0 0.0)"
    )


def test_the_warning_says_which_range_a_short_training_sees():
    from docking.presets import EXPERIMENT_1, EXPERIMENT_2
    from docking.study.cli.runs import _curriculum_cut

    assert _curriculum_cut(EXPERIMENT_2) is None and _curriculum_cut(EXPERIMENT_1) is None
    short = dataclasses.replace(EXPERIMENT_2, train_trials=100)
    text = _curriculum_cut(short)
    assert "--train-trials 100 is shorter than the curriculum's growth" in text
    assert "--curriculum.grow-trials 1400" in text
    assert "from 0.70 m to 0.76 m" in text and "starts 0.58-0.76 m away" in text
    assert "never the 1.50 m" in text and "--curriculum.grow-trials 100 (or fewer)" in text
    # A yardstick trains on nothing; a curriculum grown within the training is whole.
    oracle = dataclasses.replace(short, policy="oracle", train_trials=0, eval_trials=0)
    assert _curriculum_cut(oracle) is None
    grown = dataclasses.replace(
        short, curriculum=dataclasses.replace(short.curriculum, grow_trials=100)
    )
    assert _curriculum_cut(grown) is None


@pytest.mark.slow
def test_two_runs_that_differ_in_an_option_print_different_lines(tmp_path):
    lines = []
    for eps_w in ("0", "0.05"):
        args = ["run", "experiment1", "--seeds", "0", "--processes", "1", *TINY]
        out = _cli([*args, "--network.eps-w", eps_w], tmp_path)
        assert out.returncode == 0, out.stderr
        lines.append(out.stdout.splitlines()[0])
    assert lines[0] != lines[1]
    assert lines[0].startswith("experiment1 (--network.eps-w 0.0, --train-trials 4, ")
    assert lines[1].startswith("experiment1 (--train-trials 4, ")  # 0.05 is the preset's
    # The curriculum's warning, on stderr, before anything is computed.
    out = _cli(["run", "experiment2", "--seeds", "0", "--processes", "1", *TINY], tmp_path)
    assert out.returncode == 0, out.stderr
    assert "warning: --train-trials 4 is shorter than the curriculum's growth" in out.stderr
    assert out.stdout.startswith("experiment2 (--train-trials 4, --test-trials 3, ")


def _height(args, tmp_path) -> str:
    out = _cli([*args], tmp_path, timeout=60)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_an_experiments_help_shows_its_common_options_and_help_all_every_one(tmp_path):
    brief = _height(["run", "experiment2", "--help"], tmp_path)
    full = _height(["run", "experiment2", "--help-all"], tmp_path)
    assert len(brief.splitlines()) <= 100 < 200 < len(full.splitlines())
    assert "--help-all every one" in brief
    for option in ("--seeds", "--train-trials", "--world.scene", "--network.eps-w"):
        assert option in brief and option in full
    for option in ("--world.camera.width", "--network.q-init", "--pretrain-rule"):
        assert option not in brief and option in full
    # The trial count's help says what a short one does to the curriculum.
    assert "--curriculum.grow-trials cut the curriculum" in " ".join(
        brief.replace("│", " ").split()
    )
    # An option the help leaves out is an option all the same.
    from docking.study.cli import parse

    command = parse(["run", "experiment2", "--world.camera.tilt-deg", "5", "--network.q-init", "1"])
    assert command.experiment.world.camera.tilt_deg == 5 and command.experiment.network.q_init == 1


# ------------------------------------------------------------------------------------------
# benchmark --quick: short, and its ratios named.
# ------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_benchmark_quick_is_short_and_names_its_ratios(tmp_path):
    """At most 15 s on two idle cores; CPU time is what a loaded machine can check (the
    command's and its worker processes'), with room for the spawned workers' imports."""
    import resource

    def cpu() -> float:
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        return usage.ru_utime + usage.ru_stime

    before = cpu()
    out = _cli(["benchmark", "--quick"], tmp_path, timeout=300)
    spent = cpu() - before
    assert out.returncode == 0, out.stderr
    assert spent < 15, f"benchmark --quick took {spent:.1f} s of CPU"
    text = out.stdout
    assert "time ratio env step / floor (medians): " in text
    assert "speed-up over one process (" in text and "(at best 2.00x; below 1.00x" in text
    assert max(map(len, text.splitlines())) <= 100
    assert "3 repetitions of 500" in text and "(30 training + 10 test trials)" in text
    assert not (tmp_path / "results").exists()


# ------------------------------------------------------------------------------------------
# ledger show: a short table.
# ------------------------------------------------------------------------------------------


def test_ledger_show_is_a_short_table(tmp_path):
    from docking.study import ledger

    data = ledger.manifest(REPO / "ledger")
    out = _cli(
        ["ledger", "show"], tmp_path, env=_env(tmp_path, DOCKING_LEDGER=str(REPO / "ledger"))
    )
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert max(map(len, lines)) <= 100 and len(lines) <= len(data["tables"]) + 12
    rows = {line.split()[0]: line.split()[1:] for line in lines}
    for name in data["tables"]:  # one row per table: its runs first
        mine = [r for r in data["runs"].values() if r["name"] == name]
        assert int(rows[name][0]) == len(mine), name
    assert int(rows["all"][0]) == len(data["runs"])
    assert "checked: the manifest" in out.stdout and "python -m docking verify" in out.stdout


# ------------------------------------------------------------------------------------------
# An installed package: where it writes, and the extra it misses.
# ------------------------------------------------------------------------------------------


def _installed(tmp_path) -> Path:
    """The package as pip installs it: no pyproject.toml beside it (no checkout)."""
    import shutil

    site = tmp_path / "site"
    shutil.copytree(REPO / "docking", site / "docking", ignore=shutil.ignore_patterns("*.pyc"))
    return site


def test_an_installed_package_writes_to_the_per_user_data_folder(tmp_path, monkeypatch):
    from docking.study import paths

    monkeypatch.setattr(paths, "checkout_root", lambda: None)
    monkeypatch.delenv("DOCKING_RESULTS", raising=False)
    monkeypatch.delenv("DOCKING_FIGURES", raising=False)
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    assert paths.results_dir() == tmp_path / "data" / "docking" / "results"
    assert paths.figures_dir() == tmp_path / "data" / "docking" / "figures"
    assert paths.in_user_data(paths.results_dir())
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "mine"))
    assert paths.results_dir() == tmp_path / "mine" and not paths.in_user_data(tmp_path / "mine")


@pytest.mark.slow
def test_a_run_of_an_installed_package_says_where_it_stored_it(tmp_path):
    site, work = _installed(tmp_path), tmp_path / "work"
    work.mkdir()
    env = {**_env(tmp_path), "PYTHONPATH": str(site), "XDG_DATA_HOME": str(tmp_path / "data")}
    for name in ("DOCKING_RESULTS", "DOCKING_FIGURES"):
        env.pop(name)
    args = ["run", "experiment1", "--seeds", "0", "--processes", "1", *TINY]
    out = _cli(args, work, env=env)
    assert out.returncode == 0, out.stderr
    folder = tmp_path / "data" / "docking" / "results"
    assert f"stores its runs in the per-user data folder {folder}" in out.stderr
    assert f"computed now and stored in {folder}/experiment1/" in out.stdout
    assert list(folder.rglob("seed0.npz")) and list(work.iterdir()) == []  # not ./results
    again = _cli(args, work, env=env)  # said once, when the folder is made
    assert again.returncode == 0 and "per-user data folder" not in again.stderr


@pytest.mark.slow
def test_without_the_ppo_extra_the_published_ppo_rows_are_read_and_a_new_one_names_it(tmp_path):
    """Without the [ppo] extra the ledger's PPO runs are read as published (the same code,
    only the extra's libraries absent): the report runs; a PPO run that must be computed
    fails at once with the extra named and the line that installs it, not a stale ledger."""
    python, env = without_extra(tmp_path, _env(tmp_path, DOCKING_LEDGER=str(REPO / "ledger")))
    code = (
        "import dataclasses, importlib.util\n"
        "assert importlib.util.find_spec('skrl') is None\n"
        "from docking.study import kinds, runs\n"
        "from docking.study.designs import replication as rp\n"
        "config = rp.DESIGN.cell('floor/ppo').config\n"
        "print('read', runs.load_run(config, 7100).heldout.success.mean())\n"
        "try:\n"
        "    runs.locate(dataclasses.replace(config, steps=16000), 7100)\n"
        "except kinds.MissingExtra as exc:\n"
        "    print('refused:', exc)\n"
    )
    out = subprocess.run(
        [*python, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300
    )
    says = " ".join(out.stdout.split())
    assert out.returncode == 0 and "Traceback" not in out.stderr, out.stderr
    assert "read 0.97" in says
    assert "the [ppo] extra is not installed (skrl, jax, flax, optax missing)" in says
    assert "pip install 'docking[ppo]'" in says and "stale" not in says.lower()
    report = subprocess.run(
        [*python, "-m", "docking", "report"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert report.returncode == 0, report.stderr[-2000:]
    assert "holds ppo runs" not in report.stderr and "extra" not in report.stderr


def test_missing_extra_is_none_when_the_extra_is_installed(monkeypatch):
    import importlib.util

    from docking.study import ledger

    assert ledger.missing_extra("learner") is None
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "jax" else real(name, *a)
    )
    assert ledger.missing_extra("ppo") == (
        "the [ppo] extra is not installed (jax missing): pip install 'docking[ppo]'"
    )
