"""The glossary (docs/guide/glossary.md) defines every term the README's first screen and
summary lean on, and the README and the site link it."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GLOSSARY = ROOT / "docs" / "guide" / "glossary.md"

#: Terms the README uses without defining them in place.
TERMS = (
    "sideboard world",
    "floor world",
    "Nao-like world",
    "held-out trials",
    "pp",
    "yardsticks",
    "linear SARSA",
    "PPO",
    "early failure",
    "third edition",
    "addendum",
    "bracketing",
    "bracketed",
    "at the edge",
    "the gap",
    "revisit",
    "at the bound",
    "not supported",
    "finding",
    "holds by construction",
    "outside the counts",
    "rules first",
)


def defined() -> set[str]:
    """The defined terms: each bold line's words, split at commas and parentheses."""
    found = set()
    for line in GLOSSARY.read_text().splitlines():
        for bold in re.findall(r"^\*\*(.+?)\*\*", line) + re.findall(r"\*\*(.+?)\*\*:", line):
            found |= {t.strip() for t in re.split(r"[,()]", bold) if t.strip()}
    return found


@pytest.mark.parametrize("term", TERMS)
def test_each_term_is_defined(term):
    assert term in defined()


def test_readme_and_site_link_the_glossary():
    assert "(docs/guide/glossary.md)" in (ROOT / "README.md").read_text()
    assert "guide/glossary.md" in (ROOT / "docs" / "mkdocs.yml").read_text()


def test_a_term_missing_from_the_glossary_is_caught():
    assert "teleportation world" not in defined()
