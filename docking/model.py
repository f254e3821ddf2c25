"""The docking world's MJCF model: the asset ``docking/assets/docking.xml`` with the parts a
:class:`~docking.scene.WorldConfig` chooses set (:func:`make_mjcf`: the scene, the landmark's
shape, the distractors, the room and its shift, the camera's height and tilt, the dock), and
compiled (:func:`make_model`); the floor plan a figure draws is read back from the compiled
model (:func:`footprints`). No OpenGL: :mod:`docking.world` adds the physics, the camera and
the task (a ``dm_env.Environment``) on top of it.
"""

from __future__ import annotations

import functools

from docking import glenv  # noqa: F401  (the rendering defaults, before MuJoCo is imported)

# isort: split
import mujoco  # noqa: E402
import numpy as np  # noqa: E402
from dm_control import mjcf  # noqa: E402

from docking.scene import (  # noqa: E402
    ASSET_PATH,
    SECOND_ROOM_PATH,
    WorldConfig,
    _box_bounds,
)

# Geom groups of the asset: 0 the room, 1 the robot's visual body (hidden from its own
# camera), 2 what the robot's camera draws (everything that can appear red), 3 the virtual
# docking region (only in overview renders).
_ROOM_GROUP, _ROBOT_GROUP, _EYE_GROUP, _DOCK_GROUP = 0, 1, 2, 3


# ----------------------------------------------------------------------------------------
# The MJCF model: docking/assets/docking.xml, with the parts the configs choose set here.
# ----------------------------------------------------------------------------------------

#: The robot's planar joints, in the order of a pose ``[x, y, yaw]``; its servos carry the
#: same names.
POSE_JOINTS = ("x", "y", "yaw")


def make_mjcf(config: WorldConfig) -> mjcf.RootElement:
    """The scene of ``config`` as an editable ``dm_control.mjcf`` model: the asset with the eye
    camera's tilt, field of view and height, the docking region's position and size, the
    landmark's shape and stand, the room and its placement set from ``config``."""
    root = mjcf.from_path(str(ASSET_PATH))
    cam = config.camera
    eye = root.find("camera", "eye")
    eye.xyaxes = _eye_xyaxes(cam.tilt_deg)
    eye.fovy = cam.fovy_deg
    if config.camera_height is not None:
        eye.pos = [eye.pos[0], eye.pos[1], config.camera_height]
    dock = root.find("geom", "dock")
    dock.pos = [-config.dock_center, 0.0, dock.pos[2]]
    dock.size = [config.dock_depth / 2, config.dock_width / 2, dock.size[2]]
    landmark = root.find("geom", "landmark_slab")
    if config.landmark_shape == "slab":
        root.find("geom", "landmark_post").remove()
    if config.scene == "floor":  # take the sideboard away; the landmark stands on the floor
        sideboard = root.find("geom", "sideboard")
        top = float(sideboard.pos[2] + sideboard.size[2])
        sideboard.remove()
        for geom in _landmark_geoms(root):
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
    if config.room == "second":
        _furnish_second_room(root)
    if any(config.room_shift):
        _shift_room(root, config.room_shift)
    _mark_occluders(root)
    return root


def _landmark_geoms(root: mjcf.RootElement) -> list:
    """The landmark's geoms in ``root`` (the slab, and the post unless it was taken away)."""
    return [g for g in root.find_all("geom") if (g.name or "").startswith("landmark_")]


#: The parts of the asset that belong to its room, not to the landmark's stand: what
#: ``WorldConfig.room`` replaces and ``WorldConfig.room_shift`` moves.
_HOME_FURNITURE = ("sofa", "table", "shelf", "plant")
_ROOM_GEOMS = ("floor", "wall_front", "wall_back", "wall_left", "wall_right", "rug")


def _furnish_second_room(root: mjcf.RootElement) -> None:
    """Replace the home room's furniture, floor and walls by those of
    ``assets/second_room.xml`` (its materials ``floor``/``wall`` become the room's)."""
    second = mjcf.from_path(str(SECOND_ROOM_PATH))
    for name in _HOME_FURNITURE:
        root.find("body", name).remove()
    root.find("geom", "rug").remove()
    for material in second.asset.material:
        root.asset.add("material", **_attributes(material, prefix="second_"))
    for geom in root.find_all("geom"):
        if geom.name == "floor" or (geom.name or "").startswith("wall_"):
            geom.material = "second_" + ("floor" if geom.name == "floor" else "wall")
    for element in second.worldbody.all_children():
        _copy_into(element, root.worldbody, prefix="second_")


def _attributes(element, prefix: str = "") -> dict:
    """An element's attributes as keywords for ``add``: references to materials (by name)
    get ``prefix``, as the copies of those materials do."""
    found = {}
    for key, value in element.get_attributes().items():
        if key == "material":
            value = prefix + (value if isinstance(value, str) else value.name)
        elif key == "name":
            value = prefix + value
        found[key] = value
    return found


def _copy_into(element, parent, prefix: str = "") -> None:
    """Copy ``element`` (a body, geom or light, with its children) under ``parent``."""
    _build(_snapshot(element, prefix), parent)


def _snapshot(element, prefix: str) -> tuple:
    """``(tag, attributes, children)`` of ``element``, as :func:`_build` re-creates it."""
    children = [_snapshot(child, prefix) for child in element.all_children()]
    return element.tag, _attributes(element, prefix), children


def _build(snapshot: tuple, parent) -> None:
    tag, attributes, children = snapshot
    element = parent.add(tag, **attributes)
    for child in children:
        _build(child, element)


def _shift_room(root: mjcf.RootElement, shift: tuple[float, float, float]) -> None:
    """Move the room (floor, walls, furniture, ceiling light) by ``shift = (dx, dy,
    yaw_deg)`` about the landmark: into one body turned by yaw_deg about z, at (dx, dy)."""
    dx, dy, yaw = shift
    room = root.worldbody.add("body", name="room", pos=[dx, dy, 0.0], euler=[0, 0, np.radians(yaw)])
    moved = [
        element
        for element in root.worldbody.all_children()
        if element.tag in ("body", "geom", "light")
        and (
            element.name in _HOME_FURNITURE + _ROOM_GEOMS + ("ceiling",)
            or (element.name or "").startswith("second_")
        )
    ]
    for element in moved:
        snapshot = _snapshot(element, prefix="")
        element.remove()
        _build(snapshot, room)


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


def footprints(config: WorldConfig) -> dict[str, tuple[float, float, float, float]]:
    """Floor-plan rectangles ``(x0, y0, x1, y1)`` of the sideboard (if the scene has one), the
    landmark's two boxes and the docking region of ``config``'s compiled scene, for top-down
    figures."""
    model = make_model(config)
    rects = {}
    post = ("landmark_post",) if config.landmark_shape == "paper" else ()
    names = ("landmark_slab", *post, "dock")
    for name in (("sideboard",) if config.scene == "sideboard" else ()) + names:
        lo, hi = _box_bounds(model, name)
        rects[name] = (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
    return rects
