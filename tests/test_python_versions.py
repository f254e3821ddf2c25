"""The same run on every supported Python, bit for bit (issue 17: the builtin ``sum()`` of
floats is compensated from Python 3.12 on, so the network sums with ``math.fsum``).

``tests/data/interpreter_digest.json`` holds the content digest of one short Experiment 2 run
and the library versions it was computed with; every interpreter that runs the test suite
with the same libraries must compute the same digest (``make test PYTHON=python3.12
VENV=.venv312`` checks 3.12 against the recording). With other library versions the test
is skipped and says so: their arithmetic may differ, and their versions are in every key.
"""

import dataclasses
import json
import sys
from pathlib import Path

import pytest

from docking.experiments import run_experiment
from docking.presets import EXPERIMENT_2
from docking.store import content_digest, module_digests, result_arrays

RECORDING = Path(__file__).parent / "data" / "interpreter_digest.json"
CONFIG = dataclasses.replace(
    EXPERIMENT_2,
    name="interpreter",
    train_trials=60,
    test_trials=20,
    eval_trials=0,
    heldout_trials=10,
)


def _libraries() -> dict:
    return {k: v for k, v in module_digests().items() if k.startswith("library ")}


def digest() -> str:
    return content_digest(result_arrays(run_experiment(CONFIG, 5, progress=False)))


@pytest.mark.slow
def test_a_run_is_the_same_on_every_python():
    recorded = json.loads(RECORDING.read_text())
    if recorded["libraries"] != _libraries():
        pytest.skip(f"other library versions than the recording's: {recorded['libraries']}")
    assert digest() == recorded["digest"], (
        f"Python {sys.version.split()[0]} computes another run than Python {recorded['python']} did"
    )


if __name__ == "__main__":  # python tests/test_python_versions.py: write the recording
    text = {"python": sys.version.split()[0], "libraries": _libraries(), "digest": digest()}
    RECORDING.write_text(json.dumps(text, indent=1, sort_keys=True) + "\n")
