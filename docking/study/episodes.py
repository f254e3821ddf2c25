"""An episode as frames: one episode of the pose oracle in a world, rendered from the scene's
overview camera with the robot's input inset (what the site's page of the worlds animates).
It builds the world and runs it; :func:`docking.study.figures.episode_images` only draws the
frames it returns (captions, then an animated GIF, :func:`docking.study.figures.save_gif`).
"""

from __future__ import annotations

import numpy as np

from docking.scene import WorldConfig

__all__ = ["episode_frames"]


def episode_frames(
    world: WorldConfig,
    seed: int = 0,
    width: int = 320,
    height: int = 240,
    max_frames: int | None = None,
) -> tuple[list[np.ndarray], list[int], bool]:
    """One episode of the pose oracle (:func:`docking.oracle.oracle_action`) in ``world``
    from the start pose that ``seed`` draws, as RGB frames of the scene's ``overview`` camera
    (the robot and the yellow docking region drawn), one per pose: the start and each action's
    result, with the robot's thresholded input (what a learner sees) inset at the bottom
    right. Stops at the episode's end or after ``max_frames`` frames; also returns the actions
    taken (one fewer than the frames) and whether the robot docked."""
    from docking.oracle import oracle_action
    from docking.world import DockingEnv

    env = DockingEnv(world, seed=seed)
    _widen_overview(env.physics)
    timestep = env.reset()
    frames, actions = [], []
    while True:
        frame = env.render_view("overview", width, height)
        _inset(frame, np.asarray(timestep.observation))
        frames.append(frame)
        if timestep.last() or (max_frames is not None and len(frames) >= max_frames):
            return frames, actions, bool(env.docked)
        actions.append(oracle_action(env.pose, world))
        timestep = env.step(actions[-1])


#: The overview camera of the animations, further back and wider than the scene's (which
#: frames the dock for figures) so that the robot is in view from the farthest starts.
_ANIMATION_CAMERA = {"pos": (-2.1, -1.2, 1.4), "fovy": 58.0}


def _widen_overview(physics) -> None:
    """Move this ``physics``' overview camera to :data:`_ANIMATION_CAMERA` (its own compiled
    model: no other environment's, and not the robot's camera, which the observations use)."""
    import mujoco

    model = physics.model
    camera = mujoco.mj_name2id(model.ptr, mujoco.mjtObj.mjOBJ_CAMERA, "overview")
    model.cam_pos[camera] = _ANIMATION_CAMERA["pos"]
    model.cam_fovy[camera] = _ANIMATION_CAMERA["fovy"]


def _inset(frame: np.ndarray, observation: np.ndarray, scale: int = 3) -> None:
    """Draw the observation (a map in 0..1, strong dark) into ``frame``'s bottom-right corner,
    ``scale`` pixels per input, framed in grey."""
    image = np.repeat(np.repeat(observation, scale, 0), scale, 1)
    h, w = image.shape
    if h + 8 > frame.shape[0] or w + 8 > frame.shape[1]:
        return
    patch = (255 * (1.0 - np.clip(image, 0.0, 1.0))).astype(np.uint8)
    y, x = frame.shape[0] - h - 5, frame.shape[1] - w - 5
    frame[y - 1 : y + h + 1, x - 1 : x + w + 1] = 90
    frame[y : y + h, x : x + w] = patch[..., None]
