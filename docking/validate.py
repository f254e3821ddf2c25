"""Field checks shared by the configuration dataclasses.

Every config of the package (``WorldConfig``, ``CameraConfig``, ``NetworkConfig``,
``Curriculum``, ``ExperimentConfig``) checks each field at construction with these functions.
A wrong *type* raises :class:`FieldTypeError` (a ``TypeError`` and a ``ValueError``), a value
out of range ``ValueError``; both name ``Class.field`` and the value. Bools are not numbers;
counts are integers (numpy integers are accepted and stored as plain ``int``); reals are
stored as plain ``float``.

The ``check_*`` functions return the normalised value; :func:`normalise` writes it back into a
frozen dataclass. :func:`parse_int` and :func:`parse_real` read a number from the command line
(every option and ``--grid`` value, and the seeds' digits: :data:`DIGITS`).
"""

from __future__ import annotations

import math
import numbers
import re

import numpy as np

__all__ = [
    "DIGITS",
    "MAX_COUNT",
    "MAX_SEED",
    "FieldTypeError",
    "check_bool",
    "check_choice",
    "check_instance",
    "check_int",
    "check_name",
    "check_pose",
    "check_real",
    "check_int_tuple",
    "normalise",
    "parse_int",
    "parse_real",
]

#: A safe file-name component: letters, digits, ``.``, ``_`` and ``-``, starting with a letter
#: or digit, at most 100 characters (so ``..``, ``/`` and absolute paths are impossible).
NAME_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")


#: Digits as the command line reads them: ASCII ``0-9`` only. Python's ``int`` and ``float``
#: also read ``1_0`` as 10 and other scripts' digits (``\u0661``, ``\uff11``) as theirs.
DIGITS = "[0-9]+"
_INT_TEXT = re.compile(f"-?{DIGITS}")
#: ``5``, ``-0.5``, ``.5``, ``1e-3``, ``2.5E+2``; ``nan`` and ``inf`` are read, for the fields'
#: checks to refuse by name.
_REAL_TEXT = re.compile(
    rf"-?({DIGITS}\.?[0-9]*|\.{DIGITS})([eE][-+]?{DIGITS})?|-?(inf|infinity|nan)", re.IGNORECASE
)


def parse_int(text: str) -> int:
    """The integer ``text`` writes in ASCII digits with an optional ``-`` (``ValueError``
    otherwise, saying what an integer is written as)."""
    if not isinstance(text, str) or not _INT_TEXT.fullmatch(text):
        raise ValueError(
            f"{text!r} is not an integer: write ASCII digits 0-9 (an optional leading -), "
            "without underscores"
        )
    return int(text)


def parse_real(text: str) -> float:
    """The real number ``text`` writes in ASCII digits (``5``, ``-0.5``, ``1e-3``; ``nan``,
    ``inf``), ``ValueError`` otherwise, saying what a number is written as."""
    if not isinstance(text, str) or not _REAL_TEXT.fullmatch(text):
        raise ValueError(
            f"{text!r} is not a number: write ASCII digits 0-9 with an optional leading -, "
            "point and exponent (5, 0.5, 1e-3), without underscores"
        )
    return float(text)


#: The largest seed the package accepts (seeds name files and numpy ``SeedSequence`` entropy).
MAX_SEED = 2**32 - 1

#: The largest trial count a configuration accepts (a run of 10**6 trials takes days).
MAX_COUNT = 1_000_000


class FieldTypeError(TypeError, ValueError):
    """A value of the wrong type. A ``TypeError``, and also a ``ValueError`` so that callers
    that treat every bad input as a ``ValueError`` catch it too."""


def _where(owner: str, field: str) -> str:
    return f"{owner}.{field}"


def _is_bool(value) -> bool:
    return isinstance(value, (bool, np.bool_))


def check_int(owner: str, field: str, value, *, lo: int | None = None, hi: int | None = None):
    """An integer (Python or numpy, not a bool) in ``[lo, hi]``; returned as ``int``."""
    if _is_bool(value) or not isinstance(value, (numbers.Integral, np.integer)):
        raise FieldTypeError(
            f"{_where(owner, field)} must be an integer, got {value!r} ({type(value).__name__})"
        )
    value = int(value)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        raise ValueError(f"{_where(owner, field)} must be in [{lo}, {hi}], got {value}")
    return value


def check_real(
    owner: str,
    field: str,
    value,
    *,
    lo: float | None = None,
    hi: float | None = None,
    lo_open: bool = False,
    hi_open: bool = False,
) -> float:
    """A finite real number (int or float, Python or numpy, not a bool) in the interval
    ``lo..hi`` (each end closed unless ``*_open``); returned as ``float``, ``-0.0`` as
    ``0.0`` (a configuration's JSON, so its runs' key, must not tell them apart)."""
    if _is_bool(value) or not isinstance(value, (numbers.Real, np.integer, np.floating)):
        raise FieldTypeError(
            f"{_where(owner, field)} must be a real number, got {value!r} ({type(value).__name__})"
        )
    try:
        value = float(value)
    except OverflowError:  # an int beyond float's range, e.g. 10**400
        raise ValueError(
            f"{_where(owner, field)} must be finite, got an integer of "
            f"{len(str(abs(int(value))))} digits"
        ) from None
    if not math.isfinite(value):
        raise ValueError(f"{_where(owner, field)} must be finite, got {value}")
    below = lo is not None and (value <= lo if lo_open else value < lo)
    above = hi is not None and (value >= hi if hi_open else value > hi)
    if below or above:
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        raise ValueError(
            f"{_where(owner, field)} must be in {left}{lo_s}, {hi_s}{right}, got {value:g}"
        )
    return value + 0.0  # -0.0 + 0.0 is 0.0; every other value is unchanged


def check_bool(owner: str, field: str, value) -> bool:
    """A bool (Python or numpy); returned as ``bool``."""
    if not _is_bool(value):
        raise FieldTypeError(
            f"{_where(owner, field)} must be a bool, got {value!r} ({type(value).__name__})"
        )
    return bool(value)


def check_choice(owner: str, field: str, value, choices: tuple):
    """One of ``choices`` (compared by equality, type checked against the first choice)."""
    if not isinstance(value, type(choices[0])):
        raise FieldTypeError(
            f"{_where(owner, field)} must be one of {choices}, got {value!r} "
            f"({type(value).__name__})"
        )
    if value not in choices:
        raise ValueError(f"{_where(owner, field)} must be one of {choices}, got {value!r}")
    return value


def check_name(owner: str, field: str, value) -> str:
    """A safe file-name component (see :data:`NAME_PATTERN`)."""
    if not isinstance(value, str):
        raise FieldTypeError(
            f"{_where(owner, field)} must be a str, got {value!r} ({type(value).__name__})"
        )
    if not NAME_PATTERN.fullmatch(value):
        raise ValueError(
            f"{_where(owner, field)} must be a safe file-name component (letters, digits, "
            f"'.', '_', '-'; starting with a letter or digit; at most 100 characters), "
            f"got {value!r}"
        )
    return value


def check_instance(owner: str, field: str, value, cls: type):
    """An instance of ``cls``."""
    if not isinstance(value, cls):
        raise FieldTypeError(
            f"{_where(owner, field)} must be a {cls.__name__}, got {value!r} "
            f"({type(value).__name__})"
        )
    return value


def check_int_tuple(
    owner: str, field: str, value, length: int, *, lo: int | None = None, hi: int | None = None
) -> tuple[int, ...]:
    """A tuple or list of ``length`` integers, each in ``[lo, hi]``; returned as a tuple."""
    if not isinstance(value, (tuple, list)) or len(value) != length:
        raise FieldTypeError(
            f"{_where(owner, field)} must be a tuple of {length} integers, got {value!r}"
        )
    return tuple(check_int(owner, f"{field}[{k}]", v, lo=lo, hi=hi) for k, v in enumerate(value))


def check_pose(owner: str, pose) -> np.ndarray:
    """A robot pose ``[x, y, yaw]``: three finite reals; returned as a float64 array."""
    try:
        array = np.asarray(pose, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        array = None
    if array is None or array.shape != (3,):
        raise FieldTypeError(f"{owner}: pose must be [x, y, yaw] (3 reals), got {pose!r}")
    if not np.isfinite(array).all():
        raise ValueError(f"{owner}: pose must be finite, got {array.tolist()}")
    return array


def normalise(instance, **values) -> None:
    """Store checked, normalised field values on a frozen dataclass ``instance``."""
    for name, value in values.items():
        object.__setattr__(instance, name, value)
