"""Tests of the docking world (issue #2): determinism, observations, geometry, physics."""

import dataclasses
import os

import dm_env
import mujoco
import numpy as np
import pytest
from absl.testing import absltest
from dm_env import test_utils

from docking.camera import CameraConfig, preprocess, red_mask
from docking.oracle import oracle_action
from docking.region import StartRegion
from docking.world import (
    _DOCK_GROUP,
    _EYE_GROUP,
    _ROBOT_GROUP,
    _ROOM_GROUP,
    ASSET_PATH,
    BACKWARD,
    FORWARD,
    LEFT,
    POSE_JOINTS,
    RIGHT,
    DockingEnv,
    WorldConfig,
    footprints,
    in_dock,
    make_model,
    scene_facts,
)

QUIET = WorldConfig(step_noise_xy=0.0, step_noise_yaw_deg=0.0)


@pytest.fixture(scope="module")
def env():
    return DockingEnv(seed=0)


@pytest.fixture(scope="module")
def quiet_env():
    return DockingEnv(QUIET, seed=0)


def _rollout(seed, n_trials=3):
    env = DockingEnv(seed=seed)
    actions = np.random.default_rng(123).integers(0, 4, size=200)
    observations, poses = [], []
    timestep = env.reset()
    observations.append(timestep.observation.copy())
    poses.append(env.pose)
    trials = 0
    for a in actions:
        timestep = env.step(int(a))
        observations.append(timestep.observation.copy())
        poses.append(env.pose)
        trials += timestep.last()
        if trials == n_trials:
            break
    return np.array(observations), np.array(poses)


def test_same_seed_gives_identical_observations_and_poses():
    obs_a, poses_a = _rollout(seed=7)
    obs_b, poses_b = _rollout(seed=7)
    np.testing.assert_array_equal(obs_a, obs_b)
    np.testing.assert_array_equal(poses_a, poses_b)
    obs_c, _ = _rollout(seed=8)
    assert obs_c.shape != obs_a.shape or not np.array_equal(obs_a, obs_c)


def test_generator_seed_is_accepted_and_bad_seed_raises():
    DockingEnv(seed=np.random.default_rng(3))
    with pytest.raises(ValueError, match="seed"):
        DockingEnv(seed="three")


def test_observation_shape_dtype_range(env):
    timestep = env.reset()
    for _ in range(30):
        obs = timestep.observation
        assert obs.shape == (10, 32)
        assert obs.dtype == np.float32
        assert obs.min() >= 0.0 and obs.max() <= 1.0
        env.observation_spec().validate(obs)
        timestep = env.step(np.random.default_rng(len(_ * "x")).integers(4))
    assert env.frame.shape == (120, 160, 3) and env.frame.dtype == np.uint8


def test_landmark_inside_crop_at_every_start(env):
    cam = env.config.camera
    x0, y0, x1, y1 = cam.crop
    for _ in range(150):
        timestep = env.reset()
        assert env.landmark_in_crop()
        mask = red_mask(env.frame, cam)
        inside = mask[y0:y1, x0:x1].sum()
        assert inside > 0, "the landmark must be seen"
        assert mask.sum() == inside, "no red pixel may lie outside the crop rectangle"
        assert timestep.observation.sum() > 0
        # and the start is in the trapezoid, facing the landmark's wall
        x, y, yaw = env.pose
        assert env.start_region == StartRegion.of(env.config)
        assert env.start_region.contains(env.pose)
        assert abs(np.degrees(yaw)) <= env.config.start_yaw_deg + 1e-9


def test_start_region_can_be_narrowed(env):
    env.set_start_region(0.6, 0.8)
    try:
        assert (env.start_region.near, env.start_region.far) == (0.6, 0.8)
        assert env.start_region.half_angle_deg == env.config.start_half_angle_deg
        for _ in range(50):
            env.reset()
            assert 0.6 - 1e-9 <= -env.pose[0] <= 0.8 + 1e-9
            assert env.start_region.contains(env.pose)
    finally:
        env.set_start_region(env.config.start_near, env.config.start_far)
    with pytest.raises(ValueError, match="start_far"):
        env.set_start_region(0.9, 0.7)


@pytest.mark.parametrize(
    "action,forward,left", [(FORWARD, 1, 0), (BACKWARD, -1, 0), (LEFT, 0, 1), (RIGHT, 0, -1)]
)
def test_noise_free_step_moves_by_configured_distance(quiet_env, action, forward, left):
    yaw = 0.3
    quiet_env.reset_to([-1.2, 0.2, yaw])
    before = quiet_env.pose
    quiet_env.step(action)
    after = quiet_env.pose
    length = QUIET.step_forward * forward + QUIET.step_side * left
    expected = (
        np.array([np.cos(yaw), np.sin(yaw)]) * QUIET.step_forward * forward
        + np.array([-np.sin(yaw), np.cos(yaw)]) * QUIET.step_side * left
    )
    np.testing.assert_allclose(after[:2] - before[:2], expected, atol=5e-4)
    assert np.linalg.norm(after[:2] - before[:2]) == pytest.approx(abs(length), abs=5e-4)
    assert after[2] == pytest.approx(yaw, abs=1e-4)


def test_step_noise_perturbs_position_and_heading():
    env = DockingEnv(WorldConfig(step_noise_xy=0.01, step_noise_yaw_deg=2.0), seed=1)
    moves, turns = [], []
    for _ in range(40):
        env.reset_to([-1.2, 0.0, 0.0])
        env.step(FORWARD)
        moves.append(env.pose[0] + 1.2)
        turns.append(env.pose[2])
    assert 0.005 < np.std(moves) < 0.02
    assert np.radians(1.0) < np.std(turns) < np.radians(3.0)
    assert np.mean(moves) == pytest.approx(env.config.step_forward, abs=0.006)


def test_docking_is_detected_inside_and_not_outside(quiet_env):
    cfg = QUIET
    cx, half_depth, half_width = -cfg.dock_center, cfg.dock_depth / 2, cfg.dock_width / 2
    assert in_dock([cx, 0.0, 0.0], cfg)
    assert in_dock([cx + half_depth - 1e-3, half_width - 1e-3, 0.3], cfg)
    assert not in_dock([cx + half_depth + 1e-3, 0.0, 0.0], cfg)
    assert not in_dock([cx - half_depth - 1e-3, 0.0, 0.0], cfg)
    assert not in_dock([cx, half_width + 1e-3, 0.0], cfg)
    assert not in_dock([cx, -half_width - 1e-3, 0.0], cfg)
    # A forward step from just outside the region's far edge ends inside: reward 1, terminal.
    quiet_env.reset_to([cx - half_depth - 0.02, 0.0, 0.0])
    assert not quiet_env.docked
    timestep = quiet_env.step(FORWARD)
    assert quiet_env.docked
    assert timestep.last() and timestep.reward == 1.0 and timestep.discount == 0.0
    # A sidestep that stays outside the region: reward 0, not terminal.
    quiet_env.reset_to([cx, half_width + cfg.step_side + 0.05, 0.0])
    timestep = quiet_env.step(RIGHT)
    assert not quiet_env.docked
    assert timestep.mid() and timestep.reward == 0.0


def test_a_step_cannot_jump_over_the_region():
    # The region is shallower than a long step; the robot halts where it enters the region.
    cfg = dataclasses.replace(QUIET, step_forward=0.2)
    env = DockingEnv(cfg, seed=0)
    env.reset_to([-cfg.dock_center - cfg.dock_depth / 2 - 0.01, 0.0, 0.0])
    timestep = env.step(FORWARD)
    assert timestep.last() and timestep.reward == 1.0
    assert env.docked


def test_step_limit_ends_trial_as_truncation(quiet_env):
    quiet_env.reset_to([-1.0, 0.3, 0.0])
    for k in range(QUIET.max_steps):
        timestep = quiet_env.step(LEFT if k % 2 == 0 else RIGHT)
        assert timestep.last() == (k == QUIET.max_steps - 1)
    assert timestep.reward == 0.0 and timestep.discount == 1.0
    assert quiet_env.step(FORWARD).first()  # the next step starts a new trial


def test_walking_into_the_landmark_does_not_pass_through(quiet_env):
    # Beside the docking region (so the trial does not end) and straight at the sideboard.
    quiet_env.reset_to([-0.7, QUIET.dock_width / 2 + 0.03, 0.0])
    xs = []
    for _ in range(8):  # 0.25 m to the sideboard, then five steps more
        timestep = quiet_env.step(FORWARD)
        xs.append(quiet_env.pose[0])
        assert not timestep.last()
    # The robot's collision cylinder stops at the sideboard's front face.
    x0 = footprints(QUIET)["sideboard"][0]
    assert max(xs) <= x0 - scene_facts().robot_radius + 0.01
    assert max(xs) >= x0 - scene_facts().robot_radius - 0.01  # it did reach the sideboard
    assert np.ptp(xs[-4:]) < 0.01  # and stays there


@pytest.mark.parametrize(
    "field,value",
    [
        ("step_forward", -0.1),
        ("step_side", 0.0),
        ("step_noise_xy", -0.01),
        ("step_noise_yaw_deg", -1.0),
        ("max_steps", 0),
        ("dock_width", -0.08),
        ("dock_center", 0.3),
        ("start_far", 0.5),
        ("start_near", 0.2),
        ("start_far", 5.0),
    ],
)
def test_bad_config_raises_naming_the_parameter(field, value):
    with pytest.raises(ValueError, match=field):
        dataclasses.replace(WorldConfig(), **{field: value})


def test_bad_camera_config_raises():
    with pytest.raises(ValueError, match="crop"):
        CameraConfig(crop=(0, 0, 200, 50))
    with pytest.raises(ValueError, match="fovy_deg"):
        CameraConfig(fovy_deg=-3)


@pytest.mark.parametrize("action", [-1, 4, 1.5, "left", None])
def test_bad_action_raises(env, action):
    env.reset()
    with pytest.raises(ValueError, match="action"):
        env.step(action)


def test_oracle_docks_from_a_far_corner():
    env = DockingEnv(QUIET, seed=0)
    timestep = env.reset_to([-1.5, 0.35, 0.05])
    while not timestep.last():
        timestep = env.step(oracle_action(env.pose, env.config))
    assert timestep.reward == 1.0 and env.docked


class DockingEnvContractTest(test_utils.EnvironmentTestMixin, absltest.TestCase):
    """The dm_env interface contract, with action sequences that end trials both ways."""

    def make_object_under_test(self):
        return DockingEnv(seed=0)

    def make_action_sequence(self):
        rng = np.random.default_rng(0)
        env = self.environment
        for _ in range(60):  # random actions run into the step limit
            yield int(rng.integers(4))
        for _ in range(60):  # the oracle docks
            yield oracle_action(env.pose, env.config)


def test_timestep_types(quiet_env):
    timestep = quiet_env.reset()
    assert timestep.step_type == dm_env.StepType.FIRST and timestep.reward is None


def test_robot_pressed_against_the_sideboard_in_front_of_the_landmark_is_docked(quiet_env):
    # Arriving beside the region, at the sideboard, a sidestep along it docks the robot.
    quiet_env.reset_to([-0.6, QUIET.dock_width / 2 + 0.04, 0.0])
    for _ in range(3):
        timestep = quiet_env.step(FORWARD)
        if timestep.last():
            break
    assert not quiet_env.docked  # still beside the region, pressed against the sideboard
    timestep = quiet_env.step(RIGHT)
    assert timestep.last() and timestep.reward == 1.0


# -- the scene as an MJCF asset (issue 8) ---------------------------------------------------


def test_asset_compiles_standalone_and_matches_the_default_world():
    # The asset alone (as the viewer opens it) is the scene of the default WorldConfig.
    standalone = mujoco.MjModel.from_xml_path(str(ASSET_PATH))
    model = make_model(WorldConfig())
    for field in ("geom_size", "geom_pos", "cam_quat", "cam_fovy", "actuator_biasprm"):
        np.testing.assert_array_equal(getattr(standalone, field), getattr(model, field))


def test_config_sets_camera_and_dock_in_the_compiled_model():
    cfg = WorldConfig(
        dock_center=0.5, dock_depth=0.1, dock_width=0.3, camera=CameraConfig(tilt_deg=7.0)
    )
    model = make_model(cfg)
    np.testing.assert_allclose(model.geom("dock").pos[:2], [-0.5, 0.0])
    np.testing.assert_allclose(model.geom("dock").size[:2], [0.05, 0.15])
    assert model.cam("eye").fovy[0] == cfg.camera.fovy_deg
    # The camera's optical axis (-z) points forward and down by the tilt.
    optical_axis = -model.cam("eye").mat0.reshape(3, 3)[:, 2]
    np.testing.assert_allclose(
        optical_axis, [np.cos(np.radians(7.0)), 0.0, -np.sin(np.radians(7.0))], atol=1e-6
    )
    assert footprints(cfg)["dock"] == pytest.approx((-0.55, -0.15, -0.45, 0.15))


def test_scene_facts_are_read_from_the_compiled_model():
    facts = scene_facts()
    model = make_model(WorldConfig())
    assert facts.robot_radius == scene_facts().robot_radius == model.geom("body_collider").size[0]
    assert facts.sideboard == footprints(WorldConfig())["sideboard"]
    sideboard = model.geom("sideboard")
    assert facts.sideboard[0] == pytest.approx(sideboard.pos[0] - sideboard.size[0])
    assert facts.sideboard_height == pytest.approx(2 * sideboard.size[2])
    assert facts.camera_height == model.cam("eye").pos[2]
    # The landmark stands on the sideboard (a hairline above it), its front face is x = 0.
    slab = footprints(WorldConfig())["landmark_slab"]
    assert slab[0] == 0.0
    for name in ("landmark_slab", "landmark_post"):
        bottom = model.geom(name).pos[2] - model.geom(name).size[2]
        assert 0 < bottom - facts.sideboard_height <= 0.001 + 1e-12
    # The start region fits in the room.
    assert WorldConfig().start_far < facts.room_back


def test_servos_are_critically_damped():
    # kv = 2 sqrt(kp * inertia) as the asset's comment says, with the compiled robot's mass
    # (x, y) and yaw inertia.
    model = make_model(WorldConfig())
    robot = model.body("robot")
    inertia = {"x": robot.mass[0], "y": robot.mass[0], "yaw": robot.inertia[2]}
    for name, value in inertia.items():
        actuator = model.actuator(name)
        kp, kv = actuator.gainprm[0], -actuator.biasprm[2]
        assert kv == pytest.approx(2 * np.sqrt(kp * value), rel=1e-9), name


def test_pose_is_read_through_the_named_joints(quiet_env):
    quiet_env.reset_to([-0.9, 0.1, 0.05])
    quiet_env.step(LEFT)
    named = quiet_env.physics.named.data.qpos[list(POSE_JOINTS)]
    np.testing.assert_array_equal(quiet_env.pose, named)
    np.testing.assert_array_equal(
        quiet_env.physics.servo_targets(), quiet_env.physics.named.data.ctrl[list(POSE_JOINTS)]
    )


def test_geom_groups_of_the_asset():
    model = make_model(WorldConfig())
    groups = {model.geom(i).name: int(model.geom_group[i]) for i in range(model.ngeom)}
    assert groups["dock"] == _DOCK_GROUP
    robot = model.body("robot").id
    visual = [
        i
        for i in range(model.ngeom)
        if model.geom_bodyid[i] == robot and model.geom(i).name != "body_collider"
    ]
    assert visual and all(model.geom_group[i] == _ROBOT_GROUP for i in visual)


# -- what the robot's camera renders (issue 9) -----------------------------------------------


def _worlds():
    from docking.presets import FLOOR_WORLD, NAO_WORLD, RELOCATIONS
    from docking.world import Distractor

    cup = WorldConfig(distractors=(Distractor.cup(y=0.30),))
    return {
        "sideboard": WorldConfig(),
        "floor": FLOOR_WORLD,
        "cup": cup,
        "nao": NAO_WORLD,
        **{name.replace(" ", "-"): world for name, world in RELOCATIONS.items()},
    }


#: Every world of _worlds (the render and occlusion tests run in each).
WORLDS = ["sideboard", "floor", "cup", "nao", "along-the-wall", "another-wall", "second-room"]


def _poses_across_the_start_region(world=None, n=60, seed=0):
    """Start poses across the full start region, plus poses close to the landmark: pressed
    against the sideboard's front and at its edges (where the landmark is closest and lowest
    in the image), or in and around the docking region in the floor scene."""
    world = WorldConfig() if world is None else world
    env = DockingEnv(world, seed=seed)
    poses = [env.sample_start_pose() for _ in range(n)]
    facts = scene_facts()
    if world.scene == "sideboard":
        near, ys = facts.sideboard[0] - facts.robot_radius - 0.001, facts.sideboard[1::2]
    else:
        near, ys = -world.dock_center - world.dock_depth / 2, (-0.3, 0.3)
    for y in (ys[0], -0.2, 0.0, 0.2, ys[1]):
        for yaw in (-0.15, 0.0, 0.15):
            poses.append(np.array([near, y, yaw]))
    return env, poses


def _names(model):
    return {model.geom(i).name for i in range(model.ngeom)}


def _render(env, groups, window=None):
    cam = env.config.camera
    view = env._renderer.view(
        "eye", cam.width, cam.height, groups=groups, lights=False, window=window
    )
    return view.render(env.physics.data.ptr).copy()


@pytest.mark.parametrize("world", WORLDS)
def test_band_render_equals_the_crop_of_the_full_frame(world):
    # The narrowed frustum renders the crop's pixels of the full frame, up to rounding where a
    # triangle's edge crosses a pixel's centre: at most 8 pixels per frame (measured in the
    # default world: 1 in 515 frames with the camera's group, up to 5 with the whole room, at
    # the walls' and the floor's edges), never a pixel of the red mask.
    env, poses = _poses_across_the_start_region(_worlds()[world])
    cam = env.config.camera
    x0, y0, x1, y1 = cam.crop
    for groups in ((_EYE_GROUP,), (_ROOM_GROUP, _EYE_GROUP)):
        for pose in poses:
            env.reset_to(pose)
            full = _render(env, groups)[y0:y1, x0:x1]
            band = _render(env, groups, window=cam.crop)
            assert np.sum(np.any(full != band, axis=2)) <= 8
            np.testing.assert_array_equal(red_mask(full, cam), red_mask(band, cam))


@pytest.mark.parametrize("world", WORLDS)
def test_hiding_the_other_geoms_does_not_change_the_observation(world):
    # The robot's camera draws only group 2 (the landmark); with the room drawn as well, the
    # red mask of the crop is the same, pixel for pixel, and so is the observation.
    env, poses = _poses_across_the_start_region(_worlds()[world])
    cam = env.config.camera
    x0, y0, x1, y1 = cam.crop
    seen = 0
    for pose in poses:
        observation = env.reset_to(pose).observation
        with_room = _render(env, (_ROOM_GROUP, _EYE_GROUP))
        alone = _render(env, (_EYE_GROUP,))
        np.testing.assert_array_equal(red_mask(with_room, cam), red_mask(alone, cam))
        np.testing.assert_array_equal(preprocess(with_room, cam), observation)
        seen += bool(red_mask(alone, cam)[y0:y1, x0:x1].any())
    assert seen >= len(poses) - 6  # beside the sideboard's ends the landmark is out of view


def test_only_the_camera_group_can_appear_red():
    # Every geom whose colour passes the red threshold (hue and saturation do not depend on
    # the headlight's shading) is in the camera's group: the landmark's two boxes.
    model = make_model(WorldConfig())
    cam = WorldConfig().camera
    red = []
    for i in range(model.ngeom):
        matid = model.geom_matid[i]
        rgba = model.mat_rgba[matid] if matid >= 0 else model.geom_rgba[i]
        if rgba[3] == 0:
            continue  # never drawn
        pixel = np.uint8(np.round(255 * np.array(rgba[:3]))).reshape(1, 1, 3)
        if red_mask(pixel, cam).any():
            red.append(model.geom(i).name)
            assert model.geom_group[i] == _EYE_GROUP, model.geom(i).name
    assert sorted(red) == ["landmark_post", "landmark_slab"]


@pytest.mark.slow
@pytest.mark.parametrize("world", WORLDS)
def test_no_hidden_geom_can_occlude_the_landmark(world):
    # Rays from the robot's camera to points on the faces of the red geoms (the landmark, a
    # distractor) that lie in its crop, from a 10 cm grid over the whole floor the robot can
    # stand on, facing anywhere (every 10 deg), hit no geom outside the camera's group
    # first: the walls stand behind every line of sight, the sideboard's top below it (the
    # camera is above it and the landmark floats above it), and the furniture that can be in
    # the way is in the camera's group (docking.world._mark_occluders).
    config = _worlds()[world]
    model = make_model(config)
    data = mujoco.MjData(model)
    facts = scene_facts()
    eye = model.cam("eye")
    forward, height = float(eye.pos[0]), float(eye.pos[2])
    points = []
    red = [n for n in ("landmark_slab", "landmark_post", "distractor0") if n in _names(model)]
    for name in red:
        # The geom's bounding box (its faces for the boxes).
        k = model.geom(name).id
        centre, size = model.geom_pos[k] + model.geom_aabb[k, :3], model.geom_aabb[k, 3:]
        grid = np.linspace(-0.999, 0.999, 5)
        for axis in range(3):
            for sign in (-1.0, 1.0):
                for a in grid:
                    for b in grid:
                        local = np.empty(3)
                        local[axis] = sign
                        local[[k for k in range(3) if k != axis]] = (a, b)
                        points.append(centre + local * size)
    points = np.array(points)
    mujoco.mj_forward(model, data)
    hidden = np.array([g != _EYE_GROUP for g in range(6)], dtype=np.uint8)
    robot = model.body("robot").id
    # The robot's collision cylinder must fit: skip stands inside a collidable geom.
    blocked = []
    for i in range(model.ngeom):
        if model.geom_contype[i] and model.geom_type[i] != mujoco.mjtGeom.mjGEOM_PLANE:
            if model.geom_bodyid[i] != robot:
                half = np.abs(data.geom_xmat[i].reshape(3, 3)[:2, :2]) @ model.geom_aabb[i, 3:5]
                blocked.append((data.geom_xpos[i][:2], half))
    cam = config.camera
    x0, y0, x1, y1 = cam.crop
    tilt = np.radians(cam.tilt_deg)
    yaws = np.radians(np.arange(0, 360, 10))
    cos_yaw, sin_yaw = np.cos(yaws), np.sin(yaws)
    heights = np.full(len(yaws), height)
    ahead = np.stack(
        [cos_yaw * np.cos(tilt), sin_yaw * np.cos(tilt), np.full(len(yaws), -np.sin(tilt))], 1
    )
    right = np.stack([sin_yaw, -cos_yaw, np.zeros(len(yaws))], axis=1)
    up = np.cross(right, ahead)
    stands, rays = 0, 0
    # The grid covers the room's floor, wherever WorldConfig.room_shift put the room.
    dx, dy, turn = config.room_shift
    cos, sin = np.cos(np.radians(turn)), np.sin(np.radians(turn))
    for xr in np.arange(-facts.room_back + 0.1, facts.room_front, 0.1):
        for yr in np.arange(-facts.room_half_width + 0.1, facts.room_half_width, 0.1):
            x, y = dx + cos * xr - sin * yr, dy + sin * xr + cos * yr
            if any(np.all(np.abs([x, y] - c) < h + facts.robot_radius) for c, h in blocked):
                continue
            stands += 1
            # the camera facing every 10 deg at once: its position, and where each point
            # falls in its image (the camera's axes for each heading are computed once, below)
            cameras = np.stack([x + forward * cos_yaw, y + forward * sin_yaw, heights], axis=1)
            vecs = points[None] - cameras[:, None]
            depth = np.einsum("ypk,yk->yp", vecs, ahead)
            with np.errstate(divide="ignore", invalid="ignore"):
                u = cam.width / 2 + cam.focal_px * np.einsum("ypk,yk->yp", vecs, right) / depth
                v = cam.height / 2 - cam.focal_px * np.einsum("ypk,yk->yp", vecs, up) / depth
            in_crop = (depth > 0) & (u >= x0) & (u <= x1) & (v >= y0) & (v <= y1)
            for k in np.flatnonzero(in_crop.any(axis=1)):
                n = int(in_crop[k].sum())
                rays += n
                # mj_ray's distances, bit for bit, for all the rays from this camera at once
                hit, geomid = np.empty(n), np.empty(n, dtype=np.int32)
                seen = np.ascontiguousarray(vecs[k][in_crop[k]]).ravel()
                mujoco.mj_multiRay(
                    model,
                    data,
                    cameras[k],
                    seen,
                    hidden,
                    1,
                    robot,
                    geomid,
                    hit,
                    None,
                    n,
                    mujoco.mjMAXVAL,
                )
                first = (hit >= 0) & (hit <= 1 - 1e-9)  # a geom before the red point
                assert not first.any(), (x, y, yaws[k], model.geom(geomid[first][0]).name)
    assert stands > 500 and rays > 100_000


def test_a_distractor_is_red_solid_and_seen_when_in_view():
    from docking.experiments import ExperimentConfig
    from docking.presets import EXPERIMENT_2
    from docking.world import Distractor

    cup = Distractor.cup(y=0.30)
    world = WorldConfig(distractors=(cup,))
    plain, with_cup = DockingEnv(seed=0), DockingEnv(world, seed=0)
    geom = with_cup.physics.model.geom("distractor0")
    np.testing.assert_allclose(geom.size[:2], cup.size)
    np.testing.assert_allclose(with_cup.physics.data.geom("distractor0").xpos, cup.position)
    # Seen from straight in front, far enough back, the cup enters the crop beside the landmark.
    pose = [-1.4, 0.0, 0.0]
    seen = with_cup.reset_to(pose).observation
    baseline = plain.reset_to(pose).observation
    assert seen.sum() > baseline.sum() + 0.5
    # The cup stands on the robot's left (+y): it appears left of the landmark in the image,
    # and the landmark's own pixels are unchanged.
    assert np.array_equal(seen[:, 13:], baseline[:, 13:])
    assert seen[:, :13].sum() > 0.5 and baseline[:, :13].sum() == 0
    # The default world has none, and a config with one round-trips through a dict.
    assert WorldConfig().distractors == ()
    config = dataclasses.replace(
        EXPERIMENT_2, world=dataclasses.replace(EXPERIMENT_2.world, distractors=(cup,))
    )
    assert ExperimentConfig.from_dict(config.to_dict()) == config


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(shape="cone", size=(0.1,), position=(0, 0, 0)), "Distractor.shape"),
        (dict(shape="box", size=(0.1, 0.1), position=(0, 0, 0)), "Distractor.size"),
        (dict(shape="sphere", size=(-0.1,), position=(0, 0, 0)), r"Distractor.size\[0\]"),
        (dict(shape="sphere", size=(0.1,), position=(0, 0)), "Distractor.position"),
        (dict(shape="sphere", size=(0.1,), position=(0, float("nan"), 0)), "position"),
    ],
)
def test_bad_distractors_raise_naming_the_field(kwargs, match):
    from docking.world import Distractor

    with pytest.raises(ValueError, match=match):
        Distractor(**kwargs)
    with pytest.raises(ValueError, match="distractors"):
        WorldConfig(distractors=("cup",))


def test_the_floor_scene_has_no_sideboard_and_the_landmark_on_the_floor():
    from docking.presets import FLOOR_WORLD

    env = DockingEnv(FLOOR_WORLD, seed=0)
    model = env.physics.model
    names = {model.geom(k).name for k in range(model.ngeom)}
    assert "sideboard" not in names and "sideboard" not in footprints(FLOOR_WORLD)
    slab = env.physics.data.geom("landmark_slab")
    # On the floor, a hairline (1 mm) above it like on the sideboard (no z-fighting).
    assert slab.xpos[2] - model.geom("landmark_slab").size[2] == pytest.approx(0.001)
    # Nothing stops the robot at the dock: it can walk past the landmark's side ...
    quiet = DockingEnv(dataclasses.replace(FLOOR_WORLD, step_noise_xy=0.0, step_noise_yaw_deg=0.0))
    quiet.reset_to([-0.7, 0.25, 0.0])
    for _ in range(6):
        quiet.step(FORWARD)
    assert quiet.pose[0] > 0.0  # beyond the landmark's front face
    # ... and the landmark's image moves up the frame with distance.
    rows = []
    for d in (0.7, 1.0, 1.4):
        env.physics.set_pose([-d, 0.0, 0.0])
        env.physics.update_kinematics()
        rows.append(
            env.physics.project(env.physics.landmark_corners(), "eye", FLOOR_WORLD.camera)[
                :, 1
            ].mean()
        )
    assert rows[0] > rows[1] + 10 > rows[2] + 20
    for _ in range(30):
        env.reset()
        assert env.landmark_in_crop()


# -- the world's configuration without rendering; heading hold; actions by name -------------


def test_the_world_configuration_and_the_presets_need_no_opengl():
    """Importing docking.scene needs nothing but numpy; the presets compile the asset (with
    MuJoCo's GL disabled here: no rendering library is touched) but load no renderer."""
    import subprocess
    import sys

    code = (
        "import sys, docking.scene\n"
        "assert 'mujoco' not in sys.modules, 'docking.scene imported mujoco'\n"
        "import docking.presets\n"
        "loaded = {'dm_control', 'OpenGL', 'docking.world', 'docking.render'} & set(sys.modules)\n"
        "assert not loaded, loaded\n"
        "print(docking.presets.EXPERIMENT_2.world.n_actions)"
    )
    env = {**os.environ, "MUJOCO_GL": "disable"}
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=False
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "4"


def test_actions_are_found_by_name():
    turning = WorldConfig(actions="turning")
    assert turning.action_index("turn-left") == 4
    assert WorldConfig().action_index("forward") == 0
    with pytest.raises(ValueError, match="no action 'turn-left'; its actions are forward"):
        WorldConfig().action_index("turn-left")


def test_a_far_dock_centre_is_named_as_such():
    with pytest.raises(ValueError, match="WorldConfig.dock_center must be in"):
        WorldConfig(dock_center=1e300)


def test_heading_hold_keeps_the_heading_error_from_adding_up():
    noisy = WorldConfig(step_noise_yaw_deg=6.0, max_steps=100, start_far=0.9)
    spreads = {}
    for hold in (False, True):
        env = DockingEnv(dataclasses.replace(noisy, heading_hold=hold), seed=11)
        drift = []
        for _ in range(8):
            env.reset_to([-1.2, 0.0, 0.05])
            for _ in range(12):
                env.step(1 if env.pose[0] > -1.0 else 0)  # back and forth, never docking
            drift.append(env.pose[2] - 0.05)
        spreads[hold] = float(np.std(drift))
    # 12 steps of 6 deg noise: ~21 deg without the hold, ~6 deg (one step's) with it.
    assert spreads[True] < np.radians(12) < spreads[False]


def test_the_gl_context_is_freed_cleanly_at_exit_whatever_was_imported_first():
    """The store asks for the rendering stack before a run imports the world; the process
    must still exit without EGL errors (the context is freed before the display ends)."""
    import subprocess
    import sys

    code = (
        "from docking.render import gl_stack\n"
        "print(gl_stack())\n"
        "from docking.world import DockingEnv\n"
        "DockingEnv(seed=0).reset()\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    assert "Exception ignored" not in out.stderr and "EGLError" not in out.stderr, out.stderr


# -- input checks (issue 49): one clear line each --------------------------------------------


@pytest.mark.parametrize("pose", [[-100.0, 0.0, 0.0], [0.0, 50.0, 0.0], [-3.15, 0.0, 0.0]])
def test_reset_to_refuses_a_pose_outside_the_room(env, pose):
    with pytest.raises(ValueError, match=r"DockingEnv\.reset_to: pose must put the robot inside"):
        env.reset_to(pose)


@pytest.mark.parametrize("yaw", [1e308, -1e308, 2049 * np.pi])
def test_reset_to_refuses_a_yaw_beyond_1024_turns(env, yaw):
    with pytest.raises(ValueError, match=r"DockingEnv\.reset_to: pose's yaw must lie within"):
        env.reset_to([-1.0, 0.0, yaw])


@pytest.mark.parametrize("yaw", [np.nan, np.inf, -np.inf])
def test_reset_to_refuses_a_yaw_that_is_no_number(env, yaw):
    with pytest.raises(ValueError, match=r"DockingEnv\.reset_to: pose must be finite"):
        env.reset_to([-1.0, 0.0, yaw])


def test_reset_to_takes_a_yaw_some_turns_beyond_pi():
    """A pose read back after turns (the hinge counts them) starts a trial as its heading."""
    turned, plain = DockingEnv(QUIET, seed=0), DockingEnv(QUIET, seed=0)
    a = turned.reset_to([-1.0, 0.1, 0.05 + 6 * np.pi]).observation
    b = plain.reset_to([-1.0, 0.1, 0.05]).observation
    np.testing.assert_allclose(a, b, atol=1e-6)


def _wall_faces(env) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each wall's inner face, read from the compiled model's placed geoms: ``(a point at the
    middle of the face, the unit normal into the room)``, on the floor plane."""
    model, data = env.physics.model, env.physics.data
    walls = [f"wall_{side}" for side in ("front", "back", "left", "right")]
    centres = {w: np.array(data.geom(w).xpos[:2]) for w in walls}
    middle = np.mean(list(centres.values()), axis=0)
    faces = []
    for w in walls:
        rot = np.array(data.geom(w).xmat).reshape(3, 3)[:2, :2]
        size = np.array(model.geom(w).size[:2])
        thin = int(np.argmin(size))  # the wall's thickness is its thinnest axis on the floor
        normal = rot[:, thin] * np.sign(rot[:, thin] @ (middle - centres[w]))
        faces.append((centres[w] + normal * size[thin], normal))
    return faces


@pytest.mark.parametrize(
    "shift", [(0.0, 0.0, 0.0), (0.0, -0.6, 0.0), (-1.75, 1.375, 90.0), (0.3, 0.2, -30.0)]
)
@pytest.mark.parametrize("room", ["home", "second"])
def test_the_rooms_bounds_are_its_compiled_walls_less_the_robots_radius(room, shift):
    """A pose the robot's radius plus 1 mm inside a wall's face starts a trial; 1 mm less is
    refused, for every wall of the room wherever it is placed."""
    env = DockingEnv(WorldConfig(room=room, room_shift=shift), seed=0)
    radius = scene_facts().robot_radius
    for face, normal in _wall_faces(env):
        x, y = face + normal * (radius + 1e-3)
        env.reset_to([x, y, 0.0])
        x, y = face + normal * (radius - 1e-3)
        with pytest.raises(ValueError, match="inside the room"):
            env.reset_to([x, y, 0.0])
    env.close()


@pytest.mark.parametrize(
    "kwargs, says",
    [
        ({"margin": np.nan}, "margin must be finite"),
        ({"margin": "a"}, "margin must be a real number"),
        ({"margin": -1.0}, "margin must be in"),
        ({"pose": [np.nan, 0.0, 0.0]}, "pose must be finite"),
        ({"pose": "abc"}, r"pose must be \[x, y, yaw\]"),
        ({"pose": [0.0, 0.0]}, r"pose must be \[x, y, yaw\]"),
    ],
)
def test_landmark_in_crop_refuses_a_bad_pose_or_margin(env, kwargs, says):
    with pytest.raises((ValueError, TypeError), match=r"DockingEnv\.landmark_in_crop.*" + says):
        env.landmark_in_crop(**kwargs)


@pytest.mark.parametrize("config", ["sideboard", {}, CameraConfig()], ids=["str", "dict", "camera"])
def test_docking_env_refuses_a_config_that_is_no_world_config(config):
    with pytest.raises(TypeError, match=r"DockingEnv\.config must be a WorldConfig, got"):
        DockingEnv(config)
