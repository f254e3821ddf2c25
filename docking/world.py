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
import os

from docking.glenv import RenderingUnavailable, check_gl_backend  # noqa: E402, F401

check_gl_backend()

import dm_env  # noqa: E402
import mujoco  # noqa: E402
import numpy as np  # noqa: E402
from dm_control import mujoco as dm_mujoco  # noqa: E402
from dm_env import specs  # noqa: E402

from docking import arith  # noqa: E402
from docking.camera import CameraConfig, preprocess_band  # noqa: E402

# The MJCF model (the asset, with the parts the configs choose set, compiled) is
# docking.model's; its names are this module's too.
from docking.model import (  # noqa: E402, F401
    _DOCK_GROUP,
    _EYE_GROUP,
    _ROBOT_GROUP,
    _ROOM_GROUP,
    POSE_JOINTS,
    footprints,
    make_mjcf,
    make_model,
    make_model_xml,
)
from docking.region import StartRegion  # noqa: E402
from docking.render import SceneRenderer  # noqa: E402

# The world's configuration and the scene's facts, defined in docking.scene (importable
# without OpenGL), are this module's too: ``docking.world.WorldConfig`` is the same class.
from docking.scene import (  # noqa: E402, F401
    ACTION_LETTERS,
    ACTION_NAMES,
    ACTION_SETS,
    ASSET_PATH,
    BACKWARD,
    DISTRACTOR_SHAPES,
    FORWARD,
    LEFT,
    N_ACTIONS,
    RIGHT,
    SCENES,
    SECOND_ROOM_PATH,
    TURN_LEFT,
    TURN_RIGHT,
    Distractor,
    SceneFacts,
    WorldConfig,
    _box_bounds,
    heading_error,
    in_dock,
    in_region,
    scene_facts,
)
from docking.validate import (  # noqa: E402
    MAX_SEED,
    FieldTypeError,
    check_instance,
    check_int,
    check_pose,
    check_real,
)

# The timing of one walking step (s): the servo targets glide for _STEP_MOVE_TIME, then hold
# while the body settles for _STEP_SETTLE_TIME.
_STEP_MOVE_TIME, _STEP_SETTLE_TIME = 0.3, 0.1


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
        names = [model.geom(k).name for k in range(model.ngeom)]
        self._landmark = [n for n in ("landmark_slab", "landmark_post") if n in names]

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
        for name in self._landmark:
            geom = self.model.geom(name)
            centre = self.data.geom(name).xpos
            rot = self.data.geom(name).xmat.reshape(3, 3)
            corners.append(centre + arith.matmul(signs * geom.size, rot.T))
        return np.concatenate(corners)

    def project(self, points: np.ndarray, camera: str, config: CameraConfig) -> np.ndarray:
        """Pixel coordinates ``(u, v)`` (column, row from the top) of world ``points`` in a
        ``config.width x config.height`` frame of ``camera``; rows of NaN behind the camera."""
        cam = self.data.camera(camera)
        rot = cam.xmat.reshape(3, 3)  # columns: the camera's x (right), y (up), z (backwards)
        local = arith.matmul(np.asarray(points) - cam.xpos, rot)
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


# The checks of DockingEnv's arguments (named in fingerprint.UNKEYED: each raises or returns
# None, and the code that computes goes on with the argument as it was given).


def _check_config(config) -> None:
    """``DockingEnv.config`` must be a :class:`WorldConfig` (a ``CameraConfig``, a scene's
    name or a dict of fields is not one)."""
    check_instance("DockingEnv", "config", config, WorldConfig)


def _check_start_pose(config: WorldConfig, pose: np.ndarray) -> None:
    """A start pose (``[x, y, yaw]``, already three finite numbers) of ``config``'s world:

    * the robot inside the room: its reference point at least the robot's radius inside
      each wall (where its collision cylinder touches none), the walls' inner faces read
      back from the compiled asset (:func:`scene_facts`; the second room keeps the home
      room's walls) and placed by ``config.room_shift`` (the room turned by its yaw about
      the landmark's origin, then shifted; the frame poses are written in). Furniture is not
      checked (the physics pushes the robot out of it; ``analysis.furniture_contacts`` tells
      where it stands);
    * ``|yaw| <= 2048 pi`` (1024 whole turns either way). A heading has a representation
      in ``[-pi, pi]``, but the yaw hinge counts whole turns, so a pose read back from a
      walking robot may lie some turns beyond it; within 1024 turns the float64 yaw still
      resolves the heading to about 1e-12 rad, far below a step's heading noise, while a
      yaw such as 1e308 names no heading at all (its float spacing exceeds a whole turn
      from about 1e16 rad on)."""
    where = "DockingEnv.reset_to"
    bound = 2048 * np.pi
    if abs(pose[2]) > bound:
        raise ValueError(
            f"{where}: pose's yaw must lie within 1024 turns of facing +x "
            f"(|yaw| <= {bound:.0f} rad), got {pose[2]:g}"
        )
    facts = scene_facts()
    dx, dy, turn_deg = config.room_shift
    turn = np.radians(turn_deg)
    x, y = float(pose[0]) - dx, float(pose[1]) - dy
    room_x = float(np.cos(turn) * x + np.sin(turn) * y)  # in the room's own frame
    room_y = float(-np.sin(turn) * x + np.cos(turn) * y)
    r = facts.robot_radius
    lo_x, hi_x, half = -facts.room_back + r, facts.room_front - r, facts.room_half_width - r
    if not (lo_x <= room_x <= hi_x and abs(room_y) <= half):
        shifted = f" (the room shifted by {config.room_shift})" if any(config.room_shift) else ""
        raise ValueError(
            f"{where}: pose must put the robot inside the room{shifted}: its x in "
            f"[{lo_x:g}, {hi_x:g}] m and |y| <= {half:g} m in the room's frame (the walls "
            f"less the robot's radius {r:g} m), got [x, y] = [{pose[0]:g}, {pose[1]:g}]"
        )


def _check_crop_query(pose, margin) -> None:
    """``DockingEnv.landmark_in_crop``'s arguments: a pose of three finite numbers (or None)
    and a margin that is a finite number >= 0 (or None)."""
    where = "DockingEnv.landmark_in_crop"
    if pose is not None:
        check_pose(where, pose)
    if margin is not None:
        check_real(where, "margin", margin, lo=0)


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
        _check_config(self._config)
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
        self._start_yaw = 0.0  # set by reset_to
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
        if self._config.continuous:  # a step vector, each component in [-1, 1]
            n = self._config.n_actions
            return specs.BoundedArray((n,), np.float64, -1.0, 1.0, name="action")
        return specs.DiscreteArray(self._config.n_actions, dtype=np.int64, name="action")

    def reset(self) -> dm_env.TimeStep:
        return self.reset_to(self.sample_start_pose())

    def reset_to(self, pose) -> dm_env.TimeStep:
        """Start a trial at a given pose ``[x, y, yaw]`` (m, m, rad; for figures and tests):
        three finite numbers, the robot inside the room's walls and its yaw within 1024 turns
        of facing ``+x`` (:func:`_check_start_pose`), else ``ValueError``."""
        pose = check_pose("DockingEnv.reset_to", pose)
        _check_start_pose(self._config, pose)
        self._physics.set_pose(pose)
        self._start_yaw = float(self._physics.pose()[2])  # for WorldConfig.heading_hold
        self._steps = 0
        self._needs_reset = False
        return dm_env.restart(self._observe())

    def step(self, action) -> dm_env.TimeStep:
        if self._needs_reset:
            return self.reset()
        if self._config.continuous:
            target = self._vector_target(_check_vector_action(action, self._config.action_names))
        else:
            target = self._step_target(_check_action(action, self._config.action_names))
        docked = self._physics.walk_to(target, stop=self._in_dock)
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
        if cfg.heading_hold:  # odometry: back to the start heading, whatever the drift
            yaw = self._start_yaw
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

    def _vector_target(self, action: np.ndarray) -> np.ndarray:
        """The target of a continuous action: ``action`` scales the step lengths (forward,
        sideways) and the turn (if the set has one) of the discrete sets, so a component of
        +-1 is one of their steps; the noise is theirs (:meth:`_step_target`)."""
        cfg = self._config
        forward = cfg.step_forward * action[0]
        side = cfg.step_side * action[1]
        turn = self._turn_rad * action[2] if len(action) > 2 else 0.0
        noise = self._rng.normal(0.0, 1.0, size=3)
        forward += cfg.step_noise_xy * noise[0]
        side += cfg.step_noise_xy * noise[1]
        x, y, yaw = self._physics.servo_targets()
        if cfg.heading_hold:
            yaw = self._start_yaw
        cos, sin = np.cos(yaw), np.sin(yaw)
        return np.array(
            [
                x + cos * forward - sin * side,
                y + sin * forward + cos * side,
                yaw + turn + self._noise_yaw_rad * noise[2],
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
        (default: the current pose), keeping ``margin`` pixels from its border (default: the
        world's ``view_margin_px``). A pose must be three finite numbers and a margin a finite
        number >= 0, else ``ValueError``/``TypeError`` naming it."""
        _check_crop_query(pose, margin)
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


def _check_vector_action(action, names: tuple[str, ...]) -> np.ndarray:
    """A continuous action as a float64 vector: ``len(names)`` finite reals in [-1, 1];
    anything else raises ``ValueError``."""
    try:
        vector = np.array(action, dtype=np.float64)
    except (TypeError, ValueError):
        vector = None
    if (
        vector is None
        or vector.shape != (len(names),)
        or not np.isfinite(vector).all()
        or np.abs(vector).max() > 1.0
    ):
        raise ValueError(
            f"action must be {len(names)} finite numbers in [-1, 1] ({', '.join(names)}), "
            f"got {action!r}"
        )
    return vector


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
