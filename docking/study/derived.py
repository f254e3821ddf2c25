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
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from docking.study import analysis, kinds, ledger, paths, store
from docking.study.arrays import OracleViews

__all__ = [
    "COMMITTED",
    "RECIPES",
    "Recheck",
    "chosen",
    "commit",
    "derived",
    "feature_fidelity",
    "oracle_labelled_success",
    "recheck",
    "served",
]

#: The derived names the ledger keeps (a number per run; each has a recipe): the
#: oracle-labelled success of notebook 08's decomposition (500 held-out trials per run, about
#: three minutes of one process in all) and the feature fidelity the third edition's claims
#: judge (1500 rendered start views read per network, several seconds of every cold report).
COMMITTED = ("oracle-labelled-success", "feature-fidelity")


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
    run, n_trials: int = 300, seed: int = 0, views: OracleViews | None = None
) -> float:
    """:func:`docking.study.analysis.oracle_labelled_success` of ``run`` (its held-out trials
    with its W and the oracle-labelled Q) on the labelled views
    ``analysis.oracle_views(run.config.world, n_trials, seed)`` (``views``: those, if the
    caller has them), from the store or the ledger, else computed (:func:`derived`)."""

    key = _oracle_key(run, n_trials, seed)
    found = derived(
        "oracle-labelled-success",
        key,
        lambda: _oracle(run, n_trials, seed, views),
        code=_oracle_code(),
    )
    return float(found["success"])


def _oracle(run, n_trials: int, seed: int, views=None) -> dict[str, np.ndarray]:
    if views is None:
        views = analysis.oracle_views(run.config.world, n_trials, seed)
    return {"success": np.array(analysis.oracle_labelled_success(run, views))}


def _oracle_recipe(lines: dict[str, str], data: dict, results_dir=None) -> tuple[str, Callable]:
    from docking.study.runs import load_run

    run = load_run(*_run_of(lines["run"], data), results_dir)
    n_trials, seed = int(lines["n_trials"]), int(lines["seed"])
    key = store.derived_key(_oracle_key(run, n_trials, seed), _oracle_code())
    return key, lambda: _oracle(run, n_trials, seed)


def _fidelity_code() -> tuple:
    """What computes a feature fidelity outside the runs' code, as the module holds it now."""
    return (analysis.start_views, analysis.mean_winning_inputs, analysis.feature_fidelity)


def _fidelity_key(run, world, frozen: bool, views: int, min_views: int) -> str:
    return (
        f"feature_fidelity\nrun {kinds.run_key(run.config, run.seed)}"
        f"\nnetwork {'initial' if frozen else 'trained'}"
        f"\nworld {json.dumps(dataclasses.asdict(world), sort_keys=True)}"
        f"\nviews {views}\nseed 0\nmin_views {min_views}"
        f"\nworld_code {kinds.LEARNER.fingerprint()}"
    )


def _fidelity(run, world, frozen: bool, views: int, min_views: int) -> dict[str, np.ndarray]:
    from docking.experiments import initial_network

    network = initial_network(run.config, run.seed) if frozen else run.network
    inputs = analysis.mean_winning_inputs(network, world, n=views, seed=0)
    return {"fidelity": np.array(analysis.feature_fidelity(network, inputs, min_views))}


def feature_fidelity(run, world, views: int, min_views: int) -> float:
    """:func:`docking.study.analysis.feature_fidelity` of ``run``'s network (its W as
    trained; its random start if it trained with W frozen, ``eps_w == 0``) on the mean of
    ``views`` start views of ``world`` that each unit wins (units that win at least
    ``min_views``), from the store or the ledger, else computed (:func:`derived`)."""
    frozen = run.config.network.eps_w == 0
    key = _fidelity_key(run, world, frozen, views, min_views)
    found = derived(
        "feature-fidelity",
        key,
        lambda: _fidelity(run, world, frozen, views, min_views),
        code=_fidelity_code(),
    )
    return float(found["fidelity"])


def _fidelity_recipe(lines: dict[str, str], data: dict, results_dir=None) -> tuple[str, Callable]:
    from docking.experiments import ExperimentConfig
    from docking.study.runs import load_run

    run = load_run(*_run_of(lines["run"], data), results_dir)
    world = ExperimentConfig.from_dict(
        {**run.config.to_dict(), "world": json.loads(lines["world"])}
    ).world
    frozen = lines["network"] == "initial"
    views, min_views = int(lines["views"]), int(lines["min_views"])
    key = _fidelity_key(run, world, frozen, views, min_views)
    return store.derived_key(key, _fidelity_code()), lambda: _fidelity(
        run, world, frozen, views, min_views
    )


#: ``{name: recipe(the key's lines, the ledger's manifest, results store) -> (the key this
#: code gives what they name, compute)}``: each committed entry rebuilt from its key alone
#: (its runs read from the store, else the ledger). An entry is served only where its key is
#: the rebuilt key (:func:`served`), and ``verify`` recomputes it with ``compute()``.
RECIPES: dict[str, Callable[..., tuple[str, Callable[[], dict[str, np.ndarray]]]]] = {
    "oracle-labelled-success": _oracle_recipe,
    "feature-fidelity": _fidelity_recipe,
}


def _current(name: str, key: str, data: dict, results_dir=None) -> bool:
    """Whether ``key`` is the key :data:`RECIPES` rebuild for the entry of ``name`` it
    describes (not where its runs are not in the ledger, its lines are not a key of that
    recipe, or its code is not this code): an entry this code is served."""
    try:
        return RECIPES[name](_lines(key), data, results_dir)[0] == key
    except (KeyError, ValueError, TypeError):  # json.JSONDecodeError is a ValueError
        return False


def _lines(key: str) -> dict[str, str]:
    """A key's lines after its first (the computation's name), by their first word (the
    recipes read their own lines, not the ``code`` lines: they rebuild those)."""
    found = {}
    for line in key.split("\n")[1:]:
        word, _, rest = line.partition(" ")
        found[word] = rest
    return found


def _run_of(key: str, data: dict) -> tuple:
    """The configuration and seed of the run ``key`` of the ledger whose manifest is ``data``
    (``KeyError`` if it holds none)."""
    record = data["runs"][key]
    return kinds.runner_named(record["runner"]).from_dict(record["config"]), record["seed"]


def commit(folder: Path | str | None = None, results_dir=None) -> dict[str, int]:
    """Write into the ledger in ``folder`` the results store's derived entries of each name
    of :data:`COMMITTED` whose every run the ledger holds and whose code is this code's,
    beside (and replacing, key for key) the entries its derived table holds already that
    this code is still served (:func:`served`; the others are dropped);
    ``{name: entries written}``."""
    folder = Path(folder) if folder is not None else paths.ledger_dir()
    data = ledger.manifest(folder)
    if data is None:
        raise ValueError(f"no ledger in {folder} (it has no manifest.json)")
    written = {}
    for name in COMMITTED:
        entries = {}
        found = ledger.derived_table(data, name)
        if found is not None:  # those this code is still served
            index, table = found
            entries = {
                k: {f: table[f][index[k]] for f in table if f != "key"}
                for k in served(data, name, results_dir)
            }
        for key, arrays in store.derived_entries(name, results_dir).items():
            if _current(name, key, data, results_dir):
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


def served(data: dict, name: str, results_dir=None) -> list[str]:
    """The whole keys of the derived table ``name`` of the ledger whose manifest is ``data``
    that this code is served: each the key its recipe rebuilds from the entry's lines (its
    runs in the ledger, its code this code; any other entry is never asked for)."""
    index, _ = ledger.derived_table(data, name)
    return [key for key in sorted(index) if _current(name, key, data, results_dir)]


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
        rebuilt, compute = RECIPES[name](lines, data)
        if rebuilt != key:
            raise ValueError(f"the derived entry {key[:60]!r} is not keyed by this code")
        again = compute()
        held = {f: np.asarray(table[f][index[key]]) for f in table if f != "key"}
        equal = sorted(again) == sorted(held) and all(
            np.array_equal(np.asarray(again[f]), held[f], equal_nan=True) for f in held
        )
        record = data["runs"][lines["run"]]
        checks.append(Recheck(name, record["name"], record["seed"], equal))
    return checks
