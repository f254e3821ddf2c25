"""What the choices do: the calibration variants of Experiments 1 and 2 (notebooks 03, 04).

The paper leaves the step lengths, the start region of Experiment 1, the docking region's
orientation and the learning rates open; :mod:`docking.experiments` names our choices. How
much does each matter? Two designs (:data:`DESIGNS`) whose cells are
:data:`~docking.presets.EXPERIMENT_1` or :data:`~docking.presets.EXPERIMENT_2` with one or
two of those choices changed (coordinates ``experiment``, ``variant``, ``changes``; the rows
:func:`variants`), measured by their test trials beside the main experiment's runs (the row
"this configuration", :data:`BASELINE`). The notebooks show
:func:`docking.study.designs.calibration_report.calibration_table` and assert their claims on the
runs; ``python -m docking design run calibration-experiment1 calibration-experiment2`` prints the
tables.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

from docking.experiments import ExperimentConfig
from docking.presets import EXPERIMENT_1, EXPERIMENT_2, SEEDS
from docking.study.design import Cell, Design, Results, run_design

__all__ = [
    "BASELINE",
    "DESIGNS",
    "run",
    "run_all",
    "variants",
]

#: The key of the row "this configuration" (the main experiment itself) in every list.
BASELINE = "this"

#: The results folder name of each experiment's variants (``results/<name>/...``).
_NAMES = {"experiment1": "calibration-experiment1", "experiment2": "calibration-experiment2"}


def _variant(base: ExperimentConfig, key: str, label: str, world=None, network=None) -> Cell:
    """A row: ``base`` with the ``world`` and ``network`` fields replaced; its coordinate
    ``changes`` names them as dotted paths of :meth:`ExperimentConfig.to_dict` (besides
    ``name`` and ``eval_trials``). It keeps its experiment's test (Experiment 1: 200 greedy
    trials from its own start region; Experiment 2: 725 from the full region), so that its
    numbers compare with the main experiment's, and skips the learning curve, which changes
    neither training nor the test (they draw from other streams)."""
    world, network = dict(world or {}), dict(network or {})
    config = dataclasses.replace(
        base,
        name=_NAMES[base.name],
        eval_trials=0,
        world=dataclasses.replace(base.world, **world),
        network=dataclasses.replace(base.network, **network),
    )
    changes = tuple(f"world.{k}" for k in world) + tuple(f"network.{k}" for k in network)
    coords = {"experiment": base.name, "variant": key, "changes": changes}
    return Cell(key, config, coords, label, BASELINE)


def _baseline(base: ExperimentConfig, label: str) -> Cell:
    coords = {"experiment": base.name, "variant": BASELINE, "changes": ()}
    return Cell(BASELINE, base, coords, label)


def _experiment1() -> list[Cell]:
    """Experiment 1's rows (100 training trials, a few seconds each): where the calibration
    started; the short steps with this configuration's start region and eps_Q; eps_Q halved
    and doubled; a start region further out."""
    base = EXPERIMENT_1
    short = dict(step_forward=0.08, step_side=0.06)
    return [
        # Where the calibration started. WorldConfig accepts it: the start region's near
        # edge (0.65 m) lies beyond the 20 cm deep docking region (0.38-0.58 m).
        _variant(
            base,
            "start",
            "8 / 6 cm steps, start 0.65-0.85 m, 20 cm deep x 8 cm wide region, $\\epsilon_Q = 0.5$",
            world=dict(short, start_near=0.65, start_far=0.85, dock_depth=0.20, dock_width=0.08),
            network=dict(eps_q=0.5),
        ),
        _variant(
            base,
            "short-steps",
            "8 / 6 cm steps, start 0.58-0.70 m, $\\epsilon_Q = 0.1$",
            world=short,
        ),
        _variant(
            base,
            "epsQ-0.05",
            "15 / 10 cm steps, start 0.58-0.70 m, $\\epsilon_Q = 0.05$",
            network=dict(eps_q=0.05),
        ),
        _baseline(base, "15 / 10 cm steps, start 0.58-0.70 m, $\\epsilon_Q = 0.1$"),
        _variant(
            base,
            "epsQ-0.2",
            "15 / 10 cm steps, start 0.58-0.70 m, $\\epsilon_Q = 0.2$",
            network=dict(eps_q=0.2),
        ),
        _variant(
            base,
            "start-0.60-0.80",
            "15 / 10 cm steps, start 0.60-0.80 m, $\\epsilon_Q = 0.1$",
            world=dict(start_near=0.60, start_far=0.80),
        ),
    ]


def _experiment2() -> list[Cell]:
    """Experiment 2's rows (2000 training trials each): 8 cm forward steps (the side step
    stays 10 cm); eps_Q 0.03 and 0.2; eps_W 20 times this configuration's. Not here: W
    frozen at 15 cm steps, which the third edition measures on held-out trials."""
    base = EXPERIMENT_2
    return [
        _variant(
            base,
            "8cm-steps",
            "8 cm forward / 10 cm side steps, $\\epsilon_Q = 0.1$",
            world=dict(step_forward=0.08),
        ),
        _baseline(base, "15 / 10 cm steps, $\\epsilon_Q = 0.1$"),
        _variant(
            base, "epsQ-0.03", "15 / 10 cm steps, $\\epsilon_Q = 0.03$", network=dict(eps_q=0.03)
        ),
        _variant(
            base, "epsQ-0.2", "15 / 10 cm steps, $\\epsilon_Q = 0.2$", network=dict(eps_q=0.2)
        ),
        _variant(
            base,
            "epsW-1",
            "15 / 10 cm steps, $\\epsilon_Q = 0.1$, $\\epsilon_W = 1$",
            network=dict(eps_w=1.0),
        ),
    ]


_VARIANTS = {"experiment1": _experiment1, "experiment2": _experiment2}


def variants(experiment: str) -> list[Cell]:
    """The rows of ``experiment``'s (``"experiment1"`` or ``"experiment2"``) calibration table,
    in table order, :data:`BASELINE` among them."""
    return _rows_of(experiment)


def _rows_of(experiment: str) -> list[Cell]:
    if experiment not in _VARIANTS:
        raise ValueError(f"experiment must be one of {', '.join(_VARIANTS)}, got {experiment!r}")
    return _VARIANTS[experiment]()


# ------------------------------------------------------------------------------------------
# Running.
# ------------------------------------------------------------------------------------------


def _design(experiment: str, cells: Sequence[Cell], seeds: Sequence[int]) -> Design:
    return Design(
        name=_NAMES[experiment],
        title=f"what the choices do: {experiment}'s choices changed one or two at a time",
        cells=tuple(cells),
        seeds=tuple(seeds),
        measure="test",
        report=_report,
        keep=frozenset({"starts"}),  # notebook 04 splits the short steps' test by start
    )


def _report(results: Results) -> str:
    """The table: per row, test success and the share of training trials that ended in the
    dock (how often training's near-random walk is rewarded, what the notebooks' explanations
    turn on), and the difference to this configuration by
    :func:`docking.study.stats.difference_ci`, which resamples each row's seeds independently:
    it ignores the pairing, so its interval is, if anything, wider than a paired one."""
    from docking.study.designs.calibration_report import (
        calibration_rows,
        calibration_table,
        computing_time,
    )

    rows = calibration_rows(results, BASELINE)
    table = calibration_table(rows, BASELINE, seeds_at_100=results.design.name.endswith("1"))
    return f"{table}\n\ncomputing time of the variants: {computing_time(results, BASELINE):.0f} s"


#: The two calibration designs, ``{name: design}``, on the main experiments' seeds: a row's run
#: of seed k has the main run's initial weights and random streams (start poses, step noise,
#: action draws); the row "this configuration" *is* the main experiment's runs, not a rerun.
DESIGNS = {
    _NAMES[experiment]: _design(experiment, _rows_of(experiment), SEEDS[experiment])
    for experiment in _VARIANTS
}


def run(
    experiment: str,
    *,
    variants: Sequence[Cell] | None = None,
    seeds: Sequence[int] | None = None,
    results_dir: Path | str | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
) -> Results:
    """Run (or load) every row of ``experiment``'s calibration for its seeds in one sweep
    (:func:`docking.study.sweep.run_jobs`: stored runs are loaded, not recomputed; the row
    :data:`BASELINE` is the main experiment's own runs, shared with its notebook).

    Args:
      experiment: ``"experiment1"`` or ``"experiment2"``.
      variants: The rows (default: the module's :func:`variants` of ``experiment``; tests
        pass small ones).
      seeds: Default: the main experiment's :data:`~docking.presets.SEEDS`.
      results_dir: The results store (default :func:`docking.study.paths.results_dir`).
      workers: Worker processes (default one per core; 1: one run after another here).
      scheduler: Address of an existing Dask scheduler, as for :func:`docking.study.sweep.run_jobs`.
      progress: Show a bar of finished runs.
    """
    cells = list(variants) if variants is not None else _rows_of(experiment)
    seeds = tuple(SEEDS[experiment] if seeds is None else seeds)
    return run_design(
        _design(experiment, cells, seeds),
        full=True,
        results_dir=results_dir,
        scheduler=scheduler,
        workers=workers,
        progress=progress,
    )


def run_all(**kwargs) -> dict[str, Results]:
    """:func:`run` for both experiments (keyword arguments as there)."""
    return {experiment: run(experiment, **kwargs) for experiment in _VARIANTS}


# ------------------------------------------------------------------------------------------
# Command line.
# ------------------------------------------------------------------------------------------
