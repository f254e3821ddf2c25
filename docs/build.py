"""Build the documentation site (``make docs``): the README, the executed notebooks with their
outputs, the figures, CONTRIBUTING and the API reference, as a static mkdocs site in
``build/site`` that needs no server and no network (MathJax is served from the site).

``make test`` executes every notebook under ``pytest --nbmake --overwrite``, which writes its
outputs into ``notebooks/*.ipynb``; this script copies those. A notebook that has no
``.ipynb``, one without outputs, or one older than its ``.py`` source is executed here first
(``jupytext`` then ``jupyter nbconvert --execute``), reading its runs from the results store
or the committed ledger, so ``make docs`` works in a fresh clone without ``make test``.

    python docs/build.py [--out build/site]
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCE = ROOT / "build" / "site-src"

#: The API reference: one page per layer of the package (CONTRIBUTING's layer table).
API_MODULES = (
    "docking.design",
    "docking.claims",
    "docking.experiments",
    "docking.scene",
    "docking.world",
    "docking.network",
    "docking.trial",
    "docking.policies",
    "docking.analysis",
    "docking.stats",
    "docking.store",
    "docking.ledger",
    "docking.sweep",
    "docking.gym",
    "docking.ppo",
)

MATHJAX_CONFIG = """window.MathJax = window.MathJax || {};
MathJax.Hub && MathJax.Hub.Config({});
"""


def _executed(path: Path) -> bool:
    cells = json.loads(path.read_text())["cells"]
    return any(c.get("outputs") for c in cells if c["cell_type"] == "code")


def _markdown(text: str) -> str:
    """README/CONTRIBUTING links made site links: notebooks' .py sources to their pages."""
    text = re.sub(r"\(((?:notebooks|archive)/\d\d_\w+)\.py\)", r"(\1.ipynb)", text)
    return text.replace("(CONTRIBUTING.md)", "(contributing.md)")


def _execute(source: Path, nb: Path) -> None:
    """Write ``nb`` from its jupytext ``source`` and execute it in place (its runs come from the
    results store or the committed ledger; a run that neither holds is computed)."""
    print(f"executing {source.relative_to(ROOT)} (no executed copy, or an older one)", flush=True)
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
    (SOURCE / "index.md").write_text(_markdown((ROOT / "README.md").read_text()))
    (SOURCE / "contributing.md").write_text(_markdown((ROOT / "CONTRIBUTING.md").read_text()))
    shutil.copytree(ROOT / "figures", SOURCE / "figures")
    shutil.copy(ROOT / "docs" / "extra.css", SOURCE / "extra.css")
    sources = sorted((ROOT / "notebooks").glob("[0-9]*.py"))
    if not sources:
        raise SystemExit("no notebooks/*.py: is this the project's checkout?")
    for source in sources:
        nb = source.with_suffix(".ipynb")
        if not (nb.exists() and _executed(nb) and nb.stat().st_mtime >= source.stat().st_mtime):
            _execute(source, nb)
        shutil.copy(nb, SOURCE / "notebooks" / nb.name)
    # The archived notebooks (archive/README.md): executed at an earlier commit, copied as
    # they are.
    shutil.copytree(ROOT / "archive", SOURCE / "archive", ignore=shutil.ignore_patterns("*.py"))
    api = ["# API reference", ""]
    for module in API_MODULES:
        api += [
            f"## `{module}`",
            "",
            f"::: {module}",
            "    options:",
            "      show_root_heading: false",
            "",
        ]
    (SOURCE / "api.md").write_text("\n".join(api))
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
