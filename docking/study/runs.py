"""One path from a configuration and seed to its run: :func:`locate` answers where the run of
(configuration, seed) is, in the results store, in the committed ledger, or still to compute,
and reads it from where it is.

Every command asks it once per job (``python -m docking run`` and ``sweep``, a design's cells,
the report's check that nothing is missing); the sweep computes what it finds nowhere. The
chain of one job, from the command line to its stored file (docs/guide/layers.md draws it)::

    cli.runs: Run.execute -> _run                the configurations and seeds as jobs
      runs: locate(config, seed)                 once per job, before anything computes
        kinds: run_key, result_path              its key, the file it names
        store: find                              a valid file there: the run   -> "store"
        ledger: read                             else the ledger's entry       -> "ledger"
                                                 else                          -> "computed"
      sweep: sweep(jobs, located)                the jobs found nowhere
        sweep: _run_job (a Dask worker, or here)
          store: compute                         its runner runs it; the file is written

(:func:`docking.study.sweep.run_jobs` and :func:`~docking.study.sweep.sweep` locate the jobs
themselves when no caller has.) So a configuration enters the store once (to read its file, or to
write the file of the run just computed) and the ledger at most once (when the store holds no file
of it), and neither calls the other: both build on :mod:`docking.study.kinds` (the kinds of run, the
keys and the run files). A file in the store that is not a valid run of its key is a warning and the
run is computed again (it replaces the file), as :func:`docking.study.store.run_or_load` does.
"""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

from docking.study import kinds, ledger, store
from docking.study.kinds import CorruptResult, ForeignFile

__all__ = ["PLACES", "Located", "load_run", "locate"]

#: Where a run is: a valid file in the results store, the committed ledger's entry, or
#: neither (it is to be computed).
PLACES = ("store", "ledger", "computed")


@dataclasses.dataclass(frozen=True)
class Located:
    """Where the run of (``config``, ``seed``) is (:func:`locate`).

    Attributes:
      config: The run's configuration.
      seed: Its seed.
      key: Its key under this code (:func:`docking.study.kinds.run_key`).
      path: Its file in the results store (there, or where a computed run is written).
      place: One of :data:`PLACES`.
      run: The run, read from where it is (None where it is to be computed).
      problem: Why a file in the store is not used (it is computed again), or None.
    """

    config: object
    seed: int
    key: str
    path: Path
    place: str
    run: object = None
    problem: str | None = None


def locate(config, seed: int, results_dir: Path | str | None = None, warn: bool = True) -> Located:
    """Where the run of (``config``, ``seed``) is, with the run read from there: a valid file
    in the results store ``results_dir`` (default :func:`docking.study.paths.results_dir`),
    else the committed ledger's entry (whole, or its results table's row), else nowhere
    (``"computed"``: to compute). A file in the store that is not a valid run of its key is a
    warning naming it and the reason (``warn``), and the run is to be computed (it replaces the
    file; :attr:`Located.problem` says why);
    :class:`~docking.study.kinds.ForeignFile` if the file is nothing the store writes, or
    its folder a link out of the store (:func:`docking.study.store.check_inside`: refused
    even where no file is there yet, so that the run is never written through it);
    :class:`~docking.study.ledger.StaleLedger` if the ledger holds the run but was computed by
    other code."""
    key = kinds.run_key(config, seed)
    path = store.check_inside(kinds.result_path(config, seed, results_dir, key=key))
    if path.exists():
        try:
            found = store.find(config, seed, path, key)
        except ForeignFile:
            raise
        except CorruptResult as exc:
            if warn:
                warnings.warn(
                    f"ignoring the stored result {path}: {exc}; recomputing it",
                    RuntimeWarning,
                    stacklevel=2,
                )
            return Located(config, seed, key, path, "computed", problem=str(exc))
        if found is not None:
            return Located(config, seed, key, path, "store", found)
    found = ledger.read(config, seed, key=key)
    if found is not None:
        return Located(config, seed, key, path, "ledger", found)
    kinds.require_extra(config)  # a clear error now, not an ImportError on a worker
    return Located(config, seed, key, path, "computed")


def load_run(config, seed: int, results_dir: Path | str | None = None):
    """The run of (``config``, ``seed``) from the results store, else the ledger, else None
    (:func:`locate`'s run); a file in the store that is not a valid run of its key is a
    :class:`~docking.study.kinds.CorruptResult` here, not a warning (nothing is computed)."""
    found = locate(config, seed, results_dir, warn=False)
    if found.problem is not None:
        raise CorruptResult(f"{found.path}: {found.problem}")
    return found.run
