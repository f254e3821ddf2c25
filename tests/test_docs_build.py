"""docs/build.py's notebook preparation, without building the site: a code cell that opens
with imports is split into a folded import cell and the rest, and a cell the notebook hides
already keeps its tag once (nbformat refuses repeated tags: make docs failed on notebook 07's
hidden cells that open with imports); no notebook prints a raw dict under a figure; and the
README's figure table gives each figure the width to be read."""

from __future__ import annotations

import re
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


def _code_cells(path: Path) -> list[tuple[int, str]]:
    """``[(first line, source)]`` of the code cells of a jupytext percent-format notebook."""
    lines = path.read_text().split("\n")
    starts = [k for k, line in enumerate(lines) if line.startswith("# %%")] + [len(lines)]
    return [
        (a + 2, "\n".join(lines[a + 1 : b]))
        for a, b in zip(starts, starts[1:], strict=False)
        if "[markdown]" not in lines[a]
    ]


def _raw_dicts(source: str) -> list[int]:
    """The lines of ``source`` that show a dict as Python writes it: ``print`` of a dict (or a
    dict comprehension), or one as the cell's last expression (Jupyter shows its repr)."""
    import ast

    tree = ast.parse(source)
    dicts = (ast.Dict, ast.DictComp)
    found = [
        node.lineno
        for node in ast.walk(tree)
        if isinstance(node, ast.Call)
        and getattr(node.func, "id", None) == "print"
        and any(isinstance(a, dicts) for a in node.args)
    ]
    if tree.body and isinstance(tree.body[-1], ast.Expr) and isinstance(tree.body[-1].value, dicts):
        found.append(tree.body[-1].lineno)
    return found


def test_no_figure_of_a_notebook_has_a_raw_dict_under_it():
    """Issue 62: a cell that shows a figure says its numbers in words, not as a Python dict
    printed under it (notebook 07's fragility landscape printed {'floor': 'published ...'})."""
    import ast

    found = []
    for path in sorted((ROOT / "notebooks").glob("*.py")):
        for first, source in _code_cells(path):
            calls = {
                getattr(n.func, "id", None)
                for n in ast.walk(ast.parse(source))
                if isinstance(n, ast.Call)
            }
            if "Image" in calls:
                found += [f"{path.name}:{first + k - 1}" for k in _raw_dicts(source)]
    assert found == []


#: The width of the README's text on the site at the docs tests' screen
#: (tests/test_docs.py's SCREEN, 1400 px wide): Material's grid, 61 rem of 20 px, less its
#: 12.1 rem sidebar and the text's margins of 1.2 rem each side (docs/mkdocs.yml:
#: toc.integrate, no second sidebar). A README on GitHub is as wide, give or take 50 px.
README_TEXT_WIDTH = 930


def _png_width(path: Path) -> int:
    """A PNG file's width in pixels, read from its header."""
    import struct

    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">I", head[16:20])[0]


def test_every_readme_figure_is_shown_wide_enough_to_read():
    """Issue 62: each figure of the README's figure table gets the width to be read, at least
    tests/test_docs.py's MIN_SHOWN of its own (a 6 pt label at 150 dpi 5.6 px tall): its
    table's columns share the text's width, so a figure shares its row only if it stays
    readable at its share. In two columns, Fig. 4 (1125 px) was shown at 0.41 of its width and
    the contest figure (1890 px) at 0.25."""
    from test_docs import MIN_SHOWN

    readme = (ROOT / "README.md").read_text()
    section = readme.split("\n## Figures\n", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("|") and "![" in line]
    columns = max(line.strip().strip("|").count("|") + 1 for line in section.splitlines()[:3])
    small, shown = [], []
    for row in rows:
        for name in re.findall(r"!\[[^\]]*\]\((figures/[^)\s]+\.png)\)", row):
            width = _png_width(ROOT / name)
            shown.append(name)
            if README_TEXT_WIDTH / columns < MIN_SHOWN * width:
                small.append(f"{name}: {width} px shown at {README_TEXT_WIDTH / columns:.0f}")
    assert len(shown) >= 7, shown  # Figs. 2-5, the learning curves, Experiment 3, ...
    assert not small, small
