"""One answer, served everywhere (issue 59): the README's table of the equal contest, the glance
figure's points and contest()'s current published rows are the same numbers, read from the
committed ledger; the README's first screen says the verdicts the equal contest's rules reach."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _readme_rows() -> dict[str, tuple[str, str, str]]:
    """``{world name: (paper, linear, PPO)}`` of the README's verdict table of the equal contest."""
    text = (ROOT / "README.md").read_text()
    block = text.split("<!-- summary:start -->", 1)[1].split("<!-- summary:end -->", 1)[0]
    table = block.split("| world | the paper's learner | linear SARSA | PPO |", 1)[1]
    found = {}
    for line in table.splitlines()[2:]:
        if not line.startswith("| "):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        found[cells[0]] = tuple(cells[1:4])
    return found


@pytest.mark.slow
def test_the_readme_the_glance_figure_and_the_contest_serve_the_same_numbers(monkeypatch):
    from docking.study import contest
    from docking.study.designs import equal_contest as ec
    from docking.study.designs import equal_contest_report as ecr
    from docking.study.designs import third_edition as te

    monkeypatch.setenv("DOCKING_LEDGER", str(ROOT / "ledger"))
    equal = ec.DESIGN.read()
    worlds, learners, seeds, _ = ecr.glance_data(equal, te.part("contest").run(progress=False))
    shown = contest.published()
    readme = _readme_rows()
    names = dict(zip(ec.WORLDS, worlds, strict=True))
    for world in ec.WORLDS:
        row = readme[ecr.WORLD_NAMES[world]]
        for k, learner in enumerate(ec.LEARNERS):
            served = shown.score(f"{world}/{learner}/judged")
            drawn = seeds[names[world], learners[k + 1]]
            np.testing.assert_array_equal(served, drawn)
            assert row[k] == f"{100 * served.mean():.1f}%", (world, learner)


@pytest.mark.slow
def test_the_first_screen_says_the_rules_verdicts(monkeypatch):
    from docking.study.designs import equal_contest as ec
    from docking.study.designs import equal_contest_report as ecr

    monkeypatch.setenv("DOCKING_LEDGER", str(ROOT / "ledger"))
    verdicts = ecr.verdicts(ec.DESIGN.read())
    text = (ROOT / "README.md").read_text()
    screen = text.split("<!-- glance:start -->", 1)[1].split("<!-- glance:end -->", 1)[0]
    leads = "/".join(f"{100 * v['lead']:.1f}" for v in verdicts.values())
    assert f"linear SARSA's lead (sideboard/floor/Nao-like): {leads} pp" in screen
    assert "closed" not in screen.lower()
    assert re.search(r"notebook 0?5\b", screen) is None
