"""The source fingerprint: the code that computes a run's arrays, read so that its digest
moves when that code's arithmetic can, and only then.

A module is read as Python *tokens* (:mod:`tokenize`), not as a syntax tree: ``ast.dump``
differs between Python versions, the tokens of one source do not (3.12's split f-string tokens
are joined back into one). Left out of the tokens:

* comments, blank lines and indentation widths (indentation is kept as its structure);
* docstrings, and every other statement that is only a string (a field's docstring,
  which the command line shows as the option's help), each with its line, so that adding
  one moves nothing either;
* type annotations (of fields, arguments and returns) and what an ``assert`` says;
* what a ``raise`` statement says: it is kept as ``raise`` and the exception's name, so a
  reworded error message re-keys nothing (a raise ends a run; it computes no array);
* the definitions named in :data:`UNKEYED`: validation, parsing, serialisation and display,
  which decide whether a configuration is accepted and how it is written, never what a run
  computes (the configuration's every field enters the key as canonical JSON anyway), each
  whole: from its first decorator to the NEWLINE and DEDENT tokens that end its body, so that
  splitting a check into helpers named there moves nothing either;
* the modules named in :data:`UNKEYED_MODULES` (the atomic file writer), which are not
  followed either.

The walk starts at a root module (``docking.experiments`` for the learner's runs) and follows
the ``docking`` imports of the code it keeps. This module uses the standard library only, so
that tests can compute a fingerprint under every installed interpreter without the package's
dependencies (tests/test_fingerprint.py).
"""

from __future__ import annotations

import ast
import bisect
import hashlib
import io
import tokenize
from pathlib import Path

__all__ = ["UNKEYED", "UNKEYED_MODULES", "code_tokens", "imported_names", "module_code", "walk"]

#: Modules that compute nothing a run stores: never fingerprinted, never followed (the atomic
#: file writer). ``docking.validate`` is keyed: its checks run inside every run (on a computed
#: beta_a, on an action) and return what they are given normalised (``-0.0`` as ``0.0``), so an
#: edit there could change a run (tests/test_keyed_trace.py runs every kind of run under a
#: profiler and fails on any function it calls outside its key).
UNKEYED_MODULES = frozenset({"docking.fileio"})

#: Definitions (``function`` or ``Class.method``) per module that compute nothing a run stores.
UNKEYED: dict[str, frozenset[str]] = {
    "docking.experiments": frozenset(
        {
            # validation (values enter the key through the configuration's JSON)
            "Curriculum.__post_init__",
            "ExperimentConfig.__post_init__",
            "ExperimentConfig._check_fields",
            "ExperimentConfig._check_policy",
            "ExperimentConfig._check_before",
            "ExperimentConfig._check_worlds",
            "ExperimentConfig._check_curriculum",
            "ExperimentConfig._check_network_shape",
            # the configuration as JSON and back
            "ExperimentConfig.to_dict",
            "ExperimentConfig.from_dict",
            "_fields",
            "_tuples",
            "_world_from_dict",
        }
    ),
    "docking.network": frozenset(
        {
            "NetworkConfig.__post_init__",
            "Network.save",
            "Network.load",
            "Network.__repr__",
            "Network._check_action",
            "Network._check_vector",
            "Network._check_step",
        }
    ),
    "docking.scene": frozenset(
        {
            "Distractor.__post_init__",
            "WorldConfig.__post_init__",
            "WorldConfig._check_kinds",
            "WorldConfig._check_distractor_types",
            "WorldConfig._check_fields",
            "WorldConfig._check_crop_margin",
            "WorldConfig._check_regions",
            "WorldConfig._check_distractors",
            # the floor geometry of the distractors' check
            "_robot_regions",
            "_polygon_edges",
            "_separated",
            "_to_edges",
            "_floor_gap",
            "_footprint",
        }
    ),
    "docking.trial": frozenset({"_check_arguments"}),
    "docking.world": frozenset({"_check_config", "_check_start_pose", "_check_crop_query"}),
    "docking.camera": frozenset({"CameraConfig.__post_init__"}),
}


def _char_col(lines: list[str], lineno: int, byte_col: int) -> int:
    """ast's UTF-8 byte offset on line ``lineno`` as tokenize's character offset."""
    return len(lines[lineno - 1].encode("utf-8")[:byte_col].decode("utf-8", "replace"))


#: The replacement of a left-out statement that goes with its whole line.
_WHOLE_LINE = "<whole line>"
#: The replacement of a left-out definition, which goes with the NEWLINE and DEDENT tokens
#: that end its body (so that adding or removing one moves nothing).
_DEFINITION = "<definition>"
#: The replacement of an argument's or a return's type hint, which goes with its ":" or "->"
#: (a field's annotation keeps its ":": without one, a dataclass has no field).
_HINT = "<hint>"


def _imported(node, package: str) -> set[str]:
    """The names an import statement ``node`` of a module in ``package`` imports (a module,
    or a name in one: ``docking.world`` and ``docking.world.DockingEnv``); none for any other
    statement."""
    if isinstance(node, ast.Import):
        return {alias.name for alias in node.names}
    if not isinstance(node, ast.ImportFrom):
        return set()
    base = node.module or ""
    if node.level:  # relative import
        parts = package.split(".")[: len(package.split(".")) - node.level + 1]
        base = ".".join(parts + ([base] if base else []))
    return {base} | {f"{base}.{alias.name}" for alias in node.names}


def _spans(source: str, module: str) -> tuple[list, set[str]]:
    """``([(start, end, replacement)], {names imported by the kept code})``: the regions of
    ``source`` the fingerprint leaves out (see the module docstring), and every module (or
    name in one) that the code it keeps imports."""
    tree = ast.parse(source)
    lines = source.splitlines(keepends=True) or [""]
    unkeyed = UNKEYED.get(module, frozenset())
    spans = []

    def span(node, first=None, replacement="", column=None):
        first = first or node
        column = first.col_offset if column is None else column
        start = (first.lineno, _char_col(lines, first.lineno, column))
        end = (node.end_lineno, _char_col(lines, node.end_lineno, node.end_col_offset))
        spans.append((start, end, replacement))

    imports: set[str] = set()
    package = module.rpartition(".")[0]

    def visit(node, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if (
                isinstance(child, ast.Expr)
                and isinstance(child.value, ast.Constant)
                and isinstance(child.value.value, str)
            ):
                # a docstring, or a field's: a statement that is only a string computes
                # nothing; it goes with its line, so that adding one moves nothing either
                span(child, replacement=_WHOLE_LINE)
            elif isinstance(child, ast.AnnAssign):  # a field: its name and value, not its type
                span(child.annotation)
                visit(child, prefix)
            elif isinstance(child, ast.arg) and child.annotation is not None:
                span(child.annotation, replacement=_HINT)  # with its ":"
            elif isinstance(child, ast.Assert) and child.msg is not None:
                span(child.msg)  # what an assert says, like what a raise says
                visit(child.test, prefix)
            elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                name = f"{prefix}{child.name}"
                if name in unkeyed:
                    # from its first decorator's "@" (in the definition's column) to its end
                    first = child.decorator_list[0] if child.decorator_list else child
                    span(child, first, _DEFINITION, column=child.col_offset)
                    continue
                if getattr(child, "returns", None) is not None:
                    span(child.returns, replacement=_HINT)  # the return type, with its "->"
                visit(child, f"{name}.")
            elif isinstance(child, ast.Raise):
                exc = child.exc.func if isinstance(child.exc, ast.Call) else child.exc
                span(child, replacement=f"raise {ast.unparse(exc) if exc else ''}")
            else:
                imports.update(_imported(child, package))
                visit(child, prefix)

    visit(tree, "")
    return spans, imports


def imported_names(source: str, module: str = "") -> set[str]:
    """Every module, or name in one (``helpers``, ``helpers.GAIN``), that the code of
    ``source`` (module ``module``, for relative imports) keeps imports: what a learner's key
    follows beyond the package (:func:`docking.study.learners.own_code`)."""
    return _spans(source, module)[1]


def code_tokens(source: str, module: str = "") -> tuple[str, set[str]]:
    """The tokens of ``source`` the fingerprint reads, one string, and the ``docking``
    modules the kept code imports."""
    spans, imports = _spans(source, module)
    # names that are not modules (``docking.world.DockingEnv``) find no file and are dropped
    imports = {name for name in imports if name.startswith("docking.")}
    spans.sort()
    starts = [s[0] for s in spans]
    out: list[str] = []
    tokens = list(tokenize.generate_tokens(io.StringIO(source).readline))
    lines = source.splitlines(keepends=True)
    k = 0
    while k < len(tokens):
        tok = tokens[k]
        at = bisect.bisect_right(starts, tok.start) - 1
        inside = spans[at] if at >= 0 and tok.start < spans[at][1] else None
        if inside is not None and tok.type == tokenize.DEDENT and tok.start == inside[0]:
            inside = None  # the dedent before a left-out definition belongs to the code above
        if inside is not None:
            start, end, replacement = inside
            if replacement is _HINT:
                if out and out[-1] in (":", "->"):
                    out.pop()
            elif replacement and replacement not in (_WHOLE_LINE, _DEFINITION):
                out.append(replacement)
            depth = 0  # the blocks opened inside the span and not closed there
            while k < len(tokens) and tokens[k].start < end:
                depth += (tokens[k].type == tokenize.INDENT) - (tokens[k].type == tokenize.DEDENT)
                k += 1
            if replacement is _DEFINITION:  # and its last NEWLINE and the DEDENTs of its body
                k = _past_block_end(tokens, k, depth)
            if replacement is _WHOLE_LINE:  # and the rest of its line, up to its NEWLINE
                while k < len(tokens) and tokens[k].type in (tokenize.COMMENT, tokenize.NL):
                    k += 1
                if k < len(tokens) and tokens[k].type == tokenize.NEWLINE:
                    k += 1
            continue
        kind = tok.type
        if kind in (tokenize.COMMENT, tokenize.NL, tokenize.ENCODING, tokenize.ENDMARKER):
            pass
        elif kind == tokenize.INDENT:
            out.append("<indent>")
        elif kind == tokenize.DEDENT:
            out.append("<dedent>")
        elif kind == tokenize.NEWLINE:
            out.append("\n")
        elif tokenize.tok_name.get(kind) == "FSTRING_START":  # Python >= 3.12
            depth, j = 0, k
            while True:
                name = tokenize.tok_name.get(tokens[j].type)
                depth += (name == "FSTRING_START") - (name == "FSTRING_END")
                if depth == 0:
                    break
                j += 1
            out.append(_text(lines, tok.start, tokens[j].end))
            k = j
        else:
            out.append(tok.string)
        k += 1
    return " ".join(out), imports


def _past_block_end(tokens: list, k: int, depth: int) -> int:
    """The index after the NEWLINE at ``tokens[k]`` (if it is one) and the ``depth`` DEDENT
    tokens that follow it (comments and blank lines between them skipped): what ends a
    left-out definition's body."""
    ignored = (tokenize.COMMENT, tokenize.NL)
    while k < len(tokens) and tokens[k].type in ignored:
        k += 1
    if k < len(tokens) and tokens[k].type == tokenize.NEWLINE:
        k += 1
    while depth > 0 and k < len(tokens) and tokens[k].type in (*ignored, tokenize.DEDENT):
        depth -= tokens[k].type == tokenize.DEDENT
        k += 1
    return k


def _text(lines: list[str], start: tuple[int, int], end: tuple[int, int]) -> str:
    """The source between two tokenize positions."""
    if start[0] == end[0]:
        return lines[start[0] - 1][start[1] : end[1]]
    middle = lines[start[0] : end[0] - 1]
    return lines[start[0] - 1][start[1] :] + "".join(middle) + lines[end[0] - 1][: end[1]]


def _module_file(name: str, package_dir: Path) -> Path | None:
    relative = Path(*name.split(".")[1:])
    for candidate in (package_dir / f"{relative}.py", package_dir / relative / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def module_code(package_dir: Path, name: str) -> tuple[str, set[str], bytes] | None:
    """``(tokens, imported docking modules, the file's bytes)`` of module ``name``, or None
    for a name that is no module of the package or is unkeyed."""
    if name in UNKEYED_MODULES:
        return None
    path = _module_file(name, package_dir)
    if path is None:
        return None
    raw = path.read_bytes()
    tokens, imports = code_tokens(raw.decode("utf-8"), name)
    return tokens, imports, raw


def walk(package_dir: Path, root: str) -> tuple[str, list[tuple[str, str]], dict[str, str]]:
    """``(SHA-256 of the code, [(module, its digest)], {file: SHA-256 of its bytes})`` of
    ``root`` and every module its kept code imports, in a fixed order."""
    digest = hashlib.sha256()
    parts, files = [], {}
    seen, queue = set(), [root]
    while queue:
        name = queue.pop()
        if name in seen:
            continue
        seen.add(name)
        found = module_code(package_dir, name)
        if found is None:
            continue
        tokens, imports, raw = found
        path = _module_file(name, package_dir)
        files[path.relative_to(package_dir).as_posix()] = hashlib.sha256(raw).hexdigest()
        # sorted: a set's order changes with PYTHONHASHSEED, i.e. from process to process
        queue.extend(sorted(imports))
        code = f"module {name}\n{tokens}\n".encode()
        digest.update(code)
        parts.append((name, hashlib.sha256(code).hexdigest()))
    return digest.hexdigest(), parts, files


if __name__ == "__main__":  # python -I docking/study/fingerprint.py: the code's digests, as JSON
    import json
    import sys

    here = Path(__file__).resolve().parents[1]  # the docking package
    code, parts, _ = walk(here, sys.argv[1] if len(sys.argv) > 1 else "docking.experiments")
    print(json.dumps({"code": code, "modules": dict(parts)}, sort_keys=True))
