"""The answer as the evidence allows it (docking.study.answer): the first screen's sentences are at
most five of at most thirty words, in every outcome the replication could have; each name
what the issue asks for; the wording follows the replication's rule."""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np
import pytest

from docking.study import answer
from docking.study.answer import Replication


def _rep(world, gap, verdict, lead, first_verdict="closed", first_lead="no lead shown"):
    from docking.study.designs import replication as rp

    paper = np.full(20, 0.94)
    return Replication(
        world,
        paper,
        paper + gap[0],
        np.full(20, 0.96),
        gap,
        verdict,
        lead,
        0.01,
        (0.02, 0.002, 0.045),
        first_verdict,
        first_lead,
        rp.wording(first_verdict, verdict, first_lead, lead),
    )


OUTCOMES = list(
    itertools.product(
        ("closed", "undecided", "remains"), ("no lead shown", "paper ahead", "linear ahead")
    )
)


@pytest.mark.parametrize("verdict, lead", OUTCOMES)
def test_the_first_screen_is_five_sentences_of_at_most_thirty_words(verdict, lead):
    found = {
        "floor": _rep(
            "floor", (0.028, 0.015, 0.041), "closed", "linear ahead", first_lead="linear ahead"
        ),
        "nao": _rep("nao", (-0.005, -0.02, 0.01), verdict, lead, first_lead="paper ahead"),
    }
    text = answer.first_screen(
        {"floor": 0.375, "nao": 0.309},
        (0.999, 0.970),
        {
            "floor": {"beta_a_train": 100.0, "eps_w": 0.5},
            "nao": {"beta_a_train": 50.0, "eps_w": 0.5},
        },
        {
            ("floor", "paper"): (234, 37),
            ("nao", "paper"): (202, 33),
            ("floor", "linear"): (81, 10),
            ("nao", "linear"): (88, 11),
        },
        found,
        {"shift": 0.67, "cm": 3.0, "home": 0.953, "higher": 0.626, "lower": 0.994},
        (10, 4, 4, 3, 4),
    )
    said = answer.sentences(text)
    assert len(said) <= answer.MAX_SENTENCES
    assert all(answer.words(s) <= answer.MAX_WORDS for s in said), [answer.words(s) for s in said]
    assert "37.5%" in said[0] and "30.9%" in said[0]  # the published settings' success
    assert "β_a" in said[1] and "100 and 50" in said[1] and "234 and 202" in said[1]
    assert "81 and 88" in said[1]  # each learner's tuning effort
    assert "relocation fails" not in text.lower() and "view shifted 0.7 [input row" in said[3]
    assert "fell from 95.3% to 62.6% (lower camera), rose to 99.4%" in said[3]
    assert "linear's floor lead replicated" in said[2]  # seen in both judgements
    replicated = lead == "paper ahead"  # the first judgement put the paper ahead
    assert ("the paper's Nao-like lead replicated" in said[2]) == replicated
    assert ("lead did not" in said[2]) == (not replicated)  # named as not replicated


def test_words_counts_a_links_text_and_not_its_address():
    assert answer.words("At its [published settings](docs/guide/glossary.md#x) it *docks*.") == 6


README = Path(__file__).resolve().parents[1] / "README.md"


def _first_screen_and_rest() -> tuple[str, str]:
    from docking.study.readme import GLANCE_END, GLANCE_START

    text = README.read_text()
    a, b = text.index(GLANCE_START), text.index(GLANCE_END)
    block = text[a + len(GLANCE_START) : b]
    lines = [line for line in block.splitlines() if re.match(r"\d\. ", line)]
    return "\n".join(lines), text[:a] + text[b:]


def test_the_readmes_first_screen_is_at_most_five_sentences_of_thirty_words():
    """Counted on the README itself, as a reader sees it (links count their text)."""
    screen, _ = _first_screen_and_rest()
    said = answer.sentences(screen)
    assert 3 <= len(said) <= answer.MAX_SENTENCES, said
    assert all(answer.words(s) <= answer.MAX_WORDS for s in said), [answer.words(s) for s in said]
    assert "β_a" in screen and "published settings" in screen and "runs" in screen
    assert "relocation fails" not in README.read_text().lower()


def test_every_number_of_the_first_screen_is_also_in_the_readmes_text():
    """No number on the first screen that the README's text (outside it) does not give."""
    screen, rest = _first_screen_and_rest()
    prose = re.sub(r"\]\([^)]*\)", "]", screen)  # links' addresses are not numbers said
    numbers = set(re.findall(r"-?\d+(?:\.\d+)?", prose))
    given = set(re.findall(r"-?\d+(?:\.\d+)?", re.sub(r"\]\([^)]*\)", "]", rest)))
    assert numbers, screen
    assert numbers <= given, sorted(numbers - given)


def test_the_readme_is_at_most_2500_words():
    assert len(README.read_text().split()) <= 2500
