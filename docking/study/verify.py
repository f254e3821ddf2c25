"""Verification by recomputation: ``python -m docking verify``. Recomputes runs of the
committed ledger (:mod:`docking.study.ledger`) in a temporary store, through the sweep, and
compares each one with what the ledger holds of it: its record's content digest (every array
of the run) *and* its results table's row, column by column (the arrays a reader is served).

A digest in the manifest proves nothing against someone who can rewrite the table and
reseal the manifest; a recomputed run does, for the runs recomputed (docs/guide/ledger.md).
"""

from __future__ import annotations

import dataclasses
import hashlib
from pathlib import Path

import numpy as np

from docking.study import paths
from docking.study.ledger import manifest

#: The paper's experiments: every run of theirs is recomputed by every ``verify``.
PAPER_RUNS = ("experiment1", "experiment2")


@dataclasses.dataclass(frozen=True)
class Check:
    """One recomputed run: its name, seed, key, its record's content digest and the
    recomputed one, and the columns of its table row that the recomputed run does not give
    (empty where the row is the run's)."""

    name: str
    seed: int
    key: str
    ledger_digest: str
    digest: str
    columns: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        return self.digest == self.ledger_digest and not self.columns

    def differences(self) -> str:
        """What differs, in words ("" if nothing)."""
        found = []
        if self.digest != self.ledger_digest:
            found.append("its record's content digest")
        if self.columns:
            found.append(f"its table row ({', '.join(self.columns)[:120]})")
        return " and ".join(found)


def _commit() -> str:
    """The checkout's current commit (the source fingerprint outside a git checkout)."""
    import subprocess

    root = paths.checkout_root()
    if root is not None:
        try:
            found = subprocess.run(
                ["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, timeout=10
            )
            if found.returncode == 0 and found.stdout.strip():
                return found.stdout.strip()
        except (OSError, subprocess.SubprocessError):
            pass
    from docking.study.kinds import source_fingerprint

    return source_fingerprint()


#: The kinds of run (:attr:`docking.study.kinds.Runner.name`) whose runs a sample never draws.
UNSAMPLED_RUNNERS = ("ppo",)


def chosen(data: dict, sample: int | None, commit: str, tables=(), runs=()) -> list[str]:
    """The run keys ``verify`` recomputes: every run of :data:`PAPER_RUNS`, plus ``sample``
    others ordered by SHA-256 of the commit and the key (so each commit draws other runs);
    ``sample=None``: every run. Not the runs of :data:`UNSAMPLED_RUNNERS`: the pixel-level
    bound's (PPO) are recomputed by ``--all`` (:func:`verify`), as JAX's compiled CPU code may
    round differently on another CPU family, which a sample on every CI run should not
    hinge on. (The paper's learner's runs are drawn, and those of a learner registered from
    outside the package, :mod:`docking.study.learners`.) ``tables``: every run of these results
    tables instead (PPO's too); ``ValueError`` naming the tables for a name the ledger lacks.
    ``runs``: these ``(configuration, seed)`` runs instead, in their order
    (:func:`named_runs`)."""
    if runs:
        return named_runs(data, runs)
    keys = sorted(data["runs"])
    if tables:
        unknown = sorted(set(tables) - set(data["tables"]))
        if unknown:
            raise ValueError(
                f"the ledger has no table {', '.join(unknown)}; its tables: "
                f"{', '.join(sorted(data['tables']))}"
            )
        return [k for k in keys if data["runs"][k]["name"] in tables]
    if sample is None:
        return keys
    keys = [k for k in keys if data["runs"][k]["runner"] not in UNSAMPLED_RUNNERS]
    paper = [k for k in keys if data["runs"][k]["name"] in PAPER_RUNS]
    others = sorted(
        (k for k in keys if k not in paper),
        key=lambda k: hashlib.sha256(f"{commit}:{k}".encode()).hexdigest(),
    )
    return paper + others[:sample]


def named_runs(data: dict, runs) -> list[str]:
    """The keys, in the ledger whose manifest is ``data``, of the ``(configuration, seed)``
    runs ``runs`` (e.g. a design's cell's, :func:`docking.study.design.cell_runs`), in their
    order, each once; ``ValueError`` naming the runs the ledger does not hold."""
    from docking.study.kinds import config_json
    from docking.study.sweep import seeds_text

    keys, absent, missing = [], {}, 0
    for config, seed in runs:
        key = data["index"].get(f"{config_json(config, compact=False)}:seed{seed}")
        if key is None:
            absent.setdefault(config.name, set()).add(seed)
            missing += 1
        elif key not in keys:
            keys.append(key)
    if absent:
        named = "; ".join(f"{n} seeds {seeds_text(sorted(s))}" for n, s in sorted(absent.items()))
        raise ValueError(
            f"the ledger holds no run of {named[:300]} ({missing} of the {len(runs)} runs "
            "asked for): nothing to verify them against"
        )
    return keys


def platform_lines(mismatch: bool, folder: Path | str | None = None) -> list[str]:
    """The ledger's numeric platform beside this machine's (:mod:`docking.study.platform_info`),
    and, where they differ, what each difference means for a run's bits."""
    from docking.study.platform_info import compare, numeric_platform

    data = manifest(folder) or {}  # default: the ledger of paths.ledger_dir()
    theirs, ours = data.get("platform", {}), numeric_platform()
    lines = ["numeric platform (the ledger's | this machine's):"]
    lines += [f"  {k}: {theirs.get(k, '?')} | {ours.get(k, '?')}" for k in sorted(ours)]
    differences = compare(theirs, ours)
    if not differences:
        lines.append("the platforms are the same.")
    else:
        lines.append("where they differ, and what that means:")
        lines += [f"  {d}" for d in differences]
    if mismatch:
        lines.append(
            "a mismatch on the same code and libraries on x86-64-v3 or newer is a defect: "
            "please report it with these lines"
            if ours.get("architecture") == theirs.get("architecture") == "x86_64"
            else "runs on another architecture are not expected to equal the ledger's bits"
        )
    return lines


def _arrays(job, scratch) -> dict[str, np.ndarray]:
    """The arrays of ``job``'s recomputed run in the store ``scratch``."""
    from docking.study.kinds import result_path

    with np.load(result_path(job.config, job.seed, scratch), allow_pickle=False) as f:
        return {k: f[k] for k in f.files}


def compare(data: dict, keys: list[str], jobs: list, scratch) -> list[Check]:
    """Each recomputed run of ``jobs`` (in the store ``scratch``) against the ledger whose
    manifest is ``data``: its content digest against its record's, its table row (read and
    checked against its record's row digest) against the row the recomputed run gives."""
    from docking.study.kinds import content_digest
    from docking.study.ledger import table_rows
    from docking.study.ledger_rows import row_differences

    rows: dict[str, dict] = {}
    checks = []
    for key, job in zip(keys, jobs, strict=True):
        record = data["runs"][key]
        if record["name"] not in rows:
            rows[record["name"]] = table_rows(data, record["name"])
        arrays = _arrays(job, scratch)
        differ = row_differences(arrays, rows[record["name"]][key])
        digest = content_digest(arrays)
        checks.append(Check(record["name"], job.seed, key, record["digest"], digest, tuple(differ)))
    return checks


def recompute(data: dict, keys: list[str], scheduler, workers, progress, what: str) -> list:
    """Recompute the ledger's runs ``keys`` with this code, in a temporary store (the results
    store is not touched), and compare each with the ledger (:func:`compare`); ``what`` names
    the command on the bar and the temporary folder (``verify``, ``migrate``)."""
    import tempfile

    from docking.study.kinds import runner_named
    from docking.study.sweep import Job, run_jobs

    records = [data["runs"][k] for k in keys]
    jobs = [
        Job(runner_named(record["runner"]).from_dict(record["config"]), record["seed"])
        for record in records
    ]
    with tempfile.TemporaryDirectory(prefix=f"docking-{what}-") as scratch:
        run_jobs(
            jobs,
            scratch,
            scheduler=scheduler,
            workers=workers,
            force=True,
            progress=progress,
            desc=f"{what}: recomputing {len(jobs)} runs",
        )
        return compare(data, keys, jobs, scratch)


def verify(
    sample: int | None = 3,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    folder: Path | str | None = None,
    tables=(),
    runs=(),
) -> list[Check]:
    """Recompute the runs :func:`chosen` picks (in a temporary store; the results store is
    not touched; ``tables``: every run of those tables; ``runs``: these ``(configuration,
    seed)`` runs, e.g. a design's cell's, :func:`docking.study.design.cell_runs`) and compare
    each one with the ledger (:func:`compare`). Returns the checks; the caller decides what a
    mismatch means (the CLI fails)."""
    folder = Path(folder) if folder is not None else paths.ledger_dir()
    data = manifest(folder)
    if data is None:
        raise FileNotFoundError(f"no ledger to verify in {folder}")
    # sample=None (--all): every runner's runs
    keys = chosen(data, sample, _commit(), tables, list(runs))
    return recompute(data, keys, scheduler, workers, progress, what="verify")


def verify_derived(sample: int | None = 1, folder: Path | str | None = None) -> list:
    """Recompute ``sample`` entries (None: every one) of each derived table the ledger keeps,
    of those this code is served (:func:`docking.study.derived.chosen`, drawn from the
    current commit), each from its key alone, and compare them with the ledger bit for bit
    (:class:`docking.study.derived.Recheck` each)."""
    from docking.study import derived

    folder = Path(folder) if folder is not None else paths.ledger_dir()
    data = manifest(folder)
    if data is None:
        raise FileNotFoundError(f"no ledger to verify in {folder}")
    return derived.recheck(data, derived.chosen(data, sample, _commit()))
