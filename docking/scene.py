"""What a docking world is, without rendering it: the action sets, the red distractors, the
world's configuration (:class:`WorldConfig`), the scene's asset and the fixed sizes read back
from it (:func:`scene_facts`), and where a pose is docked.

Importing this module needs neither OpenGL nor MuJoCo: the asset is compiled (by ``mujoco``,
without a rendering context) the first time a configuration is checked against the room or
:func:`scene_facts` is asked. :mod:`docking.world` builds the scene and the task from it.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from docking.camera import CameraConfig
from docking.validate import (
    FieldTypeError,
    check_bool,
    check_choice,
    check_instance,
    check_int,
    check_real,
    normalise,
)

if TYPE_CHECKING:
    import mujoco

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
    "continuous": ("forward", "side"),
    "continuous-turning": ("forward", "side", "turn"),
}

#: The action sets whose action is a vector (one component per name, each in [-1, 1]): the
#: paper's future work (Sec. V), "allowing continuous actions".
CONTINUOUS_SETS = ("continuous", "continuous-turning")

#: Short labels of the actions, for figures and tables.
_LETTERS = {
    "forward": "F",
    "backward": "B",
    "left": "L",
    "right": "R",
    "turn-left": "TL",
    "turn-right": "TR",
    "side": "S",
    "turn": "T",
}

#: The paper's action set (the default world's); a world's own set is
#: :attr:`WorldConfig.action_names` / :attr:`WorldConfig.action_letters`.
ACTION_NAMES = ACTION_SETS["paper"]
ACTION_LETTERS = tuple(_LETTERS[name] for name in ACTION_NAMES)
N_ACTIONS = len(ACTION_NAMES)

#: The scenes a world can be built as (:attr:`WorldConfig.scene`).
SCENES = ("sideboard", "floor")

#: The rooms a world can be built in (:attr:`WorldConfig.room`): the asset's, or the second
#: room of ``assets/second_room.xml`` (other walls, floor and furniture; the same landmark).
ROOMS = ("home", "second")

#: The landmark's shapes (:attr:`WorldConfig.landmark_shape`): the asset's inverted T (a slab
#: and a post behind it), or the slab alone (no post, so no parallax between two parts).
LANDMARK_SHAPES = ("paper", "slab")

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
      shape: "box", "cylinder" (standing upright) or "sphere".
      size: MuJoCo's geom size for the shape (m): box half-extents (x, y, z), cylinder
        (radius, half-height), sphere (radius,).
      position: The centre (x, y, z) in the world frame (m; the landmark's front face is
        x = 0, the sideboard's top 0.43 m above the floor).
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
      start_near: The start trapezoid's nearest distance of the robot's reference point from
        the landmark's front plane (m).
      start_far: The start trapezoid's farthest such distance (m); Experiment 2 ends at 1.5 m.
      start_half_angle_deg: Half the opening angle of the start trapezoid, a wedge with its
        apex at the landmark, cut at start_near and start_far
        (StartRegion, which DockingEnv samples from).
      start_yaw_deg: Start headings are uniform in +-this around facing the landmark's wall.
      dock_center: Distance of the docking region's centre from the landmark's front plane (m);
        the region's near edge lies 1 cm beyond where the robot meets the sideboard (0.45 m).
      dock_depth: Extent of the region along the approach axis (m; paper: 8 cm).
      dock_width: Extent of the region across the approach axis (m; paper: 20 cm).
      view_margin_px: At a start pose the landmark's projection keeps this many pixels from
        the crop's border.
      camera: The head camera and the observation pipeline.
      distractors: Red objects besides the landmark (Distractor); none by default.
      scene: "sideboard": the landmark stands on a sideboard at the camera's
        height, whose front stops the robot at the dock. "floor": the sideboard is taken
        away and the landmark stands on the floor at the same place; nothing stops the robot
        at the dock (it can overshoot or walk past the landmark's side), and with the camera
        tilted down the landmark's image moves vertically with distance. See SCENES.
      actions: The action set (ACTION_SETS): "paper", the paper's four
        steps; "turning" adds turn-left and turn-right (indices 4 and 5), a rotation in
        place by turn_deg with the same noise as every step (position noise on both body
        axes, heading noise).
      turn_deg: The rotation of one turn (deg; used by the turning set only). Our choice:
        10 deg, the precision tolerance below, so one turn from just outside the tolerance
        ends inside it; the landmark moves about 5 of the 32 input columns.
      dock_heading_deg: Precision docking (the paper's future work): if set, the robot is
        docked only when, besides its reference point being in the region, its heading is
        within +-this many degrees of facing the landmark (of the bearing from its reference
        point to the centre of the landmark's front face). None: the paper's task,
        the reference point alone.
      heading_hold: A scripted heading compensation from odometry (the hybrid control of
        the rotation claim): every step's heading target is the heading the trial started
        with, plus that step's own noise, so heading errors do not add up over the steps.
        False: the paper's walk, each step turns from where the last one ended.
      camera_height: The eye camera's height above the floor (m); None: the asset's.
      landmark_shape: See LANDMARK_SHAPES.
      room: See ROOMS.
      room_shift: The room (its walls, floor, furniture and light) moved about the landmark,
        which keeps its place with its sideboard, the dock and the start region: (dx,
        dy, yaw_deg): a turn by yaw_deg about the landmark's origin, then a shift by (dx,
        dy) m. It is the landmark and its dock moved elsewhere in the room (the inverse
        motion), in the frame every pose is written in.
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
    heading_hold: bool = False
    camera_height: float | None = None
    landmark_shape: str = "paper"
    room: str = "home"
    room_shift: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        self._check_kinds()
        self._check_distractor_types()
        facts = scene_facts()
        self._check_fields(facts)
        self._check_crop_margin()
        self._check_regions(facts)
        self._check_distractors(facts)

    def _check_kinds(self) -> None:
        """The choices (scene, action set, landmark, room) and the optional fields."""
        owner = "WorldConfig"
        check_choice(owner, "scene", self.scene, SCENES)
        check_choice(owner, "actions", self.actions, tuple(ACTION_SETS))
        check_choice(owner, "landmark_shape", self.landmark_shape, LANDMARK_SHAPES)
        check_choice(owner, "room", self.room, ROOMS)
        if self.camera_height is not None:
            normalise(
                self,
                camera_height=check_real(
                    owner, "camera_height", self.camera_height, lo=0.1, hi=2.0
                ),
            )
        normalise(self, room_shift=_reals(owner, "room_shift", self.room_shift, 3, -180, 180))
        if self.dock_heading_deg is not None:
            normalise(
                self,
                dock_heading_deg=check_real(
                    owner, "dock_heading_deg", self.dock_heading_deg, lo=0, hi=180, lo_open=True
                ),
            )

    def _check_distractor_types(self) -> None:
        """``distractors``: a tuple (or list, stored as a tuple) of :class:`Distractor`."""
        owner = "WorldConfig"
        if not isinstance(self.distractors, (tuple, list)):
            raise FieldTypeError(
                f"WorldConfig.distractors must be a tuple of Distractor, got {self.distractors!r}"
            )
        for k, d in enumerate(self.distractors):
            check_instance(owner, f"distractors[{k}]", d, Distractor)
        object.__setattr__(self, "distractors", tuple(self.distractors))

    def _check_fields(self, facts: SceneFacts) -> None:
        """Every numeric field in its range, the camera and ``heading_hold``, normalised."""
        owner = "WorldConfig"
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
            # Beyond room_back - 0.3 m no start region (start_far's bound) could lie behind it.
            dock_center=real(
                "dock_center", self.dock_center, lo=0, hi=facts.room_back - 0.3, lo_open=True
            ),
            dock_depth=real("dock_depth", self.dock_depth, lo=0, hi=1, lo_open=True),
            dock_width=real("dock_width", self.dock_width, lo=0, hi=2, lo_open=True),
            view_margin_px=real("view_margin_px", self.view_margin_px, lo=0, hi=100),
            camera=check_instance(owner, "camera", self.camera, CameraConfig),
            turn_deg=real("turn_deg", self.turn_deg, lo=0, hi=90, lo_open=True),
            heading_hold=check_bool(owner, "heading_hold", self.heading_hold),
        )

    def _check_crop_margin(self) -> None:
        """``view_margin_px`` leaves room inside the camera's crop."""
        x0, y0, x1, y1 = self.camera.crop
        if 2 * self.view_margin_px >= min(x1 - x0, y1 - y0):
            raise ValueError(
                f"WorldConfig.view_margin_px must leave room inside the camera's crop "
                f"({x1 - x0}x{y1 - y0} px): below {min(x1 - x0, y1 - y0) / 2:g}, got "
                f"{self.view_margin_px:g}"
            )

    def _check_regions(self, facts: SceneFacts) -> None:
        """The start region lies beyond the docking region and inside the room, and the
        docking region is reachable."""
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
        if self.start_far > facts.room_back - 0.3:
            raise ValueError(
                f"WorldConfig.start_far must be <= {facts.room_back - 0.3:g} m (the room "
                f"ends at {facts.room_back:g} m), got {self.start_far}"
            )
        # What stops the robot in front of the landmark: the sideboard's front, or on the
        # floor the landmark's own front face (x = 0).
        front, what = (
            (facts.sideboard[0], "sideboard") if self.scene == "sideboard" else (0.0, "landmark")
        )
        closest = facts.robot_radius - front
        if self.dock_center + self.dock_depth / 2 < closest + 0.01:
            raise ValueError(
                f"WorldConfig.dock_center must keep the region reachable: "
                f"dock_center + dock_depth/2 >= {closest + 0.01:.2f} m (the robot "
                f"meets the {what} at {closest:.2f} m), got "
                f"dock_center={self.dock_center}"
            )

    def _check_distractors(self, facts: SceneFacts) -> None:
        """A distractor stands clear of where the robot starts and docks: its floor footprint
        keeps the robot's radius from the start trapezoid and the docking region (a box over
        the start region would hold the robot inside it, and the robot pushes it)."""
        regions = _robot_regions(self)
        clash = next(
            (
                (k, d, name)
                for k, d in enumerate(self.distractors)
                for name, region in regions.items()
                if _floor_gap(*_footprint(d), region) < facts.robot_radius
            ),
            None,
        )
        if clash is not None:
            k, d, name = clash
            raise ValueError(
                f"WorldConfig.distractors[{k}] (a {d.shape} at {d.position}) comes within the "
                f"robot's radius ({facts.robot_radius:g} m) of {name}: the robot would start or "
                f"dock inside it; move it at least that far away"
            )

    @property
    def continuous(self) -> bool:
        """Whether an action is a vector (CONTINUOUS_SETS), not an index."""
        return self.actions in CONTINUOUS_SETS

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
        """How many actions this world has (the network needs as many action units), or
        with continuous actions how many components an action has."""
        return len(self.action_names)

    def action_index(self, name: str) -> int:
        """The index of the action called ``name`` (e.g. ``"turn-left"``) in this world's
        action set; ``ValueError`` naming the set's actions if it has none of that name."""
        if name not in self.action_names:
            raise ValueError(
                f"WorldConfig(actions={self.actions!r}) has no action {name!r}; its actions "
                f"are {', '.join(self.action_names)}"
            )
        return self.action_names.index(name)


# The floor geometry of WorldConfig's distractor check (validation: in plain floats, not a
# run's arithmetic).


def _robot_regions(config: WorldConfig) -> dict[str, list[tuple[float, float]]]:
    """The floor polygons (corners) of ``config``'s start trapezoid and docking region."""
    tan = math.tan(math.radians(config.start_half_angle_deg))
    near, far = config.start_near, config.start_far
    back, front = (
        -(config.dock_center + config.dock_depth / 2),
        -(config.dock_center - config.dock_depth / 2),
    )
    w = config.dock_width / 2
    return {
        "the start region": [
            (-near, -near * tan),
            (-far, -far * tan),
            (-far, far * tan),
            (-near, near * tan),
        ],
        "the docking region": [(front, -w), (back, -w), (back, w), (front, w)],
    }


def _polygon_edges(poly) -> list:
    """The edges ``(corner, next corner)`` of a polygon of corners."""
    return [(p, poly[(i + 1) % len(poly)]) for i, p in enumerate(poly)]


def _separated(a, b) -> bool:
    """Whether a separating axis among the edges' normals parts convex polygons ``a`` and
    ``b`` (``a`` may be one point)."""
    for poly in (a, b) if len(a) > 2 else (b,):
        for (x0, y0), (x1, y1) in _polygon_edges(poly):
            nx, ny = y0 - y1, x1 - x0
            pa = [x * nx + y * ny for x, y in a]
            pb = [x * nx + y * ny for x, y in b]
            if max(pa) < min(pb) or max(pb) < min(pa):
                return True
    return False


def _to_edges(points, poly) -> float:
    """The least distance from any of ``points`` to an edge of the polygon ``poly``."""
    best = math.inf
    for (x0, y0), (x1, y1) in _polygon_edges(poly):
        dx, dy = x1 - x0, y1 - y0
        length = max(dx * dx + dy * dy, 1e-24)  # a degenerate edge: a point
        for x, y in points:
            t = min(max(((x - x0) * dx + (y - y0) * dy) / length, 0.0), 1.0)
            best = min(best, math.hypot(x - x0 - t * dx, y - y0 - t * dy))
    return best


def _floor_gap(footprint, radius: float, region) -> float:
    """The floor distance between a convex ``footprint`` (corners; one point for a disc of
    ``radius``) and the convex polygon ``region`` (0 if they meet), in plain floats (a check,
    not a run's arithmetic)."""
    if not _separated(footprint, region):
        return 0.0  # they overlap (a disc's centre is inside the region)
    apart = _to_edges(footprint, region)
    if len(footprint) > 2:
        apart = min(apart, _to_edges(region, footprint))
    return max(apart - radius, 0.0)


def _footprint(d: Distractor) -> tuple[list, float]:
    """A distractor's floor footprint: a box's corners, or an upright cylinder's or a
    sphere's centre and radius."""
    x, y = d.position[:2]
    if d.shape != "box":
        return [(x, y)], d.size[0]
    sx, sy = d.size[:2]
    return [(x - sx, y - sy), (x + sx, y - sy), (x + sx, y + sy), (x - sx, y + sy)], 0.0


#: The scene's MJCF asset (open it with ``python -m mujoco.viewer --mjcf <this path>``).
ASSET_PATH = Path(__file__).resolve().parent / "assets" / "docking.xml"

#: The second room's furniture, floor and walls (:attr:`WorldConfig.room` ``"second"``).
SECOND_ROOM_PATH = ASSET_PATH.with_name("second_room.xml")


def _reals(owner: str, name: str, value, n: int, lo: float, hi: float) -> tuple[float, ...]:
    """``value`` as a tuple of ``n`` reals in ``[lo, hi]``, or FieldTypeError/ValueError."""
    if not isinstance(value, (tuple, list)) or len(value) != n:
        raise FieldTypeError(f"{owner}.{name} must be {n} numbers, got {value!r}")
    return tuple(check_real(owner, f"{name}[{k}]", v, lo=lo, hi=hi) for k, v in enumerate(value))


def _box_bounds(model: mujoco.MjModel, name: str) -> tuple[np.ndarray, np.ndarray]:
    """World-frame corners ``(low, high)`` of an axis-aligned box geom of the world body,
    rounded to 1e-12 m (pos +- size leaves float noise in the last bit)."""
    import mujoco

    import docking.glenv  # noqa: F401  (the rendering defaults, before mujoco's import)

    geom = model.geom(name)
    if geom.type[0] != mujoco.mjtGeom.mjGEOM_BOX or geom.bodyid[0] != 0:
        raise ValueError(f"{ASSET_PATH}: geom {name!r} must be a box of the world body")
    if not np.array_equal(geom.quat, [1.0, 0.0, 0.0, 0.0]):
        raise ValueError(f"{ASSET_PATH}: geom {name!r} must be axis-aligned")
    return np.round(geom.pos - geom.size, 12), np.round(geom.pos + geom.size, 12)


@functools.cache
def _asset_model() -> mujoco.MjModel:
    import mujoco

    import docking.glenv  # noqa: F401  (the rendering defaults, before mujoco's import)

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
    """The :class:`SceneFacts` of ``model`` (default: the asset as written, compiled on first
    use and remembered)."""
    if model is None:
        return _asset_facts()
    return _facts_of(model)


@functools.cache
def _asset_facts() -> SceneFacts:
    return _facts_of(_asset_model())


def _facts_of(model) -> SceneFacts:
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
