"""The paper's figures, drawn from arrays: this module draws and does nothing else.

* :func:`fig2_scene` -- Fig. 2: the scene, the robot's camera view with the crop rectangle, the
  32x10 input; plus the views from the left of, in front of and to the right of the landmark.
* :func:`fig3` -- Fig. 3: Experiment 1's raw views, action and feature receptive fields.
* :func:`fig4` -- Fig. 4: Experiment 2's action and feature receptive fields, the feature
  units that contribute most to L, R and F framed in red.
* :func:`fig5` -- Fig. 5: sample test trajectories seen from above.
* :func:`fig_learning_curves` -- test success and steps during training (not in the paper).

Every figure function takes the arrays that :mod:`docking.study.analysis` computes (and
configurations for geometry and labels) and returns a :class:`matplotlib.figure.Figure`; it
renders nothing, runs no network and writes no file. Panels are laid out by matplotlib's
constrained layout, grouped in subfigures, each headed by its bold panel letter. The caller
saves the figure with
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

import io
import textwrap
from pathlib import Path

import numpy as np
from matplotlib import colormaps, patheffects
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyBboxPatch, Polygon, Rectangle

from docking.camera import CameraConfig
from docking.experiments import ExperimentConfig
from docking.fileio import atomic_write
from docking.region import StartRegion
from docking.scene import ACTION_LETTERS, WorldConfig, scene_facts
from docking.study.analysis import (
    Decisions,
    ExampleViews,
    LearningCurves,
    MeanInputs,
    TrajectorySample,
    best_actions,
    floor_plan,
)
from docking.study.paths import figures_dir

__all__ = [
    "FIGURES_DIR",
    "PAPER_ACTION_ORDER",
    "action_order",
    "fig2_scene",
    "fig3",
    "fig4",
    "fig5",
    "fig_action_fields",
    "fig_experiment3",
    "fig_failure_matrix",
    "fig_learning_curves",
    "fig_rewards",
    "fig_trial",
    "draw_floor_plan",
    "draw_trajectory",
    "episode_frames",
    "episode_gif",
    "save_figure",
    "to_png",
]

#: Where the notebooks write the figures (:func:`docking.study.paths.figures_dir` at import time).
FIGURES_DIR = figures_dir()

#: The order in which the paper shows the action units (Figs. 3 and 4): L, R, F, B.
PAPER_ACTION_ORDER = tuple(ACTION_LETTERS.index(letter) for letter in "LRFB")


def action_order(world: WorldConfig) -> tuple[int, ...]:
    """The order in which the figures show ``world``'s action units: the paper's L, R, F, B,
    then any further actions (the turns) in index order."""
    return PAPER_ACTION_ORDER + tuple(range(len(PAPER_ACTION_ORDER), world.n_actions))


_DPI = 150
#: The width (inches) of a figure drawn for a page: at ``_DPI``, about 1.25 times the width
#: a documentation page shows it at, so that its smallest labels (6 pt) stay readable there.
_PAGE_WIDTH_IN = 7.5
_WEIGHT_CMAP = "gray_r"  # strong = dark
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
    creation date and the layout is frozen first (:func:`_freeze_layout`), so regenerating an
    unchanged figure leaves both files unchanged. Returns the two paths."""
    path = Path(path)
    if path.suffix.lower() in (".png", ".pdf"):
        path = path.with_suffix("")
    _freeze_layout(fig)
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


def _freeze_layout(fig: Figure) -> None:
    """Lay ``fig`` out as saving does, then fix every axes' and subfigure's position, rounded
    to 1e-9 of the figure, and turn the layout engine off. Constrained layout's positions
    differ in their last bits from process to process (its solver meets the grid specs in an
    order set by memory addresses): invisible in the PNG's pixels, but written into the PDF,
    whose bytes (Fig. 4's) changed on every run."""
    fig.savefig(io.BytesIO(), format="png", dpi=_DPI)
    fig.set_layout_engine("none")
    for ax in fig.get_axes():  # the box the layout gave (an image's aspect is applied in it)
        ax.set_position(np.round(ax.get_position(original=True).bounds, 9) + 0.0)  # no -0.0
    subfigures = list(fig.subfigs)
    while subfigures:
        sub = subfigures.pop()
        sub.bbox_relative.set_points(np.round(sub.bbox_relative.get_points(), 9) + 0.0)
        subfigures += sub.subfigs


def to_png(fig: Figure) -> bytes:
    """The figure as PNG bytes (``_DPI`` dpi), e.g. for ``IPython.display.Image(data=...)``."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=_DPI)
    return buffer.getvalue()


def _new_figure(width: float, height: float) -> Figure:
    """A figure with constrained layout on the Agg canvas (no pyplot, no window)."""
    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _panel(sub, letter: str, caption: str = "") -> None:
    """Head a (sub)figure with its bold panel letter and a caption, left-aligned; constrained
    layout makes room for it."""
    text = f"$\\mathbf{{{letter}}}$   {caption}" if caption else f"$\\mathbf{{{letter}}}$"
    sub.suptitle(text, x=0.0, ha="left", fontsize=11)


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
      views: Three views (:func:`docking.study.analysis.example_views`).
      overview: The overview render (:func:`docking.study.analysis.overview`) at the middle pose.
    """
    names = list(views.names)
    if len(names) != 3:
        raise ValueError(f"fig2_scene needs three views, got {names}")
    poses = dict(zip(names, views.poses, strict=True))
    frames = dict(zip(names, views.frames, strict=True))
    inputs = dict(zip(names, views.inputs, strict=True))
    main = names[1]
    rows, cols = camera.input_shape
    frame_aspect = camera.height / camera.width
    input_aspect = rows / cols

    fig = _new_figure(10.0, 9.3)
    top, bottom = fig.subfigures(2, 1, height_ratios=(5.1, 4.2))
    sf_a, right = top.subfigures(1, 2, width_ratios=(1.75, 1.0))
    _panel(sf_a, "A", "the robot in front of the docking region (yellow) and the landmark (red)")
    _image(sf_a.subplots(), overview)

    sf_b, sf_c = right.subfigures(2, 1, height_ratios=(frame_aspect + 0.1, input_aspect + 0.12))
    _panel(sf_b, "B", f"robot's camera ({camera.width}x{camera.height} px), crop dotted")
    ax_b = sf_b.subplots()
    _image(ax_b, frames[main])
    _crop_rectangle(ax_b, camera)
    _panel(sf_c, "C", f"input I ({cols}x{rows})")
    ax_c = sf_c.subplots()
    _image(ax_c, inputs[main], vmax=1.0)
    ax_c.set_xlabel(
        "fraction of each pixel's block that is red (0 white, 1 black)", fontsize=7, color="0.3"
    )

    _panel(bottom, "D", "camera frames (crop dotted) and inputs from three positions")
    axes = bottom.subplots(2, 3, height_ratios=(frame_aspect, input_aspect))
    for k, name in enumerate(names):
        _image(axes[0, k], frames[name])
        _crop_rectangle(axes[0, k], camera)
        axes[0, k].set_title(_view_title(name, poses[name]), fontsize=9, pad=3)
        _image(axes[1, k], inputs[name], vmax=1.0)
    return fig


# ------------------------------------------------------------------------------------------
# Figs. 3 and 4: receptive fields.
# ------------------------------------------------------------------------------------------


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
      views: The three views (:func:`docking.study.analysis.example_views`).
      decisions: The network's decisions on ``views.inputs``
        (:func:`docking.study.analysis.decisions`).
      action_rf, feature_rf: :func:`docking.study.analysis.receptive_fields` of the network.
      Q: The network's action weights (for the unit titles).
    """
    shape = config.world.camera.input_shape
    camera = config.world.camera
    n_feat = feature_rf.shape[0]
    order, letters = action_order(config.world), config.world.action_letters
    per_row = max(len(order), min(n_feat, 6))
    feat_rows = int(np.ceil(n_feat / per_row))
    frame_aspect = camera.height / camera.width
    rf_aspect = shape[0] / shape[1]
    # Heights (inches) of the three rows of panels at a 10-inch width, titles included.
    heights = (
        3.3 * frame_aspect + 0.8,
        2.35 * rf_aspect + 0.9,
        feat_rows * (2.35 * rf_aspect + 0.6) + 0.3,
    )
    fig = _new_figure(10.0, sum(heights) + 0.4)
    fig.suptitle(
        f"Experiment 1 ({n_feat} feature units, {config.network.rule} rule), "
        f"seed {seed}, after {config.train_trials} training trials",
        fontsize=11,
    )
    sf_a, sf_b, sf_c = fig.subfigures(3, 1, height_ratios=heights)

    _decided_views(sf_a, views, decisions, camera, letters)
    _panel(sf_b, "B", "action units: receptive fields $\\Sigma_j\\,Q_{ij} W_j$")
    for ax, i in zip(sf_b.subplots(1, per_row)[: len(order)], order, strict=True):
        _weight_map(ax, action_rf[i], f"{letters[i]}", title_size=12)
    for ax in sf_b.axes[len(order) :]:
        ax.set_visible(False)

    _feature_fields(sf_c, feature_rf, Q, letters, (feat_rows, per_row))
    return fig


def _feature_fields(sub, feature_rf: np.ndarray, Q: np.ndarray, letters, grid) -> None:
    """Fig. 3 C: the feature units' receptive fields ``W_j`` on a ``grid`` of (rows,
    columns), each titled with the action it contributes to most (``argmax_i Q_ij``)."""
    best = best_actions(Q)
    _panel(sub, "C", "feature units: receptive fields $W_j$, each with the action it drives most")
    axes = np.atleast_2d(sub.subplots(*grid))
    for j, ax in enumerate(axes.flat):
        if j >= feature_rf.shape[0]:
            ax.set_visible(False)
            continue
        label = (
            f"unit {j} \u2192 {letters[best[j]]} (Q = {Q[best[j], j]:.2f})"
            if best[j] >= 0
            else f"unit {j}: no action"
        )
        _weight_map(ax, feature_rf[j], label, title_size=9)


def _decided_views(sub, views: ExampleViews, decisions: Decisions, camera, letters) -> None:
    """Fig. 3 A: each view's camera frame (crop rectangle dotted) with the feature unit that
    wins for it, its activation and the greedy action."""
    _panel(sub, "A", "raw camera images: the feature unit that wins and the greedy action")
    for k, ax in enumerate(sub.subplots(1, len(views.names))):
        winner, activation, action = (
            int(decisions.winners[k]),
            float(decisions.activations[k]),
            int(decisions.actions[k]),
        )
        _image(ax, views.frames[k])
        _crop_rectangle(ax, camera)
        ax.set_title(_view_title(views.names[k], views.poses[k]).split("\n")[0], fontsize=9)
        ax.set_xlabel(
            f"unit {winner} wins (s = {activation:.2f}); greedy action {letters[action]}",
            fontsize=8,
        )


def _field_block(
    sub,
    letter: str,
    heading: str,
    actions: np.ndarray,
    units: np.ndarray,
    framed: dict[int, list[str]],
    columns: int,
    action_notes,
    unit_notes,
    world: WorldConfig,
) -> None:
    """One block of Fig. 4 in the subfigure ``sub``: the action panels (L, R, F, B, then any
    turns; ``actions`` None: the text ``action_notes`` in their place) above a grid of unit
    panels, the units in ``framed`` framed red."""
    _panel(sub, letter, heading)
    rows = int(np.ceil(units.shape[0] / columns))
    top = 0.9 if actions is not None else 0.3  # the action panels, or a line of text
    sf_actions, sf_units = sub.subfigures(2, 1, height_ratios=(top, rows * 0.52))
    order = action_order(world)
    if actions is None:
        sf_actions.text(
            0.5, 0.45, action_notes, ha="center", va="center", fontsize=9, color="0.25", wrap=True
        )
    else:
        for ax, i in zip(sf_actions.subplots(1, len(order)), order, strict=True):
            _image(ax, actions[i])
            ax.set_title(world.action_letters[i], fontsize=11, pad=2)
            ax.set_xlabel(action_notes[i], fontsize=7, color="0.3", labelpad=2)
    for j, ax in enumerate(sf_units.subplots(rows, columns).flat):
        if j >= units.shape[0]:
            ax.set_visible(False)
            continue
        _image(ax, units[j])
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


def _fig4_blocks(
    config: ExperimentConfig, seed: int, n_feat: int, rows: int, blocks: int
) -> tuple[Figure, np.ndarray]:
    """Fig. 4's page-wide figure with its title, and its blocks' subfigures, top to bottom."""
    block = 1.2 + rows * 0.52  # one block's height (inches), as wide as a page
    heights = [block] * 2 + [block - 0.6] * (blocks - 2)  # C: a line of text, not panels
    fig = _new_figure(_PAGE_WIDTH_IN, 0.75 + sum(heights))
    fig.suptitle(
        f"Experiment 2 ({n_feat} feature units, {config.network.rule} rule, "
        f"$\\epsilon_W$ = {config.network.eps_w:g}), seed {seed}, after "
        f"{config.train_trials} training trials\nEach panel scaled 0..its own maximum, strong "
        "dark; framed red: the unit with the\nlargest action weight (argmax$_j$ Q$_{ij}$) for L, "
        "R and F.",
        fontsize=10,
    )
    return fig, fig.subfigures(blocks, 1, hspace=0.02, height_ratios=heights)


def _fig4_weights(
    sub,
    config: ExperimentConfig,
    action_rf: np.ndarray,
    feature_rf: np.ndarray,
    framed: dict[int, list[str]],
    columns: int,
) -> None:
    """Fig. 4's block A: the action units' and the feature units' receptive fields."""
    _field_block(
        sub,
        "A",
        "weights: action units $\\Sigma_j\\,Q_{ij} W_j$ (top row), feature units $W_j$ (grid)",
        action_rf,
        feature_rf,
        framed,
        columns,
        action_notes=[f"max {np.max(f):.3g}" for f in action_rf],
        unit_notes=[f"unit {j}" for j in range(feature_rf.shape[0])],
        world=config.world,
    )


def _fig4_responses(
    sub,
    config: ExperimentConfig,
    mean_inputs: MeanInputs,
    framed: dict[int, list[str]],
    columns: int,
) -> None:
    """Fig. 4's block B: the mean input for which each action is chosen, each unit wins."""
    action_mean, unit_mean, action_counts, unit_counts = mean_inputs
    n_samples = int(np.sum(action_counts))
    _field_block(
        sub,
        "B",
        f"mean input when the action is chosen / the unit wins ({n_samples} start views)",
        action_mean,
        unit_mean,
        framed,
        columns,
        action_notes=[f"{c} views" for c in action_counts],
        unit_notes=[
            f"unit {j}: {c} views" if c else f"unit {j}: never wins"
            for j, c in enumerate(unit_counts)
        ],
        world=config.world,
    )


def _fig4_start(
    sub,
    config: ExperimentConfig,
    initial_rf: np.ndarray,
    n_feat: int,
    framed: dict[int, list[str]],
    columns: int,
) -> None:
    """Fig. 4's block C: the feature units' receptive fields at their random start."""
    _field_block(
        sub,
        "C",
        "feature units $W_j$ at their random start (what W frozen, eps_W = 0, keeps)",
        None,
        initial_rf,
        framed,
        columns,
        action_notes="the same seed's W before training; framed: the units framed in A and B",
        unit_notes=[f"unit {j}" for j in range(n_feat)],
        world=config.world,
    )


def fig4(
    config: ExperimentConfig,
    seed: int,
    action_rf: np.ndarray,
    feature_rf: np.ndarray,
    mean_inputs: MeanInputs,
    framed: dict[int, list[str]],
    columns: int | None = None,
    initial_rf: np.ndarray | None = None,
) -> Figure:
    """The paper's Fig. 4 for Experiment 2 (36 feature units), in two blocks one above the
    other, and below them (if ``initial_rf`` is given) the feature units' weights at their
    random start: one column of blocks, as wide as a page, so that its labels can be read at
    the width a page shows it (the documentation site's test checks that).

    A, the weights (as in the paper): the action units' receptive fields
    ``sum_j Q_ij W_j`` (L, R, F, B) above the feature units' receptive fields ``W_j`` (6x6).
    B, what the units respond to: the mean input over the sampled start views for which
    each action is the greedy one, and for which each feature unit wins (blank where a unit
    never wins). In both blocks the units in ``framed`` (the one that contributes most to each
    of L, R and F, ``argmax_j Q_ij``) are framed in red. Strong dark, each panel scaled 0..its
    maximum.

    Args:
      config: The experiment (input shape and labels).
      seed: The run's seed (for the title).
      action_rf, feature_rf: :func:`docking.study.analysis.receptive_fields` of the network.
      mean_inputs: :func:`docking.study.analysis.mean_winning_inputs` of the network.
      framed: :func:`docking.study.analysis.strongest_units` of the network.
      columns: Grid columns; default ``ceil(sqrt(n_features))``.
      initial_rf: The feature units' receptive fields at the run's random start (the same
        seed's initial ``W``: what W frozen, eps_W = 0, keeps), drawn as a third block C, so
        that a reader can see what training changed.
    """
    n_feat = feature_rf.shape[0]
    columns = columns or int(np.ceil(np.sqrt(n_feat)))
    blocks = 2 if initial_rf is None else 3
    fig, subs = _fig4_blocks(config, seed, n_feat, int(np.ceil(n_feat / columns)), blocks)
    _fig4_weights(subs[0], config, action_rf, feature_rf, framed, columns)
    _fig4_responses(subs[1], config, mean_inputs, framed, columns)
    if initial_rf is not None:
        _fig4_start(subs[2], config, initial_rf, n_feat, framed, columns)
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
        if name not in fp:  # a scene without a sideboard
            continue
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


def _plan_extent(config: WorldConfig) -> tuple[float, float, float]:
    """``(y_min, y_max, x_max)`` over the floor plan's rectangles (m): how far the furniture
    and the landmark reach across and beyond the landmark's front."""
    rects = np.array(list(floor_plan(config).values()))
    return float(rects[:, 1].min()), float(rects[:, 3].max()), float(rects[:, 2].max())


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
    ``scene_facts().robot_radius``) drawn once at the end of a successful trial for scale.

    Args:
      config: The world (floor plan, docking region, start region).
      sample: The trials to show (:func:`docking.study.analysis.trajectory_sample`).
      label: Names the run in the title, e.g. ``"experiment2, seed 0"``.
      start_region: The start trapezoid to draw; default the config's.
      shade_seed: Seeds the order of the shades of green (so neighbouring paths differ).
    """
    region = start_region if start_region is not None else StartRegion.of(config)
    ok = [m for m in range(len(sample.indices)) if sample.success[m]]
    bad = [m for m in range(len(sample.indices)) if not sample.success[m]]
    paths = dict(enumerate(sample.paths))

    fig, ax = _plan_axes(config, region, list(paths.values()))

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
                scene_facts().robot_radius,
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
    docked_colour = shades[len(shades) // 2] if ok else "green"
    handles = _fig5_legend(config, region, docked_colour, len(ok), len(bad))
    fig.legend(handles=handles, loc="outside lower center", ncol=2, fontsize=7.5, frameon=False)
    return fig


def _plan_axes(config: WorldConfig, region: StartRegion, paths: list[np.ndarray]):
    """A figure and its axes for a floor plan seen from above: the plotted area holds the
    floor plan, the start region and every path of ``paths``, plus a margin, with one metre
    drawn the same length on both axes and +y (the robot's left) on the left."""
    y_min, y_max, x_max = _plan_extent(config)
    ys = np.concatenate(
        [[region.half_width(region.far), -region.half_width(region.far), y_min, y_max]]
        + [p[:, 1] for p in paths]
    )
    xs = np.concatenate([[-region.far, x_max]] + [p[:, 0] for p in paths])
    margin = 0.08
    y_lo, y_hi = float(np.min(ys)) - margin, float(np.max(ys)) + margin
    x_lo, x_hi = float(np.min(xs)) - margin, float(np.max(xs)) + margin
    inch_per_m = min(7.5 / (x_hi - x_lo), 6.5 / (y_hi - y_lo))
    plot_w, plot_h = inch_per_m * (y_hi - y_lo), inch_per_m * (x_hi - x_lo)
    fig = _new_figure(max(plot_w, 3.6) + 1.3, plot_h + 2.1)
    ax = fig.add_subplot()
    draw_floor_plan(ax, config, region)
    ax.set_xlim(y_hi, y_lo)  # inverted: +y (the robot's left) on the left
    ax.set_ylim(x_lo, x_hi)
    return fig, ax


def _fig5_legend(config: WorldConfig, region: StartRegion, docked_colour, n_ok: int, n_bad: int):
    """Fig. 5's legend entries: the paths shown, the start region, the docking region, the
    landmark, the sideboard and the robot's body."""
    dock_cm = f"{100 * config.dock_depth:.0f}x{100 * config.dock_width:.0f} cm"
    return [
        Line2D(
            [],
            [],
            color=docked_colour,
            marker=".",
            label=f"docked ({n_ok} shown)",
        ),
        Line2D([], [], color=_FAIL_RED, marker=".", label=f"failed ({n_bad} shown)"),
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
            label=f"robot body (r = {100 * scene_facts().robot_radius:.0f} cm)",
        ),
    ]


# ------------------------------------------------------------------------------------------
# Learning curves.
# ------------------------------------------------------------------------------------------

# The paper's final test success rates (Sec. III): Experiment 1 100%, Experiment 2 95%.
_PAPER_SUCCESS = {"experiment1": 1.0, "experiment2": 0.95}


def fig_learning_curves(curves1: LearningCurves | None, curves2: LearningCurves | None) -> Figure:
    """Learning curves of both experiments (not a figure of the paper).

    One column per experiment with curves (``None`` skips its column), from
    :func:`docking.study.analysis.learning_curves`. Top: test success rate (greedy trials from the
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
    fig = _new_figure(4.6 * len(columns) + 0.6, 7.6)
    grid = fig.add_gridspec(3, len(columns), height_ratios=(3, 2, 1.2))
    letters = iter("ABCDEF")
    for col, (label, curves) in enumerate(columns):
        ax_s = fig.add_subplot(grid[0, col])
        ax_n = fig.add_subplot(grid[1, col], sharex=ax_s)
        ax_c = fig.add_subplot(grid[2, col], sharex=ax_s)
        for ax in (ax_s, ax_n, ax_c):  # letters down each column: A-C, then D-F
            ax.set_title(next(letters), loc="left", fontweight="bold", fontsize=12)
        color = f"C{col}"
        _success_panel(ax_s, curves, label, color)
        _actions_panel(ax_n, curves, color)
        _curriculum_panel(ax_c, curves, color)
        if col == 0:
            ax_s.set_ylabel("test success (%)")
            ax_n.set_ylabel("actions per\nsuccessful test trial")
            ax_c.set_ylabel("start region\n(m from landmark)")
        for ax in (ax_s, ax_n):
            ax.tick_params(labelbottom=False)
        for ax in (ax_s, ax_n, ax_c):
            ax.grid(alpha=0.3, lw=0.5)
        ax_s.set_xlim(0, int(np.max(curves.final_trials)) * 1.03)  # room for the diamonds
    return fig


def _success_panel(ax, curves: LearningCurves, label: str, color) -> None:
    """Test success against training trials: a thin line per seed with a diamond at its
    final test, their mean thick, the paper's final result dashed."""
    cfg = curves.config
    thin = dict(color=color, alpha=0.35, lw=0.8)
    diamond = dict(color=color, alpha=0.6, markersize=4)
    for k in range(len(curves.seeds)):
        ax.plot(curves.trials[k], 100 * curves.success[k], **thin)
        ax.plot(
            curves.final_trials[k],
            100 * curves.final_success[k],
            "D",
            **diamond,
            clip_on=False,
            zorder=4,
        )
    ax.plot(curves.mean_trials, 100 * curves.mean_success, color=color, lw=2.2)
    # Legend: what a thin line, the thick line and a diamond are.
    ax.plot(
        [], [], **thin, label=f"one seed ({cfg.eval_trials} test trials every {cfg.eval_every})"
    )
    ax.plot([], [], color=color, lw=2.2, label=f"mean of {len(curves.seeds)} seeds")
    ax.plot([], [], "D", **diamond, label=f"final test ({cfg.test_trials} trials)")
    paper = _PAPER_SUCCESS.get(cfg.name)
    if paper is not None:
        ax.axhline(
            100 * paper, color="0.2", linestyle="--", lw=1.0, label=f"paper: {100 * paper:.0f}%"
        )
    ax.set_ylim(-3, 103)
    ax.set_title(
        f"{label}: {cfg.network.n_features} feature units, {cfg.network.rule} rule", fontsize=10
    )
    ax.legend(fontsize=7, loc="lower right", framealpha=0.9)


def _actions_panel(ax, curves: LearningCurves, color) -> None:
    """Mean actions of the successful test trials: a thin line per seed, the mean thick, the
    step limit dotted."""
    max_steps = curves.config.world.max_steps
    for k in range(len(curves.seeds)):
        ax.plot(curves.trials[k], curves.steps[k], color=color, alpha=0.35, lw=0.8)
    ax.plot(curves.mean_trials, curves.mean_steps, color=color, lw=2.2)
    ax.axhline(max_steps, color="0.2", linestyle=":", lw=1.0, label=f"step limit ({max_steps})")
    ax.set_ylim(0, max_steps + 2)
    ax.legend(fontsize=7, loc="center right", framealpha=0.9)


def _curriculum_panel(ax, curves: LearningCurves, color) -> None:
    """The start region during training (the seeds share the configuration's curriculum)."""
    world = curves.config.world
    trials = np.arange(len(curves.start_far[0]))
    ax.fill_between(
        trials, world.start_near, curves.start_far[0], color=color, alpha=0.2, lw=0, step="post"
    )
    for start_far in curves.start_far:
        ax.plot(np.arange(len(start_far)), start_far, color=color, lw=1.0, drawstyle="steps-post")
    ax.set_ylim(0, world.start_far * 1.15)
    ax.set_xlabel("training trials")


def fig_trial(config: WorldConfig, poses: np.ndarray, title: str, color="green") -> Figure:
    """One trial seen from above (``poses``: rows ``[x, y, yaw]``) on the floor plan, framed
    to the start region and the sideboard: the path, an arrow at each pose pointing where
    the robot faces, and a legend of every mark."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    poses = np.asarray(poses, dtype=float)
    region = StartRegion.of(config)
    fig = _new_figure(6.4, 6.8)
    ax = fig.add_subplot()
    draw_floor_plan(ax, config, region)
    draw_trajectory(ax, poses, color)
    length = 0.08  # m: the arrows' length on the plan
    ax.quiver(
        poses[:, 1],
        poses[:, 0],
        length * np.sin(poses[:, 2]),
        length * np.cos(poses[:, 2]),
        angles="xy",
        scale_units="xy",
        scale=1.0,
        color="0.15",
        width=0.006,
        headwidth=3.5,
        zorder=5,
    )
    ax.set_title(title)
    ax.set_ylim(-region.far - 0.1, _plan_extent(config)[2] + 0.05)
    ax.set_xlim(region.half_width(region.far) + 0.1, -region.half_width(region.far) - 0.1)
    handles = [
        Line2D([], [], color=color, marker=".", lw=1.1, label="path (a dot after each step)"),
        Line2D([], [], ls="none", marker="o", mfc="white", mec=color, label="start pose"),
        Line2D([], [], ls="none", marker=r"$\uparrow$", color="0.15", ms=9, label="heading"),
        Patch(facecolor=_DOCK_YELLOW, edgecolor="0.3", label="docking region"),
        Patch(fill=False, linestyle="--", edgecolor="0.45", label="start region"),
        Patch(facecolor=_LANDMARK_RED, label="landmark"),
    ]
    if "sideboard" in floor_plan(config):
        handles.append(Patch(facecolor=_SIDEBOARD_GREY, edgecolor="0.4", label="sideboard"))
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return fig


def fig_rewards(curves: LearningCurves, headline_seed: int, paper_rewards: float = 25) -> Figure:
    """Greedy test success against the rewarded training trials so far, one line per seed (the
    headline seed thick), with the paper's "about 25" rewards dotted (Experiment 1's measure
    of learning speed; not a figure of the paper)."""
    fig = _new_figure(7.0, 3.2)
    ax = fig.add_subplot()
    for seed, rewarded, success in zip(curves.seeds, curves.rewarded, curves.success, strict=True):
        ax.plot(
            rewarded,
            100 * success,
            lw=2.5 if seed == headline_seed else 0.8,
            label=f"seed {seed}" + (" (headline)" if seed == headline_seed else ""),
        )
    ax.axvline(paper_rewards, color="k", ls=":", lw=1)
    ax.text(paper_rewards + 0.5, 5, f"paper: ~{paper_rewards:g} rewards", fontsize=8)
    ax.set_xlabel("rewarded training trials so far")
    ax.set_ylabel("greedy test success (%)")
    ax.set_ylim(0, 102)
    ax.legend(fontsize=7, ncol=3)
    return fig


# ------------------------------------------------------------------------------------------
# Experiment 3 (notebook 06).
# ------------------------------------------------------------------------------------------


def _experiment3_points(
    ax,
    t: int,
    k: int,
    label: str,
    x: np.ndarray,
    offset: float,
    values: np.ndarray,
    seeds: dict[str, np.ndarray],
    oracle: dict[str, np.ndarray],
) -> None:
    """The ``k``-th action set in task ``t``'s panel of :func:`fig_experiment3`: learner, oracle."""
    color = f"C{k}"
    mean, low, high = (100 * np.asarray(values)[t, :, i] for i in range(3))
    ax.errorbar(
        x,
        mean,
        yerr=(mean - low, high - mean),
        fmt="o",
        color=color,
        ms=5,
        capsize=3,
        label=f"{label}: learner",
        zorder=3,
    )
    points = 100 * np.asarray(seeds[label])[t]
    for n in range(len(x)):
        jitter = np.linspace(-0.06, 0.06, points.shape[1])
        ax.plot(x[n] + jitter, points[n], ".", color=color, ms=3, alpha=0.5)
    # Each action set's oracle beside its learner (not at the tick), so that equal
    # bounds (both at 100%) stay two visible diamonds.
    ax.plot(
        x + 0.5 * offset,
        100 * np.asarray(oracle[label])[t],
        "--",
        marker="D" if k == 0 else "s",
        mfc="none",
        mew=1.3,
        color=color,
        lw=0.9,
        ms=6,
        label=f"{label}: oracle (the bound)",
    )


def fig_experiment3(
    noise: np.ndarray,
    tasks: list[str],
    series: dict[str, np.ndarray],
    seeds: dict[str, np.ndarray],
    oracle: dict[str, np.ndarray],
) -> Figure:
    """Experiment 3: held-out success against heading noise, one panel per task.

    Args:
      noise: The heading noises (deg), the x axis.
      tasks: Panel titles, one per task.
      series: ``{action set label: (tasks, noises, 3)}`` mean, low, high of the held-out
        success (fractions), drawn as points with 95% interval bars.
      seeds: ``{action set label: (tasks, noises, seeds)}`` per-seed success (dots).
      oracle: ``{action set label: (tasks, noises)}`` the pose-reading oracle's success with
        that action set (open markers, one shape per action set, joined by a dashed line:
        the bound), drawn beside its learner's points.
    """
    noise = np.asarray(noise, dtype=float)
    for label, values in series.items():
        if np.shape(values) != (len(tasks), len(noise), 3):
            raise ValueError(f"fig_experiment3: series {label!r} has shape {np.shape(values)}")
    fig = _new_figure(5.0 * len(tasks), 3.8)
    axes = np.atleast_1d(fig.subplots(1, len(tasks), sharey=True))
    offsets = np.linspace(-0.18, 0.18, len(series))
    for t, (ax, task) in enumerate(zip(axes, tasks, strict=True)):
        for k, (label, values) in enumerate(series.items()):
            _experiment3_points(
                ax, t, k, label, noise + offsets[k], offsets[k], values, seeds, oracle
            )
        ax.set_title(task, fontsize=10)
        ax.set_xticks(noise, [f"{v:g}" for v in noise])
        ax.set_xlabel("heading noise per step (deg)")
        ax.grid(alpha=0.3, lw=0.5)
    axes[0].set_ylabel("held-out success (%)")
    axes[0].set_ylim(0, 101)
    axes[-1].legend(fontsize=7, loc="lower left")
    return fig


def fig_failure_matrix(
    cell_labels: list[str], classes: list[str], shares: np.ndarray, failures: list[int]
) -> Figure:
    """The failure taxonomy of many cells as a table of shades: row = cell, column = class,
    the share of the cell's failed trials in the class written in each square (classes
    overlap, so a row need not sum to 100%)."""
    shares = np.asarray(shares, dtype=float)
    if shares.shape != (len(cell_labels), len(classes)) or len(failures) != len(cell_labels):
        raise ValueError(f"fig_failure_matrix: shares {shares.shape} for {len(cell_labels)} cells")
    fig = _new_figure(1.15 * len(classes) + 3.6, 0.34 * len(cell_labels) + 1.6)
    ax = fig.subplots()
    ax.imshow(100 * shares, cmap="Reds", vmin=0, vmax=100, aspect="auto")
    for i in range(shares.shape[0]):
        for j in range(shares.shape[1]):
            value = 100 * shares[i, j]
            text = "-" if np.isnan(value) else f"{value:.0f}"
            ax.text(
                j,
                i,
                text,
                ha="center",
                va="center",
                fontsize=7,
                color="white" if value > 60 else "black",
            )
    ax.set_xticks(
        range(len(classes)),
        [c.replace("_", " ") for c in classes],
        fontsize=8,
        rotation=20,
        ha="right",
    )
    ax.set_yticks(
        range(len(cell_labels)),
        [f"{label} ({n} failures)" for label, n in zip(cell_labels, failures, strict=True)],
        fontsize=8,
    )
    ax.set_title(
        "share of failed held-out trials in each class (%); classes overlap (a failure can "
        "fall in several), so a row need not sum to 100",
        fontsize=8,
    )
    return fig


def fig_action_fields(
    letters: list[str],
    action_rf: np.ndarray,
    action_mean: np.ndarray,
    counts: np.ndarray,
    title: str,
) -> Figure:
    """What each action unit reads (Fig. 3/4 style), one column per action: above, its
    receptive field ``sum_j Q_ij W_j``; below, the mean network input of the views on which
    it is the greedy action (with how many views)."""
    n = len(letters)
    if action_rf.shape[0] != n or action_mean.shape[0] != n or len(counts) != n:
        raise ValueError("fig_action_fields: one field, mean input and count per action")
    fig = _new_figure(1.9 * n + 0.6, 2.6)
    fig.suptitle(title, fontsize=10)
    axes = fig.subplots(2, n)
    for i, letter in enumerate(letters):
        _weight_map(axes[0, i], action_rf[i], letter, title_size=11)
        _image(axes[1, i], action_mean[i], vmax=1.0)
        axes[1, i].set_xlabel(f"greedy on {int(counts[i])} views", fontsize=7, color="0.3")
    axes[0, 0].set_ylabel("field", fontsize=8)
    axes[1, 0].set_ylabel("mean input", fontsize=8)
    return fig


# ------------------------------------------------------------------------------------------
# The study's third edition and the untested claims (notebooks 07 and 08).
# ------------------------------------------------------------------------------------------


def fig_contest(
    worlds: list[str],
    columns: list[str],
    seeds: dict[tuple[str, str], np.ndarray],
    trials: int = 500,
) -> Figure:
    """The fair contest: held-out success per world (one panel each) of every learner and
    yardstick of ``columns`` (left to right), each seed a dot, the mean a bar with its 95%
    interval for a rate (:func:`docking.study.stats.rate_ci`, ``trials`` held-out trials per seed).

    Args:
      worlds: Panel titles.
      columns: Labels of the learners and yardsticks, in order; a label ending in "tuned"
        is drawn filled, "untuned" hatched, the yardsticks grey.
      seeds: ``{(world, column): per-seed success (fractions)}``; a pair absent is left out.
      trials: Held-out trials per seed.
    """
    from docking.study.stats import rate_ci

    fig = _new_figure(4.2 * len(worlds), 4.4)
    axes = np.atleast_1d(fig.subplots(1, len(worlds), sharey=True))
    x = np.arange(len(columns))
    learners = {}
    for ax, world in zip(axes, worlds, strict=True):
        for k, label in enumerate(columns):
            values = seeds.get((world, label))
            if values is None or not len(values):
                continue
            base = label.replace(", untuned", "").replace(", tuned", "")
            color = learners.setdefault(base, f"C{len(learners)}") if "tuned" in label else "0.6"
            ci = rate_ci(values, trials) if len(values) > 1 else None
            mean = 100 * float(np.mean(values))
            ax.bar(
                k,
                mean,
                color=color if not label.endswith("untuned") else "white",
                edgecolor=color,
                hatch="///" if label.endswith("untuned") else None,
                lw=1.2,
                alpha=0.85,
            )
            if ci is not None:
                ax.errorbar(
                    k,
                    mean,
                    yerr=[[mean - 100 * ci.low], [100 * ci.high - mean]],
                    color="black",
                    capsize=3,
                    lw=1,
                )
            jitter = np.linspace(-0.25, 0.25, len(values))
            ax.plot(k + jitter, 100 * np.asarray(values), ".", color="black", ms=3, alpha=0.6)
        ax.set_title(world, fontsize=10)
        ax.set_xticks(x, columns, rotation=60, ha="right", fontsize=8)
        ax.grid(axis="y", alpha=0.3, lw=0.5)
        ax.set_ylim(0, 103)
    axes[0].set_ylabel("held-out success (%), each seed a dot")
    return fig


def _verdict_bounds(ax, p: dict) -> None:
    """The lines behind a claim's panel of :func:`fig_verdicts`: margin, bound, reference."""
    s = p["scale"]
    if p.get("band") is not None:
        ax.axvspan(s * p["band"][0], s * p["band"][1], color="0.9", zorder=0)
    ax.axvline(s * p["bound"], color="0.25", lw=0.9, ls="--", zorder=1)
    if p.get("reference") is not None:  # (value, label): e.g. another learner's level
        value, label = p["reference"]
        ax.axvline(s * value, color="C0", lw=1.2, ls=":", zorder=1)
        ax.annotate(
            label,
            (s * value, 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(3, -9),
            textcoords="offset points",
            fontsize=7,
            color="C0",
        )


def _verdict_panel(ax, p: dict, title: str, colours: dict[str, str]) -> None:
    """One claim's panel of :func:`fig_verdicts`: a row per comparison, over its bound lines."""
    s, rows = p["scale"], p["rows"]
    y = np.arange(len(rows))[::-1].astype(float)
    _verdict_bounds(ax, p)
    for yk, (_, ci, verdict, per_seed) in zip(y, rows, strict=True):
        color = colours.get(verdict, "C0")
        if per_seed is not None:
            jitter = np.linspace(-0.2, 0.2, len(per_seed))
            ax.plot(s * np.asarray(per_seed), yk + jitter, ".", color=color, ms=3, alpha=0.5)
        ax.plot([s * ci.low, s * ci.high], [yk, yk], color=color, lw=3, solid_capstyle="butt")
        ax.plot(s * ci.estimate, yk, "o", color=color, ms=6, mec="black", mew=0.6, zorder=3)
    ax.set_yticks(y, [f"{r[0]}: {r[2]}" for r in rows], fontsize=8)
    ax.set_ylim(-0.7, len(rows) - 0.3)
    ax.set_title(title, loc="left", fontsize=9)
    ax.set_xlabel(p["xlabel"], fontsize=8)
    ax.tick_params(axis="x", labelsize=8)
    ax.grid(axis="x", alpha=0.3, lw=0.5)


def fig_verdicts(panels: list[dict]) -> Figure:
    """A study's verdicts, one panel per claim: per comparison the 95% interval of its
    statistic (a bar, the estimate a dot), each seed's paired value (small dots) where the
    statistic has one per seed, the rule's bound (a dashed line) or margin (shaded), coloured
    by the decision.

    Args:
      panels: One dict per claim, top to bottom, with ``title`` (str), ``xlabel`` (the
        statistic and its unit), ``scale`` (the factor from the statistic to the axis, e.g.
        100 for a difference of success rates drawn in percentage points), ``bound``
        (float), ``band`` (``(low, high)`` or None, shaded), and ``rows``: ``(label,
        interval, verdict, per_seed)`` with a :class:`docking.study.stats.Interval`, a verdict
        string (:data:`docking.study.claims.VERDICT_COLOURS`; a finding is blue) and the per-seed
        values or None; optionally ``reference``, ``(value, label)``, drawn dotted (e.g.
        where another learner stands).
    """
    from docking.study.claims import VERDICT_COLOURS

    if not panels:
        raise ValueError("fig_verdicts needs at least one panel")
    # titles wrapped to the axes' width (long labels on the left narrow it)
    titles = [textwrap.fill(p["title"], width=85) for p in panels]
    heights = [
        len(p["rows"]) + 1.6 + 0.6 * t.count("\n") for p, t in zip(panels, titles, strict=True)
    ]
    fig = _new_figure(9.5, 0.36 * sum(heights) + 0.6)
    axes = np.atleast_1d(fig.subplots(len(panels), 1, height_ratios=heights))
    for ax, p, title in zip(axes, panels, titles, strict=True):
        _verdict_panel(ax, p, title, VERDICT_COLOURS)
    fig.suptitle(
        "each comparison: its 95% interval (bar), estimate (circle) and seeds (dots), "
        "coloured by the decision; dashed: the rule's bound; grey: its margin",
        fontsize=8.5,
        color="0.3",
    )
    return fig


def fig_coping(
    changes: list[str],
    curves: dict[tuple[str, str, str], tuple[np.ndarray, np.ndarray]],
    levels: dict[str, float],
) -> Figure:
    """Coping with change: per change (one panel each), the learning curves (greedy test
    success against training trials, mean over seeds) of a fresh network (dashed) and of the
    home network learning on (solid), per learner (a colour each), with the level each
    learner must regain (dotted: a share of its home success).

    Args:
      changes: Panel titles, left to right.
      curves: ``{(change, learner, "fresh" | "relearn"): (trials, success)}`` with
        ``success`` of shape ``(seeds, points)``.
      levels: ``{learner: the level to regain}`` (fractions).
    """
    if not changes or not curves:
        raise ValueError("fig_coping needs at least one change and one curve")
    fig = _new_figure(3.8 * len(changes) + 0.4, 3.6)
    axes = np.atleast_1d(fig.subplots(1, len(changes), sharey=True))
    colours = {learner: f"C{k}" for k, learner in enumerate(levels)}
    for ax, change in zip(axes, changes, strict=True):
        for (c, learner, kind), (trials, success) in curves.items():
            if c != change:
                continue
            ax.plot(
                trials,
                100 * np.mean(success, axis=0),
                color=colours[learner],
                ls="-" if kind == "relearn" else "--",
                lw=1.6,
                label=f"{learner}, {'home network learning on' if kind == 'relearn' else 'fresh'}",
            )
        for learner, level in levels.items():
            ax.axhline(100 * level, color=colours[learner], lw=0.8, ls=":")
        ax.set_title(change, fontsize=10)
        ax.set_xlabel("training trials in the changed world")
        ax.grid(alpha=0.3, lw=0.5)
        ax.set_ylim(0, 103)
    axes[0].set_ylabel("greedy test success (%), mean over seeds")
    axes[0].legend(fontsize=7, loc="lower right")
    return fig


def fig_decomposition(
    worlds: list[str], columns: list[str], seeds: dict[tuple[str, str], np.ndarray], split: dict
) -> Figure:
    """Which part of the paper's learner breaks: per world (a panel), held-out success of
    each column (a bar with its mean, each seed a dot), and two arrows beside the paper's
    learner: from linear SARSA down to its own W with the best-labelled Q (what the
    representation loses), and from there down to the Q it learned (what learning Q loses).

    Args:
      worlds: Panel titles.
      columns: Bar labels, left to right; the first three are linear SARSA, the paper's W
        with the oracle-labelled Q, and the paper's learner.
      seeds: ``{(world, column): per-seed success (fractions)}``.
      split: ``{world: (representation, learning Q)}`` in percentage points; a world
        absent has no arrows.
    """
    fig = _new_figure(4.6 * len(worlds), 4.6)
    axes = np.atleast_1d(fig.subplots(1, len(worlds), sharey=True))
    colors = ("C0", "C2", "C1", "0.55", "0.75")
    for ax, world in zip(axes, worlds, strict=True):
        means = []
        for k, label in enumerate(columns):
            values = 100 * np.asarray(seeds[world, label])
            means.append(float(values.mean()))
            ax.bar(k, means[-1], color=colors[k % len(colors)], alpha=0.85)
            ax.plot(k + np.linspace(-0.25, 0.25, len(values)), values, ".", color="k", ms=3)
            ax.text(k, means[-1] + 1.5, f"{means[-1]:.0f}%", ha="center", fontsize=8)
        ax.set_title(world, fontsize=10)
        representation, learning_q = split.get(world, (None, None))
        for top, bottom, text, x in (
            (means[0], means[1], f"representation\n{representation} pp", 0.5),
            (means[1], means[2], f"learning Q\n{learning_q} pp", 1.5),
        ):
            if world not in split:
                break
            ax.annotate(
                "", (x, bottom), (x, top), arrowprops=dict(arrowstyle="->", color="k", lw=1.2)
            )
            ax.text(x + 0.06, (top + bottom) / 2, text, fontsize=8, va="center")
        ax.set_xticks(np.arange(len(columns)), columns, rotation=35, ha="right", fontsize=8)
        ax.grid(axis="y", alpha=0.3, lw=0.5)
        ax.set_ylim(0, 105)
    axes[0].set_ylabel("held-out success (%), each seed a dot")
    return fig


def _glance_yardsticks(
    ax, i: int, world: str, names: list[str], yardsticks: dict[tuple[str, str], float]
) -> None:
    """World ``i``'s yardsticks in :func:`fig_glance`: each one's mean a line across the group."""
    styles = ("--", ":", "-.", (0, (1, 3)))
    for j, name in enumerate(names):
        if (world, name) in yardsticks:
            value = 100 * yardsticks[world, name]
            ax.plot(
                [i - 0.45, i + 0.45],
                [value, value],
                color="0.35",
                lw=1.1,
                ls=styles[j % len(styles)],
                label=name if i == 0 else None,
            )


def _glance_learners(
    ax,
    i: int,
    world: str,
    learners: list[str],
    seeds: dict[tuple[str, str], np.ndarray],
    trials: int,
) -> None:
    """World ``i``'s learners in :func:`fig_glance`: the seeds' dots, the mean and its interval."""
    from docking.study.stats import rate_ci

    width = 0.8 / max(len(learners), 1)
    markers = "oDs^v"
    for k, learner in enumerate(learners):
        values = seeds.get((world, learner))
        if values is None:
            continue
        x = i - 0.4 + width * (k + 0.5)
        values = 100 * np.asarray(values)
        ax.plot(np.full(len(values), x), values, ".", color=f"C{k}", alpha=0.3, ms=4)
        ci = rate_ci(values / 100, trials)
        ax.errorbar(
            x,
            values.mean(),
            yerr=[[values.mean() - 100 * ci.low], [100 * ci.high - values.mean()]],
            fmt=markers[k % len(markers)],
            color=f"C{k}",
            ms=7,
            capsize=3,
            label=learner if i == 0 else None,
        )


def fig_glance(
    worlds: list[str],
    learners: list[str],
    seeds: dict[tuple[str, str], np.ndarray],
    yardsticks: dict[tuple[str, str], float],
    trials: int = 500,
) -> Figure:
    """The answer at a glance: per world (a group on the x axis), each learner's held-out
    success (its mean as a marker with the 95% interval for a rate over its seeds'
    ``trials`` held-out trials each, :func:`docking.study.stats.rate_ci`; each seed a
    faint dot) and each yardstick's mean as a line across the group (one style each, in the
    legend).

    Args:
      worlds: The worlds, left to right (their labels).
      learners: The learners, in the legend's order.
      seeds: ``{(world, learner): per-seed success (fractions)}``; absent pairs are skipped.
      yardsticks: ``{(world, yardstick): mean success (fraction)}``.
      trials: Held-out trials per seed.
    """
    fig = _new_figure(7.6, 2.7)
    ax = fig.subplots()
    names = list(dict.fromkeys(y for _, y in yardsticks))
    for i, world in enumerate(worlds):
        _glance_yardsticks(ax, i, world, names, yardsticks)
        _glance_learners(ax, i, world, learners, seeds, trials)
    ax.set_xticks(range(len(worlds)), worlds, fontsize=9)
    ax.set_xlim(-0.5, len(worlds) - 0.5)
    ax.set_ylim(0, 104)
    ax.set_ylabel("held-out success (%)")
    ax.grid(axis="y", alpha=0.3, lw=0.5)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.25), ncol=3, fontsize=8, frameon=False)
    return fig


def _inch_canvas(width: float, height: float):
    """A figure on the Agg canvas with one frameless axes over it, in inches, y downwards."""
    fig = Figure(figsize=(width, height))  # inches as data units
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, width)
    ax.set_ylim(height, 0)
    ax.axis("off")
    return fig, ax


def _claim_box(
    ax,
    corner: tuple[float, float],
    size: tuple[float, float],
    colour: str,
    heading: str,
    interval: str,
) -> None:
    """One comparison's box in :func:`fig_claims`: a tinted rounded box, two lines of text."""
    left, y0 = corner
    ax.add_patch(
        FancyBboxPatch(
            (left, y0),
            *size,
            boxstyle="round,pad=0.0,rounding_size=0.06",
            facecolor=colour,
            alpha=0.22,
            edgecolor=colour,
        )
    )
    ax.text(left + 0.06, y0 + 0.14, heading, fontsize=7, va="center")
    ax.text(left + 0.06, y0 + 0.31, interval, fontsize=7, va="center", color="0.2")


def fig_claims(rows: list[tuple]) -> Figure:
    """The paper's claims at a glance: one row per claim (its key and the bound its rule
    tests, left), one box per comparison (its world or setting, its 95% interval, its
    decision; three boxes a line), coloured by the decision; a claim outside the counts is
    greyed, with why. As wide as a page (``_PAGE_WIDTH_IN``), so that it can be read where a
    page shows it.

    Args:
      rows: :func:`docking.study.report.claims_glance_rows`' rows.
    """
    from docking.study.claims import VERDICT_COLOURS

    if not rows:
        raise ValueError("fig_claims needs at least one claim")
    label_w, box_w, gap, per_line, line_h = 1.95, 1.78, 0.06, 3, 0.5
    notes = [
        textwrap.fill(f"outside the counts: {note}" if note else bound, 34)
        for _, bound, _, note in rows
    ]
    heights = [
        max(line_h * int(np.ceil(len(comparisons) / per_line)), 0.24 + 0.115 * (n.count("\n") + 1))
        + 0.12
        for (_, _, comparisons, _), n in zip(rows, notes, strict=True)
    ]
    top = 0.55  # the title
    fig, ax = _inch_canvas(_PAGE_WIDTH_IN, top + sum(heights))
    y = top
    for (key, _, comparisons, note), wrapped, height in zip(rows, notes, heights, strict=True):
        ax.text(0.08, y + 0.14, key, fontsize=9, weight="bold", va="center")
        ax.text(0.08, y + 0.3, wrapped, fontsize=6.5, va="top", color="0.35", linespacing=1.05)
        for k, (label, interval, verdict) in enumerate(comparisons):
            colour = "0.75" if note else VERDICT_COLOURS.get(verdict, "C0")
            left = label_w + (box_w + gap) * (k % per_line)
            y0 = y + 0.04 + line_h * (k // per_line)
            _claim_box(
                ax, (left, y0), (box_w, line_h - 0.08), colour, f"{label}: {verdict}", interval
            )
        y += height
        ax.axhline(y - 0.04, color="0.88", linewidth=0.6)
    ax.text(
        0.08,
        0.08,
        "The paper's claims, judged on fresh seeds (rules committed before the runs):\neach "
        "box one comparison, its 95% interval and decision",
        fontsize=9,
        va="top",
    )
    return fig


# ------------------------------------------------------------------------------------------
# An episode as an animation (the site's page of the worlds, as Gymnasium's environment pages).
# ------------------------------------------------------------------------------------------


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


def episode_gif(
    world: WorldConfig,
    path,
    seed: int = 0,
    width: int = 320,
    height: int = 240,
    step_ms: int = 450,
    max_frames: int | None = None,
    label: str = "",
) -> Path:
    """Write one episode of the pose oracle in ``world`` (:func:`episode_frames`) as an
    animated GIF at ``path`` (one frame per action, ``step_ms`` each, the last held three
    times as long), each frame captioned with ``label``, the step and the action taken, and
    at the end whether the robot docked; the written path.

    The oracle reads the robot's true pose: the animation shows the task and its world, not
    what a learner does. Drawn with Pillow (matplotlib's own dependency)."""
    from PIL import Image, ImageDraw, ImageFont

    frames, actions, docked = episode_frames(world, seed, width, height, max_frames)
    try:  # Pillow >= 10.1: its own scalable font; before, a small bitmap one
        font = ImageFont.load_default(size=max(10, height // 18))
    except TypeError:  # pragma: no cover
        font = ImageFont.load_default()
    images = []
    for k, frame in enumerate(frames):
        image = Image.fromarray(frame)
        draw = ImageDraw.Draw(image)
        if k == 0:
            text = "start"
        else:
            text = f"step {k}: {world.action_names[actions[k - 1]]}"
        if k == len(frames) - 1 and len(frames) != max_frames:  # the episode's end
            text += ", docked" if docked else ", not docked"
        for line, y in ((label, 4), (text, 6 + max(10, height // 18))):
            if line:
                draw.text((6, y + 1), line, fill=(255, 255, 255), font=font)
                draw.text((5, y), line, fill=(20, 20, 20), font=font)
        images.append(image.quantize(colors=128, method=Image.Quantize.MAXCOVERAGE, dither=0))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    durations = [step_ms] * (len(images) - 1) + [3 * step_ms]
    images[0].save(
        path,
        save_all=True,
        append_images=images[1:],
        duration=durations,
        loop=0,
        optimize=True,
    )
    return path


def fig_landscape(
    panels: list[dict],
    marks: dict[tuple[str, str], list[tuple[str, tuple[float, float]]]] | None = None,
) -> Figure:
    """Success over two tuning knobs, one heat map a panel (rows of panels: worlds; columns:
    learners), each evaluated setting coloured by its mean held-out success and labelled with
    it (and its runs, ``n``), settings never run left blank; marks (a star, a circle) at named
    settings.

    Args:
      panels: Each ``{"world", "learner", "title", "row_label", "col_label", "grid"}`` with
        ``grid`` a :class:`docking.study.analysis.Landscape` (rows: the y axis, bottom up).
      marks: ``{(world, learner): [(label, (row value, column value)), ...]}``; the first
        label of each kind gets a star, the second a circle (in the legend).
    """
    worlds = list(dict.fromkeys(p["world"] for p in panels))
    learners = list(dict.fromkeys(p["learner"] for p in panels))
    fig = _new_figure(3.7 * len(learners), 3.0 * len(worlds) + 0.6)
    axes = fig.subplots(len(worlds), len(learners), squeeze=False)
    image = None
    for p in panels:
        ax = axes[worlds.index(p["world"])][learners.index(p["learner"])]
        image = _landscape_panel(ax, p)
        for k, (label, (r, c)) in enumerate((marks or {}).get((p["world"], p["learner"]), [])):
            grid = p["grid"]
            y = float(np.interp(np.log(r), np.log(grid.rows), np.arange(len(grid.rows))))
            x = float(np.interp(np.log(c), np.log(grid.cols), np.arange(len(grid.cols))))
            ax.scatter(
                [x],
                [y],
                s=260,
                marker="*" if k == 0 else "o",
                facecolors="none",
                edgecolors="#d62728" if k == 0 else "#1f77b4",
                linewidths=1.8,
                label=label,
            )
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="lower right", fontsize=6.5, framealpha=0.85)
    if image is not None:
        fig.colorbar(image, ax=axes, shrink=0.6, label="held-out success (%)")
    return fig


def _landscape_panel(ax, panel: dict):
    """One heat map of :func:`fig_landscape`; returns its image (for the colour bar)."""
    grid = panel["grid"]
    image = ax.imshow(
        100 * grid.mean,
        origin="lower",
        cmap="viridis",
        vmin=0,
        vmax=100,
        interpolation="nearest",
        aspect="auto",
    )
    for i in range(len(grid.rows)):
        for j in range(len(grid.cols)):
            if grid.n[i, j]:
                value = 100 * grid.mean[i, j]
                ax.text(
                    j,
                    i,
                    f"{value:.0f}\n{grid.n[i, j]}",
                    ha="center",
                    va="center",
                    fontsize=6,
                    color="black" if value > 60 else "white",
                )
    ax.set_xticks(range(len(grid.cols)), [f"{c:g}" for c in grid.cols], fontsize=7)
    ax.set_yticks(range(len(grid.rows)), [f"{r:g}" for r in grid.rows], fontsize=7)
    ax.set_xlabel(panel["col_label"], fontsize=8)
    ax.set_ylabel(panel["row_label"], fontsize=8)
    ax.set_title(panel["title"], fontsize=8.5)
    return image
