"""The Python examples of the guide's pages and of CONTRIBUTING.md run as they are written
(each in a fresh namespace; a design file's example builds its design)."""

from __future__ import annotations

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


@pytest.mark.parametrize("code", EXAMPLES)
def test_an_example_runs_as_written(code, tmp_path, monkeypatch):
    monkeypatch.setenv("DOCKING_RESULTS", str(tmp_path / "results"))
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "<example>", "exec"), {"__name__": "example"})
