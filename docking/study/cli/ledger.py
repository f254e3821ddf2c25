"""``ledger``, ``verify`` and ``benchmark``: the committed ledger written, shown or migrated,
verified by recomputation, and the environment's speed measured (the benchmark beside the
package, ``benchmarks/env_speed.py``, run without importing the command line).
"""

from __future__ import annotations

import collections
import dataclasses
import json
import os
import sys
from pathlib import Path
from typing import Annotated, Literal

import tyro

from docking.study import paths
from docking.study.cli import PROG
from docking.study.cli.options import _no_ledger, _Processes, _ResultsDir, _Scheduler, _shown
from docking.study.designs import names as _design_names


@dataclasses.dataclass
class Ledger:
    """Write the results ledger (ledger/, committed) from the results store: the runs of every
    design (python -m docking design list), as results tables and the few runs the designs
    keep whole; show what the ledger holds; or migrate its runs to this code."""

    action: tyro.conf.Positional[Literal["update", "show", "migrate", "derive"]]
    """update: write the ledger from the results store; show: its runs, size, fingerprint,
    every file checked; migrate: after a change of code that changes no number, recompute a
    sample covering every table, kind of run and world, and only if every recomputed run
    equals the ledger, re-key the ledger's runs (and the results store's) to this code;
    derive: add the results store's derived arrays that the ledger keeps (notebook 08's
    oracle-labelled success, the third edition's feature fidelity), those of runs the ledger
    holds, computed by this code."""
    results_dir: _ResultsDir = None
    """The results store (update, and migrate: its runs are re-keyed too)."""
    under_way: Annotated[tuple[str, ...], _shown("NAME ...", "none: every design complete")] = ()
    """Designs whose runs are under way: only the cells whose runs the store holds are
    written (update only)."""
    only: Annotated[tuple[str, ...], _shown("NAME ...", "every design")] = ()
    """Write only these designs' results tables, keeping every other table of the ledger as
    it is (checked against its digests and this code): the results store need not hold the
    other designs' runs (update only)."""
    old: Annotated[str | None, _shown("COMMIT", "the newest commit with the ledger's code")] = None
    """The commit (or a folder holding the docking package) of the code that computed the
    ledger, whose short runs the battery compares with this code's (migrate only)."""

    def execute(self) -> int:
        from docking.study import ledger

        folder = paths.ledger_dir()  # ValueError if DOCKING_LEDGER is not off or a folder
        if folder is None:
            raise ValueError(_no_ledger())
        if self.action == "migrate":
            return _migrate(folder, self.results_dir, self.old)
        if self.action == "derive":
            from docking.study import derived

            written = derived.commit(folder, self.results_dir)
            for name, count in written.items():
                print(f"{folder}: derived table {name}: {count} entries")
            if not written:
                print(f"{folder}: the results store holds no derived arrays the ledger keeps")
            return 0
        if self.action == "update":
            from docking.study.design import ledger_runs
            from docking.study.designs import design, names

            unknown = sorted((set(self.under_way) | set(self.only)) - set(names()))
            if unknown:
                raise ValueError(f"no design {', '.join(unknown)}; the designs are {names()}")
            runs = {}
            for name in self.only or names():
                partial = name in self.under_way
                for config, seed, whole, keep in ledger_runs(
                    design(name), stored_only=partial, results_dir=self.results_dir
                ):
                    key = (json.dumps(config.to_dict(), sort_keys=True), seed)
                    old = runs.get(key, (config, seed, False, frozenset()))
                    runs[key] = (config, seed, whole or old[2], keep | old[3])
            from docking.study.designs import rules_digest

            rules = {name: rules_digest(name) for name in self.only or names()}
            data = ledger.update(
                list(runs.values()),
                results_dir=self.results_dir,
                only=self.only or None,
                rules=rules,
            )
        else:
            data = ledger.manifest(folder)
            if data is None:
                raise ValueError(f"no ledger in {folder} (it has no manifest.json)")
        checked = ledger.check_files(folder)  # CorruptLedger naming the first damaged file
        print(_ledger_table(data, folder, checked, ledger.size_bytes(folder)))
        return 0


def _migrate(folder: Path, results_dir, old: str | None = None) -> int:
    """``ledger migrate``: what :func:`docking.study.migrate.migrate` did, in a few lines; 1 if a
    battery case or a recomputed run differs (nothing migrated)."""
    from docking.study import migrate

    done = migrate.migrate(folder, results_dir, old=old)
    if done.refused:
        print(f"{PROG}: nothing migrated: the battery's short runs differ", file=sys.stderr)
        for line in done.refused:
            print(f"  {line}", file=sys.stderr)
        return 1
    if done.differ:
        print(f"{PROG}: nothing migrated: this code computes other arrays for", file=sys.stderr)
        for name, seed, what in done.differ:
            print(f"  {name} seed {seed}: {what} differ", file=sys.stderr)
        return 1
    if done.record is None:
        print(f"{folder}: its runs are keyed by this code already: nothing to migrate")
    else:
        record = done.record
        for name in sorted(record["to"]):
            print(
                f"{folder}: {record['moved'][name]} {name} runs re-keyed from "
                f"{record['from'][name][:16]} to {record['to'][name][:16]} "
                f"(changed: {', '.join(record['changed'][name])[:200]})"
            )
        covered = record.get("covered", {})
        cases = sum(v["cases"] for v in covered.get("covered", {}).values())
        print(
            f"proof: {cases} short runs of the battery equal under the old code "
            f"({str(covered.get('old', '?'))[:12]}) and this code; {len(record['recomputed'])} "
            "runs recomputed, covering every table, kind of run, world, field value and seed, "
            "each equal to the ledger (digest and table row)"
        )
    if done.dropped:
        print(
            f"{folder}: derived tables dropped ({', '.join(done.dropped)}): each entry's key "
            "holds the keys of the runs it read, which moved; compute them again (the "
            "notebooks, report) and write them with: python -m docking ledger derive"
        )
    if done.store is not None:
        moved = done.store
        print(
            f"results store: {moved['moved']} runs re-keyed, {moved['current']} keyed by "
            f"this code already, {moved['left']} left (other code, or no migration "
            "whose proof recomputed their seed and field values)"
        )
    return 0


#: The widest line ``ledger show`` prints.
LEDGER_WIDTH = 100


def _checked_text(checked: dict) -> str:
    """What ``ledger show`` says it checked (``checked``: the counts of
    :func:`docking.study.ledger.check_files`)."""
    derived = checked.get("derived", 0)
    files = (
        f"the {checked['tables']} tables, {checked['whole']} whole runs and {derived} derived "
        f"{'table' if derived == 1 else 'tables'}"
        if derived
        else f"the {checked['tables']} tables and {checked['whole']} whole runs"
    )
    return (
        f"checked: the manifest against this code's fingerprints and its seals (each "
        f"table's SHA-256 with its runs' digests and wall times); {files} against their "
        f"SHA-256; every row of every table against its record's row digest; the whole runs' "
        f"arrays against their digests; the {checked['runs']} runs' keys against their "
        "configurations and seeds. Digests catch an edit, not a forgery resealed by someone "
        "who can run this code: that a run's arrays are its own is shown only by recomputing "
        "it (python -m docking verify)."
    )


def _ledger_table(data: dict, folder: Path, checked: dict, size: int) -> str:
    """What ``ledger show`` prints of the manifest ``data`` of the ledger in ``folder``
    (``size`` bytes; ``checked``: :func:`docking.study.ledger.check_files`'s counts): a line of
    totals, one row per results table (its runs by runner, configurations, whole runs, bytes
    and the runs' recorded wall time), the code and rendering stack, and what was checked;
    no line wider than :data:`LEDGER_WIDTH`."""
    import textwrap

    runs = data["runs"].values()
    runners = sorted({r["runner"] for r in runs})
    kinds = collections.Counter(r["runner"] for r in runs)

    def fill(text: str) -> str:
        return textwrap.fill(text, LEDGER_WIDTH, subsequent_indent="  ", break_on_hyphens=False)

    def row(name, mine, mib) -> str:
        configs = {json.dumps(r["config"], sort_keys=True) for r in mine}
        counts = collections.Counter(r["runner"] for r in mine)
        hours = sum(r["wall_seconds"] for r in mine) / 3600
        cells = [f"{counts[k]:>7d}" for k in runners]
        whole = sum(1 for r in mine if r.get("whole"))
        return (
            f"{name[:30]:30s} {len(mine):>6d} {' '.join(cells)} {len(configs):>7d} "
            f"{whole:>5d} {mib:>6.1f} {hours:>7.1f}"
        )

    lines = [
        fill(
            f"{folder}: {len(data['runs'])} runs ("
            + ", ".join(f"{n} {k}" for k, n in sorted(kinds.items()))
            + f") of {len(data['configs'])} configurations in {len(data['tables'])} results "
            f"tables, {size / 2**20:.1f} MiB"
        ),
        f"{'results table':30s} {'runs':>6s} {' '.join(f'{k[:7]:>7s}' for k in runners)} "
        f"{'configs':>7s} {'whole':>5s} {'MiB':>6s} {'run (h)':>7s}",
    ]
    for name in sorted(data["tables"]):
        mine = [r for r in runs if r["name"] == name]
        files = [folder / "tables" / f"{name}.npz"] + [
            folder / r["whole"] for r in mine if r.get("whole")
        ]
        mib = sum(p.stat().st_size for p in files if p.is_file()) / 2**20
        lines.append(row(name, mine, mib))
    lines.append(row("all", list(runs), size / 2**20))
    sources = ", ".join(f"{k} {v[:16]}" for k, v in sorted(data["fingerprints"].items()))
    lines.append(fill(f"code: {sources}; rendered by {data['rendering_stack']}"))
    lines.append(fill(_checked_text(checked)))
    return "\n".join(lines)


#: The designs' names (docking.study.designs), as choices.
_DesignName = Literal[tuple(_design_names())]  # type: ignore[valid-type]


@dataclasses.dataclass
class Verify:
    """Recompute runs of the ledger and check each one against the ledger: its record's
    content digest and the row its results table serves, column by column. Every run of
    Experiments 1 and 2, plus SAMPLE others chosen from the current commit (successive
    commits check different runs); --table NAME: every run of a table; --all: every run;
    --design NAME [--cells KEY ...] [--seeds SEEDS]: the runs behind a number, those of a
    design's cells (e.g. --design bracketing-replication --cells floor/paper --seeds
    7100-7104). Its first line says how many runs and about how long, from the ledger's
    wall times of those runs."""

    sample: int = 3
    """How many runs besides Experiments 1 and 2 (0 or more)."""
    all: bool = False
    """Recompute every run of the ledger (hours on 2 cores; use --scheduler for a cluster)."""
    table: Annotated[tuple[str, ...], _shown("NAME ...", "none: the sample")] = ()
    """Recompute every run of these results tables instead (python -m docking ledger show
    lists them)."""
    design: Annotated[_DesignName | None, _shown("NAME", "none: the sample")] = None
    """Recompute the runs of this design that the ledger keeps instead (python -m docking
    design list): every cell's, or those of --cells, for every seed, or those of --seeds."""
    cells: Annotated[tuple[str, ...], _shown("PATTERN ...", "every cell of --design")] = ()
    """With --design: only the cells whose keys match one of these shell-style patterns
    (floor/paper, 'floor/*')."""
    seeds: Annotated[str | None, _shown("STR", "the cells' seeds")] = None
    """With --design: only these seeds of its cells, as ranges or lists (7100-7104, 7102)."""
    scheduler: _Scheduler = None
    """Address of an existing Dask scheduler (tcp://HOST:PORT)."""
    processes: _Processes = None
    """Worker processes of the embedded cluster."""
    derived: int = 1
    """How many entries of each derived table the ledger keeps (arrays computed from runs:
    notebook 08's oracle-labelled success, the third edition's feature fidelity) to recompute
    from their keys (0 or more; --all: every one; --table: none)."""

    def execute(self) -> int:
        from docking.study import verify

        if self.sample < 0:
            raise ValueError(f"--sample must be 0 or more, got {self.sample}")
        if self.derived < 0:
            raise ValueError(f"--derived must be 0 or more, got {self.derived}")
        if sum(map(bool, (self.table, self.all, self.design))) > 1:
            raise ValueError("--table, --all and --design: give one of them")
        if (self.cells or self.seeds is not None) and self.design is None:
            raise ValueError("--cells and --seeds choose runs of a design: name it (--design)")
        runs = self._design_runs()
        print(
            _verify_plan(self.sample, self.all, self.processes, self.scheduler, self.table, runs),
            flush=True,
        )
        checks = verify.verify(
            None if self.all else self.sample,
            self.scheduler,
            workers=self.processes,
            tables=self.table,
            runs=[(config, seed) for _, config, seed in runs],
        )
        bad = [c for c in checks if not c.ok]
        for c in checks:
            differs = "" if c.ok else f": {c.differences()} differ"
            print(
                f"{'ok' if c.ok else 'MISMATCH':8s} {c.name} seed {c.seed} ({c.key[:16]}){differs}"
            )
        print(f"{len(checks) - len(bad)} of {len(checks)} recomputed runs equal the ledger")
        if not self.table and self.design is None:
            bad += _verify_derived(None if self.all else self.derived)
        for line in verify.platform_lines(bool(bad)):
            print(line)
        return 1 if bad else 0

    def _design_runs(self) -> list[tuple[str, object, int]]:
        """``(cell key, config, seed)`` of the runs of --design, --cells and --seeds
        (:func:`docking.study.design.cell_runs`); none without --design."""
        if self.design is None:
            return []
        from docking.study.design import cell_runs
        from docking.study.designs import design
        from docking.study.sweep import parse_seeds

        seeds = None if self.seeds is None else parse_seeds(self.seeds)
        return cell_runs(design(self.design), self.cells, seeds)


def _verify_derived(sample: int | None) -> list:
    """``verify``'s derived entries recomputed and printed a line each; those that differ."""
    from docking.study import verify

    rechecks = verify.verify_derived(sample)
    for r in rechecks:
        state = "ok" if r.equal else "MISMATCH"
        print(f"{state:8s} derived {r.name} of {r.run} seed {r.seed}")
    bad = [r for r in rechecks if not r.equal]
    if rechecks:
        print(
            f"{len(rechecks) - len(bad)} of {len(rechecks)} recomputed derived entries equal "
            "the ledger"
        )
    return bad


def _verify_plan(
    sample: int,
    everything: bool,
    processes: int | None,
    scheduler: str | None = None,
    tables: tuple[str, ...] = (),
    runs: list[tuple[str, object, int]] = (),
) -> str:
    """What ``verify`` is about to recompute, in one line: how many runs (``--sample`` capped
    at the other runs the ledger holds; ``runs``: a design's, ``(cell key, config, seed)``)
    and about how long, from the ledger's wall times of those runs, on ``processes`` workers
    (default: one per core; on a ``scheduler``'s cluster, their sum)."""
    from docking.study import ledger, verify

    data = ledger.manifest()
    if data is None:  # verify.verify says so
        return "verify: no ledger"
    commit = verify._commit()
    named = [(config, seed) for _, config, seed in runs]
    keys = verify.chosen(data, None if everything else sample, commit, tables, named)
    paper = len(verify.chosen(data, 0, commit))
    others = len(verify.chosen(data, len(data["runs"]), commit)) - paper
    seconds = sum(data["runs"][k]["wall_seconds"] for k in keys)
    workers = max(1, min(processes or os.cpu_count() or 1, len(keys)))
    what = (
        f"every run of the ledger ({len(keys)})"
        if everything
        else f"every run of {', '.join(tables)} ({len(keys)})"
        if tables
        else _runs_text(runs, data, keys)
        if runs
        else (
            f"{len(keys)} runs: the {paper} of {' and '.join(verify.PAPER_RUNS)} and "
            f"{len(keys) - paper} of the {others} others the ledger holds"
            + (f" (--sample {sample} capped at {others})" if sample > others else "")
        )
    )
    if scheduler is not None:
        return f"verify: recomputing {what} on {scheduler}: {_duration(seconds)} of wall time"
    return (
        f"verify: recomputing {what}; about {_duration(seconds / workers)} on {workers} "
        f"processes ({_duration(seconds)} of the runs' wall times in the ledger)"
    )


def _runs_text(runs: list[tuple[str, object, int]], data: dict, keys: list[str]) -> str:
    """``the 5 runs behind cell floor/paper, seeds 7100-7104 (table bracketing-replication)``:
    the runs of a design's cells, ``runs`` as ``(cell key, config, seed)``, whose ledger keys
    are ``keys``."""
    from docking.study.sweep import seeds_text

    cells = list(dict.fromkeys(cell for cell, _, _ in runs))
    seeds = seeds_text(sorted({seed for _, _, seed in runs}))
    named = (
        ", ".join(cells) if len(cells) <= 3 else f"{', '.join(cells[:2])} and {len(cells) - 2} more"
    )
    tables = sorted({data["runs"][k]["name"] for k in keys})
    return (
        f"the {len(keys)} runs behind {'cell' if len(cells) == 1 else 'cells'} {named[:300]}, "
        f"seeds {seeds} ({'table' if len(tables) == 1 else 'tables'} {', '.join(tables)[:200]})"
    )


def _duration(seconds: float) -> str:
    """``1 h 05 min``, ``12 min``, ``40 s``."""
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds} s"
    hours, minutes = divmod(round(seconds / 60), 60)
    return f"{hours} h {minutes:02d} min" if hours else f"{minutes} min"


@dataclasses.dataclass
class Benchmark:
    """Environment steps per second against their floor (rendering + physics + preprocessing
    alone), and full Experiment 2 runs, one process and two (benchmarks/env_speed.py of a
    clone of the repository)."""

    repeats: Annotated[int | None, _shown("INT", "5; 3 with --quick")] = None
    """Repetitions of each timing (min and median are reported)."""
    steps: Annotated[int | None, _shown("INT", "2000; 500 with --quick")] = None
    """Environment steps per repetition."""
    seeds: str = "0-1"
    """Seeds of the Experiment 2 runs, as ranges or lists (0-1, 0,3)."""
    quick: bool = False
    """A smoke test of about 10 s on two idle cores: fewer, shorter repetitions and an
    Experiment 2 of 30 training and 10 test trials without its learning curve."""

    def execute(self) -> int:
        from docking.study.sweep import parse_seeds

        benchmark_module().run(self.repeats, self.steps, parse_seeds(self.seeds), self.quick)
        return 0


def benchmark_module():
    """The benchmark, ``benchmarks/env_speed.py`` of the clone this package runs from (it is
    not part of the package: a wheel has none, and says so)."""
    import importlib

    root = Path(__file__).resolve().parents[3]
    if not (root / "benchmarks" / "env_speed.py").is_file():
        raise ValueError(
            f"the benchmark is benchmarks/env_speed.py of the repository, and {root} holds "
            "none (an installed package): run it from a clone"
        )
    if str(root) not in sys.path:  # also where the benchmark's spawned processes look
        sys.path.insert(0, str(root))
    return importlib.import_module("benchmarks.env_speed")
