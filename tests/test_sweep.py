"""Sweeps on Dask: a real scheduler and workers on 127.0.0.1, bit-identical results, a worker
killed mid-sweep, resuming, and no orphaned worker processes."""

from __future__ import annotations

import dataclasses
import json
import logging
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import psutil
import pytest
from helpers import user_scripts

from docking.presets import EXPERIMENT_1
from docking.study.kinds import load_result
from docking.study.sweep import (
    Job,
    apply_override,
    grid_configs,
    jobs_for,
    parse_seeds,
    run_configs,
    run_jobs,
)

REPO = Path(__file__).resolve().parent.parent
TINY = dataclasses.replace(EXPERIMENT_1, train_trials=4, test_trials=3, eval_every=2, eval_trials=2)
# About 2 s per run: long enough to kill something while runs are in flight.
SLOW = dataclasses.replace(
    EXPERIMENT_1, train_trials=120, test_trials=10, eval_every=120, eval_trials=0
)
SLOW_ARGS = ["--train-trials", "120", "--test-trials", "10", "--eval-every", "120"]
SLOW_ARGS += ["--eval-trials", "0"]


def _env() -> dict[str, str]:
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
        "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl"),
    }


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _stop(proc: subprocess.Popen) -> None:
    """Stop ``proc`` by its PID (SIGTERM, then SIGKILL) and check that it and every process
    it started are gone."""
    try:
        family = [psutil.Process(proc.pid), *psutil.Process(proc.pid).children(recursive=True)]
    except psutil.NoSuchProcess:
        family = []
    if proc.poll() is None:
        os.kill(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.kill(proc.pid, signal.SIGKILL)
            proc.wait(timeout=10)
    _, alive = psutil.wait_procs(family, timeout=15)
    assert not alive, f"left running: {alive}"


@dataclasses.dataclass
class DaskCluster:
    address: str
    scheduler: subprocess.Popen
    workers: list[subprocess.Popen]


@pytest.fixture
def dask_cluster(tmp_path):
    """``dask scheduler`` and two ``dask worker`` processes (one thread each) on 127.0.0.1."""
    from distributed import Client

    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = tmp_path / "dask-logs"
    logs.mkdir()
    procs: list[subprocess.Popen] = []

    def start(name, args):
        log = open(logs / f"{name}.log", "wb")
        proc = subprocess.Popen(
            [sys.executable, "-m", "dask", *args], env=_env(), stdout=log, stderr=log
        )
        log.close()
        procs.append(proc)
        return proc

    try:
        scheduler = start(
            "scheduler",
            ["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
        )
        deadline = time.monotonic() + 60
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert scheduler.poll() is None, (logs / "scheduler.log").read_text()
                assert time.monotonic() < deadline, "the scheduler did not start in 60 s"
                time.sleep(0.2)
        workers = [
            start(
                f"worker{k}",
                [
                    "worker",
                    address,
                    "--host",
                    "127.0.0.1",
                    "--nworkers",
                    "1",
                    "--nthreads",
                    "1",
                    "--no-dashboard",
                    "--name",
                    f"worker{k}",
                    "--local-directory",
                    str(tmp_path / f"worker{k}"),
                ],
            )
            for k in range(2)
        ]
        with Client(address, timeout=60) as client:
            client.wait_for_workers(2, timeout=120)
        yield DaskCluster(address, scheduler, workers)
    finally:
        for proc in reversed(procs):
            _stop(proc)


def _same_files(a: Path, b: Path) -> None:
    """Every stored run under ``a`` is under ``b`` at the same relative path with equal
    arrays and equal metadata (but for the wall times)."""
    files_a = sorted(p.relative_to(a) for p in a.rglob("seed*.npz"))
    files_b = sorted(p.relative_to(b) for p in b.rglob("seed*.npz"))
    assert files_a and files_a == files_b
    for rel in files_a:
        with np.load(a / rel) as x, np.load(b / rel) as y:
            assert sorted(x.files) == sorted(y.files)
            for name in x.files:
                if name == "meta":
                    mx, my = json.loads(str(x[name])), json.loads(str(y[name]))
                    for m in (mx, my):
                        # when and how long it took, not what it computed
                        m.pop("wall_time_train"), m.pop("wall_time_test"), m.pop("computed_utc")
                    assert mx == my
                else:
                    np.testing.assert_array_equal(x[name], y[name], err_msg=f"{rel}: {name}")
                    assert x[name].dtype == y[name].dtype


# ------------------------------------------------------------------------------------------


def test_parse_seeds():
    assert parse_seeds("0-4") == [0, 1, 2, 3, 4]
    assert parse_seeds("0,3,5") == [0, 3, 5]
    assert parse_seeds("0-2, 10-11") == [0, 1, 2, 10, 11]
    assert parse_seeds("7") == [7]
    for bad in ("", "a", "3-1", "-1", "1-2-3", "0,0", "1.5"):
        with pytest.raises(ValueError, match="seeds"):
            parse_seeds(bad)


def test_grid_and_overrides():
    configs = grid_configs(TINY, ["network.eps_w=0,0.05", "world.step-forward=0.12,0.15"])
    assert [(c.network.eps_w, c.world.step_forward) for c in configs] == [
        (0.0, 0.12),
        (0.0, 0.15),
        (0.05, 0.12),
        (0.05, 0.15),
    ]
    assert grid_configs(TINY, []) == [TINY]
    assert apply_override(TINY, "network.rule", "nonlocal").network.rule == "nonlocal"
    assert apply_override(TINY, "bootstrap_on_truncation", "false").bootstrap_on_truncation is False
    assert apply_override(TINY, "train_trials", "7").train_trials == 7
    with pytest.raises(ValueError, match="NetworkConfig.nope is not a field"):
        apply_override(TINY, "network.nope", "1")
    with pytest.raises(ValueError, match="ExperimentConfig.world is a group"):
        apply_override(TINY, "world", "1")
    with pytest.raises(ValueError, match="ExperimentConfig.train_trials takes an integer"):
        apply_override(TINY, "train_trials", "many")
    with pytest.raises(ValueError, match="NetworkConfig.eps_w"):
        apply_override(TINY, "network.eps_w", "-1")  # the dataclass validates
    with pytest.raises(ValueError, match="PATH=V1,V2"):
        grid_configs(TINY, ["network.eps_w"])
    with pytest.raises(ValueError, match="seed"):
        Job(TINY, -1)


@pytest.mark.slow
def test_source_fingerprint_is_the_same_in_every_process():
    code = "from docking.study.kinds import source_fingerprint; print(source_fingerprint())"
    prints = {
        subprocess.run(
            [sys.executable, "-c", code],
            env={**_env(), "PYTHONHASHSEED": str(hash_seed)},
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        for hash_seed in (1, 2, 3)
    }
    assert len(prints) == 1


@pytest.mark.slow
def test_local_cluster_and_in_process_give_identical_files(tmp_path):
    jobs = jobs_for(grid_configs(TINY, ["network.eps_w=0,0.05"]), [0, 1])
    in_process = run_jobs(jobs, tmp_path / "a", workers=1, progress=False)
    on_cluster = run_jobs(jobs, tmp_path / "b", workers=2, progress=False)
    assert [p.relative_to(tmp_path / "a") for p in in_process] == [
        p.relative_to(tmp_path / "b") for p in on_cluster
    ]
    _same_files(tmp_path / "a", tmp_path / "b")
    # run_configs loads what it ran, in seed order, the same on a cluster as in this process.
    on_two = run_configs({"t": TINY}, [0, 1], tmp_path / "c", workers=2, progress=False)["t"]
    in_one = run_configs({"t": TINY}, [0, 1], tmp_path / "d", workers=1, progress=False)["t"]
    assert [r.seed for r in on_two] == [r.seed for r in in_one] == [0, 1]
    _same_files(tmp_path / "c", tmp_path / "d")


@pytest.mark.slow
def test_sweep_resumes_without_recomputing(tmp_path):
    first = run_jobs(jobs_for([TINY], [0, 1]), tmp_path, workers=1, progress=False)
    mtimes = [p.stat().st_mtime_ns for p in first]
    time.sleep(0.05)
    paths = run_jobs(jobs_for([TINY], [0, 1, 2, 3]), tmp_path, workers=2, progress=False)
    assert paths[:2] == first and [p.stat().st_mtime_ns for p in first] == mtimes
    assert all(p.exists() for p in paths)
    forced = run_jobs(jobs_for([TINY], [0]), tmp_path, workers=1, force=True, progress=False)
    assert forced[0].stat().st_mtime_ns != mtimes[0]


@pytest.mark.slow
def test_remote_cluster_gives_files_identical_to_a_local_sweep(dask_cluster, tmp_path):
    jobs = jobs_for(grid_configs(TINY, ["network.eps_w=0,0.05"]), [0, 1, 2])
    local = run_jobs(jobs, tmp_path / "local", workers=2, progress=False)
    remote = run_jobs(jobs, tmp_path / "remote", scheduler=dask_cluster.address, progress=False)
    assert len(remote) == len(local) == 6
    _same_files(tmp_path / "local", tmp_path / "remote")
    for p in remote:
        load_result(p)  # valid


@pytest.mark.slow
def test_a_scripts_learner_module_runs_on_an_existing_scheduler(dask_cluster, tmp_path):
    """Issue 62: a learner in a module beside the user's script (with a helper module of its
    own), the script started from a third folder, on a cluster whose scheduler and workers
    were started elsewhere: the modules are sent to them (the scheduler could not unpickle the
    jobs), and a module edited between two sweeps on the same cluster runs as edited."""
    script = user_scripts(tmp_path / "scripts")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()

    def sweep(results: str) -> list[Path]:
        out = subprocess.run(
            [sys.executable, str(script), str(tmp_path / results), dask_cluster.address],
            cwd=elsewhere,
            env={**_env(), "PYTHONPATH": str(REPO), "DOCKING_LEDGER": "off"},
            capture_output=True,
            text=True,
            timeout=240,
        )
        assert out.returncode == 0, out.stderr[-3000:]
        return [Path(line) for line in out.stdout.split()]

    def actions(paths: list[Path]) -> set[int]:
        found = set()
        for path in paths:
            with np.load(path) as data:
                found |= {int(a) for a in data["heldout.actions"].ravel() if a >= 0}
        return found

    first = sweep("results")
    assert [p.name for p in first] == ["seed0.npz", "seed1.npz"]
    assert actions(first) == {0}
    assert list((tmp_path / "worker0").rglob("user_helper.py"))  # sent, not found in place
    (script.parent / "user_helper.py").write_text("ACTION = 2\n")
    again = sweep("results")
    assert again[0].parent != first[0].parent  # another key: the helper's code changed
    assert actions(again) == {2}


@pytest.mark.slow
def test_killing_a_worker_mid_sweep_loses_no_finished_run(dask_cluster, tmp_path):
    jobs = jobs_for([SLOW], range(6))
    outcome: dict = {}

    def sweep():
        try:
            outcome["paths"] = run_jobs(
                jobs, tmp_path, scheduler=dask_cluster.address, progress=False
            )
        except BaseException as exc:  # reported by the assertion below
            outcome["error"] = exc

    thread = threading.Thread(target=sweep)
    thread.start()
    deadline = time.monotonic() + 120
    while not list(tmp_path.rglob("seed*.npz")):
        assert thread.is_alive(), outcome
        assert time.monotonic() < deadline, "no run finished within 120 s"
        time.sleep(0.05)
    finished = {p: p.stat().st_mtime_ns for p in tmp_path.rglob("seed*.npz")}
    victim = dask_cluster.workers[0]
    family = [psutil.Process(victim.pid), *psutil.Process(victim.pid).children(recursive=True)]
    os.kill(victim.pid, signal.SIGKILL)
    _, alive = psutil.wait_procs(family, timeout=15)
    assert not alive, f"the killed worker left {alive}"
    thread.join(timeout=300)
    assert not thread.is_alive(), "the sweep did not complete"
    assert "error" not in outcome, outcome.get("error")
    assert len(finished) < len(jobs), "the worker was killed only after the sweep"
    assert sorted(outcome["paths"]) == sorted(tmp_path.rglob("seed*.npz"))
    for p in outcome["paths"]:
        load_result(p)
    for p, mtime in finished.items():  # finished before the kill: kept, never recomputed
        assert p.stat().st_mtime_ns == mtime


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGKILL, signal.SIGTERM], ids=["kill-9", "sigterm"])
def test_workers_end_with_their_parent(signum, tmp_path):
    args = ["sweep", "experiment1", "--seeds", "0-5", "--processes", "2", *SLOW_ARGS]
    parent = subprocess.Popen(
        [sys.executable, "-m", "docking", *args, "--results-dir", str(tmp_path)],
        env=_env(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 120
        while not list(tmp_path.rglob("seed*.npz")):
            assert parent.poll() is None, parent.communicate()
            assert time.monotonic() < deadline, "no run finished within 120 s"
            time.sleep(0.05)
        family = psutil.Process(parent.pid).children(recursive=True)
        assert len(family) >= 2  # the two worker processes (and multiprocessing helpers)
        os.kill(parent.pid, signum)
        _, alive = psutil.wait_procs(family, timeout=10)
        assert not alive, f"orphaned after {signal.Signals(signum).name}: {alive}"
        _, stderr = parent.communicate(timeout=30)  # EOF: every writer of the pipe is gone
        assert "leaked semaphore" not in stderr
        assert "resource_tracker" not in stderr
        assert parent.returncode == (-signal.SIGKILL if signum == signal.SIGKILL else 128 + 15)
    finally:
        if parent.poll() is None:
            parent.kill()
            parent.wait()


@pytest.mark.slow
def test_the_embedded_cluster_listens_on_loopback_only():
    """The scheduler, its dashboard and every worker's servers: no socket of the cluster's
    processes is bound to anything but 127.0.0.1 (whoever reaches a Dask scheduler can run
    code as its user)."""
    from docking.study.cluster import _EmbeddedCluster

    cluster = _EmbeddedCluster(2)
    try:
        pids = [os.getpid()] + [p.pid for p in cluster._procs]
        listening = [
            c.laddr
            for c in psutil.net_connections(kind="inet")
            if c.status == psutil.CONN_LISTEN and c.pid in pids
        ]
    finally:
        cluster.close()
    assert len(listening) >= 5  # scheduler, its dashboard, and two servers per worker
    assert {addr.ip for addr in listening} == {"127.0.0.1"}, listening


def test_bad_seeds_and_scheduler_addresses_are_refused_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="at most 10000 seeds"):
        parse_seeds("0-9999999")
    with pytest.raises(ValueError, match="at most 4294967295"):
        parse_seeds("0-99999999999999999999")
    jobs = jobs_for([EXPERIMENT_1], [0])
    for address in ("http://127.0.0.1:8787", "127.0.0.1", "tcp://host/path:1"):
        with pytest.raises(ValueError, match="tcp://HOST:PORT"):
            run_jobs(jobs, tmp_path, scheduler=address, progress=False)


@pytest.mark.slow
def test_a_scheduler_that_does_not_answer_is_a_clear_error(tmp_path):
    from docking.study.cluster import _connect

    with socket.socket() as s:  # a port that nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    start = time.monotonic()
    with pytest.raises(OSError, match="cannot reach a Dask scheduler"):
        _connect(f"tcp://127.0.0.1:{port}")
    assert time.monotonic() - start < 30


class _RecordingBar:
    """A stand-in for tqdm that records every update (issue 20: trials, not runs)."""

    made: list = []

    def __init__(self, *args, total=0, initial=0, unit="it", **kwargs):
        self.total, self.n, self.updates, self.unit = total, initial, [], unit
        _RecordingBar.made.append(self)

    def update(self, n=1):
        self.updates.append(n)
        self.n += n

    def set_postfix_str(self, *args, **kwargs):
        pass

    def refresh(self):
        pass

    def close(self):
        pass


@pytest.mark.parametrize("workers", [1, 2], ids=["in-process", "dask"])
def test_the_bar_counts_trials_as_they_finish(workers, tmp_path, monkeypatch):
    from docking.experiments import trials_in_run

    monkeypatch.setattr("tqdm.auto.tqdm", _RecordingBar)
    _RecordingBar.made.clear()
    slow = dataclasses.replace(TINY, train_trials=40, eval_trials=0, test_trials=20)
    jobs = jobs_for([slow], [0, 1])
    run_jobs(jobs, tmp_path, workers=workers, progress=True)
    reading, bar = _RecordingBar.made  # the runs looked for, then the trials computed
    assert reading.unit == "run" and reading.updates == [1] * len(jobs)
    assert bar.unit == "trial"
    assert bar.total == bar.n == 2 * trials_in_run(slow)
    # trials reported while runs compute: more updates than runs, each below a run's total
    assert len(bar.updates) > len(jobs) and min(bar.updates) < trials_in_run(slow)


def test_a_sweep_of_stored_runs_shows_the_reading_and_no_trial_bar(tmp_path, monkeypatch):
    """Reading stored runs moves a bar run by run; no bar of trials jumps to 100% (issue
    52: every bar of the report did, while the time went into reading)."""
    jobs = jobs_for([TINY], [0, 1])
    run_jobs(jobs, tmp_path, workers=1, progress=False)
    monkeypatch.setattr("tqdm.auto.tqdm", _RecordingBar)
    _RecordingBar.made.clear()
    run_jobs(jobs, tmp_path, workers=1, progress=True)
    (reading,) = [b for b in _RecordingBar.made if b.unit == "run"]
    assert reading.updates == [1] * len(jobs) and reading.n == reading.total == len(jobs)
    assert all(b.updates == [] for b in _RecordingBar.made if b.unit == "trial")


#: A sweep of TINY, seeds given as "0-2", on stderr left as it is (a file, below).
LOGGED = """
import dataclasses
import sys

from docking.presets import EXPERIMENT_1
from docking.study.sweep import jobs_for, parse_seeds, run_jobs

TINY = dataclasses.replace(EXPERIMENT_1, train_trials=4, test_trials=3, eval_every=2, eval_trials=2)
jobs = jobs_for([TINY], parse_seeds(sys.argv[2]))
run_jobs(jobs, sys.argv[1], workers=int(sys.argv[3]), desc="logged")
"""


@pytest.mark.parametrize(
    "workers, where, about",
    [
        (1, "one after another in this process", "about 3 min"),
        pytest.param(
            2, "on 2 worker processes (an embedded cluster)", "about 2 min", marks=pytest.mark.slow
        ),
    ],
    ids=["in-process", "dask"],
)
def test_a_sweep_whose_stderr_is_a_file_writes_a_line_per_run(workers, where, about, tmp_path):
    """Issue 62: with stderr not a terminal (a file: the bar is quiet) a sweep says at the start
    how many runs it computes and about how long (no ledger here: the default time a run),
    then a line per run finished (a contest said nothing for 10.7 minutes)."""
    from docking.study.progress import PROGRESS_LINE

    def sweep(seeds: str) -> list[str]:
        log = tmp_path / "stderr.log"
        with open(log, "w") as err:
            done = subprocess.run(
                [sys.executable, "-c", LOGGED, str(tmp_path / "results"), seeds, str(workers)],
                stdout=subprocess.DEVNULL,
                stderr=err,
                env={**_env(), "DOCKING_LEDGER": "off"},
                timeout=240,
            )
        assert done.returncode == 0, log.read_text()[-3000:]
        return log.read_text().splitlines()

    lines = sweep("0-2")
    default = "no recorded run like it: 60 s a run assumed"
    assert lines[0] == f"logged: 3 of 3 runs to compute, {where}: {about} ({default})"
    done = [
        re.fullmatch(r"logged: run (\d)/3 done, computed \(experiment1 seed (\d)\); .*", x)
        for x in lines[1:]
    ]
    assert len(done) == 3 and all(done), lines
    assert [m[1] for m in done] == ["1", "2", "3"]  # one line per run, as each finished
    assert sorted(m[2] for m in done) == ["0", "1", "2"]
    assert all(PROGRESS_LINE.fullmatch(x) for x in lines)
    lines = sweep("0-3")  # three stored: read, one computed
    assert lines[0].startswith("logged: 1 of 4 runs to compute (3 read from the store or the ")
    assert lines[1].startswith("logged: run 4/4 done, computed (experiment1 seed 3); ")
    assert len(lines) == 2 and all(PROGRESS_LINE.fullmatch(x) for x in lines)
    assert sweep("0-3") == []  # nothing to compute: nothing to say


def test_a_sweeps_estimate_is_the_recorded_time_of_similar_runs(monkeypatch):
    """The time a run is expected to take: the ledger's recorded runs of the same kind in the
    same world (with as many trials: their median; else their median time per trial times
    the run's trials), else the kind's in other worlds, else the default."""
    from docking.experiments import trials_in_run
    from docking.study import ledger
    from docking.study.progress import DEFAULT_RUN_SECONDS, estimates
    from docking.study.sweep import Job

    other = dataclasses.replace(TINY, world=dataclasses.replace(TINY.world, step_noise_xy=0.0))
    longer = dataclasses.replace(TINY, train_trials=2 * TINY.train_trials)

    def record(config, seconds, runner="learner"):
        return {"runner": runner, "config": config.to_dict(), "wall_seconds": seconds}

    runs = [record(TINY, 10.0), record(TINY, 20.0), record(TINY, 90.0), record(other, 400.0)]
    runs.append(record(TINY, 5000.0, runner="ppo"))  # another kind: not similar
    monkeypatch.setattr(ledger, "manifest", lambda: {"runs": dict(enumerate(runs))})
    seconds, basis = estimates([Job(TINY, 0), Job(longer, 0)])
    per_trial = 20.0 / trials_in_run(TINY)
    assert seconds == [20.0, pytest.approx(per_trial * trials_in_run(longer))]
    assert basis == "the ledger's times of runs of the same kind in the same world"
    elsewhere = dataclasses.replace(TINY, world=dataclasses.replace(TINY.world, step_noise_xy=0.02))
    seconds, basis = estimates([Job(elsewhere, 0)])
    per_trial = sorted(
        s / trials_in_run(c) for c, s in ((TINY, 10), (TINY, 20), (TINY, 90), (other, 400))
    )
    assert seconds == [pytest.approx((per_trial[1] + per_trial[2]) / 2 * trials_in_run(TINY))]
    assert basis == "the ledger's times of runs of the same kind in other worlds"
    monkeypatch.setattr(ledger, "manifest", lambda: None)
    assert estimates([Job(TINY, 0), Job(TINY, 1)]) == (
        [DEFAULT_RUN_SECONDS] * 2,
        f"no recorded run like it: {DEFAULT_RUN_SECONDS:.0f} s a run assumed",
    )


class _Collect(logging.Handler):
    """The records that pass a logger's level, kept."""

    def __init__(self):
        super().__init__(logging.DEBUG)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)


@pytest.mark.slow
def test_closing_our_cluster_logs_no_warning_of_its_own_shutdown():
    """On a busy machine a worker's heartbeat can reach the scheduler after the worker left
    (issue 41: "WARNING:distributed.scheduler:Received heartbeat from unregistered worker" on
    the terminal as the cluster closed). Here that heartbeat arrives, deterministically,
    while the cluster closes: nothing at WARNING. The same heartbeat while the cluster runs
    is still logged (a lost worker stays visible)."""
    from docking.study.cluster import _EmbeddedCluster, _quiet_distributed

    collect = _Collect()
    scheduler_log = logging.getLogger("distributed.scheduler")
    scheduler_log.addHandler(collect)
    try:
        with _quiet_distributed():
            cluster = _EmbeddedCluster(1)
            scheduler = cluster._cluster.scheduler
            ghost = "tcp://127.0.0.1:9"  # a worker the scheduler does not know
            try:
                scheduler.heartbeat_worker(address=ghost, metrics={})
                during_run = [r.getMessage() for r in collect.records]
                worker = cluster._procs[0]
                wait = worker.wait

                def late_heartbeat(timeout=None):
                    out = wait(timeout=timeout)
                    scheduler.heartbeat_worker(address=ghost, metrics={})
                    return out

                worker.wait = late_heartbeat
            finally:
                cluster.close()
    finally:
        scheduler_log.removeHandler(collect)
    assert any("unregistered worker" in m for m in during_run), during_run
    at_close = [r.getMessage() for r in collect.records if r.levelno >= logging.WARNING]
    assert at_close == during_run, at_close
    assert logging.getLogger("distributed").level <= logging.WARNING  # restored


@pytest.mark.slow
def test_the_embedded_cluster_keeps_its_scratch_in_its_own_folder(tmp_path, monkeypatch):
    """The scheduler's scratch and the workers' are under the cluster's own temporary folder,
    which its close removes: nothing is left in the system's temporary folder (issue 52: the
    in-process scheduler wrote <tmp>/dask-scratch-space, Dask's default, and left it)."""
    import tempfile

    from docking.study.cluster import _EmbeddedCluster, _quiet_distributed

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))  # the system's temporary folder
    with _quiet_distributed():
        cluster = _EmbeddedCluster(1)
        try:
            own = Path(cluster._scratch.name)
            scratch = [Path(cluster._cluster.scheduler.local_directory)]
            scratch += cluster.client.run(lambda dask_worker: dask_worker.local_directory).values()
            assert own.parent == tmp_path
            assert all(own in Path(p).parents for p in scratch), scratch
        finally:
            cluster.close()
    assert not any(tmp_path.iterdir()), list(tmp_path.iterdir())


def _worker_record(level: int, msg: str) -> logging.LogRecord:
    """A record an embedded worker's ``distributed.worker`` logger would make."""
    return logging.LogRecord("distributed.worker", level, __file__, 1, msg, None, None)


def test_a_heartbeat_cut_by_the_workers_own_close_is_no_traceback_once_its_cluster_closes(
    tmp_path,
):
    """CI, stop 47: a sweep interrupted by Ctrl-C printed a worker's "Failed to communicate
    with scheduler during heartbeat." and its traceback (a heartbeat still waiting when the
    closing worker shut its connections). distributed logs it at ERROR: while the cluster
    runs it is news; once the cluster that started the worker closes it, it is our race."""
    from docking.study.cluster import _QuietFailures

    closing = tmp_path / "closing"
    quiet = _QuietFailures(str(closing))
    cut = _worker_record(logging.ERROR, "Failed to communicate with scheduler during heartbeat.")
    assert quiet.filter(cut)
    closing.touch()
    assert not quiet.filter(cut)


@pytest.mark.slow
def test_a_terminals_ctrl_c_reaches_the_command_not_its_workers():
    """A terminal's Ctrl-C signals its foreground process group. The embedded cluster's
    workers live in a session of their own, so only the command hears it and closes them in
    order (the file they watch first); hearing it too, they raced that close (CI, stop 47)."""
    from docking.study.cluster import _EmbeddedCluster

    cluster = _EmbeddedCluster(2)
    try:
        for proc in cluster._procs:
            assert os.getpgid(proc.pid) != os.getpgid(0)
            assert os.getsid(proc.pid) != os.getsid(0)
    finally:
        cluster.close()
    assert all(proc.poll() is not None for proc in cluster._procs)


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/self/autogroup").exists(), reason="no autogroups")
def test_a_niced_commands_workers_yield_the_cpu_as_it_does():
    """Its workers' sessions are scheduling groups of their own (Linux autogroups), which a
    process's nice value does not reach: ``nice -n 7`` on the command gives each worker's
    group the command's nice value, 7 more than this process's, at most 19 (the kernel's
    cap: under ``nice -n 19 make test`` the command runs at 19, as its workers' groups do)
    (make test runs verify niced beside the tests)."""
    code = (
        "from docking.study.cluster import _EmbeddedCluster\n"
        "c = _EmbeddedCluster(1)\n"
        "print(open(f'/proc/{c._procs[0].pid}/autogroup').read().split()[-1])\n"
        "c.close()\n"
    )
    done = subprocess.run(
        ["nice", "-n", "7", sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parent.parent)},
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split()[-1] == str(min(os.nice(0) + 7, 19))


def test_an_embedded_worker_is_quiet_below_error_once_its_cluster_closes(tmp_path):
    from docking.study.cluster import _QuietFailures

    closing = tmp_path / "closing"
    quiet = _QuietFailures(str(closing))

    unaware = "Scheduler was unaware of this worker; shutting down."
    assert quiet.filter(_worker_record(logging.WARNING, unaware))  # while it runs: news
    assert not quiet.filter(_worker_record(logging.ERROR, "Compute Failed\nKey: x"))
    closing.touch()
    assert not quiet.filter(_worker_record(logging.WARNING, unaware))
    assert quiet.filter(_worker_record(logging.ERROR, "an error"))
    assert _QuietFailures().filter(_worker_record(logging.WARNING, unaware))  # no file to watch
