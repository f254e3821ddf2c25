"""Tests of docking.study.figures: every figure is drawn from the analysis arrays of fresh and
re-loaded results, returns a Figure and writes nothing; save_figure writes png and pdf; the
report's save_fig* functions run analysis, figure and save end to end."""

import dataclasses

import numpy as np
import pytest
from matplotlib.figure import Figure

from docking.experiments import Curriculum, run_experiment
from docking.presets import EXPERIMENT_1, EXPERIMENT_2
from docking.region import StartRegion
from docking.study import analysis, arrays, figures, readme
from docking.study.designs import paper_report
from docking.study.kinds import load_result, save_result
from docking.world import ACTION_LETTERS, DockingEnv

TINY = dict(train_trials=4, test_trials=6, eval_every=2, eval_trials=2)


@pytest.fixture(scope="module")
def result1():
    return run_experiment(dataclasses.replace(EXPERIMENT_1, **TINY), seed=0, progress=False)


@pytest.fixture(scope="module")
def result2():
    curriculum = Curriculum(far_initial=EXPERIMENT_2.curriculum.far_initial, grow_trials=2)
    config = dataclasses.replace(EXPERIMENT_2, curriculum=curriculum, **TINY)
    return run_experiment(config, seed=0, progress=False)


@pytest.fixture(scope="module")
def loaded2(result2, tmp_path_factory):
    path = save_result(result2, tmp_path_factory.mktemp("results") / "seed0.npz")
    return load_result(path)


@pytest.fixture(scope="module")
def env():
    return DockingEnv(seed=0)


@pytest.fixture(scope="module")
def views(env):
    return analysis.example_views(env)


def _drawn(fig, min_axes=1):
    """A figure with axes, drawn without error (the Agg canvas renders every artist)."""
    assert isinstance(fig, Figure)
    assert len(fig.axes) >= min_axes
    fig.canvas.draw()
    return fig


def _assert_written(path):
    for suffix in (".png", ".pdf"):
        out = path.with_suffix(suffix)
        assert out.exists() and out.stat().st_size > 1000, out
    # The atomic writes leave no temporary files behind.
    assert not [p for p in path.parent.iterdir() if p.name.startswith(".")]


def test_figure_functions_write_nothing(env, views, result1, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    overview = analysis.overview(env, views.poses[1], size=(160, 120))
    _drawn(figures.fig2_scene(env.config.camera, views, overview), min_axes=9)
    net = result1.network
    _drawn(
        figures.fig3(
            result1.config,
            0,
            views,
            arrays.decisions(net, views.inputs),
            *arrays.receptive_fields(net),
            net.Q,
        ),
        min_axes=3 + 4 + 4,
    )
    assert list(tmp_path.iterdir()) == []


def test_fig2_needs_three_views(env, views):
    two = arrays.ExampleViews(views.names[:2], views.poses[:2], views.frames[:2], views.inputs[:2])
    with pytest.raises(ValueError, match="three views"):
        figures.fig2_scene(env.config.camera, two, views.frames[0])


@pytest.mark.slow
def test_fig4_from_fresh_and_loaded_results(result2, loaded2):
    for result in (result2, loaded2):
        net = result.network
        fig = figures.fig4(
            result.config,
            result.seed,
            *arrays.receptive_fields(net),
            analysis.mean_winning_inputs(net, result.config.world, n=40),
            arrays.strongest_units(net.Q),
        )
        _drawn(fig, min_axes=2 * (4 + 36))


def test_fig5_and_floor_plan(result1, loaded2):
    for result in (result1, loaded2):
        sample = arrays.trajectory_sample(result.test, n=4)
        plan = analysis.floor_plan(result.config.world)
        fig = _drawn(figures.fig5(result.config.world, plan, sample, "label"))
        assert "label: 4 of 6 test trials" in fig.axes[0].get_title()
    # The start trapezoid drawn is the StartRegion's, corners in (y, x).
    region = StartRegion(near=0.6, far=0.9, half_angle_deg=10.0)
    fig = Figure()
    ax = fig.add_subplot()
    figures.draw_floor_plan(ax, analysis.floor_plan(result1.config.world), region)
    polygon = [p for p in ax.patches if type(p).__name__ == "Polygon"]
    assert len(polygon) == 1
    np.testing.assert_allclose(polygon[0].get_xy()[:4], region.corners()[:, ::-1])


@pytest.mark.slow
def test_learning_curves_with_one_or_both_experiments(result1, result2, loaded2):
    c1 = arrays.learning_curves([result1])
    c2 = arrays.learning_curves([result2, loaded2])
    for curves in ((c1, c2), (c1, None), (None, c2)):
        n_columns = sum(c is not None for c in curves)
        _drawn(figures.fig_learning_curves(*curves), min_axes=3 * n_columns)
    with pytest.raises(ValueError):
        figures.fig_learning_curves(None, None)
    fig = _drawn(figures.fig_rewards(c2, headline_seed=0))
    assert len(fig.axes[0].get_lines()) == 2 + 1  # two seeds and the paper's line
    assert figures.to_png(fig)[:8] == b"\x89PNG\r\n\x1a\n"


def test_fig_trial_draws_the_path_on_the_floor_plan(result1):
    poses = result1.test.trial_poses(0)
    world = result1.config.world
    fig = _drawn(figures.fig_trial(world, analysis.floor_plan(world), poses, "a trial"))
    ax = fig.axes[0]
    assert ax.get_title() == "a trial" and ax.xaxis_inverted()
    np.testing.assert_array_equal(ax.get_lines()[0].get_xydata(), poses[:, [1, 0]])


def test_floor_plans_of_a_scene_without_a_sideboard(result1):
    world = dataclasses.replace(result1.config.world, scene="floor")
    plan = analysis.floor_plan(world)
    fig = _drawn(figures.fig_trial(world, plan, result1.test.trial_poses(0), "floor scene"))
    assert len(fig.axes[0].patches) == 3 + 1  # slab, post, dock and the start trapezoid
    _drawn(figures.fig5(world, plan, arrays.trajectory_sample(result1.test, n=3), "floor"))


def test_save_figure_writes_png_and_pdf(tmp_path):
    fig = Figure()
    fig.add_subplot().plot([0, 1], [1, 0])
    for name in ("a.png", "b.pdf", "c"):
        png, pdf = figures.save_figure(fig, tmp_path / name)
        assert png.suffix == ".png" and pdf.suffix == ".pdf"
        _assert_written(tmp_path / name)
    # No creation date in the PDF: the same figure gives the same bytes.
    first = (tmp_path / "c.pdf").read_bytes()
    figures.save_figure(fig, tmp_path / "c")
    assert (tmp_path / "c.pdf").read_bytes() == first


_FIG4_SCRIPT = """
import dataclasses, sys
from docking.study import analysis
from docking.study.designs import paper_report
from docking.experiments import Curriculum, run_experiment
from docking.presets import EXPERIMENT_2
config = dataclasses.replace(
    EXPERIMENT_2, curriculum=Curriculum(far_initial=0.7, grow_trials=2), train_trials=4,
    test_trials=6, eval_every=2, eval_trials=2,
)
run = run_experiment(config, seed=0, progress=False)
inputs = analysis.mean_winning_inputs(run.network, config.world, n=20)
paper_report.save_fig4(run, inputs, analysis.start_fields(run), sys.argv[1])
"""


@pytest.mark.slow
def test_a_figure_saved_in_another_process_has_the_same_bytes(tmp_path):
    """Fig. 4 of the same run, saved by three processes: the same PNG and the same PDF.
    Constrained layout's positions differ in their last bits from process to process; the
    PDF wrote them out (its bytes differed in two of three processes before the layout was
    frozen, figures.common._freeze_layout)."""
    import subprocess
    import sys

    for k in range(3):
        subprocess.run([sys.executable, "-c", _FIG4_SCRIPT, str(tmp_path / str(k))], check=True)
    for suffix in ("png", "pdf"):
        found = {(tmp_path / str(k) / f"fig4_experiment2.{suffix}").read_bytes() for k in range(3)}
        assert len(found) == 1, suffix


@pytest.mark.slow
def test_report_saves_every_figure(result1, result2, tmp_path):
    env = DockingEnv(seed=0)
    views = analysis.example_views(env)
    paper_report.save_fig2(
        env.config.camera, views, analysis.overview(env, views.poses[1]), tmp_path
    )
    views1 = analysis.example_views(DockingEnv(result1.config.world, seed=0))
    paper_report.save_fig3(result1, views1, tmp_path)
    inputs = analysis.mean_winning_inputs(result2.network, result2.config.world, n=20)
    paper_report.save_fig4(result2, inputs, analysis.start_fields(result2), tmp_path)
    paper_report.save_fig5(result2, analysis.floor_plan(result2.config.world), tmp_path, n=4)
    paper_report.save_learning_curves([result1], [result2], tmp_path)
    for name in (
        "fig2_scene",
        "fig3_experiment1",
        "fig4_experiment2",
        "fig5_trajectories",
        "learning_curves",
    ):
        _assert_written(tmp_path / name)


def test_paper_action_order_is_L_R_F_B():
    assert [ACTION_LETTERS[i] for i in figures.PAPER_ACTION_ORDER] == list("LRFB")


@pytest.mark.slow
def test_fig4_draws_the_random_start_below_the_learned_weights(result2):
    from docking.experiments import initial_network

    net = result2.network
    start = initial_network(result2.config, result2.seed)
    args = (
        result2.config,
        result2.seed,
        *arrays.receptive_fields(net),
        analysis.mean_winning_inputs(net, result2.config.world, n=40),
        arrays.strongest_units(net.Q),
    )
    two = figures.fig4(*args)
    three = figures.fig4(*args, initial_rf=arrays.receptive_fields(start)[1])
    assert len(three.axes) == len(two.axes) + 36
    # the blocks one above the other, as wide as a page (the site's figures are read there)
    assert three.get_figheight() > two.get_figheight()
    assert three.get_figwidth() == two.get_figwidth() == figures.common._PAGE_WIDTH_IN


def test_results_table_rows_of_sample_efficiency_and_held_out_success(result1, result2):
    r2 = dataclasses.replace(result2, curve_success=np.array([0.5, 0.95, 1.0]))
    r2.curve_trials = np.array([0, 5, 10])
    never = dataclasses.replace(r2, seed=1, curve_success=np.array([0.5, 0.6, 0.7]))
    table = paper_report.results_table([result1], [r2, never], {"Exp. 1": np.array([0.9, 1.0])})
    row = next(line for line in table.splitlines() if "first reach 90%" in line)
    assert "per seed 5, never; median 5" in row
    assert "| Exp. 1 held-out success, 2 seeds (the study) | (not reported) | mean 95.0%" in table
    assert "held-out" not in paper_report.results_table([result1], [r2])


def test_the_summary_quotes_the_runs_and_the_world_they_hold_in(result1, result2):
    from docking.study.stats import Interval

    text = readme.summary_text([result1], [result2])
    h1, h2 = result1, result2
    assert f"{h1.test_successes}/{len(h1.test)} test trials of Experiment 1" in text
    assert f"{h2.test_successes}/{len(h2.test)} = " in text
    w = result2.config.world
    assert f"({100 * w.step_forward:.0f} cm forward, {100 * w.step_side:.0f} cm sideways" in text
    assert "Not supported" not in text  # no Experiment 3 given: no sentence about it

    class Pair:  # an Experiment 3 comparison: six minus four actions
        def __init__(self, gain):
            self.gain = Interval(gain, gain - 0.03, gain + 0.03, ())
            self.four = Interval(0.9, 0.88, 0.92, ())

    text = readme.summary_text([result1], [result2], [Pair(-0.2), Pair(-0.05)])
    assert "**Not supported.**" in text
    assert "in 2 of Experiment 3's 2 cells; six minus four actions ranges from -20.0 to" in text
    text = readme.summary_text([result1], [result2], [Pair(-0.2), Pair(0.01)])
    assert "**Mixed.**" in text and "in 1 of Experiment 3's 2 cells" in text


def test_fig_coping_draws_fresh_and_relearning_curves_per_change():
    trials = np.arange(0, 2001, 100)
    rise = np.clip(trials / 1000, 0, 1)
    curves = {
        (c, learner, kind): (trials, np.vstack([rise * (0.9 if kind == "fresh" else 1.0)] * 3))
        for c in ("object", "sensor")
        for learner in ("paper", "linear")
        for kind in ("fresh", "relearn")
    }
    fig = figures.fig_coping(["object", "sensor"], curves, {"paper": 0.85, "linear": 0.9})
    assert len(fig.axes) == 2
    assert len(fig.axes[0].lines) == 4 + 2  # four curves, two levels
    with pytest.raises(ValueError, match="at least one change"):
        figures.fig_coping([], curves, {})


def test_fig_verdicts_draws_a_reference_where_asked():
    from docking.study.stats import t_paired_ci

    ci = t_paired_ci([0.5, 0.6, 0.7], [0.4, 0.4, 0.5])
    panel = dict(title="t", xlabel="x", scale=100.0, bound=0.0, band=None)
    bare = figures.fig_verdicts([dict(panel, rows=[("w", ci, "finding", ci.values)])])
    drawn = figures.fig_verdicts(
        [dict(panel, rows=[("w", ci, "finding", ci.values)], reference=(0.3, "linear SARSA"))]
    )
    assert len(drawn.axes[0].lines) == len(bare.axes[0].lines) + 1
    assert any(t.get_text() == "linear SARSA" for t in drawn.axes[0].texts)


def test_fig_claims_is_as_wide_as_a_page_however_many_comparisons():
    bound = "supported if the 95% interval lies above 0"
    seven = [(f"setting {k}", "1 [0, 2]", "contradicted") for k in range(7)]
    rows = [("claim-a", bound, [("sideboard", "1 [0, 2]", "supported")], None)]
    rows.append(("claim-b", bound, seven, "why"))
    one, both = figures.fig_claims(rows[:1]), figures.fig_claims(rows)
    assert one.get_figwidth() == both.get_figwidth() == figures.common._PAGE_WIDTH_IN
    assert both.get_figheight() > one.get_figheight()  # seven boxes: three lines of boxes
    with pytest.raises(ValueError, match="at least one claim"):
        figures.fig_claims([])


def test_episode_gif_writes_an_animation_of_an_episode(tmp_path):
    """One episode of the pose oracle as a GIF (the site's page of the worlds): a few frames
    here, each the overview with the robot's input inset; more than one frame, small. The
    frames are computed outside the figures (docking.study.episodes), which only draw them."""
    from PIL import Image

    from docking.presets import FLOOR_WORLD
    from docking.study.episodes import episode_frames

    frames, actions, docked = episode_frames(FLOOR_WORLD, seed=0, width=64, height=48)
    assert len(frames) == len(actions) + 1 >= 2 and frames[0].shape == (48, 64, 3)
    assert docked  # the oracle docks from this start
    frames, actions, docked = episode_frames(FLOOR_WORLD, seed=0, max_frames=3)
    names = FLOOR_WORLD.action_names
    images = figures.episode_images(frames, actions, docked, names, ended=False, label="x")
    path = figures.save_gif(images, tmp_path / "a" / "floor.gif")
    with Image.open(path) as gif:
        assert gif.format == "GIF" and gif.n_frames == 3 and gif.size == (320, 240)
        assert gif.info["loop"] == 0
    assert path.stat().st_size < 1_000_000


def test_fig_landscape_draws_each_panel_with_its_marks():
    grid = arrays.landscape({(2.0, 0.05): [0.4], (100.0, 0.5): [0.95]}, [2.0, 100.0], [0.05, 0.5])
    panels = [
        dict(world=w, learner=lr, title=f"{w} {lr}", row_label="beta_a", col_label="eps", grid=grid)
        for w in ("floor", "nao")
        for lr in ("paper", "linear")
    ]
    marks = {("floor", "paper"): [("tuned", (100.0, 0.5)), ("published", (2.0, 0.05))]}
    fig = figures.fig_landscape(panels, marks)
    assert isinstance(fig, Figure)
    axes = [ax for ax in fig.axes if ax.get_title()]
    assert len(axes) == 4
    texts = [t.get_text() for t in axes[0].texts]
    assert "40\n1" in texts and "95\n1" in texts  # each setting's mean and runs
    assert [h.get_label() for h in axes[0].get_legend_handles_labels()[0]] == ["tuned", "published"]
