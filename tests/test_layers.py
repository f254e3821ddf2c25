"""The package's layers: the import-linter contract holds, and CONTRIBUTING.md's layer table
is that contract (issue 18: no import cycles, the table checked against the contract)."""

import re
import subprocess
import sys
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: import-linter installs tomli
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def _contract_layers() -> list[list[str]]:
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    (contract,) = data["tool"]["importlinter"]["contracts"]
    return [[m.strip() for m in layer.split("|")] for layer in contract["layers"]]


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
    assert "1 kept, 0 broken" in out.stdout


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
