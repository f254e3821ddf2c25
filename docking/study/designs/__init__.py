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
    """The SHA-256 of design ``name``'s rules (its module's ``rules_text()``, what its test
    pins), or None for a design without committed rules: what the ledger records beside each
    of its runs (:func:`docking.study.ledger.update`'s ``rules``)."""
    import hashlib

    design(name)  # ValueError naming the designs
    module = importlib.import_module(MODULES[name])
    text = getattr(module, "rules_text", None)
    if text is None or getattr(module, "NAME", None) != name:
        return None
    return hashlib.sha256(text().encode()).hexdigest()
