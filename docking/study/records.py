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

__all__ = ["data", "digest", "exists", "folder", "parts", "procedure", "replay", "text"]


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
