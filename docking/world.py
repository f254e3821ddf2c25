"""The docking world: a domestic room, a Nao-sized robot, a red landmark, a virtual dock.

This is the dm-control rebuild of the paper's Webots scene (Sec. II-C, Fig. 2). Like a
dm-control ``suite`` domain it has three parts: the MJCF model (:func:`make_model_xml`), a
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
four actions is one walking step whose target is displaced by noise in position and heading,
and the servos walk the body there through MuJoCo physics, so collisions with the landmark's
sideboard, the walls and the furniture are real. The humanoid itself (torso, head, arms, legs)
is visual only.
"""

from __future__ import annotations

import dataclasses
import functools
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
from dm_control import mujoco as dm_mujoco  # noqa: E402
from dm_control.mujoco import engine, wrapper  # noqa: E402
from dm_env import specs  # noqa: E402

from docking.camera import CameraConfig, preprocess  # noqa: E402
from docking.validate import check_instance, check_int, check_real, normalise  # noqa: E402

# Action indices. The paper (Sec. II-C): "four actions - moving forward, backward, right and
# left"; left and right are sidesteps (Nao walks sideways), not turns.
FORWARD, BACKWARD, LEFT, RIGHT = 0, 1, 2, 3
ACTION_NAMES = ("forward", "backward", "left", "right")
ACTION_LETTERS = ("F", "B", "L", "R")
N_ACTIONS = 4

# Geom groups: 0 the room (seen by everyone), 1 the robot's visual body (hidden from its own
# camera), 3 the virtual docking region (only in overview renders).
_ROBOT_GROUP, _DOCK_GROUP = 1, 3


@dataclasses.dataclass(frozen=True)
class WorldConfig:
    """Everything the paper leaves open about the world, with documented defaults.

    Attributes:
      step_forward: Length of a forward or backward step (m). One action is a short walk
        (about two of Nao's steps). The paper gives no length; it decides how much of the
        25-action budget a start 1.5 m away needs, and with it how often the near-random
        walk of training (beta_a = 2) reaches the dock and how large the learned values
        are: with 8 cm, Experiment 2 reached 49-76% in our runs, with 15 cm 98%.
      step_side: Length of a left or right sidestep (m); half the docking region's width, so
        one sidestep from anywhere within 10 cm outside the region ends inside it. (Nao's
        walk allows up to 16 cm sideways per step.)
      step_noise_xy: Std. of the displacement error added to each step, per body axis (m).
      step_noise_yaw_deg: Std. of the heading error of each step (deg). The paper names
        uncorrected rotation from Webots' movement noise as its main cause of failure.
      max_steps: At most this many actions per trial (paper: 25).
      start_near, start_far: The start trapezoid spans these distances of the robot's
        reference point from the landmark's front plane (m). Experiment 2 ends at 1.5 m.
      start_half_angle_deg: The trapezoid's lateral half-width grows as
        ``distance * tan(start_half_angle_deg)``; a wedge with its apex at the landmark, cut
        at ``start_near`` and ``start_far``.
      start_yaw_deg: Start headings are uniform in +-this around facing the landmark's wall.
      dock_center: Distance of the docking region's centre from the landmark's front plane (m);
        the region's near edge lies 1 cm beyond where the robot meets the sideboard (0.45 m).
      dock_depth: Extent of the region along the approach axis (m; paper: 8 cm).
      dock_width: Extent of the region across the approach axis (m; paper: 20 cm).
      view_margin_px: At a start pose the landmark's projection keeps this many pixels from
        the crop's border.
      camera: The head camera and the observation pipeline.
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

    def __post_init__(self):
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
            dock_center=real("dock_center", self.dock_center, lo=0, lo_open=True),
            dock_depth=real("dock_depth", self.dock_depth, lo=0, hi=1, lo_open=True),
            dock_width=real("dock_width", self.dock_width, lo=0, hi=2, lo_open=True),
            view_margin_px=real("view_margin_px", self.view_margin_px, lo=0, hi=100),
            camera=check_instance(owner, "camera", self.camera, CameraConfig),
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
        closest = _ROBOT_RADIUS - _CABINET["front"]
        if self.dock_center + self.dock_depth / 2 < closest + 0.01:
            raise ValueError(
                f"WorldConfig.dock_center must keep the region reachable: "
                f"dock_center + dock_depth/2 >= {closest + 0.01:.2f} m (the robot "
                f"meets the sideboard at {closest:.2f} m), got "
                f"dock_center={self.dock_center}"
            )


# ----------------------------------------------------------------------------------------
# The MJCF model.
# ----------------------------------------------------------------------------------------

# Fixed geometry of the scene (m). The landmark sits on a sideboard so that it appears near the
# camera's height at every distance, inside a wide, flat crop band like the paper's 32x10.
# The sideboard is deep and wide: the robot's body meets its front face at x = -0.45, 1 cm
# inside the docking region's near edge (so a robot pressed against the sideboard in front of
# the landmark is docked); a robot cannot walk past the landmark, and one that arrives beside
# the region stands at the sideboard and has to sidestep along it.
_CABINET = dict(front=-0.35, back=0.25, width=0.90, height=0.43)
# The landmark: a red, wide, low slab on the sideboard, 35 cm behind its front, and a red
# post standing behind it. Seen from the front the two read as an inverted T; from the left or
# right the post's parallax shifts it to one side (an L or a mirrored L), and the slab foreshortens.
_SLAB = dict(depth=0.05, width=0.12, height=0.05)
_POST = dict(depth=0.04, width=0.04, height=0.12, behind=0.15)
_ROBOT_RADIUS = 0.10  # the collision cylinder around the robot's body
_ROBOT_MASS = 5.2  # kg, a Nao
_CAM_FORWARD, _CAM_HEIGHT = 0.07, 0.48  # Nao's top camera: forehead, 0.48 m above the floor
_ROOM_FRONT, _ROOM_BACK, _ROOM_HALF_WIDTH = 0.45, 3.2, 2.2
_TIMESTEP = 0.02
_STEP_MOVE_TIME, _STEP_SETTLE_TIME = 0.3, 0.1  # s: one walking step, then standing still
_KP_XY, _KP_YAW = 20000.0, 100.0  # servo stiffness (N/m, N m/rad)


def _kv(kp: float, inertia: float) -> float:
    """Critical damping for a servo of stiffness ``kp`` on ``inertia``."""
    return 2.0 * float(np.sqrt(kp * inertia))


def make_model_xml(config: WorldConfig) -> str:
    """The MJCF of the room, the robot and the landmark for ``config``."""
    cam = config.camera
    tilt = np.radians(cam.tilt_deg)
    # MuJoCo cameras look along their -z axis with +y up: x-axis to the robot's right,
    # y-axis up and tilted forward by the camera's downward pitch.
    cam_axes = f"0 -1 0 {np.sin(tilt):.6f} 0 {np.cos(tilt):.6f}"
    c, s, p = _CABINET, _SLAB, _POST
    dock_x = -config.dock_center
    yaw_inertia = 0.5 * _ROBOT_MASS * _ROBOT_RADIUS**2
    return f"""
<mujoco model="docking">
  <compiler angle="radian"/>
  <option timestep="{_TIMESTEP}" integrator="implicitfast" gravity="0 0 -9.81"/>
  <visual>
    <!-- No shadow maps and no multisampling: a software-rendered frame is ~20x faster. -->
    <quality shadowsize="0" offsamples="0" numslices="16" numstacks="10"/>
    <global offwidth="960" offheight="720"/>
    <headlight ambient="0.55 0.55 0.55" diffuse="0.4 0.4 0.4" specular="0.05 0.05 0.05"/>
  </visual>
  <asset>
    <!-- Untextured on purpose: texture sampling doubles the cost of a software-rendered
         frame (measured 1.35 ms vs 0.69 ms at 160x120 under llvmpipe). -->
    <material name="floor" rgba="0.70 0.62 0.48 1"/>
    <material name="wall" rgba="0.90 0.88 0.82 1"/>
    <material name="cabinet" rgba="0.80 0.80 0.82 1"/>
    <material name="landmark" rgba="0.85 0.05 0.05 1" emission="0.35"/>
    <material name="sofa" rgba="0.25 0.35 0.55 1"/>
    <material name="wood" rgba="0.78 0.70 0.56 1"/>
    <material name="rug" rgba="0.35 0.50 0.40 1"/>
    <material name="plant" rgba="0.20 0.55 0.25 1"/>
    <material name="pot" rgba="0.35 0.35 0.38 1"/>
    <material name="nao_white" rgba="0.93 0.93 0.93 1"/>
    <material name="nao_grey" rgba="0.45 0.47 0.50 1"/>
    <material name="nao_blue" rgba="0.25 0.45 0.80 1"/>
    <material name="nao_eye" rgba="0.10 0.10 0.12 1"/>
    <material name="dock" rgba="1.0 0.9 0.0 0.6"/>
  </asset>
  <default>
    <geom contype="1" conaffinity="1" friction="0.6 0.005 0.0001"/>
    <default class="visual">
      <geom contype="0" conaffinity="0" density="0" group="{_ROBOT_GROUP}"/>
    </default>
  </default>
  <worldbody>
    <light name="ceiling" pos="-1.0 0 2.6" dir="0.3 0 -1" diffuse="0.3 0.3 0.3"
           specular="0.1 0.1 0.1" castshadow="false"/>
    <geom name="floor" type="plane" size="{_ROOM_BACK + 0.5} {_ROOM_HALF_WIDTH + 0.5} 0.1"
          material="floor"/>
    <!-- Walls -->
    <geom name="wall_front" type="box" pos="{_ROOM_FRONT + 0.05} 0 1.2"
          size="0.05 {_ROOM_HALF_WIDTH + 0.1} 1.2" material="wall"/>
    <geom name="wall_back" type="box" pos="{-_ROOM_BACK - 0.05} 0 1.2"
          size="0.05 {_ROOM_HALF_WIDTH + 0.1} 1.2" material="wall"/>
    <geom name="wall_left" type="box" pos="{(_ROOM_FRONT - _ROOM_BACK) / 2} {_ROOM_HALF_WIDTH + 0.05} 1.2"
          size="{(_ROOM_FRONT + _ROOM_BACK) / 2} 0.05 1.2" material="wall"/>
    <geom name="wall_right" type="box" pos="{(_ROOM_FRONT - _ROOM_BACK) / 2} {-_ROOM_HALF_WIDTH - 0.05} 1.2"
          size="{(_ROOM_FRONT + _ROOM_BACK) / 2} 0.05 1.2" material="wall"/>
    <!-- The landmark's sideboard and the landmark (the only red things in the room) -->
    <geom name="cabinet" type="box" pos="{(c["front"] + c["back"]) / 2} 0 {c["height"] / 2}"
          size="{(c["back"] - c["front"]) / 2} {c["width"] / 2} {c["height"] / 2}"
          material="cabinet"/>
    <geom name="landmark_slab" type="box"
          pos="{s["depth"] / 2} 0 {c["height"] + s["height"] / 2}"
          size="{s["depth"] / 2} {s["width"] / 2} {s["height"] / 2}" material="landmark"/>
    <geom name="landmark_post" type="box"
          pos="{p["behind"] + p["depth"] / 2} 0 {c["height"] + p["height"] / 2}"
          size="{p["depth"] / 2} {p["width"] / 2} {p["height"] / 2}" material="landmark"/>
    <!-- Furniture: a sofa, a low table, a shelf, a plant, a rug -->
    <body name="sofa" pos="-2.75 0.3 0">
      <geom type="box" pos="0 0 0.22" size="0.40 0.95 0.22" material="sofa"/>
      <geom type="box" pos="-0.30 0 0.55" size="0.10 0.95 0.20" material="sofa"/>
      <geom type="box" pos="0 0.90 0.35" size="0.40 0.10 0.12" material="sofa"/>
      <geom type="box" pos="0 -0.90 0.35" size="0.40 0.10 0.12" material="sofa"/>
    </body>
    <body name="table" pos="-1.6 1.55 0">
      <geom type="box" pos="0 0 0.40" size="0.35 0.25 0.02" material="wood"/>
      <geom type="cylinder" pos="0.3 0.2 0.19" size="0.02 0.19" material="wood"/>
      <geom type="cylinder" pos="-0.3 0.2 0.19" size="0.02 0.19" material="wood"/>
      <geom type="cylinder" pos="0.3 -0.2 0.19" size="0.02 0.19" material="wood"/>
      <geom type="cylinder" pos="-0.3 -0.2 0.19" size="0.02 0.19" material="wood"/>
    </body>
    <body name="shelf" pos="0.2 -1.45 0">
      <geom type="box" pos="0 0 0.55" size="0.18 0.45 0.55" material="wood"/>
    </body>
    <body name="plant" pos="0.15 1.3 0">
      <geom type="cylinder" pos="0 0 0.15" size="0.13 0.15" material="pot"/>
      <geom type="ellipsoid" pos="0 0 0.55" size="0.22 0.22 0.3" material="plant"/>
    </body>
    <geom name="rug" type="box" pos="-2.0 -0.2 0.002" size="0.8 0.6 0.002" material="rug"
          contype="0" conaffinity="0"/>
    <!-- The virtual docking region: drawn in overviews only, never seen by the robot -->
    <geom name="dock" type="box" pos="{dock_x} 0 0.003"
          size="{config.dock_depth / 2} {config.dock_width / 2} 0.003" material="dock"
          contype="0" conaffinity="0" group="{_DOCK_GROUP}"/>
    <!-- A Nao-sized humanoid (0.58 m) on a planar, servo-driven base -->
    <body name="robot" pos="0 0 0">
      <joint name="x" type="slide" axis="1 0 0" damping="0"/>
      <joint name="y" type="slide" axis="0 1 0" damping="0"/>
      <joint name="yaw" type="hinge" axis="0 0 1" damping="0"/>
      <geom name="body_collider" type="cylinder" pos="0 0 0.30" size="{_ROBOT_RADIUS} 0.27"
            mass="{_ROBOT_MASS}" rgba="0 0 0 0" group="4"/>
      <site name="reference" pos="0 0 0.005" size="0.01"/>
      <geom class="visual" type="box" pos="0.02 0.05 0.015" size="0.08 0.04 0.015" material="nao_grey"/>
      <geom class="visual" type="box" pos="0.02 -0.05 0.015" size="0.08 0.04 0.015" material="nao_grey"/>
      <geom class="visual" type="capsule" fromto="0 0.05 0.04 0 0.05 0.15" size="0.033" material="nao_white"/>
      <geom class="visual" type="capsule" fromto="0 -0.05 0.04 0 -0.05 0.15" size="0.033" material="nao_white"/>
      <geom class="visual" type="sphere" pos="0.01 0.05 0.155" size="0.034" material="nao_grey"/>
      <geom class="visual" type="sphere" pos="0.01 -0.05 0.155" size="0.034" material="nao_grey"/>
      <geom class="visual" type="capsule" fromto="0 0.05 0.16 0 0.05 0.26" size="0.036" material="nao_white"/>
      <geom class="visual" type="capsule" fromto="0 -0.05 0.16 0 -0.05 0.26" size="0.036" material="nao_white"/>
      <geom class="visual" type="box" pos="0 0 0.28" size="0.05 0.085 0.03" material="nao_grey"/>
      <geom class="visual" type="box" pos="0 0 0.365" size="0.055 0.075 0.065" material="nao_white"/>
      <geom class="visual" type="cylinder" pos="0.052 0 0.37" euler="0 1.5708 0" size="0.03 0.006" material="nao_blue"/>
      <geom class="visual" type="sphere" pos="0 0.1 0.41" size="0.03" material="nao_grey"/>
      <geom class="visual" type="sphere" pos="0 -0.1 0.41" size="0.03" material="nao_grey"/>
      <geom class="visual" type="capsule" fromto="0 0.11 0.40 0.03 0.12 0.30" size="0.024" material="nao_white"/>
      <geom class="visual" type="capsule" fromto="0 -0.11 0.40 0.03 -0.12 0.30" size="0.024" material="nao_white"/>
      <geom class="visual" type="capsule" fromto="0.03 0.12 0.30 0.08 0.12 0.24" size="0.021" material="nao_grey"/>
      <geom class="visual" type="capsule" fromto="0.03 -0.12 0.30 0.08 -0.12 0.24" size="0.021" material="nao_grey"/>
      <geom class="visual" type="cylinder" pos="0 0 0.44" size="0.025 0.015" material="nao_grey"/>
      <geom class="visual" type="ellipsoid" pos="0 0 0.505" size="0.062 0.068 0.062" material="nao_white"/>
      <geom class="visual" type="sphere" pos="0.052 0.025 0.51" size="0.012" material="nao_eye"/>
      <geom class="visual" type="sphere" pos="0.052 -0.025 0.51" size="0.012" material="nao_eye"/>
      <geom class="visual" type="cylinder" pos="0 0.066 0.505" euler="1.5708 0 0" size="0.035 0.008" material="nao_grey"/>
      <geom class="visual" type="cylinder" pos="0 -0.066 0.505" euler="1.5708 0 0" size="0.035 0.008" material="nao_grey"/>
      <camera name="eye" pos="{_CAM_FORWARD} 0 {_CAM_HEIGHT}" xyaxes="{cam_axes}"
              fovy="{cam.fovy_deg}"/>
    </body>
    <camera name="overview" pos="-1.55 -0.95 1.05" mode="targetbody" target="overview_target" fovy="45"/>
    <body name="overview_target" pos="-0.40 0.0 0.3"/>
    <camera name="top" pos="-0.85 0 2.6" xyaxes="0 -1 0 1 0 0" fovy="50"/>
  </worldbody>
  <actuator>
    <position name="x" joint="x" kp="{_KP_XY}" kv="{_kv(_KP_XY, _ROBOT_MASS)}"
              forcerange="-400 400"/>
    <position name="y" joint="y" kp="{_KP_XY}" kv="{_kv(_KP_XY, _ROBOT_MASS)}"
              forcerange="-400 400"/>
    <position name="yaw" joint="yaw" kp="{_KP_YAW}" kv="{_kv(_KP_YAW, yaw_inertia)}"
              forcerange="-40 40"/>
  </actuator>
</mujoco>
"""


class Physics(dm_mujoco.Physics):
    """MuJoCo physics of the docking world with the helpers the task needs."""

    def pose(self) -> np.ndarray:
        """The robot's ground-truth pose ``[x, y, yaw]`` (m, m, rad)."""
        return np.array(self.data.qpos[:3], dtype=np.float64)

    def set_pose(self, pose) -> None:
        """Place the robot at ``pose`` at rest, with its servos holding it there."""
        pose = np.asarray(pose, dtype=np.float64)
        with self.reset_context():
            self.data.qpos[:3] = pose
            self.data.qvel[:3] = 0.0
            self.data.ctrl[:3] = pose

    def walk_to(self, target, stop=None) -> bool:
        """One walking step: the servo targets glide from the current pose to ``target``
        (smoothstep over the step's duration), then hold while the body settles. Contacts
        stop the body where it meets an obstacle.

        ``stop(pose)`` (optional) is checked after every physics step; once it holds, the
        robot halts on the spot and ``walk_to`` returns True (the dock's detector)."""
        start = np.array(self.data.ctrl[:3])
        target = np.asarray(target, dtype=np.float64)
        n_move = int(round(_STEP_MOVE_TIME / _TIMESTEP))
        n_settle = int(round(_STEP_SETTLE_TIME / _TIMESTEP))
        qpos, ctrl = self.data.qpos, self.data.ctrl
        stopped = False
        for k in range(1, n_move + n_settle + 1):
            if k <= n_move:
                u = k / n_move
                ctrl[:3] = start + (target - start) * (u * u * (3.0 - 2.0 * u))
            mujoco.mj_step(self.model.ptr, self.data.ptr)
            if stop is not None and stop(qpos):
                stopped = True
                break
        # The servos now hold the body where it actually is, so a blocked step does not
        # keep pushing into the obstacle during the next one.
        ctrl[:3] = qpos[:3]
        self.data.qvel[:3] = 0.0
        self.forward()
        return stopped

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


def _scene_option(show_robot: bool, show_dock: bool) -> wrapper.MjvOption:
    option = wrapper.MjvOption()
    option.geomgroup[_ROBOT_GROUP] = int(show_robot)
    option.geomgroup[_DOCK_GROUP] = int(show_dock)
    return option


def _as_generator(seed) -> np.random.Generator:
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or isinstance(seed, (int, np.integer)):
        return np.random.default_rng(seed)
    raise ValueError(f"seed must be None, an int or a numpy.random.Generator, got {seed!r}")


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
        self._camera = _make_camera(self._physics, cam.height, cam.width, "eye")
        self._camera_option = _scene_option(show_robot=False, show_dock=False)
        self._start_near = self._config.start_near
        self._start_far = self._config.start_far
        self._frame = None
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
    def start_region(self) -> tuple[float, float]:
        """``(near, far)`` distances of the start trapezoid; the curriculum widens ``far``."""
        return self._start_near, self._start_far

    def set_start_region(self, near: float, far: float) -> None:
        """Change the start trapezoid for the following trials (Learning from Easy Missions)."""
        dataclasses.replace(self._config, start_near=near, start_far=far)  # validates
        self._start_near, self._start_far = float(near), float(far)

    # -- ground truth (never read by the learner) -----------------------------------------
    @property
    def pose(self) -> np.ndarray:
        """The robot's pose ``[x, y, yaw]``."""
        return self._physics.pose()

    @property
    def docked(self) -> bool:
        """Whether the robot's reference point is inside the docking region."""
        return in_dock(self._physics.pose(), self._config)

    @property
    def frame(self) -> np.ndarray | None:
        """The raw RGB camera frame behind the latest observation."""
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
        return specs.DiscreteArray(N_ACTIONS, dtype=np.int64, name="action")

    def reset(self) -> dm_env.TimeStep:
        return self.reset_to(self.sample_start_pose())

    def reset_to(self, pose) -> dm_env.TimeStep:
        """Start a trial at a given pose (for figures and tests)."""
        self._physics.set_pose(pose)
        self._steps = 0
        self._needs_reset = False
        return dm_env.restart(self._observe())

    def step(self, action) -> dm_env.TimeStep:
        if self._needs_reset:
            return self.reset()
        action = _check_action(action)
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
    def _in_dock(self, pose) -> bool:
        return in_dock(pose, self._config)

    def _step_target(self, action: int) -> np.ndarray:
        cfg = self._config
        forward = (cfg.step_forward, -cfg.step_forward, 0.0, 0.0)[action]
        side = (0.0, 0.0, cfg.step_side, -cfg.step_side)[action]
        noise = self._rng.normal(0.0, 1.0, size=3)
        forward += cfg.step_noise_xy * noise[0]
        side += cfg.step_noise_xy * noise[1]
        x, y, yaw = self._physics.data.ctrl[:3]
        cos, sin = np.cos(yaw), np.sin(yaw)
        return np.array(
            [
                x + cos * forward - sin * side,
                y + sin * forward + cos * side,
                yaw + np.radians(cfg.step_noise_yaw_deg) * noise[2],
            ]
        )

    def _observe(self) -> np.ndarray:
        frame = self.render_camera()
        self._frame = frame
        return preprocess(frame, self._config.camera)

    def render_camera(self) -> np.ndarray:
        """The robot's RGB camera frame (the robot's body and the dock are not drawn).

        Lit by the camera's headlight alone: the room's ceiling light, which overview renders
        use, would make each software-rendered frame ~50% slower, and the red threshold
        does not need it."""
        lights = self._physics.model.light_active
        lights[:] = 0
        try:
            return self._camera.render(scene_option=self._camera_option)
        finally:
            lights[:] = 1

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
        _check_frame_size(self._physics, width, height, "render_view width x height")
        return self._physics.render(
            height, width, camera_id=camera, scene_option=_scene_option(show_robot, show_dock)
        )

    def landmark_in_crop(self, pose=None, margin: float | None = None) -> bool:
        """Whether the whole landmark projects inside the crop rectangle from ``pose``
        (default: the current pose), keeping ``margin`` pixels from its border."""
        cam = self._config.camera
        margin = self._config.view_margin_px if margin is None else margin
        if pose is not None:
            saved = self._physics.pose()
            self._physics.data.qpos[:3] = pose
            self._physics.update_kinematics()
        uv = self._physics.project(self._physics.landmark_corners(), "eye", cam)
        if pose is not None:
            self._physics.data.qpos[:3] = saved
            self._physics.update_kinematics()
        x0, y0, x1, y1 = cam.crop
        return bool(
            np.all(np.isfinite(uv))
            and uv[:, 0].min() >= x0 + margin
            and uv[:, 0].max() <= x1 - margin
            and uv[:, 1].min() >= y0 + margin
            and uv[:, 1].max() <= y1 - margin
        )

    def sample_start_pose(self, max_tries: int = 10000) -> np.ndarray:
        """A uniform random pose in the start trapezoid from which the landmark is inside the
        crop rectangle (rejection sampling)."""
        cfg = self._config
        near, far = self._start_near, self._start_far
        tan = np.tan(np.radians(cfg.start_half_angle_deg))
        for _ in range(max_tries):
            # Uniform over the trapezoid's area: its width grows linearly with distance d,
            # so d has density proportional to d.
            d = np.sqrt(self._rng.uniform(near**2, far**2))
            y = self._rng.uniform(-1.0, 1.0) * d * tan
            yaw = np.radians(self._rng.uniform(-cfg.start_yaw_deg, cfg.start_yaw_deg))
            pose = np.array([-d, y, yaw])
            if self.landmark_in_crop(pose):
                return pose
        raise RuntimeError(
            f"no start pose with the landmark in view after {max_tries} tries; "
            "narrow start_half_angle_deg or start_yaw_deg"
        )


def footprints(config: WorldConfig) -> dict[str, tuple[float, float, float, float]]:
    """Floor-plan rectangles ``(x0, y0, x1, y1)`` of the sideboard, the landmark's two boxes and
    the docking region, for top-down figures."""
    c, s, p = _CABINET, _SLAB, _POST
    return {
        "cabinet": (c["front"], -c["width"] / 2, c["back"], c["width"] / 2),
        "landmark_slab": (0.0, -s["width"] / 2, s["depth"], s["width"] / 2),
        "landmark_post": (p["behind"], -p["width"] / 2, p["behind"] + p["depth"], p["width"] / 2),
        "dock": (
            -config.dock_center - config.dock_depth / 2,
            -config.dock_width / 2,
            -config.dock_center + config.dock_depth / 2,
            config.dock_width / 2,
        ),
    }


#: Radius of the robot's collision cylinder (m), for drawing its footprint.
ROBOT_RADIUS = _ROBOT_RADIUS


def in_dock(pose, config: WorldConfig) -> bool:
    """Whether ``pose``'s reference point lies in the docking region of ``config``."""
    x, y = pose[0], pose[1]
    return bool(
        abs(x + config.dock_center) <= config.dock_depth / 2 and abs(y) <= config.dock_width / 2
    )


def _check_action(action) -> int:
    """The action as an ``int``: exactly the integers ``0..N_ACTIONS-1``, as Python or numpy
    integers or a 0-d integer array; bools, floats (also integral ones), strings, other
    shapes and out-of-range values raise ``ValueError``."""
    value = action[()] if isinstance(action, np.ndarray) and action.ndim == 0 else action
    if (
        isinstance(value, (bool, np.bool_))
        or not isinstance(value, (int, np.integer))
        or not 0 <= value < N_ACTIONS
    ):
        raise ValueError(
            f"action must be an integer in 0..{N_ACTIONS - 1} "
            f"({', '.join(ACTION_NAMES)}), got {action!r}"
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


def _make_camera(physics: Physics, height: int, width: int, camera: str) -> engine.Camera:
    """A reusable offscreen camera; one clear error if no OpenGL backend can start."""
    _check_frame_size(physics, width, height, "CameraConfig.width x height")
    try:
        return engine.Camera(physics, height=height, width=width, camera_id=camera)
    except Exception as exc:  # the backends raise many different types
        backend = os.environ.get("MUJOCO_GL", "")
        raise RuntimeError(
            f"Could not start headless OpenGL rendering with MUJOCO_GL={backend!r} ({exc}). "
            "On a CPU-only Linux machine set MUJOCO_GL=egl and install Mesa's EGL "
            "(Debian/Ubuntu: apt-get install libegl1 libgl1-mesa-dri); `make setup` does "
            "both."
        ) from exc
