"""The study's figures: Experiment 3's, the third edition's contest, verdicts and claims at a
glance, coping after a change, the addendum's decomposition, the README's first screen, the
fragility landscape, and an episode's frames captioned for an animation (computed by
:mod:`docking.study.episodes`)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import FancyBboxPatch

from docking.study.figures.common import (
    _PAGE_WIDTH_IN,
    _image,
    _inch_canvas,
    _new_figure,
    _weight_map,
)


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
    worlds: list[str], columns: list[str], seeds: dict[tuple[str, str], np.ndarray]
) -> Figure:
    """Which part of the paper's learner breaks: per world (a panel), held-out success of
    each column (a bar with its mean, each seed a dot).

    Args:
      worlds: Panel titles.
      columns: Bar labels, left to right.
      seeds: ``{(world, column): per-seed success (fractions)}``.
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
            # the mean at the bar's foot, where no seed's dot (or the bar's top) hides it
            ax.text(k, 2, f"{means[-1]:.0f}%", ha="center", va="bottom", fontsize=8)
        ax.set_title(world, fontsize=10)
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
      rows: :func:`docking.study.designs.third_edition_report.claims_glance_rows`' rows.
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


def episode_images(
    frames: list[np.ndarray],
    actions: list[int],
    docked: bool,
    action_names: tuple[str, ...],
    ended: bool = True,
    label: str = "",
) -> list:
    """One episode's ``frames`` (:func:`docking.study.episodes.episode_frames`: RGB arrays,
    one per pose) as images for an animation, each captioned with ``label``, the step and the
    action taken (``action_names[actions[k - 1]]``), and the last, if the episode ``ended``
    there, with whether the robot ``docked``. Drawn with Pillow (matplotlib's own
    dependency); nothing is rendered or computed here."""
    from PIL import Image, ImageDraw, ImageFont

    height = frames[0].shape[0]
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
            text = f"step {k}: {action_names[actions[k - 1]]}"
        if k == len(frames) - 1 and ended:  # the episode's end
            text += ", docked" if docked else ", not docked"
        for line, y in ((label, 4), (text, 6 + max(10, height // 18))):
            if line:
                draw.text((6, y + 1), line, fill=(255, 255, 255), font=font)
                draw.text((5, y), line, fill=(20, 20, 20), font=font)
        images.append(image.quantize(colors=128, method=Image.Quantize.MAXCOVERAGE, dither=0))
    return images


def save_gif(images: list, path, step_ms: int = 450) -> Path:
    """Write ``images`` (:func:`episode_images`) as an animated GIF at ``path``, ``step_ms``
    each, the last held three times as long; the written path."""
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
        ``grid`` a :class:`docking.study.arrays.Landscape` (rows: the y axis, bottom up).
      marks: ``{(world, learner): [(label, (row value, column value)), ...]}``; the first
        label of each kind gets a star, the second a circle (in the legend).
    """
    worlds = list(dict.fromkeys(p["world"] for p in panels))
    learners = list(dict.fromkeys(p["learner"] for p in panels))
    fig = _new_figure(3.7 * len(learners), 3.5 * len(worlds) + 0.6)
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
            ax.legend(  # below the panel, covering no cell
                loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, fontsize=7, frameon=False
            )
    if image is not None:
        fig.colorbar(image, ax=axes, shrink=0.6, label="held-out success (%)")
    fig.suptitle(
        "Each cell: mean held-out success (%) of a setting, above its number of runs "
        "(tuning seeds); blank: never run",
        fontsize=9,
    )
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
