"""The design files: every question the package asks, as data (:mod:`docking.study.design`).

Each module defines ``DESIGN`` (a :class:`docking.study.design.Design`); :data:`DESIGNS` names
them for ``python -m docking design list|run NAME``. A new study is a new module here,
registered below.
"""

from __future__ import annotations

import importlib

#: ``{design name: the module that defines it}``, in the order a reproduction runs them.
MODULES = {
    "paper": "docking.study.designs.paper",
    "calibration-experiment1": "docking.study.designs.calibration",
    "calibration-experiment2": "docking.study.designs.calibration",
    "experiment3": "docking.study.designs.experiment3",
    "experiment3-oracle": "docking.study.designs.experiment3",
    "third-edition": "docking.study.designs.third_edition",
    "third-edition-addendum": "docking.study.designs.addendum",
    "addendum-bracketing": "docking.study.designs.bracketing",
    "addendum-bracketing-continued": "docking.study.designs.bracketing_continued",
    "untested": "docking.study.designs.untested",
    "untested-revisited": "docking.study.designs.revisited",
    "bracketing-replication": "docking.study.designs.replication",
    "fragility-landscape": "docking.study.designs.landscape",
    "equal-contest": "docking.study.designs.equal_contest",
}


def design(name: str):
    """The :class:`~docking.study.design.Design` called ``name`` (``ValueError`` listing the
    names otherwise)."""
    if name not in MODULES:
        raise ValueError(f"no design {name!r}; the designs are {', '.join(MODULES)}")
    module = importlib.import_module(MODULES[name])
    found = getattr(
        module, "DESIGNS", {module.DESIGN.name: module.DESIGN} if hasattr(module, "DESIGN") else {}
    )
    return found[name]


def names() -> list[str]:
    """Every design's name."""
    return list(MODULES)


def rules_digest(name: str) -> str | None:
    """The SHA-256 of design ``name``'s rules as committed before its runs, with any
    amendment committed before the runs it changes (:func:`docking.study.records.in_force_digest`),
    or None for a design without committed rules: what the
    ledger records beside each of its runs (:func:`docking.study.ledger.update`'s
    ``rules``)."""
    from docking.study import records

    design(name)  # ValueError naming the designs
    return records.in_force_digest(name) if records.exists(name) else None


def rules_data(name: str) -> dict:
    """Design ``name``'s rules as its live code states them: its module's constants named in
    its ``RULES`` and its cells and claims (:func:`docking.study.design.rules_data`), or its
    module's own ``rules_data()`` where it has more (the equal contest's ladders): what
    tests/test_records.py holds against its record."""
    import json

    from docking.study.design import rules_data as data_of

    module = importlib.import_module(MODULES[name])
    if hasattr(module, "rules_data"):
        return module.rules_data()
    constants = {n: getattr(module, n) for n in module.RULES}
    return data_of(design(name), json.loads(json.dumps(constants, default=list)))


# ------------------------------------------------------------------------------------------
# Replaying a design's rules on the committed ledger's runs (its record's replay).
# ------------------------------------------------------------------------------------------


def _extra_verdicts(name: str, results) -> dict:
    """The verdicts design ``name``'s rules reach beyond its claims (a gap rule, leads, the
    chosen settings), as data: its module's ``replayed(results)``, or none."""
    module = importlib.import_module(MODULES[name])
    return module.replayed(results) if hasattr(module, "replayed") else {}


def replay(name: str, results_dir=None) -> dict:
    """Design ``name``'s rules replayed on the runs the results store or the committed ledger
    holds (never computed; ``LookupError`` if a run the rules ask for is in neither): the cells
    its procedure walks (key, SHA-256 of the configuration, seeds), its claims' decisions
    (Holm within each claim) and the verdicts of its other rules. What its record's
    ``replay.json`` holds; the live code must give the same (tests/test_records.py)."""
    import hashlib
    import json

    from docking.study import design as layer

    found = design(name)
    results = layer._walk(
        found,
        found.select(False),
        lambda new, _: layer._loaded(found, new, results_dir),
        results_dir,
    )[1]
    cells = [
        [
            c.key,
            hashlib.sha256(json.dumps(c.config.to_dict(), sort_keys=True).encode()).hexdigest(),
            list(c.seeds or found.seeds),
        ]
        for c in results.cells
    ]
    decisions = []
    if found.claims:
        from docking.study.claims import judge_family

        for d in judge_family(found.claims, results, alpha=found.alpha, per_claim=True):
            decisions.append([d.claim, d.world, d.key, d.verdict, d.p, d.p_adjusted])
    return {"cells": cells, "decisions": decisions, "verdicts": _extra_verdicts(name, results)}
