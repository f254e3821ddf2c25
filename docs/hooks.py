"""The site's mkdocs hooks (docs/mkdocs.yml: ``hooks``): what nbconvert's template leaves out
of a notebook page.

- A figure's alt text: the template writes none (nbconvert then puts "No description has been
  provided for this image"); docs/build.py writes each figure's caption into its output's
  metadata, ``image/png`` -> ``alt``, where IPython's ``Image(alt=...)`` puts it and
  JupyterLab reads it, and here it becomes the ``<img>``'s ``alt``.
- Cells tagged ``hide-input`` (Jupyter Book's tag; docs/build.py gives it to the notebooks'
  import blocks): their code folded in a ``<details>`` whose summary says what it holds.
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
