"""The study's cells are valid, distinct runs with their baselines."""

import dataclasses

import numpy as np
import pytest

from docking.experiments import heldout_trials, run_experiment
from docking.presets import EXPERIMENT_1, EXPERIMENT_2
from docking.store import config_key
from docking.study import HELDOUT_TRIALS, STUDY_SEEDS, cells, control_cell


def test_cells_are_distinct_runs_judged_on_held_out_trials():
    all_cells = cells(full=True) + [control_cell(0.05)]
    keys = [c.key for c in all_cells]
    assert len(set(keys)) == len(keys)
    trained = [c for c in all_cells if c.test_world is None]
    assert len({config_key(c.config) for c in trained}) == len(trained)
    by_key = {c.key: c for c in all_cells}
    for c in all_cells:
        assert c.config.heldout_trials == HELDOUT_TRIALS >= 500
        assert c.baseline is None or c.baseline in by_key
        if c.baseline:
            assert c.config.world.scene == by_key[c.baseline].config.world.scene
        if c.test_world is not None:  # a test-only cell judges its baseline's networks
            assert c.config == by_key[c.baseline].config
    assert len(STUDY_SEEDS) >= 10
    core = {c.key for c in cells()}
    assert {"paper", "frozen", "none", "near-only", "no-yaw-noise", "cup-test"} <= core
    assert {"floor/paper", "floor/frozen", "floor/none", "exp1/frozen"} <= core


def test_the_paper_cell_trains_exactly_as_experiment_2():
    paper = {c.key: c for c in cells()}["paper"].config
    assert paper.network == EXPERIMENT_2.network and paper.world == EXPERIMENT_2.world
    assert paper.curriculum == EXPERIMENT_2.curriculum
    assert paper.train_trials == EXPERIMENT_2.train_trials


def test_variants_change_only_what_they_name():
    by_key = {c.key: c for c in cells(full=True)}
    paper = by_key["paper"].config
    frozen = dataclasses.replace(by_key["frozen"].config, network=paper.network, eval_trials=50)
    assert frozen == paper  # only the network (and the skipped learning curve) differ
    assert by_key["frozen"].config.network.eps_w == 0
    assert by_key["local"].config.network.rule == "local"
    assert by_key["none"].config.curriculum.grow_trials == 0
    assert by_key["near-only"].config.curriculum.far_final == paper.curriculum.far_initial
    assert by_key["cup-test"].test_world.distractors and not paper.world.distractors
    assert by_key["no-yaw-noise"].test_world.step_noise_yaw_deg == 0
    assert by_key["cup"].config.world.distractors
    for k in ("beta-10", "beta-30"):
        n = by_key[k].config.network
        assert n.eps_w / n.beta_s == pytest.approx(paper.network.eps_w / paper.network.beta_s)
    assert by_key["floor/paper"].config.world.scene == "floor"
    assert control_cell(0.07).config.network.feature_delta == 0.07


def test_held_out_trials_are_paired_across_worlds():
    config = dataclasses.replace(
        EXPERIMENT_1, train_trials=2, test_trials=1, eval_trials=0, heldout_trials=4
    )
    result = run_experiment(config, 5, progress=False)
    again = heldout_trials(config, 5, result.network, config.world)
    np.testing.assert_array_equal(again.poses, result.heldout.poses)
    quiet = dataclasses.replace(config.world, step_noise_yaw_deg=0.0)
    paired = heldout_trials(config, 5, result.network, quiet)
    np.testing.assert_array_equal(paired.starts, result.heldout.starts)  # the same starts
    assert not np.array_equal(paired.poses, result.heldout.poses)  # but other headings


def _log(rate: float, n: int = 200, seed: int = 0):
    from docking.experiments import TrialLog

    success = np.random.default_rng(seed).random(n) < rate
    return TrialLog(
        success=success,
        steps=np.ones(n, dtype=np.int64),
        start_far=np.full(n, 1.5),
        poses=np.zeros((2 * n, 3)),
        actions=np.zeros(n, dtype=np.int64),
        winners=np.zeros(n, dtype=np.int64),
        deltas=np.zeros(n),
    )


def _study(rates: dict[str, float]):
    from docking.study import DESIGN, StudyResults

    by_key = {c.key: c for c in cells(full=True)}
    chosen = [by_key[k] for k in rates]
    heldout = {k: [_log(r, seed=s) for s in STUDY_SEEDS] for k, r in rates.items()}
    return StudyResults(DESIGN, chosen, {}, heldout)


def verdict(claim: str, results, key: str) -> str:
    """The rule of ``claim`` on cell ``key`` (one comparison)."""
    from docking.claims import claim_of
    from docking.study import CLAIMS

    found = claim_of(CLAIMS, claim)
    return found.rule.decide(found.interval(results, key))


def test_verdict_rules_on_synthetic_results():
    from docking.claims import overall
    from docking.study import difference, rotation_share

    s = _study(
        {
            "paper": 0.95,
            "frozen": 0.80,
            "local": 0.95,
            "cup-test": 0.949,
            "cup": 0.70,
            "no-yaw-noise": 0.99,
            "none": 0.99,
        }
    )
    assert verdict("features", s, "frozen") == "supported"
    assert difference(s, "frozen").low > 0.1
    assert verdict("features", s, "local") == "not supported"
    assert verdict("curriculum", s, "none") == "contradicted"  # no curriculum does better
    assert verdict("distractor", s, "cup-test") == "supported"  # within the +-2 pp margin
    assert verdict("distractor", s, "cup") == "contradicted"
    share = rotation_share(s, "no-yaw-noise")
    assert 0.6 < share.estimate < 0.95 and verdict("rotation", s, "no-yaw-noise") == "supported"
    assert overall({"sideboard": "supported", "floor": "supported"}) == "supported"
    assert overall({"sideboard": "supported", "floor": "not supported"}) == (
        "supported only in the sideboard world"
    )
    assert overall({"a, 2 deg": "not supported", "b": "contradicted", "c": "not supported"}) == (
        "not supported in a, 2 deg / c; contradicted in b"
    )


def test_study_figures_draw_from_arrays():
    from matplotlib.figure import Figure

    from docking import figures

    seeds = [np.linspace(0.9, 1.0, 10), np.linspace(0.8, 0.9, 10)]
    fig = figures.fig_forest(
        ["paper", "frozen"],
        ["world"] * 2,
        seeds,
        np.array([[0.95, 0.93, 0.97], [0.85, 0.83, 0.87]]),
        np.array([[np.nan] * 3, [0.1, 0.08, 0.12]]),
        margins=[None, 0.02],
    )
    assert isinstance(fig, Figure)
    with pytest.raises(ValueError, match="length"):
        figures.fig_forest(["a"], ["g", "h"], seeds, np.zeros((1, 3)), np.zeros((1, 3)))
    W0 = np.random.default_rng(0).random((4, 320))
    assert isinstance(figures.fig_weight_change(W0, W0 + 0.01, (10, 32), "t"), Figure)
    with pytest.raises(ValueError, match="shapes"):
        figures.fig_weight_change(W0, W0[:2], (10, 32), "t")
    assert isinstance(figures.fig_failures(["a"], ["x", "y"], np.array([[0.5, 0.2]]), [3]), Figure)
