"""The source fingerprint (docking.study.fingerprint): the same on every Python; moved by a change
to what computes a run, never by a reworded message, docstring or comment."""

import ast
import glob
import json
import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest

import docking
from docking.study import fingerprint
from docking.study.kinds import source_fingerprint

PACKAGE = Path(docking.__file__).resolve().parent


def _copy_package(tmp_path: Path) -> Path:
    target = tmp_path / "docking"
    shutil.copytree(PACKAGE, target, ignore=shutil.ignore_patterns("__pycache__"))
    return target


def _edit(path: Path, old: str, new: str) -> None:
    source = path.read_text()
    assert source.count(old) >= 1, f"{old!r} is not in {path.name}"
    path.write_text(source.replace(old, new, 1))


def _interpreters() -> list[str]:
    """Every CPython 3.10+ this machine has (pyenv's and the PATH's), by version."""
    found = {}
    candidates = glob.glob("/root/.pyenv/versions/3.*/bin/python3") + [
        shutil.which(f"python3.{minor}") or "" for minor in range(10, 15)
    ]
    for exe in filter(None, candidates):
        try:
            out = subprocess.run(
                [exe, "-c", "import sys; print(sys.version_info[:2] >= (3, 10), sys.version)"],
                capture_output=True,
                text=True,
                timeout=30,
            )
        except (OSError, subprocess.SubprocessError):
            continue
        ok, _, version = out.stdout.partition(" ")
        if out.returncode == 0 and ok == "True":
            found.setdefault(version.split()[0][:4].rstrip("."), exe)
    return sorted(found.values())


def test_the_fingerprint_is_the_same_under_every_installed_python():
    interpreters = _interpreters()
    assert interpreters, "no Python 3.10+ interpreter found"
    ours = fingerprint.walk(PACKAGE, "docking.experiments")
    for exe in interpreters:
        out = subprocess.run(
            [exe, "-I", str(PACKAGE / "study" / "fingerprint.py")],
            capture_output=True,
            text=True,
            timeout=120,
            check=True,
        )
        theirs = json.loads(out.stdout)
        assert theirs == {"code": ours[0], "modules": dict(ours[1])}, exe


def test_the_field_checks_are_keyed(tmp_path):
    """docking.validate runs inside every run (check_real on a computed beta_a, on actions):
    its code is keyed (issue 60; it was in UNKEYED_MODULES, and an edit there changed a run's
    arrays under the same key)."""
    package = _copy_package(tmp_path)
    before = source_fingerprint(package)
    (package / "validate.py").write_text((package / "validate.py").read_text() + "\nX = 1\n")
    assert source_fingerprint(package) != before
    assert "docking.validate" not in fingerprint.UNKEYED_MODULES


def test_messages_docstrings_comments_validation_and_parsing_leave_the_key_alone(tmp_path):
    package = _copy_package(tmp_path)
    before = source_fingerprint(package)
    assert before == source_fingerprint()  # the copy is the same code
    # an error message in a computation
    _edit(package / "network.py", "softmax input contains NaN", "softmax input holds NaN")
    # validation messages (the field checks' module is keyed since issue 60, its messages not)
    _edit(package / "experiments.py", "must equal the camera's", "has to equal the camera's")
    _edit(package / "validate.py", "is not an integer: write", "is not an integer: use")
    # the configuration's parsing, a docstring, a comment
    _edit(package / "experiments.py", "fields = _fields(", "fields = dict(d) and _fields(")
    _edit(package / "trial.py", '"""', '""" Reworded. ')
    _edit(package / "trial.py", "# Eq. (6)", "# Eq. (6), the TD error")
    # a field's docstring (the command line's help for its option), added where none was
    _edit(
        package / "camera.py", "    width: int = 160\n", '    width: int = 160\n    """Pixels."""\n'
    )
    assert source_fingerprint(package) == before


@pytest.mark.parametrize(
    "module, old, new",
    [
        (
            "trial.py",
            "delta = r + cfg.gamma * discount * following.v - v",
            "delta = r + cfg.gamma * following.v - v",
        ),
        ("arith.py", 'np.einsum("ij,j->i", A, x)', "A @ x"),
        ("network.py", "e *= 1.0 / total", "e /= total"),
        ("world.py", "import numpy as np  # noqa: E402", "import numpy as np  # noqa: E402\nX = 1"),
    ],
)
def test_an_arithmetic_change_moves_the_key(tmp_path, module, old, new):
    package = _copy_package(tmp_path)
    before = source_fingerprint(package)
    _edit(package / module, old, new)
    assert source_fingerprint(package) != before


def test_every_left_out_definition_exists():
    """A renamed definition would silently be fingerprinted again; a typo here would leave
    nothing out. Every name of UNKEYED is a definition of its module."""
    for module, names in fingerprint.UNKEYED.items():
        tree = ast.parse((PACKAGE / f"{module.split('.', 1)[1]}.py").read_text())
        defined = set()
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                defined.add(node.name)
            if isinstance(node, ast.ClassDef):
                defined.update(
                    f"{node.name}.{m.name}" for m in node.body if isinstance(m, ast.FunctionDef)
                )
        assert names <= defined, (module, names - defined)


def test_a_raise_is_kept_as_its_exception():
    tokens, _ = fingerprint.code_tokens("def f(x):\n    if x:\n        raise ValueError(f'{x}')\n")
    assert "raise ValueError" in tokens and "{x}" not in tokens
    other, _ = fingerprint.code_tokens("def f(x):\n    if x:\n        raise TypeError('no')\n")
    assert other != tokens


def test_added_docstrings_type_hints_and_assert_messages_leave_the_key_alone(tmp_path):
    package = _copy_package(tmp_path)
    before = source_fingerprint(package)
    # a field's docstring (the command line's help for its option), added where none was
    _edit(
        package / "camera.py", "    width: int = 160\n", '    width: int = 160\n    """Pixels."""\n'
    )
    # a function's type hints dropped
    _edit(package / "arith.py", "def exp(x: np.ndarray) -> np.ndarray:", "def exp(x):")
    assert source_fingerprint(package) == before
    # a new function is code; its docstring, hints and assert message are not
    code = "\n\ndef _f(a: int) -> int:\n    assert a == a, 'a message'\n    return a\n"
    (package / "trial.py").write_text((package / "trial.py").read_text() + code)
    with_function = source_fingerprint(package)
    assert with_function != before
    _edit(
        package / "trial.py",
        "def _f(a: int) -> int:",
        'def _f(a: "float") -> float:\n    """Added."""',
    )
    _edit(package / "trial.py", "'a message'", "'reworded'")
    assert source_fingerprint(package) == with_function


def test_adding_a_left_out_definition_leaves_the_key_alone(monkeypatch):
    """A left-out definition goes with the NEWLINE and DEDENT tokens that end its body, so a
    validation helper split out of a left-out ``__post_init__`` (a method, a decorated
    function, a nested block at its end, a comment after it) moves nothing."""
    monkeypatch.setitem(
        fingerprint.UNKEYED, "m", frozenset({"C.__post_init__", "C._check", "_helper"})
    )
    before = (
        "class C:\n"
        "    x: int = 1\n\n"
        "    def __post_init__(self):\n"
        "        if self.x:\n"
        "            raise ValueError('x')\n\n"
        "    def run(self):\n"
        "        return self.x + 1\n\n\n"
        "def g():\n"
        "    return 2\n"
    )
    after = (
        "class C:\n"
        "    x: int = 1\n\n"
        "    def __post_init__(self):\n"
        "        self._check()\n\n"
        "    def _check(self):\n"
        "        for y in (1, 2):\n"
        "            if self.x:\n"
        "                raise ValueError('x')\n"
        "        # a comment after it\n\n"
        "    def run(self):\n"
        "        return self.x + 1\n\n\n"
        "@staticmethod\n"
        "def _helper(a):\n"
        "    while a:\n"
        "        a -= 1\n\n\n"
        "def g():\n"
        "    return 2\n"
    )
    assert fingerprint.code_tokens(after, "m") == fingerprint.code_tokens(before, "m")
    # the same helper, kept: code
    monkeypatch.setitem(fingerprint.UNKEYED, "m", frozenset({"C.__post_init__", "C._check"}))
    assert fingerprint.code_tokens(after, "m") != fingerprint.code_tokens(before, "m")


def _age(package: Path, seconds: float = 100.0) -> None:
    """Every file and folder of ``package`` last modified ``seconds`` ago (older than the
    fingerprint cache's racy window, so its answers are cached)."""
    then = time.time_ns() - int(seconds * 1e9)
    for path in [package, *package.rglob("*")]:
        os.utime(path, ns=(then, then))


def _counting_walk(monkeypatch) -> list:
    calls, walk = [], fingerprint.walk
    monkeypatch.setattr(fingerprint, "walk", lambda *a: calls.append(a) or walk(*a))
    return calls


def test_the_fingerprint_is_cached_until_a_file_it_reads_changes(tmp_path, monkeypatch):
    package = _copy_package(tmp_path)
    _age(package)
    calls = _counting_walk(monkeypatch)
    before = source_fingerprint(package)
    assert source_fingerprint(package) == before and len(calls) == 1  # cached
    # an edit of the same size, dated one second later: the stamp moves, the key too
    path = package / "network.py"
    _edit(path, "e *= 1.0 / total", "e *= 2.0 / total")
    then = path.stat().st_mtime_ns
    os.utime(path, ns=(then, then - 10**9 * 50))
    edited = source_fingerprint(package)
    assert edited != before and len(calls) == 2
    assert source_fingerprint(package) == edited and len(calls) == 2  # cached again
    # an edit just now (inside the racy window) is seen, and not cached
    _edit(path, "e *= 2.0 / total", "e *= 1.0 / total")
    assert source_fingerprint(package) == before
    assert source_fingerprint(package) == before and len(calls) == 4


def test_the_fingerprint_cache_sees_the_assets_and_new_files(tmp_path, monkeypatch):
    package = _copy_package(tmp_path)
    _age(package)
    calls = _counting_walk(monkeypatch)
    before = source_fingerprint(package)
    asset = package / "assets" / "docking.xml"
    asset.write_bytes(asset.read_bytes() + b"\n")
    _age(package, 50)
    moved = source_fingerprint(package)
    assert moved != before and len(calls) == 2
    # a file added beside the fingerprinted ones moves its folder's time: read again
    (package / "unrelated.py").write_text("X = 1\n")
    _age(package, 40)
    assert source_fingerprint(package) == moved and len(calls) == 3
    # a file no fingerprinted module imports, edited: the cached answer stands
    (package / "study" / "readme.py").write_text("X = 2\n")
    os.utime(package / "study" / "readme.py", ns=(1, 1))
    assert source_fingerprint(package) == moved and len(calls) == 3
