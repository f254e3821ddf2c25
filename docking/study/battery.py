"""The migration's differential battery: short runs across the configuration space, computed
by the code that computed the ledger (the *old* code, from its commit) and by this code, and
compared bit for bit (:func:`prove`).

A migration's sample (:func:`docking.study.migrate.sample`) recomputes whole ledger runs, so it
can afford only some; a change that alters numbers in a corner it does not reach would pass.
The battery reaches every corner the ledger names, cheaply:

* **every value of every configuration field** the ledger holds (``network.beta_a_train = 5``,
  ``world.camera_height = 0.527``, ``learning_rate = 0.0003`` ...): a case per value, the
  cheapest ledger configuration that holds it, run short (:func:`short`: a few trials, a few
  PPO updates; the counts it shortens are the only values not run as they are, and the
  sample covers them);
* **every seed** of the paper's learner's runs, and each table's first and last seed of the
  other kinds;
* **pairs of knobs**: every combination of the learning rules' knobs (beta_a, eps_Q, eps_W,
  the world) that a ledger run holds.

Each case runs in a subprocess of each code (:data:`SCRIPT`, which asks only what every
package version since the kinds of run has: ``kinds.runner_named``, ``from_dict``, ``run``,
``arrays``), and its arrays' SHA-256 is compared. Any difference refuses the migration, naming
the field values every differing case holds and no equal case does (:func:`culprits`).

What it does not cover: a change that alters a run only in a combination of values that no
ledger run holds and no pair above names, or only after more trials than a short run has.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from docking.study import kinds, paths

__all__ = ["Case", "cases", "coverage", "culprits", "flat", "old_tree", "prove", "run", "short"]

#: The counts a short run lowers to at most these (a field not here runs as the ledger has it).
SHORT = {
    "learner": {
        "train_trials": 6,
        "test_trials": 3,
        "eval_every": 3,
        "eval_trials": 2,
        "heldout_trials": 4,
        "pretrain_trials": 3,
    },
    "ppo": {"heldout_trials": 3},
}
#: The knobs whose combinations the battery runs as the ledger holds them.
PAIRED = ("network.beta_a_train", "network.eps_q", "network.eps_w", "world", "policy")
#: Kinds of run the battery runs (a registered learner's code is the user's: the sample only).
BUILT_IN = ("learner", "ppo")


def flat(config: dict, prefix: str = "") -> dict[str, str]:
    """``{field path: canonical JSON of its value}`` of a configuration dict, nested fields
    joined by dots (``network.beta_a_train``), the name left out (it names a table); the world
    also whole (``world``: what a world is, beyond its fields)."""
    found = {}
    for key, value in config.items():
        path = f"{prefix}{key}"
        if path == "name":
            continue
        if isinstance(value, dict):
            found.update(flat(value, f"{path}."))
            if path in ("world", "heldout_world"):
                found[path] = json.dumps(value, sort_keys=True)
        else:
            found[path] = json.dumps(value, sort_keys=True)
    return found


@dataclasses.dataclass(frozen=True)
class Case:
    """One short run of the battery: its kind, its configuration (a dict, shortened), its seed,
    and what it stands for (``(field path, value)`` pairs, ``("seed", n)``)."""

    runner: str
    config: dict
    seed: int
    covers: tuple[tuple[str, str], ...]

    @property
    def text(self) -> str:
        return json.dumps([self.runner, self.config, self.seed], sort_keys=True)


def short(runner: str, config: dict) -> dict:
    """``config`` (a dict) run short: its counts lowered (:data:`SHORT`); a PPO run to two
    updates (``steps``: two rollouts of every copy of the world)."""
    found = json.loads(json.dumps(config))
    for field, most in SHORT.get(runner, {}).items():
        if field in found and isinstance(found[field], int):
            found[field] = min(found[field], most)
    if runner == "ppo":
        found["steps"] = min(found["steps"], 2 * found["envs"] * found["rollouts"])
    return found


def cases(data: dict, runners) -> list[Case]:
    """The battery of the ledger ``data``'s runs of ``runners`` (see the module docstring),
    each case once (the cheapest ledger run of what it stands for)."""
    runs = sorted(
        (r for r in data["runs"].values() if r["runner"] in runners and r["runner"] in BUILT_IN),
        key=lambda r: (r["wall_seconds"], r["name"], r["seed"]),
    )
    wanted: dict[tuple, tuple] = {}  # what a case stands for -> (runner, config, seed)
    for r in runs:
        fields = flat(r["config"])
        base = (r["runner"], r["config"], r["seed"])
        for path, value in fields.items():
            wanted.setdefault((r["runner"], path, value), base)
        combo = tuple((p, fields.get(p)) for p in PAIRED)
        if r["runner"] == "learner":
            wanted.setdefault((r["runner"], "knobs", json.dumps(combo)), base)
    seeds = _seeds(runs)
    found: dict[str, Case] = {}
    for (runner, path, value), (_, config, seed) in wanted.items():
        _add(found, Case(runner, short(runner, config), seed, ((path, value),)))
    for runner, seed, config in seeds:
        _add(found, Case(runner, short(runner, config), seed, (("seed", str(seed)),)))
    return sorted(found.values(), key=lambda c: c.text)


def _seeds(runs: list[dict]) -> list[tuple[str, int, dict]]:
    """The seeds the battery runs: every seed of the paper's learner's runs (with the cheapest
    configuration), each table's first and last of the others."""
    found, cheapest = {}, {}
    for r in runs:
        cheapest.setdefault(r["runner"], r["config"])
        if r["runner"] == "learner":
            found.setdefault(("learner", r["seed"]), cheapest["learner"])
    by_table: dict[tuple, list[int]] = {}
    for r in runs:
        if r["runner"] != "learner":
            by_table.setdefault((r["runner"], r["name"]), []).append(r["seed"])
    for (runner, _), seeds in by_table.items():
        for seed in (min(seeds), max(seeds)):
            found.setdefault((runner, seed), cheapest[runner])
    return [(runner, seed, config) for (runner, seed), config in sorted(found.items())]


def _add(found: dict, case: Case) -> None:
    if case.text in found:
        old = found[case.text]
        found[case.text] = dataclasses.replace(old, covers=old.covers + case.covers)
    else:
        found[case.text] = case


def coverage(data: dict, runners, battery: list[Case]) -> dict:
    """What the battery covered, for the manifest's migration record: per kind of run, the
    fields and how many of the ledger's values each held as the ledger has them, the seeds,
    and the battery's size."""
    found = {}
    for runner in sorted({c.runner for c in battery}):
        mine = [c for c in battery if c.runner == runner]
        fields: dict[str, set] = {}
        for c in mine:
            for path, value in flat(c.config).items():
                fields.setdefault(path, set()).add(value)
        seeds = sorted({c.seed for c in mine})
        found[runner] = {
            "cases": len(mine),
            "fields": {p: len(v) for p, v in sorted(fields.items())},
            "seeds": seeds,
        }
    return found


#: What each code runs: the battery's cases (JSON lines in the file named by its argument), each
#: case's arrays' SHA-256 (by name, dtype, shape and bytes, ``meta`` left out) as a JSON line
#: on stdout.
SCRIPT = r"""
import hashlib, json, sys
import numpy as np
from docking.study import kinds
for line in open(sys.argv[1]):
    runner_name, config, seed = json.loads(line)
    try:
        runner = kinds.runner_named(runner_name)
        result = runner.run(runner.from_dict(config), seed, progress=False)
        arrays = runner.arrays(result)
        digest = hashlib.sha256()
        for name in sorted(n for n in arrays if n != "meta"):
            a = np.ascontiguousarray(arrays[name])
            digest.update(f"{name}\0{a.dtype.str}\0{a.shape}\0".encode())
            digest.update(a.tobytes())
        print(json.dumps({"digest": digest.hexdigest()}), flush=True)
    except Exception as exc:
        print(json.dumps({"error": f"{type(exc).__name__}: {exc}"[:300]}), flush=True)
"""


def _env(tree: Path) -> dict:
    """The environment of a process that imports the ``docking`` package in ``tree``, the
    ledger off."""
    env = {**os.environ, "PYTHONPATH": str(tree), "DOCKING_LEDGER": "off"}
    env.setdefault("MUJOCO_GL", "egl")
    env.setdefault("PYOPENGL_PLATFORM", "egl")
    return env


def _process(tree: Path, cases_file: Path) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-c", SCRIPT, str(cases_file)],
        cwd=tree,
        env=_env(tree),
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )


def run(battery: list[Case], trees: tuple[Path, Path], progress: bool = True) -> tuple[list, list]:
    """Each case's result under each code (``trees``: the folders holding the old and the new
    ``docking`` package), the two codes in two processes at once: ``(old, new)``, each a list
    of ``{"digest": ...}`` or ``{"error": ...}``."""
    from tqdm import tqdm

    with tempfile.NamedTemporaryFile("w", suffix=".jsonl", delete=False) as f:
        f.write("".join(c.text + "\n" for c in battery))
    try:
        return _collect(battery, [_process(tree, Path(f.name)) for tree in trees], progress, tqdm)
    finally:
        os.unlink(f.name)


def _collect(battery, processes, progress: bool, tqdm) -> tuple[list, list]:
    found: tuple[list, list] = ([], [])
    with tqdm(
        total=2 * len(battery), desc="migrate: the battery (old and new code)", disable=not progress
    ) as bar:
        streams = [iter(p.stdout) for p in processes]
        while any(len(f) < len(battery) for f in found):
            for k, stream in enumerate(streams):
                if len(found[k]) < len(battery):
                    line = next(stream, None)
                    found[k].append(json.loads(line) if line else {"error": "no answer"})
                    bar.update()
    for p in processes:
        p.wait()
    return found


def culprits(battery: list[Case], differ: set[int]) -> list[str]:
    """The field values (and seeds) that only differing cases hold (``differ``: indices of the
    differing cases), those that explain the most differing cases first; a value held by
    every differing case and no equal one is marked so."""
    held: dict[tuple[str, str], set[int]] = {}
    for k, case in enumerate(battery):
        for path, value in [*flat(case.config).items(), ("seed", str(case.seed))]:
            held.setdefault((path, value), set()).add(k)
    by_path: dict[str, set[int]] = {}
    values: dict[str, list[str]] = {}
    for (path, value), ks in sorted(held.items()):
        if ks <= differ and path not in ("world", "heldout_world"):
            by_path.setdefault(path, set()).update(ks)
            values.setdefault(path, []).append(value)
    ranked = sorted(by_path, key=lambda p: (-len(by_path[p]), p))
    return [
        f"{p} = {', '.join(values[p])}"
        + (" (every differing case)" if by_path[p] == differ else f" ({len(by_path[p])} cases)")
        for p in ranked
    ]


def old_tree(data: dict, runners, folder: Path, commit: str | None = None) -> tuple[str, Path]:
    """The code that computed the ledger ``data``'s runs of ``runners``, extracted into
    ``folder``: ``commit``'s ``docking`` package, or (None) the newest commit of the checkout
    whose package gives every such runner the ledger's recorded fingerprint. ``(commit,
    folder)``; ``LookupError`` naming what was searched if none does."""
    if commit is not None and (Path(commit) / "docking").is_dir():  # a folder holding it
        tree = Path(commit)
        if _fingerprints_match(tree, data, runners):
            return str(tree), tree
        raise LookupError(f"the package in {tree} is not the code that computed the ledger")
    root = paths.checkout_root()
    if root is None:
        raise LookupError("the battery needs the old code: no git checkout to take it from")
    candidates = [commit] if commit else _history(root)
    for rev in candidates:
        tree = folder / rev[:12]
        if not tree.exists():
            archive = subprocess.run(
                ["git", "archive", rev, "docking"], cwd=root, capture_output=True, timeout=120
            )
            if archive.returncode != 0:
                continue
            tree.mkdir(parents=True)
            subprocess.run(["tar", "-x", "-C", str(tree)], input=archive.stdout, check=True)
        if _fingerprints_match(tree, data, runners):
            return rev, tree
    raise LookupError(
        f"no commit of {len(candidates)} searched ({'given' if commit else 'the newest'}) holds "
        "the code whose fingerprints the ledger records; name it: ledger migrate --old COMMIT"
    )


def _history(root: Path, limit: int = 300) -> list[str]:
    found = subprocess.run(
        ["git", "rev-list", f"--max-count={limit}", "HEAD", "--", "docking"],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=60,
    )
    return found.stdout.split() if found.returncode == 0 else []


#: What the old code's own process prints: each named runner's fingerprint, by the old code's
#: rule. Which modules are keyed is itself code (``kinds.UNKEYED_MODULES``, the modules a
#: runner's root imports): a change that keys another module changes the rule, so this code's
#: rule applied to the old files gives a fingerprint the old code never recorded.
FINGERPRINT_SCRIPT = r"""
import json, sys
from docking.study import kinds
found = {}
for name in sys.argv[1:]:
    runner = kinds.runner_named(name)
    found[name] = kinds.source_fingerprint(None, runner.root, runner.libraries)
print(json.dumps(found))
"""


def _fingerprints_match(tree: Path, data: dict, names) -> bool:
    """Whether the ``docking`` package in ``tree`` gives each runner of ``names`` the ledger
    ``data``'s recorded fingerprint, computed by that package's own code in one process of
    its own (:data:`FINGERPRINT_SCRIPT`)."""
    names = sorted(names)
    try:
        done = subprocess.run(
            [sys.executable, "-c", FINGERPRINT_SCRIPT, *names],
            cwd=tree,
            env=_env(tree),
            capture_output=True,
            text=True,
            timeout=300,
        )
        found = json.loads(done.stdout) if done.returncode == 0 else None
    except (OSError, ValueError, subprocess.TimeoutExpired):
        return False
    return found is not None and all(found.get(n) == data["fingerprints"][n] for n in names)


def prove(
    data: dict, runners, old: str | None = None, progress: bool = True
) -> tuple[list[str], dict]:
    """Run the battery of the ledger ``data``'s ``runners`` under the old code (``old``: a
    commit, else found, :func:`old_tree`) and this code. ``(differences, record)``: the
    refusal's lines (empty if every case is equal) and what the battery covered."""
    battery = cases(data, runners)
    if not battery:
        return [], {"cases": 0}
    new = Path(kinds._OWN).parent
    with tempfile.TemporaryDirectory(prefix="docking-battery-") as scratch:
        commit, tree = old_tree(data, {c.runner for c in battery}, Path(scratch), old)
        before, after = run(battery, (tree, new), progress)
    differ = {k for k, (a, b) in enumerate(zip(before, after, strict=True)) if a != b}
    lines = []
    if differ:
        lines.append(
            f"{len(differ)} of the battery's {len(battery)} short runs differ between the old "
            f"code ({commit[:12]}) and this code; what only differing cases hold: "
            + ("; ".join(culprits(battery, differ)) or "no single field value")
        )
        errors = sorted({str(b.get("error")) for b in after if "error" in b})
        if errors:
            lines.append(f"this code failed on some: {errors[0]}")
    record = {"old": commit, **{"cases": len(battery)}, "covered": coverage(data, runners, battery)}
    return lines, record
