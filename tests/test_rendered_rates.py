"""The tables the README and notebook 07 show, rendered from the committed ledger: no
success rate with an interval of zero width or outside [0, 1], no "p 0"."""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

#: A success rate with its interval as the tables print it: "97.5% [96.8, 98.0]" or, in the
#: summary's sentences, "97.5% [96.8%, 98.0%]".
RATE = re.compile(r"(-?\d+\.\d+)% \[(-?\d+\.\d+)%?, (-?\d+\.\d+)%?\]")


@pytest.mark.slow
def test_the_committed_contest_and_verdicts_have_no_degenerate_rate_and_no_p_0(
    monkeypatch, tmp_path
):
    from docking.study.claims import design_verdicts
    from docking.study.designs import third_edition, third_edition_report, untested, untested_report

    monkeypatch.setenv("DOCKING_LEDGER", str(REPO / "ledger"))
    contest = third_edition.DESIGN.run(results_dir=tmp_path, progress=False)
    judged = untested.part("judged").run(results_dir=tmp_path, progress=False)
    text = third_edition_report.contest_table(
        contest, third_edition_report.CONTEST_WORLDS
    ) + third_edition_report.contest_summary(contest)
    rates = RATE.findall(text)
    assert len(rates) >= 30 + 3  # every row and world of the table, the summary's three
    for found in rates:
        estimate, low, high = map(float, found)
        assert 0 <= low <= estimate <= high <= 100 and low < high, found
    verdicts = design_verdicts(contest, (judged, untested_report.UNTESTED_IN_README))
    assert not re.search(r", p 0( |<|$)", verdicts)
    assert "identical in every trial" in verdicts  # relocation: "another wall", "second room"


def _outputs(notebook: Path) -> str:
    """Every text and Markdown output of an executed notebook, joined."""
    import json

    found = []
    for cell in json.loads(notebook.read_text())["cells"]:
        for output in cell.get("outputs", []):
            data = output.get("data", {})
            for kind in ("text/markdown", "text/plain"):
                text = data.get(kind)
                if text:
                    found.append("".join(text) if isinstance(text, list) else text)
            if output.get("text"):
                found.append("".join(output["text"]))
    return "\n".join(found)


@pytest.mark.docs
@pytest.mark.parametrize("name", sorted(p.stem for p in (REPO / "notebooks").glob("[0-9]*.py")))
def test_no_rendered_percentage_has_a_zero_width_interval_or_exceeds_100(name):
    """The executed notebooks (make test writes their outputs before the docs tests): no
    percentage with an interval of zero width, none above 100%, and no "p 0"."""
    notebook = REPO / "notebooks" / f"{name}.ipynb"
    if not notebook.exists():
        pytest.skip(f"{notebook.name} is not executed here (make test executes it)")
    text = _outputs(notebook)
    for found in RATE.findall(text):
        estimate, low, high = map(float, found)
        assert low < high and high <= 100 and estimate <= 100, (name, found)
    assert not re.search(r", p 0( |<|$)", text), name
