"""docs/build.py's notebook preparation, without building the site: a code cell that opens
with imports is split into a folded import cell and the rest, and a cell the notebook hides
already keeps its tag once (nbformat refuses repeated tags: make docs failed on notebook 07's
hidden cells that open with imports)."""

from __future__ import annotations

import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parent.parent


def _build():
    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import build
    finally:
        sys.path.remove(str(ROOT / "docs"))
    return build


def _cell(source: str, tags: list[str]) -> dict:
    cell = nbformat.v4.new_code_cell(source)
    cell["metadata"]["tags"] = list(tags)
    return cell


def test_a_hidden_cell_opening_with_imports_keeps_one_hide_input_tag():
    build = _build()
    imports = "\n".join(f"import m{k}  # noqa" for k in range(build.FOLDED_IMPORT_LINES + 1))
    for tags in ([], ["hide-input"], ["hide-input", "fold-output"]):
        cells = build._fold_imports(_cell(imports + "\nx = 1\n", tags))
        assert len(cells) == 2 and cells[1]["source"] == "x = 1"
        assert cells[0]["metadata"]["tags"].count("hide-input") == 1
        notebook = nbformat.v4.new_notebook(cells=cells)
        nbformat.validate(notebook, relax_add_props=True)  # what mkdocs-jupyter runs
