"""Per-seed measures that claims judge by, beyond held-out success
(:func:`docking.study.claims.success`): each is ``measure(results, key) -> (seeds,)``.

A design's rules text names a claim's measure by its function's ``__name__``; the measures
built from a design's constants (:func:`interpretability`, :func:`regain`) keep theirs. A
measure's ``unit`` (:func:`_unit`: its unit's text and the decimals it is shown with) is
display only, read by :meth:`docking.study.claims.Claim.format`; without one, three decimals.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

Measure = Callable[..., np.ndarray]


def _unit(text: str, digits: int, label: str) -> Callable[[Measure], Measure]:
    """Mark a measure's values as shown in ``text`` (e.g. ``" m"``) to ``digits`` decimals,
    and named ``label`` on a figure's axis."""

    def mark(measure: Measure) -> Measure:
        measure.unit, measure.label = (text, digits), label
        return measure

    return mark


def interpretability(n_seeds: Callable, views: int, min_views: int) -> Measure:
    """The measure ``fidelity``: per seed (the first ``n_seeds(cell)`` of a cell), each
    winning unit's weights against the mean of the ``views`` start views it wins
    (:func:`docking.study.analysis.feature_fidelity`, units that win at least ``min_views``),
    averaged over its units; a network with W frozen is read at its random start. Computed
    once per results (it renders)."""

    def compute(results, key: str) -> np.ndarray:
        from docking.study.derived import feature_fidelity

        cell = results.cell(key)
        runs = results.runs[key][: n_seeds(cell)]
        # each renders the world's start views: kept in the store and the committed ledger,
        # keyed by the run's key (its configuration, code, rendering stack and seed) and views
        return np.array([feature_fidelity(run, cell.world, views, min_views) for run in runs])

    def fidelity(results, key: str) -> np.ndarray:
        return results.measured(compute, key)

    label = "interpretability (each winning unit's weights against the mean view it wins)"
    return _unit("", 3, label)(fidelity)


@_unit("°", 2, "|heading error| at docking")
def heading_error_deg(results, key: str) -> np.ndarray:
    """Per seed, the mean |heading error| (deg) at docking in the held-out trials."""
    from docking.study.arrays import docked_heading_error_deg

    return np.array([docked_heading_error_deg(log) for log in results.logs[key]])


@_unit(" actions", 2, "actions per docking")
def actions_per_docking(results, key: str) -> np.ndarray:
    """Per seed, the mean actions of the docked held-out trials."""
    from docking.study.arrays import actions_per_docking as per_log

    return np.array([per_log(log) for log in results.logs[key]])


def regain(level: float, censored: float) -> Measure:
    """The measure ``regain_trials``: per seed, the training trials until cell ``key``'s
    learning curve reaches ``level`` times the same seed's held-out success at home (the
    cell ``home/<learner>`` of its learner, the first word of its variant); ``censored`` if
    it never does."""

    def regain_trials(results, key: str) -> np.ndarray:
        learner = results.cell(key)["variant"].split("-")[0]
        home = results.score(f"home/{learner}")
        out = []
        for run, bar in zip(results.runs[key], level * home, strict=True):
            hits = np.flatnonzero(run.curve_success >= bar)
            out.append(float(run.curve_trials[hits[0]]) if len(hits) else float(censored))
        return np.array(out)

    return _unit(" trials", 0, f"training trials to regain {level:.0%}")(regain_trials)


@_unit(" m", 4, "final distance from the dock's centre")
def final_error_m(results, key: str) -> np.ndarray:
    """Per seed, the mean distance (m) of the final reference point from the docking
    region's centre, over the docked held-out trials."""
    from docking.study.arrays import final_poses

    centre = -results.cell(key).world.dock_center
    out = []
    for log in results.logs[key]:
        ends = final_poses(log)[np.asarray(log.success, dtype=bool)]
        out.append(
            float(np.mean(np.hypot(ends[:, 0] - centre, ends[:, 1]))) if len(ends) else np.nan
        )
    return np.array(out)


@_unit(" m", 3, "metres walked per docking")
def metres_per_docking(results, key: str) -> np.ndarray:
    """Per seed, the mean distance walked (m) in the docked held-out trials."""
    from docking.study.arrays import path_lengths

    out = []
    for log in results.logs[key]:
        walked = path_lengths(log)[np.asarray(log.success, dtype=bool)]
        out.append(float(np.mean(walked)) if len(walked) else np.nan)
    return np.array(out)
