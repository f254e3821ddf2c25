"""Where the package writes its results and figures, and where it reads the ledger.

* ``DOCKING_RESULTS`` / ``DOCKING_FIGURES``, if set, name the folders.
* Otherwise, when the package runs from a source checkout (``pyproject.toml`` next to the
  ``docking`` folder, as after ``pip install -e .`` or in a clone), the checkout's
  ``results/`` and ``figures/``, so notebooks (whose working directory is ``notebooks/``),
  the CLI and the tests all use the same folders.
* Otherwise (an installed package, such as a wheel) ``results/`` and ``figures/`` of the
  per-user data folder, by the platform's convention (:func:`user_data_dir`, through
  ``platformdirs``: ``~/.local/share/docking`` on Linux), never a folder inside
  site-packages nor the current working directory.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = [
    "checkout_root",
    "figures_dir",
    "ledger_dir",
    "ledger_off",
    "results_dir",
    "user_data_dir",
]

#: The values of ``DOCKING_LEDGER`` that turn the ledger off (in any case).
LEDGER_OFF = ("off", "0", "none", "false")


def checkout_root() -> Path | None:
    """The source checkout the package runs from, or None for an installed package."""
    root = Path(__file__).resolve().parents[2]
    return root if (root / "pyproject.toml").is_file() else None


def user_data_dir() -> Path:
    """The per-user data folder of an installed package (``platformdirs``' user data
    folder of ``docking``: ``$XDG_DATA_HOME/docking`` or ``~/.local/share/docking`` on
    Linux)."""
    import platformdirs

    return Path(platformdirs.user_data_dir("docking", appauthor=False))


def _folder(variable: str, name: str) -> Path:
    value = os.environ.get(variable)
    if value is not None:
        if not value.strip():
            raise ValueError(f"{variable} is set but empty; unset it or name a folder")
        return Path(value).expanduser()
    root = checkout_root()
    return (root if root is not None else user_data_dir()) / name


def results_dir() -> Path:
    """The results store's folder (``DOCKING_RESULTS``, the checkout's ``results/`` or the
    per-user data folder's)."""
    return _folder("DOCKING_RESULTS", "results")


def figures_dir() -> Path:
    """The figures' folder (``DOCKING_FIGURES``, the checkout's ``figures/`` or the per-user
    data folder's)."""
    return _folder("DOCKING_FIGURES", "figures")


def in_user_data(folder: Path) -> bool:
    """Whether ``folder`` is inside the per-user data folder (an installed package's default)."""
    return checkout_root() is None and Path(folder).resolve().is_relative_to(
        user_data_dir().resolve()
    )


def ledger_off() -> bool:
    """Whether ``DOCKING_LEDGER`` turns the ledger off."""
    value = os.environ.get("DOCKING_LEDGER")
    return value is not None and value.strip().lower() in LEDGER_OFF


def ledger_dir() -> Path | None:
    """The ledger's folder: ``DOCKING_LEDGER`` if set (``off``: none; else an existing
    folder's absolute path, any other value a ``ValueError``), else the checkout's
    ``ledger/`` (None for an installed package without one)."""
    value = os.environ.get("DOCKING_LEDGER")
    if value is None:
        root = checkout_root()
        return root / "ledger" if root is not None else None
    if ledger_off():
        return None
    usage = "set it to off or to the absolute path of a ledger folder, or unset it"
    path = Path(value).expanduser()
    if not value.strip():
        raise ValueError(f"DOCKING_LEDGER is set but empty; {usage}")
    if not path.is_absolute():
        raise ValueError(f"DOCKING_LEDGER={value!r} is neither off nor an absolute path; {usage}")
    if not path.is_dir():
        raise ValueError(f"DOCKING_LEDGER={value!r} names no folder; {usage}")
    return path
