"""Triton's LLVM beside Mesa's (issue 53): ``import docking`` loads Triton's compiler library
before rendering puts Mesa's ``libLLVM`` into the process's global symbol scope, so the
library's references to its own LLVM's symbols bind to itself, whenever Triton is imported.

Without Triton, a stand-in holds the mechanism: a small library installed as
``triton/_C/libtriton.so`` that exports a symbol of LLVM's C API (``LLVMIsMultithreaded``,
returning 42) and calls it through its PLT, as libtriton calls its LLVM. Loaded after Mesa's
LLVM went global, the call binds to Mesa's LLVM (which answers 1); loaded by ``docking``
first, to itself."""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent

STAND_IN = """
int LLVMIsMultithreaded(void) { return 42; }
int probe(void) { return LLVMIsMultithreaded(); }
"""

#: Renders one observation, then loads the stand-in as ``import triton`` would (RTLD_LOCAL).
PROBE = """
import ctypes, sys
if sys.argv[1] == "dm_control":  # Mesa's LLVM global before docking is imported
    import dm_control.mujoco
import docking.gym_ids, gymnasium
gymnasium.make("docking/Docking-v0").reset(seed=0)
llvm_global = hasattr(ctypes.CDLL(None), "LLVMContextCreate")
print(llvm_global, ctypes.CDLL(sys.argv[2]).probe())
"""


def _python(code: str, *args: str, path: str = "") -> subprocess.CompletedProcess:
    env = {**os.environ, "MUJOCO_GL": "egl", "PYOPENGL_PLATFORM": "egl"}
    env["PYTHONPATH"] = os.pathsep.join(p for p in (path, str(REPO)) if p)
    return subprocess.run(
        [sys.executable, "-c", code, *args], capture_output=True, text=True, env=env, timeout=300
    )


@pytest.fixture(scope="module")
def stand_in(tmp_path_factory) -> Path:
    """A folder holding a package ``triton`` whose ``_C/libtriton.so`` is the stand-in."""
    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler to build the stand-in library")
    root = tmp_path_factory.mktemp("stand-in")
    (root / "triton" / "_C").mkdir(parents=True)
    (root / "triton" / "__init__.py").write_text("")
    source = root / "stand_in.c"
    source.write_text(STAND_IN)
    library = root / "triton" / "_C" / "libtriton.so"
    # -O0 -fPIC: the call to the exported symbol goes through the PLT, interposable.
    subprocess.run([compiler, "-shared", "-fPIC", "-O0", "-o", library, source], check=True)
    return root


@pytest.mark.parametrize("first", ["docking", "dm_control"])
def test_a_library_with_its_own_llvm_binds_to_itself_after_rendering(stand_in, first):
    library = str(stand_in / "triton" / "_C" / "libtriton.so")
    out = _python(PROBE, first, library, path=str(stand_in))
    assert out.returncode == 0, out.stderr
    llvm_global, answer = out.stdout.split()
    if llvm_global != "True":
        pytest.skip("rendering here puts no LLVM into the global scope (no llvmpipe)")
    assert answer == "42", "the stand-in's own symbol was bound to Mesa's LLVM"


def test_import_docking_finds_triton_but_never_imports_it():
    code = (
        "import sys, docking\nprint(docking._triton_library() is not None, 'triton' in sys.modules)"
    )
    out = _python(code)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == [str(importlib.util.find_spec("triton") is not None), "False"]


needs_triton = pytest.mark.skipif(
    importlib.util.find_spec("triton") is None,
    reason="Triton is not installed (pip install stable-baselines3 brings it with torch)",
)


@needs_triton
@pytest.mark.parametrize("first", ["docking", "dm_control"])
def test_triton_imports_after_rendering(first):
    """The crash itself: ``import triton`` after rendering ended the process with SIGSEGV."""
    code = (
        "import sys\n"
        "if sys.argv[1] == 'dm_control':\n"
        "    import dm_control.mujoco\n"
        "import docking.gym_ids, gymnasium\n"
        "gymnasium.make('docking/Docking-v0').reset(seed=0)\n"
        "import triton\n"
        "print('imported')\n"
    )
    out = _python(code, first)
    assert (out.returncode, out.stdout.strip()) == (0, "imported"), out.stderr[-2000:]


@pytest.mark.slow
@pytest.mark.parametrize("first", ["docking", "stable_baselines3"])
def test_stable_baselines3_trains_in_either_import_order(first):
    pytest.importorskip("stable_baselines3", reason="Stable-Baselines3 is not installed")
    code = (
        "import sys, importlib\n"
        "importlib.import_module(sys.argv[1])\n"
        "import gymnasium, docking.gym_ids\n"
        "from stable_baselines3 import PPO\n"
        "env = gymnasium.make('docking/Docking-v0', observation='flat')\n"
        "PPO('MlpPolicy', env, n_steps=64, batch_size=32, n_epochs=1, seed=0).learn(64)\n"
        "print('trained')\n"
    )
    out = _python(code, first)
    assert (out.returncode, out.stdout.strip()) == (0, "trained"), out.stderr[-2000:]
