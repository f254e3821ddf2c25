"""The same run on every supported Python and x86-64 CPU, bit for bit.

``tests/data/platform_digest.json`` holds the content digest of one short Experiment 2 run and
the library versions it was computed with (the lock's). This test computes that run again in
subprocesses, one per row:

* each numpy dispatch level this CPU has (``NPY_DISABLE_CPU_FEATURES`` switching AVX-512 off,
  then AVX2 too): numpy's own ``exp`` differs under AVX-512;
* each OpenBLAS core type this CPU can run (``OPENBLAS_CORETYPE``): its kernels sum products
  in other orders;
* OpenCV's optimised code off (``cv2.setUseOptimized(False)``);

and every row must equal the recording. A row this machine cannot run (no AVX-512 here, say)
is skipped and says "not available on this machine", never passed. The interpreter running
the suite computes the in-process row: ``make test PYTHON=python3.12 VENV=.venv312`` checks
3.12 against the recording (made on another Python).
"""

import dataclasses
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from docking.experiments import run_experiment
from docking.presets import EXPERIMENT_2
from docking.study import platform_info
from docking.study.kinds import content_digest, module_digests, result_arrays

RECORDING = Path(__file__).parent / "data" / "platform_digest.json"
CONFIG = dataclasses.replace(
    EXPERIMENT_2,
    name="platform",
    train_trials=60,
    test_trials=20,
    eval_trials=0,
    heldout_trials=10,
)

#: numpy's dispatch levels above its x86-64 baseline, the features that switch each one off.
NUMPY_LEVELS = {
    "numpy without AVX-512": ("X86_V4", "AVX512_ICL", "AVX512_SPR"),
    "numpy without AVX-512 and AVX2": ("X86_V4", "AVX512_ICL", "AVX512_SPR", "X86_V3"),
}
#: OpenBLAS core types and the CPU feature (numpy's name) each one's kernels need.
OPENBLAS_CORES = {
    "Prescott": None,
    "Nehalem": None,
    "Sandybridge": "AVX",
    "Haswell": "AVX2",
    "Zen": "AVX2",
    "SkylakeX": "AVX512F",
    "Cooperlake": "AVX512_CPX",
    "SapphireRapids": "AVX512_SPR",
}


def _option_configs() -> dict:
    """Short runs through the world and network options of the third edition and the
    untested claims: the Nao-like world (its camera height, the whole frame), a forced
    single winner, a network learning on after a change (``before``), the oracle's
    continuous steps with turns, and held-out trials in the second room."""
    from docking.presets import NAO_WORLD
    from docking.study.design import yardstick_config

    base = dataclasses.replace(CONFIG, train_trials=40, test_trials=10)
    winner = dataclasses.replace(base.network, feature_layer="winner", rule="local")
    changed = dataclasses.replace(base.world, landmark_shape="slab", camera_height=0.42)
    turning = dataclasses.replace(NAO_WORLD, actions="continuous-turning")
    return {
        "nao": dataclasses.replace(base, world=NAO_WORLD),
        "winner": dataclasses.replace(base, network=winner),
        "before": dataclasses.replace(base, world=changed, before=base),
        "continuous": dataclasses.replace(yardstick_config(base, "oracle", 10), world=turning),
        "second room": dataclasses.replace(
            base, heldout_world=dataclasses.replace(base.world, room="second")
        ),
    }


def option_digests() -> dict:
    return {
        name: content_digest(result_arrays(run_experiment(c, 5, progress=False)))
        for name, c in _option_configs().items()
    }


def _libraries() -> dict:
    return {k: v for k, v in module_digests().items() if k.startswith("library ")}


def digest() -> str:
    return content_digest(result_arrays(run_experiment(CONFIG, 5, progress=False)))


def _recorded() -> dict:
    recorded = json.loads(RECORDING.read_text())
    assert recorded["libraries"] == _libraries(), (
        f"the libraries differ from the recording's {recorded['libraries']}: install the lock "
        "(make setup) to run this check"
    )
    return recorded


def _digest_in_subprocess(env: dict, *args: str) -> str:
    out = subprocess.run(
        [sys.executable, __file__, "--digest", *args],
        env={**os.environ, **env},
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.strip().splitlines()[-1]


@pytest.mark.slow
def test_a_run_is_the_same_on_this_python():
    recorded = _recorded()
    assert digest() == recorded["digest"], (
        f"Python {sys.version.split()[0]} computes another run than Python {recorded['python']} did"
    )


@pytest.mark.parametrize("level", sorted(NUMPY_LEVELS))
def test_a_run_is_the_same_at_every_numpy_dispatch_level(level):
    recorded = _recorded()
    features = platform_info.cpu_features()
    found = [f for f in NUMPY_LEVELS[level] if features.get(f)]
    if not found:
        pytest.skip(f"not available on this machine: its CPU has none of {NUMPY_LEVELS[level]}")
    got = _digest_in_subprocess({"NPY_DISABLE_CPU_FEATURES": " ".join(found)})
    assert got == recorded["digest"], f"{level}: another run than the recording"


@pytest.mark.parametrize("level", ["this process", *sorted(NUMPY_LEVELS)])
def test_the_recorded_platform_names_the_dispatch_levels_that_are_on(level):
    """numeric_platform()'s numpy line reads numpy.show_config: a level switched off by
    NPY_DISABLE_CPU_FEATURES is not named, and the others are, as numpy's own table has them."""
    off = [] if level == "this process" else list(NUMPY_LEVELS[level])
    features = platform_info.cpu_features()
    off = [f for f in off if features.get(f)]
    if level != "this process" and not off:
        pytest.skip(f"not available on this machine: its CPU has none of {NUMPY_LEVELS[level]}")
    code = (
        "from docking.study import platform_info as p; import json; "
        "print(json.dumps([p.numeric_platform()['numpy'], p.cpu_features()]))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        env={**os.environ, "NPY_DISABLE_CPU_FEATURES": " ".join(off)},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    line, seen = json.loads(out.stdout.strip().splitlines()[-1])
    levels = ("X86_V3", "X86_V4", "AVX512_ICL", "AVX512_SPR")
    on = " ".join(k for k in levels if seen.get(k)) or "its baseline only"
    assert line.endswith(f"dispatching to {on}") and not set(off) & set(line.split())


@pytest.mark.parametrize("core", sorted(OPENBLAS_CORES))
def test_a_run_is_the_same_under_every_openblas_core_type(core):
    recorded = _recorded()
    needs = OPENBLAS_CORES[core]
    if needs is not None and not platform_info.cpu_features().get(needs):
        pytest.skip(f"not available on this machine: {core}'s kernels need {needs}")
    got = _digest_in_subprocess({"OPENBLAS_CORETYPE": core})
    assert got == recorded["digest"], f"OpenBLAS {core}: another run than the recording"


@pytest.mark.slow
@pytest.mark.parametrize("level", ["this process", *sorted(NUMPY_LEVELS)])
def test_the_options_runs_are_the_same_at_every_numpy_dispatch_level(level):
    recorded = _recorded()
    if level == "this process":
        assert option_digests() == recorded["options"]
        return
    features = platform_info.cpu_features()
    found = [f for f in NUMPY_LEVELS[level] if features.get(f)]
    if not found:
        pytest.skip(f"not available on this machine: its CPU has none of {NUMPY_LEVELS[level]}")
    got = _digest_in_subprocess({"NPY_DISABLE_CPU_FEATURES": " ".join(found)}, "--options")
    assert json.loads(got) == recorded["options"], f"{level}: other runs than the recording"


def test_a_run_is_the_same_without_opencvs_optimised_code():
    recorded = _recorded()
    assert _digest_in_subprocess({}, "--no-opencv-optimisations") == recorded["digest"]


#: numpy functions whose kernels numpy or OpenBLAS pick by the CPU: only docking.arith (and
#: code off a run's path, which is not fingerprinted) may call them.
DISPATCHED = {
    "exp",
    "log",
    "tan",
    "arctan",
    "tanh",
    "power",
    "dot",
    "matmul",
    "inner",
    "vdot",
    "tensordot",
    "linalg",
}


def _dispatched_calls(path: Path) -> list[str]:
    """``np.<name>`` uses of :data:`DISPATCHED` and ``@`` products in ``path`` (a decorator's
    ``@`` opens a line, a product's does not), as ``"line: what"``."""
    import tokenize

    found = []
    with path.open("rb") as f:
        tokens = [t for t in tokenize.tokenize(f.readline) if t.type != tokenize.COMMENT]
    for i, tok in enumerate(tokens):
        if tok.type == tokenize.OP and tok.string in ("@", "@="):
            before = tokens[i - 1].type if i else tokenize.NEWLINE
            if before not in (tokenize.NEWLINE, tokenize.NL, tokenize.INDENT, tokenize.DEDENT):
                found.append(f"{tok.start[0]}: {tok.string}")
        if (
            tok.type == tokenize.NAME
            and tok.string in DISPATCHED
            and i >= 2
            and tokens[i - 1].string == "."
            and tokens[i - 2].string in ("np", "numpy")
        ):
            found.append(f"{tok.start[0]}: np.{tok.string}")
    return found


def test_fingerprinted_modules_compute_products_and_exp_only_through_arith():
    # The digest rows above prove one short run; this holds every module a run can execute
    # (the fingerprinted ones) to the rule that keeps them so: no numpy call whose kernel is
    # chosen by the CPU, no `@` (OpenBLAS), except in docking.arith.
    import docking
    from docking.study import fingerprint, kinds

    package_dir = Path(docking.__file__).parent
    keyed = sorted(name for name, _ in fingerprint.walk(package_dir, kinds._ROOT_MODULE)[1])
    assert "docking.arith" in keyed and "docking.network" in keyed, keyed
    offences = {
        name: calls
        for name in keyed
        if name != "docking.arith"
        and (calls := _dispatched_calls(fingerprint._module_file(name, package_dir)))
    }
    assert offences == {}, f"CPU-dispatched arithmetic outside docking.arith: {offences}"


def test_the_dispatch_check_finds_what_it_looks_for(tmp_path):
    source = tmp_path / "m.py"
    source.write_text(
        "import numpy as np\n@property\ndef f(a, b):\n    return a @ b + np.exp(a)  # np.dot\n"
    )
    assert _dispatched_calls(source) == ["4: @", "4: np.exp"]


if __name__ == "__main__":
    if "--digest" in sys.argv:  # one row: print the run's digest
        if "--no-opencv-optimisations" in sys.argv:
            import cv2

            cv2.setUseOptimized(False)
        print(json.dumps(option_digests(), sort_keys=True) if "--options" in sys.argv else digest())
    else:  # python tests/test_platform.py: write the recording
        text = {
            "python": sys.version.split()[0],
            "libraries": _libraries(),
            "digest": digest(),
            "options": option_digests(),
        }
        RECORDING.write_text(json.dumps(text, indent=1, sort_keys=True) + "\n")
