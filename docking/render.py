"""Offscreen rendering with MuJoCo's low-level API on one OpenGL context per process.

A :class:`SceneRenderer` draws views of one model with ``mjv_updateScene``, ``mjr_render`` and
``mjr_readPixels``, on an OpenGL context that the whole process shares and that is made
current only when some other context has taken its place (dm-control's ``Physics.render``
makes its own contexts current, for instance). A :class:`View` is one fixed way of looking:
a camera, a pixel size, the geom groups drawn, the lights, and optionally a *window*: a
rectangle of a larger frame that is rendered on its own, with the projection narrowed to it,
so that its pixels are those the larger frame has there (up to rounding at triangle edges;
``tests/test_world.py`` counts them).

The OpenGL backend follows ``MUJOCO_GL`` (``egl`` for headless CPU rendering with Mesa's
llvmpipe); :mod:`docking.world` sets it before MuJoCo is imported.
"""

from __future__ import annotations

import atexit
import ctypes
import os

import mujoco
import numpy as np

_CONTEXT = None  # the process's OpenGL context (created on first use)
_BOUND = None  # the SceneRenderer whose offscreen framebuffer is bound
_ADDRESSES = {}  # id(context) -> its EGL handle as an int (looked up once)


def _gl_context():
    """The process's shared OpenGL context, current on return."""
    global _CONTEXT
    if _CONTEXT is None:
        # dm_control's renderer initialises the same EGL display when it is imported and
        # registers its termination at exit; imported before this context exists, it
        # terminates after the context is freed (atexit runs handlers in reverse order).
        import dm_control.mujoco  # noqa: F401
        from mujoco.gl_context import GLContext

        # The size matters for window/pbuffer backends only; the models render into their
        # own offscreen framebuffers (visual/global offwidth x offheight).
        _CONTEXT = GLContext(960, 720)
        _CONTEXT.make_current()
        # Free it before the backend shuts down at exit (atexit runs handlers in reverse).
        atexit.register(_free_context)
    else:
        _make_current(_CONTEXT)
    return _CONTEXT


def gl_stack() -> str:
    """The OpenGL stack that renders the frames: ``MUJOCO_GL``, then the driver's
    ``GL_VERSION``, ``GL_RENDERER`` and ``GL_VENDOR`` strings (e.g. Mesa's version and llvmpipe
    with its LLVM version), read from the process's context. Frames, and so runs, depend on
    it; the results store puts it in every run's key."""
    global _STACK
    if _STACK is None:
        _gl_context()
        from OpenGL import GL

        names = (GL.GL_VERSION, GL.GL_RENDERER, GL.GL_VENDOR)
        strings = [(GL.glGetString(n) or b"?").decode("utf-8", "replace") for n in names]
        _STACK = " | ".join([f"MUJOCO_GL={os.environ.get('MUJOCO_GL', '')}", *strings])
    return _STACK


_STACK = None


def _free_context() -> None:
    global _CONTEXT, _BOUND
    _BOUND = None
    if _CONTEXT is not None:
        _ADDRESSES.pop(id(_CONTEXT), None)
        _CONTEXT.free()
        _CONTEXT = None


def _make_current(context) -> None:
    """Make ``context`` current unless it already is (one cheap query per frame with EGL)."""
    if _current_context is not None:
        address = _ADDRESSES.get(id(context))
        if address is None:
            address = _ADDRESSES[id(context)] = _address(context)
        if address is not None and _current_context() == address:
            return
    context.make_current()


def _egl_current_context():
    """libEGL's ``eglGetCurrentContext`` as a bare ctypes function (PyOpenGL's wrapper costs
    ~15 us a call), or None when rendering does not go through EGL."""
    if os.environ.get("MUJOCO_GL") != "egl":
        return None
    try:
        function = ctypes.CDLL("libEGL.so.1").eglGetCurrentContext
    except (OSError, AttributeError):
        return None
    function.restype, function.argtypes = ctypes.c_void_p, []
    return function


def _address(context) -> int | None:
    """The EGL context handle of a ``mujoco.egl.GLContext`` as an int."""
    handle = getattr(context, "_context", None)
    return ctypes.cast(handle, ctypes.c_void_p).value if handle is not None else None


_current_context = _egl_current_context()


class SceneRenderer:
    """Renders views of one ``mujoco.MjModel`` on the process's shared OpenGL context.

    Args:
      model: The compiled model; its ``visual/global offwidth x offheight`` bounds the size of
        a view.
      max_geom: Capacity of the abstract scene (geoms drawn at once).
    """

    def __init__(self, model: mujoco.MjModel, max_geom: int = 1000):
        self._gl = _gl_context()
        self.model = model
        self._context = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_50)
        self._scene = mujoco.MjvScene(model, maxgeom=max_geom)
        self._perturb = mujoco.MjvPerturb()
        self.max_width = int(model.vis.global_.offwidth)
        self.max_height = int(model.vis.global_.offheight)

    def view(
        self,
        camera: str,
        width: int,
        height: int,
        groups,
        lights: bool = True,
        window: tuple[int, int, int, int] | None = None,
    ) -> View:
        """A reusable :class:`View` of ``camera`` for a ``width x height`` frame.

        Args:
          camera: Name of a camera of the model.
          width, height: The frame's size in pixels.
          groups: The geom groups drawn (0-5).
          lights: Light the scene with the model's lights and the headlight (True) or with
            the headlight alone (False).
          window: ``(x0, y0, x1, y1)``: render only this rectangle of the frame (pixels,
            rows from the top), with the frame's projection narrowed to it.
        """
        return View(self, camera, width, height, groups, lights, window)

    def _draw(self, data: mujoco.MjData, view: View) -> np.ndarray:
        global _BOUND
        _make_current(self._gl)
        if _BOUND is not self:  # several renderers (models) share the context
            mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._context)
            _BOUND = self
        scene = self._scene
        mujoco.mjv_updateScene(
            self.model,
            data,
            view.option,
            self._perturb,
            view.camera,
            mujoco.mjtCatBit.mjCAT_ALL,
            scene,
        )
        if not view.lights:
            # mjv_updateScene puts the headlight (if active) first, then the model's lights.
            scene.nlight = min(scene.nlight, int(self.model.vis.headlight.active))
        if view.window is not None:
            view.narrow(scene)
        mujoco.mjr_render(view.rect, scene, self._context)
        mujoco.mjr_readPixels(view.pixels, None, view.rect, self._context)
        return view.pixels[::-1]  # OpenGL's rows run bottom-up


class View:
    """One fixed way of rendering a model: camera, size, geom groups, lights, window.

    ``render(data)`` returns the RGB image ``(rows, cols, 3)`` uint8 as a view of the
    ``View``'s own buffer, overwritten by the next call (copy it to keep it)."""

    def __init__(self, renderer, camera, width, height, groups, lights, window):
        model = renderer.model
        x0, y0, x1, y1 = window if window is not None else (0, 0, width, height)
        if not (0 <= x0 < x1 <= width and 0 <= y0 < y1 <= height):
            raise ValueError(f"window must lie inside the {width}x{height} frame, got {window}")
        if x1 - x0 > renderer.max_width or y1 - y0 > renderer.max_height:
            raise ValueError(
                f"a {x1 - x0}x{y1 - y0} view exceeds the model's offscreen buffer "
                f"({renderer.max_width}x{renderer.max_height})"
            )
        self._renderer = renderer
        self.size = (width, height)
        self.window = None if window is None else (x0, y0, x1, y1)
        self.lights = bool(lights)
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
        self.camera.fixedcamid = model.camera(camera).id
        self.option = mujoco.MjvOption()
        self.option.geomgroup[:] = 0
        for group in groups:
            self.option.geomgroup[group] = 1
        self.rect = mujoco.MjrRect(0, 0, x1 - x0, y1 - y0)
        self.pixels = np.empty((y1 - y0, x1 - x0, 3), dtype=np.uint8)
        self._frustum = None

    def render(self, data: mujoco.MjData) -> np.ndarray:
        """The view of ``data``'s current kinematics (``mj_kinematics``/``mj_camlight``
        must be up to date)."""
        return self._renderer._draw(data, self)

    def narrow(self, scene: mujoco.MjvScene) -> None:
        """Narrow the scene's frustum (set by ``mjv_updateScene`` for the whole frame) to the
        window: the window's pixels keep their place on the near plane."""
        if self._frustum is None:
            cam = scene.camera[0]
            width, height = self.size
            x0, y0, x1, y1 = self.window
            top, bottom = float(cam.frustum_top), float(cam.frustum_bottom)
            # mjr_render's half-width when frustum_width is 0: the viewport's aspect ratio.
            half = float(cam.frustum_width) or 0.5 * width / height * (top - bottom)
            left = float(cam.frustum_center) - half
            row, col = (top - bottom) / height, 2 * half / width
            l, r = left + x0 * col, left + x1 * col
            self._frustum = (top - y0 * row, top - y1 * row, (l + r) / 2, (r - l) / 2)
        top, bottom, center, half = self._frustum
        for cam in scene.camera:
            cam.frustum_top, cam.frustum_bottom = top, bottom
            cam.frustum_center, cam.frustum_width = center, half
