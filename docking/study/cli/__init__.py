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
import os
import signal
import sys

__all__ = ["DESCRIPTION", "HELP_ALL", "PROG", "check_rendering", "main", "parse", "take_ctrl_c"]

#: The command line's name in its messages.
PROG = "python -m docking"

DESCRIPTION = (
    "Kleesiek et al. (2011) on dm-control: run the experiments, sweep parameters on a Dask "
    "cluster, print the results table, benchmark the environment."
)

#: The option that prints every option of an experiment (``--help`` shows the common ones,
#: :data:`docking.study.cli.named.COMMON`).
HELP_ALL = "--help-all"


def _commands():
    """The commands, as tyro's subcommands: each a dataclass whose ``execute()`` runs it, and
    whose docstring is its description. Their modules import what a command runs when it
    runs (and run's and sweep's options the experiment's modules when they are built:
    :mod:`docking.study.cli.named`)."""
    from typing import Annotated, Union

    import tyro

    from docking.study.cli.ledger import Benchmark, Ledger, Verify
    from docking.study.cli.options import reflow
    from docking.study.cli.report import Figures, Report
    from docking.study.cli.runs import DesignCommand, Run, Sweep

    commands = {
        "run": Run,
        "sweep": Sweep,
        "design": DesignCommand,
        "report": Report,
        "figures": Figures,
        "ledger": Ledger,
        "verify": Verify,
        "benchmark": Benchmark,
    }
    # Each class its own constructor: tyro then builds the options of the command given alone
    # (it expands a Union's every member to see whether it is one of structs, else).
    return Union[  # noqa: UP007 (tyro needs a runtime Union of Annotated members)
        tuple(
            Annotated[
                kind, tyro.conf.subcommand(name, description=reflow(kind.__doc__), constructor=kind)
            ]
            for name, kind in commands.items()
        )
    ]


def _exit_on_sigterm(signum, frame):
    # SystemExit unwinds the stack: a running sweep closes its cluster and workers.
    raise SystemExit(128 + signum)


def _exit_on_ctrl_c(signum, frame):
    """Ctrl-C while ``python -m docking`` imports a command's modules and parses its command
    line: one line and status 130, nothing to undo. (A KeyboardInterrupt there is a traceback,
    or an ImportError when an extension module's initialisation meets it.)"""
    print(f"{PROG}: interrupted", file=sys.stderr, flush=True)
    os._exit(130)


def take_ctrl_c() -> bool:
    """Make Ctrl-C :func:`_exit_on_ctrl_c` until :func:`main` runs the command, unless SIGINT
    is ignored (a shell's background job: it stays ignored, as Python leaves it); whether it
    did. ``python -m docking`` calls it first."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        return False
    signal.signal(signal.SIGINT, _exit_on_ctrl_c)
    return True


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


#: The narrowest help tyro is given: at a few columns its formatter never ends (issue 41).
MIN_COLUMNS = 40


@contextlib.contextmanager
def _wide_enough():
    """``COLUMNS`` at least :data:`MIN_COLUMNS` while tyro builds the parser and its help (tyro
    reads the width as :func:`shutil.get_terminal_size` gives it): a narrower terminal (or
    ``COLUMNS=5``) gets the help at that width, wrapped by the terminal."""
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


def parse(argv: list[str]):
    """The command ``argv`` names, parsed and checked, not run (``SystemExit`` as argparse
    exits: on bad input, and after printing ``--help``). ``--help`` shows an experiment's
    common options, :data:`HELP_ALL` every one."""
    import tyro

    from docking.study.cli.options import registry

    brief = HELP_ALL not in argv and any(a in ("-h", "--help") for a in argv)
    with _wide_enough():
        return tyro.cli(
            _commands(),
            args=["--help" if a == HELP_ALL else a for a in argv],
            prog=PROG,
            description=DESCRIPTION,
            config=(tyro.conf.CascadeSubcommandArgs,),
            registry=registry(brief),
        )


def main(argv=None) -> int:
    """Parse ``argv`` (default ``sys.argv[1:]``) and run the subcommand; its exit status."""
    from docking.glenv import RenderingUnavailable

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
    except RenderingUnavailable as exc:  # run's and sweep's options import MuJoCo: checked
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 1
    signal.signal(signal.SIGTERM, _exit_on_sigterm)
    # From here Ctrl-C interrupts the command (a KeyboardInterrupt), so that a sweep closes its
    # cluster on the way out; this says so in one line and returns 130.
    if signal.getsignal(signal.SIGINT) is _exit_on_ctrl_c:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        check_rendering()  # RenderingUnavailable, a RuntimeError: one line
        return command.execute()
    except KeyboardInterrupt:
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


def check_rendering() -> None:
    """:class:`docking.glenv.RenderingUnavailable`, in one line, if MuJoCo cannot render here:
    before a command imports MuJoCo, whose own failure is a traceback. Its backend
    (:func:`docking.glenv.check_gl_backend`), and ``PYOPENGL_PLATFORM``, which must be unset or
    the ``MUJOCO_GL`` backend (egl or osmesa), or dm-control's renderer fails with an
    ``ImportError`` on its first import (checked here, not in :mod:`docking.glenv`, whose code
    keys every run)."""
    from docking.glenv import RenderingUnavailable, check_gl_backend

    check_gl_backend()
    backend = os.environ.get("MUJOCO_GL", "")
    platform = os.environ.get("PYOPENGL_PLATFORM", "")
    if backend in ("egl", "osmesa") and platform not in ("", backend):
        raise RenderingUnavailable(
            f"PYOPENGL_PLATFORM={platform!r} does not match MUJOCO_GL={backend}: dm-control "
            f"renders with {backend} only if PYOPENGL_PLATFORM is unset or {backend!r}"
        )
