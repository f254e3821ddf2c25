"""The package's two layers and their sizes, as a Markdown table: the core and the study layer
of the import contract "the core never imports the study layer" (``pyproject.toml``), each
module with its lines, docstrings and comments included (a subpackage, ``docking/designs/``,
as the sum of its files).

    python tools/layers.py            # the table
    python tools/layers.py --totals   # one line a layer

docs/build.py writes the table into docs/guide/layers.md on the site (at ``MARK``), so that
the page's figures are the code's at the time of the build.
"""

from __future__ import annotations

import sys
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]

#: Where docs/guide/layers.md wants the table.
MARK = "<!-- tools/layers.py writes the table of sizes here -->"


def layers(root: Path = ROOT) -> dict[str, list[str]]:
    """``{"core": [...], "study layer": [...]}``: the two sides of the forbidden contract."""
    contracts = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["importlinter"]
    (contract,) = [c for c in contracts["contracts"] if c["type"] == "forbidden"]
    return {"core": contract["source_modules"], "study layer": contract["forbidden_modules"]}


def lines(module: str, root: Path = ROOT) -> int:
    """The lines of ``module``'s file, or of every file of the subpackage it names."""
    path = root.joinpath(*module.split("."))
    files = sorted(path.rglob("*.py")) if path.is_dir() else [path.with_suffix(".py")]
    return sum(len(f.read_text().splitlines()) for f in files)


def table(root: Path = ROOT) -> str:
    """The Markdown table: per layer, its modules from the largest, then the layer's total and
    its share of the package (``docking/__init__.py`` is in neither layer)."""
    sizes = {name: {m: lines(m, root) for m in mods} for name, mods in layers(root).items()}
    package = sum(sum(s.values()) for s in sizes.values())
    rows = ["| layer | modules (lines) | modules | lines | share |", "|---|---|---:|---:|---:|"]
    for name, size in sizes.items():
        listed = ", ".join(
            f"`{m.removeprefix('docking.')}` {n:,}" for m, n in sorted(size.items(), key=_larger)
        )
        total = sum(size.values())
        rows.append(
            f"| {name} | {listed} | {len(size)} | {total:,} | {100 * total / package:.0f}% |"
        )
    return "\n".join(rows)


def _larger(item: tuple[str, int]) -> tuple[int, str]:
    return -item[1], item[0]


def totals(root: Path = ROOT) -> str:
    """One line a layer: its modules and its lines."""
    return "\n".join(
        f"{name}: {len(mods)} modules, {sum(lines(m, root) for m in mods):,} lines"
        for name, mods in layers(root).items()
    )


if __name__ == "__main__":
    print(totals() if "--totals" in sys.argv[1:] else table())
