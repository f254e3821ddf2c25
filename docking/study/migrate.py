"""Migration: a change of code that changes no number moves no run
(``python -m docking ledger migrate``).

A run's key names the code that computed it (its runner's source fingerprint,
:mod:`docking.study.store`), so splitting a keyed function, giving a keyed module an input check or
moving it into a folder re-keys every stored run, though every array stays as it was. A
migration re-keys them instead of recomputing them, **only after** showing, for this change,
that the new code computes what the old code did:

1. *Which runs.* The runners whose recorded fingerprint is not this code's (the others are
   left alone).
2. *The battery* (:mod:`docking.study.battery`): short runs of every value of every
   configuration field the ledger holds, every seed, and the learning rules' knobs as the
   ledger combines them, computed by the old code (the commit whose package has the ledger's
   fingerprints) and by this code, compared bit for bit. If any differs, nothing is migrated
   and the field values that every differing case holds (and no equal one) are named.
3. *The sample* (:func:`sample`): runs of those runners chosen to cover every results table,
   every kind of run (the runner, and for the paper's learner the policy, the feature layer
   and the rule, the action set and the pretraining), every world, every value of every
   configuration field and every seed of the ledger, the cheapest first (by their recorded
   wall times).
4. *The proof.* The sample is recomputed by this code in a temporary store, and each run is
   compared with what the ledger holds of it, as ``verify`` compares
   (:func:`docking.study.verify.compare`): its content digest, its table row, column by column.
   If any run differs, nothing is migrated and the runs that differ are named.
5. *The move.* Every run of those runners gets the key this code gives its configuration and
   seed (under the ledger's rendering stack): the records, the tables' ``key`` column, the
   whole runs' files and their meta records. The manifest records the migration
   (:data:`MIGRATION_FIELDS`: the fingerprints from and to, the modules that changed, the
   commit, the runs recomputed with their digests, the runs moved, what the proof covered)
   and seals it with the rest.

A results store (a user's ``results/``) is migrated by the same proof
(:func:`migrate_store`): a stored run whose key was made with a fingerprint a recorded
migration moved from is re-keyed, along the chain of migrations, to this code's key, if every
migration of that chain recomputed its seed and every value of its configuration's fields
(:func:`covered_by`); any other run is left as it is (recomputed when asked for, as before).

What the proof covers, and what it does not: it shows that the runs it recomputed and the
battery's short runs are the same under both codes, on this machine; that the others are is an
inference from them covering every value of every field, every seed, and the knobs'
combinations the ledger holds. A change that alters numbers only in a combination of values
that neither reaches, or only after more trials than a short run has, would pass. ``verify``
keeps sampling other runs at every commit.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
from pathlib import Path

import numpy as np

from docking.fileio import atomic_write, read_regular
from docking.study import kinds, ledger, ledger_rows, paths, store

__all__ = ["Migration", "MIGRATION_FIELDS", "migrate", "migrate_store", "sample"]

#: What a migration record of the manifest holds.
MIGRATION_FIELDS = (
    "from",  # {runner: the fingerprint its runs had}
    "to",  # {runner: this code's}
    "changed",  # {runner: the modules (and assets, libraries) whose digests differ}
    "commit",  # the checkout's commit (the code that recomputed the sample)
    "utc",  # when
    "recomputed",  # [{name, seed, key (new), digest}] the sample, equal to the ledger
    "moved",  # {runner: how many runs were re-keyed}
    "covered",  # what the proof covered: the battery's cases, fields and seeds, the sample's
)


@dataclasses.dataclass(frozen=True)
class Migration:
    """What :func:`migrate` did: ``record`` (the manifest's new migration record, or None if
    there was nothing to migrate or a run differed), ``differ`` (the sampled runs that the
    new code computes otherwise: ``(name, seed, what differs)``), ``store`` (the store's
    counts, :func:`migrate_store`), ``refused`` (the battery's lines where its short runs
    differ: the field values that differ), ``dropped`` (the ledger's derived tables removed:
    an entry's key holds the keys of the runs it read, so a re-keyed run leaves it a key no
    reader asks for; ``python -m docking ledger derive`` writes them again once computed)."""

    record: dict | None
    differ: tuple[tuple[str, int, str], ...] = ()
    store: dict | None = None
    refused: tuple[str, ...] = ()
    dropped: tuple[str, ...] = ()


# ------------------------------------------------------------------------------------------
# The sample.
# ------------------------------------------------------------------------------------------


def _kind(record: dict) -> str:
    """The kind of a run, as the sample covers kinds: its runner, and for the paper's learner
    what decides which code paths it takes."""
    config = record["config"]
    if record["runner"] != "learner":
        return record["runner"]
    network = config.get("network", {})
    world = config.get("world", {})
    parts = (
        config.get("policy"),
        network.get("feature_layer"),
        network.get("rule"),
        world.get("actions"),
        bool(config.get("pretrain_trials")),
        network.get("eps_w") == 0,
    )
    return "learner " + json.dumps(parts)


def _features(record: dict) -> set[tuple]:
    """What a run covers: its table, its kind, its world (per runner), the value of each of
    its configuration's fields (per runner) and its seed."""
    from docking.study.battery import flat

    world = json.dumps(record["config"].get("world"), sort_keys=True)
    fields = flat(record["config"]).items()
    return {
        ("table", record["name"], record["runner"]),
        ("kind", _kind(record)),
        ("world", record["runner"], world),
        ("seed", record["seed"]),
        *(("field", record["runner"], path, value) for path, value in fields),
    }


def sample(data: dict, runners) -> list[str]:
    """The keys of the runs of ``runners`` that cover every table, kind, world, field value
    and seed they have in the ledger ``data`` (:func:`_features`): greedy set cover, each step
    the run with the most features not yet covered per second of its recorded wall time
    (ties: the key), in key order."""
    candidates = {k: r for k, r in data["runs"].items() if r["runner"] in runners}
    features = {k: _features(r) for k, r in candidates.items()}
    left = set().union(*features.values()) if features else set()
    chosen = []
    while left:
        key = max(
            sorted(features),
            key=lambda k: len(features[k] & left) / (candidates[k]["wall_seconds"] + 1.0),
        )
        chosen.append(key)
        left -= features[key]
    return sorted(chosen)


# ------------------------------------------------------------------------------------------
# The ledger.
# ------------------------------------------------------------------------------------------


def _changed(data: dict) -> dict[str, kinds.Runner]:
    """The runners of the ledger ``data`` whose recorded fingerprint is not this code's."""
    found = {}
    for name, fingerprint in sorted(data["fingerprints"].items()):
        runner = kinds.runner_named(name)
        if runner.fingerprint() != fingerprint:
            found[name] = runner
    return found


def _prove(data: dict, keys: list[str], scheduler, workers, progress) -> list:
    """Recompute the runs ``keys`` with this code and compare them with the ledger
    (:func:`docking.study.verify.compare`): the checks."""
    from docking.study.verify import recompute

    return recompute(data, keys, scheduler, workers, progress, what="migrate")


def _new_keys(data: dict, changed) -> dict[str, str]:
    """``{key: its key under this code}`` of every run (unchanged for the other runners)."""
    found, by_config = {}, {}
    for key, record in data["runs"].items():
        if record["runner"] not in changed:
            found[key] = key
            continue
        text = json.dumps(record["config"], sort_keys=True)
        if text not in by_config:
            config = changed[record["runner"]].from_dict(record["config"])
            by_config[text] = kinds.config_key(config, data["rendering_stack"])
        found[key] = f"{by_config[text]}:seed{record['seed']}"
    if len(set(found.values())) != len(found):
        raise ValueError("two runs of the ledger would have one key under this code")
    return found


def _whole_file(raw: bytes, key: str) -> bytes:
    """A whole run's file ``raw`` with its meta record's key replaced by ``key`` (its arrays,
    and so its content digest, unchanged)."""
    with np.load(io.BytesIO(raw), allow_pickle=False) as found:
        arrays = {k: found[k] for k in found.files}
    meta = json.loads(str(arrays["meta"]))
    meta["key"] = key
    arrays["meta"] = np.array(json.dumps(meta))
    return ledger_rows.npz(arrays)


def _rekeyed(data: dict, keys: dict[str, str]) -> tuple[dict, dict]:
    """``(files, records)`` of the ledger ``data`` with every run under its new key: every
    table and whole file (the tables' rows and the whole runs' arrays unchanged)."""
    folder, files, records = data["folder"], {}, {}
    for name in sorted(data["tables"]):
        rows = ledger.table_rows(data, name)  # each row checked against its record
        moved = sorted((keys[k], cells) for k, cells in rows.items())
        files[f"tables/{name}.npz"] = ledger_rows.npz(ledger_rows.columns(moved))
    for key, record in data["runs"].items():
        new = dict(record, config=ledger._config_ref(record["config"]))
        if record.get("whole"):
            raw = ledger._verified(folder / record["whole"], record["sha256"], folder)
            seed = record["seed"]
            new["whole"] = path = f"whole/{record['name']}/{keys[key][:16]}/seed{seed}.npz"
            files[path] = _whole_file(raw, keys[key])
            new["sha256"] = hashlib.sha256(files[path]).hexdigest()
        records[keys[key]] = new
    return files, records


def migrate(
    folder: Path | str | None = None,
    results_dir: Path | str | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    commit: str | None = None,
    old: str | None = None,
) -> Migration:
    """Migrate the ledger in ``folder`` (default :func:`docking.study.paths.ledger_dir`) to this
    code, as the module docstring says, then the results store ``results_dir`` (default
    :func:`docking.study.paths.results_dir`; ``False``: none). ``old``: the commit (or a folder
    holding the ``docking`` package) of the code that computed the ledger, for the battery
    (default: found in the checkout's history). Returns what was done; nothing is written if a
    battery case or a sampled run differs."""
    folder = Path(folder) if folder is not None else paths.ledger_dir()
    if folder is None:
        raise ValueError("no ledger folder: DOCKING_LEDGER is off and no folder was given")
    data = ledger._stored_manifest(Path(folder))
    if data is None:
        raise FileNotFoundError(f"no ledger in {folder} (it has no manifest.json)")
    changed = _changed(data)
    record = None
    if changed:
        from docking.study import battery

        refused, covered = battery.prove(data, changed, old, progress)
        if refused:
            return Migration(None, refused=tuple(refused))
        keys = sample(data, changed)
        checks = _prove(data, keys, scheduler, workers, progress)
        differ = tuple((c.name, c.seed, c.differences()) for c in checks if not c.ok)
        if differ:
            return Migration(None, differ)
        covered["sample"] = _sample_coverage(data, keys)
        record = _write(data, changed, checks, commit, covered)
    moved = None if results_dir is False else migrate_store(results_dir, folder)
    dropped = tuple(sorted(data.get("derived", {}))) if record is not None else ()
    return Migration(record, (), moved, dropped=dropped)


def _sample_coverage(data: dict, keys: list[str]) -> dict:
    """What the sample covered: its runs, and per kind of run the fields and seeds; with, for
    :func:`migrate_store`, every value of every field (``values``: ``{runner: {field path:
    [canonical JSON of each value]}}``) and every seed (``seed_list``) that it recomputed."""
    features = set().union(*(_features(data["runs"][k]) for k in keys)) if keys else set()
    fields: dict[str, dict[str, int]] = {}
    values: dict[str, dict[str, set]] = {}
    for f in features:
        if f[0] == "field":
            counts = fields.setdefault(f[1], {})
            counts[f[2]] = counts.get(f[2], 0) + 1
            values.setdefault(f[1], {}).setdefault(f[2], set()).add(f[3])
    seeds = sorted(f[1] for f in features if f[0] == "seed")
    return {
        "runs": len(keys),
        "tables": len({f[1] for f in features if f[0] == "table"}),
        "seeds": len(seeds),
        "fields": {r: dict(sorted(v.items())) for r, v in sorted(fields.items())},
        "values": {
            r: {path: sorted(v) for path, v in sorted(by.items())}
            for r, by in sorted(values.items())
        },
        "seed_list": seeds,
    }


def _write(data: dict, changed: dict, checks, commit: str | None, covered: dict) -> dict:
    """Re-key the ledger ``data`` (its runners ``changed`` proven by ``checks``) and record
    the migration; the record."""
    from docking.study.verify import _commit

    keys = _new_keys(data, changed)
    files, records = _rekeyed(data, keys)
    configs = {ledger._config_ref(r["config"]): r["config"] for r in data["runs"].values()}
    runners = {name: kinds.runner_named(name) for name in data["fingerprints"]}
    migration = {
        "from": {n: data["fingerprints"][n] for n in changed},
        "to": {n: r.fingerprint() for n, r in changed.items()},
        "changed": {n: _modules_changed(data, r) for n, r in changed.items()},
        "commit": commit or _commit(),
        "utc": kinds.computed_utc(),
        "recomputed": [
            {"name": c.name, "seed": c.seed, "key": keys[c.key], "digest": c.digest} for c in checks
        ],
        "moved": {n: sum(r["runner"] == n for r in records.values()) for n in changed},
        "covered": covered,
    }
    migrations = [*data.get("migrations", []), migration]
    manifest = ledger._manifest(files, records, runners, configs, data["platform"], migrations)
    manifest["rendering_stack"] = data["rendering_stack"]  # the runs' stack, not this machine's
    if "table_platforms" in data:
        manifest["table_platforms"] = data["table_platforms"]
    folder = data["folder"]
    ledger._replace_files(folder, files)
    text = json.dumps(manifest, indent=1, sort_keys=True) + "\n"
    atomic_write(folder / "manifest.json", lambda f: f.write(text.encode()))
    for name in data.get("derived", {}):  # keyed by the old runs' keys: none is asked for now
        (folder / "derived" / f"{name}.npz").unlink(missing_ok=True)
    ledger._read_manifest.cache_clear()
    ledger._table.cache_clear()
    ledger.check_files(folder)  # the migrated ledger, every check
    return migration


def _modules_changed(data: dict, runner) -> list[str]:
    ours, theirs = runner.module_digests(), data["modules"].get(runner.name, {})
    return sorted(k for k in set(ours) | set(theirs) if ours.get(k) != theirs.get(k))


# ------------------------------------------------------------------------------------------
# A results store.
# ------------------------------------------------------------------------------------------


def _chains(migrations: list) -> dict[str, dict[str, str]]:
    """``{runner: {a fingerprint migrated from: the one it was migrated to}}``."""
    found: dict[str, dict[str, str]] = {}
    for m in migrations:
        for name, before in m["from"].items():
            found.setdefault(name, {})[before] = m["to"][name]
    return found


def _proofs(migrations: list) -> dict[str, dict[str, dict | None]]:
    """``{runner: {a fingerprint migrated from: what that migration's sample recomputed of
    that runner (its field values and seeds), or None if its record does not say}}``."""
    found: dict[str, dict[str, dict | None]] = {}
    for m in migrations:
        sample = (m.get("covered") or {}).get("sample") or {}
        for name, before in m["from"].items():
            values = (sample.get("values") or {}).get(name)
            seeds = sample.get("seed_list")
            proof = None if values is None or seeds is None else {"values": values, "seeds": seeds}
            found.setdefault(name, {})[before] = proof
    return found


def covered_by(proof: dict | None, config: dict, seed: int) -> bool:
    """Whether a migration's proof (:func:`_proofs`) recomputed this run's seed and every value
    of its configuration's fields (``config``: the run's configuration as a dict), so that
    what it showed equal covers the run. A store run it does not cover is not moved: the
    laundering a proof over the ledger's runs cannot see is a change that alters only a seed
    or a field value the ledger never holds."""
    from docking.study.battery import flat

    if proof is None or seed not in proof["seeds"]:
        return False
    values = proof["values"]
    return all(value in values.get(path, ()) for path, value in flat(config).items())


def migrate_store(results_dir=None, folder=None) -> dict[str, int]:
    """Re-key the runs of the results store ``results_dir`` whose key was made with a
    fingerprint that the ledger in ``folder`` records a migration from, along the chain of
    its migrations, when it ends at this code's fingerprint and each of them recomputed the
    run's seed and field values (:func:`covered_by`). Returns ``{"moved", "current",
    "left"}``: runs re-keyed, runs keyed by this code already, runs left as they are (other
    code, no proven migration, a seed or value no proof recomputed, or a file that is not a
    valid run)."""
    root = Path(results_dir) if results_dir is not None else paths.results_dir()
    data = ledger._stored_manifest(Path(folder) if folder is not None else paths.ledger_dir())
    migrations = data.get("migrations", []) if data else []
    chains, proofs = _chains(migrations), _proofs(migrations)
    counts = {"moved": 0, "current": 0, "left": 0}
    for path in sorted(root.glob("*/*/seed*.npz")) if root.is_dir() else ():
        try:
            store.check_inside(path, root)
        except kinds.ForeignFile:  # a folder linked out of the store: neither read nor moved
            counts["left"] += 1
            continue
        counts[_migrate_file(path, root, chains, proofs)] += 1
    return counts


def _migrate_file(path: Path, root: Path, chains: dict, proofs: dict) -> str:
    """Migrate one stored run (:func:`migrate_store`): ``"moved"``, ``"current"`` or
    ``"left"`` (also when a migration of its chain did not recompute its seed and every
    value of its fields: :func:`covered_by`)."""
    try:
        raw = read_regular(path, kinds.RESULT_LIMIT, path.parent)
        with np.load(io.BytesIO(raw), allow_pickle=False) as found:
            arrays = {k: found[k] for k in found.files}
        meta = json.loads(str(arrays["meta"]))
        runner = kinds.runner_named(meta.get("runner", "learner"))
        config, seed = runner.from_dict(meta["config"]), int(meta["seed"])
        if meta["key"] == kinds.run_key(config, seed):
            return "current"
        now, chain = runner.fingerprint(), chains.get(runner.name, {})
        for before in chain:
            if meta["key"] != kinds.run_key(config, seed, source=before):
                continue
            kinds.load_result(path, meta["key"], source=before)  # valid: arrays and digest
            fingerprint, seen = before, set()
            while fingerprint in chain and fingerprint not in seen:
                if not covered_by(proofs[runner.name][fingerprint], meta["config"], seed):
                    return "left"
                seen.add(fingerprint)
                fingerprint = chain[fingerprint]
            if fingerprint != now:
                return "left"
            _move(path, arrays, meta, config, seed, root)
            return "moved"
    except (OSError, ValueError, KeyError, TypeError, kinds.CorruptResult):
        return "left"
    return "left"


def _move(path: Path, arrays: dict, meta: dict, config, seed: int, root: Path) -> None:
    """Write the stored run ``arrays`` under this code's key and remove the old file (and
    its folder once it holds no run)."""
    meta["key"] = kinds.run_key(config, seed)
    arrays["meta"] = np.array(json.dumps(meta))
    target = kinds.result_path(config, seed, root)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    atomic_write(target, lambda f: f.write(buffer.getvalue()))
    config_json = target.parent / "config.json"
    if not config_json.exists():
        text = json.dumps(meta["config"], indent=2, sort_keys=True) + "\n"
        atomic_write(config_json, lambda f: f.write(text.encode()))
    kinds.load_result(target, meta["key"])  # the moved file is a valid run of its new key
    path.unlink()
    if not any(path.parent.glob("seed*.npz")):
        for left in path.parent.iterdir():
            if left.name == "config.json":
                left.unlink()
        if not any(path.parent.iterdir()):
            path.parent.rmdir()
