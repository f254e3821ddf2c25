"""What every figure shares: saving (:func:`save_figure`, ``.png`` and ``.pdf``;
:func:`to_png`), the page's width and the house's colours, a new figure on the Agg canvas,
panel letters, images of weights and inputs with their scale, the crop rectangle, and the
floor plan a path is drawn on (:func:`draw_floor_plan`, :func:`draw_trajectory`)."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
from matplotlib import patheffects
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Polygon, Rectangle

from docking.camera import CameraConfig
from docking.fileio import atomic_write
from docking.region import StartRegion
from docking.scene import ACTION_LETTERS, WorldConfig
from docking.study.paths import figures_dir

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
    whose bytes (Fig. 4's) changed on every run.

    The layout is computed by a draw that renders nothing (``draw_without_rendering``) on
    the renderer saving uses, at the saving resolution (``_DPI``): the text it measures, and
    so the positions, are those a saved PNG's draw gives, at a fraction of its cost."""
    dpi = fig.dpi
    fig.set_dpi(_DPI)
    try:
        fig.draw_without_rendering()
    finally:
        fig.set_dpi(dpi)
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


def draw_floor_plan(ax, plan: dict, start_region: StartRegion) -> None:
    """Draw the floor plan ``plan`` (rectangles ``(x0, y0, x1, y1)`` by name,
    :func:`docking.study.analysis.floor_plan` of the world) on ``ax`` (horizontal: y, inverted;
    vertical: x): the grey sideboard, the landmark's red boxes, the yellow docking region and,
    dashed, the start trapezoid ``start_region`` (``StartRegion.of(world)`` for the world's)."""
    fp = plan
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
    corners = start_region.corners()[:, ::-1]  # (y, x): y is the horizontal axis
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


def _plan_extent(plan: dict) -> tuple[float, float, float]:
    """``(y_min, y_max, x_max)`` over the floor plan's rectangles (m): how far the furniture
    and the landmark reach across and beyond the landmark's front."""
    rects = np.array(list(plan.values()))
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


def _inch_canvas(width: float, height: float):
    """A figure on the Agg canvas with one frameless axes over it, in inches, y downwards."""
    fig = Figure(figsize=(width, height))  # inches as data units
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, width)
    ax.set_ylim(height, 0)
    ax.axis("off")
    return fig, ax
