"""The package's layers: the import-linter contract holds, and CONTRIBUTING.md's layer table
is that contract (issue 18: no import cycles, the table checked against the contract)."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import tool

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: import-linter installs tomli
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def _contract(kind: str) -> dict:
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    (contract,) = [c for c in data["tool"]["importlinter"]["contracts"] if c["type"] == kind]
    return contract


def _contract_layers() -> list[list[str]]:
    return [[m.strip() for m in layer.split("|")] for layer in _contract("layers")["layers"]]


def _table_layers() -> list[list[str]]:
    text = (ROOT / "CONTRIBUTING.md").read_text()
    section = text.split("| layer (top first) |", 1)[1].split("\n\n", 1)[0]
    rows = [line for line in section.splitlines()[2:] if line.startswith("|")]
    return [re.findall(r"`(docking[\w.]*)`", row.split("|")[1]) for row in rows]


def test_contributing_lists_the_contracts_layers_in_order():
    assert _table_layers() == _contract_layers()


def test_every_module_is_in_a_layer():
    layered = {m for layer in _contract_layers() for m in layer}
    modules = {
        "docking." + ".".join(p.relative_to(ROOT / "docking").with_suffix("").parts)
        for p in (ROOT / "docking").rglob("*.py")
        if p.name != "__init__.py" and "__pycache__" not in p.parts
    }
    # A package's modules belong to its layer (docking.designs.builders to docking.designs).
    unplaced = {m for m in modules if not any(m == x or m.startswith(x + ".") for x in layered)}
    assert not unplaced, unplaced


def test_the_layers_contract_is_kept():
    lint = Path(sys.executable).with_name("lint-imports")
    out = subprocess.run(
        [str(lint), "--config", str(ROOT / "pyproject.toml")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stdout[-3000:]
    assert "2 kept, 0 broken" in out.stdout
    assert "the core never imports the study layer KEPT" in out.stdout


# The core and the study layer (issue 43): the second contract.


def _modules() -> set[str]:
    """Every module of the package, a subpackage's modules as the subpackage."""
    return {
        "docking." + p.relative_to(ROOT / "docking").with_suffix("").parts[0]
        for p in (ROOT / "docking").rglob("*.py")
        if p.name != "__init__.py" and "__pycache__" not in p.parts
    }


def test_every_module_is_in_the_core_or_the_study_layer_not_both():
    contract = _contract("forbidden")
    core, study = set(contract["source_modules"]), set(contract["forbidden_modules"])
    assert not core & study, core & study
    assert core | study == _modules(), (core | study) ^ _modules()


def test_the_core_facade_imports_no_module_of_the_study_layer():
    """``import docking.core`` loads the core and nothing of the study layer (the contract reads
    the code; this runs it, lazy imports and ``import_module`` included)."""
    study = _contract("forbidden")["forbidden_modules"]
    code = (
        "import sys, docking.core\n"
        "print('\\n'.join(m for m in sys.modules if m.startswith('docking')))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    loaded = set(out.stdout.split())
    assert "docking.world" in loaded and "docking.core" in loaded
    assert not {m for m in loaded if any(m == s or m.startswith(s + ".") for s in study)}


def test_the_core_facade_exports_the_core_and_says_why_it_is_not_a_folder():
    import types

    import docking.core as core

    def origin(obj) -> str | None:
        if isinstance(obj, types.ModuleType):
            return obj.__name__
        return getattr(type(obj) if not callable(obj) else obj, "__module__", None)

    origins = {origin(getattr(core, name)) for name in core.__all__}
    assert origins - {"builtins"} <= set(_contract("forbidden")["source_modules"])
    assert "re-key every stored run" in " ".join(core.__doc__.split())


LAYERS_PAGE = ROOT / "docs" / "guide" / "layers.md"


def test_the_layers_page_names_each_module_once_on_its_side():
    """docs/guide/layers.md's two tables are the contract's two sides."""
    text = LAYERS_PAGE.read_text()
    contract = _contract("forbidden")
    for heading, side in (
        ("## The core", "source_modules"),
        ("## The study layer", "forbidden_modules"),
    ):
        section = text.split(heading + "\n", 1)[1].split("\n## ", 1)[0]
        rows = [line for line in section.splitlines() if line.startswith("| `docking")]
        named = [re.findall(r"`(docking[\w.]*)`", row.split("|")[1]) for row in rows]
        assert sorted(m for ms in named for m in ms) == sorted(contract[side]), heading
    assert "guide/layers.md" in (ROOT / "docs" / "mkdocs.yml").read_text()


def test_the_layers_sizes_are_counted_by_code_when_the_site_is_built():
    """The page holds no measured number: tools/layers.py counts each module's lines (a
    subpackage's files summed) and docs/build.py writes its table at the page's mark."""
    layers = tool("layers")
    assert layers.MARK in LAYERS_PAGE.read_text()
    assert "layers.table()" in (ROOT / "docs" / "build.py").read_text()
    table = layers.table()
    sides = layers.layers()
    for modules in sides.values():
        for m in modules:
            assert f"`{m.removeprefix('docking.')}` {layers.lines(m):,}" in table
    counted = sum(layers.lines(m) for ms in sides.values() for m in ms)
    files = [p for p in (ROOT / "docking").rglob("*.py") if "__pycache__" not in p.parts]
    every = sum(len(p.read_text().splitlines()) for p in files)
    assert counted == every - len((ROOT / "docking" / "__init__.py").read_text().splitlines())
    assert f"{sum(layers.lines(m) for m in sides['core']):,} |" in table


def test_contributings_example_design_is_a_valid_design_in_one_file(tmp_path):
    """The example of "How to add a design" builds as written (issue 18: a new study is a
    design file)."""
    text = (ROOT / "CONTRIBUTING.md").read_text()
    section = text.split("### a design", 1)[1]
    code = section.split("```python", 1)[1].split("```", 1)[0]
    namespace: dict = {}
    exec(compile(code, "two_cups.py", "exec"), namespace)
    design = namespace["DESIGN"]
    from docking.design import Design

    assert isinstance(design, Design) and [c.key for c in design.cells] == [
        "paper",
        "frozen",
        "cups",
    ]
    assert design.cell("cups").config.world.distractors and design.claims[0].cells == {
        "floor": ("cups",)
    }


# What a preset's run loads: python -m docking run, with the ledger off, on a tiny run.
_LOADED = """
import atexit, runpy, sys
atexit.register(lambda: print("LOADED", *sorted(m for m in sys.modules if m.startswith("docking")),
                              file=sys.stderr))
sys.argv = ["docking", "run", "experiment1", "--seeds", "0", "--train-trials", "2",
            "--test-trials", "1", "--eval-every", "2", "--eval-trials", "1",
            "--results-dir", sys.argv[1]]
runpy.run_module("docking", run_name="__main__")
"""


@pytest.mark.slow
def test_a_presets_run_loads_no_ppo_code_and_no_design_file(tmp_path):
    """Issue 43: no module is loaded only to reach another kind of run. A run of the paper's
    learner loads neither docking.ppo (PPO's runner is made when a PPO run is asked for) nor
    a design file (docking.designs' package, which names the designs for the command line's
    choices, imports none of them)."""
    env = {**os.environ, "DOCKING_LEDGER": "off", "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    done = subprocess.run(
        [sys.executable, "-c", _LOADED, str(tmp_path)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    loaded = done.stderr.split("LOADED", 1)[1].split()
    assert "docking.experiments" in loaded and "docking.store" in loaded  # it ran, and stored
    assert "docking.ppo" not in loaded
    assert [m for m in loaded if m.startswith("docking.designs.")] == []
