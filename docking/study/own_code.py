"""A registered learner's own code, as its key reads it (:func:`own_code`): what its
configuration class and its run function *reach*, not every line of the files they live in.

In a module with a file (a user's module, a script run as ``__main__``, a test file), the key
reads the module's top-level statements that the class and the function reach: starting from
their definitions, every top-level definition, assignment or import that binds a name they use,
and so on (a helper function, a constant, a class, the import that brings a name in). A
statement nothing reaches is not keyed: the ``contest(...)`` call, the
``if __name__ == "__main__":`` block, an unrelated function. Each statement is read as the
package's code is (:func:`docking.study.fingerprint.code_tokens`: no comments, docstrings, type
hints or error messages).

In a notebook cell (no module file), the class's and the function's own source, and the
functions and classes of other cells they refer to (their source, found as ``inspect`` finds
it), and the value of every other name they refer to in the notebook's namespace (its
``repr``, for numbers, strings and tuples of them; its type otherwise).

Every module *of the user's own* that the reached code imports is keyed whole, transitively: a
module whose file is not in the standard library, the installed distributions' folders or
``docking`` (decided by the file it loads from, not by its name: a ``tree.py`` beside the
learner is the user's even though dm-tree installs a module ``tree``). Relative imports are
resolved from the importing module's package (a package's ``__init__`` included). Data files
the learner reads are keyed only when declared (``register(..., files=...)``): by their bytes.

What the key cannot see is refused where it can be seen: a module of the user's that a run
loads and its key does not cover (an ``importlib.import_module`` inside the run) fails that
run, which is then not stored (:func:`unkeyed_modules`, asked by
:mod:`docking.study.learner_run`).
"""

from __future__ import annotations

import ast
import dataclasses
import hashlib
import inspect
import linecache
import sys
import textwrap
import types
from pathlib import Path

from docking.study import fingerprint
from docking.study.learner_run import is_users_file, unkeyed_modules

__all__ = ["OwnCode", "is_users_file", "own_code", "unkeyed_modules", "user_modules"]


@dataclasses.dataclass(frozen=True)
class OwnCode:
    """A learner's own code as its key reads it (:func:`own_code`).

    Attributes:
      digest: SHA-256 of its tokens (and of its declared files' bytes).
      imports: The ``docking`` modules it imports (or refers to).
      where: Where it was read: module files, or ``"<cell>: class X, function run"``; the
        declared files.
      modules: ``((module, its file), ...)``: the modules of the user's own that a process
        running the learner imports (by name, as it unpickles the configuration or the run
        function, and as those import others): the module files that define the class and
        the function (not a script run as ``__main__``, whose code travels by value), the
        packages they are in, and the modules of the user's own that any of these import,
        transitively (:func:`user_modules`). What a sweep ships to its Dask workers
        (:mod:`docking.study.sweep`), and what a run may load (:func:`keyed_names`).
    """

    digest: str
    imports: tuple[str, ...]
    where: tuple[str, ...]
    modules: tuple[tuple[str, str], ...] = ()

    def keyed_names(self, config_type: type, run) -> tuple[str, ...]:
        """The modules of the user's own this key covers: :attr:`modules` and those defining
        the class and the function (``__main__`` included): a run that loads another is
        refused (:func:`docking.study.learner_run.unkeyed_modules`)."""
        names = {m for m, _ in self.modules} | {config_type.__module__, run.__module__}
        return tuple(sorted(names))


# ------------------------------------------------------------------------------------------
# Whose module is it: decided by its file.
# ------------------------------------------------------------------------------------------


def _module_path(name: str) -> Path | None:
    """The file module ``name`` loads from (its loaded module's, if loaded), or None."""
    import importlib.util

    loaded = sys.modules.get(name)
    if loaded is not None:
        spec = getattr(loaded, "__spec__", None)
        origin = getattr(loaded, "__file__", None) or (spec and spec.origin)
    else:
        try:
            spec = importlib.util.find_spec(name)
        except (ImportError, ValueError, AttributeError):
            return None
        origin = spec.origin if spec is not None else None
    if not origin or origin in ("built-in", "frozen"):
        return None
    return Path(origin)


def _is_users(name: str) -> bool:
    top = name.partition(".")[0]
    if not top or top == "docking" or top in sys.builtin_module_names:
        return False
    path = _module_path(name)
    return path is not None and is_users_file(path)


def user_modules(names) -> list[tuple[str, Path]]:
    """``[(module, its file)]`` of the modules of the user's own among ``names`` (imported
    names: modules, or names in one) and every module of the user's own that those import,
    transitively, in name order (a module of the user's own: :func:`is_users_file`). A name
    that is no module is passed over. ``TypeError`` naming a module of the user's that has no
    Python source (a compiled extension, a ``.pyc`` only), which no key can cover."""
    found: dict[str, Path] = {}
    queue = sorted(_with_parents(names))
    while queue:
        name = queue.pop()
        if name in found or not _is_users(name):
            continue
        path = _module_path(name)
        if path.suffix != ".py" or not path.is_file():
            raise TypeError(
                f"register: the learner's code imports {name}, a module of your own with no "
                f"Python source ({path.name}): its code cannot be keyed; import it from a .py file"
            )
        found[name] = path.resolve()
        source = path.read_text(encoding="utf-8")
        imported = fingerprint.imported_names(source, _context(name, path))
        queue.extend(sorted(_with_parents(imported) | _with_parents([name])))
    return sorted(found.items())


def _context(name: str, path: Path) -> str:
    """The module name relative imports of ``name`` resolve from (a package's ``__init__``
    resolves from the package itself)."""
    return f"{name}.__init__" if path.name == "__init__.py" else name


def _with_parents(names) -> set[str]:
    """``names`` with each one's parents (``helpers.GAIN``: ``helpers`` too)."""
    found = set()
    for name in names:
        while name:
            found.add(name)
            name = name.rpartition(".")[0]
    return found


# ------------------------------------------------------------------------------------------
# What a module's definitions reach.
# ------------------------------------------------------------------------------------------


def _flat(body) -> list[ast.stmt]:
    """A module's top-level statements, those inside top-level ``if``, ``try`` and ``with``
    blocks included (their tests and handlers' types are not kept)."""
    found = []
    for stmt in body:
        if isinstance(stmt, ast.If | ast.Try | ast.With):
            blocks = [stmt.body, getattr(stmt, "orelse", []), getattr(stmt, "finalbody", [])]
            blocks += [h.body for h in getattr(stmt, "handlers", [])]
            for block in blocks:
                found += _flat(block)
        else:
            found.append(stmt)
    return found


def _binds(stmt: ast.stmt) -> set[str]:
    """The top-level names a statement binds."""
    if isinstance(stmt, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
        return {stmt.name}
    if isinstance(stmt, ast.Import | ast.ImportFrom):
        return {(a.asname or a.name).partition(".")[0] for a in stmt.names if a.name != "*"}
    targets = []
    if isinstance(stmt, ast.Assign):
        targets = stmt.targets
    elif isinstance(stmt, ast.AnnAssign | ast.AugAssign | ast.For | ast.AsyncFor):
        targets = [stmt.target]
    return {n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)}


def _uses(stmt: ast.stmt) -> set[str]:
    """Every name a statement mentions (a superset of what it reads: safe for a key)."""
    return {n.id for n in ast.walk(stmt) if isinstance(n, ast.Name)}


def _segment(lines: list[str], stmt: ast.stmt) -> str:
    first = min([stmt.lineno, *(d.lineno for d in getattr(stmt, "decorator_list", []))])
    return textwrap.dedent("".join(lines[first - 1 : stmt.end_lineno]))


def reached(source: str, starts: set[str]) -> list[ast.stmt]:
    """The top-level statements of ``source`` that the definitions of the names ``starts``
    reach (see the module docstring), in source order."""
    statements = _flat(ast.parse(source).body)
    bound: dict[str, list[int]] = {}
    for k, stmt in enumerate(statements):
        for name in _binds(stmt):
            bound.setdefault(name, []).append(k)
    seen: set[int] = set()
    names, done = list(starts), set()
    while names:
        name = names.pop()
        if name in done:
            continue
        done.add(name)
        for k in bound.get(name, ()):
            if k not in seen:
                seen.add(k)
                names.extend(_uses(statements[k]) - done)
    return [statements[k] for k in sorted(seen)]


def _module_text(name: str, path: Path, starts: set[str]) -> tuple[str, set[str], set[str]]:
    """``(tokens, docking modules, imported names)`` of what ``starts`` reach in module
    ``name`` (file ``path``)."""
    source = path.read_text(encoding="utf-8")
    lines = source.splitlines(keepends=True)
    texts, imports, names = [], set(), set()
    context = _context(name, path)
    for stmt in reached(source, starts):
        segment = _segment(lines, stmt)
        tokens, found = fingerprint.code_tokens(segment, context)
        texts.append(tokens)
        imports |= found
        names |= fingerprint.imported_names(segment, context)  # at the top or inside
    return "\n".join(texts), imports, names


def _file_of(module: str, objects: list) -> Path | None:
    """The file of ``module`` if it is loaded from a ``.py`` file and ``objects`` are defined
    in it (not a notebook's or ``exec``'s namespace)."""
    found = getattr(sys.modules.get(module), "__file__", None)
    if not found or not found.endswith(".py") or not Path(found).is_file():
        return None
    path = Path(found).resolve()
    for obj in objects:
        code = getattr(obj, "__code__", None)
        if code is not None and Path(code.co_filename).resolve() != path:
            return None
    return path


# ------------------------------------------------------------------------------------------
# Code without a module file (a notebook cell).
# ------------------------------------------------------------------------------------------


def _class_source(text: str, name: str) -> str | None:
    """The source of the last definition of class ``name`` in ``text`` (with its
    decorators), or None."""
    try:
        tree = ast.parse(text)
    except SyntaxError:
        return None
    found = [n for n in ast.walk(tree) if isinstance(n, ast.ClassDef) and n.name == name]
    if not found:
        return None
    return _segment(text.splitlines(keepends=True), found[-1])


def _source(obj, hint: types.FunctionType | None = None) -> tuple[str, str]:
    """``(source, its file name)`` of a class or function defined outside a module file."""
    if not isinstance(obj, type):
        try:
            return textwrap.dedent(inspect.getsource(obj)), obj.__code__.co_filename
        except (OSError, TypeError):
            pass
    else:
        # inspect cannot find a class without a module file (before Python 3.13): look for
        # its definition in the cells its methods or the run function were defined in
        files = [
            f.__code__.co_filename
            for f in vars(obj).values()
            if isinstance(f, types.FunctionType)
            and not f.__code__.co_filename.startswith("<string")
        ]
        if hint is not None:
            files.append(hint.__code__.co_filename)
        for filename in dict.fromkeys(files):
            found = _class_source("".join(linecache.getlines(filename)), obj.__name__)
            if found is not None:
                return found, filename
    raise TypeError(
        f"cannot read the source of {obj.__qualname__} (defined in {obj.__module__!r}): define "
        "the learner in a module file, a script or a notebook cell"
    )


def _functions(obj) -> list[types.FunctionType]:
    if isinstance(obj, types.FunctionType):
        return [obj]
    return [f for f in vars(obj).values() if isinstance(f, types.FunctionType)]


def _namespace(obj) -> dict:
    functions = _functions(obj)
    if functions:
        return functions[0].__globals__
    return vars(sys.modules.get(obj.__module__, types.SimpleNamespace()))


_SIMPLE = (int, float, complex, str, bytes, bool, type(None))


def _value_text(value) -> str:
    def simple(v) -> bool:
        if isinstance(v, tuple | list | frozenset):
            return all(simple(x) for x in v)
        return isinstance(v, _SIMPLE)

    return repr(value) if simple(value) else f"<{type(value).__qualname__}>"


def _cell_code(objects: list, run) -> tuple[list[str], set[str], set[str], list[str]]:
    """``(texts, docking modules, imported names, where)`` of ``objects`` (defined outside a
    module file) and what they reach in their namespace."""
    texts, imports, names, where = [], set(), set(), []
    queue, seen = list(objects), set()
    while queue:
        obj = queue.pop(0)
        if id(obj) in seen:
            continue
        seen.add(id(obj))
        source, origin = _source(obj, run)
        tokens, found = fingerprint.code_tokens(source, obj.__module__)
        texts.append(f"{'class' if isinstance(obj, type) else 'function'}\n{tokens}")
        imports |= found
        names |= fingerprint.imported_names(source, obj.__module__)
        where.append(f"{origin}: {obj.__qualname__}")
        namespace = _namespace(obj)
        used = {n.id for n in ast.walk(ast.parse(source)) if isinstance(n, ast.Name)}
        for name in sorted(used):
            if name not in namespace:
                continue
            value = namespace[name]
            module = value.__name__ if isinstance(value, types.ModuleType) else None
            module = module or getattr(value, "__module__", None)
            if isinstance(value, types.FunctionType | type) and module == obj.__module__:
                queue.append(value)  # another cell's function or class
            elif isinstance(module, str) and (module == "docking" or module.startswith("docking.")):
                imports.add(module)
            elif isinstance(module, str) and _is_users(module):
                names.add(module)
            elif not isinstance(value, types.ModuleType | types.BuiltinFunctionType | type):
                if not callable(value):
                    texts.append(f"value {name} = {_value_text(value)}")
    return texts, imports, names, where


# ------------------------------------------------------------------------------------------
# The own code.
# ------------------------------------------------------------------------------------------


def own_code(config_type: type, run, files=()) -> OwnCode:
    """The own code of the learner of ``config_type`` and ``run`` (see the module docstring),
    with the declared data ``files`` (paths) keyed by their bytes. ``TypeError`` if a source
    cannot be read, or a module of the user's cannot be keyed (:func:`user_modules`);
    ``FileNotFoundError`` naming a declared file that is not a file."""
    texts, imports, names, where = [], set(), set(), []
    by_module: dict[str, list] = {}
    for obj in (config_type, run):
        by_module.setdefault(obj.__module__, []).append(obj)
    done = set()
    for module, objects in by_module.items():
        path = _file_of(module, objects)
        if path is not None:
            starts = {o.__qualname__.partition(".")[0] for o in objects}
            tokens, found, imported = _module_text(module, path, starts)
            texts.append(f"file\n{tokens}")  # not its name: a script is __main__ or a module
            imports |= found
            names |= imported
            where.append(str(path))
            done.add(module)
        else:
            more, found, imported, places = _cell_code(objects, run)
            texts += more
            imports |= found
            names |= imported
            where += places
    needed = dict(user_modules(names - done))
    for name, path in needed.items():
        tokens, found = fingerprint.code_tokens(path.read_text(encoding="utf-8"), name)
        texts.append(f"module {name}\n{tokens}")
        imports |= found
        where.append(str(path))
    for file in files:
        path = Path(file).resolve()
        if not path.is_file():
            raise FileNotFoundError(f"register: files names {file}, which is not a file")
        texts.append(f"file {path.name}\n{hashlib.sha256(path.read_bytes()).hexdigest()}")
        where.append(f"{path} (data)")
    digest = hashlib.sha256("\n".join(texts).encode()).hexdigest()
    followed = sorted(m for m in imports if m.startswith("docking."))
    return OwnCode(digest, tuple(followed), tuple(where), _shipped(done, needed))


def _shipped(defining: set[str], needed: dict[str, Path]) -> tuple[tuple[str, str], ...]:
    """:attr:`OwnCode.modules`: ``needed`` (the user's modules the learner's code imports),
    the modules ``defining`` the class and the run function that have a file (but
    ``__main__``), the packages these are in, and what those import, in name order."""
    found = {name: str(path) for name, path in needed.items()}
    for name in defining - {"__main__"}:
        path = _file_of(name, [])
        if path is not None:
            found[name] = str(path)
    parents = {p for name in found for p in _with_parents([name]) if p not in found}
    found.update((name, str(path)) for name, path in user_modules(parents - set(found)))
    return tuple(sorted(found.items()))
