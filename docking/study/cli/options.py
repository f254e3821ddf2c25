"""What every command's options share: tyro's registry (numbers read as the seeds are, every
option's help reflowed, the configuration dataclasses handed to
:mod:`docking.study.cli.named`), the option types the commands share, and the words every
command says (why the ledger serves no run). Imports nothing heavy: a command's own modules
are imported when it runs.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import os
import re
from pathlib import Path
from typing import Annotated

import tyro

from docking.study import paths


def registry(brief: bool = False) -> tyro.constructors.ConstructorRegistry:
    """tyro's rules for a command line (:func:`docking.study.cli.parse`): every integer and
    real option read as the seeds are (:func:`_as_number`), every dataclass's fields with
    their help reflowed, and a configuration's as :func:`docking.study.cli.named.as_options`
    shows them (``brief``, for ``--help``: its common fields alone)."""
    found = tyro.constructors.ConstructorRegistry()
    found.primitive_rule(_as_number)
    found.struct_rule(functools.partial(_as_options, brief=brief))
    return found


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


#: ``(the name of its parser in docking.validate, is_instance)`` per number type: every integer
#: and real option (and each number of a tuple option) is read as the seeds are, ASCII digits
#: and no underscores (tyro's own ``int`` and ``float`` would read ``1_0`` as 10 and other
#: scripts' digits as theirs).
_NUMBERS = {
    int: ("parse_int", _is_int),
    float: ("parse_real", lambda v: isinstance(v, float) or ("~" if _is_int(v) else False)),
}


def _as_number(info):
    """An ``int`` or ``float`` option read by :func:`docking.validate.parse_int` or
    :func:`docking.validate.parse_real` (tyro prints their error as the option's)."""
    if info.type not in _NUMBERS:
        return None
    parser, is_instance = _NUMBERS[info.type]
    return tyro.constructors.PrimitiveConstructorSpec(
        nargs=1,
        metavar=info.type.__name__.upper(),
        instance_from_str=functools.partial(_parsed, parser),
        is_instance=is_instance,
        str_from_instance=lambda value: [str(value)],
    )


def _parsed(parser: str, args: list[str]):
    """``args``' one value read by ``docking.validate``'s ``parser`` (imported here: numpy)."""
    from docking import validate

    return getattr(validate, parser)(args[0])


#: The dataclasses :func:`_as_options` is expanding (tyro's own expansion is asked for inside
#: it, which asks the rules again).
_expanding: set[type] = set()


def _as_options(info, brief: bool):
    """tyro's own expansion of a struct (a command's dataclass, a configuration, tyro's own),
    with each field's help reflowed (:func:`reflow`) and, for a dataclass of the core (a
    configuration: the experiment's parts; the commands' are the study layer's), its fields as
    the command line shows them (:func:`docking.study.cli.named.as_options`, imported only
    then: no other command's options meet one)."""
    if info.type in _expanding:
        return None
    _expanding.add(info.type)
    try:
        spec = tyro.constructors.ConstructorRegistry.get_struct_spec(info)
    finally:
        _expanding.discard(info.type)
    if not isinstance(spec, tyro.constructors.StructConstructorSpec):
        return spec
    fields = tuple(dataclasses.replace(f, helptext=_reflowed(f.helptext)) for f in spec.fields)
    module = getattr(info.type, "__module__", "")
    if module.startswith("docking.") and not module.startswith("docking.study."):
        from docking.study.cli import named  # the core's: a configuration

        fields = named.as_options(info.type, fields, brief)
    return dataclasses.replace(spec, fields=fields)


def _reflowed(helptext):
    """An option's help (a text, None, or tyro's callable that gives it) as :func:`reflow`
    gives it."""
    if callable(helptext):
        return lambda: _reflowed(helptext())
    return reflow(helptext) if helptext else helptext


_LIST_ITEM = re.compile(r"\s*([-*\u2022]|\d+\.)\s")


def reflow(text: str) -> str:
    """``text`` (a docstring) as one line per paragraph: blank lines and list items
    ("- ", "* ", "1. ") keep their breaks, every other line break becomes a space. (tyro keeps
    a docstring's line break wherever the next line does not begin with a letter, and reads an
    attribute's docstring with its indentation: every continued line of an option's help, and
    a line beginning ``(`` or ``--``, broke the help mid-sentence.)"""
    paragraphs = re.split(r"\n\s*\n", inspect.cleandoc(text))
    return "\n\n".join(
        "".join(
            ("\n" + line) if _LIST_ITEM.match(line) else (" " if k else "") + line.strip()
            for k, line in enumerate(p.split("\n"))
        )
        for p in paragraphs
    )


def _shown(metavar: str, default: str):
    """An option whose value None means "not given": its value as ``metavar`` (instead of
    tyro's "{None}|STR") and its default in words (instead of "(default: None)")."""
    return tyro.conf.arg(metavar=metavar, help_behavior_hint=f"(default: {default})")


_Processes = Annotated[int | None, _shown("INT", "one per core")]


_Scheduler = Annotated[str | None, _shown("STR", "an embedded cluster on 127.0.0.1")]


_ResultsDir = Annotated[
    Path | None,
    _shown("PATH", "DOCKING_RESULTS, the checkout's results/ or the per-user data folder's"),
]


_FiguresDir = Annotated[
    Path | None,
    _shown("PATH", "DOCKING_FIGURES, the checkout's figures/ or the per-user data folder's"),
]


_ExperimentSeeds = Annotated[
    str | None, _shown("STR", "the experiment's, docking.presets.SEEDS; a world's: Experiment 2's")
]


_DesignSeeds = Annotated[str | None, _shown("STR", "the design's")]


def _seed_text(seeds) -> str:
    """``0-4, 7`` for ``[0, 1, 2, 3, 4, 7]`` (:func:`docking.study.sweep.seeds_text`)."""
    from docking.study.sweep import seeds_text

    return seeds_text(seeds)


def _absent(text: str, how: str) -> str:
    """The error of runs that are neither stored nor in the ledger: ``text`` says which, then
    how to get the ledger if it is off or absent, then ``how`` to compute them."""
    why = _no_ledger()
    return f"{text}. {why[0].upper()}{why[1:]}. Or {how}" if why else f"{text}: {how}"


def _no_ledger() -> str | None:
    """Why the ledger serves no run, and what to do, if it is switched off or absent (an
    installed package: the ledger is the ledger/ folder of the project's git repository, which
    no wheel carries); None if there is a ledger."""
    if paths.ledger_off():
        return (
            f"the ledger is switched off by DOCKING_LEDGER={os.environ['DOCKING_LEDGER']}; "
            "unset it, or set it to a ledger folder"
        )
    if paths.ledger_dir() is None:
        return (
            "this installed package has no ledger (the committed runs that report and figures "
            "read are the ledger/ folder of the project's git repository, which no wheel "
            "carries): clone the repository and run python -m docking in the clone, or set "
            "DOCKING_LEDGER to the absolute path of the clone's ledger/ folder"
        )
    return None
