"""A pinned design's proof across a move of modules (issue 51).

A design pins its rules by the SHA-256 of its ``rules_text()`` at the commit that added them,
before any of its runs. Four designs' digests also cover code: their module's tokens
(:func:`docking.study.fingerprint.code_tokens`, its import statements included) and the source
(:func:`inspect.getsource`) of the functions that judge them. When the study layer moved into
``docking/study/`` their import statements had to name the new modules, so their digests
moved, though not one rule did. Their tests keep the digest pinned at the rules' commit and
show, from the repository's history, that it still describes the rules:

1. the digest of the rules as they are now, with the design files' tokens and the judging
   functions' source read as they were at the rules' commit (``git show COMMIT:PATH``), is
   the digest pinned at that commit (:func:`digest_at`): the constants, cells and claims are
   the committed ones;
2. each design file then and now differs only in import statements (:func:`without_imports`:
   the syntax trees without imports and docstrings, which the tokens leave out too);
3. each judging function's text then and now is the same but for its import statements
   (:func:`same_but_imports`; every one is byte for byte the same except
   ``report.paired_over_shared_seeds``, whose body imports ``t_paired_ci`` by module name);

and pin the digest as it is since the move beside it. Without the history (a shallow clone)
only the new digest is checked.
"""

from __future__ import annotations

import ast
import contextlib
import hashlib
import inspect
import subprocess
import textwrap
from pathlib import Path
from unittest import mock

ROOT = Path(__file__).resolve().parents[1]


def history() -> bool:
    """Whether the repository's history is here (not a shallow clone, and git runs)."""
    try:
        found = subprocess.run(
            ["git", "rev-parse", "--is-shallow-repository"],
            capture_output=True,
            text=True,
            cwd=ROOT,
        )
    except OSError:
        return False
    return found.returncode == 0 and found.stdout.strip() == "false"


def show(commit: str, path: str) -> str:
    """The text of ``path`` at ``commit``."""
    return subprocess.run(
        ["git", "show", f"{commit}:{path}"], capture_output=True, text=True, check=True, cwd=ROOT
    ).stdout


def old_path(module: str) -> str:
    """Where ``module`` (``docking.study.X``) was before the study layer moved:
    ``docking/X.py``."""
    return module.replace("docking.study.", "docking.", 1).replace(".", "/") + ".py"


class _Stripped(ast.NodeTransformer):
    """A syntax tree without import statements and docstrings (a statement that is only a
    string), at every depth."""

    def generic_visit(self, node):
        super().generic_visit(node)
        for field in ("body", "orelse", "finalbody"):
            body = getattr(node, field, None)
            if isinstance(body, list):
                kept = [n for n in body if not _left_out(n)]
                setattr(node, field, kept or [ast.Pass()])
        return node


def _left_out(node) -> bool:
    if isinstance(node, ast.Import | ast.ImportFrom):
        return True
    return (
        isinstance(node, ast.Expr)
        and isinstance(node.value, ast.Constant)
        and isinstance(node.value.value, str)
    )


def without_imports(source: str) -> str:
    """``source``'s syntax tree without import statements and docstrings, as text: two sources
    with equal results differ in nothing else but comments and layout."""
    return ast.dump(_Stripped().visit(ast.parse(source)))


def definition(source: str, qualname: str) -> str | None:
    """The text of the top-level function or class ``qualname`` of ``source``, from its first
    decorator to its end, as :func:`inspect.getsource` gives it (None if there is none)."""
    lines = source.splitlines(keepends=True)
    for node in ast.parse(source).body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef) and node.name == qualname:
            first = node.decorator_list[0].lineno if node.decorator_list else node.lineno
            return "".join(lines[first - 1 : node.end_lineno])
    return None


def _import_lines(text: str) -> set[int]:
    """The line numbers (from 1) of ``text``'s import statements."""
    found = set()
    for node in ast.walk(ast.parse(textwrap.dedent(text))):
        if isinstance(node, ast.Import | ast.ImportFrom):
            found.update(range(node.lineno, node.end_lineno + 1))
    return found


def same_but_imports(before: str, now: str) -> bool:
    """Whether two texts of a definition are the same line for line but for import
    statements."""
    a, b = before.splitlines(), now.splitlines()
    ia, ib = _import_lines(before), _import_lines(now)
    return [x for k, x in enumerate(a, 1) if k not in ia] == [
        x for k, x in enumerate(b, 1) if k not in ib
    ]


@contextlib.contextmanager
def as_at(commit: str, modules):
    """Within this, the design ``modules``' tokens and every judging function's source are
    read as they were at ``commit`` (see the module docstring); yields ``{"files": {path now:
    path then}, "functions": {qualified name: (text then, text now)}}``, filled as they are
    read."""
    from docking.study import fingerprint

    now = {Path(m.__file__).read_text(): (m.__name__, old_path(m.__name__)) for m in modules}
    read = {"files": {}, "functions": {}}
    tokens, source = fingerprint.code_tokens, inspect.getsource

    def code_tokens(text, module=""):
        if text in now:
            name, path = now[text]
            read["files"][name] = path
            text = show(commit, path)
        return tokens(text, module)

    def getsource(obj):
        current = source(obj)
        module = getattr(obj, "__module__", "") or ""
        if not module.startswith("docking.study."):
            return current
        before = definition(show(commit, old_path(module)), obj.__qualname__)
        assert before is not None, f"{module}.{obj.__qualname__} is not in {commit}"
        read["functions"][f"{module}.{obj.__qualname__}"] = (before, current)
        return before

    with (
        mock.patch.object(fingerprint, "code_tokens", code_tokens),
        mock.patch.object(inspect, "getsource", getsource),
    ):
        yield read


def digest_at(rules_text, commit: str, modules) -> tuple[str, dict]:
    """The SHA-256 of ``rules_text()`` with ``modules``' tokens and the judging functions'
    source read as at ``commit`` (:func:`as_at`), and what was read."""
    with as_at(commit, modules) as read:
        text = rules_text()
    return hashlib.sha256(text.encode()).hexdigest(), read


def check_moved(rules_text, commit: str, modules, pinned: str) -> dict:
    """Assert the three parts of the proof (module docstring) for a design whose
    ``rules_text`` reads ``modules``' tokens and pinned ``pinned`` at ``commit``; returns
    what was read (``files``, ``functions``) for the test to check further."""
    digest, read = digest_at(rules_text, commit, modules)
    assert digest == pinned, "the rules, read as at their commit, are not the pinned rules"
    assert set(read["files"]) == {m.__name__ for m in modules}
    for module in modules:
        then = show(commit, old_path(module.__name__))
        assert without_imports(then) == without_imports(Path(module.__file__).read_text()), (
            f"{module.__name__} differs from {commit} in more than its imports"
        )
    for name, (then, now) in read["functions"].items():
        assert same_but_imports(then, now), f"{name} differs from {commit}"
    return read


def changed_functions(read: dict) -> set[str]:
    """The judging functions whose text is not byte for byte the one at the rules' commit."""
    return {name for name, (then, now) in read["functions"].items() if then != now}
