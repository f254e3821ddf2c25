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
