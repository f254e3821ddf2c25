"""Arrays computed from runs (not runs themselves) that a reader is served: kept in the results
store (:func:`docking.study.store.derived`) and, for the names in :data:`COMMITTED`, in the
committed ledger too, so that a fresh clone reads them instead of computing them again.

A derived entry is keyed as a run is, by the text of everything it depends on: the keys of
the runs it reads (configuration, the code's fingerprint, the rendering stack, seed), its own
arguments and the SHA-256 of the modules that compute it outside the runs' code. Its key is
*self-describing*: :data:`RECIPES` recompute an entry from its key alone, which is how
``python -m docking verify`` proves a sample of the ledger's entries (a seal refuses an edit;
a forger can reseal, not make this code compute the forged number).

Where an entry comes from (:func:`derived`): the results store, else the committed ledger's
derived table of that name (its file checked against its sealed digest, its key against the
key asked for), else it is computed and stored. ``python -m docking ledger derive`` writes
the store's entries of :data:`COMMITTED` whose runs the ledger holds into the ledger
(:func:`commit`).
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Callable
from pathlib import Path

import numpy as np

from docking.study import analysis, kinds, ledger, paths, store

__all__ = [
    "COMMITTED",
    "RECIPES",
    "Recheck",
    "chosen",
    "commit",
    "derived",
    "oracle_labelled_success",
    "recheck",
    "served",
]

#: The derived names the ledger keeps (small arrays a notebook reads whole; each has a
#: recipe): the oracle-labelled success of notebook 08's decomposition (500 held-out trials
#: per run, about four minutes of one process in all).
COMMITTED = ("oracle-labelled-success",)


def derived(
    name: str,
    key: str,
    compute: Callable[[], dict[str, np.ndarray]],
    results_dir=None,
    code: tuple = (),
) -> dict[str, np.ndarray]:
    """:func:`docking.study.store.derived`, asking the committed ledger (for a name of
    :data:`COMMITTED`) before computing: the arrays of the entry whose whole key is this
    key, from the derived table checked against its sealed digest."""

    def from_ledger(whole: str) -> dict[str, np.ndarray] | None:
        return _from_ledger(name, whole) if name in COMMITTED else None

    return store.derived(name, key, compute, results_dir, code=code, elsewhere=from_ledger)


def _from_ledger(name: str, whole: str) -> dict[str, np.ndarray] | None:
    data = ledger.manifest()
    found = ledger.derived_table(data, name) if data is not None else None
    if found is None:
        return None
    index, table = found
    row = index.get(whole)
    if row is None:
        return None
    return {f: np.array(table[f][row]) for f in table if f != "key"}


# ------------------------------------------------------------------------------------------
# The derived entries.
# ------------------------------------------------------------------------------------------


def _oracle_code() -> tuple:
    """What computes an oracle-labelled success outside the runs' code (the labelled views,
    the labelled network, its held-out trials), as the module holds them now: keyed by their
    sources, so that an edit elsewhere in analysis.py leaves the committed entries served."""
    return (
        analysis.oracle_views,
        analysis.winners,
        analysis.oracle_labelled,
        analysis.oracle_labelled_success,
    )


def _oracle_key(run, n_trials: int, seed: int) -> str:
    return (
        f"oracle_labelled_success\nrun {kinds.run_key(run.config, run.seed)}"
        f"\nviews oracle_views of the run's world\nn_trials {n_trials}\nseed {seed}"
    )


def oracle_labelled_success(
    run, n_trials: int = 300, seed: int = 0, views: analysis.OracleViews | None = None
) -> float:
    """:func:`docking.study.analysis.oracle_labelled_success` of ``run`` (its held-out trials
    with its W and the oracle-labelled Q) on the labelled views
    ``analysis.oracle_views(run.config.world, n_trials, seed)`` (``views``: those, if the
    caller has them), from the store or the ledger, else computed (:func:`derived`)."""

    def compute():
        labelled = (
            views if views is not None else analysis.oracle_views(run.config.world, n_trials, seed)
        )
        return {"success": np.array(analysis.oracle_labelled_success(run, labelled))}

    key = _oracle_key(run, n_trials, seed)
    return float(derived("oracle-labelled-success", key, compute, code=_oracle_code())["success"])


def _recompute_oracle(key: str, lines: dict[str, str]) -> dict[str, np.ndarray]:
    from docking.study.runs import load_run

    run = load_run(*_run_of(lines["run"]))
    n_trials, seed = int(lines["n_trials"]), int(lines["seed"])
    if store.derived_key(_oracle_key(run, n_trials, seed), _oracle_code()) != key:
        raise ValueError("its key is not the key this code gives what it names")
    labelled = analysis.oracle_views(run.config.world, n_trials, seed)
    return {"success": np.array(analysis.oracle_labelled_success(run, labelled))}


#: ``{name: recompute(whole key, its lines) -> arrays}``: each committed entry recomputed
#: from its key alone (``verify`` uses them).
RECIPES: dict[str, Callable[[str, dict], dict[str, np.ndarray]]] = {
    "oracle-labelled-success": _recompute_oracle,
}


def _lines(key: str) -> dict[str, str]:
    """A key's lines after its first (the computation's name), by their first word (of
    several ``code`` lines, the last; :func:`_current_code` reads them all)."""
    found = {}
    for line in key.split("\n")[1:]:
        word, _, rest = line.partition(" ")
        found[word] = rest
    return found


def _current_code(key: str) -> bool:
    """Whether every ``code`` line of ``key`` is the line of the module or function it names
    as it is now (:func:`docking.study.store.code_line`; a name that is no longer there:
    not)."""
    import importlib

    for line in key.split("\n"):
        if line.startswith("code "):
            name = line.split(" ")[1]
            module, _, attribute = name, "", ""
            while True:
                try:
                    item = importlib.import_module(module)
                    break
                except ImportError:
                    if "." not in module:
                        return False
                    module, _, rest = module.rpartition(".")
                    attribute = f"{rest}.{attribute}" if attribute else rest
            try:
                for part in filter(None, attribute.split(".")):
                    item = getattr(item, part)
            except AttributeError:
                return False
            if store.code_line(item) != line:
                return False
    return True


def _run_of(key: str) -> tuple:
    """The configuration and seed of the ledger's run ``key`` (``KeyError`` if it holds none)."""
    data = ledger.manifest()
    record = data["runs"][key] if data is not None else None
    if record is None:
        raise KeyError(f"the ledger holds no run {key[:16]}")
    return kinds.runner_named(record["runner"]).from_dict(record["config"]), record["seed"]


def commit(folder: Path | str | None = None, results_dir=None) -> dict[str, int]:
    """Write into the ledger in ``folder`` the results store's derived entries of each name
    of :data:`COMMITTED` whose every run the ledger holds and whose code is this code's,
    beside (and replacing, key for key) the entries its derived table holds already;
    ``{name: entries written}``."""
    folder = Path(folder) if folder is not None else paths.ledger_dir()
    data = ledger.manifest(folder)
    if data is None:
        raise ValueError(f"no ledger in {folder} (it has no manifest.json)")
    written = {}
    for name in COMMITTED:
        entries = {}
        found = ledger.derived_table(data, name)
        if found is not None:
            index, table = found
            entries = {k: {f: table[f][r] for f in table if f != "key"} for k, r in index.items()}
        for key, arrays in store.derived_entries(name, results_dir).items():
            runs = [line[4:] for line in key.split("\n") if line.startswith("run ")]
            if runs and all(r in data["runs"] for r in runs) and _current_code(key):
                entries[key] = arrays
        if entries:
            data = ledger.write_derived(folder, name, entries)
            written[name] = len(entries)
    return written


@dataclasses.dataclass(frozen=True)
class Recheck:
    """One committed derived entry recomputed by ``verify``: its name, the run it reads
    (table name and seed), and whether the recomputed arrays equal the ledger's."""

    name: str
    run: str
    seed: int
    equal: bool


def served(data: dict, name: str) -> list[str]:
    """The whole keys of the derived table ``name`` of the ledger whose manifest is ``data``
    that this code can be served: every run they name in the ledger, their code this code
    (an entry keyed by other code is never asked for)."""
    index, _ = ledger.derived_table(data, name)
    return [
        k
        for k in sorted(index)
        if all(line[4:] in data["runs"] for line in k.split("\n") if line.startswith("run "))
        and _current_code(k)
    ]


def chosen(data: dict, sample: int | None, commit_id: str) -> list[tuple[str, str]]:
    """``(name, whole key)`` of ``sample`` entries (None: all) per derived table of the
    ledger whose manifest is ``data``, of those this code can be served (:func:`served`),
    ordered by SHA-256 of the commit and the key (as ``verify`` draws runs,
    :func:`docking.study.verify.chosen`)."""
    picked = []
    for name in sorted(data.get("derived", {})):
        order = sorted(
            served(data, name),
            key=lambda k: hashlib.sha256(f"{commit_id}:{k}".encode()).hexdigest(),
        )
        picked += [(name, k) for k in (order if sample is None else order[:sample])]
    return picked


def recheck(data: dict, picked: list[tuple[str, str]]) -> list[Recheck]:
    """Recompute each entry of ``picked`` (:func:`chosen`) from its key (:data:`RECIPES`) and
    compare it with the ledger's arrays, bit for bit."""
    checks = []
    for name, key in picked:
        if name not in RECIPES:
            raise ValueError(f"the ledger's derived table {name!r} has no recipe in this code")
        index, table = ledger.derived_table(data, name)
        lines = _lines(key)
        again = RECIPES[name](key, lines)
        held = {f: np.asarray(table[f][index[key]]) for f in table if f != "key"}
        equal = sorted(again) == sorted(held) and all(
            np.array_equal(np.asarray(again[f]), held[f]) for f in held
        )
        record = data["runs"][lines["run"]]
        checks.append(Recheck(name, record["name"], record["seed"], equal))
    return checks
