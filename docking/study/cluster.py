"""The Dask clusters a sweep runs on (:mod:`docking.study.sweep`): the embedded cluster (the
scheduler in this process, one worker process per core, which end with this process and leave
the reports of a failed job and of their own shutdown to it) and a connection to an existing
scheduler (``tcp://HOST:PORT``, or ``tls://`` with Dask's TLS configuration), checked within
:data:`CONNECT_SECONDS`.

The embedded cluster's workers end with the process that started them
(:func:`_die_with_parent`: ``PR_SET_PDEATHSIG`` on Linux and a ``getppid`` watchdog), and
they are plain subprocesses rather than ``multiprocessing`` children, so neither ``kill -9``
nor ``SIGTERM`` of the parent leaves orphans or leaked semaphores. They preload this module
(:func:`dask_setup`).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import signal
import sys
import threading
import time
from collections.abc import Mapping
from pathlib import Path

from docking.study import learners

_PR_SET_PDEATHSIG = 1


_LOG_VARIABLE = "DASK_LOGGING__DISTRIBUTED"


#: Set in the environment of the embedded cluster's workers: the PID they must die with.
_PARENT_VARIABLE = "DOCKING_SWEEP_PARENT"


#: Set in the environment of the embedded cluster's workers: a file that exists once the
#: cluster that started them is closing (:meth:`_EmbeddedCluster.close`).
_CLOSING_VARIABLE = "DOCKING_SWEEP_CLOSING"


def _die_with_parent(parent: int) -> None:
    """End this process when ``parent`` (its parent process) ends: ``PR_SET_PDEATHSIG`` =
    SIGKILL where Linux offers it, and a watchdog thread that exits once the process is
    re-parented (``getppid`` changes), which also covers a parent that died before."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent died already
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="docking-parent-watchdog", daemon=True).start()


#: What a worker logs, at ERROR with a traceback, when it closes its connections while a
#: heartbeat still waits for the scheduler's answer (distributed's ``Worker.heartbeat``).
_HEARTBEAT_CUT = "Failed to communicate with scheduler during heartbeat."


class _QuietFailures(logging.Filter):
    """Drops what an embedded worker reports of a failed job: "Compute Failed" (the job's
    exception and its traceback; the client re-raises the exception and the command prints
    it once, in one line) and the jobs cancelled when the failed sweep closes the cluster;
    and, once the file ``closing`` exists (the cluster that started the worker is closing
    it), every record below ERROR and the heartbeat its own close cut (``_HEARTBEAT_CUT``):
    the races of our own shutdown ("Scheduler was unaware of this worker; shutting down.")
    are not news. A worker lost while the cluster runs is still reported, and so is any
    other error while it closes."""

    def __init__(self, closing: str | None = None):
        super().__init__()
        self.closing = closing

    def filter(self, record: logging.LogRecord) -> bool:
        if str(record.msg).startswith("Compute Failed"):
            return False
        if record.name.startswith("distributed.worker") and "CancelledError" in record.getMessage():
            return False
        if self.closing is None or not os.path.exists(self.closing):
            return True
        return record.levelno >= logging.ERROR and record.getMessage() != _HEARTBEAT_CUT


def dask_setup(worker=None) -> None:
    """Dask preload hook (``dask worker --preload docking.study.cluster``): a worker of the embedded
    cluster ends with the process that started it, and leaves reporting a failed job to the
    client, and its shutdown to the cluster's close (:class:`_QuietFailures`). Does nothing
    in other workers."""
    parent = os.environ.get(_PARENT_VARIABLE)
    if parent:
        # on the handlers: it sees the records of every logger
        quiet = _QuietFailures(os.environ.get(_CLOSING_VARIABLE))
        for handler in logging.getLogger("distributed").handlers + logging.getLogger().handlers:
            handler.addFilter(quiet)
        logging.getLogger("distributed.worker").addFilter(quiet)
        _die_with_parent(int(parent))
        _nice_as_a_group()


def _nice_as_a_group() -> None:
    """Give this process's scheduling group its nice value. A worker of the embedded cluster
    runs in a session of its own, and Linux schedules each session as a group (autogroup),
    which shares the CPU equally with the others whatever its processes' nice values: so
    ``nice python -m docking ...`` (``make test`` runs ``verify`` so, beside the tests) would
    not yield to other work. The group's own nice value (``/proc/self/autogroup``) is what
    the scheduler weighs; it takes the process's, which the worker inherited. Nothing where
    the kernel has no autogroups, or the process is not niced."""
    niceness = os.nice(0)
    if niceness > 0:
        with contextlib.suppress(OSError):
            Path("/proc/self/autogroup").write_text(f"{niceness}\n")


class _EmbeddedCluster:
    """A Dask cluster on this machine: the scheduler in this process (a ``LocalCluster``
    without in-process workers) and ``n_workers`` worker processes, ``dask worker --no-nanny``
    with one thread each, that end with this process (:func:`dask_setup`). Workers are plain
    subprocesses, not ``multiprocessing`` children, so a killed parent leaves neither
    orphans nor semaphores behind. Why not a stock ``LocalCluster(processes=True)``: its
    nannies start the workers through ``multiprocessing``, and when its process is ended by
    SIGKILL or SIGTERM the resource tracker reports leaked semaphores
    (distributed 2026.8; tests/test_sweep.py's ``test_workers_end_with_their_parent``)."""

    def __init__(self, n_workers: int, modules: Mapping[str, tuple[str, str]] | None = None):
        import subprocess
        import tempfile

        import dask
        from distributed import Client, LocalCluster

        # The cluster's own folder, removed when it closes: the workers' scratch
        # (--local-directory) and the scheduler's (Dask's temporary-directory while it
        # starts; by default <the system's temporary folder>/dask-scratch-space, shared by
        # every cluster and left behind).
        self._scratch = tempfile.TemporaryDirectory(prefix="docking-dask-")
        self._closing = os.path.join(self._scratch.name, "closing")  # see close()
        self._procs: list[subprocess.Popen] = []
        with dask.config.set({"temporary-directory": self._scratch.name}):
            self._cluster = LocalCluster(
                n_workers=0,
                processes=False,
                protocol="tcp",  # not inproc: the workers are other processes
                host="127.0.0.1",
                scheduler_port=0,
                dashboard_address="127.0.0.1:0",  # ":0" would listen on every interface
                silence_logs=logging.ERROR,
            )
        package_root = str(Path(__file__).resolve().parents[2])
        path = (package_root, *learners.import_path(modules), os.environ.get("PYTHONPATH"))
        env = {
            **os.environ,
            _PARENT_VARIABLE: str(os.getpid()),
            _CLOSING_VARIABLE: self._closing,
            # The workers import this very package, and what this process imports (a
            # learner's modules of the user's own among it: learners.import_path).
            "PYTHONPATH": os.pathsep.join(dict.fromkeys(p for p in path if p)),
        }
        try:
            for k in range(n_workers):
                self._procs.append(
                    subprocess.Popen(
                        self._worker_command(k),
                        env=env,
                        stdin=subprocess.DEVNULL,
                        # A session of their own: a terminal's Ctrl-C (SIGINT to its
                        # foreground group) reaches the command only, which then closes its
                        # workers in order (close()); reaching them too, it raced that close.
                        start_new_session=True,
                    )
                )
            self.client = Client(self._cluster)
            self._wait_for_workers(n_workers)
        except BaseException:
            self.close()
            raise

    def _worker_command(self, k: int) -> list[str]:
        """The command of worker ``k``: ``dask worker`` without a nanny, one thread, every
        server on loopback, this module preloaded (:func:`dask_setup`)."""
        return [
            sys.executable,
            "-m",
            "dask",
            "worker",
            self._cluster.scheduler_address,
            "--no-nanny",
            "--nthreads",
            "1",
            "--host",
            "127.0.0.1",
            "--no-dashboard",
            # The worker's HTTP server (metrics, health) listens here even without a
            # dashboard: on loopback only.
            "--dashboard-address",
            "127.0.0.1:0",
            "--name",
            f"docking-{k}",
            "--local-directory",
            self._scratch.name,
            "--preload",
            "docking.study.cluster",
        ]

    def alive(self) -> bool:
        """Whether any of the worker processes still runs."""
        return any(proc.poll() is None for proc in self._procs)

    def _wait_for_workers(self, n: int, timeout: float = 120.0) -> None:
        deadline = time.monotonic() + timeout
        while len(self.client.scheduler_info(n_workers=-1)["workers"]) < n:
            dead = [p.args[-1] for p in self._procs if p.poll() is not None]
            if dead or time.monotonic() > deadline:
                raise RuntimeError(
                    f"Dask workers did not start ({len(dead)} of {n} exited, see above)"
                )
            time.sleep(0.1)

    def close(self, grace: float = 10.0) -> None:
        """Close the client, end the workers, close the scheduler. Each worker is sent
        SIGTERM, and those still there ``grace`` seconds later (one deadline for them all)
        SIGKILL: a worker still computing a job does not end on SIGTERM (its thread runs on),
        so after an interrupt or a failed job, with jobs still running, a short grace is all
        that is worth waiting (:func:`docking.study.sweep._run_on_dask`). On a busy machine a
        worker's heartbeat can reach the scheduler after the worker has left, and the
        scheduler and the worker each log it at WARNING ("Received heartbeat from
        unregistered worker", "Scheduler was unaware of this worker"); the shutdown is ours,
        so within it distributed logs errors only, here (:func:`_quiet_shutdown`) and in the
        workers (the file they watch, :class:`_QuietFailures`)."""
        with _quiet_shutdown():
            with contextlib.suppress(OSError):
                Path(self._closing).touch()
            client = getattr(self, "client", None)
            if client is not None:
                client.close()
            for proc in self._procs:
                if proc.poll() is None:
                    proc.terminate()
            deadline = time.monotonic() + grace
            for proc in self._procs:
                try:
                    proc.wait(timeout=max(0.0, deadline - time.monotonic()))
                except Exception:
                    proc.kill()
                    proc.wait()
            self._cluster.close()
            self._scratch.cleanup()


#: How long connecting to a scheduler (TCP, and Dask's handshake) may take, in seconds.
CONNECT_SECONDS = 10.0


_HOST = r"\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+"  # [IPv6], an IPv4 address or a host name


def _check_scheduler(scheduler) -> None:
    """``ValueError`` unless ``scheduler`` is ``tcp://HOST:PORT`` (PORT 1-65535), or
    ``tls://HOST:PORT`` with a TLS configuration in Dask's config to connect with."""
    import re

    found = (
        re.fullmatch(rf"(tcp|tls)://({_HOST}):(\d+)", scheduler)
        if isinstance(scheduler, str)
        else None
    )
    if found is None:
        raise ValueError(
            f"the scheduler address must be tcp://HOST:PORT or tls://HOST:PORT, got "
            f"{scheduler!r:.120}"
        )
    protocol, host, port = found.groups()
    if len(port) > 5 or not 1 <= int(port) <= 65535:
        raise ValueError(f"the scheduler's port must be 1-65535, got {port:.30} in {scheduler:.80}")
    if len(host) > 253 or any(len(label) > 63 for label in host.split(".")):
        raise ValueError(f"the scheduler's host {host:.80}... is too long to be a host name")
    if protocol == "tls":
        from distributed.security import Security

        tls = Security().get_tls_config_for_role("client")
        if not (tls["ca_file"] and tls["cert"]):
            raise ValueError(
                f"tls:// schedulers need a security configuration ({scheduler}): Dask's "
                "distributed.comm.tls.ca-file and distributed.comm.tls.client.cert (and .key), "
                "e.g. DASK_DISTRIBUTED__COMM__TLS__CA_FILE=...; or use tcp://HOST:PORT"
            )


def _connect(scheduler: str):
    """A client of the Dask scheduler at ``scheduler`` (``tcp://HOST:PORT`` or
    ``tls://HOST:PORT``); ``OSError`` naming it if it does not answer as one within
    :data:`CONNECT_SECONDS` (a server that accepts and never answers included:
    :func:`_handshake`)."""

    from distributed import Client

    _check_scheduler(scheduler)
    _handshake(scheduler, CONNECT_SECONDS)
    try:
        return Client(scheduler, timeout=f"{CONNECT_SECONDS}s")
    except MemoryError:  # e.g. an HTTP server: its reply read as a frame length
        raise OSError(f"{scheduler} does not answer as a Dask scheduler") from None
    except (OSError, TimeoutError) as exc:
        raise OSError(
            f"cannot reach a Dask scheduler at {scheduler} within {CONNECT_SECONDS:g} s "
            f"({type(exc).__name__}: {exc})"
        ) from None


def _handshake(scheduler: str, seconds: float) -> None:
    """Connect to ``scheduler`` and exchange Dask's handshake, within ``seconds``; ``OSError``
    naming it otherwise. ``Client(address, timeout=...)`` bounds the TCP connection but waits
    for the scheduler's handshake forever (a server that accepts and never answers hangs it);
    this attempt runs in a thread of its own, with its own event loop, and is abandoned at
    the deadline."""
    from distributed.comm import connect
    from distributed.security import Security

    args = Security().get_connection_args("client")
    outcome: dict = {}

    async def attempt() -> None:
        comm = await asyncio.wait_for(connect(scheduler, timeout=seconds, **args), seconds)
        await comm.close()

    def run() -> None:
        try:
            asyncio.run(attempt())
        except BaseException as exc:  # reported by the caller's thread
            outcome["error"] = exc
        else:
            outcome["ok"] = True

    thread = threading.Thread(target=run, name="docking-scheduler-handshake", daemon=True)
    thread.start()
    thread.join(seconds + 5.0)
    if outcome.get("ok"):
        return
    error = outcome.get("error")
    if error is None or isinstance(error, (OSError, TimeoutError)):
        detail = "no answer" if error is None else f"{type(error).__name__}: {error}"
        if error is not None and not str(error):
            detail = f"{type(error).__name__}: no handshake"
        raise OSError(
            f"cannot reach a Dask scheduler at {scheduler} within {seconds:g} s ({detail})"
        )
    raise OSError(
        f"{scheduler} does not answer as a Dask scheduler ({type(error).__name__}: {error})"
    )


@contextlib.contextmanager
def _quiet_shutdown():
    """Within this, distributed's loggers (every ``distributed.*`` logger, and the ones
    created within, which inherit from ``distributed``) log errors only: for the close of a
    cluster this process started, whose warnings are the races of its own shutdown."""
    loggers = [logging.getLogger("distributed")] + [
        logger
        for name, logger in list(logging.Logger.manager.loggerDict.items())
        if name.startswith("distributed.") and isinstance(logger, logging.Logger)
    ]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(max(logger.level, logging.ERROR))
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels, strict=True):
            logger.setLevel(level)


@contextlib.contextmanager
def _quiet_distributed():
    """distributed logs at INFO through the root handler that absl (dm-control) installs:
    within this, it logs warnings only (a lost worker stays visible), and so do the worker
    processes started within (they read the variable at start)."""
    logger = logging.getLogger("distributed")
    level, saved_env = logger.level, os.environ.get(_LOG_VARIABLE)
    logger.setLevel(max(level, logging.WARNING))
    os.environ[_LOG_VARIABLE] = "warning"
    try:
        yield
    finally:
        logger.setLevel(level)
        if saved_env is None:
            os.environ.pop(_LOG_VARIABLE, None)
        else:
            os.environ[_LOG_VARIABLE] = saved_env
