"""What a sweep (:mod:`docking.study.sweep`) says of its runs while they compute: on a terminal,
the runs done beside its bar of trials; where stderr is not a terminal (a log file, a pipe),
lines: at the start how many runs it computes and about how long, from the committed ledger's
recorded times of similar runs (:func:`estimates`), then one line per run finished
(:class:`Progress`)."""

from __future__ import annotations

import dataclasses
import json
import re
import sys
import time

from docking.study import kinds

__all__ = ["DEFAULT_RUN_SECONDS", "PROGRESS_LINE", "Progress", "estimates"]

#: What a run is taken to last where the ledger records no run of its kind, in seconds.
DEFAULT_RUN_SECONDS = 60.0

#: The lines a sweep writes where stderr is not a terminal (:class:`Progress`): the first
#: (the runs to compute, about how long) and one per run finished.
PROGRESS_LINE = re.compile(r".*: (\d+ of \d+ runs? to compute|run \d+/\d+ done, computed)\b.*")


def duration(seconds: float) -> str:
    """``seconds`` in words: ``45 s``, ``12 min``, ``2.5 h``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 90 * 60:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def world_key(config) -> str:
    """The world of ``config`` as JSON, what :func:`estimates` compares."""
    return json.dumps(dataclasses.asdict(config.world), sort_keys=True)


def recorded_times(names: set[str]) -> dict[tuple[str, str], list[tuple[int, float]]]:
    """``{(kind of run, its world as JSON): [(trials in the run, wall seconds), ...]}`` of the
    ledger's runs of the kinds ``names`` (:func:`docking.study.ledger.manifest` records each
    run's ``wall_seconds``); empty where no ledger is read (switched off, absent, stale)."""
    from docking.study import ledger

    try:
        data = ledger.manifest()
    except (ledger.StaleLedger, kinds.StaleCode, ValueError, OSError):
        data = None  # said where the ledger is read for its runs, if at all
    found: dict[tuple[str, str], list[tuple[int, float]]] = {}
    sizes: dict[int, tuple[int, str] | None] = {}
    for record in (data or {}).get("runs", {}).values():
        name, seconds, d = record.get("runner"), record.get("wall_seconds"), record.get("config")
        if name not in names or not seconds:
            continue
        d = data["configs"].get(d) if isinstance(d, str) else d  # its id, or the dict read
        key = id(d)  # each configuration is one dict of the manifest
        if key not in sizes:
            sizes[key] = None
            try:
                runner = kinds.runner_named(name)
                config = runner.config_type.from_dict(d)
                world = world_key(config)
                sizes[key] = (runner.trials_in_run(config), world)
            except (ValueError, TypeError, KeyError, AttributeError):
                pass  # a configuration this code no longer reads: no estimate from it
        if sizes[key] is not None and sizes[key][0] > 0:
            trials, world = sizes[key]
            found.setdefault((name, world), []).append((trials, float(seconds)))
    return found


def estimates(jobs) -> tuple[list[float], str]:
    """What each of ``jobs`` (:class:`docking.study.sweep.Job` s) is expected to last, in
    seconds, from the ledger's recorded times of similar runs (:func:`recorded_times`): the
    median of the runs of the same kind in the same world with as many trials; else their
    median time per trial (or, in no run of that world, that of the kind's runs in any world)
    times the job's trials; else :data:`DEFAULT_RUN_SECONDS`. And where the estimate comes
    from, in words."""
    import statistics

    runners = [kinds.runner_for(j.config) for j in jobs]
    recorded = recorded_times({r.name for r in runners})
    by_kind: dict[str, list[tuple[int, float]]] = {}
    for (name, _), runs in recorded.items():
        by_kind.setdefault(name, []).extend(runs)
    seconds, basis = [], {"world": 0, "kind": 0, "default": 0}
    for job, runner in zip(jobs, runners, strict=True):
        trials = runner.trials_in_run(job.config)
        same = recorded.get((runner.name, world_key(job.config)), [])
        kind = by_kind.get(runner.name, [])
        exact = [s for t, s in same if t == trials]
        if exact:
            seconds.append(statistics.median(exact))
        elif same or kind:
            seconds.append(statistics.median(s / t for t, s in (same or kind)) * trials)
        else:
            seconds.append(DEFAULT_RUN_SECONDS)
        basis["world" if same else "kind" if kind else "default"] += 1
    words = {
        "world": "the ledger's times of runs of the same kind in the same world",
        "kind": "the ledger's times of runs of the same kind in other worlds",
        "default": f"no recorded run like it: {DEFAULT_RUN_SECONDS:.0f} s a run assumed",
    }
    used = [k for k in words if basis[k]]
    if len(used) == 1:
        return seconds, words[used[0]]
    return seconds, "; ".join(f"{basis[k]} by {words[k]}" for k in used)


class Progress:
    """What a sweep says of its runs. On a terminal: the runs done beside the bar of trials.
    Where stderr is not a terminal (a log file, a pipe), where the bar is quiet: a line
    before the first run computes (how many runs it computes, how many were read, on how many
    workers, and about how long: :func:`estimates`), then a line per run finished (the runs
    done of all, computed, which one, the time elapsed and about how long is left), flushed
    at once. Nothing without ``progress``, or when nothing is computed."""

    def __init__(self, bar, jobs, todo, desc: str, progress: bool):
        self.bar, self.jobs, self.todo, self.desc = bar, jobs, list(todo), desc
        self.total, self.count, self.computed = len(jobs), len(jobs) - len(todo), 0
        self.lines = progress and bool(todo) and bool(getattr(bar, "disable", False))
        self.started = time.monotonic()
        self.done([])

    def say(self, text: str) -> None:
        if self.lines:
            print(f"{self.desc}: {text}", file=sys.stderr, flush=True)

    def start(self, workers: int, where: str) -> None:
        """The first line: the runs to compute ``where`` (on ``workers`` of them)."""
        self.started = time.monotonic()
        if not self.lines:
            return
        seconds, basis = estimates([self.jobs[k] for k in self.todo])
        parallel = max(sum(seconds) / max(workers, 1), max(seconds))
        n, read = len(self.todo), self.total - len(self.todo)
        self.say(
            f"{n} of {self.total} runs to compute"
            + (f" ({read} read from the store or the ledger)" if read else "")
            + f", {where}: "
            + ("under a minute" if parallel < 60 else f"about {duration(parallel)}")
            + f" ({basis})"
        )

    def done(self, ks: list[int]) -> None:
        """The jobs ``ks`` (indices) are finished: computed now."""
        for k in ks:
            self.count += 1
            self.computed += 1
            elapsed = time.monotonic() - self.started
            left = elapsed / self.computed * (len(self.todo) - self.computed)
            job = self.jobs[k]
            self.say(
                f"run {self.count}/{self.total} done, computed ({job.config.name} seed "
                f"{job.seed}); {duration(elapsed)} elapsed"
                + (f", about {duration(left)} left" if left else "")
            )
        self.bar.set_postfix_str(f"runs {self.count}/{self.total}", refresh=True)
