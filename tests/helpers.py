"""Shared test fixtures' data: the tiny learner configuration and seeds that the ledger's
tests (tests/test_ledger.py, tests/test_fuzz_defects.py) build their stores and ledgers of."""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path

from docking.presets import EXPERIMENT_1

ROOT = Path(__file__).resolve().parent.parent

#: A learner run of a few trials (seconds): what a tiny store and ledger hold.
TINY = dataclasses.replace(
    EXPERIMENT_1,
    name="tiny",
    train_trials=4,
    test_trials=6,
    eval_every=4,
    eval_trials=1,
    heldout_trials=5,
)
#: The seeds of a tiny store.
SEEDS = (0, 1)


def unknown_cells(design) -> list[tuple[str, tuple[str, ...]]]:
    """The comparisons of ``design``'s claims that name a cell the design does not have:
    ``[(claim key, the comparison's cells), ...]``."""
    keys = {c.key for c in design.cells}
    found = []
    for claim in design.claims:
        for entries in claim.cells.values():
            for entry in entries:
                names = (entry,) if isinstance(entry, str) else tuple(entry)
                if not set(names) <= keys:
                    found.append((claim.key, names))
    return found


def unquoted(claims, paper_text: str, skip=()) -> list[tuple[str, str]]:
    """The parts (between "...") of each claim's words, a "(finding ...)" prefix left out,
    that the paper's text does not contain (case and whitespace ignored); claims in
    ``skip`` are questions of ours, not quotes."""
    import re

    text = re.sub(r"\s+", " ", paper_text).lower()
    found = []
    for claim in claims:
        if claim.key in skip:
            continue
        words = re.sub(r"^\(finding[^)]*\) ", "", claim.words)
        for part in filter(None, (p.strip() for p in words.split("..."))):
            if part.lower() not in text:
                found.append((claim.key, part))
    return found


def tool(name: str):
    """``tools/NAME.py`` as a module (the tools are scripts beside the package, not a
    package)."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "tools" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def old_path(module: str) -> str:
    """Where ``module`` (``docking.study.X``) was before the study layer moved into
    ``docking/study/`` (issue 51): ``docking/X.py``."""
    return module.replace("docking.study.", "docking.", 1).replace(".", "/") + ".py"


#: A learner in a module of the user's own (``user_learner``), which imports a module of its
#: own beside it (``user_helper``): what a script in the user's folder imports.
USER_LEARNER = """
import dataclasses

import user_helper
from docking.scene import WorldConfig
from docking.study import learners


@dataclasses.dataclass(frozen=True)
class Steady:
    name: str = "steady"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 2


def run(config, seed, progress=True, on_trials=None):
    return learners.judge(config, seed, lambda o, env: user_helper.ACTION, 0, on_trials)


learners.register(Steady, run)
"""

#: The script that sweeps the user's learner: ``python run_it.py RESULTS [SCHEDULER]``; prints
#: the stored runs' paths.
USER_SCRIPT = """
import sys

import user_learner
from docking.study.sweep import Job, run_jobs

scheduler = sys.argv[2] if len(sys.argv) > 2 else None
jobs = [Job(user_learner.Steady(), seed) for seed in (0, 1)]
paths = run_jobs(jobs, sys.argv[1], scheduler=scheduler, workers=2, progress=False)
print("\\n".join(str(p) for p in paths))
"""


def user_scripts(folder: Path) -> Path:
    """The user's learner, its helper module and the script that sweeps it, written in
    ``folder`` (created); the script's path."""
    folder.mkdir(parents=True)
    (folder / "user_learner.py").write_text(USER_LEARNER)
    (folder / "user_helper.py").write_text("ACTION = 0\n")
    (folder / "run_it.py").write_text(USER_SCRIPT)
    return folder / "run_it.py"


#: The [ppo] extra's distributions (and what only they pull in), by their folders' prefixes.
PPO_EXTRA = ("skrl", "jax", "jaxlib", "flax", "flaxlib", "optax", "orbax", "chex")


def without_extra(tmp_path, env: dict, prefixes=PPO_EXTRA) -> tuple[list[str], dict]:
    """A Python as a virtual environment without the [ppo] extra would be: this one's
    site-packages linked entry by entry into a folder but for the extra's distributions
    (modules and metadata), started with ``-S`` so that only that folder and the checkout
    are on its path. ``(command prefix, env with that path)``."""
    import os
    import site
    import sys

    (packages,) = [Path(p) for p in site.getsitepackages() if Path(p).name == "site-packages"]
    folder = tmp_path / "site-packages-without-extra"
    folder.mkdir()
    for entry in packages.iterdir():
        if not entry.name.lower().startswith(prefixes) and entry.suffix != ".pth":
            (folder / entry.name).symlink_to(entry)
    return [sys.executable, "-S"], {**env, "PYTHONPATH": os.pathsep.join([str(ROOT), str(folder)])}
