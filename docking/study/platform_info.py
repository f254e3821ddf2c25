"""The numeric platform a process computes on: what the ledger records and ``verify`` prints.

Runs are computed so that their bits do not depend on the CPU's SIMD level
(:mod:`docking.arith`): on x86-64 machines with AVX2 and FMA (x86-64-v3, Intel since 2013,
AMD since 2015) and the same libraries (the lock file), every run is the same, whatever numpy
dispatches to, whichever OpenBLAS kernel is loaded, with OpenCV's optimised code on or off
(tests/test_platform.py). Elsewhere (an x86-64 CPU without FMA, whose C library computes
``exp``, ``sin`` and ``cos`` by other code paths; aarch64; another C library) runs may differ
in the last bits, and ``verify`` says which of these facts differ.
"""

from __future__ import annotations

import platform

__all__ = ["compare", "cpu_features", "numeric_platform", "x86_64_level"]


def cpu_features() -> dict[str, bool]:
    """numpy's view of the CPU's features (``{"AVX2": True, ...}``), as numpy dispatches by
    them: a feature switched off by ``NPY_DISABLE_CPU_FEATURES`` reads False.

    Read from numpy's private table because ``numpy.show_config(mode="dicts")`` lists only
    numpy's dispatch targets (``X86_V3``, ...), not the CPU's features (``FMA3``,
    ``AVX512F``, ...) that :func:`x86_64_level` and tests/test_platform.py need."""
    import numpy as np

    try:
        from numpy._core._multiarray_umath import __cpu_features__
    except ImportError:  # numpy < 2
        from numpy.core._multiarray_umath import __cpu_features__
    del np
    return dict(__cpu_features__)


def x86_64_level(features: dict[str, bool] | None = None) -> str:
    """The x86-64 micro-architecture level the CPU offers numpy (``v1`` to ``v4``), or the
    machine's architecture elsewhere."""
    machine = platform.machine()
    if machine not in ("x86_64", "AMD64"):
        return machine
    f = cpu_features() if features is None else features
    if all(f.get(k) for k in ("AVX512F", "AVX512BW", "AVX512CD", "AVX512DQ", "AVX512VL")):
        return "x86-64-v4"
    if all(f.get(k) for k in ("AVX", "AVX2", "FMA3", "F16C")):
        return "x86-64-v3"
    if all(f.get(k) for k in ("SSE3", "SSSE3", "SSE41", "SSE42", "POPCNT")):
        return "x86-64-v2"
    return "x86-64"


def _numpy_levels() -> str:
    """numpy's dispatch targets above its baseline that are on, as ``numpy.show_config`` lists
    them (a target switched off by ``NPY_DISABLE_CPU_FEATURES`` is not listed)."""
    import numpy as np

    simd = np.show_config(mode="dicts").get("SIMD Extensions", {})
    return " ".join(simd.get("found", ())) or "its baseline only"


def _openblas_core() -> str:
    try:
        from threadpoolctl import threadpool_info
    except ImportError:
        return "unknown (threadpoolctl not installed)"
    import numpy  # noqa: F401  (loads numpy's OpenBLAS, so that threadpoolctl sees it)

    cores = [
        i.get("architecture", "?") for i in threadpool_info() if i["internal_api"] == "openblas"
    ]
    return ", ".join(sorted(set(cores))) or "none loaded"


def numeric_platform() -> dict[str, str]:
    """The facts that decide a run's arithmetic besides the code and the libraries' versions
    (which are in every key): the CPU's architecture and x86-64 level, what numpy
    dispatches to, OpenBLAS's core type, the C library, OpenCV's optimised code."""
    import cv2
    import numpy as np

    features = cpu_features()
    return {
        "architecture": platform.machine(),
        "level": x86_64_level(features),
        "numpy": f"{np.__version__}, dispatching to {_numpy_levels()}",
        "openblas": _openblas_core(),
        "libc": " ".join(platform.libc_ver()) or "unknown",
        "opencv": f"{cv2.__version__}, optimised code {'on' if cv2.useOptimized() else 'off'}",
        "python": platform.python_version(),
    }


#: What a difference in each fact means for a run's bits.
_MEANING = {
    "architecture": "another architecture: runs may differ in the last bits (not checked)",
    "level": "runs are the same on x86-64-v3 and v4; below v3 (no FMA) the C library's exp, "
    "sin and cos take other code paths and runs may differ",
    "numpy": "the same run at every numpy dispatch level (tests/test_platform.py)",
    "openblas": "runs do not use OpenBLAS (docking.arith): no effect",
    "libc": "another C library: its exp, sin and cos (numpy's and MuJoCo's) may round otherwise",
    "opencv": "the same run with OpenCV's optimised code on or off (tests/test_platform.py)",
    "python": "the same run on every supported Python (tests/test_platform.py)",
}


def compare(theirs: dict[str, str], ours: dict[str, str] | None = None) -> list[str]:
    """One line per fact of ``theirs`` (a recorded platform) that differs from ``ours``
    (default: this process's), with what the difference means."""
    ours = numeric_platform() if ours is None else ours
    return [
        f"{k}: {theirs.get(k)!r} there, {ours.get(k)!r} here ({_MEANING.get(k, 'unknown fact')})"
        for k in sorted(set(theirs) | set(ours))
        if theirs.get(k) != ours.get(k)
    ]
