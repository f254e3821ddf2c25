"""Bad input found by fuzzing (issue 41, points 3-5) is a clear one-line error or an honest
result: continuous actions of the wrong kind, seeds in other digits, distractors where the
robot starts or docks, repeated grid values, held-out worlds of the wrong type, a bogus
``MUJOCO_GL``, Ctrl-C, a terminal a few columns wide."""

from __future__ import annotations

import contextlib
import dataclasses
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import gymnasium
import numpy as np
import psutil
import pytest

import docking.gym_ids  # noqa: F401  (registers the Gymnasium ids)
from docking.camera import CameraConfig
from docking.experiments import ExperimentConfig
from docking.gym import DockingGymEnv
from docking.presets import EXPERIMENT_1, EXPERIMENT_2, FLOOR_WORLD, NAO_WORLD
from docking.scene import Distractor, WorldConfig
from docking.study.cli import main
from docking.study.progress import PROGRESS_LINE
from docking.study.sweep import grid_configs, parse_seeds

REPO = Path(__file__).resolve().parent.parent


def _with_sigint(disposition: str, command: list[str]) -> list[str]:
    """``command`` (a Python command line, its interpreter first) started with SIGINT at
    ``disposition`` (``"SIG_DFL"``: as a terminal's foreground job has it, even where the
    tests run with SIGINT ignored, a script's background job, which the child would inherit
    and python -m docking, as Python, would keep; ``"SIG_IGN"``: as a background job has it).
    A small Python sets it and execs the command, which keeps it. Not ``preexec_fn``: Python
    code run in a forked child can deadlock once the tests' process has threads (JAX, imported
    by the PPO tests, warns of it at every fork)."""
    code = (
        f"import os, signal, sys; signal.signal(signal.SIGINT, signal.{disposition}); "
        "os.execv(sys.argv[1], sys.argv[1:])"
    )
    return [sys.executable, "-c", code, *command]


def _cli(args, tmp_path, timeout=120, foreground=False, **env):
    command = [sys.executable, "-m", "docking", *args]
    return subprocess.run(
        _with_sigint("SIG_DFL", command) if foreground else command,
        cwd=tmp_path,
        env={
            **os.environ,
            "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
            "DOCKING_LEDGER": "off",
            "DOCKING_RESULTS": str(tmp_path / "results"),
            **env,
        },
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _one_error_line(err: str) -> str:
    """The one line of ``err`` (a command's stderr) but a sweep's progress lines
    (:data:`docking.study.progress.PROGRESS_LINE`: where stderr is not a terminal, the runs it
    computes and each run finished), checked to be the command's message."""
    lines = [line for line in err.strip().splitlines() if not PROGRESS_LINE.fullmatch(line)]
    assert "Traceback" not in err, err
    assert len(lines) == 1 and lines[0].startswith("python -m docking: "), err
    return lines[0]


# Continuous-v0: actions of the wrong kind; gym.make's seed -------------------------------------


@pytest.mark.parametrize(
    "action",
    [["0.5", "0.5"], np.ones(2, bool), np.full(2, 0.5 + 0.5j), [0.5, "x"], [True, False]],
    ids=["strings", "bools", "complex", "mixed", "bool-list"],
)
def test_a_continuous_action_of_the_wrong_kind_is_refused(action):
    env = gymnasium.make("docking/Continuous-v0", seed=0)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"action must be 2 finite numbers in \[-1, 1\]"):
        env.step(action)
    discrete = gymnasium.make("docking/Docking-v0", seed=0)
    discrete.reset(seed=0)
    with pytest.raises(ValueError, match="action must be an integer"):
        discrete.step(np.asarray(action).ravel()[0] if np.ndim(action) else action)


def test_a_valid_continuous_action_is_the_adapters():
    """The check passes a valid action on unchanged: the same episode as the adapter's."""
    made = gymnasium.make("docking/Continuous-v0", seed=3).unwrapped
    plain = DockingGymEnv(seed=3, preset="continuous")
    for env in (made, plain):
        env.reset(seed=3)
    for action in ([0.5, -0.25], np.array([1, 0]), np.float32([0.1, 0.9])):
        a, b = made.step(action), plain.step(action)
        np.testing.assert_array_equal(a[0], b[0])
        assert a[1:4] == b[1:4] and np.array_equal(a[4]["pose"], b[4]["pose"])


@pytest.mark.parametrize("seed", [True, False, 1.0, "1", -1])
def test_gym_make_refuses_a_seed_that_is_no_integer(seed):
    with pytest.raises((TypeError, ValueError), match=r"DockingGymEnv.seed must be"):
        gymnasium.make("docking/Docking-v0", seed=seed)


def test_gym_make_takes_integer_seeds():
    a = gymnasium.make("docking/Docking-v0", seed=np.int64(4))
    b = gymnasium.make("docking/Docking-v0", seed=4)
    np.testing.assert_array_equal(a.reset()[0], b.reset()[0])


# Seeds: ASCII digits only -----------------------------------------------------------------------


@pytest.mark.parametrize("text", ["1_0", "\u0661", "\u0663-5", "0-1_0", "+1", "1e3", "\uff11"])
def test_seeds_are_ascii_digits(text):
    with pytest.raises(ValueError, match="seeds must be integers >= 0"):
        parse_seeds(text)


def test_seeds_in_ascii_digits_still_parse():
    assert parse_seeds("0-2, 7 9") == [0, 1, 2, 7, 9]


def test_the_command_line_refuses_other_digits(tmp_path):
    out = _cli(["run", "experiment1", "--seeds", "\u0661"], tmp_path)
    assert out.returncode == 2
    assert "seeds must be integers >= 0" in _one_error_line(out.stderr)


# --grid: repeated values, as repeated seeds --------------------------------------------------


@pytest.mark.parametrize(
    "grid, says",
    [
        (["network.eps_w=0,0.0"], "network.eps_w=0 and network.eps_w=0.0 are the same"),
        (["network.eps_w=0.05,0.05"], "are the same configuration"),
        (["network.eps_w=0,0.05", "network.eps-w=0.1"], "names network.eps_w twice"),
        (["world.heading_hold=true,yes"], "are the same configuration"),
    ],
)
def test_a_grid_that_names_one_configuration_twice_is_refused(grid, says):
    with pytest.raises(ValueError, match=says):
        grid_configs(EXPERIMENT_1, grid)


def test_a_grid_of_distinct_values_is_every_combination():
    configs = grid_configs(EXPERIMENT_1, ["network.eps_w=0,0.05", "world.step_noise_xy=0,0.01"])
    assert len({str(c.to_dict()) for c in configs}) == 4


# ExperimentConfig.heldout_world of the wrong type ---------------------------------------------


@pytest.mark.parametrize("value", [1, "x", {}, CameraConfig()], ids=str)
def test_a_heldout_world_of_the_wrong_type_is_a_clear_type_error(value):
    with pytest.raises(TypeError, match="ExperimentConfig.heldout_world must be a WorldConfig"):
        dataclasses.replace(EXPERIMENT_2, heldout_world=value)


# Distractors where the robot starts or docks --------------------------------------------------


@pytest.mark.parametrize(
    "distractor, region",
    [
        (Distractor("box", (1.0, 1.0, 1.0), (-1.0, 0.0, 1.0)), "the start region"),  # the issue's
        (Distractor("box", (0.04, 0.04, 0.04), (-0.48, 0.0, 0.04)), "the docking region"),
        (Distractor("sphere", (0.05,), (-1.0, 0.3, 0.05)), "the start region"),  # 3 cm clear
        (Distractor("cylinder", (0.05, 0.3), (-0.48, 0.18, 0.3)), "the docking region"),
    ],
)
def test_a_distractor_where_the_robot_starts_or_docks_is_refused(distractor, region):
    world = dataclasses.replace(EXPERIMENT_2.world, start_near=0.8)  # the regions 0.26 m apart
    with pytest.raises(ValueError, match=rf"WorldConfig.distractors\[0\] .* of {region}"):
        dataclasses.replace(world, distractors=(distractor,))


def test_distractors_clear_of_the_robot_are_accepted():
    cup = Distractor.cup(0.3)
    floor_cup = Distractor("cylinder", cup.size, (0.03, 0.3, cup.size[1]))
    for world in (WorldConfig(), EXPERIMENT_2.world, NAO_WORLD):
        dataclasses.replace(world, distractors=(cup,))
    dataclasses.replace(FLOOR_WORLD, distractors=(floor_cup,))
    beside = Distractor("sphere", (0.05,), (-1.0, 0.5, 0.05))  # 0.25 m beside the wedge
    dataclasses.replace(EXPERIMENT_2.world, distractors=(beside,))


# MUJOCO_GL, Ctrl-C, narrow terminals, a closed pipe -------------------------------------------


@pytest.mark.parametrize("value", ["bogus", ""])
def test_a_bogus_rendering_backend_is_one_clear_line(value, tmp_path):
    out = _cli(["ledger", "show"], tmp_path, MUJOCO_GL=value)
    assert out.returncode == 1
    assert "is not a rendering backend MuJoCo knows" in _one_error_line(out.stderr)


def test_ctrl_c_while_a_command_runs_is_one_line_and_130(monkeypatch, capsys):
    from docking.study.cli import ledger

    def interrupted(self):
        raise KeyboardInterrupt

    monkeypatch.setattr(ledger.Verify, "execute", interrupted)
    handler = signal.getsignal(signal.SIGTERM)
    try:
        assert main(["verify"]) == 130
    finally:
        signal.signal(signal.SIGTERM, handler)
    assert capsys.readouterr().err == "python -m docking: interrupted\n"


def _until_workers_compute(pid: int, workers: int, cpu_s: float, timeout: float = 120) -> None:
    """Wait until ``workers`` processes below ``pid`` have each spent ``cpu_s`` seconds of CPU:
    its sweep's workers past importing the package (about 2 s of CPU here) and training."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        spent = []
        for child in psutil.Process(pid).children(recursive=True):
            with contextlib.suppress(psutil.Error):
                spent.append(sum(child.cpu_times()[:2]))
        if sum(s >= cpu_s for s in spent) >= workers:
            return
        time.sleep(0.2)
    raise AssertionError(f"no {workers} processes spent {cpu_s} s of CPU within {timeout} s")


@pytest.mark.slow
@pytest.mark.parametrize(
    "args, after",
    [
        (["run", "experiment1", "--seeds", "0", "--processes", "1"], 1.0),  # still importing
        (["run", "experiment1", "--seeds", "0", "--processes", "1"], 8.0),
        # once both workers train (5 s of CPU each; a fixed 15 s cost 30 s of their CPU)
        (["sweep", "experiment1", "--seeds", "0,1", "--processes", "2"], (2, 5.0)),
    ],
    ids=["run-importing", "run", "sweep"],
)
def test_ctrl_c_prints_one_line_exits_130_and_leaves_no_process(args, after, tmp_path):
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
        "DOCKING_LEDGER": "off",
        "DOCKING_RESULTS": str(tmp_path / "results"),
    }
    proc = subprocess.Popen(
        # Training long enough that every command is still running when it is interrupted,
        # on a machine ten times faster (2 seeds of 300 trials could end inside 15 s).
        _with_sigint("SIG_DFL", [sys.executable, "-m", "docking", *args, "--train-trials", "5000"]),
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, as a terminal's foreground job
    )
    if isinstance(after, tuple):
        _until_workers_compute(proc.pid, *after)
    else:
        time.sleep(after)
    family = [psutil.Process(proc.pid), *psutil.Process(proc.pid).children(recursive=True)]
    os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C: the terminal signals the whole group
    interrupted = time.monotonic()
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    # promptly: a sweep waited 10 s for each busy worker to end on SIGTERM (20 s for two)
    assert time.monotonic() - interrupted < 10, time.monotonic() - interrupted
    assert _one_error_line(err) == "python -m docking: interrupted"
    _, alive = psutil.wait_procs(family, timeout=20)
    assert not alive, alive


# Ctrl-C where a timed signal lands only now and then: at the moment a module is imported.
# sitecustomize (found on PYTHONPATH before the interpreter runs anything else) puts a finder
# first on sys.meta_path; when the named module is first looked for, it sends the process
# SIGINT, so the interrupt arrives in that import every time.
_CTRL_C_AT_IMPORT = """
import os, signal, sys

class _CtrlC:
    def find_spec(self, name, path=None, target=None):
        if name == {module!r} and {when}:
            sys.meta_path.remove(self)
            {before}
            os.kill(os.getpid(), signal.SIGINT)
        return None

sys.meta_path.insert(0, _CtrlC())
"""


def _ctrl_c_at_import(tmp_path, module, when="True", before="pass"):
    site = tmp_path / "site"
    site.mkdir()
    code = _CTRL_C_AT_IMPORT.format(module=module, when=when, before=before)
    (site / "sitecustomize.py").write_text(code)
    return _cli(
        ["run", "experiment1", "--seeds", "0", "--train-trials", "2", "--test-trials", "1"],
        tmp_path,
        foreground=True,
        PYTHONPATH=os.pathsep.join([str(site), str(REPO), os.environ.get("PYTHONPATH", "")]),
    )


def test_ctrl_c_while_the_commands_modules_import_is_one_line_and_130(tmp_path):
    """python -m docking imports a command's modules (numpy, MuJoCo, ...) as it parses the
    command line, before the command runs: an interrupt there was a traceback and a death by
    SIGINT (when the package imported gymnasium and numpy itself, there)."""
    out = _ctrl_c_at_import(tmp_path, "numpy")
    assert out.returncode == 130, out.stderr
    assert _one_error_line(out.stderr) == "python -m docking: interrupted"


def test_ctrl_c_that_cpython_counts_unhandled_still_ends_130(tmp_path):
    """CPython 3.11 can hold a KeyboardInterrupt unhandled although main caught it (seen under
    load: one raised in code that namedtuple evaluates while dm_control is imported), and then
    ends python -m by SIGINT whatever the status. Here the flag is set by hand, at the import
    of dm_control.mujoco while the command runs (docking.study.sweep imported), just before the
    interrupt."""
    import ctypes

    try:
        ctypes.c_int.in_dll(ctypes.pythonapi, "_Py_UnhandledKeyboardInterrupt")
    except ValueError:
        pytest.skip("this CPython keeps the flag out of reach of ctypes (3.12 and later)")
    flag = 'ctypes.c_int.in_dll(ctypes.pythonapi, "_Py_UnhandledKeyboardInterrupt").value = 1'
    out = _ctrl_c_at_import(
        tmp_path,
        "dm_control.mujoco",
        when='"docking.study.sweep" in sys.modules',
        before=f"import ctypes; {flag}",
    )
    assert out.returncode == 130, out.stderr
    assert _one_error_line(out.stderr) == "python -m docking: interrupted"


def test_a_command_started_with_ctrl_c_ignored_keeps_it_ignored(tmp_path):
    """A shell starts a background job (``cmd &``) with SIGINT ignored; Python leaves it so,
    and so does python -m docking: a Ctrl-C meant for the foreground does not end it."""
    proc = subprocess.Popen(
        _with_sigint("SIG_IGN", [sys.executable, "-m", "docking", "run", "--help"]),
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": str(REPO), "COLUMNS": "100"},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(0.5)  # the package's imports, or later: either way the interrupt is ignored
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 0 and "--seeds" in out, err


def test_import_docking_leaves_ctrl_c_alone():
    """Only python -m docking handles Ctrl-C itself; a notebook or a script that imports the
    package keeps Python's KeyboardInterrupt."""
    code = "import signal, docking; print(signal.getsignal(2) is signal.default_int_handler)"
    out = subprocess.run(
        _with_sigint("SIG_DFL", [sys.executable, "-c", code]),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.stdout.strip() == "True", out.stderr


@pytest.mark.parametrize("columns", ["5", "2", "1"])
def test_help_at_a_few_columns_ends(columns, tmp_path):
    out = _cli(["run", "--help"], tmp_path, timeout=60, COLUMNS=columns)
    assert out.returncode == 0 and "--seeds" in out.stdout


def test_help_into_a_closed_pipe_is_no_traceback(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(REPO), "COLUMNS": "100"}
    out = subprocess.run(
        f"'{sys.executable}' -m docking run --help | head -1",
        shell=True,
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.stdout.startswith("usage: python -m docking run") and out.stderr == ""


# Issue 52: every number of the command line read as seeds are ----------------------------------


def _parse_error(args, monkeypatch, capsys) -> str:
    """What tyro says of the command line ``args`` (it must refuse it), on one line."""
    from docking.study import cli

    monkeypatch.setenv("COLUMNS", "200")
    with pytest.raises(SystemExit) as exit_:
        cli.parse(args)
    assert exit_.value.code == 2
    return " ".join(capsys.readouterr().err.replace("\u2502", " ").split())


@pytest.mark.parametrize(
    "option, value, says",
    [
        ("--train-trials", "1_0", "'1_0' is not an integer"),
        ("--test-trials", "\u0661\u0660", "'\u0661\u0660' is not an integer"),  # Arabic-Indic 10
        ("--network.eps-w", "1_0", "'1_0' is not a number"),
        ("--network.eps-w", "0.0_5", "'0.0_5' is not a number"),
        ("--network.eps-w", "\u0660.\u0665", "is not a number"),  # Arabic-Indic 0.5
        ("--world.start-near", "\uff10.6", "is not a number"),  # a full-width 0
        ("--processes", "1_0", "'1_0' is not an integer"),  # an int | None option
    ],
)
def test_a_number_option_is_ascii_digits_without_underscores(
    option, value, says, monkeypatch, capsys
):
    said = _parse_error(["run", "experiment1", option, value], monkeypatch, capsys)
    assert f"Error parsing {option}: " in said and says in said and "Traceback" not in said


def test_ordinary_numbers_still_parse():
    from docking.study import cli

    args = ["run", "experiment1", "--train-trials", "12", "--network.eps-w", "1e-3"]
    args += ["--network.eps-q", "0.5", "--network.beta-s", "5", "--world.start-near", ".6"]
    command = cli.parse([*args, "--processes", "2"])
    config = command.experiment
    assert (config.train_trials, config.network.eps_w, config.network.eps_q) == (12, 1e-3, 0.5)
    assert (config.network.beta_s, config.world.start_near, command.processes) == (5.0, 0.6, 2)


@pytest.mark.parametrize(
    "grid, says",
    [
        (["train_trials=1_0,20"], "ExperimentConfig.train_trials takes an integer; '1_0'"),
        (["network.eps_w=0.0_5"], "NetworkConfig.eps_w takes a number; '0.0_5'"),
        (["train_trials=\u0661\u0660"], "ExperimentConfig.train_trials takes an integer"),
    ],
)
def test_a_grid_value_is_ascii_digits_without_underscores(grid, says):
    with pytest.raises(ValueError, match=says):
        grid_configs(EXPERIMENT_1, grid)


# Issue 52: a run without test trials says so --------------------------------------------------


@pytest.mark.slow
def test_a_run_without_test_trials_says_so_not_nan(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path))
    args = ["run", "experiment1", "--seeds", "0", "--processes", "1", "--train-trials", "2"]
    args += ["--test-trials", "0", "--eval-trials", "0", "--heldout-trials", "2"]
    handler = signal.getsignal(signal.SIGTERM)
    try:
        assert main(args) == 0
    finally:
        signal.signal(signal.SIGTERM, handler)
    line = capsys.readouterr().out.splitlines()[0]
    assert "no test trials (--test-trials 0); held-out success mean" in line, line
    assert "nan" not in line and "0: " in line and "/2" in line, line


# Issue 52: grids capped as seeds are, before any work ------------------------------------------


def test_a_grid_of_millions_is_refused_before_any_configuration_is_built(monkeypatch):
    monkeypatch.setattr(
        "docking.study.sweep.apply_override", lambda *a: pytest.fail("a configuration was built")
    )
    values = ",".join(str(k) for k in range(1, 201))
    grid = [f"train_trials={values}", f"test_trials={values}", f"heldout_trials={values}"]
    with pytest.raises(ValueError, match=r"at most 10000 grid configurations .* 8,000,000"):
        grid_configs(EXPERIMENT_1, grid)


@pytest.mark.parametrize(
    "args, says",
    [
        (["--grid", "train_trials=" + ",".join(map(str, range(1, 10002)))], "10,001 (10001)"),
        (["--seeds", "0-9999", "--grid", "network.eps_w=0,0.05"], "at most 10000 runs"),
    ],
    ids=["grid", "grid x seeds"],
)
def test_a_sweep_too_large_is_one_line_before_any_run(args, says, monkeypatch, capsys):
    from docking.study.cli import runs

    monkeypatch.setattr(runs, "_run", lambda *a: pytest.fail("the sweep started"))
    handler = signal.getsignal(signal.SIGTERM)
    try:
        assert main(["sweep", "experiment1", *args]) == 2
    finally:
        signal.signal(signal.SIGTERM, handler)
    assert says in _one_error_line(capsys.readouterr().err)


# Issue 52: the contest's arguments -------------------------------------------------------------


def _knobs():
    from docking.study.contest import Knob, Ladder

    return (
        Knob("train_trials", Ladder((100, 200, 500), 0, integer=True)),
        Knob("eval_trials", Ladder((1, 2, 5), 0, integer=True)),
    )


@pytest.mark.parametrize(
    "learner, knobs, error, says",
    [
        (None, None, TypeError, "contest: learner must be a learner's configuration"),
        (ExperimentConfig, None, TypeError, "contest: learner must be"),  # the class
        (EXPERIMENT_2, ("ab", "cd"), TypeError, "contest.rows must be a Knob"),
        (lambda: EXPERIMENT_2, None, TypeError, "contest: learner must be callable as make"),
        (lambda world, **s: 3, None, TypeError, "contest: learner.* must return a learner's"),
        ("same", None, ValueError, "rows and cols both name the field 'train_trials'"),
        ("flat", None, ValueError, "give the same configuration"),  # a knob it ignores
        ("nope", None, ValueError, "the knob nope is not a field of ExperimentConfig"),
    ],
    ids=["None", "a class", "a text", "lambda()", "lambda->3", "same", "flat", "nope"],
)
def test_the_contests_arguments_are_checked_before_any_work(
    learner, knobs, error, says, monkeypatch
):
    from docking.study import contest as contest_module
    from docking.study.contest import Knob, Ladder

    rows, cols = _knobs()
    if learner == "same":
        learner, cols = EXPERIMENT_2, Knob("train_trials", Ladder((1,), 0, integer=True))
    elif learner == "flat":  # a maker that ignores the second knob

        def learner(world, train_trials=100, eval_trials=1):
            return dataclasses.replace(EXPERIMENT_2, world=world, train_trials=train_trials)

    elif learner == "nope":
        learner, rows = EXPERIMENT_2, Knob("nope", Ladder((1, 2, 5), 0))
    if knobs is not None:
        rows, cols = knobs
    monkeypatch.setattr(contest_module, "published", lambda *a: pytest.fail("it went on"))
    budget = contest_module.small_budget(rows=2, cols=2)
    with pytest.raises(error, match=says):
        contest_module.contest(learner, rows, cols, budget)


# Issue 52: a PYOPENGL_PLATFORM that does not match MUJOCO_GL -----------------------------------


def test_a_bogus_opengl_platform_is_one_clear_line(tmp_path):
    args = ["run", "experiment1", "--seeds", "0", "--processes", "1", "--train-trials", "2"]
    out = _cli(args, tmp_path, PYOPENGL_PLATFORM="bogus", MUJOCO_GL="egl")
    assert out.returncode == 1
    said = _one_error_line(out.stderr)
    assert "PYOPENGL_PLATFORM='bogus' does not match MUJOCO_GL=egl" in said
    assert not (tmp_path / "results").exists()


# Issue 52: a policy's bad action while judging ------------------------------------------------


@pytest.mark.parametrize(
    "world, action",
    [(WorldConfig(), 1.5), (WorldConfig(), "0"), (WorldConfig(actions="continuous"), [2.0, 0.0])],
    ids=["a float", "a text", "beyond 1"],
)
def test_a_bad_action_while_judging_is_the_policys(world, action):
    from docking.protocol import heldout_log

    with pytest.raises(ValueError, match=rf"^your policy returned {re.escape(repr(action))}: "):
        heldout_log(world, 0, 1, lambda observation, env: action)


@pytest.mark.parametrize(
    "args, says",
    [
        (["run", "experiment1", "--seeds", "0", "--seeds", "1"], "--seeds is given twice"),
        (["run", "experiment1", "--seeds=0", "--seeds", "1"], "--seeds is given twice"),
        (
            ["run", "experiment1", "--train_trials", "3", "--train-trials", "4"],
            "--train_trials and --train-trials are both given",
        ),
        (
            ["run", "experiment1", "--network.eps-w", "0", "--network.eps_w=1"],
            "--network.eps-w and --network.eps_w are both given",
        ),
        (["report", "--no-experiment3", "--experiment3"], "--no-experiment3 and --experiment3"),
        (["sweep", "experiment1", "--grid", "a=1", "--grid", "b=2"], "--grid is given twice"),
        (["verify", "--design", "paper", "--design", "experiment3"], "--design is given twice"),
    ],
)
def test_an_option_given_twice_is_refused_in_one_line(args, says, tmp_path, monkeypatch, capsys):
    """Issue 60: argparse kept the last of `--seeds 0 --seeds 1` without a word."""
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))
    handler = signal.getsignal(signal.SIGTERM)
    try:
        assert main(args) == 2
    finally:
        signal.signal(signal.SIGTERM, handler)
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"python -m docking: error: {says}"), err
    assert len(err.splitlines()) == 1 and "give it once" in err
    assert not (tmp_path / "results").exists()


def test_options_given_once_are_not_taken_for_repeated():
    from docking.study.cli import _repeated_option, parse

    once = ["sweep", "experiment1", "--seeds", "0-1", "--network.eps-w", "0", "--world.eps-w"]
    once += ["1", "--grid", "network.eps_w=0,1", "train_trials=3,4", "--no-force"]
    assert _repeated_option(once) is None
    assert _repeated_option(["run", "experiment1", "--", "--seeds", "--seeds"]) is None
    assert _repeated_option(["run", "--help", "--help"]) is None
    found = parse(["verify", "--design", "paper", "--cells", "experiment1", "--seeds", "0"])
    assert (found.design, found.cells, found.seeds) == ("paper", ("experiment1",), "0")
