"""The command line, ``python -m docking`` (also installed as ``docking``).

Built by tyro from the configuration dataclasses and their docstrings, so every field of an
:class:`~docking.experiments.ExperimentConfig` (but its held-out world, see :data:`HIDDEN`) is
an option with its documented default::

    python -m docking run experiment2 --seeds 0-19 --network.eps-w 0
    python -m docking sweep experiment2 --seeds 0-9 --grid network.eps_w=0,0.05 \
        --scheduler tcp://127.0.0.1:8786
    python -m docking design list
    python -m docking design run experiment3 [--full]
    python -m docking report --readme README.md
    python -m docking benchmark --steps 2000

``run`` and ``sweep`` store every run they compute in the results store
(:mod:`docking.study.store`), keyed by its configuration and seed; a run the store or the committed
ledger holds is loaded, not recomputed, so an interrupted command resumes where it stopped. Progress
bars go to the terminal (stderr); where stderr is not a terminal, a line at the start (the runs to
compute, about how long) and one per run finished. ``--help`` (of the command and of each
subcommand) prints usage and starts nothing.
"""

from __future__ import annotations

import contextlib
import inspect
import os
import re
import signal
import sys
from typing import Annotated, Union

import tyro

from docking import _check_opengl_platform
from docking.study.cli import options
from docking.study.cli.ledger import Benchmark, Ledger, Verify
from docking.study.cli.options import HELP_ALL, PROG, _registry
from docking.study.cli.report import Figures, Report
from docking.study.cli.runs import DesignCommand, Run, Sweep

__all__ = ["DESCRIPTION", "PROG", "Command", "main", "parse"]

DESCRIPTION = (
    "Kleesiek et al. (2011) on dm-control: run the experiments, sweep parameters on a Dask "
    "cluster, print the results table, benchmark the environment."
)


Command = Union[  # noqa: UP007
    Annotated[Run, tyro.conf.subcommand("run")],
    Annotated[Sweep, tyro.conf.subcommand("sweep")],
    Annotated[DesignCommand, tyro.conf.subcommand("design")],
    Annotated[Report, tyro.conf.subcommand("report")],
    Annotated[Figures, tyro.conf.subcommand("figures")],
    Annotated[Ledger, tyro.conf.subcommand("ledger")],
    Annotated[Verify, tyro.conf.subcommand("verify")],
    Annotated[Benchmark, tyro.conf.subcommand("benchmark")],
]


def _exit_on_sigterm(signum, frame):
    # SystemExit unwinds the stack: a running sweep closes its cluster and workers.
    raise SystemExit(128 + signum)


#: The folder options whose empty value tyro would read as the current folder.
_FOLDER_OPTIONS = ("--results-dir", "--results_dir", "--folder", "--figures-dir", "--figures_dir")


def _empty_folder_option(argv: list[str]) -> str | None:
    """The first folder option of ``argv`` given an empty value (``--results-dir ''`` or
    ``--results-dir=``), which ``Path`` would turn into the current folder; else None."""
    for k, arg in enumerate(argv):
        name, equals, value = arg.partition("=")
        if name not in _FOLDER_OPTIONS:
            continue
        if not equals:
            value = argv[k + 1] if k + 1 < len(argv) else None
        if value is not None and not value.strip():
            return name
    return None


def _option_name(arg: str) -> str | None:
    """The option ``arg`` gives, as one name for its spellings (``--train_trials`` and
    ``--train-trials=4`` are ``--train-trials``; the flag ``--no-x`` is ``--x``'s), or None
    for what is no option (a value, a subcommand, ``--help``)."""
    if not arg.startswith("--") or arg == "--":
        return None
    name = arg.partition("=")[0].replace("_", "-")
    if name in ("--help", HELP_ALL):
        return None
    head, dot, last = name[2:].rpartition(".")
    return f"--{head}{dot}{last.removeprefix('no-')}"


def _repeated_option(argv: list[str]) -> str | None:
    """Why ``argv`` is refused if it gives one option twice (``--seeds 0 --seeds 1``, or
    ``--experiment3 --no-experiment3``): argparse would keep the last without a word; else
    None. Nothing after ``--`` is read."""
    seen: dict[str, str] = {}
    for arg in argv:
        if arg == "--":
            break
        name = _option_name(arg)
        if name is None:
            continue
        given = arg.partition("=")[0]
        if name in seen:
            first = seen[name]
            both = (
                f"{given} is given twice"
                if first == given
                else f"{first} and {given} are both given"
            )
            return f"{both}: the command line would keep the last alone; give it once"
        seen[name] = given
    return None


_LIST_ITEM = re.compile(r"\s*([-*\u2022]|\d+\.)\s")


def _reflow(text: str) -> str:
    """``text`` (a docstring) as one line per paragraph: blank lines and list items
    ("- ", "* ", "1. ") keep their breaks, every other line break becomes a space."""
    paragraphs = re.split(r"\n\s*\n", inspect.cleandoc(text))
    return "\n\n".join(
        "".join(
            ("\n" + line) if _LIST_ITEM.match(line) else (" " if k else "") + line.strip()
            for k, line in enumerate(p.split("\n"))
        )
        for p in paragraphs
    )


@contextlib.contextmanager
def _reflowed_help():
    """Help texts reflowed by :func:`_reflow` while tyro builds the parser. tyro 1.0 keeps a
    docstring's line break wherever the next line does not begin with a letter, and reads an
    option's docstring with its indentation, so every continued line of an option's text
    (and a line beginning ``_,`` or ``25-action``) broke the help mid-sentence."""
    from tyro import _strings

    original = getattr(_strings, "remove_single_line_breaks", None)
    if original is None:  # another tyro: its own reflowing
        yield
        return
    _strings.remove_single_line_breaks = _reflow
    try:
        yield
    finally:
        _strings.remove_single_line_breaks = original


#: The narrowest help tyro is given: at a few columns its formatter never ends (issue 41).
MIN_COLUMNS = 40


@contextlib.contextmanager
def _wide_enough():
    """``COLUMNS`` at least :data:`MIN_COLUMNS` while tyro builds the parser and its help: a
    narrower terminal (or ``COLUMNS=5``) gets the help at that width, wrapped by the
    terminal."""
    import shutil

    saved = os.environ.get("COLUMNS")
    if shutil.get_terminal_size().columns < MIN_COLUMNS:
        os.environ["COLUMNS"] = str(MIN_COLUMNS)
    try:
        yield
    finally:
        if saved is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = saved


@contextlib.contextmanager
def _help_of(argv: list[str]):
    """``argv`` with :data:`HELP_ALL` read as ``--help``; while tyro builds the parser for a
    ``--help`` (not :data:`HELP_ALL`), an experiment's options are its common ones
    (:data:`docking.study.cli.options.COMMON`)."""
    saved = options._brief
    options._brief = HELP_ALL not in argv and any(a in ("-h", "--help") for a in argv)
    try:
        yield ["--help" if a == HELP_ALL else a for a in argv]
    finally:
        options._brief = saved


def parse(argv: list[str]) -> Command:
    """The command ``argv`` names, parsed and checked, not run (``SystemExit`` as argparse
    exits: on bad input, and after printing ``--help``)."""
    with _reflowed_help(), _wide_enough(), _help_of(argv) as args:
        return tyro.cli(
            Command,
            args=args,
            prog=PROG,
            description=DESCRIPTION,
            config=(tyro.conf.CascadeSubcommandArgs,),
            registry=_registry,
        )


def main(argv=None) -> int:
    """Parse ``argv`` (default ``sys.argv[1:]``) and run the subcommand; its exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    empty = _empty_folder_option(argv)
    if empty is not None:  # as DOCKING_RESULTS / DOCKING_FIGURES set but empty are refused
        print(
            f"{PROG}: error: {empty} is empty; name a folder, or leave the option out",
            file=sys.stderr,
        )
        return 2
    repeated = _repeated_option(argv)
    if repeated is not None:
        print(f"{PROG}: error: {repeated}", file=sys.stderr)
        return 2
    try:
        command = parse(argv)
    except KeyboardInterrupt:  # Ctrl-C while tyro builds the parser
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    signal.signal(signal.SIGTERM, _exit_on_sigterm)
    try:
        _check_opengl_platform()  # RenderingUnavailable, a RuntimeError: one line
        return command.execute()
    except KeyboardInterrupt:  # Ctrl-C: a running sweep has closed its cluster on the way
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except ValueError as exc:  # bad input (seeds, grid entries, configuration values)
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    except (OSError, RuntimeError, LookupError) as exc:
        # A folder that cannot be written, a scheduler that does not answer, code or a
        # ledger that changed (StaleCode, StaleLedger), a run the ledger does not keep.
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 1
