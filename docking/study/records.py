"""Pre-registered rules kept as records (``rules/`` beside the package, committed before a
design's runs): a design's rules text as data, and for a procedural rule a verbatim copy of
the procedure's source as it was committed, never imported.

A record ``rules/<design>.json.gz`` holds the rules text whose SHA-256 the design's test
pins (:func:`text`); ``rules/<design>.procedure.py.txt`` (:func:`procedure`) the source the
text's ``procedure`` digest names. The live design is checked against them: its constants and
cells equal the record's, and its procedure, replayed on the ledger's runs, gives the cells
and verdicts the recorded procedure gives (tests/test_equal_contest.py).
"""

from __future__ import annotations

import gzip
import hashlib
import json
from pathlib import Path

__all__ = [
    "amended",
    "amendments",
    "data",
    "digest",
    "exists",
    "folder",
    "in_force_digest",
    "parts",
    "procedure",
    "replay",
    "text",
]


def folder() -> Path:
    """The records' folder: ``rules/`` in the checkout (a wheel carries none)."""
    return Path(__file__).resolve().parents[2] / "rules"


def _path(name: str, suffix: str) -> Path:
    path = folder() / f"{name}{suffix}"
    if not path.is_file():
        raise FileNotFoundError(
            f"no rules record {path}: records live in the checkout's rules/ folder"
        )
    return path


def text(name: str) -> str:
    """The recorded rules text of design ``name``."""
    return gzip.decompress(_path(name, ".json.gz").read_bytes()).decode()


def data(name: str) -> dict:
    """The recorded rules of design ``name``, parsed."""
    return json.loads(text(name))


def digest(name: str) -> str:
    """The SHA-256 of the recorded rules text (what the design's test pins)."""
    return hashlib.sha256(text(name).encode()).hexdigest()


def procedure(name: str) -> str:
    """The verbatim source of design ``name``'s procedure as committed with its rules."""
    return _path(name, ".procedure.py.txt").read_text()


def parts(name: str) -> list[tuple[str, str, str]]:
    """The verbatim copy of design ``name``'s procedure in its parts, in the order the rules'
    digest read them: ``(kind, name, text)`` with kind ``"module"`` or ``"function"``."""
    found = []
    for chunk in procedure(name).split("# ==== ")[1:]:
        head, _, body = chunk.partition("\n")
        kind, _, what = head.partition(" ")
        found.append((kind, what, body))
    return found


def exists(name: str) -> bool:
    """Whether design ``name`` has a rules record."""
    return (folder() / f"{name}.json.gz").is_file()


def replay(name: str) -> dict:
    """What design ``name``'s rules gave on the committed ledger's runs when its record was
    written (:func:`docking.study.designs.replay`)."""
    return json.loads(_path(name, ".replay.json").read_text())


def amendments(name: str) -> list[dict]:
    """The amendments of design ``name``'s rules, in order (``[]`` if none): each
    ``{"design", "number", "path", "before", "after", "why", "seen"}``, ``path`` the keys and
    indices into :func:`data` of the one value it changes."""
    found = []
    for path in sorted(folder().glob(f"{name}.amendment-*.json")):
        amendment = json.loads(path.read_text())
        if amendment.get("design") != name:
            raise ValueError(f"{path} amends {amendment.get('design')!r}, not {name!r}")
        found.append(amendment)
    found.sort(key=lambda a: a["number"])
    if [a["number"] for a in found] != list(range(1, len(found) + 1)):
        raise ValueError(f"{name}'s amendments are not numbered 1, 2, ...: {found!r}")
    return found


def amended(name: str) -> dict:
    """The rules of design ``name`` in force: its record (:func:`data`) with its amendments
    applied, each checked to change the value it says it changes from the value it says."""
    rules = data(name)
    for amendment in amendments(name):
        *parents, last = amendment["path"]
        place = rules
        for key in parents:
            place = place[key]
        if place[last] != amendment["before"]:
            raise ValueError(
                f"{name}'s amendment {amendment['number']}: {amendment['path']} is "
                f"{place[last]!r}, not {amendment['before']!r} as it says"
            )
        place[last] = amendment["after"]
    return rules


def in_force_digest(name: str) -> str:
    """The SHA-256 of design ``name``'s rules in force: the record's text's (:func:`digest`)
    where it has no amendment, else of that text followed by each amendment record's bytes, in
    order. What the ledger records beside each of the design's runs."""
    files = sorted(
        folder().glob(f"{name}.amendment-*.json"), key=lambda p: int(p.stem.rsplit("-", 1)[1])
    )
    if not files:
        return digest(name)
    found = hashlib.sha256(text(name).encode())
    for path in files:
        found.update(path.read_bytes())
    return found.hexdigest()
