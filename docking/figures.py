"""The paper's figures, drawn from arrays: this module draws and does nothing else.

* :func:`fig2_scene` -- Fig. 2: the scene, the robot's camera view with the crop rectangle, the
  32x10 input; plus the views from the left of, in front of and to the right of the landmark.
* :func:`fig3` -- Fig. 3: Experiment 1's raw views, action and feature receptive fields.
* :func:`fig4` -- Fig. 4: Experiment 2's action and feature receptive fields, the feature
  units that contribute most to L, R and F framed in red.
* :func:`fig5` -- Fig. 5: sample test trajectories seen from above.
* :func:`fig_learning_curves` -- test success and steps during training (not in the paper).

Every figure function takes the arrays that :mod:`docking.analysis` computes (and
configurations for geometry and labels) and returns a :class:`matplotlib.figure.Figure`; it
renders nothing, runs no network and writes no file. The caller saves the figure with
:func:`save_figure` (``.png`` and ``.pdf``). The figures are drawn on matplotlib's Agg canvas
without pyplot, so the library never opens a window.

Conventions, as in the paper's captions: "Strong weights are displayed dark" -- every weight
or input image uses a reversed gray colormap (white = 0), without interpolation and with square
pixels, so a 32x10 field looks 32x10. Each receptive field is scaled from 0 to its own maximum
(written under it, so a weak field is not mistaken for a strong one; negative values, if any,
show white); network inputs use the fixed scale 0..1. Action fields are shown in the paper's
order L, R, F, B.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib import colormaps, patheffects
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Polygon, Rectangle

from docking.analysis import (
    Decisions,
    ExampleViews,
    LearningCurves,
    MeanInputs,
    TrajectorySample,
    best_actions,
    floor_plan,
)
from docking.camera import CameraConfig
from docking.experiments import ExperimentConfig
from docking.fileio import atomic_write
from docking.paths import figures_dir
from docking.region import StartRegion
from docking.world import ACTION_LETTERS, ROBOT_RADIUS, WorldConfig

__all__ = [
    "FIGURES_DIR",
    "PAPER_ACTION_ORDER",
    "fig2_scene",
    "fig3",
    "fig4",
    "fig5",
    "fig_learning_curves",
    "draw_floor_plan",
    "draw_trajectory",
    "save_figure",
]

#: Where the notebooks write the figures (:func:`docking.paths.figures_dir` at import time).
FIGURES_DIR = figures_dir()

#: The order in which the paper shows the action units (Figs. 3 and 4): L, R, F, B.
PAPER_ACTION_ORDER = tuple(ACTION_LETTERS.index(letter) for letter in "LRFB")

_DPI = 150
_WEIGHT_CMAP = "gray_r"  # strong = dark
_LETTER_FONT = dict(fontsize=15, fontweight="bold", va="bottom", ha="left")
_LANDMARK_RED = "#d90d0d"
_SIDEBOARD_GREY = "#b8b8bc"
_DOCK_YELLOW = "#ffe600"
_FAIL_RED = "#d62020"


# ------------------------------------------------------------------------------------------
# Saving, layout and drawing helpers.
# ------------------------------------------------------------------------------------------


def save_figure(fig: Figure, path) -> tuple[Path, Path]:
    """Save ``fig`` as ``<path>.png`` (``_DPI`` dpi) and ``<path>.pdf``, each atomically.

    ``path`` may end in ``.png`` or ``.pdf`` or have no suffix; both files are written either
    way, each first to a temporary file in the same folder and then renamed into place, so a
    reader never sees half a figure (:func:`docking.fileio.atomic_write`). The PDF carries no
    creation date, so regenerating an unchanged figure leaves the file unchanged. Returns the
    two paths."""
    path = Path(path)
    if path.suffix.lower() in (".png", ".pdf"):
        path = path.with_suffix("")
    written = []
    for fmt in ("png", "pdf"):
        # No creation date in the PDF: the same figure gives the same file.
        metadata = {"CreationDate": None} if fmt == "pdf" else None
        written.append(
            atomic_write(
                path.parent / f"{path.name}.{fmt}",
                lambda f, fmt=fmt, metadata=metadata: fig.savefig(
                    f, format=fmt, dpi=_DPI, metadata=metadata
                ),
            )
        )
    return written[0], written[1]


def _new_figure(width: float, height: float) -> Figure:
    """A figure on the Agg canvas (no pyplot, no window)."""
    fig = Figure(figsize=(width, height))
    FigureCanvasAgg(fig)
    return fig


def _axes(fig: Figure, left: float, top: float, width: float, height: float):
    """Axes placed in inches, measured from the figure's top-left corner."""
    W, H = fig.get_size_inches()
    return fig.add_axes((left / W, 1 - (top + height) / H, width / W, height / H))


def _letter(fig: Figure, ax, letter: str) -> None:
    """A panel letter just above the top-left corner of ``ax``."""
    bbox = ax.get_position()
    W, H = fig.get_size_inches()
    fig.text(bbox.x0 - 0.05 / W, bbox.y1 + 0.06 / H, letter, **_LETTER_FONT)


def _image(ax, image, vmax=None, frame_color="0.35") -> None:
    """Show an RGB image or a weight/input map (strong = dark, 0..``vmax``) with square pixels
    and no interpolation."""
    if image.ndim == 3:
        ax.imshow(image, interpolation="nearest", aspect="equal")
    else:
        vmax = float(np.max(image)) if vmax is None else float(vmax)
        # An all-zero (or all-negative) field is shown white: it has no structure.
        ax.imshow(
            image,
            cmap=_WEIGHT_CMAP,
            vmin=0.0,
            vmax=max(vmax, 1e-12),
            interpolation="nearest",
            aspect="equal",
        )
    ax.set_xticks([])
    ax.set_yticks([])
    for spine in ax.spines.values():
        spine.set_color(frame_color)
        spine.set_linewidth(0.8)


def _weight_map(
    ax, field: np.ndarray, title: str | None = None, title_color="black", title_size=10
) -> None:
    """A receptive field scaled from 0 to its own maximum, the maximum written beneath."""
    _image(ax, field)
    if title:
        ax.set_title(title, fontsize=title_size, color=title_color, pad=3)
    ax.set_xlabel(f"max {np.max(field):.3g}", fontsize=7, color="0.3", labelpad=2)


def _crop_rectangle(ax, camera: CameraConfig) -> None:
    """The crop rectangle of Fig. 2B: white, dotted, with a thin dark outline so it stays
    visible on the light walls. Pixel ``k`` covers ``[k - 0.5, k + 0.5]`` in image coordinates."""
    x0, y0, x1, y1 = camera.crop
    rect = Rectangle(
        (x0 - 0.5, y0 - 0.5),
        x1 - x0,
        y1 - y0,
        fill=False,
        edgecolor="white",
        linestyle=(0, (1.5, 1.5)),
        linewidth=1.8,
        clip_on=False,
        zorder=3,
    )
    rect.set_path_effects([patheffects.withStroke(linewidth=3.0, foreground="0.15")])
    ax.add_patch(rect)


def _view_title(name: str, pose) -> str:
    where = {
        "left": "left of the landmark",
        "front": "in front of the landmark",
        "right": "right of the landmark",
    }.get(name, name)
    return f"{where}\n(x = {pose[0]:+.2f} m, y = {pose[1]:+.2f} m)"


# ------------------------------------------------------------------------------------------
# Fig. 2: the scene.
# ------------------------------------------------------------------------------------------


def fig2_scene(camera: CameraConfig, views: ExampleViews, overview: np.ndarray) -> Figure:
    """The paper's Fig. 2 for this world, plus the three example views of Fig. 3 (top).

    (A) An overview render of the room: the robot in front of the docking region (yellow;
    virtual, never seen by the robot) and the red landmark on its sideboard. (B) The robot's
    camera frame at the middle view's pose, the crop rectangle drawn white and dotted. (C) The
    32x10 network input after cropping, red thresholding and downsizing (coverage fraction of
    each pixel, 1 = dark). (D) The camera frames and inputs of the three views, ordered left,
    front, right.

    Args:
      camera: The camera (frame size, crop, input shape).
      views: Three views (:func:`docking.analysis.example_views`).
      overview: The overview render (:func:`docking.analysis.overview`) at the middle pose.
    """
    names = list(views.names)
    if len(names) != 3:
        raise ValueError(f"fig2_scene needs three views, got {names}")
    poses = dict(zip(names, views.poses, strict=True))
    frames = dict(zip(names, views.frames, strict=True))
    inputs = dict(zip(names, views.inputs, strict=True))
    main = names[1]
    overview_size = (overview.shape[1], overview.shape[0])

    rows, cols = camera.input_shape
    frame_aspect = camera.height / camera.width
    input_aspect = rows / cols
    # Layout in inches. Top: A on the left, B above C on the right, both columns equally tall.
    W, margin, gap = 10.0, 0.3, 0.35
    c_gap = 0.45  # room for C's caption line
    b = (W - 2 * margin - gap - c_gap / (overview_size[1] / overview_size[0])) / (
        1 + (frame_aspect + input_aspect) / (overview_size[1] / overview_size[0])
    )
    a = W - 2 * margin - gap - b
    top_h = a * overview_size[1] / overview_size[0]
    # Bottom: three columns, frame above input.
    col_gap = 0.3
    c = (W - 2 * margin - 2 * col_gap) / 3
    title_h, top0 = 0.5, 0.35
    bottom0 = top0 + top_h + 0.4 + title_h
    H = bottom0 + c * frame_aspect + 0.08 + c * input_aspect + 0.15
    fig = _new_figure(W, H)

    ax_a = _axes(fig, margin, top0, a, top_h)
    _image(ax_a, overview)
    ax_a.set_title(
        "the robot in front of the docking region (yellow) and the landmark (red)",
        fontsize=9,
        pad=3,
    )
    _letter(fig, ax_a, "A")

    right = margin + a + gap
    ax_b = _axes(fig, right, top0, b, b * frame_aspect)
    _image(ax_b, frames[main])
    _crop_rectangle(ax_b, camera)
    ax_b.set_title(f"robot's camera ({camera.width}x{camera.height} px)", fontsize=9, pad=3)
    _letter(fig, ax_b, "B")
    ax_c = _axes(fig, right, top0 + top_h - b * input_aspect, b, b * input_aspect)
    _image(ax_c, inputs[main], vmax=1.0)
    ax_c.set_title(f"input I ({cols}x{rows})", fontsize=9, pad=3)
    ax_c.set_xlabel(
        "fraction of each pixel's block that is red (0 white, 1 black)",
        fontsize=7,
        color="0.3",
        labelpad=2,
    )
    _letter(fig, ax_c, "C")

    for k, name in enumerate(names):
        left = margin + k * (c + col_gap)
        ax_f = _axes(fig, left, bottom0, c, c * frame_aspect)
        _image(ax_f, frames[name])
        _crop_rectangle(ax_f, camera)
        ax_f.set_title(_view_title(name, poses[name]), fontsize=9, pad=3)
        ax_i = _axes(fig, left, bottom0 + c * frame_aspect + 0.08, c, c * input_aspect)
        _image(ax_i, inputs[name], vmax=1.0)
        if k == 0:
            _letter(fig, ax_f, "D")
    return fig


# ------------------------------------------------------------------------------------------
# Figs. 3 and 4: receptive fields.
# ------------------------------------------------------------------------------------------


def _row_label(fig: Figure, ax, text: str) -> None:
    """A rotated row label left of ``ax``."""
    bbox = ax.get_position()
    W, _ = fig.get_size_inches()
    fig.text(
        bbox.x0 - 0.12 / W,
        (bbox.y0 + bbox.y1) / 2,
        text,
        rotation=90,
        ha="right",
        va="center",
        fontsize=9,
    )


def fig3(
    config: ExperimentConfig,
    seed: int,
    views: ExampleViews,
    decisions: Decisions,
    action_rf: np.ndarray,
    feature_rf: np.ndarray,
    Q: np.ndarray,
) -> Figure:
    """The paper's Fig. 3 for Experiment 1 (4 feature units).

    Top: the camera frames from the left of, in front of and to the right of the landmark
    (crop rectangle dotted), each with the feature unit that wins for it, its activation
    ``s_j`` (Eq. 2) and the greedy action (the largest ``h_i`` of Eq. 3).
    Middle: the action units' receptive fields ``sum_j Q_ij W_j`` in the paper's order L, R,
    F, B. Bottom: the feature units' receptive fields ``W_j``, each titled with the action it
    contributes to most (``argmax_i Q_ij``). Strong weights dark, each field scaled 0..max.

    Args:
      config: The experiment (camera, sizes and labels).
      seed: The run's seed (for the title).
      views: The three views (:func:`docking.analysis.example_views`).
      decisions: The network's decisions on ``views.inputs``
        (:func:`docking.analysis.decisions`).
      action_rf, feature_rf: :func:`docking.analysis.receptive_fields` of the network.
      Q: The network's action weights (for the unit titles).
    """
    shape = config.world.camera.input_shape
    camera = config.world.camera
    best = best_actions(Q)
    frame_aspect = camera.height / camera.width
    rf_aspect = shape[0] / shape[1]
    n_feat = feature_rf.shape[0]
    per_row = max(len(PAPER_ACTION_ORDER), min(n_feat, 6))

    W, margin_l, margin_r, gap = 10.0, 0.55, 0.2, 0.25
    c3 = (W - margin_l - margin_r - 2 * gap) / 3
    c4 = (W - margin_l - margin_r - (per_row - 1) * gap) / per_row
    title_h, label_h = 0.5, 0.25
    y_top = 0.15 + title_h
    y_mid = y_top + c3 * frame_aspect + 0.35 + 0.3
    feat_rows = int(np.ceil(n_feat / per_row))
    y_bot = y_mid + c4 * rf_aspect + label_h + 0.35
    H = y_bot + feat_rows * (c4 * rf_aspect + label_h) + (feat_rows - 1) * 0.35 + 0.1
    fig = _new_figure(W, H)
    fig.suptitle(
        f"Experiment 1 ({n_feat} feature units, {config.network.rule} rule), "
        f"seed {seed}, after {config.train_trials} training trials",
        fontsize=10,
        y=1 - 0.08 / H,
        va="top",
    )

    for k, (name, pose) in enumerate(zip(views.names, views.poses, strict=True)):
        winner, activation, action = (
            int(decisions.winners[k]),
            float(decisions.activations[k]),
            int(decisions.actions[k]),
        )
        ax = _axes(fig, margin_l + k * (c3 + gap), y_top, c3, c3 * frame_aspect)
        _image(ax, views.frames[k])
        _crop_rectangle(ax, camera)
        ax.set_title(_view_title(name, pose).split("\n")[0], fontsize=9, pad=3)
        ax.set_xlabel(
            f"unit {winner} wins (s = {activation:.2f}); greedy action {ACTION_LETTERS[action]}",
            fontsize=8,
            labelpad=3,
        )
        if k == 0:
            _row_label(fig, ax, "raw camera image")

    for k, i in enumerate(PAPER_ACTION_ORDER):
        ax = _axes(fig, margin_l + k * (c4 + gap), y_mid, c4, c4 * rf_aspect)
        _weight_map(ax, action_rf[i], f"{ACTION_LETTERS[i]}", title_size=12)
        if k == 0:
            _row_label(fig, ax, "action\nunits")

    for j in range(n_feat):
        r, k = divmod(j, per_row)
        ax = _axes(
            fig,
            margin_l + k * (c4 + gap),
            y_bot + r * (c4 * rf_aspect + label_h + 0.35),
            c4,
            c4 * rf_aspect,
        )
        label = (
            f"unit {j} \u2192 {ACTION_LETTERS[best[j]]} (Q = {Q[best[j], j]:.2f})"
            if best[j] >= 0
            else f"unit {j}: no action"
        )
        _weight_map(ax, feature_rf[j], label, title_size=9)
        if j == 0:
            _row_label(fig, ax, "feature\nunits")
    return fig


# Layout of one block of Fig. 4 (inches): heading, 4 action panels, then the unit grid.
_BLOCK_HEAD, _BLOCK_ACTION_GAP, _BLOCK_GRID_TOP = 0.55, 0.18, 0.75
_BLOCK_GRID_GAP_X, _BLOCK_GRID_GAP_Y = 0.08, 0.3


def _block_geometry(
    width: float, aspect: float, n_units: int, columns: int
) -> tuple[float, float, float, float]:
    """``(action panel width, unit panel width, grid top, block height)`` of a Fig. 4 block
    ``width`` inches wide, measured from the block's top."""
    ca = (width - 3 * _BLOCK_ACTION_GAP) / 4
    cg = (width - (columns - 1) * _BLOCK_GRID_GAP_X) / columns
    grid_top = _BLOCK_HEAD + ca * aspect + _BLOCK_GRID_TOP
    rows = int(np.ceil(n_units / columns))
    return ca, cg, grid_top, grid_top + rows * (cg * aspect + _BLOCK_GRID_GAP_Y)


def _field_block(
    fig: Figure,
    x0: float,
    y0: float,
    width: float,
    actions: np.ndarray,
    units: np.ndarray,
    framed: dict[int, list[str]],
    columns: int,
    heading: str,
    action_notes=None,
    unit_notes=None,
) -> None:
    """Draw 4 action panels (L, R, F, B) above a grid of unit panels in a column ``width``
    inches wide starting at ``(x0, y0)``."""
    aspect = actions.shape[1] / actions.shape[2]
    ca, cg, grid_top, _ = _block_geometry(width, aspect, units.shape[0], columns)
    fig.text(
        x0 / fig.get_size_inches()[0],
        1 - y0 / fig.get_size_inches()[1],
        heading,
        fontsize=10,
        fontweight="bold",
        va="top",
    )
    y_act = y0 + _BLOCK_HEAD
    for k, i in enumerate(PAPER_ACTION_ORDER):
        ax = _axes(fig, x0 + k * (ca + _BLOCK_ACTION_GAP), y_act, ca, ca * aspect)
        _image(ax, actions[i])
        ax.set_title(ACTION_LETTERS[i], fontsize=11, pad=2)
        if action_notes is not None:
            ax.set_xlabel(action_notes[i], fontsize=7, color="0.3", labelpad=2)
    y_grid = y0 + grid_top
    for j in range(units.shape[0]):
        r, k = divmod(j, columns)
        ax = _axes(
            fig,
            x0 + k * (cg + _BLOCK_GRID_GAP_X),
            y_grid + r * (cg * aspect + _BLOCK_GRID_GAP_Y),
            cg,
            cg * aspect,
        )
        _image(ax, units[j])
        if unit_notes is not None:
            ax.set_xlabel(unit_notes[j], fontsize=6, color="0.3", labelpad=1)
        if j in framed:
            for spine in ax.spines.values():
                spine.set_color(_FAIL_RED)
                spine.set_linewidth(2.5)
            ax.set_title(
                f"unit {j} \u2192 {', '.join(framed[j])}",
                fontsize=7,
                color=_FAIL_RED,
                pad=2,
                fontweight="bold",
            )


def fig4(
    config: ExperimentConfig,
    seed: int,
    action_rf: np.ndarray,
    feature_rf: np.ndarray,
    mean_inputs: MeanInputs,
    framed: dict[int, list[str]],
    columns: int | None = None,
) -> Figure:
    """The paper's Fig. 4 for Experiment 2 (36 feature units), in two halves.

    Left, the weights (as in the paper): the action units' receptive fields
    ``sum_j Q_ij W_j`` (L, R, F, B) above the feature units' receptive fields ``W_j`` (6x6).
    Right, what the units respond to: the mean input over the sampled start views for which
    each action is the greedy one, and for which each feature unit wins (blank where a unit
    never wins). In both halves the units in ``framed`` (the one that contributes most to each
    of L, R and F, ``argmax_j Q_ij``) are framed in red. Strong dark, each panel scaled 0..its
    maximum.

    Args:
      config: The experiment (input shape and labels).
      seed: The run's seed (for the title).
      action_rf, feature_rf: :func:`docking.analysis.receptive_fields` of the network.
      mean_inputs: :func:`docking.analysis.mean_winning_inputs` of the network.
      framed: :func:`docking.analysis.strongest_units` of the network.
      columns: Grid columns; default ``ceil(sqrt(n_features))``.
    """
    shape = config.world.camera.input_shape
    action_mean, unit_mean, action_counts, unit_counts = mean_inputs
    n_samples = int(np.sum(action_counts))
    n_feat = feature_rf.shape[0]
    columns = columns or int(np.ceil(np.sqrt(n_feat)))

    W, margin, middle = 15.0, 0.3, 0.6
    half = (W - 2 * margin - middle) / 2
    top = 0.45
    H = top + _block_geometry(half, shape[0] / shape[1], n_feat, columns)[3] + 0.5
    fig = _new_figure(W, H)
    fig.suptitle(
        f"Experiment 2 ({n_feat} feature units, {config.network.rule} rule), "
        f"seed {seed}, after {config.train_trials} training trials",
        fontsize=11,
        y=1 - 0.06 / H,
        va="top",
    )
    _field_block(
        fig,
        margin,
        top,
        half,
        action_rf,
        feature_rf,
        framed,
        columns,
        "weights: action units $\\sum_j Q_{ij} W_j$ (top), feature units $W_j$ (grid)",
        action_notes=[f"max {np.max(f):.3g}" for f in action_rf],
    )
    never = "never wins"
    _field_block(
        fig,
        margin + half + middle,
        top,
        half,
        action_mean,
        unit_mean,
        framed,
        columns,
        f"mean input when the action is chosen / the unit wins ({n_samples} start views)",
        action_notes=[f"{c} views" for c in action_counts],
        unit_notes=[f"{c} views" if c else never for c in unit_counts],
    )
    fig.text(
        margin / W,
        0.12 / H,
        "Each panel scaled 0..its own maximum, strong dark. Framed red: the unit with the "
        "largest action weight (argmax$_j$ Q$_{ij}$) for L, R and F.",
        fontsize=8,
        color="0.3",
        va="bottom",
    )
    return fig


# ------------------------------------------------------------------------------------------
# Fig. 5: trajectories.
# ------------------------------------------------------------------------------------------
# Seen from above with the landmark at the top and the robot walking up towards it: the
# vertical axis is x (the approach axis), the horizontal axis is y, inverted so that the
# robot's left (+y) is on the reader's left, as it is for a robot walking up the page.


def draw_floor_plan(ax, config: WorldConfig, start_region: StartRegion | None = None) -> None:
    """Draw the floor plan on ``ax`` (horizontal: y, inverted; vertical: x): the grey sideboard,
    the landmark's red boxes, the yellow docking region and, dashed, the start trapezoid
    (default the config's, ``StartRegion.of(config)``)."""
    fp = floor_plan(config)
    styles = {
        "sideboard": dict(facecolor=_SIDEBOARD_GREY, edgecolor="0.4", zorder=1),
        "landmark_slab": dict(facecolor=_LANDMARK_RED, edgecolor="none", zorder=2),
        "landmark_post": dict(facecolor=_LANDMARK_RED, edgecolor="none", zorder=2),
        "dock": dict(facecolor=_DOCK_YELLOW, edgecolor="0.3", linewidth=0.6, zorder=1),
    }
    for name, style in styles.items():
        x0, y0, x1, y1 = fp[name]
        ax.add_patch(Rectangle((y0, x0), y1 - y0, x1 - x0, **style))
    region = start_region if start_region is not None else StartRegion.of(config)
    corners = region.corners()[:, ::-1]  # (y, x): y is the horizontal axis
    ax.add_patch(
        Polygon(
            corners,
            closed=True,
            fill=False,
            linestyle="--",
            edgecolor="0.45",
            linewidth=1.0,
            zorder=1,
        )
    )
    ax.set_aspect("equal")
    if not ax.xaxis_inverted():
        ax.invert_xaxis()
    ax.set_xlabel("y (m), lateral; the robot's left (+y) is on the left")
    ax.set_ylabel("x (m), approach axis; landmark's front at x = 0")


def draw_trajectory(ax, poses: np.ndarray, color, start_marker: bool = True, **kwargs) -> None:
    """Draw one trial's reference-point path (``poses``: rows ``[x, y, yaw]``) on a floor plan
    made by :func:`draw_floor_plan`: a line through the poses after each step, a dot at each
    step and an open circle at the start."""
    poses = np.asarray(poses)
    line = dict(linewidth=1.1, marker=".", markersize=3, zorder=3)
    line.update(kwargs)
    ax.plot(poses[:, 1], poses[:, 0], color=color, **line)
    if start_marker:
        ax.plot(
            poses[0, 1],
            poses[0, 0],
            "o",
            markersize=5,
            markerfacecolor="white",
            markeredgecolor=color,
            markeredgewidth=1.2,
            zorder=4,
        )


def fig5(
    config: WorldConfig,
    sample: TrajectorySample,
    label: str,
    start_region: StartRegion | None = None,
    shade_seed: int = 0,
) -> Figure:
    """The paper's Fig. 5: sample test trajectories of the robot seen from above.

    Successful trials in different shades of green, failures in red, start points as open
    circles; the docking region yellow (its size from the config), the sideboard grey, the
    landmark's two boxes red, the test start trapezoid dashed, and the robot's body (radius
    ``ROBOT_RADIUS``) drawn once at the end of a successful trial for scale.

    Args:
      config: The world (floor plan, docking region, start region).
      sample: The trials to show (:func:`docking.analysis.trajectory_sample`).
      label: Names the run in the title, e.g. ``"experiment2, seed 0"``.
      start_region: The start trapezoid to draw; default the config's.
      shade_seed: Seeds the order of the shades of green (so neighbouring paths differ).
    """
    region = start_region if start_region is not None else StartRegion.of(config)
    ok = [m for m in range(len(sample.indices)) if sample.success[m]]
    bad = [m for m in range(len(sample.indices)) if not sample.success[m]]
    paths = dict(enumerate(sample.paths))

    # The plotted area: the floor plan, the start region and every shown path, plus a margin;
    # one metre is drawn the same length on both axes.
    sideboard = floor_plan(config)["sideboard"]
    ys = np.concatenate(
        [
            [
                region.half_width(region.far),
                -region.half_width(region.far),
                sideboard[1],
                sideboard[3],
            ]
        ]
        + [p[:, 1] for p in paths.values()]
    )
    xs = np.concatenate([[-region.far, sideboard[2]]] + [p[:, 0] for p in paths.values()])
    margin = 0.08
    y_lo, y_hi = float(np.min(ys)) - margin, float(np.max(ys)) + margin
    x_lo, x_hi = float(np.min(xs)) - margin, float(np.max(xs)) + margin
    inch_per_m = min(7.5 / (x_hi - x_lo), 6.5 / (y_hi - y_lo))
    plot_w, plot_h = inch_per_m * (y_hi - y_lo), inch_per_m * (x_hi - x_lo)
    legend_h = 0.85
    W = max(plot_w, 3.6) + 1.2
    H = 0.55 + plot_h + 0.6 + legend_h
    fig = _new_figure(W, H)
    ax = _axes(fig, 0.9, 0.55, plot_w, plot_h)
    draw_floor_plan(ax, config, region)
    ax.set_xlim(y_hi, y_lo)  # inverted: +y (the robot's left) on the left
    ax.set_ylim(x_lo, x_hi)

    # Shades of green, shuffled (seeded) so that neighbouring paths differ.
    shades = colormaps["Greens"](np.linspace(0.45, 0.95, max(len(ok), 1)))
    shades = shades[np.random.default_rng(shade_seed).permutation(len(shades))]
    for m, k in enumerate(ok):
        draw_trajectory(ax, paths[k], shades[m])
    for k in bad:
        draw_trajectory(ax, paths[k], _FAIL_RED, zorder=5)
    if ok:  # the robot's body once, at the end of a successful trial, for scale
        end = paths[ok[0]][-1]
        ax.add_patch(
            Circle(
                (end[1], end[0]),
                ROBOT_RADIUS,
                fill=False,
                edgecolor="0.3",
                linestyle=":",
                linewidth=1.0,
                zorder=6,
            )
        )

    n, docked = sample.n_trials, sample.n_docked
    ax.set_title(
        f"{label}: {len(sample.indices)} of {n} test trials\n(all {n}: {docked} docked, "
        f"{100 * (docked / n):.0f}%)",
        fontsize=9,
    )
    dock_cm = f"{100 * config.dock_depth:.0f}x{100 * config.dock_width:.0f} cm"
    handles = [
        Line2D(
            [],
            [],
            color=shades[len(shades) // 2] if ok else "green",
            marker=".",
            label=f"docked ({len(ok)} shown)",
        ),
        Line2D([], [], color=_FAIL_RED, marker=".", label=f"failed ({len(bad)} shown)"),
        Line2D(
            [],
            [],
            linestyle="none",
            marker="o",
            markerfacecolor="white",
            markeredgecolor="0.3",
            label="start of a trial",
        ),
        Line2D(
            [],
            [],
            color="0.45",
            linestyle="--",
            label=f"start region ({region.near:.2f}-{region.far:.2f} m)",
        ),
        Rectangle(
            (0, 0),
            1,
            1,
            facecolor=_DOCK_YELLOW,
            edgecolor="0.3",
            label=f"docking region ({dock_cm})",
        ),
        Rectangle((0, 0), 1, 1, facecolor=_LANDMARK_RED, label="landmark (slab, post)"),
        Rectangle((0, 0), 1, 1, facecolor=_SIDEBOARD_GREY, edgecolor="0.4", label="sideboard"),
        Line2D(
            [],
            [],
            color="0.3",
            linestyle=":",
            label=f"robot body (r = {100 * ROBOT_RADIUS:.0f} cm)",
        ),
    ]
    fig.legend(
        handles=handles,
        loc="upper left",
        ncol=2,
        fontsize=7.5,
        frameon=False,
        bbox_to_anchor=(0.15 / W, 1 - (0.55 + plot_h + 0.6) / H),
    )
    return fig


# ------------------------------------------------------------------------------------------
# Learning curves.
# ------------------------------------------------------------------------------------------

# The paper's final test success rates (Sec. III): Experiment 1 100%, Experiment 2 95%.
_PAPER_SUCCESS = {"experiment1": 1.0, "experiment2": 0.95}


def fig_learning_curves(curves1: LearningCurves | None, curves2: LearningCurves | None) -> Figure:
    """Learning curves of both experiments (not a figure of the paper).

    One column per experiment with curves (``None`` skips its column), from
    :func:`docking.analysis.learning_curves`. Top: test success rate (greedy trials from the
    full start region) against training trials; thin lines one per seed, the thick line their
    mean; a diamond per seed at the end is the final test's success rate; dashed, the paper's
    final result (100% and 95%). Middle: mean actions of the successful test trials, with the
    step limit dotted. Bottom: the start region's far edge during training (the curriculum of
    Experiment 2, "Learning from Easy Missions").
    """
    columns = [
        (label, curves)
        for label, curves in (("Experiment 1", curves1), ("Experiment 2", curves2))
        if curves is not None
    ]
    if not columns:
        raise ValueError("fig_learning_curves needs the curves of at least one experiment")
    W = 4.6 * len(columns) + 0.6
    fig = _new_figure(W, 7.6)
    grid = fig.add_gridspec(
        3,
        len(columns),
        height_ratios=(3, 2, 1.2),
        hspace=0.12,
        wspace=0.28,
        left=0.9 / W,
        right=1 - 0.25 / W,
        top=0.93,
        bottom=0.08,
    )
    for col, (label, curves) in enumerate(columns):
        ax_s = fig.add_subplot(grid[0, col])
        ax_n = fig.add_subplot(grid[1, col], sharex=ax_s)
        ax_c = fig.add_subplot(grid[2, col], sharex=ax_s)
        cfg = curves.config
        color = f"C{col}"
        thin = dict(color=color, alpha=0.35, lw=0.8)
        for k in range(len(curves.seeds)):
            ax_s.plot(curves.trials[k], 100 * curves.success[k], **thin)
            ax_n.plot(curves.trials[k], curves.steps[k], **thin)
            ax_s.plot(
                curves.final_trials[k],
                100 * curves.final_success[k],
                "D",
                color=color,
                alpha=0.6,
                markersize=4,
                clip_on=False,
                zorder=4,
            )
        ax_s.plot(curves.mean_trials, 100 * curves.mean_success, color=color, lw=2.2)
        ax_n.plot(curves.mean_trials, curves.mean_steps, color=color, lw=2.2)

        # Legend: what a thin line, the thick line and a diamond are.
        ax_s.plot(
            [], [], **thin, label=f"one seed ({cfg.eval_trials} test trials every {cfg.eval_every})"
        )
        ax_s.plot([], [], color=color, lw=2.2, label=f"mean of {len(curves.seeds)} seeds")
        ax_s.plot(
            [],
            [],
            "D",
            color=color,
            alpha=0.6,
            markersize=4,
            label=f"final test ({cfg.test_trials} trials)",
        )
        paper = _PAPER_SUCCESS.get(cfg.name)
        if paper is not None:
            ax_s.axhline(
                100 * paper, color="0.2", linestyle="--", lw=1.0, label=f"paper: {100 * paper:.0f}%"
            )
        ax_s.set_ylim(-3, 103)
        ax_s.set_title(
            f"{label}: {cfg.network.n_features} feature units, {cfg.network.rule} rule", fontsize=10
        )
        ax_s.legend(fontsize=7, loc="lower right", framealpha=0.9)
        ax_n.axhline(
            cfg.world.max_steps,
            color="0.2",
            linestyle=":",
            lw=1.0,
            label=f"step limit ({cfg.world.max_steps})",
        )
        ax_n.set_ylim(0, cfg.world.max_steps + 2)
        ax_n.legend(fontsize=7, loc="lower right", framealpha=0.9)

        # The start region during training (the seeds share the configuration's curriculum).
        trials = np.arange(len(curves.start_far[0]))
        ax_c.fill_between(
            trials,
            cfg.world.start_near,
            curves.start_far[0],
            color=color,
            alpha=0.2,
            lw=0,
            step="post",
        )
        for start_far in curves.start_far:
            ax_c.plot(
                np.arange(len(start_far)),
                start_far,
                color=color,
                lw=1.0,
                drawstyle="steps-post",
            )
        ax_c.set_ylim(0, cfg.world.start_far * 1.15)
        ax_c.set_xlabel("training trials")
        if col == 0:
            ax_s.set_ylabel("test success (%)")
            ax_n.set_ylabel("actions per\nsuccessful test trial")
            ax_c.set_ylabel("start region\n(m from landmark)")
        for ax in (ax_s, ax_n):
            ax.tick_params(labelbottom=False)
        for ax in (ax_s, ax_n, ax_c):
            ax.grid(alpha=0.3, lw=0.5)
        last = int(np.max(curves.final_trials))
        ax_s.set_xlim(0, last * 1.03)  # room for the final-test diamonds
    return fig
