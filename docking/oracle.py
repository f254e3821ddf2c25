"""A scripted policy that reads the robot's ground-truth pose.

It is not part of the paper. It proves that the docking task, with this world's step sizes,
noise and 25-step budget, is solvable, and it bounds what a learner that sees only pixels can
reach: the learner's success rate is judged against the oracle's. Running it is
:func:`docking.policies.oracle` (with :func:`docking.policies.run_oracle_trial`).
"""

from __future__ import annotations

import numpy as np

from docking.scene import (
    BACKWARD,
    FORWARD,
    LEFT,
    RIGHT,
    TURN_LEFT,
    TURN_RIGHT,
    WorldConfig,
    heading_error,
    in_dock,
    in_region,
)


def oracle_vector(pose, config: WorldConfig) -> np.ndarray:
    """The oracle's continuous action at ``pose`` (``config.continuous``): the step that
    aims the reference point at the docking region's centre, each component the needed
    displacement in the body frame over the longest step (``step_forward``,
    ``step_side``) and clipped to [-1, 1]; with a turn component, the turn that faces the
    landmark (its heading error over ``turn_deg``, clipped). Each component is bounded
    alone, so a diagonal step may be longer than either limit (Nao's walk bounds the step
    jointly; our choice, the one the discrete sets imply)."""
    x, y, yaw = pose
    dx, dy = -config.dock_center - x, -y
    ahead = np.cos(yaw) * dx + np.sin(yaw) * dy
    left = -np.sin(yaw) * dx + np.cos(yaw) * dy
    step = [ahead / config.step_forward, left / config.step_side]
    if len(config.action_names) > 2:
        step.append(-heading_error(pose) / np.radians(config.turn_deg))
    return np.clip(np.array(step, dtype=np.float64), -1.0, 1.0)


def oracle_action(pose, config: WorldConfig) -> int:
    """The oracle's action at ``pose``: sidestep while the docking region's centre is more
    than a quarter of the region's width (at least half a sidestep) to the side, otherwise
    step forward (or back, after
    an overshoot) towards the region's centre. Errors are taken in the robot's body frame,
    so heading drift is accounted for. Aiming at the region's inner half, rather than its
    centre line, leaves room for the drift of the forward steps without wasting sidesteps.

    With the turning action set it first turns towards facing the landmark whenever the
    heading is farther from it than one turn (:func:`~docking.world.heading_error` beyond
    ``turn_deg``: a turn then cannot overshoot to the other side), and, with precision
    docking, whenever its reference point is in the region but its heading outside the
    tolerance. (Turning at half a turn, whenever a turn brings the heading closer, spends so
    many of the 25 actions on turns at 8 deg heading noise that it docks less often.)"""
    x, y, yaw = pose
    if config.actions == "turning":
        error = heading_error(pose)
        must_turn = abs(error) > np.radians(config.turn_deg)
        if config.dock_heading_deg is not None and not must_turn:
            must_turn = in_region(pose, config) and not in_dock(pose, config)
        if must_turn:
            return TURN_RIGHT if error > 0 else TURN_LEFT
    dx, dy = -config.dock_center - x, -y
    ahead = np.cos(yaw) * dx + np.sin(yaw) * dy
    left = -np.sin(yaw) * dx + np.cos(yaw) * dy
    # A quarter of the region's width, but never less than half a sidestep: a sidestep must be
    # able to land within the tolerance, or the oracle would step to and fro around it.
    tolerance = max(config.dock_width / 4, config.step_side / 2)
    if abs(left) > tolerance:
        return LEFT if left > 0 else RIGHT
    return FORWARD if ahead > 0 else BACKWARD
