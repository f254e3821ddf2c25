"""docs/build.py's notebook preparation, without building the site: a code cell that opens
with imports is split into a folded import cell and the rest, and a cell the notebook hides
already keeps its tag once (nbformat refuses repeated tags: make docs failed on notebook 07's
hidden cells that open with imports); and no notebook prints a raw dict under a figure."""

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
