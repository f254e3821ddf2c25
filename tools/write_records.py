"""Write the pre-registered designs' rules as records (``rules/``, issue 61), once, from the
repository's history: for each design, the rules text whose SHA-256 its test pinned at the
rules' commit, and, where its rules digest covered code (a walk, a verdict function), a
verbatim copy of that code as it was at the rules' commit, never imported.

The text is what ``rules_text()`` gives with the design module's tokens and the judging
functions' source read as at the rules' commit (``git show``): its digest is checked against
the pinned one before anything is written. Run from the checkout's root, with its history:

    .venv/bin/python tools/write_records.py

It also writes ``rules/<design>.replay.json``: the cells each design's procedure walks on the
committed ledger's runs and the verdicts it reaches (docking.study.designs.replay), so that a
later change of the live code that walks or judges otherwise is caught by the replay test.
"""

from __future__ import annotations

import ast
import contextlib
import gzip
import hashlib
import inspect
import json
import subprocess
import sys
from pathlib import Path
from unittest import mock

ROOT = Path(__file__).resolve().parents[1]
RULES = ROOT / "rules"

#: ``{design: (module, pinned digest, commit, the judging functions the digest covered)}``;
#: commit None: the rules text is the live one (it covers no code).
PINNED = {
    "third-edition": (
        "third_edition",
        "cd2a0602b296679342c67a9afe926c24a0baa8901a6f55c48a4e2fbac2984ac4",
        None,
        (),
    ),
    "untested": (
        "untested",
        "9c3e3a99b36d5f6f16eef28e8ef64bc9a7751bcb46b6b99a23932784e66c52b7",
        None,
        (),
    ),
    "fragility-landscape": (
        "landscape",
        "1e457a7d4dd78ecef8eb4de75b91126021a8c63dfacfb4740d533a4c9b89ac9c",
        None,
        (),
    ),
    "third-edition-addendum": (
        "addendum",
        "7809d4840d852585f603d398a8a24f8c31a1c635af7b71396390d747cd9728b9",
        "d1c52e9bf46ba23103503e7970b191404d74bc41",
        ("report.contest_gaps", "report.paired_over_shared_seeds", "stats.t_paired_ci"),
    ),
    "addendum-bracketing": (
        "bracketing",
        "061f85bf9f2da895b0038717c06fc814a98c213ab4f01bd8f64c1c14b1978077",
        "670c9e6773a9e2035b391bce4e358110d9ff574a",
        ("report.contest_gaps", "report.paired_over_shared_seeds", "stats.t_paired_ci"),
    ),
    "addendum-bracketing-continued": (
        "bracketing_continued",
        "0cbf59c64e30ae0423858268f0e5a7404f26b340fe772a75ca72fc26450976e4",
        "b0c138ea24092af1c9a7dceb12989d1ec4b14fb1",
        ("report.contest_gaps", "report.paired_over_shared_seeds", "stats.t_paired_ci"),
    ),
    "untested-revisited": (
        "revisited",
        "580a6f6e3a0dfcf48976abdfd065c7cb93e73cc70325192beb9f0925c49d0f6b",
        "52625147765c7d4dc7461dbebe4ae30eb3ce338f",
        (
            "claims.Rule",
            "claims.Above",
            "claims.Equivalent",
            "claims.judge_family",
            "claims.one_family",
            "claims.pair_of",
            "stats.holm",
            "stats.t_paired_ci",
            "stats.Interval",
        ),
    ),
    "bracketing-replication": (
        "replication",
        "4aacdf6f66bdac36460b5e0ed4941a87ab22c8b2cd894c912704c27a484cf15e",
        "792adb7ac21e904685cd3b2080140ec9c2eb4ca8",
        (),
    ),
}
#: The erratum of the third edition's rules (a label; its test shows it is the only change).
ERRATUM = (
    "the paper's networks without a red cup minus with one never seen in training",
    "the paper's networks with a red cup never seen minus without",
)


def show(commit: str, path: str) -> str:
    return subprocess.run(
        ["git", "show", f"{commit}:{path}"], capture_output=True, text=True, check=True, cwd=ROOT
    ).stdout


def path_at(commit: str, module: str) -> str:
    """The file of ``module`` (``docking.study.X``) at ``commit``: ``docking/study/X.py``, or
    ``docking/X.py`` before the study layer moved."""
    now = module.replace(".", "/") + ".py"
    found = subprocess.run(
        ["git", "cat-file", "-e", f"{commit}:{now}"], cwd=ROOT, stderr=subprocess.DEVNULL
    )
    return now if found.returncode == 0 else now.replace("docking/study/", "docking/", 1)


def definition(source: str, qualname: str) -> str:
    lines = source.splitlines(keepends=True)
    for node in ast.parse(source).body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef) and node.name == qualname:
            first = node.decorator_list[0].lineno if node.decorator_list else node.lineno
            return "".join(lines[first - 1 : node.end_lineno])
    raise LookupError(f"{qualname} is not in the source")


@contextlib.contextmanager
def as_at(commit: str, modules):
    """Within this, the design ``modules``' tokens and the study layer's functions' source are
    read as they were at ``commit``; yields what was read."""
    from docking.study import fingerprint

    now = {Path(m.__file__).read_text(): m.__name__ for m in modules}
    read = {"files": {}, "functions": {}}
    tokens, source = fingerprint.code_tokens, inspect.getsource

    def code_tokens(text, module=""):
        if text in now:
            name = now[text]
            text = show(commit, path_at(commit, name))
            read["files"][name] = text
        return tokens(text, module)

    def getsource(obj):
        current = source(obj)
        module = getattr(obj, "__module__", "") or ""
        if not module.startswith("docking.study."):
            return current
        before = definition(show(commit, path_at(commit, module)), obj.__qualname__)
        read["functions"][f"{module}.{obj.__qualname__}"] = before
        return before

    with (
        mock.patch.object(fingerprint, "code_tokens", code_tokens),
        mock.patch.object(inspect, "getsource", getsource),
    ):
        yield read


def committed(name: str) -> tuple[str, dict]:
    """The rules text of design ``name`` as committed, and the code read as at its commit."""
    import importlib

    module_name, digest, commit, _ = PINNED[name]
    module = importlib.import_module(f"docking.study.designs.{module_name}")
    if commit is None:
        text, read = module.rules_text(), {"files": {}, "functions": {}}
        if name == "third-edition":
            text = text.replace(ERRATUM[0], ERRATUM[1])
    else:
        from docking.study.designs import addendum, bracketing

        chain = {
            "addendum-bracketing": [addendum],
            "addendum-bracketing-continued": [bracketing, addendum],
        }
        with as_at(commit, [module, *chain.get(name, [])]) as read:
            text = module.rules_text()
    found = hashlib.sha256(text.encode()).hexdigest()
    if found != digest:
        raise SystemExit(f"{name}: the text read as at {commit} has digest {found}, not {digest}")
    return text, read


def procedure_text(name: str, read: dict) -> str:
    """The verbatim copy: the design modules as at the rules' commit, then each judging
    function's definition then, in the order the rules' digest read them, each part headed by
    a line naming it (``# ==== module NAME`` or ``# ==== function NAME``)."""
    parts = [(f"module {k}", v) for k, v in read["files"].items()]  # in the order read
    parts += [(f"function {k}", v) for k, v in read["functions"].items()]
    return "".join(f"# ==== {head}\n{body}" for head, body in parts)


def main(names: list[str]) -> int:
    """Write the records of ``names`` (default: every pinned design; the rules text only for
    those of :data:`PINNED`), their replays from the ledger."""
    sys.path.insert(0, str(ROOT))
    from docking.study import designs

    names = names or list(PINNED)
    RULES.mkdir(exist_ok=True)
    for name in [n for n in names if n in PINNED]:
        text, read = committed(name)
        with gzip.GzipFile(RULES / f"{name}.json.gz", "wb", mtime=0) as f:
            f.write(text.encode())
        if read["files"] or read["functions"]:
            assert "# ==== " not in "".join([*read["files"].values(), *read["functions"].values()])
            (RULES / f"{name}.procedure.py.txt").write_text(procedure_text(name, read))
        print(f"{name}: rules {hashlib.sha256(text.encode()).hexdigest()[:16]}", flush=True)
    for name in names:
        replay = designs.replay(name)
        (RULES / f"{name}.replay.json").write_text(
            json.dumps(replay, indent=1, sort_keys=True) + "\n"
        )
        print(f"{name}: replay of {len(replay['cells'])} cells", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
