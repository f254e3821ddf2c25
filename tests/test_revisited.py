"""Relocation and coping revisited (docking.study.designs.revisited): rules pinned before the runs,
tests that can fail, and censoring handled by a method made for it."""

from __future__ import annotations

import json
import types
from pathlib import Path

import numpy as np
import pytest

from docking.study import claims
from docking.study.designs import revisited as rv


def test_seeds_are_fresh():
    """No run of another design used the revisit's seeds: the only runs on them outside its
    table are its own pose-oracle cells, which the shared yardsticks table holds."""
    manifest = Path(__file__).resolve().parents[1] / "ledger" / "manifest.json"
    data = json.loads(manifest.read_text())
    own = [c.config.to_dict() for c in rv.DESIGN.cells if c.config.name == "yardsticks"]
    assert own  # else the exception below would be empty
    for r in data["runs"].values():
        if r["name"] != rv.NAME and r["seed"] in rv.SEEDS:
            assert r["name"] == "yardsticks" and data["configs"][r["config"]] in own, r


def test_each_place_changes_every_start_view():
    """The old relocation changed no start view; each new place changes them (counted)."""
    for world in rv.places().values():
        changed, n = rv.changed_start_views(world, n=20)
        assert changed == n


def test_the_places_move_the_landmark_by_the_stated_height():
    eye = rv.home_camera_height()
    heights = sorted(w.camera_height for w in rv.places().values())
    assert heights == pytest.approx([eye - rv.HEIGHT_CHANGE, eye + rv.HEIGHT_CHANGE])


def test_the_curve_has_at_least_ten_points_in_the_first_200_trials():
    config = rv.DESIGN.cell("sensor/paper-relearn").config
    points = range(0, config.train_trials + 1, config.eval_every)
    assert config.train_trials == rv.EARLY_TRIALS <= 200 and len(points) >= 10
    assert config.eval_trials >= 50 and config.before == rv.DESIGN.cell("home/paper").config


class _Fake:
    """What the claims read of results, from synthetic learning curves per cell."""

    def __init__(self, curves: dict[str, np.ndarray], home: float = 0.95):
        self.curves, self.home = curves, home
        trials = np.arange(0, rv.EARLY_TRIALS + 1, rv.EVAL_EVERY)
        self.runs = {
            k: [types.SimpleNamespace(curve_trials=trials, curve_success=c) for c in v]
            for k, v in curves.items()
        }

    def cell(self, key):
        return rv.DESIGN.cell(key)

    def score(self, key):
        return np.full(len(rv.SEEDS), self.home)


def _curves(start: float, rise_at: int, home: float = 0.95, n: int = 10, seed: int = 0):
    rng = np.random.default_rng(seed)
    trials = np.arange(0, rv.EARLY_TRIALS + 1, rv.EVAL_EVERY)
    out = []
    for _ in range(n):
        c = np.where(trials >= rise_at, home, start) + rng.normal(0, 0.02, len(trials))
        out.append(np.clip(c, 0, 1))
    return np.array(out)


def _verdicts(relearn, fresh):
    curves = {}
    for change in rv.untested.CHANGES:
        curves[f"{change}/paper-relearn"], curves[f"{change}/paper-fresh"] = relearn, fresh
    claim = next(c for c in rv.CLAIMS if c.key == "coping-early")
    return [d.verdict for d in claims.judge_family([claim], _Fake(curves), rv.ALPHA)]


def test_a_network_already_at_home_success_is_not_called_contradicted():
    """The old rule's failure: a fresh network at 90% by its first curve point made a home
    network that transfers look no faster. At trial resolution the head start shows."""
    at_home = _curves(0.95, 0, seed=1)  # transfers: at home success from trial 0
    fresh = _curves(0.15, 10, seed=2)  # a fresh network, at home success from trial 10
    assert set(_verdicts(at_home, fresh)) == {"supported"}


def test_a_handicap_is_contradicted_and_no_difference_is_not_supported():
    slow = _curves(0.10, 120, seed=3)
    fresh = _curves(0.15, 30, seed=4)
    assert set(_verdicts(slow, fresh)) == {"contradicted"}
    same = _curves(0.15, 30, seed=5)
    assert set(_verdicts(same, fresh)) == {"not supported"}


def test_censoring_enters_the_sign_test_by_order_only():
    inf = np.inf
    sooner, n, p = rv.regain_sign_test(np.array([0, 10, inf, inf]), np.array([20, inf, inf, 30]))
    assert (sooner, n) == (2, 3)  # the pair censored in both carries no sign
    assert 0 < p <= 1
    # a censored fresh value counts the same however late "never" would have been
    assert rv.regain_sign_test(np.array([10.0] * 8), np.full(8, inf))[:2] == (8, 8)
    assert rv.regain_sign_test(np.array([10.0] * 8), np.full(8, inf))[2] < 0.01


def test_regain_trials_marks_a_curve_that_never_regains_as_censored():
    fake = _Fake({"sensor/paper-relearn": _curves(0.2, 10_000, n=10)})
    got = rv.regain_trials(fake, "sensor/paper-relearn", "home/paper")
    assert np.all(np.isinf(got))
