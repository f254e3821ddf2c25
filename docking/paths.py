"""Where the package writes its results and figures.

* ``DOCKING_RESULTS`` / ``DOCKING_FIGURES``, if set, name the folders.
* Otherwise, when the package runs from a source checkout (``pyproject.toml`` next to the
  ``docking`` folder, as after ``pip install -e .`` or in a clone), the checkout's
  ``results/`` and ``figures/``, so notebooks (whose working directory is ``notebooks/``),
  the CLI and the tests all use the same folders.
* Otherwise (an installed package) ``./results`` and ``./figures`` of the current working
  directory, never a folder inside site-packages.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["checkout_root", "results_dir", "figures_dir"]


def checkout_root() -> Path | None:
    """The source checkout the package runs from, or None for an installed package."""
    root = Path(__file__).resolve().parent.parent
    return root if (root / "pyproject.toml").is_file() else None


def _folder(variable: str, name: str) -> Path:
    value = os.environ.get(variable)
    if value is not None:
        if not value.strip():
            raise ValueError(f"{variable} is set but empty; unset it or name a folder")
        return Path(value).expanduser()
    root = checkout_root()
    return (root if root is not None else Path.cwd()) / name


def results_dir() -> Path:
    """The results store's folder (``DOCKING_RESULTS``, the checkout's or ``./results``)."""
    return _folder("DOCKING_RESULTS", "results")


def figures_dir() -> Path:
    """The figures' folder (``DOCKING_FIGURES``, the checkout's or ``./figures``)."""
    return _folder("DOCKING_FIGURES", "figures")
