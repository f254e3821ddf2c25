"""The site's mkdocs hooks (docs/mkdocs.yml: ``hooks``): what nbconvert's template leaves out
of a notebook page.

- A figure's alt text: the template writes none (nbconvert then puts "No description has been
  provided for this image"); docs/build.py writes each figure's caption into its output's
  metadata, ``image/png`` -> ``alt``, where IPython's ``Image(alt=...)`` puts it and
  JupyterLab reads it, and here it becomes the ``<img>``'s ``alt``.
- Each figure's caption visible under it: the ``<img>`` in a ``<figure>`` with its alt text
  as the ``<figcaption>`` (glightbox shows the same text in its lightbox).
- Cells tagged ``hide-input`` (Jupyter Book's tag; docs/build.py gives it to the notebooks'
  import blocks): their code folded in a ``<details>`` whose summary says what it holds.
- Folded on the page, a click away, what a reader does not need on the way (a notebook's
  ``.py`` source tags the cell: ``# %% tags=["fold-output"]``):

  - ``fold-output``: a code cell's outputs (a long table, a listing) in a ``<details>``
    whose summary says what they are ("table: 12 rows", "figure", "output: 40 lines"), or,
    if the cell's code opens with a comment line, that comment;
  - ``fold``: on a markdown cell that opens with a heading, its whole section (the cell and
    the cells after it up to the next heading of its level or above: a derivation, a side
    analysis) in a ``<details>`` whose summary is the heading; on any other cell, the cell
    (its outputs too) in a ``<details>`` whose summary is its code's leading comment or its
    first line.
"""

from __future__ import annotations

import ast
import json
from pathlib import Path

from bs4 import BeautifulSoup
from mkdocs.plugins import event_priority


@event_priority(50)  # before glightbox, which links each <img> and takes its alt as caption
def on_page_content(html, page, config, files):
    if not page.file.src_uri.endswith(".ipynb"):
        return html
    soup = BeautifulSoup(html, "html.parser")
    alts = _alts(Path(page.file.abs_src_path))
    for img in soup.select(".jp-OutputArea img"):
        if img.get("src") in alts:
            img["alt"] = alts[img["src"]]
    for img in soup.select(".jp-OutputArea img"):
        _captioned(soup, img)
    # a cell's tags are on it, on the cell nbconvert nests inside it and on its markdown
    for cell in _outermost(soup, ".jp-Cell.celltag_fold-output"):
        _fold_outputs(soup, cell)
    for cell in _outermost(soup, ".celltag_fold"):
        _fold_cell(soup, cell)
    for wrapper in soup.select(".celltag_hide-input .jp-Cell-inputWrapper"):
        for toolbar in wrapper.select(".celltoolbar"):  # the tag's name, shown as a label
            toolbar.decompose()
        code = wrapper.select_one("pre")
        details = soup.new_tag("details", attrs={"class": "docking-hidden-input"})
        summary = soup.new_tag("summary")
        summary.string = _summary(code.get_text() if code else "")
        wrapper.wrap(details)
        details.insert(0, summary)
    return str(soup)


def _alts(notebook: Path) -> dict[str, str]:
    """The notebook's figures: their file (the ``<img>``'s src) -> their alt text."""
    alts = {}
    for cell in json.loads(notebook.read_text())["cells"]:
        for output in cell.get("outputs", []):
            metadata = output.get("metadata", {})
            src = metadata.get("filenames", {}).get("image/png")
            alt = metadata.get("image/png", {}).get("alt")
            if src and alt:
                alts[src] = alt
    return alts


def _summary(code: str) -> str:
    """What a folded cell holds: "imports: numpy, docking.network, ..." for imports only."""
    try:
        body = ast.parse(code).body
    except SyntaxError:
        body = None
    if body and all(isinstance(node, (ast.Import, ast.ImportFrom)) for node in body):
        modules = []
        for node in body:
            if isinstance(node, ast.Import):
                modules += [alias.name for alias in node.names]
            else:
                modules.append("." * node.level + (node.module or ""))
        return "imports: " + ", ".join(dict.fromkeys(modules))
    return f"code ({len(code.strip().splitlines())} lines)"


def _outermost(soup, selector: str) -> list:
    """The cells ``selector`` matches, each once: the outermost ``.jp-Cell`` of each match (a
    markdown cell's tag is on its rendering; nbconvert nests a cell in a copy of itself)."""
    cells = []
    for found in soup.select(selector):
        cell = found if "jp-Cell" in found.get("class", []) else found.find_parent(class_="jp-Cell")
        while cell is not None and cell.find_parent(class_="jp-Cell") is not None:
            cell = cell.find_parent(class_="jp-Cell")
        if cell is not None and all(cell is not c for c in cells):
            cells.append(cell)
    return cells


def _captioned(soup, img) -> None:
    """``img`` in a ``<figure>``, its alt text (the figure's caption) beneath as the
    ``<figcaption>``."""
    alt = (img.get("alt") or "").strip()
    if not alt or img.find_parent("figure"):
        return
    figure = soup.new_tag("figure", attrs={"class": "docking-figure"})
    img.wrap(figure)
    caption = soup.new_tag("figcaption")
    caption.string = alt
    figure.append(caption)


def _details(soup, css: str, summary: str):
    details = soup.new_tag("details", attrs={"class": css})
    head = soup.new_tag("summary")
    head.string = summary
    details.append(head)
    return details


def _remove_tag_label(cell) -> None:
    for toolbar in cell.select(".celltoolbar"):  # the tags' names, shown as a label
        toolbar.decompose()


def _fold_outputs(soup, cell) -> None:
    """A ``fold-output`` cell: its outputs in a closed ``<details>`` (:func:`_output_summary`)."""
    _remove_tag_label(cell)
    wrapper = cell.select_one(".jp-Cell-outputWrapper") or cell.select_one(".jp-OutputArea")
    if wrapper is None:
        return
    code = cell.select_one(".jp-InputArea pre")
    details = _details(
        soup, "docking-folded-output", _output_summary(code.get_text() if code else "", wrapper)
    )
    wrapper.wrap(details)


def _fold_cell(soup, cell) -> None:
    """A ``fold`` cell: its section (a markdown cell that opens with a heading) or the cell
    alone in a closed ``<details>``; the heading becomes its summary, and its anchor (the
    contents' link) the ``<details>``'s."""
    _remove_tag_label(cell)
    heading = cell.select_one(".jp-RenderedMarkdown > :first-child")
    if heading is not None and heading.name in ("h1", "h2", "h3", "h4", "h5", "h6"):
        level = int(heading.name[1])
        section = [cell]
        for sibling in cell.find_next_siblings():
            first = sibling.select_one(".jp-RenderedMarkdown > :first-child")
            if first is not None and first.name in [f"h{k}" for k in range(1, level + 1)]:
                break
            section.append(sibling)
        summary = heading.get_text(" ", strip=True).rstrip("¶").strip()
        details = _details(soup, "docking-folded", summary)
        if heading.get("id"):
            details["id"] = heading["id"]
        heading.decompose()
        cell.insert_before(details)
        for part in section:
            details.append(part.extract())
        return
    code = cell.select_one(".jp-InputArea pre")
    comment = _leading_comment(code.get_text()) if code else ""
    text = cell.get_text("\n", strip=True)
    summary = comment or (text.splitlines()[0][:120] if text else "folded")
    details = _details(soup, "docking-folded", summary)
    cell.wrap(details)


def _leading_comment(code: str) -> str:
    """The code's first line if it is a comment ("# the verdict table" -> "the verdict
    table"), else ""."""
    first = code.strip().splitlines()[0] if code.strip() else ""
    return first.lstrip("#").strip() if first.startswith("#") else ""


def _output_summary(code: str, outputs) -> str:
    """What a folded output holds: the code's leading comment if it has one, else its first
    table's columns and rows, how many more tables, its figures and its text lines ("table of
    place, room (3 rows); 2 more tables")."""
    comment = _leading_comment(code)
    if comment:
        return comment
    parts = []
    tables = outputs.select("table")
    if tables:
        head = [th.get_text(" ", strip=True) for th in tables[0].select("tr")[0].select("th, td")]
        columns = ", ".join(h for h in head if h)
        columns = columns if len(columns) <= 90 else columns[:90].rsplit(" ", 1)[0] + " …"
        rows = max(len(tables[0].select("tr")) - 1, 0)
        parts.append(f"table of {columns} ({rows} rows)" if columns else f"table ({rows} rows)")
        if len(tables) > 1:
            parts.append(f"{len(tables) - 1} more table{'s' if len(tables) > 2 else ''}")
    figures = len(outputs.select("img"))
    if figures:
        parts.append("figure" if figures == 1 else f"{figures} figures")
    lines = sum(len(pre.get_text().strip().splitlines()) for pre in outputs.select("pre"))
    if lines:
        parts.append(f"output: {lines} line{'s' if lines > 1 else ''}")
    return "; ".join(parts) or "output"
