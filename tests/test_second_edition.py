"""The study's second edition (issue 19): its rules are fixed before its runs, its cells
are well formed, and its statistics do what they say."""

import hashlib

import numpy as np
import pytest

from docking import claims, stats
from docking.designs import second_edition as se

#: SHA-256 of second_edition.rules_text() as committed before the edition's runs. A change
#: of a rule, a cell or a constant fails this test: a new rule is a new, labelled analysis,
#: never an edit of this one after its runs.
#: History: b5371a03... (2371ece) fixed every rule before any run; the pixel-level bound's
#: cells (one PPOConfig per world of the path, the settings of docking.ppo with 16 copies of
#: the world per agent step) were added before any PPO run of this edition, while its learner
#: runs were being computed and before any of them was read.
RULES_DIGEST = "47b08985e8523c642c6fa4acd2840843b4661f1e9839615c36d3273322fe3ec5"


def test_the_rules_are_those_committed_before_the_runs():
    digest = hashlib.sha256(se.rules_text().encode()).hexdigest()
    assert digest == RULES_DIGEST, "the second edition's rules changed after they were fixed"


def test_every_comparison_names_cells_of_the_design():
    keys = {c.key for c in se.DESIGN.cells}
    for claim in se.CLAIMS:
        for entries in claim.cells.values():
            for entry in entries:
                assert set([entry] if isinstance(entry, str) else entry) <= keys, entry


def test_the_path_changes_one_factor_at_a_time_and_ends_in_the_floor_world():
    import dataclasses

    from docking.presets import FLOOR_WORLD

    worlds = [w for _, _, w, _ in se.PATH[:5]]
    assert worlds[-1] == FLOOR_WORLD
    for a, b in zip(worlds, worlds[1:], strict=False):
        changed = {
            f.name for f in dataclasses.fields(a) if getattr(a, f.name) != getattr(b, f.name)
        }
        # one factor: a field, or the fields that must move together (named in PATH)
        assert changed and changed <= {
            "scene",
            "camera",
            "dock_width",
            "dock_depth",
            "start_near",
            "step_side",
            "start_half_angle_deg",
        }, changed
        assert len(changed) <= 3


def test_yardsticks_do_not_learn_and_run_on_their_own_seeds():
    for cell in se.DESIGN.cells:
        if cell.coords.get("variant") in se.YARDSTICKS:
            assert cell.config.policy == cell["variant"] and cell.config.train_trials == 0
            assert cell.seeds == se.YARDSTICK_SEEDS


# -- statistics ------------------------------------------------------------------------------


def test_t_intervals_cover_at_ten_seeds_where_the_percentile_bootstrap_does_not():
    t = stats.coverage("t", repeats=300, seed=1)
    percentile = stats.coverage("percentile", repeats=300, seed=1)
    assert t >= 0.92 and t > percentile


def test_holm_adjusts_step_down():
    adjusted = stats.holm([0.01, 0.04, 0.03, 0.5])
    np.testing.assert_allclose(adjusted, [0.04, 0.09, 0.09, 0.5])
    with pytest.raises(ValueError, match="p-values"):
        stats.holm([1.5])


def test_welch_interval_and_p_value_agree_with_scipy():
    from scipy import stats as sps

    rng = np.random.default_rng(0)
    a, b = rng.normal(0.9, 0.03, 10), rng.normal(0.85, 0.05, 10)
    ci = stats.t_difference_ci(a, b)
    ref = sps.ttest_ind(a, b, equal_var=False)
    assert ci.p_value(0.0) == pytest.approx(ref.pvalue)
    low, high = ref.confidence_interval(0.95)
    assert (ci.low, ci.high) == pytest.approx((low, high))


def test_a_share_of_failures_by_the_delta_method():
    base = np.array([0.10, 0.12, 0.08, 0.11, 0.09])
    ci = stats.t_share_ci(base / 4, base)  # a quarter of every seed's failures remain
    assert ci.estimate == pytest.approx(0.75) and ci.low == pytest.approx(0.75)


# -- the family of verdicts --------------------------------------------------------------------


class _Fake:
    """Results with given per-seed values per cell."""

    def __init__(self, values, baselines):
        self._values, self._baselines = values, baselines

    def score(self, key):
        return np.asarray(self._values[key])

    def cell(self, key):
        return type("C", (), {"baseline": self._baselines.get(key)})()


def _above(key, words, cells, judged=True):
    """A claim "the baseline minus the cell lies above 0" (Student-t) over ``cells``."""
    return claims.Claim(
        key, words, "Sec. I", "baseline minus", claims.Above(0.0, method="t"), cells, judged=judged
    )


def test_a_family_is_judged_with_holm_and_near_bounds_are_not_decided():
    rng = np.random.default_rng(3)
    values = {
        "paper": 0.90 + 0.0005 * rng.standard_normal(10),
        "clear": 0.70 + 0.01 * rng.standard_normal(10),  # far below the paper: supported
        "edge": 0.895 + 0.0005 * rng.standard_normal(10),  # decided, but 0.5 pp from 0
        "same": 0.90 + 0.01 * rng.standard_normal(10),  # no difference
    }
    base = {k: "paper" for k in values if k != "paper"}
    claim = _above("x", "words", {"w1": ("clear",), "w2": ("edge",), "w3": ("same",)})
    decisions = {d.key: d for d in claims.judge_family([claim], _Fake(values, base))}
    assert decisions["clear"].verdict == claims.SUPPORTED
    assert decisions["edge"].p_adjusted < 0.05  # decided by the test ...
    assert decisions["edge"].verdict == claims.AT_BOUND  # ... but reported at the bound
    assert decisions["same"].verdict == claims.NOT_SUPPORTED
    p = [d.p for d in decisions.values()]
    np.testing.assert_allclose([d.p_adjusted for d in decisions.values()], stats.holm(p))


def test_equivalence_and_gap_rules():
    within = claims.Within(0.02, method="t")
    tight = stats.t_difference_ci(np.full(10, 0.9) + np.linspace(-1e-3, 1e-3, 10), np.full(10, 0.9))
    p, side = within.p_side(tight)
    assert side == claims.SUPPORTED and p < 0.01
    far = stats.t_difference_ci(np.linspace(0.80, 0.82, 10), np.linspace(0.90, 0.92, 10))
    assert within.p_side(far)[1] == claims.CONTRADICTED
    values = {"paper": [0.9] * 5, "cup": [0.88] * 5, "frozen": [0.8] * 5, "cupf": [0.7] * 5}
    values = {k: np.asarray(v) + np.linspace(0, 0.01, 5) for k, v in values.items()}
    gap = claims.Gap().interval(
        _Fake(values, {}), ("cup", "paper", "frozen", "cupf"), claims.success
    )
    assert gap.estimate == pytest.approx((0.8 - 0.7) - (0.9 - 0.88))


# -- its analysis and figure, on synthetic arrays ----------------------------------------------


class _Run:
    def __init__(self, trials, success, name="x", seed=0):
        self.curve_trials, self.curve_success = np.asarray(trials), np.asarray(success)
        self.config = type("C", (), {"name": name})()
        self.seed = seed


def test_trials_to_level_and_flatness():
    from docking.analysis import curve_flatness, trials_to_level

    runs = [
        _Run([0, 100, 200, 300], [0.1, 0.5, 0.92, 0.95]),
        _Run([0, 100, 200, 300], [0.1, 0.2, 0.3, 0.4]),
    ]
    out = trials_to_level(runs, 0.9)
    assert out[0] == 200 and np.isnan(out[1])
    flat = [_Run(range(8), [0.1, 0.5, 0.8, 0.9, 0.9, 0.9, 0.91, 0.9])]
    assert abs(curve_flatness(flat)) < 0.01
    rising = [_Run(range(8), np.linspace(0, 0.7, 8))]
    assert curve_flatness(rising) == pytest.approx(0.2)
    with pytest.raises(ValueError, match="level"):
        trials_to_level(runs, 0)


def test_path_drops_are_welch_intervals_of_consecutive_worlds():
    from docking.analysis import path_drops

    a, b, c = np.full(10, 0.9), np.full(10, 0.6), np.full(10, 0.6)
    a = a + np.linspace(0, 0.01, 10)
    drops = path_drops([a, b, c])
    assert len(drops) == 2 and drops[0].estimate == pytest.approx(a.mean() - 0.6)
    assert drops[1].estimate == 0


def test_the_path_figure_draws_every_learner_in_every_world():
    from matplotlib.figure import Figure

    from docking import figures

    rng = np.random.default_rng(0)
    worlds = ["sideboard", "floor-view", "dock", "sidestep", "floor"]
    learners = {name: [rng.random(10) for _ in worlds] for name in ("paper", "linear", "PPO")}
    learners["PPO"][1] = np.array([])  # not run there
    fig = figures.fig_path(worlds, learners, bound=0.9)
    assert isinstance(fig, Figure)
    (ax,) = fig.axes
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts[:3] == ["paper", "linear", "PPO"]
    assert texts[3].startswith("90%: the pixels suffice")  # the dashed line, named
    with pytest.raises(ValueError, match="one array per world"):
        figures.fig_path(worlds, {"paper": learners["paper"][:2]}, 0.9)


def test_every_world_of_the_path_has_the_pixel_level_bound():
    for key, _, world, _ in se.PATH:
        cell = se.DESIGN.cell(f"{key}/ppo")
        assert cell.config.world == world and cell.config.steps == se.PPO_STEPS
        assert cell.seeds == se.PPO_SEEDS and len(cell.seeds) >= 5


def test_the_world_table_has_a_row_per_world_and_a_column_per_yardstick():
    from types import SimpleNamespace

    from docking.design import Results

    cells = [c for c in se.DESIGN.cells if c["world"] in ("sideboard", "floor")]
    logs = {c.key: [SimpleNamespace(success_rate=r) for r in (0.9, 1.0, 0.95)] for c in cells}
    table = se.world_table(Results(se.DESIGN, cells, {}, logs))
    lines = table.splitlines()
    assert len(lines) == 2 + len(se.PATH)
    assert lines[0].count("|") == 3 + len(se.WORLD_COLUMNS)
    sideboard = next(line for line in lines if line.startswith("| sideboard |"))
    assert sideboard.count("95.0% [") == len(se.WORLD_COLUMNS)
    dock = next(line for line in lines if line.startswith("| dock |"))
    assert dock.count("| - ") == len(se.WORLD_COLUMNS)  # not run: never a number


def _path_results(paper: dict[str, float], ppo: float):
    """Results of the path's paper and PPO cells with fixed per-world means (10 seeds)."""
    from types import SimpleNamespace

    from docking.design import Results

    spread = np.linspace(-0.01, 0.01, 10)
    cells = [c for c in se.DESIGN.cells if c["variant"] in ("paper", "ppo") and c["world"] in paper]
    logs = {
        c.key: [
            SimpleNamespace(
                success_rate=(paper[c["world"]] if c["variant"] == "paper" else ppo) + e
            )
            for e in spread
        ]
        for c in cells
    }
    return Results(se.DESIGN, cells, {}, logs)


def test_a_factor_breaks_the_learner_only_past_the_drop_and_after_holm():
    worlds = dict(zip(se.MAIN_PATH, (0.95, 0.93, 0.80, 0.79, 0.60), strict=True))
    worlds.update({"sideboard-step8": 0.70, "floor-step8": 0.58})
    steps = se.path_steps(_path_results(worlds, ppo=0.95))
    assert [(s.before, s.after) for s in steps] == list(
        zip(se.MAIN_PATH[:-1], se.MAIN_PATH[1:], strict=True)
    )
    # 2 pp: significant (tiny spread) but not past BREAK_DROP; 13 pp and 19 pp break it
    assert [s.breaks for s in steps] == [False, True, False, True]
    assert all(s.pixels_suffice for s in steps)
    np.testing.assert_allclose(
        [s.p_adjusted for s in steps], stats.holm([s.drop.p_value(0.0) for s in steps])
    )
    branches = se.path_steps(_path_results(worlds, ppo=0.5), se.BRANCHES)
    assert [s.breaks for s in branches] == [True, False]
    assert not any(s.pixels_suffice for s in branches)
    table = se.path_table(steps + branches).splitlines()
    assert len(table) == 2 + 6 and table[3].count("| yes |") == 2  # dock: breaks, suffices


def test_the_family_table_has_a_row_per_judged_claim_with_every_comparison():
    rng = np.random.default_rng(5)
    values = {k: 0.9 + 0.01 * rng.standard_normal(10) for k in ("paper", "a", "b")}
    values["a"] = values["a"] - 0.2
    base = {"a": "paper", "b": "paper"}
    judged = _above("x", "words x", {"w1": ("a",), "w2": ("b",)})
    finding = _above("y", "words y", {"w1": ("b",)}, judged=False)
    fake = _Fake(values, base)
    decisions = claims.judge_family([judged, finding], fake)
    table = claims.family_table([judged, finding], decisions).splitlines()
    assert len(table) == 3 and "words y" not in "\n".join(table)
    row = table[2]
    assert row.startswith("| words x (Sec. I) | supported only in the w1 world |")
    assert "w1: 20." in row and "-> supported" in row and "w2: " in row
    assert f"Holm {decisions[0].p_adjusted:.2g}" in row


def test_episodes_to_level_finds_the_first_window_at_the_level():
    from docking.analysis import episodes_to_level

    success = np.r_[np.zeros(30), np.ones(60)]
    assert episodes_to_level(success, 0.9, window=50) == 30 + 45  # 45 of 50 succeed
    assert episodes_to_level(success, 1.0, window=50) == 80
    assert np.isnan(episodes_to_level(np.zeros(200), 0.9))
    assert np.isnan(episodes_to_level(np.ones(10), 0.9, window=50))  # too short to judge
    with pytest.raises(ValueError, match="window"):
        episodes_to_level(success, 0.9, window=0)


def test_the_efficiency_table_counts_seeds_that_never_reach_the_level():
    found = {
        (k, n): np.array([100.0, np.nan, 300.0])
        for k, *_ in se.PATH
        for n in ("paper", "linear", "ppo")
    }
    lines = se.efficiency_table(found).splitlines()
    assert len(lines) == 2 + len(se.PATH)
    assert lines[2].count("2/3 seeds, median 200") == 3


def test_a_design_with_alpha_is_summarised_as_one_family():
    import dataclasses

    from docking.design import Design, Results, summary

    with pytest.raises(ValueError, match="alpha"):
        dataclasses.replace(se.DESIGN, alpha=1.5)
    found = _path_results({"sideboard": 0.95, "floor": 0.60}, ppo=0.95)
    claim = _above("drop", "the floor is harder", {"path": (("floor/paper", "sideboard/paper"),)})
    cells = list(found.cells)
    for alpha, marker in ((0.05, "Holm"), (None, "the number (95% interval)")):
        design = Design("d", "t", tuple(cells), (0,), claims=(claim,), alpha=alpha)
        text = summary(Results(design, cells, {}, found.logs))
        assert marker in text and "the floor is harder" in text


def test_every_world_of_the_path_has_a_short_label():
    assert list(se.PATH_LABELS) == [key for key, *_ in se.PATH]


def test_a_costly_measure_is_computed_once_per_results_and_served_read_only():
    found = _path_results({"sideboard": 0.95, "floor": 0.60}, ppo=0.95)
    calls = []

    def measure(results, key):
        calls.append(key)
        return results.score(key)

    first = found.measured(measure, "floor/paper")
    again = found.measured(measure, "floor/paper")
    assert calls == ["floor/paper"] and again is first
    np.testing.assert_array_equal(first, found.score("floor/paper"))
    with pytest.raises(ValueError, match="read-only"):
        first[0] = 1.0
    found.measured(measure, "sideboard/paper")
    assert calls == ["floor/paper", "sideboard/paper"]
