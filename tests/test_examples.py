"""The Python examples of the guide's pages and of CONTRIBUTING.md run as they are written
(each in a fresh namespace, its source in ``linecache`` as Jupyter keeps a cell's, so that
``inspect`` reads the code it defines; a design file's example builds its design)."""

from __future__ import annotations

import hashlib
import linecache
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = sorted((ROOT / "docs" / "guide").glob("*.md")) + [ROOT / "CONTRIBUTING.md"]
EXAMPLES = [
    pytest.param(code, id=f"{page.name}:{k}")
    for page in PAGES
    for k, code in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(), re.S))
]


def test_the_pages_have_examples():
    assert len(EXAMPLES) >= 3


#: Libraries an example may use that the package does not install (its page says how to):
#: the example is skipped where one is missing.
OPTIONAL = ("stable_baselines3",)


@pytest.mark.parametrize("code", EXAMPLES)
def test_an_example_runs_as_written(code, tmp_path, monkeypatch):
    for name in OPTIONAL:
        if re.search(rf"^(from|import) {name}\b", code, re.M):
            pytest.importorskip(name, reason=f"the example needs {name}, not installed")
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))
    # as in a reader's session, the committed ledger: an example may read published runs
    # (the contest's rows); it computes its own runs into the empty results store
    monkeypatch.delenv("DOCKING_LEDGER", raising=False)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, remembered(code), "exec", dont_inherit=True), {"__name__": "example"})


def remembered(code: str) -> str:
    """A file name for ``code``, with its source in ``linecache`` (as Jupyter registers a
    cell's): a learner defined in an example is keyed by its source (docking.study.learners)."""
    name = f"<example {hashlib.sha256(code.encode()).hexdigest()[:12]}>"
    linecache.cache[name] = (len(code), None, code.splitlines(keepends=True), name)
    return name


#: Words of documented command lines that stand for a value the reader chooses, and the
#: design CONTRIBUTING.md writes as an example of a new one (not in the package).
PLACEHOLDERS = {"NAME", "K", "...", "two-cups"}
COMMAND_PAGES = [ROOT / "README.md", ROOT / "archive" / "README.md", *PAGES]


def _command_lines() -> list:
    """Every ``python -m docking ...`` line of the README, the archive's README, the guide's
    pages and CONTRIBUTING.md (a line ending in a backslash joined with the next; comments
    cut), as the arguments after ``docking``."""
    import shlex

    found = {}
    for page in COMMAND_PAGES:
        text = re.sub(r"\\\n\s*", " ", page.read_text())
        for match in re.finditer(r"python -m docking ([^`|\n]*)", text):
            args = shlex.split(match.group(1).split(" #")[0])
            if args and not PLACEHOLDERS & set(args):
                found[" ".join(args)] = pytest.param(args, id=f"{page.name}: {' '.join(args)}")
    return list(found.values())


COMMANDS = _command_lines()


def test_the_pages_have_command_lines():
    assert len(COMMANDS) >= 15


@pytest.mark.parametrize("args", COMMANDS)
def test_a_documented_command_line_parses(args, capsys):
    """Each documented command line is one the CLI takes (parsed, not run); ``--help``
    prints its help and exits 0."""
    from docking.study.cli import parse

    if "--help" in args or "--help-all" in args:
        with pytest.raises(SystemExit) as exit_:
            parse(args)
        assert exit_.value.code == 0
        return
    assert parse(args) is not None
