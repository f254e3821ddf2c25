"""The package's two layers and their sizes, by folder, as a Markdown table: the core (the
files of ``docking/``'s top level) and the study layer (``docking/study/``), each module with
its lines, docstrings and comments included (a subpackage, such as ``docking/study/designs/``,
as the sum of its files).

    python tools/layers.py            # the table
    python tools/layers.py --totals   # one line a layer

docs/build.py writes the table into docs/guide/layers.md on the site (at ``MARK``), so that
the page's figures are the code's at the time of the build. The import contract "the core
never imports the study layer" (``pyproject.toml``) names the same two folders.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Where docs/guide/layers.md wants the table.
MARK = "<!-- tools/layers.py writes the table of sizes here -->"

#: The two layers: their names and folders (relative to the checkout).
FOLDERS = {"core": "docking", "study layer": "docking/study"}

#: The most lines the core (``docking/``'s top level) may hold (issue 51).
CORE_LIMIT = 6000


def _modules(folder: Path) -> list[str]:
    """The modules of ``folder`` (its ``.py`` files, ``__init__`` included) and its
    subpackages (folders with an ``__init__.py``, each counted as one), by dotted name."""
    package = ".".join(folder.relative_to(ROOT).parts)
    found = [f"{package}.{p.stem}" for p in sorted(folder.glob("*.py"))]
    found += [
        f"{package}.{p.name}"
        for p in sorted(folder.iterdir())
        if p.is_dir()
        and (p / "__init__.py").is_file()
        and f"{package}.{p.name}" not in layer_roots()
    ]
    return found


def layer_roots() -> set[str]:
    """The packages that are layers of their own (not a module of the layer above them)."""
    return {".".join(Path(f).parts) for f in FOLDERS.values()}


def layers(root: Path = ROOT) -> dict[str, list[str]]:
    """``{"core": [...], "study layer": [...]}``: every module of each folder."""
    del root  # the checkout's, always (kept for the callers' signature)
    return {name: _modules(ROOT / folder) for name, folder in FOLDERS.items()}


def lines(module: str, root: Path = ROOT) -> int:
    """The lines of ``module``'s file, or of every file of the subpackage it names."""
    path = root.joinpath(*module.split("."))
    files = sorted(path.rglob("*.py")) if path.is_dir() else [path.with_suffix(".py")]
    return sum(len(f.read_text().splitlines()) for f in files if "__pycache__" not in f.parts)


def table(root: Path = ROOT) -> str:
    """The Markdown table: per layer, its folder, its modules from the largest, then the
    layer's total and its share of the package."""
    sizes = {name: {m: lines(m, root) for m in mods} for name, mods in layers(root).items()}
    package = sum(sum(s.values()) for s in sizes.values())
    rows = [
        "| layer | folder | modules (lines) | modules | lines | share |",
        "|---|---|---|---:|---:|---:|",
    ]
    for name, size in sizes.items():
        prefix = ".".join(Path(FOLDERS[name]).parts) + "."
        listed = ", ".join(
            f"`{m.removeprefix(prefix)}` {n:,}" for m, n in sorted(size.items(), key=_larger)
        )
        total = sum(size.values())
        rows.append(
            f"| {name} | `{FOLDERS[name]}/` | {listed} | {len(size)} | {total:,} | "
            f"{100 * total / package:.0f}% |"
        )
    return "\n".join(rows)


def _larger(item: tuple[str, int]) -> tuple[int, str]:
    return -item[1], item[0]


def totals(root: Path = ROOT) -> str:
    """One line a layer: its folder, its modules and its lines."""
    return "\n".join(
        f"{name} ({FOLDERS[name]}/): {len(mods)} modules, {sum(lines(m, root) for m in mods):,} "
        "lines"
        for name, mods in layers(root).items()
    )


if __name__ == "__main__":
    print(totals() if "--totals" in sys.argv[1:] else table())
