"""The process's rendering environment, set before MuJoCo is first imported.

MuJoCo reads ``MUJOCO_GL`` when it is imported, and with ``egl`` initialises its EGL display
(and with it Mesa) there and then: the defaults below must be in place before *any* module
imports ``mujoco`` (:mod:`docking.scene` compiles the asset with it, :mod:`docking.world`
renders). Importing this module sets them (unless the user did) and does nothing else.
"""

from __future__ import annotations

import os

# Headless rendering by default: EGL through Mesa works on CPU-only machines. Must be set
# before dm_control.mujoco is imported.
os.environ.setdefault("MUJOCO_GL", "egl")
if os.environ["MUJOCO_GL"] in ("egl", "osmesa"):
    os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])
# Mesa's llvmpipe rasterizes in the calling thread: for 160x120 frames its worker threads
# cost more in synchronisation than they save (measured ~1.6x slower per frame on 2 cores),
# and experiments run one process per core.
os.environ.setdefault("LP_NUM_THREADS", "0")


class RenderingUnavailable(RuntimeError):
    """MuJoCo cannot render here: the ``MUJOCO_GL`` backend is unknown or its library is
    missing. The message says what to install or set."""


#: The rendering backends MuJoCo knows, the library each one loads, and where to get it.
_GL_BACKENDS = {
    "egl": ("EGL", "Debian/Ubuntu: apt-get install libegl1 libgl1-mesa-dri (`make setup` does it)"),
    "osmesa": ("OSMesa", "Debian/Ubuntu: apt-get install libosmesa6"),
    "glfw": (None, "it needs a display (X11/Wayland); on a headless machine use MUJOCO_GL=egl"),
}


def check_gl_backend() -> None:
    """Fail with a clear message, before ``import mujoco`` does with an obscure one, when
    ``MUJOCO_GL`` names no backend or its library is missing."""
    import ctypes.util

    backend = os.environ["MUJOCO_GL"]
    if backend not in _GL_BACKENDS:
        raise RenderingUnavailable(
            f"MUJOCO_GL={backend!r} is not a rendering backend MuJoCo knows; use one of "
            f"{', '.join(_GL_BACKENDS)} (headless machines: MUJOCO_GL=egl)"
        )
    library, remedy = _GL_BACKENDS[backend]
    if library is not None and ctypes.util.find_library(library) is None:
        raise RenderingUnavailable(
            f"MUJOCO_GL={backend} needs the {library} library, which is not installed: {remedy}"
        )
