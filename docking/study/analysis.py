"""What the figures and the notebooks compute, as functions that return arrays.

Analysis is kept apart from drawing (rliable's way): every function here takes networks,
results, trial logs or an environment and returns numbers and arrays; :mod:`docking.study.figures`
takes those arrays and returns a figure; the caller (a notebook or :mod:`docking.study.report`)
saves it. Nothing here draws or writes files.

* Weights: :func:`receptive_fields`, :func:`best_actions`, :func:`strongest_units`,
  :func:`feature_change`.
* Decisions: :func:`decide` (one observation), :func:`decisions` (many).
* Views: :data:`VIEW_POSES`, :func:`example_views` (frames and inputs at given poses),
  :func:`overview` (a render of the room), :func:`mean_winning_inputs` (what the units
  respond to over many start views).
* Trials: :func:`sample_trials`, :func:`trajectory_sample`, :func:`failure_taxonomy`.
* Learning curves: :func:`mean_curve`, :func:`learning_curves`.
* Geometry for floor plans: :func:`floor_plan`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import warnings
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from docking import arith
from docking.camera import CameraConfig
from docking.experiments import ExperimentConfig, ExperimentResult, TrialLog, initial_network
from docking.network import Network
from docking.scene import (
    ACTION_LETTERS,
    LEFT,
    RIGHT,
    TURN_LEFT,
    TURN_RIGHT,
    WorldConfig,
    in_dock,
    in_region,
    scene_facts,
)

if TYPE_CHECKING:  # the task renders (OpenGL): imported where a function needs it
    from docking.world import DockingEnv

__all__ = [
    "feature_fidelity",
    "trials_to_level",
    "rewarded_share",
    "VIEW_POSES",
    "FAILURE_CLASSES",
    "ExampleViews",
    "Decisions",
    "MeanInputs",
    "TrajectorySample",
    "LearningCurves",
    "receptive_fields",
    "best_actions",
    "strongest_units",
    "feature_change",
    "decide",
    "decisions",
    "example_views",
    "overview",
    "mean_winning_inputs",
    "sample_trials",
    "trajectory_sample",
    "mean_curve",
    "learning_curves",
    "floor_plan",
    "failure_taxonomy",
]

#: Robot poses ``[x, y, yaw]`` of the three example views (Fig. 2 D, Fig. 3 top): to the left
#: of, in front of and to the right of the landmark, 0.68 m from its front plane (inside
#: Experiment 1's start region, 0.58-0.70 m) and 0.15 m to the side (near the edge of the start
#: trapezoid, whose half-width there is ``StartRegion.half_width(0.68)`` = 0.17 m). The robot
#: faces +x and its left is +y, so a robot standing *left of* the landmark is at +y and sees
#: the landmark on the right of its image; it has to step right to dock.
VIEW_POSES = {
    "left": (-0.68, 0.15, 0.0),
    "front": (-0.68, 0.0, 0.0),
    "right": (-0.68, -0.15, 0.0),
}


# ------------------------------------------------------------------------------------------
# Weights.
# ------------------------------------------------------------------------------------------


def receptive_fields(net: Network, shape=None) -> tuple[np.ndarray, np.ndarray]:
    """The receptive fields of the action and the feature units, as images.

    * Feature unit ``j``: its weight row ``W_j`` (Eq. 1), reshaped to the input image.
    * Action unit ``i``: its action weights mapped back into input space through the feature
      layer, ``RF_i = sum_j Q_ij W_j`` (i.e. the rows of ``Q @ W``). With a winner-take-all
      feature layer (``s`` nearly one-hot) an input that matches ``W_j`` drives action ``i``
      with ``Q_ij``, so ``RF_i`` shows which inputs favour action ``i``.

    Args:
      net: A network (``W``: features x inputs, ``Q``: actions x features).
      shape: ``(rows, cols)`` of the input image; default the camera's 32x10 input
        (``CameraConfig().input_shape``). Inputs are flattened row-major (``Network.prepare``).

    Returns:
      ``(action_rf, feature_rf)`` of shapes ``(n_actions, rows, cols)`` and
      ``(n_features, rows, cols)``, in action index order (``ACTION_LETTERS``) and unit order.
    """
    shape = tuple(CameraConfig().input_shape if shape is None else shape)
    if int(np.prod(shape)) != net.W.shape[1]:
        raise ValueError(f"shape {shape} does not hold the network's {net.W.shape[1]} inputs")
    action_rf = arith.matmul(net.Q, net.W).reshape(-1, *shape)
    feature_rf = net.W.reshape(-1, *shape)
    return action_rf, feature_rf


def best_actions(Q: np.ndarray) -> np.ndarray:
    """Per feature unit ``j``, the action it votes for most, ``argmax_i Q_ij``; -1 for a unit
    with no positive action weight (an unused unit). Shape ``(n_features,)``."""
    Q = np.asarray(Q)
    best = np.argmax(Q, axis=0).astype(np.int64)
    best[np.max(Q, axis=0) <= 0] = -1
    return best


def strongest_units(Q: np.ndarray, letters: str = "LRF") -> dict[int, list[str]]:
    """For each action in ``letters``, the feature unit with the largest action weight
    (``argmax_j Q_ij``), as ``{unit: [letters]}``; an action no unit votes for (all
    ``Q_ij <= 0``) has no strongest unit."""
    framed: dict[int, list[str]] = {}
    for letter in letters:
        i = ACTION_LETTERS.index(letter)
        if np.max(Q[i]) > 0:
            framed.setdefault(int(np.argmax(Q[i])), []).append(letter)
    return framed


def feature_change(result: ExperimentResult) -> np.ndarray:
    """Per feature unit, the cosine between its initial and final weight vector (1 = the
    unit's receptive field did not change). Rows of W have unit length, so the cosine is the
    dot product. Shape ``(n_features,)``."""
    start = initial_network(result.config, result.seed).W
    return np.einsum("jn,jn->j", start, result.network.W)


# ------------------------------------------------------------------------------------------
# Decisions.
# ------------------------------------------------------------------------------------------


class Decisions(NamedTuple):
    """Per observation: the winning feature unit (``argmax_j s_j``, Eq. 2), its activation
    ``s_j`` and the greedy action (``argmax_i h_i``, Eq. 3)."""

    winners: np.ndarray  # int64
    activations: np.ndarray  # float64
    actions: np.ndarray  # int64


def decide(net: Network, observation: np.ndarray) -> tuple[int, float, int]:
    """The winning feature unit, its activation ``s_j`` and the greedy action (argmax of
    Eq. 3) for one ``observation``."""
    s = net.features(net.prepare(observation))
    winner = int(np.argmax(s))
    return winner, float(s[winner]), int(np.argmax(arith.matvec(net.Q, s)))


def decisions(net: Network, observations) -> Decisions:
    """:func:`decide` for each of ``observations`` (a sequence or an array with one
    observation per leading index)."""
    rows = [decide(net, obs) for obs in observations]
    winners, activations, actions = zip(*rows, strict=True) if rows else ((), (), ())
    return Decisions(
        np.array(winners, dtype=np.int64),
        np.array(activations, dtype=np.float64),
        np.array(actions, dtype=np.int64),
    )


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


def winner_change(start: Network, end: Network, views) -> tuple[float, float]:
    """What learning W changed: over ``views``, the fraction whose winning feature unit
    (argmax of Eq. 2) differs between the network ``start`` (W before training) and ``end``
    (after), and the fraction whose greedy action differs when ``end``'s Q reads the
    features of either W. A measure of the partition of image space the units draw, where a
    cosine between the weights says little: at beta_s = 100 a tiny change of W moves the
    boundaries between units."""
    before = decisions(Network.from_weights(end.config, start.W, end.Q), views)
    after = decisions(end, views)
    return float(np.mean(before.winners != after.winners)), float(
        np.mean(before.actions != after.actions)
    )


# ------------------------------------------------------------------------------------------
# Views.
# ------------------------------------------------------------------------------------------


class ExampleViews(NamedTuple):
    """Camera frames and network inputs at named poses."""

    names: tuple[str, ...]
    poses: np.ndarray  # (n, 3): [x, y, yaw]
    frames: np.ndarray  # (n, height, width, 3) uint8 RGB
    inputs: np.ndarray  # (n, rows, cols) float32 in [0, 1]


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


class MeanInputs(NamedTuple):
    """Mean network inputs per greedy action and per winning feature unit (zeros where an
    action is never chosen or a unit never wins), with the numbers of views behind them."""

    action_mean: np.ndarray  # (n_actions, rows, cols)
    unit_mean: np.ndarray  # (n_features, rows, cols)
    action_counts: np.ndarray  # (n_actions,) int64
    unit_counts: np.ndarray  # (n_features,) int64


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


def final_poses(log: TrialLog) -> np.ndarray:
    """The final pose of every trial of ``log``, ``(n, 3)`` (a results table's column where
    the log is read from one)."""
    if log.poses is None:
        return log.require(log.ends, "the trials' final poses")
    return log.poses[np.cumsum(log.steps + 1) - 1] if len(log) else np.zeros((0, 3))


def path_lengths(log: TrialLog) -> np.ndarray:
    """The distance the reference point walked in each trial of ``log`` (m; the sum of its
    steps' displacements; a results table's column where the log is read from one)."""
    if log.poses is None:
        return log.require(log.lengths, "the trials' path lengths")
    steps = np.linalg.norm(np.diff(log.poses[:, :2], axis=0), axis=1)
    ends = np.cumsum(log.steps + 1)
    walked = np.concatenate([[0.0], np.cumsum(steps)])
    return walked[ends - 1] - walked[ends - 1 - log.steps]


def docked_heading_error_deg(log: TrialLog) -> float:
    """The mean absolute heading error (deg; :func:`docking.scene.heading_error`, against
    facing the landmark) at the end of the docked trials of ``log`` (NaN if none docked)."""
    from docking.scene import heading_error

    ends = final_poses(log)[np.asarray(log.success, dtype=bool)]
    if not len(ends):
        return float("nan")
    return float(np.mean([abs(np.degrees(heading_error(p))) for p in ends]))


def actions_per_docking(log: TrialLog) -> float:
    """The mean number of actions of the docked trials of ``log`` (NaN if none docked)."""
    docked = np.asarray(log.steps)[np.asarray(log.success, dtype=bool)]
    return float(np.mean(docked)) if len(docked) else float("nan")


# ------------------------------------------------------------------------------------------
# Trials.
# ------------------------------------------------------------------------------------------


def sample_trials(success: np.ndarray, n: int, seed: int = 0, min_failures: int = 3) -> np.ndarray:
    """A seeded random sample of ``n`` trial indices that represents the success rate but
    shows failures when there are any: failures get ``round(n * failure rate)`` places, at
    least ``min(min_failures, failures)``. Sorted indices; fewer if there are fewer trials."""
    success = np.asarray(success, dtype=bool)
    rng = np.random.default_rng(seed)
    fails, oks = np.flatnonzero(~success), np.flatnonzero(success)
    n = min(n, len(success))
    n_fail = int(round(n * len(fails) / max(len(success), 1)))
    n_fail = min(len(fails), max(n_fail, min(min_failures, len(fails), n)))
    n_ok = min(n - n_fail, len(oks))
    n_fail = min(len(fails), n - n_ok)
    chosen = np.concatenate(
        [rng.choice(fails, n_fail, replace=False), rng.choice(oks, n_ok, replace=False)]
    ).astype(np.int64)
    return np.sort(chosen)


class TrajectorySample(NamedTuple):
    """Some trials of a log: their indices, their poses and whether each docked, plus the
    totals of the whole log."""

    indices: np.ndarray  # (k,) int64, sorted
    paths: list[np.ndarray]  # k arrays (steps + 1, 3)
    success: np.ndarray  # (k,) bool
    n_trials: int  # trials in the log
    n_docked: int  # docked trials in the log


def trajectory_sample(log: TrialLog, n: int = 30, seed: int = 0) -> TrajectorySample:
    """``n`` trials of ``log`` chosen by :func:`sample_trials` (seeded; failures shown if there
    are any), with their paths."""
    chosen = sample_trials(log.success, n, seed)
    return TrajectorySample(
        chosen,
        [log.trial_poses(k) for k in chosen],
        np.asarray(log.success)[chosen].astype(bool),
        len(log),
        int(np.sum(log.success)),
    )


#: The failure classes of :func:`failure_taxonomy`, with the definition of each (the numbers
#: are the function's defaults).
FAILURE_CLASSES = {
    "heading_drift": "the heading drifted beyond heading_deg (10 deg) from facing the landmark's "
    "wall (yaw 0) at some pose of the trial",
    "landmark_lost": "at some pose after the start the landmark left the crop rectangle "
    "(DockingEnv.landmark_in_crop(pose, margin=0), a projection, no rendering)",
    "ended_farther": "the trial ended farther from the docking region's centre than it started",
    "oscillating": "at least min_reversals (2) immediate reversals of a sidestep (L then R, or "
    "R then L, as consecutive actions) or of a turn (TL then TR, or TR then TL)",
    "timed_out_near": "the step limit ended the trial within near_m (10 cm) of the docking "
    "region (distance of the reference point to the region's rectangle)",
    "pressed_beside_dock": "the trial ended against the sideboard's front (the floor scene: the "
    "landmark's front) (within contact_tol, "
    "2 cm, of where the robot's body meets it) beside the docking region (|y| > half its width)",
    "heading_off_in_region": "(precision docking only) at some pose of the trial the reference "
    "point was in the docking region but the heading outside the tolerance, and the trial did "
    "not dock",
}


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


def rewarded_share(runs: list[ExperimentResult], beyond: float = 0.0) -> np.ndarray:
    """Per run, the share of its training trials that started more than ``beyond`` m from
    the landmark's front plane and ended in the dock (NaN if none started there). Every trial
    starts at least the world's ``start_near`` (0.45 m or more) from it, so for ``beyond``
    below half of that it is every trial, and the start poses are not read."""
    out = []
    for r in runs:
        if beyond < r.config.world.start_near / 2:
            far = np.ones(len(r.train.success), dtype=bool)
        else:
            far = -r.train.starts[:, 0] > beyond
        out.append(float(np.mean(r.train.success[far])) if far.any() else float("nan"))
    return np.array(out)


# ------------------------------------------------------------------------------------------
# Learning curves.
# ------------------------------------------------------------------------------------------


def mean_curve(xs: list[np.ndarray], ys: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Mean over runs at the learning-curve points all runs share (NaNs ignored; a point with
    no value in any run stays NaN). Returns ``(points, mean)``."""
    common = xs[0]
    for x in xs[1:]:
        common = np.intersect1d(common, x)
    stack = np.array(
        [[y[np.flatnonzero(x == c)[0]] for c in common] for x, y in zip(xs, ys, strict=True)],
        dtype=np.float64,
    )
    with warnings.catch_warnings():  # an all-NaN column (no success anywhere) stays NaN
        warnings.simplefilter("ignore", RuntimeWarning)
        mean = np.nanmean(stack, axis=0)
    return common, mean


@dataclasses.dataclass(frozen=True)
class LearningCurves:
    """The learning curves of several seeds of one configuration, and their means.

    Per seed (lists, one entry per run): ``trials`` (training trials done at each point),
    ``success`` (greedy test success there), ``steps`` (mean actions of the successful test
    trials there), ``rewarded`` (rewarded training trials so far there), ``start_far`` (the
    start region's far edge in each training trial); ``final_trials`` and ``final_success``
    (the final test). Means over the seeds at their shared points: ``mean_trials``,
    ``mean_success``, ``mean_steps``.
    """

    config: ExperimentConfig
    seeds: tuple[int, ...]
    trials: list[np.ndarray]
    success: list[np.ndarray]
    steps: list[np.ndarray]
    rewarded: list[np.ndarray]
    start_far: list[np.ndarray]
    final_trials: np.ndarray
    final_success: np.ndarray
    mean_trials: np.ndarray
    mean_success: np.ndarray
    mean_steps: np.ndarray


def learning_curves(results: list[ExperimentResult]) -> LearningCurves:
    """:class:`LearningCurves` of the runs of one configuration (all of ``results`` must have
    been made with the same configuration)."""
    results = list(results)
    if not results:
        raise ValueError("learning_curves needs at least one result")
    if any(r.config != results[0].config for r in results):
        raise ValueError("learning_curves needs results of one configuration")
    xs = [r.curve_trials for r in results]
    mean_trials, mean_success = mean_curve(xs, [r.curve_success for r in results])
    _, mean_steps = mean_curve(xs, [r.curve_steps for r in results])
    return LearningCurves(
        config=results[0].config,
        seeds=tuple(r.seed for r in results),
        trials=xs,
        success=[r.curve_success for r in results],
        steps=[r.curve_steps for r in results],
        rewarded=[r.curve_rewarded for r in results],
        start_far=[np.asarray(r.train.start_far) for r in results],
        final_trials=np.array([r.config.train_trials for r in results], dtype=np.int64),
        final_success=np.array([r.test.success_rate for r in results], dtype=np.float64),
        mean_trials=mean_trials,
        mean_success=mean_success,
        mean_steps=mean_steps,
    )


# ------------------------------------------------------------------------------------------
# Sample efficiency.
# ------------------------------------------------------------------------------------------


def trials_to_level(runs: list[ExperimentResult], level: float) -> np.ndarray:
    """Per run, the training trials at the first learning-curve point whose greedy success
    is at least ``level`` (NaN if none is): a run's sample efficiency."""
    if not 0 < level <= 1:
        raise ValueError(f"level must be in (0, 1], got {level}")
    out = []
    for r in runs:
        if len(r.curve_trials) == 0:
            raise ValueError(f"run {r.config.name} seed {r.seed} has no learning curve")
        hits = np.flatnonzero(r.curve_success >= level)
        out.append(float(r.curve_trials[hits[0]]) if len(hits) else np.nan)
    return np.array(out)


class Ambiguity(NamedTuple):
    """What one 32x10 input cannot tell apart (:func:`ambiguous_views`): of ``views`` start
    views, ``shared`` have an input that at least one other start view has too;
    ``ambiguous`` are in such a group whose poses the pose oracle answers with different
    actions (no policy of the input alone can act as the oracle on all of them); ``groups``
    holds the poses (``(m, 3)``) of each such group."""

    views: int
    shared: int
    ambiguous: int
    groups: tuple[np.ndarray, ...]


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


#: The parts of a view that :func:`weight_mass` tells apart.
MASS_PARTS = ("landmark", "distractor", "background")


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


class OracleViews(NamedTuple):
    """Views ``(n, inputs)`` and the pose oracle's action at each ``(n,)``."""

    views: np.ndarray
    actions: np.ndarray


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


class Landscape(NamedTuple):
    """Success over a grid of two knobs (:func:`landscape`): ``mean[i, j]`` the mean held-out
    success (fraction) of the setting ``(rows[i], cols[j])`` over its runs (NaN: none),
    ``n[i, j]`` its runs."""

    rows: np.ndarray
    cols: np.ndarray
    mean: np.ndarray
    n: np.ndarray


def landscape(scores: dict[tuple[float, float], list[float]], rows, cols) -> Landscape:
    """The grid of ``scores`` (``{(row value, column value): per-run success}``) over the
    knob values ``rows`` x ``cols``; a setting of ``scores`` off the grid is left out."""
    rows, cols = np.asarray(rows, dtype=np.float64), np.asarray(cols, dtype=np.float64)
    mean = np.full((len(rows), len(cols)), np.nan)
    n = np.zeros((len(rows), len(cols)), dtype=np.int64)
    for (r, c), found in scores.items():
        i, j = np.flatnonzero(np.isclose(rows, r)), np.flatnonzero(np.isclose(cols, c))
        if len(i) and len(j) and len(found):
            mean[i[0], j[0]], n[i[0], j[0]] = float(np.mean(found)), len(found)
    return Landscape(rows, cols, mean, n)


def share_near_best(means, margin: float = 0.05) -> tuple[int, int]:
    """``(k, n)``: of ``n`` settings' mean success ``means``, the ``k`` within ``margin`` of
    the best (the best among them counts)."""
    values = np.asarray(list(means), dtype=np.float64)
    if not len(values):
        return 0, 0
    return int(np.sum(values >= values.max() - margin)), len(values)


def centroid_rows(views) -> np.ndarray:
    """Each view's centroid row (``(n, rows, cols)`` network inputs): the mean row index of
    its pixels weighted by their intensity (NaN for an empty view)."""
    views = np.asarray(views, dtype=np.float64)
    rows = np.arange(views.shape[1], dtype=np.float64)
    mass = views.sum(axis=(1, 2))
    weighted = np.einsum("nrc,r->n", views, rows)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(mass > 0, weighted / mass, np.nan)


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
