"""Sweeps: many (configuration, seed) runs on a Dask cluster, saved in the results store.

A sweep is a list of :class:`Job` s. Each job is located once, before anything computes
(:func:`docking.study.runs.locate`: a valid file in the results store, else the committed
ledger's entry, else to compute); the runs found nowhere are computed through
``dask.distributed``:

* by default on an embedded cluster: the scheduler of a ``LocalCluster`` in this process and
  one worker *process* per core (or per job, if fewer), ``dask worker`` with one thread
  each, so every worker renders with its own OpenGL context;
* or on an existing cluster, ``scheduler="tcp://HOST:PORT"`` (started with ``dask scheduler``
  and ``dask worker tcp://HOST:PORT``, or by dask-jobqueue on SLURM). The workers must import
  the same ``docking`` code and see the results folder under the same path (one machine or a
  shared file system).

A learner registered from a module of the user's own reaches the workers by name: the
embedded cluster's workers import from this process's import path, an existing cluster is sent
the modules' files, and a worker that cannot import them stops the sweep before any job
(:mod:`docking.study.learners`: ``import_path``, ``ship_code``, ``check_imports``). A sweep
whose embedded workers have all ended stops too.

Each such job computes its run on a worker, which saves it in the store in the file its key
names (:func:`docking.study.store.compute`, :func:`docking.study.kinds.result_path`) and
returns the path (or the run, to a caller that keeps the runs: :func:`sweep`). Stored runs
are skipped before anything is submitted, so an interrupted sweep resumes where it stopped and
no finished run is computed twice. A job lost with a worker is rescheduled by Dask on another
one. A progress bar on the terminal (stderr) counts finished trials and jobs; where stderr is
not a terminal, lines say what the sweep computes, about how long it takes, and each run
finished (:class:`docking.study.progress.Progress`).

The clusters themselves, the embedded one's workers (which end with the process that started
them) and the connection to an existing scheduler, are :mod:`docking.study.cluster`.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import os
import sys
import threading
import time
import uuid
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from docking.experiments import ExperimentConfig
from docking.study import learners, paths, store
from docking.study.cluster import _check_scheduler, _connect, _EmbeddedCluster, _quiet_distributed
from docking.study.kinds import result_path, runner_for
from docking.study.progress import Progress
from docking.study.runs import Located, locate
from docking.validate import (
    DIGITS,
    MAX_SEED,
    check_instance,
    check_int,
    parse_int,
    parse_real,
)

if TYPE_CHECKING:
    from docking.study.ppo import PPOConfig

__all__ = [
    "Job",
    "apply_override",
    "grid_configs",
    "jobs_for",
    "missing",
    "parse_seeds",
    "run_configs",
    "run_jobs",
    "sweep",
]


@dataclasses.dataclass(frozen=True)
class Job:
    """One run of a sweep: a configuration of a kind of run (:func:`docking.study.kinds.runner_for`:
    the paper's learner or a yardstick, PPO, or a registered learner) and a seed."""

    config: ExperimentConfig | PPOConfig
    seed: int

    def __post_init__(self):
        try:
            runner_for(self.config)
        except TypeError:
            raise TypeError(
                f"Job.config must be an ExperimentConfig or a PPOConfig, got {self.config!r:.80}"
            ) from None
        object.__setattr__(self, "seed", check_int("Job", "seed", self.seed, lo=0))


def _trials(config) -> int:
    return runner_for(config).trials_in_run(config)


def jobs_for(configs: Iterable[ExperimentConfig], seeds: Iterable[int]) -> list[Job]:
    """Every configuration with every seed, configuration-major."""
    seeds = list(seeds)
    return [Job(c, s) for c in configs for s in seeds]


# ------------------------------------------------------------------------------------------
# Seeds and parameter grids from the command line.
# ------------------------------------------------------------------------------------------


#: The most seeds one command may name (each seed is a run of minutes).
MAX_SEEDS = 10_000
#: The most configurations one grid may name, as for seeds (each is a run of minutes per seed).
MAX_CONFIGS = 10_000
#: The most runs (configurations x seeds) one sweep command may name.
MAX_RUNS = 10_000


def parse_seeds(text: str) -> list[int]:
    """Seeds from ``"0-19"``, ``"0,3,5"``, ``"0 3 5"`` or ``"0-4,10-12"`` (ranges include both
    ends; commas and/or whitespace separate the items, spaces around a range's ``-`` are
    allowed), at most :data:`MAX_SEEDS` of them, each at most
    :data:`docking.validate.MAX_SEED`. Seeds are ASCII digits (:data:`docking.validate.DIGITS`,
    as every number of the command line): ``int`` would also read ``1_0`` as 10 and other
    scripts' digits (``١``) as theirs."""
    import re

    usage = (
        "seeds must be integers >= 0 or ranges like 0-19, separated by commas or spaces; got "
        f"{text!r}"
    )
    seeds: list[int] = []
    # "0 - 4" is the range 0-4; "1 2" the seeds 1 and 2 (never 12).
    for chunk in re.sub(r"\s*-\s*", "-", str(text)).split(","):
        items = chunk.split()
        if not items:  # "", "1,,2", "1,"
            raise ValueError(usage)
        for part in items:
            bounds = part.split("-")
            try:
                if len(bounds) > 2 or not all(re.fullmatch(DIGITS, b) for b in bounds):
                    raise ValueError
                lo, hi = int(bounds[0]), int(bounds[-1])
                if lo < 0 or hi < lo:
                    raise ValueError
            except ValueError:
                raise ValueError(usage) from None
            if hi > MAX_SEED:
                raise ValueError(f"seeds must be at most {MAX_SEED}; got {text!r}")
            if len(seeds) + hi - lo + 1 > MAX_SEEDS:
                raise ValueError(f"at most {MAX_SEEDS} seeds in one command; got more in {text!r}")
            seeds.extend(range(lo, hi + 1))
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"seeds must not repeat; got {text!r}")
    return seeds


def seeds_text(seeds) -> str:
    """``0-4, 7`` for ``[0, 1, 2, 3, 4, 7]``: the seeds as ranges (in the order given; what
    :func:`parse_seeds` reads back, with the spaces dropped)."""
    seeds, parts, start = list(seeds), [], None
    for i, s in enumerate(seeds):
        if start is None:
            start = s
        if i + 1 == len(seeds) or seeds[i + 1] != s + 1:
            parts.append(str(start) if start == s else f"{start}-{s}")
            start = None
    return ", ".join(parts)


def _convert(value: str, current, where: str):
    if isinstance(current, bool):
        lowered = value.lower()
        if lowered in ("true", "1", "yes"):
            return True
        if lowered in ("false", "0", "no"):
            return False
        raise ValueError(f"{where} takes true or false, got {value!r}")
    if isinstance(current, int):  # ASCII digits, as every number of the command line
        try:
            return parse_int(value)
        except ValueError as exc:
            raise ValueError(f"{where} takes an integer; {exc}") from None
    if isinstance(current, float):
        try:
            return parse_real(value)
        except ValueError as exc:
            raise ValueError(f"{where} takes a number; {exc}") from None
    if isinstance(current, str):
        return value
    raise ValueError(f"{where} ({type(current).__name__}) cannot be set from the command line")


def apply_override(config, path: str, value: str):
    """A copy of the (nested, frozen) dataclass ``config`` with the field at the dotted
    ``path`` (e.g. ``"network.eps_w"``; dashes may replace underscores) set to ``value``,
    converted to the field's current type; the dataclasses validate the result."""
    head, _, rest = path.replace("-", "_").partition(".")
    names = {f.name for f in dataclasses.fields(config)}
    where = f"{type(config).__name__}.{head}"
    if head not in names:
        raise ValueError(f"{where} is not a field (fields: {', '.join(sorted(names))})")
    current = getattr(config, head)
    if rest:
        if not dataclasses.is_dataclass(current):
            raise ValueError(f"{where} has no field {rest!r}")
        new = apply_override(current, rest, value)
    else:
        if dataclasses.is_dataclass(current):
            raise ValueError(f"{where} is a group of fields; name one of them ({where}.FIELD)")
        new = _convert(value, current, where)
    return dataclasses.replace(config, **{head: new})


def grid_configs(base: ExperimentConfig, grid: Sequence[str]) -> list[ExperimentConfig]:
    """The configurations of a parameter grid: every combination of the values of each
    ``"path=v1,v2,..."`` entry (e.g. ``"network.eps_w=0,0.05"``) applied to ``base``. A field
    named twice, or two values that give the same configuration (``0,0.0``), are refused as
    repeated seeds are; so is a grid of more than :data:`MAX_CONFIGS` configurations, before
    any is built."""
    axes, named = [], {}
    for entry in grid:
        path, sep, values = entry.partition("=")
        if not sep or not path or not values:
            raise ValueError(
                f"a grid entry is PATH=V1,V2,... (e.g. network.eps_w=0,0.05); got {entry!r}"
            )
        field = path.strip().replace("-", "_")
        if field in named:
            raise ValueError(f"the grid names {field} twice ({named[field]!r} and {entry!r})")
        named[field] = entry
        axes.append([(path.strip(), v.strip()) for v in values.split(",")])
    count = math.prod(len(axis) for axis in axes)
    if count > MAX_CONFIGS:
        sizes = " x ".join(str(len(axis)) for axis in axes)
        raise ValueError(
            f"at most {MAX_CONFIGS} grid configurations in one command; the grid names "
            f"{count:,} ({sizes})"
        )
    configs, seen = [], {}
    for combination in itertools.product(*axes):
        config = base
        for path, value in combination:
            config = apply_override(config, path, value)
        text = json.dumps(config.to_dict(), sort_keys=True)
        point = " ".join(f"{path}={value}" for path, value in combination)
        if text in seen:
            raise ValueError(
                f"the grid's values must differ; {seen[text]} and {point} are the same "
                f"configuration"
            )
        seen[text] = point
        configs.append(config)
    return configs


# ------------------------------------------------------------------------------------------
# Jobs on a worker.
# ------------------------------------------------------------------------------------------


#: The Dask event topic on which workers report finished trials (``(job index, trials)``).
_PROGRESS_TOPIC = "docking-trials"


def _run_job(
    config: ExperimentConfig,
    seed: int,
    path: str,
    force: bool = False,
    on_trials=None,
    report: str | None = None,
    keep: bool = False,
):
    """The task a worker runs: compute one run and store it at ``path``
    (:func:`docking.study.store.compute`: the client located it,
    :func:`docking.study.runs.locate`, and found it nowhere, or was told to recompute it:
    ``force``); the run if ``keep``, else the path. A job Dask runs again after its worker was
    lost reads the run an earlier attempt stored.
    ``on_trials(n)``: called as trials finish (in this process); ``report``: ``"sweep:k"``
    to publish them, at most once a second, on the Dask event topic
    :data:`_PROGRESS_TOPIC` (in a worker)."""
    if report is not None:
        on_trials = _Reporter(report)
    try:
        result = store.compute(
            config, seed, Path(path), progress=False, on_trials=on_trials, again=force
        )
    finally:
        if report is not None:
            on_trials.flush()
    return result if keep else path


class _Reporter:
    """Counts a worker's finished trials and publishes them on the Dask event topic at most
    once a second (``flush`` sends the rest)."""

    def __init__(self, tag: str):
        self.tag, self.count, self.sent_at = tag, 0, time.monotonic()

    def __call__(self, n: int) -> None:
        self.count += n
        if time.monotonic() - self.sent_at >= 1.0:
            self.flush()

    def flush(self) -> None:
        if self.count:
            from distributed import get_worker

            get_worker().log_event(_PROGRESS_TOPIC, {"tag": self.tag, "trials": self.count})
            self.count, self.sent_at = 0, time.monotonic()


def missing(jobs: Iterable[Job], results_dir: Path | str | None = None) -> list[Job]:
    """The jobs whose runs neither the store nor the ledger holds (what a sweep would
    compute), each located once (:func:`docking.study.runs.locate`)."""
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    return [j for j in jobs if locate(j.config, j.seed, root, warn=False).place == "computed"]


def run_jobs(
    jobs: Sequence[Job],
    results_dir: Path | str | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    force: bool = False,
    progress: bool = True,
    desc: str = "runs",
) -> list[Path]:
    """Run (or load) every job; the paths of their stored results, in the order of ``jobs``
    (:func:`sweep`, which says where each run came from and gives the runs).

    Args:
      jobs: The (configuration, seed) runs.
      results_dir: The results store (default :func:`docking.study.paths.results_dir`).
      scheduler: Address of an existing Dask scheduler (``tcp://HOST:PORT``); ``None`` starts
        an embedded ``LocalCluster`` of ``workers`` processes.
      workers: Worker processes of the embedded cluster (default: one per core, at most one
        per job to run). ``1`` runs the jobs one after another in this process, no Dask.
      force: Recompute and replace stored runs.
      progress: Show a bar on stderr that counts trials as they finish (the runs' trials
        of :func:`docking.experiments.trials_in_run`), with the runs done beside it; when
        stderr is not a terminal, a line at the start (the runs to compute, about how long)
        and a line per run finished instead (:class:`docking.study.progress.Progress`).
      desc: The bar's label.
    """
    found = sweep(jobs, results_dir, scheduler, workers, force, progress, desc, keep=False)
    return [f.path for f in found]


def sweep(
    jobs: Sequence[Job],
    results_dir: Path | str | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    force: bool = False,
    progress: bool = True,
    desc: str = "runs",
    keep: bool = True,
    located: Sequence[Located] | None = None,
) -> list[Located]:
    """Run (or load) every job, as :func:`run_jobs` (the same arguments): each job is located
    once (:func:`docking.study.runs.locate`: the store, else the ledger), the runs found
    nowhere (every one with ``force``) are computed on the cluster and stored, and each job's
    :class:`~docking.study.runs.Located` is returned in the order of ``jobs``: where its run
    was (``"computed"`` for those computed now) and, with ``keep``, the run. ``located``: the
    jobs located already by the caller (once each), who has read the ledger's runs before
    anything computes."""
    jobs = [check_instance("run_jobs", "jobs[]", j, Job) for j in jobs]
    if workers is not None:
        workers = check_int("run_jobs", "workers", workers, lo=1)
    if scheduler is not None:
        _check_scheduler(scheduler)
    root = Path(results_dir if results_dir is not None else paths.results_dir()).resolve()
    if force:
        located = [_to_compute(j, root) for j in jobs]
    elif located is None:
        located = _located(jobs, root, desc, progress)
    located = list(located)
    todo = [k for k, found in enumerate(located) if found.place == "computed"]
    if todo:  # a read-only store that holds every run can still be read
        store.check_writable(root)

    trials = [_trials(j.config) for j in jobs]
    # computing: a bar of trials (none when every run was found: it would say nothing)
    stored = sum(trials) - sum(trials[k] for k in todo)
    bar = _trial_bar(sum(trials), stored, desc, progress and bool(todo))
    runs = Progress(bar, jobs, todo, desc, progress)
    computed: dict[int, object] = {}
    try:
        if todo:
            n_workers = workers or min(len(todo), os.cpu_count() or 1)
            args = (jobs, located, todo, force, bar, trials, runs, computed, keep)
            if scheduler is None and n_workers <= 1:
                _run_here(*args)
            else:
                _run_on_dask(scheduler, n_workers, *args)
    finally:
        bar.close()
    return [
        dataclasses.replace(found, run=computed.get(k)) if k in computed and keep else found
        for k, found in enumerate(located)
    ]


def _located(jobs: list[Job], root: Path, desc: str, progress: bool) -> list[Located]:
    """Each job located once (:func:`docking.study.runs.locate`), with a bar of the runs
    read (from the store or the ledger) that moves as each is found; quiet when stderr is not
    a terminal, or without ``progress``."""
    from tqdm.auto import tqdm

    bar = tqdm(
        total=len(jobs),
        desc=f"{desc}: reading",
        unit="run",
        disable=None if progress else True,  # None: quiet unless stderr is a terminal
        file=sys.stderr,
        dynamic_ncols=True,
        leave=False,
    )
    located = []
    try:
        for job in jobs:
            located.append(locate(job.config, job.seed, root))
            bar.update(1)
    finally:
        bar.close()
    return located


def _to_compute(job: Job, root: Path) -> Located:
    """A job to compute whatever is stored (``force``), not located."""
    from docking.study.kinds import run_key

    key = run_key(job.config, job.seed)
    return Located(job.config, job.seed, key, result_path(job.config, job.seed, root), "computed")


def _trial_bar(total: int, stored: int, desc: str, progress: bool):
    """:func:`run_jobs`'s bar on stderr: ``total`` trials, ``stored`` of them in runs stored
    already; quiet when stderr is not a terminal, or without ``progress``."""
    from tqdm.auto import tqdm

    return tqdm(
        total=total,
        initial=stored,
        desc=desc,
        unit="trial",
        disable=None if progress else True,  # None: quiet unless stderr is a terminal
        file=sys.stderr,
        dynamic_ncols=True,
        smoothing=0.05,
    )


def run_configs(
    configs: Mapping[str, ExperimentConfig],
    seeds: Iterable[int],
    results_dir: Path | str | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    desc: str = "runs",
    sources: dict | None = None,
) -> dict:
    """Run (or load) every configuration of ``configs`` for every seed in one sweep
    (:func:`sweep`); ``{key: its runs in seed order}`` (``ExperimentResult`` s, or
    ``docking.study.ppo.PPOResult`` s for PPO configurations). ``sources``: a dict that gets
    ``{key: where each seed's run came from}`` (:data:`docking.study.runs.PLACES`)."""
    seeds = tuple(seeds)
    jobs = jobs_for(configs.values(), seeds)
    found = iter(
        sweep(
            jobs,
            results_dir,
            scheduler=scheduler,
            workers=workers,
            progress=progress,
            desc=desc,
        )
    )
    located = {key: [next(found) for _ in seeds] for key in configs}
    if sources is not None:
        sources.update({key: [f.place for f in runs] for key, runs in located.items()})
    return {key: [f.run for f in runs] for key, runs in located.items()}


def _run_here(jobs, located, todo, force, bar, trials, runs, computed, keep) -> None:
    """Compute the jobs ``todo`` one after another in this process (the bar moving with each
    trial); with ``keep``, each run goes into ``computed`` by its job's index."""
    runs.start(1, "one after another in this process")
    for k in todo:
        job, path = jobs[k], str(located[k].path)
        result = _run_job(job.config, job.seed, path, force, bar.update, keep=keep)
        if keep:
            computed[k] = result
        runs.done([k])


def _run_on_dask(
    scheduler, n_workers: int, jobs, located, todo, force, bar, trials, runs, computed, keep
) -> None:
    """Compute the jobs ``todo`` on ``scheduler``'s cluster (None: an embedded one of
    ``n_workers`` processes), following their progress (:func:`_submit_and_follow`), once its
    workers import the modules of the user's own the jobs need (:func:`_ready`)."""
    modules = learners.modules_of(jobs[k].config for k in todo)
    with _quiet_distributed():
        cluster = _EmbeddedCluster(n_workers, modules) if scheduler is None else None
        finished = False
        try:
            with cluster.client if cluster is not None else _connect(scheduler) as client:
                _ready(client, scheduler, n_workers if cluster else None, modules, runs)
                follow = (jobs, located, todo, force, bar, trials, runs, computed, keep)
                _submit_and_follow(client, *follow, alive=cluster.alive if cluster else None)
            finished = True
        finally:
            if cluster is not None:
                # Interrupted or failed, workers may still be computing: SIGTERM does not
                # end those, so SIGKILL follows after 1 s instead of 10 (a Ctrl-C took 20 s
                # to return with two workers busy). A job's file is written atomically.
                cluster.close(grace=10.0 if finished else 1.0)


def _ready(client, scheduler, embedded: int | None, modules, runs) -> None:
    """Before the first job: the modules of the user's own the jobs need (``modules``) sent to
    an existing cluster (:func:`docking.study.learners.ship_code`) and imported by every worker
    (:func:`~docking.study.learners.check_imports`); then the first line of progress (``runs``:
    :class:`~docking.study.progress.Progress`). ``embedded``: the embedded cluster's workers."""
    if embedded is None:
        learners.ship_code(client, modules)
    learners.check_imports(client, modules, embedded=embedded is not None)
    if embedded is not None:
        runs.start(embedded, f"on {embedded} worker processes (an embedded cluster)")
    else:
        count = len(client.scheduler_info(n_workers=-1)["workers"])
        runs.start(count, f"on the {count} workers of {scheduler} now")


def _submit(client, jobs, located, todo, force: bool, keep: bool, tag: str) -> dict:
    """Submit the jobs ``todo`` to ``client``, each reporting its trials under ``tag``;
    ``{future: its job's index}``."""
    return {
        client.submit(
            _run_job,
            jobs[k].config,
            jobs[k].seed,
            str(located[k].path),
            force,
            report=f"{tag}:{k}",
            keep=keep,
            key=f"docking-{jobs[k].config.name}-seed{jobs[k].seed}-{tag}-{k}",
            pure=False,
        ): k
        for k in todo
    }


def _submit_and_follow(
    client, jobs, located, todo, force, bar, trials, runs, computed, keep, alive=None
) -> None:
    """Submit the jobs ``todo`` to ``client`` and move ``bar`` with the trials their workers
    report (:data:`_PROGRESS_TOPIC`) and ``runs`` with the jobs done, until all are done (a
    job's exception is raised here); with ``keep``, each computed run goes into ``computed``
    (by its job's index). ``alive()``: whether any worker still runs (the embedded cluster's,
    which no one restarts); once not, ``RuntimeError``, not a wait for workers that never come."""
    from distributed import wait

    tag = uuid.uuid4().hex[:8]
    reported = dict.fromkeys(todo, 0)  # trials each job has reported so far
    news: list = []  # (job, trials) from the event topic's handler thread
    lock = threading.Lock()

    def heard(event) -> None:
        _, message = event
        name, _, k = str(message.get("tag", "")).partition(":")
        if name == tag and k.isdigit() and int(k) in reported:
            with lock:
                news.append((int(k), int(message.get("trials", 0))))

    def apply_news() -> None:
        with lock:
            found, news[:] = list(news), []
        for k, n in found:
            n = min(n, trials[k] - reported[k])  # never beyond the job's total
            reported[k] += n
            bar.update(n)

    client.subscribe_topic(_PROGRESS_TOPIC, heard)
    # The longest first (by their trials; Dask runs what was submitted first first), so that
    # no worker is left with a long job while the others wait at the end.
    longest = sorted(todo, key=lambda k: -trials[k])
    index = _submit(client, jobs, located, longest, force, keep, tag)
    pending = set(index)
    while pending:
        # Wake every second: trials reported since, and the bar's clock.
        try:
            done, pending = wait(pending, timeout=1.0, return_when="FIRST_COMPLETED")
        except TimeoutError:
            apply_news()
            bar.refresh()
            if alive is not None and not alive():
                raise RuntimeError(
                    f"every Dask worker of the sweep has ended, {len(pending)} of its jobs "
                    "unfinished (the workers' own messages are above)"
                ) from None
            continue
        apply_news()
        for future in done:
            found = future.result()  # re-raises a job's exception here
            k = index[future]
            if keep:
                computed[k] = found
            bar.update(trials[k] - reported[k])  # a loaded run, or unreported trials
            reported[k] = trials[k]
        runs.done([index[future] for future in done])
    client.unsubscribe_topic(_PROGRESS_TOPIC)
