"""The paper's figures (Figs. 2-5) and the learning curves of its experiments, drawn from
arrays (:mod:`docking.study.arrays`' and :mod:`docking.study.analysis`', computed by the
caller); a single trial's path and the rewards to mastery."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Rectangle

from docking.camera import CameraConfig
from docking.region import StartRegion
from docking.scene import WorldConfig, scene_facts
from docking.study.arrays import (
    Decisions,
    ExampleViews,
    LearningCurves,
    MeanInputs,
    TrajectorySample,
    best_actions,
)
from docking.study.figures.common import (
    _DOCK_YELLOW,
    _FAIL_RED,
    _LANDMARK_RED,
    _PAGE_WIDTH_IN,
    _SIDEBOARD_GREY,
    _crop_rectangle,
    _image,
    _new_figure,
    _panel,
    _plan_extent,
    _view_title,
    _weight_map,
    action_order,
    draw_floor_plan,
    draw_trajectory,
)

if TYPE_CHECKING:  # a configuration's fields are read, no run is made
    from docking.experiments import ExperimentConfig


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
        (:func:`docking.study.arrays.decisions`).
      action_rf, feature_rf: :func:`docking.study.arrays.receptive_fields` of the network.
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
      action_rf, feature_rf: :func:`docking.study.arrays.receptive_fields` of the network.
      mean_inputs: :func:`docking.study.analysis.mean_winning_inputs` of the network.
      framed: :func:`docking.study.arrays.strongest_units` of the network.
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


def fig5(
    config: WorldConfig,
    plan: dict,
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
      config, plan: The world (docking and start region), its floor plan (``analysis.floor_plan``).
      sample: The trials to show (:func:`docking.study.arrays.trajectory_sample`).
      label: Names the run in the title, e.g. ``"experiment2, seed 0"``.
      start_region: The start trapezoid to draw; default the config's.
      shade_seed: Seeds the order of the shades of green (so neighbouring paths differ).
    """
    region = start_region if start_region is not None else StartRegion.of(config)
    ok = [m for m in range(len(sample.indices)) if sample.success[m]]
    bad = [m for m in range(len(sample.indices)) if not sample.success[m]]
    paths = dict(enumerate(sample.paths))

    fig, ax = _plan_axes(plan, region, list(paths.values()))

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


def _plan_axes(plan: dict, region: StartRegion, paths: list[np.ndarray]):
    """A figure and its axes for a floor plan seen from above: the plotted area holds the
    floor plan ``plan``, the start region and every path of ``paths``, plus a margin, with one metre
    drawn the same length on both axes and +y (the robot's left) on the left."""
    y_min, y_max, x_max = _plan_extent(plan)
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
    draw_floor_plan(ax, plan, region)
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


# The paper's final test success rates (Sec. III): Experiment 1 100%, Experiment 2 95%.
_PAPER_SUCCESS = {"experiment1": 1.0, "experiment2": 0.95}


def fig_learning_curves(curves1: LearningCurves | None, curves2: LearningCurves | None) -> Figure:
    """Learning curves of both experiments (not a figure of the paper).

    One column per experiment with curves (``None`` skips its column), from
    :func:`docking.study.arrays.learning_curves`. Top: test success rate (greedy trials from the
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


def fig_trial(
    config: WorldConfig, plan: dict, poses: np.ndarray, title: str, color="green"
) -> Figure:
    """One trial seen from above (``poses``: rows ``[x, y, yaw]``) on the floor plan ``plan``
    of the world ``config`` (:func:`docking.study.analysis.floor_plan`), framed to the start
    region and the sideboard: the path, an arrow at each pose pointing where
    the robot faces, and a legend of every mark."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    poses = np.asarray(poses, dtype=float)
    region = StartRegion.of(config)
    fig = _new_figure(6.4, 6.8)
    ax = fig.add_subplot()
    draw_floor_plan(ax, plan, region)
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
    ax.set_ylim(-region.far - 0.1, _plan_extent(plan)[2] + 0.05)
    ax.set_xlim(region.half_width(region.far) + 0.1, -region.half_width(region.far) - 0.1)
    handles = [
        Line2D([], [], color=color, marker=".", lw=1.1, label="path (a dot after each step)"),
        Line2D([], [], ls="none", marker="o", mfc="white", mec=color, label="start pose"),
        Line2D([], [], ls="none", marker=r"$\uparrow$", color="0.15", ms=9, label="heading"),
        Patch(facecolor=_DOCK_YELLOW, edgecolor="0.3", label="docking region"),
        Patch(fill=False, linestyle="--", edgecolor="0.45", label="start region"),
        Patch(facecolor=_LANDMARK_RED, label="landmark"),
    ]
    if "sideboard" in plan:
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
