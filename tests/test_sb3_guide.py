"""The guide's Stable-Baselines3 page (docs/guide/sb3.md): its example, at most 40 lines, saved
as a script in a folder of its own and run from another, prints its contest table. Skipped,
saying so, where stable-baselines3 is not installed (the package's environment does not
install torch)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "guide" / "sb3.md"


def _example() -> str:
    (code,) = re.findall(r"```python\n(.*?)```", PAGE.read_text(), re.S)
    return code


def test_the_example_is_at_most_40_lines_and_enters_the_contest():
    code = _example()
    assert len([line for line in code.splitlines() if line.strip()]) <= 40
    assert "learners.register(" in code and "contest(" in code and "learners.judge(" in code
    assert 'streams(seed)["train_world"]' in code  # trains on the training stream
    assert "guide/sb3.md" in (ROOT / "docs" / "mkdocs.yml").read_text()


@pytest.mark.slow
def test_the_example_runs_from_another_folder(tmp_path):
    pytest.importorskip(
        "stable_baselines3", reason="stable-baselines3 is not installed: the SB3 page's example"
    )
    folder, elsewhere = tmp_path / "mine", tmp_path / "elsewhere"
    folder.mkdir()
    elsewhere.mkdir()
    (folder / "sb3_contest.py").write_text(_example())
    env = {**os.environ, "DOCKING_RESULTS": str(tmp_path / "results")}
    env["DOCKING_LEDGER"] = str(ROOT / "ledger")
    out = subprocess.run(
        [sys.executable, str(folder / "sb3_contest.py")],
        cwd=elsewhere,
        env=env,
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stdout.startswith("**Not the contest: a smaller budget**")
    assert "| **sb3-ppo, chosen (yours)** |" in out.stdout
