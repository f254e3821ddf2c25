"""What the figures and the reports compute from runs' arrays, as functions that return arrays:
nothing here renders, replays the world or runs a network's training.

Analysis is kept apart from drawing (rliable's way): every function here takes networks,
trial logs, results or arrays and returns numbers and arrays; :mod:`docking.study.figures`
takes those arrays and returns a figure; the caller (a notebook, a design's report) saves it.
What needs the world (a rendered view, the oracle's views, the scene's compiled floor plan, a
landmark's projection) is :mod:`docking.study.analysis`, which builds on this module; the
figures and the reports import this one only (an import contract of ``pyproject.toml``).

* Weights: :func:`receptive_fields`, :func:`best_actions`, :func:`strongest_units`.
* Decisions: :func:`decide` (one observation), :func:`decisions` (many), :func:`winner_change`.
* What a replay returns: :class:`ExampleViews`, :class:`MeanInputs`, :class:`OracleViews`,
  :class:`Ambiguity`; the example poses :data:`VIEW_POSES`.
* A trial log's columns: :func:`final_poses`, :func:`path_lengths`,
  :func:`docked_heading_error_deg`, :func:`actions_per_docking`.
* Trials: :func:`sample_trials`, :func:`trajectory_sample`, :data:`FAILURE_CLASSES` (the
  failure taxonomy's classes), :func:`rewarded_share`.
* Learning curves: :func:`mean_curve`, :func:`learning_curves`; :func:`trials_to_level`.
* Grids and views: :func:`landscape`, :func:`share_near_best`, :func:`centroid_rows`.
"""

from __future__ import annotations

import dataclasses
import warnings
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from docking import arith
from docking.camera import CameraConfig
from docking.network import Network
from docking.scene import ACTION_LETTERS

if TYPE_CHECKING:  # the run's types: a run is read here, never computed
    from docking.experiments import ExperimentConfig, ExperimentResult, TrialLog

__all__ = [
    "Ambiguity",
    "Decisions",
    "ExampleViews",
    "FAILURE_CLASSES",
    "Landscape",
    "LearningCurves",
    "MASS_PARTS",
    "MeanInputs",
    "OracleViews",
    "TrajectorySample",
    "VIEW_POSES",
    "actions_per_docking",
    "best_actions",
    "centroid_rows",
    "decide",
    "decisions",
    "docked_heading_error_deg",
    "final_poses",
    "landscape",
    "learning_curves",
    "mean_curve",
    "path_lengths",
    "receptive_fields",
    "rewarded_share",
    "sample_trials",
    "share_near_best",
    "strongest_units",
    "trajectory_sample",
    "trials_to_level",
    "winner_change",
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
# What a replay of the world returns (docking.study.analysis computes them).
# ------------------------------------------------------------------------------------------


class ExampleViews(NamedTuple):
    """Camera frames and network inputs at named poses."""

    names: tuple[str, ...]
    poses: np.ndarray  # (n, 3): [x, y, yaw]
    frames: np.ndarray  # (n, height, width, 3) uint8 RGB
    inputs: np.ndarray  # (n, rows, cols) float32 in [0, 1]


class MeanInputs(NamedTuple):
    """Mean network inputs per greedy action and per winning feature unit (zeros where an
    action is never chosen or a unit never wins), with the numbers of views behind them."""

    action_mean: np.ndarray  # (n_actions, rows, cols)
    unit_mean: np.ndarray  # (n_features, rows, cols)
    action_counts: np.ndarray  # (n_actions,) int64
    unit_counts: np.ndarray  # (n_features,) int64


class OracleViews(NamedTuple):
    """Views ``(n, inputs)`` and the pose oracle's action at each ``(n,)``."""

    views: np.ndarray
    actions: np.ndarray


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


#: The parts of a view that :func:`weight_mass` tells apart.
MASS_PARTS = ("landmark", "distractor", "background")


# ------------------------------------------------------------------------------------------
# A trial log's columns.
# ------------------------------------------------------------------------------------------


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


# ------------------------------------------------------------------------------------------
# Grids of settings and views' centroids.
# ------------------------------------------------------------------------------------------


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
