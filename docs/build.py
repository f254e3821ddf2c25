"""Build the documentation site (``make docs``): the README, the executed notebooks with their
outputs, the figures, CONTRIBUTING and the API reference, as a static mkdocs site in
``build/site`` that needs no server and no network (MathJax is served from the site).

What the site shows beyond the sources' text: each figure's caption as its alt text (the
README's figure table for the figures it shows; a caption the notebook passes, as with
IPython's ``Image(alt=...)``; else the notebook's text before the figure), each notebook
figure as a PNG file of its own that opens full size (docs/mkdocs.yml: glightbox), its caption
visible beneath it, the notebooks' import blocks folded (tagged ``hide-input``), and what the
notebooks' sources tag ``fold-output`` or ``fold`` folded too (docs/hooks.py renders the tags,
the alt text and the captions, which nbconvert's template leaves out); and an animation of one
episode per world (:data:`ANIMATIONS`, docs/guide/worlds.md).

``make test`` executes every notebook under ``pytest --nbmake --overwrite``, which writes its
outputs into ``notebooks/*.ipynb``; this script copies those. A notebook that has no
``.ipynb``, one without outputs, or one older than its ``.py`` source is executed here first
(``jupytext`` then ``jupyter nbconvert --execute``), reading its runs from the results store
or the committed ledger, so ``make docs`` works in a fresh clone without ``make test``; such
notebooks are executed side by side, one per core (at most four), as nbmake runs them.

    python docs/build.py [--out build/site]
"""

from __future__ import annotations

import argparse
import ast
import base64
import concurrent.futures
import copy
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCE = ROOT / "build" / "site-src"

#: The API reference: one page per layer of the package (its two folders).
API_MODULES = (
    "docking.study.design",
    "docking.study.claims",
    "docking.experiments",
    "docking.scene",
    "docking.world",
    "docking.network",
    "docking.trial",
    "docking.policies",
    "docking.study.arrays",
    "docking.study.analysis",
    "docking.study.stats",
    "docking.study.store",
    "docking.study.learners",
    "docking.protocol",
    "docking.study.contest",
    "docking.study.ledger",
    "docking.study.sweep",
    "docking.gym",
    "docking.study.ppo",
)

#: The API reference's pages, one per layer (pyproject.toml's import contract names them).
API_TITLES = {"core": "the docking library", "study": "the study layer"}
API_INTROS = {
    "core": "The world, the camera, the network and its trials, the experiments: what a run "
    "computes. It never imports the study layer (`lint-imports` checks it).",
    "study": "Runs stored, keyed and served from the ledger; designs, claims and statistics; "
    "sweeps, learners and the contest: how the study asks its questions.",
}


def _api_layers() -> dict[str, list[str]]:
    """``{"core": [...], "study": [...]}``: :data:`API_MODULES` by folder, as the import
    contract "the core never imports the study layer" in pyproject.toml names them (its source
    modules, docking/'s top level; its forbidden modules, docking/study/); a module in neither
    is refused."""
    import tomllib

    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    name = "the core never imports the study layer"
    (contract,) = [c for c in contracts["contracts"] if c["name"] == name]
    found = {"core": [], "study": []}
    for module in API_MODULES:
        if module in contract["source_modules"]:
            found["core"].append(module)
        elif any(module.startswith(f"{side}.") for side in contract["forbidden_modules"]):
            found["study"].append(module)
        else:
            raise ValueError(f"{module} is in neither layer of pyproject.toml's import contract")
    return found


MATHJAX_CONFIG = """window.MathJax = window.MathJax || {};
MathJax.Hub && MathJax.Hub.Config({});
"""


#: The worlds' animations (docs/guide/worlds.md): file name, the preset of the Gymnasium id
#: (:func:`docking.gym.preset_world`), the label on each frame, the start's seed.
ANIMATIONS = (
    ("world-sideboard", "experiment2", "sideboard world (docking/Experiment2-v0)", 0),
    ("world-floor", "floor", "floor world (docking/Floor-v0)", 0),
    ("world-nao", "nao", "Nao-like world (docking/Nao-v0)", 0),
)


def _animations(folder: Path) -> None:
    """One episode of each world of :data:`ANIMATIONS` as a GIF in ``folder``: the pose
    oracle's frames, the robot's input inset (:func:`docking.study.episodes.episode_frames`),
    captioned and written by :func:`docking.study.figures.episode_images` and
    :func:`docking.study.figures.save_gif`."""
    from docking.gym import preset_world
    from docking.study.episodes import episode_frames
    from docking.study.figures import episode_images, save_gif

    for name, preset, label, seed in ANIMATIONS:
        world = preset_world(preset)
        frames, actions, docked = episode_frames(world, seed)
        images = episode_images(frames, actions, docked, world.action_names, label=label)
        save_gif(images, folder / f"{name}.gif")


#: The notebook whose displays carry the paper's equation numbers (the site's copy).
EQUATIONS = "notebooks/01_gradient.ipynb"

#: A code cell's leading imports are folded when they take at least this many lines (a cell of
#: imports only is folded however short).
FOLDED_IMPORT_LINES = 3

#: TeX commands of the notebooks' text, as plain text for an alt attribute.
_TEX = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "Delta": "Δ", "varepsilon": "ε",
    "epsilon": "ε", "theta": "θ", "pi": "π", "sigma": "σ", "sum": "Σ", "propto": "∝",
    "partial": "∂", "approx": "≈", "neq": "≠", "leq": "≤", "geq": "≥", "times": "×",
    "pm": "±", "cdot": "·",
}  # fmt: skip


def _plain(text: str) -> str:
    """Markdown with TeX as one line of plain text (for an ``alt`` attribute)."""
    text = re.sub(r"\$+([^$]*)\$+", lambda m: _plain_tex(m.group(1)), text)
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links, images: their text
    text = re.sub(r"(\*\*|__|\*|`)", "", text)
    return " ".join(text.split())


def _plain_tex(tex: str) -> str:
    tex = re.sub(r"\\([A-Za-z]+)", lambda m: _TEX.get(m.group(1), ""), tex)
    return " ".join(re.sub(r"[{}\\]", "", tex).split())


def _readme_captions(readme: str) -> dict[str, str]:
    """The README's figure table: ``figures/NAME.png`` -> the caption beside the image (its
    bold title set off by a dash unless the sentence runs on: "Fig. 2 — the scene: ...",
    "Where W changed in Experiment 2 ...")."""
    captions = {}
    # the caption runs to the table's next cell, or to the end of its paragraph
    for m in re.finditer(r"!\[[^\]]*\]\((figures/[^)\s]+)\)((?:[^|\n]|\n(?!\s*\n))*)", readme):
        caption = re.sub(
            r"^\s*\*\*([^*]+)\*\*\s+(?=[A-Za-z])(?!(?:in|of|on|at|for|from|with)\b)",
            r"\1 — ",
            m.group(2).split("<!--")[0],  # a generated block's end marker ends its caption
        )
        captions[m.group(1)] = _plain(caption)
    return captions


def _with_captions(readme: str, captions: dict[str, str]) -> str:
    """The README's figures with their captions as alt text (``![Fig. 2](...)`` has only
    "Fig. 2")."""

    def alt(m: re.Match) -> str:
        caption = captions.get(m.group(2), m.group(1)).replace("[", "(").replace("]", ")")
        return f"![{caption}]({m.group(2)})"

    return re.sub(r"!\[([^\]]*)\]\(([^)\s]+)\)", alt, readme)


def _fold_imports(cell: dict) -> list[dict]:
    """A code cell that opens with a block of imports: the block as a cell of its own, tagged
    ``hide-input`` (shown folded), and the rest, with the outputs, as another."""
    if cell["cell_type"] != "code":
        return [cell]
    source = "".join(cell["source"])
    try:
        body = ast.parse(source).body
    except SyntaxError:
        return [cell]
    n = next(
        (i for i, node in enumerate(body) if not isinstance(node, (ast.Import, ast.ImportFrom))),
        len(body),
    )
    if n == 0:
        return [cell]
    lines = source.splitlines(keepends=True)
    end = body[n - 1].end_lineno
    imports, rest = "".join(lines[:end]).strip("\n"), "".join(lines[end:]).strip("\n")
    if rest and end < FOLDED_IMPORT_LINES:
        return [cell]
    folded = copy.deepcopy(cell)
    tags = folded["metadata"].setdefault("tags", [])
    if "hide-input" not in tags:  # a cell hidden already keeps one tag (nbformat: unique)
        tags.append("hide-input")
    folded["source"] = imports
    if not rest:
        return [folded]
    folded["outputs"], folded["execution_count"] = [], None
    if "id" in cell:
        folded["id"] = f"{cell['id']}-imports"
    rest_cell = copy.deepcopy(cell)
    rest_cell["source"] = rest
    return [folded, rest_cell]


def _leading_text(cells: list[dict], index: int) -> str:
    """The notebook's text before cell ``index``: the heading of its section and the paragraph
    right before the cell (its last sentence if it ends in a colon, "One trial from a random
    start:"; else its first sentences)."""
    heading, paragraphs = "", []
    for cell in reversed(cells[:index]):
        if cell["cell_type"] != "markdown":
            if paragraphs or heading:
                break
            continue
        blocks = [b.strip() for b in re.split(r"\n\s*\n", "".join(cell["source"])) if b.strip()]
        for block in reversed(blocks):
            if block.startswith("#"):
                heading = block.lstrip("#").strip()
                break
            paragraphs.insert(0, block)
        if heading:
            break
    lead = ""
    if paragraphs and paragraphs[-1].endswith(":"):
        lead = _sentences(_plain(paragraphs[-1]))[-1].rstrip(":")
    elif paragraphs:
        lead = _first_sentences(_plain(paragraphs[-1]))
    heading = _plain(heading)
    return f"{heading}: {lead}" if heading and lead else heading or lead


def _sentences(text: str) -> list[str]:
    return re.split(r"(?<=[.!?])\s+(?=[A-Z(\"“])", text)


def _first_sentences(text: str, limit: int = 240) -> str:
    """The sentences of ``text`` that fit ``limit`` characters (at least the first, cut at a
    word with an ellipsis if it alone is longer)."""
    sentences = _sentences(text)
    kept = sentences[0]
    for sentence in sentences[1:]:
        if len(kept) + 1 + len(sentence) > limit:
            break
        kept += " " + sentence
    if len(kept) > limit:
        kept = kept[:limit].rsplit(" ", 1)[0] + " …"
    return kept


#: A display equation's number as the notebooks write it, "... \quad (8)$$", two equations of
#: a display set apart by "\qquad".
_NUMBERED = re.compile(r"\\quad\s*\((\d+)\)\s*(?:\\qquad\s*|$)")


def _tagged(markdown: str) -> str:
    """The paper's equation numbers as MathJax tags: "$$A \\quad (1) \\qquad B \\quad (2)$$"
    becomes "$$A \\tag{1}$$" and "$$B \\tag{2}$$", each equation centred on its line and
    its number at the right margin, as in the paper (and an anchor, ``#mjx-eqn-1``). A display
    whose text does not end in its number is left as it is."""

    def tag(m: re.Match) -> str:
        parts = _NUMBERED.split(m.group(1).strip())
        if len(parts) < 3 or parts[-1].strip():
            return m.group(0)
        pairs = zip(parts[0:-1:2], parts[1:-1:2], strict=True)
        return "\n\n".join(f"$${tex.strip()} \\tag{{{n}}}$$" for tex, n in pairs)

    return re.sub(r"\$\$(.+?)\$\$", tag, markdown, flags=re.S)


#: A mention of the paper's equations in the text: "Eq. 8", "Eq. (7)-(8)", "Eqs. 5-6".
_MENTION = re.compile(r"\b(Eqs?\.\s?)((?:\(\d+\)|\d+)(?:\s?[-–,]\s?(?:\(\d+\)|\d+))*)")
#: What a mention is not looked for in: code spans, TeX, links.
_NOT_TEXT = re.compile(r"(`[^`]*`|\$\$.*?\$\$|\$[^$]*\$|\[[^\]]*\]\([^)]*\))")


def _linked(markdown: str, target: str, numbers: set[str]) -> str:
    """Each number of a mention of the paper's equations ("Eq. (8)") a link to the equation in
    notebook 01 (``target``: its page, relative to the text's), whose displays carry the
    paper's numbers (``numbers``); headings and code left as they are."""

    def number(m: re.Match) -> str:
        n = m.group(0).strip("()")
        return f"[{m.group(0)}]({target}#mjx-eqn-{n})" if n in numbers else m.group(0)

    def mention(m: re.Match) -> str:
        return m.group(1) + re.sub(r"\(\d+\)|\d+", number, m.group(2))

    lines, fenced = [], False
    for line in markdown.split("\n"):
        if line.lstrip().startswith(("```", "~~~")):
            fenced = not fenced
        if fenced or line.lstrip().startswith(("#", "```", "~~~")):
            lines.append(line)
            continue
        parts = _NOT_TEXT.split(line)  # odd: code, TeX, links
        lines.append("".join(p if i % 2 else _MENTION.sub(mention, p) for i, p in enumerate(parts)))
    return "\n".join(lines)


def _equation_numbers(notebook: Path) -> set[str]:
    """The equation numbers that the displays of ``notebook`` (the site's copy) carry."""
    cells = json.loads(notebook.read_text())["cells"]
    text = "".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
    return set(re.findall(r"\\tag\{(\d+)\}", text))


#: A Jupyter widget's output (its view of the notebook's widget state).
WIDGET = "application/vnd.jupyter.widget-view+json"


def _site_notebook(path: Path, captions: dict[str, str]) -> None:
    """Rewrite the site's copy of a notebook (``path``, in build/site-src): equation numbers
    as MathJax tags, import blocks tagged ``hide-input``, each PNG figure a file of its own
    (the same file as the README's when the figure is one of ``figures/``), its caption in the
    output's metadata. Jupyter widgets (tqdm's progress bars) are shown by their text: their
    state would make the page load the widgets' script from unpkg.com, and the site asks for
    nothing beyond its own files."""
    nb = json.loads(path.read_text())
    nb["metadata"].pop("widgets", None)
    for cell in (c for c in nb["cells"] if "outputs" in c):
        for output in cell["outputs"]:
            output.get("data", {}).pop(WIDGET, None)
        cell["outputs"] = [o for o in cell["outputs"] if o.get("data", True)]
    nb["cells"] = [part for cell in nb["cells"] for part in _fold_imports(cell)]
    for cell in nb["cells"]:
        if cell["cell_type"] == "markdown":
            cell["source"] = _unbroken(_tagged("".join(cell["source"])))
        for output in cell.get("outputs", []):
            if "text/markdown" in output.get("data", {}):
                markdown = "".join(output["data"]["text/markdown"])
                output["data"]["text/markdown"] = _unbroken(markdown)
    known = {
        hashlib.sha256(png.read_bytes()).hexdigest(): f"figures/{png.name}"
        for png in (ROOT / "figures").glob("*.png")
    }
    files = path.parent / f"{path.stem}_files"
    count = 0
    for index, cell in enumerate(nb["cells"]):
        for output in cell.get("outputs", []):
            png = output.get("data", {}).get("image/png")
            if png is None:
                continue
            data = base64.b64decode(png)
            figure = known.get(hashlib.sha256(data).hexdigest())
            if figure:
                src = f"../{figure}"  # notebooks/ and archive/ are beside figures/
            else:
                count += 1
                files.mkdir(exist_ok=True)
                (files / f"figure-{count}.png").write_bytes(data)
                src = f"{files.name}/figure-{count}.png"
            metadata = output.setdefault("metadata", {})
            image = metadata.setdefault("image/png", {})
            image["alt"] = _plain(
                image.get("alt") or captions.get(figure) or _leading_text(nb["cells"], index)
            )
            metadata.setdefault("filenames", {})["image/png"] = src
    path.write_text(json.dumps(nb, indent=1, ensure_ascii=False))


def _layers():
    """tools/layers.py (the core's and the study layer's modules and lines), as a module."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("layers", ROOT / "tools" / "layers.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _executed(path: Path) -> bool:
    cells = json.loads(path.read_text())["cells"]
    return any(c.get("outputs") for c in cells if c["cell_type"] == "code")


def _markdown(text: str) -> str:
    """README/CONTRIBUTING links made site links: notebooks' .py sources to their pages."""
    text = re.sub(r"\(((?:notebooks|archive)/\d\d_\w+)\.py\)", r"(\1.ipynb)", text)
    text = re.sub(r"\(docs/guide/(\w+\.md)(#[\w-]+)?\)", r"(guide/\1\2)", text)
    return _unbroken(text.replace("(CONTRIBUTING.md)", "(contributing.md)"))


#: An interval of a table's cell, "[95.8, 98.6]", and a number with its unit, "29.4 pp".
_INTERVAL = re.compile(r"\[(-?\d+(?:\.\d+)?),\s(-?\d+(?:\.\d+)?)\]")
_UNIT = re.compile(r"(\d) (pp|cm|deg)\b")


def _unbroken(markdown: str) -> str:
    """A table's intervals and numbers with their units kept on one line (no-break spaces), so
    that a narrow column breaks between "97.2%" and "[95.8, 98.6]", not inside the interval."""
    lines = []
    for line in markdown.split("\n"):
        if line.lstrip().startswith("|"):
            line = _UNIT.sub("\\1\u00a0\\2", _INTERVAL.sub("[\\1,\u00a0\\2]", line))
        lines.append(line)
    return "\n".join(lines)


def _execute(source: Path, nb: Path) -> None:
    """Write ``nb`` from its jupytext ``source`` and execute it in place (its runs come from the
    results store or the committed ledger; a run that neither holds is computed)."""
    # one write, so that the lines of notebooks executed side by side do not run together
    print(
        f"executing {source.relative_to(ROOT)} (no executed copy, or an older one)\n",
        end="",
        flush=True,
    )
    bin_dir = Path(sys.executable).parent
    subprocess.run(
        [bin_dir / "jupytext", "--quiet", "--to", "ipynb", "--output", nb, source], check=True
    )
    subprocess.run(
        [
            bin_dir / "jupyter",
            "nbconvert",
            "--to",
            "notebook",
            "--execute",
            "--inplace",
            "--ExecutePreprocessor.timeout=-1",
            nb,
        ],
        check=True,
        cwd=ROOT,
    )


def prepare() -> Path:
    if SOURCE.exists():
        shutil.rmtree(SOURCE)
    (SOURCE / "notebooks").mkdir(parents=True)
    readme = (ROOT / "README.md").read_text()
    captions = _readme_captions(readme)
    (SOURCE / "index.md").write_text(_with_captions(_markdown(readme), captions))
    (SOURCE / "contributing.md").write_text(_markdown((ROOT / "CONTRIBUTING.md").read_text()))
    # The guides (docs/guide/): the README's long material, one page each.
    (SOURCE / "guide").mkdir()
    layers = _layers()
    for guide in sorted((ROOT / "docs" / "guide").glob("*.md")):
        text = _markdown(guide.read_text()).replace("](guide/", "](")
        text = text.replace(layers.MARK, layers.table())  # layers.md: the sizes, as built
        (SOURCE / "guide" / guide.name).write_text(text.replace("](notebooks/", "](../notebooks/"))
    shutil.copytree(ROOT / "figures", SOURCE / "figures")
    _animations(SOURCE / "figures" / "worlds")  # docs/guide/worlds.md
    shutil.copy(ROOT / "docs" / "extra.css", SOURCE / "extra.css")
    sources = sorted((ROOT / "notebooks").glob("[0-9]*.py"))
    if not sources:
        raise SystemExit("no notebooks/*.py: is this the project's checkout?")
    stale = [
        source
        for source in sources
        if not (
            (nb := source.with_suffix(".ipynb")).exists()
            and _executed(nb)
            and nb.stat().st_mtime >= source.stat().st_mtime
        )
    ]
    # executed as nbmake does in make test: one notebook per core (each is a kernel of its
    # own; they read the ledger and write figures of their own)
    with concurrent.futures.ThreadPoolExecutor(max(1, min(os.cpu_count() or 1, 4))) as pool:
        for done in [pool.submit(_execute, s, s.with_suffix(".ipynb")) for s in stale]:
            done.result()
    for source in sources:
        nb = source.with_suffix(".ipynb")
        shutil.copy(nb, SOURCE / "notebooks" / nb.name)
    # The archived notebooks (archive/README.md): executed at an earlier commit, copied as
    # they are.
    shutil.copytree(ROOT / "archive", SOURCE / "archive", ignore=shutil.ignore_patterns("*.py"))
    for nb in sorted(SOURCE.glob("*/*.ipynb")):
        _site_notebook(nb, captions)
    # Mentions of the paper's equations linked to them, in notebook 01.
    numbers = _equation_numbers(SOURCE / EQUATIONS)
    for page in (SOURCE / "index.md", SOURCE / "contributing.md"):
        page.write_text(_linked(page.read_text(), EQUATIONS, numbers))
    for page in sorted((SOURCE / "guide").glob("*.md")):
        page.write_text(_linked(page.read_text(), f"../{EQUATIONS}", numbers))
    for nb in sorted(SOURCE.glob("*/*.ipynb")):
        own = nb.relative_to(SOURCE).as_posix() == EQUATIONS
        target = "" if own else Path("..", EQUATIONS).with_suffix(".html").as_posix()
        notebook = json.loads(nb.read_text())
        for cell in notebook["cells"]:
            if cell["cell_type"] == "markdown":
                cell["source"] = _linked("".join(cell["source"]), target, numbers)
        nb.write_text(json.dumps(notebook, indent=1, ensure_ascii=False))
    (SOURCE / "api").mkdir(exist_ok=True)
    for layer, modules in _api_layers().items():
        api = [f"# API reference: {API_TITLES[layer]}", "", API_INTROS[layer], ""]
        for module in modules:
            api += [
                f"## `{module}`",
                "",
                f"::: {module}",
                "    options:",
                "      show_root_heading: false",
                "",
            ]
        (SOURCE / "api" / f"{layer}.md").write_text("\n".join(api))
    import jupyter_server_mathjax

    mathjax = Path(jupyter_server_mathjax.__file__).parent / "static"
    shutil.copytree(mathjax, SOURCE / "mathjax")
    (SOURCE / "mathjax-config.js").write_text(
        "window.MathJax = {tex2jax: {inlineMath: [['$', '$'], ['\\\\(', '\\\\)']],"
        " displayMath: [['$$', '$$'], ['\\\\[', '\\\\]']], processEscapes: true},"
        # the bundle (jupyter_server_mathjax) carries STIX-Web's font data only: with TeX's
        # asked for, a glyph such as v' fetched TeX's fontdata.js, which is not there, and
        # showed "[Math Processing Error]"
        " 'HTML-CSS': {availableFonts: ['STIX-Web'], preferredFont: 'STIX-Web',"
        " webFont: 'STIX-Web', imageFont: null}};\n"
    )
    return SOURCE


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "build" / "site")
    args = parser.parse_args(argv)
    prepare()
    mkdocs = Path(sys.executable).with_name("mkdocs")
    return subprocess.call(
        [
            str(mkdocs),
            "build",
            "-f",
            str(ROOT / "docs" / "mkdocs.yml"),
            "--site-dir",
            str(args.out.resolve()),
        ],
        cwd=ROOT,
    )


if __name__ == "__main__":
    raise SystemExit(main())
