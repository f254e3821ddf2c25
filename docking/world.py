"""The docking world: a domestic room, a Nao-sized robot, a red landmark, a virtual dock.

This is the dm-control rebuild of the paper's Webots scene (Sec. II-C, Fig. 2). Like a
dm-control ``suite`` domain it has three parts: the MJCF model (the asset
``docking/assets/docking.xml``, with the parts the configs choose set by :func:`make_mjcf`), a
:class:`Physics` with the helpers the task needs (the robot's pose, its camera, the landmark's
projection), and the task itself as a ``dm_env.Environment`` (:class:`DockingEnv`).

Frame of reference (all lengths in metres): the landmark stands at the origin side of the room
at the back of a low grey sideboard; the landmark's front face is the plane ``x = 0`` and the
sideboard's front face stands 0.35 m in front of it. The robot starts at negative ``x`` facing
``+x`` (yaw 0). The robot's body frame has ``x`` forward and ``y`` to its left.

The docking region (paper, Fig. 5: "The yellow docking region measures 8x20 cm") is centred on
the landmark's axis. The paper does not say which side is which; here it is **20 cm across**
(along ``y``) and **8 cm deep** (along ``x``, towards the landmark): a strip the robot must
reach at the right distance, squarely enough in front of the landmark. Its depth is less than
a forward step, so the region is detected continuously, at every physics step of a walking
step, and the robot halts once its reference point is inside: a step cannot jump over it
(the paper does not say how "reaching the goal position" was detected). The region is
virtual: the robot's camera never sees it; overview renders draw it in yellow.

The robot is a planar base (slide x, slide y, hinge yaw) driven by position servos; each of the
paper's four actions (or six with the turning set of Experiment 3) is one walking step whose
target is displaced by noise in position and heading,
and the servos walk the body there through MuJoCo physics, so collisions with the landmark's
sideboard, the walls and the furniture are real. The humanoid itself (torso, head, arms, legs)
is visual only.

Rendering (:mod:`docking.render`): the robot's camera renders, for each observation, only the
crop rectangle of its frame (the projection narrowed to it) and only geom group 2 of the
asset, the geoms that can change the input (what can appear red, and what can stand between
the camera and the landmark); ``tests/test_world.py`` shows that this gives the pixels of the
whole frame with the whole room. Figures get the whole frame (``DockingEnv.frame``) and the
overview cameras (``DockingEnv.render_view``).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
from pathlib import Path

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


def _check_gl_backend() -> None:
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


_check_gl_backend()

import dm_env  # noqa: E402
import mujoco  # noqa: E402
import numpy as np  # noqa: E402
from dm_control import mjcf  # noqa: E402
from dm_control import mujoco as dm_mujoco  # noqa: E402
from dm_env import specs  # noqa: E402

from docking.camera import CameraConfig, preprocess_band  # noqa: E402
from docking.region import StartRegion  # noqa: E402
from docking.render import SceneRenderer  # noqa: E402
from docking.validate import (  # noqa: E402
    MAX_SEED,
    FieldTypeError,
    check_choice,
    check_instance,
    check_int,
    check_pose,
    check_real,
    normalise,
)

# Action indices. The paper (Sec. II-C): "four actions - moving forward, backward, right and
# left"; left and right are sidesteps (Nao walks sideways), not turns. The turning set (the
# paper's future work, Experiment 3) adds two rotations in place after them, so the paper's
# four keep their indices in either set.
FORWARD, BACKWARD, LEFT, RIGHT, TURN_LEFT, TURN_RIGHT = 0, 1, 2, 3, 4, 5

#: The action sets a world can have (:attr:`WorldConfig.actions`): action names in index
#: order.
ACTION_SETS = {
    "paper": ("forward", "backward", "left", "right"),
    "turning": ("forward", "backward", "left", "right", "turn-left", "turn-right"),
}

#: Short labels of the actions, for figures and tables.
_LETTERS = {
    "forward": "F",
    "backward": "B",
    "left": "L",
    "right": "R",
    "turn-left": "TL",
    "turn-right": "TR",
}

#: The paper's action set (the default world's); a world's own set is
#: :attr:`WorldConfig.action_names` / :attr:`WorldConfig.action_letters`.
ACTION_NAMES = ACTION_SETS["paper"]
ACTION_LETTERS = tuple(_LETTERS[name] for name in ACTION_NAMES)
N_ACTIONS = len(ACTION_NAMES)

# Geom groups of the asset: 0 the room, 1 the robot's visual body (hidden from its own
# camera), 2 what the robot's camera draws (everything that can appear red), 3 the virtual
# docking region (only in overview renders).
_ROOM_GROUP, _ROBOT_GROUP, _EYE_GROUP, _DOCK_GROUP = 0, 1, 2, 3


#: The scenes a world can be built as (:attr:`WorldConfig.scene`).
SCENES = ("sideboard", "floor")

#: The shapes a distractor can have and how many ``size`` values each takes (MuJoCo's geom
#: sizes: box half-extents x, y, z; cylinder radius and half-height; sphere radius).
DISTRACTOR_SHAPES = {"box": 3, "cylinder": 2, "sphere": 1}


@dataclasses.dataclass(frozen=True)
class Distractor:
    """A red object in the room besides the landmark.

    The paper (Sec. IV): "noise (e.g. other red objects within the visual field) should not
    affect performance". A distractor has the landmark's red, so it passes the camera's
    threshold wherever it enters the crop; it is solid (the robot bumps into it).

    Attributes:
      shape: ``"box"``, ``"cylinder"`` (standing upright) or ``"sphere"``.
      size: MuJoCo's geom size for the shape (m): box half-extents ``(x, y, z)``, cylinder
        ``(radius, half-height)``, sphere ``(radius,)``.
      position: The centre ``(x, y, z)`` in the world frame (m; the landmark's front face is
        ``x = 0``, the sideboard's top 0.43 m above the floor).
    """

    shape: str
    size: tuple[float, ...]
    position: tuple[float, float, float]

    def __post_init__(self):
        owner = "Distractor"
        shape = check_choice(owner, "shape", self.shape, tuple(DISTRACTOR_SHAPES))
        n = DISTRACTOR_SHAPES[shape]
        if not isinstance(self.size, (tuple, list)) or len(self.size) != n:
            raise FieldTypeError(
                f"Distractor.size of a {shape} must be {n} numbers, got {self.size!r}"
            )
        size = tuple(
            check_real(owner, f"size[{k}]", v, lo=0, hi=1, lo_open=True)
            for k, v in enumerate(self.size)
        )
        if not isinstance(self.position, (tuple, list)) or len(self.position) != 3:
            raise FieldTypeError(
                f"Distractor.position must be (x, y, z) in metres, got {self.position!r}"
            )
        position = tuple(
            check_real(owner, f"position[{k}]", v, lo=-5, hi=5) for k, v in enumerate(self.position)
        )
        normalise(self, shape=shape, size=size, position=position)

    @classmethod
    def cup(cls, y: float = 0.30) -> Distractor:
        """A red cup (7 cm across, 9 cm high) on the sideboard, ``y`` m beside the landmark's
        axis, level with the landmark's front face."""
        return cls("cylinder", (0.035, 0.045), (0.03, y, 0.43 + 0.045))


@dataclasses.dataclass(frozen=True)
class WorldConfig:
    """Everything the paper leaves open about the world, with documented defaults.

    Attributes:
      step_forward: Length of a forward or backward step (m). One action is a short walk
        (about two of Nao's steps). The paper gives no length; it decides how much of the
        25-action budget a start 1.5 m away needs, and with it how often the near-random
        walk of training (beta_a = 2) reaches the dock and how large the learned values
        are (measured in notebook 04, "What the choices do").
      step_side: Length of a left or right sidestep (m); half the docking region's width, so
        one sidestep from anywhere within 10 cm outside the region ends inside it. (Nao's
        walk allows up to 16 cm sideways per step.)
      step_noise_xy: Std. of the displacement error added to each step, per body axis (m).
      step_noise_yaw_deg: Std. of the heading error of each step (deg). The paper names
        uncorrected rotation from Webots' movement noise as its main cause of failure.
      max_steps: At most this many actions per trial (paper: 25).
      start_near, start_far: The start trapezoid spans these distances of the robot's
        reference point from the landmark's front plane (m). Experiment 2 ends at 1.5 m.
      start_half_angle_deg: Half the opening angle of the start trapezoid, a wedge with its
        apex at the landmark, cut at ``start_near`` and ``start_far``
        (:class:`docking.region.StartRegion`, which ``DockingEnv`` samples from).
      start_yaw_deg: Start headings are uniform in +-this around facing the landmark's wall.
      dock_center: Distance of the docking region's centre from the landmark's front plane (m);
        the region's near edge lies 1 cm beyond where the robot meets the sideboard (0.45 m).
      dock_depth: Extent of the region along the approach axis (m; paper: 8 cm).
      dock_width: Extent of the region across the approach axis (m; paper: 20 cm).
      view_margin_px: At a start pose the landmark's projection keeps this many pixels from
        the crop's border.
      camera: The head camera and the observation pipeline.
      distractors: Red objects besides the landmark (:class:`Distractor`); none by default.
      scene: ``"sideboard"`` (default): the landmark stands on a sideboard at the camera's
        height, whose front stops the robot at the dock. ``"floor"``: the sideboard is taken
        away and the landmark stands on the floor at the same place; nothing stops the robot
        at the dock (it can overshoot or walk past the landmark's side), and with the camera
        tilted down the landmark's image moves vertically with distance. See :data:`SCENES`.
      actions: The action set (:data:`ACTION_SETS`): ``"paper"`` (default), the paper's four
        steps; ``"turning"`` adds turn-left and turn-right (indices 4 and 5), a rotation in
        place by ``turn_deg`` with the same noise as every step (position noise on both body
        axes, heading noise).
      turn_deg: The rotation of one turn (deg; used by the turning set only). Our choice:
        10 deg, the precision tolerance below, so one turn from just outside the tolerance
        ends inside it; the landmark moves about 5 of the 32 input columns.
      dock_heading_deg: Precision docking (the paper's future work): if set, the robot is
        docked only when, besides its reference point being in the region, its heading is
        within +-this many degrees of facing the landmark (of the bearing from its reference
        point to the centre of the landmark's front face). None (default): the paper's task,
        the reference point alone.
    """

    step_forward: float = 0.15
    step_side: float = 0.10
    step_noise_xy: float = 0.01
    step_noise_yaw_deg: float = 2.0
    max_steps: int = 25
    start_near: float = 0.58
    start_far: float = 1.5
    start_half_angle_deg: float = 14.0
    start_yaw_deg: float = 5.0
    dock_center: float = 0.48
    dock_depth: float = 0.08
    dock_width: float = 0.20
    view_margin_px: float = 1.0
    camera: CameraConfig = dataclasses.field(default_factory=CameraConfig)
    distractors: tuple[Distractor, ...] = ()
    scene: str = "sideboard"
    actions: str = "paper"
    turn_deg: float = 10.0
    dock_heading_deg: float | None = None

    def __post_init__(self):
        owner = "WorldConfig"
        check_choice(owner, "scene", self.scene, SCENES)
        check_choice(owner, "actions", self.actions, tuple(ACTION_SETS))
        if self.dock_heading_deg is not None:
            normalise(
                self,
                dock_heading_deg=check_real(
                    owner, "dock_heading_deg", self.dock_heading_deg, lo=0, hi=180, lo_open=True
                ),
            )
        if not isinstance(self.distractors, (tuple, list)):
            raise FieldTypeError(
                f"WorldConfig.distractors must be a tuple of Distractor, got {self.distractors!r}"
            )
        for k, d in enumerate(self.distractors):
            check_instance(owner, f"distractors[{k}]", d, Distractor)
        object.__setattr__(self, "distractors", tuple(self.distractors))
        real = functools.partial(check_real, owner)
        normalise(
            self,
            step_forward=real("step_forward", self.step_forward, lo=0, hi=1, lo_open=True),
            step_side=real("step_side", self.step_side, lo=0, hi=1, lo_open=True),
            step_noise_xy=real("step_noise_xy", self.step_noise_xy, lo=0, hi=0.5),
            step_noise_yaw_deg=real("step_noise_yaw_deg", self.step_noise_yaw_deg, lo=0, hi=90),
            max_steps=check_int(owner, "max_steps", self.max_steps, lo=1, hi=100_000),
            start_near=real("start_near", self.start_near, lo=0, lo_open=True),
            start_far=real("start_far", self.start_far, lo=0, lo_open=True),
            start_half_angle_deg=real(
                "start_half_angle_deg", self.start_half_angle_deg, lo=0, hi=45, hi_open=True
            ),
            start_yaw_deg=real("start_yaw_deg", self.start_yaw_deg, lo=0, hi=90),
            dock_center=real("dock_center", self.dock_center, lo=0, lo_open=True),
            dock_depth=real("dock_depth", self.dock_depth, lo=0, hi=1, lo_open=True),
            dock_width=real("dock_width", self.dock_width, lo=0, hi=2, lo_open=True),
            view_margin_px=real("view_margin_px", self.view_margin_px, lo=0, hi=100),
            camera=check_instance(owner, "camera", self.camera, CameraConfig),
            turn_deg=real("turn_deg", self.turn_deg, lo=0, hi=90, lo_open=True),
        )
        x0, y0, x1, y1 = self.camera.crop
        if 2 * self.view_margin_px >= min(x1 - x0, y1 - y0):
            raise ValueError(
                f"WorldConfig.view_margin_px must leave room inside the camera's crop "
                f"({x1 - x0}x{y1 - y0} px): below {min(x1 - x0, y1 - y0) / 2:g}, got "
                f"{self.view_margin_px:g}"
            )
        if self.start_far < self.start_near:
            raise ValueError(
                f"WorldConfig.start_far must be >= start_near "
                f"({self.start_near}), got {self.start_far}"
            )
        if self.start_near <= self.dock_center + self.dock_depth / 2:
            raise ValueError(
                f"WorldConfig.start_near must lie beyond the docking region (> "
                f"{self.dock_center + self.dock_depth / 2:.3f} m), got {self.start_near}"
            )
        if self.start_far > _ROOM_BACK - 0.3:
            raise ValueError(
                f"WorldConfig.start_far must be <= {_ROOM_BACK - 0.3} m (the room "
                f"ends at {_ROOM_BACK} m), got {self.start_far}"
            )
        # What stops the robot in front of the landmark: the sideboard's front, or on the
        # floor the landmark's own front face (x = 0).
        front, what = (
            (_FACTS.sideboard[0], "sideboard") if self.scene == "sideboard" else (0.0, "landmark")
        )
        closest = ROBOT_RADIUS - front
        if self.dock_center + self.dock_depth / 2 < closest + 0.01:
            raise ValueError(
                f"WorldConfig.dock_center must keep the region reachable: "
                f"dock_center + dock_depth/2 >= {closest + 0.01:.2f} m (the robot "
                f"meets the {what} at {closest:.2f} m), got "
                f"dock_center={self.dock_center}"
            )

    @property
    def action_names(self) -> tuple[str, ...]:
        """The names of this world's actions, in index order."""
        return ACTION_SETS[self.actions]

    @property
    def action_letters(self) -> tuple[str, ...]:
        """Short labels of this world's actions (``F B L R``, then ``TL TR``), in index order."""
        return tuple(_LETTERS[name] for name in self.action_names)

    @property
    def n_actions(self) -> int:
        """How many actions this world has (the network needs as many action units)."""
        return len(self.action_names)


# ----------------------------------------------------------------------------------------
# The MJCF model: docking/assets/docking.xml, with the parts the configs choose set here.
# ----------------------------------------------------------------------------------------

#: The scene's MJCF asset (open it with ``python -m mujoco.viewer --mjcf <this path>``).
ASSET_PATH = Path(__file__).resolve().parent / "assets" / "docking.xml"

#: The robot's planar joints, in the order of a pose ``[x, y, yaw]``; its servos carry the
#: same names.
POSE_JOINTS = ("x", "y", "yaw")

# The timing of one walking step (s): the servo targets glide for _STEP_MOVE_TIME, then hold
# while the body settles for _STEP_SETTLE_TIME.
_STEP_MOVE_TIME, _STEP_SETTLE_TIME = 0.3, 0.1


def make_mjcf(config: WorldConfig) -> mjcf.RootElement:
    """The scene of ``config`` as an editable ``dm_control.mjcf`` model: the asset with the eye
    camera's tilt and field of view and the docking region's position and size set from
    ``config``."""
    root = mjcf.from_path(str(ASSET_PATH))
    cam = config.camera
    eye = root.find("camera", "eye")
    eye.xyaxes = _eye_xyaxes(cam.tilt_deg)
    eye.fovy = cam.fovy_deg
    dock = root.find("geom", "dock")
    dock.pos = [-config.dock_center, 0.0, dock.pos[2]]
    dock.size = [config.dock_depth / 2, config.dock_width / 2, dock.size[2]]
    landmark = root.find("geom", "landmark_slab")
    if config.scene == "floor":  # take the sideboard away; the landmark stands on the floor
        sideboard = root.find("geom", "sideboard")
        top = float(sideboard.pos[2] + sideboard.size[2])
        sideboard.remove()
        for name in ("landmark_slab", "landmark_post"):
            geom = root.find("geom", name)
            geom.pos = [geom.pos[0], geom.pos[1], geom.pos[2] - top]
    for k, d in enumerate(config.distractors):
        root.worldbody.add(
            "geom",
            name=f"distractor{k}",
            type=d.shape,
            size=list(d.size),
            pos=list(d.position),
            material=landmark.material,
            group=landmark.group,
        )
    _mark_occluders(root)
    return root


def _mark_occluders(root: mjcf.RootElement) -> None:
    """Put into the robot camera's geom group every geom that could stand between the camera
    and a red geom (those of the group already: the landmark, the distractors), so that the
    camera can draw that group alone.

    A line of sight from the camera to a point of a red geom never runs below the lower of
    the two, so a geom whose top lies below ``min(camera height, lowest red bottom)`` cannot
    cut it (the sideboard's top, 1 mm below the landmark); nor can the room's walls and floor
    (the room is a box and the camera and the red geoms are inside it), nor the robot's own
    body (hidden from its camera). Every other geom is drawn. ``tests/test_world.py`` checks
    the result by casting rays over the whole floor."""
    red = [g for g in root.find_all("geom") if g.group == _EYE_GROUP]
    eye = root.find("camera", "eye")
    lowest = min(_geom_extent_z(g)[0] for g in red)
    level = min(lowest, _z_in_world(eye.parent) + eye.pos[2])
    robot = root.find("body", "robot")
    for geom in root.find_all("geom"):
        if geom.group == _EYE_GROUP or geom.group == _DOCK_GROUP:
            continue
        if geom.name == "floor" or (geom.name or "").startswith("wall_"):
            continue
        if _inside(geom, robot):
            continue
        if _geom_extent_z(geom)[1] >= level:
            geom.group = _EYE_GROUP


def _z_in_world(body) -> float:
    """Height of a body's frame (the scene's bodies are not rotated)."""
    z = 0.0
    while body is not None and getattr(body, "tag", None) == "body":
        z += float(body.pos[2]) if body.pos is not None else 0.0
        body = body.parent
    return z


def _inside(element, body) -> bool:
    while element is not None:
        if element is body:
            return True
        element = element.parent
    return False


def _geom_extent_z(geom) -> tuple[float, float]:
    """``(bottom, top)`` of an upright geom of a non-rotated body (boxes, cylinders,
    spheres, ellipsoids and planes, as the room's furniture and the distractors are)."""
    if geom.quat is not None or geom.euler is not None or geom.fromto is not None:
        raise ValueError(f"{ASSET_PATH}: geom {geom.name!r} must be upright for _mark_occluders")
    size = list(geom.size) if geom.size is not None else [0.0]
    half = {"box": size[-1], "ellipsoid": size[-1], "cylinder": size[1] if len(size) > 1 else 0}
    kind = geom.type or "sphere"
    h = half.get(kind, size[0] if kind == "sphere" else 0.0)
    z = _z_in_world(geom.parent) + (float(geom.pos[2]) if geom.pos is not None else 0.0)
    return z - h, z + h


@functools.lru_cache(maxsize=16)
def make_model_xml(config: WorldConfig) -> str:
    """The MJCF of ``config``'s scene as one string (every number at full precision); the
    model of :func:`make_model` and of :class:`DockingEnv` is compiled from it (cached per
    config: a run builds three environments of one world)."""
    return make_mjcf(config).to_xml_string()


def make_model(config: WorldConfig) -> mujoco.MjModel:
    """The compiled MuJoCo model of ``config``'s scene."""
    return mujoco.MjModel.from_xml_string(make_model_xml(config))


def _eye_xyaxes(tilt_deg: float) -> list[float]:
    """The eye camera's ``xyaxes`` for a downward pitch of ``tilt_deg``: x to the robot's
    right, y up and tilted forward. Rounded to 6 decimals, as the scene has always been
    written (so that runs stay bit-identical)."""
    tilt = np.radians(tilt_deg)
    sin, cos = float(f"{np.sin(tilt):.6f}"), float(f"{np.cos(tilt):.6f}")
    return [0.0, -1.0, 0.0, sin, 0.0, cos]


def _box_bounds(model: mujoco.MjModel, name: str) -> tuple[np.ndarray, np.ndarray]:
    """World-frame corners ``(low, high)`` of an axis-aligned box geom of the world body,
    rounded to 1e-12 m (pos +- size leaves float noise in the last bit)."""
    geom = model.geom(name)
    if geom.type[0] != mujoco.mjtGeom.mjGEOM_BOX or geom.bodyid[0] != 0:
        raise ValueError(f"{ASSET_PATH}: geom {name!r} must be a box of the world body")
    if not np.array_equal(geom.quat, [1.0, 0.0, 0.0, 0.0]):
        raise ValueError(f"{ASSET_PATH}: geom {name!r} must be axis-aligned")
    return np.round(geom.pos - geom.size, 12), np.round(geom.pos + geom.size, 12)


@functools.cache
def _asset_model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(ASSET_PATH))


@dataclasses.dataclass(frozen=True)
class SceneFacts:
    """The fixed sizes of the scene that checks and figures need, read from the compiled
    asset (m).

    Attributes:
      room_front, room_back: The room's inner faces along ``x``: the wall behind the landmark
        at ``x = room_front`` and the one behind the start region at ``x = -room_back``.
      room_half_width: The side walls' inner faces are ``y = +-room_half_width``.
      sideboard: The sideboard's floor rectangle ``(x0, y0, x1, y1)``; ``x0`` is its front.
      sideboard_height: Its top (the landmark stands on it).
      robot_radius: Radius of the robot's collision cylinder.
      camera_height: Height of the robot's eye camera above the floor.
    """

    room_front: float
    room_back: float
    room_half_width: float
    sideboard: tuple[float, float, float, float]
    sideboard_height: float
    robot_radius: float
    camera_height: float


def scene_facts(model: mujoco.MjModel | None = None) -> SceneFacts:
    """The :class:`SceneFacts` of ``model`` (default: the asset as written)."""
    model = _asset_model() if model is None else model
    lo, hi = _box_bounds(model, "sideboard")
    robot = model.body("robot").id
    eye = model.camera("eye")
    if model.geom("body_collider").bodyid[0] != robot or eye.bodyid[0] != robot:
        raise ValueError(f"{ASSET_PATH}: body_collider and eye must belong to the robot")
    return SceneFacts(
        room_front=float(_box_bounds(model, "wall_front")[0][0]),
        room_back=float(-_box_bounds(model, "wall_back")[1][0]),
        room_half_width=float(_box_bounds(model, "wall_left")[0][1]),
        sideboard=(float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])),
        sideboard_height=float(hi[2]),
        robot_radius=float(model.geom("body_collider").size[0]),
        camera_height=float(eye.pos[2]),
    )


class Physics(dm_mujoco.Physics):
    """MuJoCo physics of the docking world with the helpers the task needs.

    The robot's pose ``[x, y, yaw]`` is read and written through the joints and servos named
    in :data:`POSE_JOINTS` (``physics.named.data.qpos[["x", "y", "yaw"]]``); their addresses
    are looked up once, when the model is loaded, and must be consecutive, so that the hot
    path uses plain slices."""

    def _reload_from_data(self, data) -> None:
        super()._reload_from_data(data)
        model = self.model.ptr
        self._qpos = _consecutive([model.joint(n).qposadr[0] for n in POSE_JOINTS], "qpos")
        self._qvel = _consecutive([model.joint(n).dofadr[0] for n in POSE_JOINTS], "qvel")
        self._ctrl = _consecutive([model.actuator(n).id for n in POSE_JOINTS], "ctrl")
        steps = [_STEP_MOVE_TIME / model.opt.timestep, _STEP_SETTLE_TIME / model.opt.timestep]
        self._n_move, self._n_settle = (int(round(n)) for n in steps)
        # Smoothstep u^2 (3 - 2u) of the gliding phase, u = k / n_move for k = 1..n_move.
        u = [k / self._n_move for k in range(1, self._n_move + 1)]
        self._smoothstep = np.array([[v * v * (3.0 - 2.0 * v)] for v in u])

    def pose(self) -> np.ndarray:
        """The robot's ground-truth pose ``[x, y, yaw]`` (m, m, rad)."""
        return np.array(self.data.qpos[self._qpos], dtype=np.float64)

    def servo_targets(self) -> np.ndarray:
        """The pose ``[x, y, yaw]`` the servos currently hold (a view)."""
        return self.data.ctrl[self._ctrl]

    def set_pose(self, pose) -> None:
        """Place the robot at ``pose`` at rest, with its servos holding it there: the
        simulation state is reset (time, velocities, warm starts), then the kinematics are
        brought up to date for rendering (the next ``mj_step`` computes everything else)."""
        pose = np.asarray(pose, dtype=np.float64)
        mujoco.mj_resetData(self.model.ptr, self.data.ptr)
        self.data.qpos[self._qpos] = pose
        self.data.qvel[self._qvel] = 0.0
        self.data.ctrl[self._ctrl] = pose
        self.update_kinematics()

    def walk_to(self, target, stop=None) -> bool:
        """One walking step: the servo targets glide from the current pose to ``target``
        (smoothstep over the step's duration), then hold while the body settles. Contacts
        stop the body where it meets an obstacle.

        ``stop(pose)`` (optional) is checked after every physics step; once it holds, the
        robot halts on the spot and ``walk_to`` returns True (the dock's detector). On
        return the kinematics are up to date for rendering."""
        model, data = self.model.ptr, self.data.ptr
        qpos = self.data.qpos[self._qpos]  # views of the robot's pose and servo targets
        ctrl = self.data.ctrl[self._ctrl]
        start = np.array(ctrl)
        # The servo targets of the gliding phase, one row per physics step.
        targets = start + (np.asarray(target, dtype=np.float64) - start) * self._smoothstep
        stopped = False
        for k in range(self._n_move + self._n_settle):
            if k < self._n_move:
                ctrl[:] = targets[k]
            mujoco.mj_step(model, data)
            if stop is not None and stop(qpos):
                stopped = True
                break
        # The servos now hold the body where it actually is, so a blocked step does not
        # keep pushing into the obstacle during the next one.
        ctrl[:] = qpos
        self.data.qvel[self._qvel] = 0.0
        self.update_kinematics()
        return stopped

    def place(self, pose) -> None:
        """Move the robot to ``pose`` for geometric queries: ``qpos`` and the kinematics only
        (velocities, servo targets and dynamics are left as they are)."""
        self.data.qpos[self._qpos] = pose
        self.update_kinematics()

    def update_kinematics(self) -> None:
        """Recompute body and camera frames from ``qpos`` (no dynamics)."""
        mujoco.mj_kinematics(self.model.ptr, self.data.ptr)
        mujoco.mj_camlight(self.model.ptr, self.data.ptr)

    def landmark_corners(self) -> np.ndarray:
        """World coordinates of the 8 corners of each of the landmark's boxes, ``(16, 3)``."""
        corners = []
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        for name in ("landmark_slab", "landmark_post"):
            geom = self.model.geom(name)
            centre = self.data.geom(name).xpos
            rot = self.data.geom(name).xmat.reshape(3, 3)
            corners.append(centre + (signs * geom.size) @ rot.T)
        return np.concatenate(corners)

    def project(self, points: np.ndarray, camera: str, config: CameraConfig) -> np.ndarray:
        """Pixel coordinates ``(u, v)`` (column, row from the top) of world ``points`` in a
        ``config.width x config.height`` frame of ``camera``; rows of NaN behind the camera."""
        cam = self.data.camera(camera)
        rot = cam.xmat.reshape(3, 3)  # columns: the camera's x (right), y (up), z (backwards)
        local = (np.asarray(points) - cam.xpos) @ rot
        depth = -local[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = config.width / 2 + config.focal_px * local[:, 0] / depth
            v = config.height / 2 - config.focal_px * local[:, 1] / depth
        uv = np.stack([u, v], axis=1)
        uv[depth <= 1e-6] = np.nan
        return uv


def _consecutive(addresses, what: str) -> slice:
    """The slice of ``addresses`` if they are consecutive (fast views), else ValueError."""
    first = int(addresses[0])
    if list(addresses) != list(range(first, first + len(addresses))):
        raise ValueError(
            f"{ASSET_PATH}: the {what} addresses of {POSE_JOINTS} must be consecutive, "
            f"got {list(addresses)}"
        )
    return slice(first, first + len(addresses))


def _as_generator(seed) -> np.random.Generator:
    if isinstance(seed, np.random.Generator):
        return seed  # used as is, not copied
    if seed is None:
        return np.random.default_rng()
    try:
        seed = check_int("DockingEnv", "seed", seed, lo=0, hi=MAX_SEED)
    except FieldTypeError:
        raise FieldTypeError(
            f"DockingEnv.seed must be None, an int in [0, {MAX_SEED}] or a "
            f"numpy.random.Generator, got {seed!r} ({type(seed).__name__})"
        ) from None
    return np.random.default_rng(seed)


class DockingEnv(dm_env.Environment):
    """The docking task as a ``dm_env.Environment`` (paper Sec. II-C).

    A trial starts at a uniformly random pose in the start trapezoid (rejection-sampled until
    the landmark lies inside the camera's crop rectangle). Each action is one step of the
    robot. Reaching the docking region gives reward 1 and ends the trial (``discount`` 0);
    the ``max_steps``-th action without docking ends it unrewarded as a time-limit
    truncation (``discount`` 1: the state itself is not terminal).

    Observations are the network input ``I``: float32 ``(10, 32)`` in [0, 1]. The learner
    reads nothing else; ``pose``, ``docked`` and ``frame`` are there for figures and tests.

    Args:
      config: The world's parameters.
      seed: An int, ``None`` or a ``numpy.random.Generator``; it drives start poses and step
        noise, so the same seed gives the same trial for the same actions.
    """

    def __init__(self, config: WorldConfig | None = None, seed=None):
        self._config = config if config is not None else WorldConfig()
        self._rng = _as_generator(seed)
        self._physics = Physics.from_xml_string(make_model_xml(self._config))
        cam = self._config.camera
        self._renderer = _make_camera(self._physics, cam.height, cam.width)
        # The robot's camera, lit by its headlight alone (the room's ceiling light, which
        # overview renders use, would make each software-rendered frame ~50% slower, and the
        # red threshold does not need it). Its observations render only the crop band (the
        # frame's projection narrowed to it) and only the geoms that can change the input
        # (group 2); `frame` renders the whole frame with the room, for figures.
        self._eye_band = self._renderer.view(
            "eye", cam.width, cam.height, groups=(_EYE_GROUP,), lights=False, window=cam.crop
        )
        self._eye_view = self._renderer.view(
            "eye", cam.width, cam.height, groups=(_ROOM_GROUP, _EYE_GROUP), lights=False
        )
        dc, half_depth, half_width = (
            self._config.dock_center,
            self._config.dock_depth / 2,
            self._config.dock_width / 2,
        )
        self._noise_yaw_rad = np.radians(self._config.step_noise_yaw_deg)
        self._turn_rad = np.radians(self._config.turn_deg)
        # The dock's detector, checked at every physics step (in_dock's test, inlined).
        if self._config.dock_heading_deg is None:
            self._in_dock = lambda p: abs(p[0] + dc) <= half_depth and abs(p[1]) <= half_width
        else:
            limit = np.radians(self._config.dock_heading_deg)
            self._in_dock = lambda p: (
                abs(p[0] + dc) <= half_depth
                and abs(p[1]) <= half_width
                and abs(heading_error(p)) <= limit
            )
        self._start_region = StartRegion.of(self._config)
        self._frame = None
        self._observed = False
        self._steps = 0
        self._needs_reset = True

    # -- configuration -------------------------------------------------------------------
    def reseed(self, seed=None) -> None:
        """Replace the random generator that drives start poses and step noise.

        ``seed`` is what the constructor takes: an int, ``None`` (fresh OS entropy) or a
        ``numpy.random.Generator`` (used as is, not copied). After ``reseed(k)`` the env
        produces the same trials for the same actions as ``DockingEnv(config, seed=k)``.
        The current trial is ended: the next ``step`` starts a new one.
        """
        self._rng = _as_generator(seed)
        self._needs_reset = True

    @property
    def config(self) -> WorldConfig:
        return self._config

    @property
    def physics(self) -> Physics:
        return self._physics

    @property
    def start_region(self) -> StartRegion:
        """The start trapezoid of the following trials (the config's, until
        :meth:`set_start_region` changes its edges)."""
        return self._start_region

    def set_start_region(self, near: float, far: float) -> None:
        """Cut the start trapezoid at other distances for the following trials (Learning from
        Easy Missions widens ``far``); the same checks as ``WorldConfig.start_near/start_far``."""
        dataclasses.replace(self._config, start_near=near, start_far=far)  # validates
        self._start_region = self._start_region.with_edges(float(near), float(far))

    # -- ground truth (never read by the learner) -----------------------------------------
    @property
    def pose(self) -> np.ndarray:
        """The robot's pose ``[x, y, yaw]``."""
        return self._physics.pose()

    @property
    def docked(self) -> bool:
        """Whether the robot is docked: its reference point inside the docking region (and,
        with precision docking, its heading within the tolerance; :func:`in_dock`)."""
        return in_dock(self._physics.pose(), self._config)

    @property
    def frame(self) -> np.ndarray | None:
        """The robot's whole RGB camera frame (with the room) at the latest observation, for
        figures; rendered on first access. The observation came from its crop band with the
        landmark alone drawn, which has the same red pixels (``tests/test_world.py``)."""
        if self._frame is None and self._observed:
            self._frame = self.render_camera()
        return self._frame

    @property
    def steps(self) -> int:
        """Actions taken in the current trial."""
        return self._steps

    # -- dm_env interface -----------------------------------------------------------------
    def observation_spec(self):
        rows, cols = self._config.camera.input_shape
        return specs.BoundedArray((rows, cols), np.float32, 0.0, 1.0, name="pixels")

    def action_spec(self):
        return specs.DiscreteArray(self._config.n_actions, dtype=np.int64, name="action")

    def reset(self) -> dm_env.TimeStep:
        return self.reset_to(self.sample_start_pose())

    def reset_to(self, pose) -> dm_env.TimeStep:
        """Start a trial at a given pose ``[x, y, yaw]`` (m, m, rad; for figures and tests)."""
        self._physics.set_pose(check_pose("DockingEnv.reset_to", pose))
        self._steps = 0
        self._needs_reset = False
        return dm_env.restart(self._observe())

    def step(self, action) -> dm_env.TimeStep:
        if self._needs_reset:
            return self.reset()
        action = _check_action(action, self._config.action_names)
        docked = self._physics.walk_to(self._step_target(action), stop=self._in_dock)
        self._steps += 1
        observation = self._observe()
        if docked:
            self._needs_reset = True
            return dm_env.termination(reward=1.0, observation=observation)
        if self._steps >= self._config.max_steps:
            self._needs_reset = True
            return dm_env.truncation(reward=0.0, observation=observation)
        return dm_env.transition(reward=0.0, observation=observation)

    # -- internals ------------------------------------------------------------------------
    def _step_target(self, action: int) -> np.ndarray:
        cfg = self._config
        # A turn (turning set only) is a step of length 0 that also rotates by turn_deg; the
        # noise is every step's: three standard normals, scaled per body axis and heading.
        forward = (cfg.step_forward, -cfg.step_forward, 0.0, 0.0, 0.0, 0.0)[action]
        side = (0.0, 0.0, cfg.step_side, -cfg.step_side, 0.0, 0.0)[action]
        noise = self._rng.normal(0.0, 1.0, size=3)
        forward += cfg.step_noise_xy * noise[0]
        side += cfg.step_noise_xy * noise[1]
        x, y, yaw = self._physics.servo_targets()
        cos, sin = np.cos(yaw), np.sin(yaw)
        if action == TURN_LEFT:
            yaw = yaw + self._turn_rad
        elif action == TURN_RIGHT:
            yaw = yaw - self._turn_rad
        return np.array(
            [
                x + cos * forward - sin * side,
                y + sin * forward + cos * side,
                yaw + self._noise_yaw_rad * noise[2],
            ]
        )

    def _observe(self) -> np.ndarray:
        self._frame, self._observed = None, True
        return preprocess_band(self._eye_band.render(self._physics.data.ptr), self._config.camera)

    def render_camera(self) -> np.ndarray:
        """The robot's RGB camera frame of the current pose, as a new array (the robot's body
        and the dock are not drawn; lit by the camera's headlight alone)."""
        return self._eye_view.render(self._physics.data.ptr).copy()

    def render_view(
        self,
        camera: str = "overview",
        width: int = 640,
        height: int = 480,
        show_robot: bool = True,
        show_dock: bool = True,
    ) -> np.ndarray:
        """An RGB render from one of the scene's fixed cameras (``overview``, ``top``), with
        the robot and the virtual docking region drawn, for figures."""
        width = check_int("DockingEnv.render_view", "width", width, lo=1)
        height = check_int("DockingEnv.render_view", "height", height, lo=1)
        _check_frame_size(self._physics, width, height, "render_view width x height")
        groups = [_ROOM_GROUP, _EYE_GROUP] + [_ROBOT_GROUP] * show_robot
        groups += [_DOCK_GROUP] * show_dock
        view = self._renderer.view(camera, width, height, groups=groups, lights=True)
        return view.render(self._physics.data.ptr).copy()

    def landmark_in_crop(self, pose=None, margin: float | None = None) -> bool:
        """Whether the whole landmark projects inside the crop rectangle from ``pose``
        (default: the current pose), keeping ``margin`` pixels from its border."""
        cam = self._config.camera
        margin = self._config.view_margin_px if margin is None else margin
        if pose is not None:
            saved = self._physics.pose()
            self._physics.place(pose)
        uv = self._physics.project(self._physics.landmark_corners(), "eye", cam)
        if pose is not None:
            self._physics.place(saved)
        x0, y0, x1, y1 = cam.crop
        return bool(
            np.all(np.isfinite(uv))
            and uv[:, 0].min() >= x0 + margin
            and uv[:, 0].max() <= x1 - margin
            and uv[:, 1].min() >= y0 + margin
            and uv[:, 1].max() <= y1 - margin
        )

    def sample_start_pose(self, max_tries: int = 10000) -> np.ndarray:
        """A uniform random pose in the start trapezoid (:meth:`StartRegion.sample`) from which
        the landmark is inside the crop rectangle (rejection sampling)."""
        max_tries = check_int("DockingEnv.sample_start_pose", "max_tries", max_tries, lo=1)
        for _ in range(max_tries):
            pose = self._start_region.sample(self._rng)
            if self.landmark_in_crop(pose):
                return pose
        raise RuntimeError(
            f"no start pose with the landmark in view after {max_tries} tries; "
            f"narrow start_half_angle_deg or start_yaw_deg, or lower view_margin_px "
            f"(now {self._config.view_margin_px:g})"
        )


def footprints(config: WorldConfig) -> dict[str, tuple[float, float, float, float]]:
    """Floor-plan rectangles ``(x0, y0, x1, y1)`` of the sideboard (if the scene has one), the
    landmark's two boxes and the docking region of ``config``'s compiled scene, for top-down
    figures."""
    model = make_model(config)
    rects = {}
    names = ("landmark_slab", "landmark_post", "dock")
    for name in (("sideboard",) if config.scene == "sideboard" else ()) + names:
        lo, hi = _box_bounds(model, name)
        rects[name] = (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
    return rects


_FACTS = scene_facts()
_ROOM_BACK = _FACTS.room_back

#: Radius of the robot's collision cylinder (m), for drawing its footprint.
ROBOT_RADIUS = _FACTS.robot_radius


def heading_error(pose) -> float:
    """How far ``pose``'s heading is turned from facing the landmark (rad, in ``[-pi, pi)``,
    positive: turned to the left): the heading minus the bearing from the reference point to
    the centre of the landmark's front face (the world's origin)."""
    error = float(pose[2]) - math.atan2(-float(pose[1]), -float(pose[0]))
    return (error + math.pi) % (2 * math.pi) - math.pi


def in_region(pose, config: WorldConfig) -> bool:
    """Whether ``pose``'s reference point lies in the docking region of ``config`` (whatever
    the heading)."""
    x, y = pose[0], pose[1]
    return bool(
        abs(x + config.dock_center) <= config.dock_depth / 2 and abs(y) <= config.dock_width / 2
    )


def in_dock(pose, config: WorldConfig) -> bool:
    """Whether ``pose`` is docked in ``config``'s world: :func:`in_region` and, with precision
    docking (``config.dock_heading_deg``), its :func:`heading_error` within the tolerance."""
    if config.dock_heading_deg is None:
        return in_region(pose, config)
    limit = np.radians(config.dock_heading_deg)
    return in_region(pose, config) and abs(heading_error(pose)) <= limit


def _check_action(action, names: tuple[str, ...] = ACTION_NAMES) -> int:
    """The action as an ``int``: exactly the integers ``0..len(names)-1``, as Python or numpy
    integers or a 0-d integer array; bools, floats (also integral ones), strings, other
    shapes and out-of-range values raise ``ValueError``."""
    value = action[()] if isinstance(action, np.ndarray) and action.ndim == 0 else action
    if (
        isinstance(value, (bool, np.bool_))
        or not isinstance(value, (int, np.integer))
        or not 0 <= value < len(names)
    ):
        raise ValueError(
            f"action must be an integer in 0..{len(names) - 1} ({', '.join(names)}), got {action!r}"
        )
    return int(value)


def _check_frame_size(physics: Physics, width: int, height: int, what: str) -> None:
    """A frame must fit MuJoCo's offscreen framebuffer (``<visual><global offwidth
    offheight>`` of the model)."""
    buffer = physics.model.vis.global_
    if width > buffer.offwidth or height > buffer.offheight:
        raise ValueError(
            f"{what} {width}x{height} is larger than the scene's offscreen framebuffer "
            f"({buffer.offwidth}x{buffer.offheight}, <visual><global offwidth offheight> of "
            f"the model); render a smaller frame or enlarge the framebuffer"
        )


def _make_camera(physics: Physics, height: int, width: int) -> SceneRenderer:
    """The renderer of ``physics``' scene, checked for a ``width x height`` camera frame;
    one clear error if no OpenGL backend can start."""
    _check_frame_size(physics, width, height, "CameraConfig.width x height")
    try:
        return SceneRenderer(physics.model.ptr)
    except Exception as exc:  # the backends raise many different types
        backend = os.environ.get("MUJOCO_GL", "")
        raise RuntimeError(
            f"Could not start headless OpenGL rendering with MUJOCO_GL={backend!r} ({exc}). "
            "On a CPU-only Linux machine set MUJOCO_GL=egl and install Mesa's EGL "
            "(Debian/Ubuntu: apt-get install libegl1 libgl1-mesa-dri); `make setup` does "
            "both."
        ) from exc
