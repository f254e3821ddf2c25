"""A registered learner's key follows what it executes (issues 60 and 62,
docking.study.own_code): relative imports from a package's ``__init__``, a helper module that
shares its name with an installed distribution's, a module loaded while the run runs, a data
file; and not the lines the learner never reaches (the contest call, a ``__main__`` block)."""

from __future__ import annotations

import importlib
import sys
import textwrap
from pathlib import Path

import pytest

from docking.study import kinds

LEARNER = """
import dataclasses

from docking.scene import WorldConfig
from docking.study import learners
{imports}

GAIN = 3


@dataclasses.dataclass(frozen=True)
class {cls}:
    name: str = "{name}"
    world: WorldConfig = WorldConfig()
    heldout_trials: int = 1


def helper_steps():
    return GAIN + {extra}


def run(config, seed, progress=True, on_trials=None):
    {body}
    return learners.judge(config, seed, lambda o, env: 0, helper_steps(), on_trials)


def unrelated():
    return 1


RUNNER = learners.register({cls}, run{register})

if __name__ == "__main__":
    BUDGET = 2
    print(BUDGET)
"""


def _load(folder: Path, name: str, source: str, monkeypatch, package: bool = False):
    """Import ``source`` as module (or package, ``package``) ``name`` from ``folder``."""
    monkeypatch.syspath_prepend(str(folder))
    path = folder / name / "__init__.py" if package else folder / f"{name}.py"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(source))
    for loaded in [m for m in sys.modules if m == name or m.startswith(f"{name}.")]:
        monkeypatch.delitem(sys.modules, loaded)
    importlib.invalidate_caches()
    module = importlib.import_module(name)
    monkeypatch.setitem(sys.modules, name, module)
    return module


def _learner(tmp_path, monkeypatch, tag: str, **parts):
    values = dict(imports="", extra="0", body="pass", register="", cls="Mine", name="mine")
    values.update(parts)
    folder = tmp_path / tag
    folder.mkdir()
    module = _load(folder, "mine", LEARNER.format(**values), monkeypatch)
    return module, kinds.config_key(module.Mine())


@pytest.fixture
def registry(monkeypatch):
    saved = dict(kinds.RUNNERS), dict(kinds._BY_NAME)
    yield
    kinds.RUNNERS.clear()
    kinds.RUNNERS.update(saved[0])
    kinds._BY_NAME.clear()
    kinds._BY_NAME.update(saved[1])


def test_lines_the_learner_never_reaches_are_not_keyed(tmp_path, registry, monkeypatch):
    """Issue 62: the contest call, a ``__main__`` block, an unrelated function: edited, the
    key stays; a constant the run reads through a helper: edited, the key moves."""
    _, key = _learner(tmp_path, monkeypatch, "a")
    mine = (tmp_path / "a" / "mine.py").read_text()
    for tag, (old, new) in enumerate(
        [
            ("BUDGET = 2", "BUDGET = 5"),
            ("def unrelated():\n    return 1", "def unrelated():\n    return 2"),
            (
                "RUNNER = learners.register(Mine, run)",
                "RUNNER = learners.register(Mine, run)\nX = 4",
            ),
        ]
    ):
        folder = tmp_path / f"same{tag}"
        folder.mkdir()
        assert old in mine
        module = _load(folder, "mine", mine.replace(old, new), monkeypatch)
        assert kinds.config_key(module.Mine()) == key, old
    folder = tmp_path / "gain"
    folder.mkdir()
    module = _load(folder, "mine", mine.replace("GAIN = 3", "GAIN = 4"), monkeypatch)
    assert kinds.config_key(module.Mine()) != key


def test_a_package_init_learner_follows_its_relative_imports(tmp_path, registry, monkeypatch):
    """Issue 60: a learner in a package's ``__init__`` doing ``from . import helper``: an
    edit to the helper recomputes (it passed ``userpkg``, so the import resolved to nothing)."""
    keys = []
    for tag, value in (("a", 0), ("b", 0), ("c", 1)):
        folder = tmp_path / tag
        (folder / "userpkg").mkdir(parents=True)
        (folder / "userpkg" / "helper.py").write_text(f"OFFSET = {value}\n")
        source = LEARNER.format(
            imports="from . import helper",
            extra="helper.OFFSET",
            body="pass",
            register="",
            cls="Mine",
            name="mine",
        )
        module = _load(folder, "userpkg", source, monkeypatch, package=True)
        monkeypatch.delitem(sys.modules, "userpkg.helper", raising=False)
        keys.append(kinds.config_key(module.Mine()))
        assert any(w.endswith("helper.py") for w in module.RUNNER.code.where)
    assert keys[0] == keys[1] != keys[2]


def test_a_helper_named_like_an_installed_distribution_is_keyed_by_its_file(
    tmp_path, registry, monkeypatch
):
    """Issue 60: ``tree.py`` beside the learner (dm-tree installs a module ``tree``) was
    rejected by its name and never keyed; it is the user's by the file it loads from."""
    assert importlib.util.find_spec("tree") is not None  # dm-tree's, installed
    keys = []
    for tag, value in (("a", 0), ("b", 1)):
        folder = tmp_path / tag
        folder.mkdir()
        (folder / "tree.py").write_text(f"OFFSET = {value}\n")
        monkeypatch.delitem(sys.modules, "tree", raising=False)
        monkeypatch.syspath_prepend(str(folder))
        module, key = _learner(
            tmp_path, monkeypatch, f"{tag}-l", imports="import tree", extra="tree.OFFSET"
        )
        assert sys.modules["tree"].__file__ == str(folder / "tree.py")
        keys.append(key)
    assert keys[0] != keys[1]


def test_a_module_loaded_while_the_run_runs_is_refused_and_not_stored(
    tmp_path, registry, monkeypatch
):
    """Issue 60: a helper loaded with importlib inside the run is no import the key can see:
    the run fails, naming it, and nothing is stored."""
    from docking.study import store

    folder = tmp_path / "dyn"
    folder.mkdir()
    (folder / "sneaky.py").write_text("OFFSET = 0\n")
    monkeypatch.delitem(sys.modules, "sneaky", raising=False)
    module, _ = _learner(
        tmp_path,
        monkeypatch,
        "l",
        imports="import importlib",
        body="importlib.import_module('sneaky')",
    )
    monkeypatch.syspath_prepend(str(folder))
    results = tmp_path / "results"
    with pytest.raises(RuntimeError, match="loaded sneaky .* its key does not cover"):
        store.run_or_load(module.Mine(), 0, results, progress=False)
    assert not list(results.rglob("*.npz"))


def test_a_declared_data_file_is_keyed_and_an_undeclared_one_is_not(
    tmp_path, registry, monkeypatch
):
    data = tmp_path / "weights.txt"
    data.write_text("1 2 3\n")
    declared = f", files=({str(data)!r},)"
    _, key = _learner(tmp_path, monkeypatch, "a", register=declared)
    data.write_text("1 2 4\n")
    _, changed = _learner(tmp_path, monkeypatch, "b", register=declared)
    assert changed != key
    _, plain = _learner(tmp_path, monkeypatch, "c")
    data.write_text("9\n")
    _, again = _learner(tmp_path, monkeypatch, "d")
    assert plain == again  # undeclared: not keyed (the guide says so)
    with pytest.raises(FileNotFoundError, match="files names"):
        _learner(tmp_path, monkeypatch, "e", register=", files=('/no/such/file',)")
    with pytest.raises(TypeError, match="files must be a tuple of paths"):
        _learner(tmp_path, monkeypatch, "f", register=", files='weights.txt'")


def test_a_distribution_installed_outside_the_site_folders_is_a_library(tmp_path, monkeypatch):
    """A distribution whose folder is on the path another way (``pip install --target``, a
    ``PYTHONPATH`` entry, a ``.pth`` line) is a library by its own file list, with its
    compiled modules (found running the SB3 page in such an environment: numpy's extension
    was refused as "a module of your own with no Python source"); a plain module beside it
    and an editable install's source (its file list names only its ``.pth``) stay the user's."""
    from docking.study import learner_run

    target, source = tmp_path / "target", tmp_path / "src"
    (target / "fakelib").mkdir(parents=True)
    (target / "fakelib" / "__init__.py").write_text("")
    (target / "fakelib" / "_ext.so").write_bytes(b"")
    (target / "plain.py").write_text("")
    (source / "mine").mkdir(parents=True)
    (source / "mine" / "__init__.py").write_text("")
    for name, files in (
        ("fakelib", ["fakelib/__init__.py", "fakelib/_ext.so"]),
        ("mine", ["__editable__.mine-1.0.pth"]),
    ):
        info = target / f"{name}-1.0.dist-info"
        info.mkdir()
        (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 1.0\n")
        (info / "RECORD").write_text("".join(f"{f},,\n" for f in files))
    (target / "__editable__.mine-1.0.pth").write_text(str(source) + "\n")
    monkeypatch.syspath_prepend(str(target))
    learner_run._distributed_paths.cache_clear()
    try:
        assert not learner_run.is_users_file(target / "fakelib" / "_ext.so")
        assert not learner_run.is_users_file(target / "fakelib" / "__init__.py")
        assert learner_run.is_users_file(target / "plain.py")
        assert learner_run.is_users_file(source / "mine" / "__init__.py")
    finally:
        monkeypatch.undo()
        learner_run._distributed_paths.cache_clear()
