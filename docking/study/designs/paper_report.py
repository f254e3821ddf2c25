"""The report of the paper's design (:mod:`docking.study.designs.paper`): Experiments 1 and 2
beside the paper's numbers (:func:`results_table`, the README's first table) and the paper's
figures (``save_fig*``: each takes the runs and the arrays the world gives them, computed by
the caller with :mod:`docking.study.analysis` (the rendered views, the mean inputs over
rendered start views, the floor plan), computes the rest with :mod:`docking.study.arrays`,
draws them with :mod:`docking.study.figures`, saves the figure, ``.png`` and ``.pdf``, and
returns it; ``python -m docking figures`` makes every one from the runs of both
experiments).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from docking.camera import CameraConfig
from docking.presets import HEADLINE_SEED
from docking.study import arrays, figures
from docking.study.arrays import ExampleViews, MeanInputs
from docking.study.report import _folder, _pct, md_table

if TYPE_CHECKING:  # runs are read here, never made
    from docking.experiments import ExperimentResult

#: The paper's figures (Sec. III).
PAPER = {
    "exp1_success": "100%",
    "exp1_rewards_to_mastery": "about 25",
    "exp2_success": "95% (690/725)",
    "exp2_wall_time": "about 2 days (Webots + Nao API, real time)",
}


def headline(results: list[ExperimentResult]) -> ExperimentResult:
    """The run of :data:`HEADLINE_SEED` (the first run if that seed is absent)."""
    return next((r for r in results if r.seed == HEADLINE_SEED), results[0])


def experiment1_rows(results: list[ExperimentResult]) -> list[tuple[str, str, str]]:
    """``(quantity, paper, ours)`` rows for Experiment 1."""
    h = headline(results)
    rates = np.array([r.test.success_rate for r in results])
    mastered = [r.rewarded_until_mastery for r in results]
    per_seed = ", ".join(f"{r.seed}: {r.test_successes}/{len(r.test.success)}" for r in results)
    reached = [m for m in mastered if m is not None]
    return [
        (
            "Exp. 1 test success, headline seed",
            PAPER["exp1_success"],
            f"{_pct(h.test.success_rate)} ({h.test_successes}/{len(h.test.success)}, "
            f"seed {h.seed})",
        ),
        (
            "Exp. 1 seeds with 100% test success",
            "(one run)",
            f"{int(np.sum(rates == 1.0))} of {len(results)} (mean {_pct(rates.mean())}, "
            f"min {_pct(rates.min())}; {per_seed})",
        ),
        (
            "Exp. 1 rewarded trials until the test first reaches 100%",
            PAPER["exp1_rewards_to_mastery"],
            f"{h.rewarded_until_mastery} (headline); per seed "
            + ", ".join("never" if m is None else str(m) for m in mastered)
            + (f"; median {int(np.median(reached))}" if reached else ""),
        ),
    ]


def experiment2_rows(results: list[ExperimentResult]) -> list[tuple[str, str, str]]:
    """``(quantity, paper, ours)`` rows for Experiment 2."""
    h = headline(results)
    rates = np.array([r.test.success_rate for r in results])
    per_seed = ", ".join(f"{r.seed}: {r.test_successes}/{len(r.test.success)}" for r in results)
    times = np.array([r.wall_time_train + r.wall_time_test for r in results])
    spread = f" ± {_pct(rates.std(ddof=1))} (s.d.)" if len(results) > 1 else ""
    return [
        (
            "Exp. 2 test success, headline seed",
            PAPER["exp2_success"],
            f"{_pct(h.test.success_rate)} ({h.test_successes}/{len(h.test.success)}, "
            f"seed {h.seed})",
        ),
        (
            f"Exp. 2 test success over {len(results)} seeds",
            "(one run)",
            f"mean {_pct(rates.mean())}{spread}, min {_pct(rates.min())} ({per_seed})",
        ),
        _efficiency_row(results),
        (
            "Exp. 2 wall time, 2000 training + 725 test trials",
            PAPER["exp2_wall_time"],
            f"{times.mean():.0f} s per run (2-core CPU, software rendering; "
            f"{h.wall_time_train:.0f} s training + {h.wall_time_test:.0f} s testing for the "
            f"headline seed)",
        ),
    ]


#: The learning-curve success that counts as learned in the results table (sample
#: efficiency).
EFFICIENCY_LEVEL = 0.90


def _efficiency_row(results: list[ExperimentResult]) -> tuple[str, str, str]:
    """Experiment 2's sample efficiency: per seed, the training trials at the first point of
    its learning curve (greedy trials from the full start region) at or above
    :data:`EFFICIENCY_LEVEL`."""
    trials = arrays.trials_to_level(results, EFFICIENCY_LEVEL)
    reached = trials[~np.isnan(trials)]
    r = results[0]
    return (
        f"Exp. 2 training trials until {r.config.eval_trials} greedy trials every "
        f"{r.config.eval_every} first reach {EFFICIENCY_LEVEL:.0%}",
        "(not reported)",
        "per seed "
        + ", ".join("never" if np.isnan(t) else f"{t:.0f}" for t in trials)
        + (f"; median {np.median(reached):.0f}" if len(reached) else ""),
    )


def heldout_rows(
    study: dict[str, np.ndarray], source: str = "the study"
) -> list[tuple[str, str, str]]:
    """Rows of held-out success from a design (``source``): ``{experiment label: per-seed
    held-out success of the paper's configuration}`` (each seed's network on its held-out
    trials, start poses and noise that training never sees)."""
    rows = []
    for label, success in study.items():
        success = np.asarray(success, dtype=float)
        rows.append(
            (
                f"{label} held-out success, {len(success)} seeds ({source})",
                "(not reported)",
                f"mean {_pct(success.mean())} ± {_pct(success.std(ddof=1))} (s.d.), "
                f"min {_pct(success.min())}",
            )
        )
    return rows


def save_fig2(
    camera: CameraConfig,
    views: ExampleViews,
    overview: np.ndarray,
    folder: Path | str | None = None,
) -> Figure:
    """Fig. 2 (the scene) of the three example ``views`` and the ``overview`` render at the
    middle one (:func:`docking.study.analysis.example_views`,
    :func:`docking.study.analysis.overview`), seen by ``camera``, saved as ``fig2_scene`` in
    ``folder`` (default :data:`docking.study.figures.FIGURES_DIR`)."""
    fig = figures.fig2_scene(camera, views, overview)
    figures.save_figure(fig, _folder(folder) / "fig2_scene")
    return fig


def save_fig3(
    result: ExperimentResult, views: ExampleViews, folder: Path | str | None = None
) -> Figure:
    """Fig. 3 (Experiment 1's views, decisions and receptive fields) of ``result``, saved as
    ``fig3_experiment1``; ``views``: the three example views rendered in the run's world
    (:func:`docking.study.analysis.example_views`)."""
    net = result.network
    action_rf, feature_rf = arrays.receptive_fields(net, result.config.world.camera.input_shape)
    fig = figures.fig3(
        result.config,
        result.seed,
        views,
        arrays.decisions(net, views.inputs),
        action_rf,
        feature_rf,
        net.Q,
    )
    figures.save_figure(fig, _folder(folder) / "fig3_experiment1")
    return fig


def save_fig4(
    result: ExperimentResult,
    mean_inputs: MeanInputs,
    initial_rf: np.ndarray,
    folder: Path | str | None = None,
) -> Figure:
    """Fig. 4 (Experiment 2's receptive fields, the mean input of each unit over start views,
    and the feature units at their random start) of ``result``, saved as
    ``fig4_experiment2``; ``mean_inputs``: :func:`docking.study.analysis.mean_winning_inputs`
    of its network in its world; ``initial_rf``: :func:`docking.study.analysis.start_fields`
    of it."""
    net = result.network
    action_rf, feature_rf = arrays.receptive_fields(net, result.config.world.camera.input_shape)
    fig = figures.fig4(
        result.config,
        result.seed,
        action_rf,
        feature_rf,
        mean_inputs,
        arrays.strongest_units(net.Q),
        initial_rf=initial_rf,
    )
    figures.save_figure(fig, _folder(folder) / "fig4_experiment2")
    return fig


def save_fig5(
    result: ExperimentResult,
    plan: dict,
    folder: Path | str | None = None,
    n: int = 30,
    seed: int = 0,
) -> Figure:
    """Fig. 5 (``n`` sample test trajectories of ``result``, chosen with ``seed``, on its
    world's floor plan ``plan``, :func:`docking.study.analysis.floor_plan`), saved as
    ``fig5_trajectories``."""
    sample = arrays.trajectory_sample(result.test, n, seed)
    label = f"{result.config.name}, seed {result.seed}"
    fig = figures.fig5(result.config.world, plan, sample, label, shade_seed=seed)
    figures.save_figure(fig, _folder(folder) / "fig5_trajectories")
    return fig


def save_learning_curves(
    results1: list[ExperimentResult],
    results2: list[ExperimentResult],
    folder: Path | str | None = None,
) -> Figure:
    """The learning curves of both experiments (an empty list skips one), saved as
    ``learning_curves``."""
    curves = [arrays.learning_curves(r) if len(r) else None for r in (results1, results2)]
    fig = figures.fig_learning_curves(*curves)
    figures.save_figure(fig, _folder(folder) / "learning_curves")
    return fig


#: The columns of :func:`experiment1_rows`' and :func:`experiment2_rows`' tables.
PAPER_COLUMNS = ("Quantity", "Paper", "This reproduction")


def results_table(
    results1: list[ExperimentResult],
    results2: list[ExperimentResult],
    heldout: dict[str, np.ndarray] | None = None,
) -> str:
    """The results table of both experiments in Markdown; with ``heldout`` (see
    :func:`heldout_rows`), a design's held-out rows after them."""
    rows = experiment1_rows(results1) + experiment2_rows(results2)
    rows += heldout_rows(heldout) if heldout else []
    return md_table(PAPER_COLUMNS, rows)
