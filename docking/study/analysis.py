"""What the study computes by replaying the world or a run's code: rendered views, the pose
oracle's views, the scene's compiled floor plan, the landmark's projection, held-out trials
of a changed network; as functions that return arrays.

Analysis is kept apart from drawing (rliable's way): every function here takes networks,
results, trial logs, worlds or an environment and returns numbers and arrays;
:mod:`docking.study.figures` takes those arrays and returns a figure; the caller (a notebook or
the command line) hands them to a design's report or a figure and saves it. Nothing here
draws or writes files. What needs no world is :mod:`docking.study.arrays`, which the figures
and the reports import instead of this module (the import contracts of ``pyproject.toml``):
a figure or a report takes what this module computes as arrays.

* Weights: :func:`feature_change`, :func:`start_fields` (against the network's random start).
* Views: :func:`example_views` (frames and inputs at given poses), :func:`overview` (a render
  of the room), :func:`start_views`, :func:`mean_winning_inputs` (what the units respond to
  over many start views), :func:`feature_fidelity`, :func:`weight_mass`,
  :func:`ambiguous_views`, :func:`view_shift`; the robot's walk: :func:`walking_poses`,
  :func:`furniture_contacts`.
* The floor plan: :func:`floor_plan` (the rectangles the figures draw a path on).
* Trials: :func:`failure_taxonomy`, :func:`landmark_lost`, :func:`failure_shares`.
* The representation against learning Q on it: :func:`oracle_views`, :func:`winners`,
  :func:`oracle_labelled`, :func:`partition_purity`, :func:`oracle_labelled_success`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import TYPE_CHECKING

import numpy as np

from docking import arith
from docking.experiments import ExperimentResult, initial_network
from docking.network import Network
from docking.scene import (
    LEFT,
    RIGHT,
    TURN_LEFT,
    TURN_RIGHT,
    WorldConfig,
    in_dock,
    in_region,
    scene_facts,
)
from docking.study.arrays import (
    FAILURE_CLASSES,
    MASS_PARTS,
    VIEW_POSES,
    Ambiguity,
    ExampleViews,
    MeanInputs,
    OracleViews,
    centroid_rows,
    receptive_fields,
)

if TYPE_CHECKING:  # the task renders (OpenGL): imported where a function needs it
    from docking.experiments import TrialLog
    from docking.world import DockingEnv

__all__ = [
    "ambiguous_views",
    "example_views",
    "failure_shares",
    "failure_taxonomy",
    "feature_change",
    "feature_fidelity",
    "floor_plan",
    "furniture_contacts",
    "landmark_lost",
    "mean_winning_inputs",
    "oracle_labelled",
    "oracle_labelled_success",
    "oracle_views",
    "overview",
    "partition_purity",
    "start_fields",
    "start_views",
    "view_shift",
    "walking_poses",
    "weight_mass",
    "winners",
]


# ------------------------------------------------------------------------------------------
# Weights.
# ------------------------------------------------------------------------------------------


def feature_change(result: ExperimentResult) -> np.ndarray:
    """Per feature unit, the cosine between its initial and final weight vector (1 = the
    unit's receptive field did not change). Rows of W have unit length, so the cosine is the
    dot product. Shape ``(n_features,)``."""
    start = initial_network(result.config, result.seed).W
    return np.einsum("jn,jn->j", start, result.network.W)


def start_fields(result: ExperimentResult) -> np.ndarray:
    """The feature units' receptive fields at ``result``'s random start (its W before
    training, ``docking.experiments.initial_network``), as images ``(n_features, rows,
    cols)`` (:func:`docking.study.arrays.receptive_fields`)."""
    start = initial_network(result.config, result.seed)
    return receptive_fields(start, result.config.world.camera.input_shape)[1]


# ------------------------------------------------------------------------------------------
# Views, and the robot's walk.
# ------------------------------------------------------------------------------------------


def furniture_contacts(world: WorldConfig, poses) -> np.ndarray:
    """Per pose of ``poses`` (``(n, 3)``: x, y, yaw), whether the robot placed there touches
    anything of the room but the floor (a contact of one of its geoms with a geom outside
    its body tree, MuJoCo's collision detection after ``mj_forward``)."""
    import mujoco

    from docking.world import DockingEnv

    poses = np.asarray(poses, dtype=np.float64)
    if poses.ndim != 2 or poses.shape[1] != 3:
        raise ValueError(f"poses must be (n, 3), got shape {poses.shape}")
    env = DockingEnv(world, seed=0)
    m, d = env.physics.model.ptr, env.physics.data.ptr
    robot, floor = m.body("robot").id, m.geom("floor").id

    def in_robot(geom: int) -> bool:
        body = int(m.geom_bodyid[geom])
        while body not in (0, robot):
            body = int(m.body_parentid[body])
        return body == robot

    found = []
    for pose in poses:
        env.physics.set_pose(pose)
        mujoco.mj_forward(m, d)
        pairs = [(int(c.geom1), int(c.geom2)) for c in d.contact[: d.ncon]]
        found.append(any(in_robot(a) != in_robot(b) and floor not in (a, b) for a, b in pairs))
    env.close()
    return np.array(found, dtype=bool)


def walking_poses(world: WorldConfig, n: int, seed: int = 0, points: int = 10) -> np.ndarray:
    """``(n * points, 3)`` poses of the robot's walk: ``n`` start poses of ``world``'s start
    region and ``points - 1`` more on the straight line from each to the docking region's
    centre, the start's heading kept."""
    from docking.world import DockingEnv

    env = DockingEnv(world, seed=seed)
    starts = []
    for _ in range(n):
        env.reset()
        starts.append(env.pose)
    env.close()
    dock = np.array([-world.dock_center, 0.0])
    found = []
    for start in starts:
        for t in np.linspace(0.0, 1.0, points):
            found.append([*((1 - t) * start[:2] + t * dock), start[2]])
    return np.array(found)


@functools.lru_cache(maxsize=8)
def start_views(world: WorldConfig, n: int, seed: int) -> np.ndarray:
    """``(n, rows, cols)`` network inputs at ``n`` start poses of ``world``'s start region
    (``DockingEnv(world, seed).reset()``, one rendered frame each), read-only: kept for the
    last few worlds asked for, since every network of a world is read on the same views."""
    from docking.world import DockingEnv

    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    env = DockingEnv(world, seed=seed)
    views = np.array([env.reset().observation for _ in range(n)])
    env.close()
    views.flags.writeable = False
    return views


def _check_views(poses) -> dict:
    poses = dict(VIEW_POSES if poses is None else poses)
    if len(poses) != 3:
        raise ValueError(f"poses must name three views, got {list(poses)}")
    return {name: np.asarray(p, dtype=np.float64) for name, p in poses.items()}


def example_views(env: DockingEnv, poses=None) -> ExampleViews:
    """The robot's camera frame and the network input at each of three named poses
    ``{name: [x, y, yaw]}`` (default :data:`VIEW_POSES`: left, front, right).

    The environment is moved to each pose in turn (``reset_to``), so a running trial is
    abandoned; it is left at the last pose."""
    poses = _check_views(poses)
    frames, inputs = [], []
    for pose in poses.values():
        timestep = env.reset_to(pose)
        frames.append(env.frame.copy())
        inputs.append(np.array(timestep.observation))
    return ExampleViews(
        tuple(poses), np.array(list(poses.values())), np.array(frames), np.array(inputs)
    )


def overview(env: DockingEnv, pose, size=(800, 600)) -> np.ndarray:
    """An RGB render ``(height, width, 3)`` of the room from the ``overview`` camera with the
    robot at ``pose`` and the virtual docking region drawn; ``size = (width, height)``."""
    env.reset_to(np.asarray(pose, dtype=np.float64))
    return env.render_view("overview", *size)


def _views_at(world: WorldConfig, poses: np.ndarray) -> np.ndarray:
    """The observations of ``world`` at each of ``poses``."""
    from docking.world import DockingEnv

    env = DockingEnv(world, seed=0)
    views = np.array([env.reset_to(p).observation for p in poses])
    env.close()
    return views


def mean_winning_inputs(
    net: Network, world: WorldConfig, n: int = 1500, seed: int = 0, poses=None
) -> MeanInputs:
    """What the units respond to: mean network inputs over ``n`` start views.

    Samples ``n`` start poses of ``world``'s start region (``DockingEnv(world, seed).reset()``,
    one rendered frame each) and averages the observations (the 10x32 input before Eq. 1)
    separately for every feature unit that wins (``argmax_j s_j``, Eq. 2) and for every greedy
    action (``argmax_i h_i``, Eq. 3). With ``poses`` (``(m, 3)``, e.g. every pose of logged
    trials) the views are those at ``poses`` instead, and ``n`` and ``seed`` are not used.
    """
    if poses is not None:
        poses = np.asarray(poses, dtype=np.float64)
        if poses.ndim != 2 or poses.shape[1] != 3 or len(poses) == 0:
            raise ValueError(f"poses must be a non-empty (m, 3) array, got shape {poses.shape}")
        views = _views_at(world, poses)
    elif n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    else:
        views = start_views(world, n, seed)
    shape = world.camera.input_shape
    n_act, n_feat = net.config.n_actions, net.config.n_features
    action_sum, unit_sum = np.zeros((n_act,) + shape), np.zeros((n_feat,) + shape)
    action_counts = np.zeros(n_act, dtype=np.int64)
    unit_counts = np.zeros(n_feat, dtype=np.int64)
    for obs in views:
        s = net.features(net.prepare(obs))
        j, i = int(np.argmax(s)), int(np.argmax(arith.matvec(net.Q, s)))
        unit_sum[j] += obs
        unit_counts[j] += 1
        action_sum[i] += obs
        action_counts[i] += 1
    with np.errstate(invalid="ignore", divide="ignore"):
        action_mean = np.nan_to_num(action_sum / action_counts[:, None, None])
        unit_mean = np.nan_to_num(unit_sum / unit_counts[:, None, None])
    return MeanInputs(action_mean, unit_mean, action_counts, unit_counts)


def feature_fidelity(net: Network, inputs: MeanInputs, min_views: int = 20) -> float:
    """How much each feature unit looks like what it responds to: the Pearson correlation
    of unit ``j``'s weights ``W_j`` with the mean input of the views it wins
    (``inputs.unit_mean[j]``, :func:`mean_winning_inputs`), averaged over the units that win
    at least ``min_views`` views (NaN if none does). The study's second edition measures
    "interpretable features" by it, learned W against frozen random W."""
    if min_views < 1:
        raise ValueError(f"min_views must be >= 1, got {min_views}")
    rs = []
    for j in np.flatnonzero(inputs.unit_counts >= min_views):
        w, x = net.W[j], inputs.unit_mean[j].reshape(-1)
        if np.ptp(w) == 0 or np.ptp(x) == 0:
            continue
        # Pearson's r, the same bits on every CPU (np.corrcoef's OpenBLAS products are not)
        a, b = w - math.fsum(w) / len(w), x - math.fsum(x) / len(x)
        rs.append(arith.dot(a, b) / math.sqrt(arith.dot(a, a) * arith.dot(b, b)))
    return math.fsum(rs) / len(rs) if rs else float("nan")


# ------------------------------------------------------------------------------------------
# The floor plan, and the failure taxonomy of trials.
# ------------------------------------------------------------------------------------------


def floor_plan(config: WorldConfig) -> dict[str, tuple[float, float, float, float]]:
    """Floor-plan rectangles ``(x0, y0, x1, y1)`` (m) of ``sideboard`` (if the scene has one),
    ``landmark_slab``,
    ``landmark_post`` and ``dock``, from :func:`docking.world.footprints`. The only place the
    analysis and the figures read the world's footprint keys."""
    from docking.world import footprints

    fp = footprints(config)
    names = ("sideboard",) if config.scene == "sideboard" else ()
    return {name: fp[name] for name in names + ("landmark_slab", "landmark_post", "dock")}


def _distance_to_rectangle(x, y, rect) -> np.ndarray:
    x0, y0, x1, y1 = rect
    dx = np.maximum(np.maximum(x0 - x, 0.0), x - x1)
    dy = np.maximum(np.maximum(y0 - y, 0.0), y - y1)
    return np.hypot(dx, dy)


class _CropCheck:
    """``DockingEnv.landmark_in_crop(pose, margin=0)`` for many poses: the same arithmetic on
    the same arrays (so the same bits), with the landmark's geoms and the robot's camera
    looked up once by index instead of by name at every pose (MuJoCo's accessors by name
    were most of its cost). A copy of ``Physics.landmark_corners`` and ``Physics.project``
    (a test holds them equal to the bit): ``docking/world.py`` is fingerprinted, and moving
    the lookup there would re-key every stored run; when that module next changes for its own
    reasons, it should take the lookup and this copy go."""

    _SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])

    def __init__(self, env: DockingEnv):
        self.physics, self.camera = env.physics, env.config.camera
        model = self.physics.model
        self.geoms = [model.geom(name).id for name in ("landmark_slab", "landmark_post")]
        self.eye = model.camera("eye").id

    def uv(self, pose) -> np.ndarray:
        """The landmark's 16 corners in pixels from ``pose`` (the robot is left there)."""
        physics, cam = self.physics, self.camera
        model, data = physics.model, physics.data
        physics.place(pose)
        # docking.world.Physics.landmark_corners
        corners = []
        for g in self.geoms:
            centre, rot = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3)
            corners.append(centre + arith.matmul(self._SIGNS * model.geom_size[g], rot.T))
        points = np.concatenate(corners)
        # docking.world.Physics.project
        rot = data.cam_xmat[self.eye].reshape(3, 3)
        local = arith.matmul(np.asarray(points) - data.cam_xpos[self.eye], rot)
        depth = -local[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            u = cam.width / 2 + cam.focal_px * local[:, 0] / depth
            v = cam.height / 2 - cam.focal_px * local[:, 1] / depth
        uv = np.stack([u, v], axis=1)
        uv[depth <= 1e-6] = np.nan
        return uv

    def __call__(self, pose) -> bool:
        """``DockingEnv.landmark_in_crop(pose, margin=0)`` (the robot is left at ``pose``)."""
        uv = self.uv(pose)
        # docking.world.DockingEnv.landmark_in_crop, margin 0
        x0, y0, x1, y1 = self.camera.crop
        return bool(
            np.all(np.isfinite(uv))
            and uv[:, 0].min() >= x0
            and uv[:, 0].max() <= x1
            and uv[:, 1].min() >= y0
            and uv[:, 1].max() <= y1
        )


def landmark_lost(env: DockingEnv, poses) -> bool:
    """Whether from some pose of ``poses`` (rows ``[x, y, yaw]``) the landmark is not wholly
    inside the crop rectangle: ``not env.landmark_in_crop(pose, margin=0)`` for some pose,
    bit for bit (:class:`_CropCheck`), stopping at the first."""
    check = _CropCheck(env)
    saved = check.physics.pose()
    try:
        return any(not check(pose) for pose in poses)
    finally:
        check.physics.place(saved)


def _taxonomy_geometry(config: WorldConfig) -> tuple[tuple, np.ndarray, float]:
    """The dock's rectangle, its centre, and the x at which the robot meets what stops it."""
    plan = floor_plan(config)
    dock = plan["dock"]
    dock_centre = np.array([-config.dock_center, 0.0])
    # The robot's reference point where its body meets what stops it in front of the landmark:
    # the sideboard's front, or in the floor scene the landmark's own front face.
    stop = plan["sideboard"] if "sideboard" in plan else plan["landmark_slab"]
    return dock, dock_centre, stop[0] - scene_facts().robot_radius


def _reversals(actions: np.ndarray) -> int:
    """How often an action is at once undone: a sidestep's or a turn's reverse follows it."""
    # Reversal pairs: sidesteps, and turns in a world that has them.
    pairs = [(LEFT, RIGHT), (RIGHT, LEFT), (TURN_LEFT, TURN_RIGHT), (TURN_RIGHT, TURN_LEFT)]
    a, b = actions[:-1], actions[1:]
    return sum(int(np.sum((a == p) & (b == q))) for p, q in pairs)


def failure_taxonomy(
    log: TrialLog,
    env: DockingEnv,
    heading_deg: float = 10.0,
    near_m: float = 0.10,
    min_reversals: int = 2,
    contact_tol: float = 0.02,
    trials=None,
) -> dict[str, np.ndarray]:
    """Classify the trials of ``log`` from their logged poses and actions.

    Returns ``{class: bool array over all trials}`` for the classes of
    :data:`FAILURE_CLASSES` (a trial may be in several). ``trials``: the indices of the
    trials to classify (e.g. the failures, ``np.flatnonzero(~log.success)``: only their poses
    are read, so a ledger need keep no others); default every trial, docked or not. Trials
    not classified are False in every class. ``env`` supplies the world's geometry and the
    landmark's projection (its pose is restored).
    """
    if not heading_deg > 0 or not near_m >= 0 or min_reversals < 1 or not contact_tol >= 0:
        raise ValueError(
            f"failure_taxonomy needs heading_deg > 0, near_m >= 0, min_reversals >= 1, "
            f"contact_tol >= 0; got {heading_deg}, {near_m}, {min_reversals}, {contact_tol}"
        )
    config = env.config
    dock, dock_centre, contact_x = _taxonomy_geometry(config)
    precise = config.dock_heading_deg is not None
    limit = np.radians(heading_deg)
    flags = {name: np.zeros(len(log), dtype=bool) for name in FAILURE_CLASSES}
    chosen = range(len(log)) if trials is None else np.asarray(trials, dtype=np.int64).tolist()
    if any(not 0 <= k < len(log) for k in chosen):
        raise ValueError(f"failure_taxonomy: trials must index the log's {len(log)} trials")
    for k in chosen:
        poses, actions = log.trial_poses(k), log.trial_actions(k)
        start, end = poses[0], poses[-1]
        flags["heading_drift"][k] = bool(np.any(np.abs(poses[:, 2]) > limit))
        flags["landmark_lost"][k] = landmark_lost(env, poses[1:])
        flags["ended_farther"][k] = bool(
            np.linalg.norm(end[:2] - dock_centre) > np.linalg.norm(start[:2] - dock_centre)
        )
        flags["oscillating"][k] = bool(_reversals(actions) >= min_reversals)
        timed_out = not log.success[k] and log.steps[k] >= config.max_steps
        flags["timed_out_near"][k] = bool(
            timed_out and _distance_to_rectangle(end[0], end[1], dock) <= near_m
        )
        flags["pressed_beside_dock"][k] = bool(
            end[0] >= contact_x - contact_tol and abs(end[1]) > config.dock_width / 2
        )
        flags["heading_off_in_region"][k] = bool(
            precise
            and not log.success[k]
            and any(in_region(pose, config) and not in_dock(pose, config) for pose in poses)
        )
    return flags


def failure_shares(
    results, keys: list[str], n_seeds: int | None = None
) -> tuple[np.ndarray, list[int]]:
    """The failure taxonomy (:func:`failure_taxonomy`) of the held-out failures of each cell
    in ``keys`` of a design's ``results``, its first ``n_seeds`` seeds (None: all) pooled:
    ``(shares, failures)`` with ``shares[k, c]`` the share of cell ``k``'s failed trials in
    class ``c`` (classes in the order of :data:`docking.study.arrays.FAILURE_CLASSES`; NaN for a
    cell without failures) and ``failures[k]`` its failed trials."""
    from docking.world import DockingEnv

    shares, failures = np.full((len(keys), len(FAILURE_CLASSES)), np.nan), []
    for k, key in enumerate(keys):
        env = DockingEnv(results.cell(key).config.world, seed=0)
        counts, n = np.zeros(len(FAILURE_CLASSES)), 0
        for log in results.logs[key][:n_seeds]:
            failed = ~log.success
            flags = failure_taxonomy(log, env, trials=np.flatnonzero(failed))
            n += int(failed.sum())
            counts += [int(flags[c][failed].sum()) for c in FAILURE_CLASSES]
        env.close()
        failures.append(n)
        if n:
            shares[k] = counts / n
    return shares, failures


# ------------------------------------------------------------------------------------------
# What one start view cannot tell apart; where the units put their weight.
# ------------------------------------------------------------------------------------------


def ambiguous_views(world: WorldConfig, n: int = 1500, seed: int = 0) -> Ambiguity:
    """Count the start views of ``world`` whose network input (the 10x32 observation, byte
    for byte) another start view shares while the pose oracle
    (:func:`docking.oracle.oracle_action`) acts differently at the two poses: the
    ambiguities that the paper's "population" coding "might be useful for resolving" (Sec.
    III). ``n`` start poses from ``DockingEnv(world, seed).reset()`` (every start view shows
    the landmark)."""
    from docking.oracle import oracle_action
    from docking.world import DockingEnv

    if n < 2:
        raise ValueError(f"ambiguous_views needs n >= 2 views, got {n}")
    env = DockingEnv(world, seed=seed)
    groups: dict[bytes, list[np.ndarray]] = {}
    for _ in range(n):
        obs = np.ascontiguousarray(env.reset().observation)
        groups.setdefault(obs.tobytes(), []).append(env.pose.copy())
    env.close()
    shared = sum(len(g) for g in groups.values() if len(g) > 1)
    mixed = tuple(
        np.array(g) for g in groups.values() if len({oracle_action(p, world) for p in g}) > 1
    )
    return Ambiguity(n, shared, sum(len(g) for g in mixed), mixed)


@functools.lru_cache(maxsize=4)
def _parted_views(world: WorldConfig, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` start views of ``world`` (with its distractors) and, per view, the landmark's
    part: the same pose's view without the distractors, where the view has it too."""
    from docking.world import DockingEnv

    env = DockingEnv(world, seed=seed)
    bare = DockingEnv(dataclasses.replace(world, distractors=()), seed=seed)
    views, landmark = [], []
    for _ in range(n):
        obs = env.reset().observation
        views.append(obs)
        landmark.append(np.minimum(bare.reset_to(env.pose).observation, obs))
    env.close()
    bare.close()
    views, landmark = np.array(views), np.array(landmark)
    views.flags.writeable = landmark.flags.writeable = False
    return views, landmark


def weight_mass(
    net: Network,
    world: WorldConfig,
    n: int = 1500,
    seed: int = 0,
    min_views: int = 20,
) -> np.ndarray:
    """Where the winning feature units put their weight: the shares of ``|W_j|`` on the
    landmark's pixels, the distractor's and the background's (:data:`MASS_PARTS`), averaged
    over the units that win at least ``min_views`` of ``n`` start views of ``world`` (the
    world with the distractor), weighted by the views each wins.

    A block of the 32x10 input is the landmark's in a view by its red fraction in the same
    world without its distractors, rendered at the same pose; the distractor's by what the
    distractors add; the rest is background. Per unit the parts are the means over
    the views it wins, so a unit's shares are ``sum |W_j| * part / sum |W_j|``. At W's random
    start the shares are the parts' areas; a unit that learns to neglect the distractor moves
    mass onto the landmark and off the distractor. NaN shares if no unit wins ``min_views``."""
    if n < 1 or min_views < 1:
        raise ValueError(f"weight_mass needs n >= 1 and min_views >= 1, got {n}, {min_views}")
    if not world.distractors:
        raise ValueError("weight_mass needs a world with a distractor (WorldConfig.distractors)")
    views, landmark = _parted_views(world, n, seed)
    shape = (net.config.n_features,) + world.camera.input_shape
    sums = {p: np.zeros(shape) for p in MASS_PARTS[:2]}
    counts = np.zeros(net.config.n_features, dtype=np.int64)
    for obs, mark in zip(views, landmark, strict=True):
        j = int(np.argmax(net.features(net.prepare(obs))))
        sums["landmark"][j] += mark
        sums["distractor"][j] += obs - mark
        counts[j] += 1
    units = np.flatnonzero(counts >= min_views)
    if not len(units):
        return np.full(len(MASS_PARTS), np.nan)
    weights = np.abs(net.W[units])  # (units, inputs)
    shares = []
    for part in MASS_PARTS[:2]:
        mean = (sums[part][units] / counts[units, None, None]).reshape(len(units), -1)
        shares.append((weights * mean).sum(axis=1) / weights.sum(axis=1))
    shares.append(1.0 - shares[0] - shares[1])
    return np.average(np.stack(shares, axis=1), axis=0, weights=counts[units])


# ------------------------------------------------------------------------------------------
# The representation against learning Q on it (the addendum's decomposition, notebook 08).
# ------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=4)
def oracle_views(world: WorldConfig, n_trials: int = 300, seed: int = 0) -> OracleViews:
    """Every view the pose oracle sees on ``n_trials`` trials of ``world`` (starts from its
    whole start region, ``DockingEnv(world, seed)``'s stream: none of a run's streams) and
    the action it takes there: the views a docking policy must tell apart, labelled by what
    works."""
    from docking.oracle import oracle_action
    from docking.world import DockingEnv

    env = DockingEnv(world, seed=seed)
    views, actions = [], []
    for _ in range(n_trials):
        timestep = env.reset()
        while not timestep.last():
            action = oracle_action(env.pose, world)
            views.append(np.array(timestep.observation, dtype=np.float64).reshape(-1))
            actions.append(action)
            timestep = env.step(action)
    env.close()
    found = OracleViews(np.array(views), np.array(actions, dtype=np.int64))
    found.views.flags.writeable = found.actions.flags.writeable = False
    return found


def winners(net: Network, views: np.ndarray) -> np.ndarray:
    """The winning feature unit of each view (the largest h_j of Eq. 1: the unit that the
    softmax of Eq. 2 at beta_s = 100 all but selects)."""
    inputs = np.array([net.prepare(v) for v in views])
    return np.argmax(inputs @ net.W.T, axis=1)


def oracle_labelled(net: Network, labelled: OracleViews) -> Network:
    """``net`` with its W and a Q that gives each feature unit the action the pose oracle
    takes most often on the views it wins (ties: the lower action index); a unit that wins
    none keeps its own best action. Greedy on W's partition, this is what the partition
    allows when each of its cells gets the best single action the oracle would choose."""
    won = winners(net, labelled.views)
    n_actions, n_features = net.Q.shape
    counts = np.zeros((n_features, n_actions), dtype=np.int64)
    np.add.at(counts, (won, labelled.actions), 1)
    labels = np.where(counts.sum(axis=1) > 0, counts.argmax(axis=1), net.Q.argmax(axis=0))
    Q = np.zeros_like(net.Q)
    Q[labels, np.arange(n_features)] = 1.0
    return Network.from_weights(net.config, net.W.copy(), Q)


def partition_purity(net: Network, labelled: OracleViews) -> float:
    """The share of ``labelled``'s views whose oracle action is their winning unit's most
    frequent one: 1 if W's partition never puts views the oracle acts on differently in one
    cell (aliasing lowers it)."""
    won = winners(net, labelled.views)
    n_features = net.W.shape[0]
    counts = np.zeros((n_features, int(labelled.actions.max()) + 1), dtype=np.int64)
    np.add.at(counts, (won, labelled.actions), 1)
    return float(counts.max(axis=1).sum() / len(won))


def oracle_labelled_success(
    run: ExperimentResult, labelled: OracleViews, world: WorldConfig | None = None
) -> float:
    """Held-out success of ``run``'s W with the oracle-labelled Q (:func:`oracle_labelled`),
    on ``run``'s own held-out streams (paired with its held-out success)."""
    from docking.experiments import heldout_trials

    world = world or run.config.world
    net = oracle_labelled(run.network, labelled)
    return heldout_trials(run.config, run.seed, net, world).success_rate


def view_shift(home: WorldConfig, place: WorldConfig, n: int = 300, seed: int = 0) -> np.ndarray:
    """Per start view (``n`` start poses of ``home``'s start region, rendered in ``home`` and
    in ``place``), how far the landmark moved in the network's input: the moved view's
    centroid row minus the home view's (:func:`centroid_rows`), in input rows (a row is a
    tenth of the input's height); views empty in either world left out."""
    from docking.world import DockingEnv

    env = DockingEnv(home, seed=seed)
    poses, views = [], []
    for _ in range(n):
        views.append(env.reset().observation)
        poses.append(env.pose)
    env.close()
    shift = centroid_rows(_views_at(place, np.array(poses))) - centroid_rows(views)
    return shift[np.isfinite(shift)]
