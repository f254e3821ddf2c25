"""The package's layers: the import-linter contracts hold, by folder (issue 51: the core is
docking/'s top level, the study layer docking/study/), CONTRIBUTING.md's tier tables are
those contracts (issue 18: no import cycles, the tables checked against the contracts), and
each rule of its structure names a contract or a test that fails when the rule is broken
(issue 61: coarse tiers and forbidden contracts that state rules)."""

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

#: Import contracts of pyproject.toml, by name: the top level's tiers (the core under the study
#: layer), the study layer's tiers, the core never importing the study layer, and the reports
#: taking arrays.
TOP, STUDY, FORBIDDEN, REPORTS = (
    "the top level's tiers: python -m docking, the study layer, the core (what a user imports, "
    "a run, the task and the learner, their parts)",
    "the study layer's tiers: the command line, what reads every design, the designs, what "
    "designs are built with, runs, foundations",
    "the core never imports the study layer",
    "reports never import the world, the renderer, the runs' code or what replays them",
)
#: CONTRIBUTING.md's tier tables, by the header of their first column.
TABLES = {TOP: "| tier (top first) |", STUDY: "| study tier (top first) |"}


def _contract(name: str) -> dict:
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    (contract,) = [c for c in data["tool"]["importlinter"]["contracts"] if c["name"] == name]
    return contract


def _contracts() -> list[dict]:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]


def _contract_layers(name: str) -> list[list[str]]:
    """A layers contract's layers (tiers), each a list of full module names (``a : b``, a
    tier whose modules may import each other; ``a | b``, one whose modules may not)."""
    contract = _contract(name)
    (container,) = contract["containers"]
    return [
        [f"{container}.{m.strip()}" for m in re.split(r"[|:]", layer)]
        for layer in contract["layers"]
    ]


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


def _lint(root: Path = ROOT) -> subprocess.CompletedProcess:
    lint = Path(sys.executable).with_name("lint-imports")
    return subprocess.run(
        [str(lint), "--no-cache", str(root / "pyproject.toml")],
        cwd=root,
        env={**os.environ, "PYTHONPATH": str(root)},
        capture_output=True,
        text=True,
        check=False,
    )


def test_every_contract_is_kept():
    out = _lint()
    assert out.returncode == 0, out.stdout[-3000:]
    names = [c["name"] for c in _contracts()]
    assert f"{len(names)} kept, 0 broken" in out.stdout
    for name in names:
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


def test_no_module_is_over_800_lines():
    """Issue 61: no module of the study layer over 800 lines, docstrings included. The core's
    modules are keyed (a run's key is their code), so one over 800 lines is split when it next
    changes for its own reasons; none may exceed 1,000 (issue 51)."""
    files = [p for p in (ROOT / "docking").rglob("*.py") if "__pycache__" not in p.parts]
    sizes = {str(p.relative_to(ROOT)): len(p.read_text().splitlines()) for p in files}
    study = {f: n for f, n in sizes.items() if f.startswith("docking/study/") and n > 800}
    core = {f: n for f, n in sizes.items() if not f.startswith("docking/study/") and n > 1000}
    assert not study and not core, (study, core)


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


# Issue 61: the rules of CONTRIBUTING.md's structure, each a contract or a test.

FIGURES = "figures never import the world, the renderer, the runs' code or what replays them"


def test_the_reports_contract_names_every_report():
    """The reports' contract covers the shared report, the README's blocks, the first screen
    and every design's ``<design>_report.py`` (a new one is under it from its first commit),
    and forbids what the figures' contract forbids."""
    reports = _contract(REPORTS)
    designs = ROOT / "docking" / "study" / "designs"
    found = {f"docking.study.designs.{p.stem}" for p in designs.glob("*_report.py")}
    shared = {"docking.study.report", "docking.study.readme", "docking.study.answer"}
    assert set(reports["source_modules"]) == shared | found
    assert set(reports["forbidden_modules"]) == set(_contract(FIGURES)["forbidden_modules"])
    assert {"docking.world", "docking.render", "docking.experiments"} <= set(
        reports["forbidden_modules"]
    )


def _lint_with(tmp_path: Path, module: str, line: str) -> str:
    """lint-imports on a copy of the package where ``module`` (a path under docking/) ends
    with ``line``: its output, one line per word."""
    import shutil

    copy = tmp_path / module.replace("/", "_")
    shutil.copytree(
        ROOT / "docking", copy / "docking", ignore=shutil.ignore_patterns("__pycache__")
    )
    shutil.copy(ROOT / "pyproject.toml", copy / "pyproject.toml")
    target = copy / "docking" / module
    target.write_text(target.read_text() + line + "\n")
    out = _lint(copy)
    assert out.returncode != 0
    return " ".join(out.stdout.split())


@pytest.mark.parametrize(
    ("module", "line", "broken"),
    [
        ("study/figures/study.py", "import docking.world", FIGURES),
        ("study/figures/common.py", "from docking.study import analysis", FIGURES),
        ("study/figures/paper.py", "from docking.presets import SEEDS", FIGURES),
        ("study/designs/experiment3_report.py", "import docking.world", REPORTS),
        ("study/report.py", "from docking.study.analysis import floor_plan", REPORTS),
    ],
)
def test_the_probe_contracts_fail_when_a_figure_or_a_report_reaches_the_world(
    tmp_path, module, line, broken
):
    """The contracts are not vacuous: a figure that imports the world, or imports it through
    another module (``analysis``, the presets: the runs' code), breaks the figures' contract;
    a report that imports the world or ``analysis`` breaks the reports' contract."""
    said = _lint_with(tmp_path, module, line)
    assert f"{broken} BROKEN" in said, said[-2000:]


def _structure_rules() -> list[str]:
    """The numbered rules of CONTRIBUTING.md's "The rules of the structure", each one line."""
    text = (ROOT / "CONTRIBUTING.md").read_text()
    section = text.split("### The rules of the structure\n", 1)[1].split("\nBesides", 1)[0]
    return [" ".join(item.split()) for item in re.split(r"\n(?=\d+\. )", section)[1:]]


def test_each_rule_of_the_structure_names_a_contract_or_a_test():
    """Every rule names a contract of pyproject.toml (in double quotes) or a test
    (``tests/<file>.py::<function>``) that exists; every contract is named by a rule."""
    rules = _structure_rules()
    assert len(rules) >= 10
    names = {c["name"] for c in _contracts()}
    cited = set()
    for rule in rules:
        contracts = {n for n in names if f'"{n}"' in rule}
        tests = re.findall(r"`(tests/test_\w+\.py)::(\w+)`", rule)
        assert contracts or tests, rule[:100]
        for path, function in tests:
            assert re.search(rf"^def {function}\(", (ROOT / path).read_text(), re.M), function
        cited |= contracts
    assert cited == names, names - cited


#: The designs whose reader-facing code is in a report that reads them beside others.
REPORTED_ELSEWHERE = {"bracketing_continued": "designs/bracketing_report", "replication": "answer"}
#: Names a report's functions take (tables, rows, sentences, summaries, a figure's panels).
_REPORT_CODE = re.compile(r"(_table|_rows|_sentence|_summary|_text|_words|panels|shares)$")


def test_design_files_hold_no_report_code():
    """Issue 61: a design file is its design and its procedure (its verdict rules with the
    words they allow); tables, sentences and figures' data are its report's, beside it in
    ``<design>_report.py`` (or in the report that reads it beside others). A design file
    defines no function named as a report's and imports no figure."""
    import ast

    from docking.study.designs import MODULES

    designs = ROOT / "docking" / "study" / "designs"
    for module in sorted(set(MODULES.values())):
        stem = module.rsplit(".", 1)[1]
        tree = ast.parse((designs / f"{stem}.py").read_text())
        defined = [n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)]
        assert not [d for d in defined if _REPORT_CODE.search(d) and d != "rules_text"], stem
        imported = {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)} | {
            a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names
        }
        assert not [m for m in imported if m.startswith("docking.study.figures")], stem
        if stem in REPORTED_ELSEWHERE:
            report = (ROOT / "docking" / "study" / f"{REPORTED_ELSEWHERE[stem]}.py").read_text()
            assert f"docking.study.designs.{stem}" in report or f"import {stem}" in report, stem
            assert not (designs / f"{stem}_report.py").exists(), stem
        else:
            assert (designs / f"{stem}_report.py").is_file(), stem
