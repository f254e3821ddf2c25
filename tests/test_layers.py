"""The package's layers: the import-linter contracts hold, by folder (issue 51: the core is
docking/'s top level, the study layer docking/study/), and CONTRIBUTING.md's layer tables are
those contracts (issue 18: no import cycles, the tables checked against the contracts)."""

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

#: The import contracts of pyproject.toml, by name: the top level's layers (the core under the
#: study layer), the study layer's layers, and the core never importing the study layer.
TOP, STUDY, FORBIDDEN = (
    "the core's layers, under the study layer (top imports bottom, never the other way)",
    "the study layer's layers (top imports bottom, never the other way)",
    "the core never imports the study layer",
)
#: CONTRIBUTING.md's layer tables, by the header of their first column.
TABLES = {TOP: "| layer (top first) |", STUDY: "| study layer (top first) |"}


def _contract(name: str) -> dict:
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    (contract,) = [c for c in data["tool"]["importlinter"]["contracts"] if c["name"] == name]
    return contract


def _contract_layers(name: str) -> list[list[str]]:
    """A layers contract's layers, each a list of full module names."""
    contract = _contract(name)
    (container,) = contract["containers"]
    return [[f"{container}.{m.strip()}" for m in layer.split("|")] for layer in contract["layers"]]


def _table_layers(header: str) -> list[list[str]]:
    text = (ROOT / "CONTRIBUTING.md").read_text()
    section = text.split(header, 1)[1].split("\n\n", 1)[0]
    rows = [line for line in section.splitlines()[2:] if line.startswith("|")]
    return [re.findall(r"`(docking[\w.]*)`", row.split("|")[1]) for row in rows]


@pytest.mark.parametrize("name", [TOP, STUDY])
def test_contributing_lists_the_contracts_layers_in_order(name):
    assert _table_layers(TABLES[name]) == _contract_layers(name)


def _folder(package: str) -> set[str]:
    """The modules of ``package``'s folder (``docking`` or ``docking.study``), a subpackage
    as one, ``__init__`` left out."""
    folder = ROOT.joinpath(*package.split("."))
    found = {f"{package}.{p.stem}" for p in folder.glob("*.py") if p.name != "__init__.py"}
    found |= {f"{package}.{p.name}" for p in folder.iterdir() if (p / "__init__.py").is_file()}
    return found


@pytest.mark.parametrize(("name", "package"), [(TOP, "docking"), (STUDY, "docking.study")])
def test_every_module_is_in_a_layer(name, package):
    """Each layers contract covers its folder (``exhaustive``, which lint-imports checks too)."""
    layered = {m for layer in _contract_layers(name) for m in layer}
    assert layered == _folder(package), layered ^ _folder(package)
    assert _contract(name)["exhaustive"] is True


def test_the_layers_contract_is_kept():
    lint = Path(sys.executable).with_name("lint-imports")
    out = subprocess.run(
        [str(lint), "--no-cache", str(ROOT / "pyproject.toml")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stdout[-3000:]
    assert "3 kept, 0 broken" in out.stdout
    for name in (TOP, STUDY, FORBIDDEN):
        assert f"{name} KEPT" in " ".join(out.stdout.split()), name


# The core and the study layer (issue 43; folders since issue 51): the forbidden contract.


def _modules() -> set[str]:
    """Every module of the package, a subpackage's modules as the subpackage."""
    return {
        "docking." + p.relative_to(ROOT / "docking").with_suffix("").parts[0]
        for p in (ROOT / "docking").rglob("*.py")
        if p.name != "__init__.py" and "__pycache__" not in p.parts
    }


def test_the_core_is_the_top_level_and_the_study_layer_its_folder():
    """The contract's two sides are the two folders: the core is every module of docking/'s
    top level but ``python -m docking`` (which runs the command line), the study layer is
    docking/study/."""
    contract = _contract(FORBIDDEN)
    core, study = set(contract["source_modules"]), set(contract["forbidden_modules"])
    assert core == _folder("docking") - {"docking.__main__", "docking.study"}
    assert study == {"docking.study", "docking.__main__"}
    assert core | study == _modules(), (core | study) ^ _modules()


def test_the_core_facade_imports_no_module_of_the_study_layer():
    """``import docking.core`` loads the core and nothing of the study layer (the contract reads
    the code; this runs it, lazy imports and ``import_module`` included)."""
    code = (
        "import sys, docking.core\n"
        "print('\\n'.join(m for m in sys.modules if m.startswith('docking')))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    loaded = set(out.stdout.split())
    assert "docking.world" in loaded and "docking.core" in loaded
    assert not {m for m in loaded if m == "docking.study" or m.startswith("docking.study.")}


def test_the_core_facade_exports_the_core_and_says_why_it_stays_at_the_top_level():
    import types

    import docking.core as core

    def origin(obj) -> str | None:
        if isinstance(obj, types.ModuleType):
            return obj.__name__
        return getattr(type(obj) if not callable(obj) else obj, "__module__", None)

    origins = {origin(getattr(core, name)) for name in core.__all__}
    assert origins - {"builtins"} <= set(_contract(FORBIDDEN)["source_modules"])
    assert "re-key every stored run" in " ".join(core.__doc__.split())


LAYERS_PAGE = ROOT / "docs" / "guide" / "layers.md"


def test_the_layers_page_names_each_module_once_on_its_side():
    """docs/guide/layers.md's two tables are the two folders' modules."""
    text = LAYERS_PAGE.read_text()
    for heading, side in (
        ("## The core", _folder("docking") - {"docking.study"}),
        ("## The study layer", _folder("docking.study")),
    ):
        section = text.split(heading + "\n", 1)[1].split("\n## ", 1)[0]
        rows = [line for line in section.splitlines() if line.startswith("| `docking")]
        named = [re.findall(r"`(docking[\w.]*)`", row.split("|")[1]) for row in rows]
        assert sorted(m for ms in named for m in ms) == sorted(side), heading
    assert "guide/layers.md" in (ROOT / "docs" / "mkdocs.yml").read_text()


def test_the_layers_sizes_are_counted_by_code_when_the_site_is_built():
    """The page holds no measured number: tools/layers.py counts each module's lines (a
    subpackage's files summed), by folder, and docs/build.py writes its table at the page's
    mark. The core, docking/'s top level, holds at most 6,000 lines (issue 51)."""
    layers = tool("layers")
    assert layers.MARK in LAYERS_PAGE.read_text()
    assert "layers.table()" in (ROOT / "docs" / "build.py").read_text()
    table = layers.table()
    sides = layers.layers()
    assert set(sides["core"]) == {f"docking.{p.stem}" for p in (ROOT / "docking").glob("*.py")}
    assert set(sides["study layer"]) == _folder("docking.study") | {"docking.study.__init__"}
    for name, modules in sides.items():
        prefix = ".".join(Path(layers.FOLDERS[name]).parts) + "."
        for m in modules:
            assert f"`{m.removeprefix(prefix)}` {layers.lines(m):,}" in table
    counted = sum(layers.lines(m) for ms in sides.values() for m in ms)
    files = [p for p in (ROOT / "docking").rglob("*.py") if "__pycache__" not in p.parts]
    assert counted == sum(len(p.read_text().splitlines()) for p in files)
    core = sum(layers.lines(m) for m in sides["core"])
    assert f"{core:,} |" in table
    assert core <= layers.CORE_LIMIT


def test_no_module_is_over_1000_lines():
    """Issue 51: no module of the package over 1,000 lines, docstrings included."""
    files = [p for p in (ROOT / "docking").rglob("*.py") if "__pycache__" not in p.parts]
    long = {
        str(p.relative_to(ROOT)): n for p in files if (n := len(p.read_text().splitlines())) > 1000
    }
    assert not long, long


def test_no_function_is_over_60_lines():
    """Issue 49: no function of the package over 60 lines, its docstring included."""
    import ast

    long = {}
    for p in (ROOT / "docking").rglob("*.py"):
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if (n := node.end_lineno - node.lineno + 1) > 60:
                    long[f"{p.relative_to(ROOT)}:{node.name}"] = n
    assert not long, long


def test_contributings_example_design_is_a_valid_design_in_one_file(tmp_path):
    """The example of "How to add a design" builds as written (issue 18: a new study is a
    design file)."""
    text = (ROOT / "CONTRIBUTING.md").read_text()
    section = text.split("### a design", 1)[1]
    code = section.split("```python", 1)[1].split("```", 1)[0]
    namespace: dict = {}
    exec(compile(code, "two_cups.py", "exec"), namespace)
    design = namespace["DESIGN"]
    from docking.study.design import Design

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
    learner loads neither docking.study.ppo (PPO's runner is made when a PPO run is asked for) nor
    a design file (docking.study.designs' package, which names the designs for the command line's
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
    assert "docking.experiments" in loaded and "docking.study.store" in loaded  # it ran, and stored
    assert "docking.study.ppo" not in loaded
    assert [m for m in loaded if m.startswith("docking.study.designs.")] == []
