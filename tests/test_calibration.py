"""The calibration variants of notebooks 03 and 04: valid, distinct runs that change only what
they name; their table; running them through the store."""

import dataclasses

import numpy as np
import pytest

from docking.presets import EXPERIMENT_1, EXPERIMENT_2, SEEDS
from docking.study.arrays import rewarded_share
from docking.study.design import Cell
from docking.study.designs.calibration import BASELINE, run, variants
from docking.study.designs.calibration_report import (
    analyse,
    calibration_rows,
    calibration_table,
    computing_time,
)
from docking.study.kinds import config_key
from docking.study.stats import difference_ci, mean_ci

BASES = {"experiment1": EXPERIMENT_1, "experiment2": EXPERIMENT_2}

#: What each variant sets, as dotted paths of ExperimentConfig.to_dict().
EXPECTED = {
    "experiment1": {
        "start": {
            "world.step_forward": 0.08,
            "world.step_side": 0.06,
            "world.start_near": 0.65,
            "world.start_far": 0.85,
            "world.dock_depth": 0.20,
            "world.dock_width": 0.08,
            "network.eps_q": 0.5,
        },
        "short-steps": {"world.step_forward": 0.08, "world.step_side": 0.06},
        "epsQ-0.05": {"network.eps_q": 0.05},
        BASELINE: {},
        "epsQ-0.2": {"network.eps_q": 0.2},
        "start-0.60-0.80": {"world.start_near": 0.60, "world.start_far": 0.80},
    },
    "experiment2": {
        "8cm-steps": {"world.step_forward": 0.08},
        BASELINE: {},
        "epsQ-0.03": {"network.eps_q": 0.03},
        "epsQ-0.2": {"network.eps_q": 0.2},
        "epsW-1": {"network.eps_w": 1.0},
    },
}


def _flat(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(_flat(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


@pytest.mark.parametrize("experiment", ["experiment1", "experiment2"])
def test_variants_are_distinct_runs_that_change_only_what_they_name(experiment):
    base = BASES[experiment]
    rows = variants(experiment)
    assert [v.key for v in rows] == list(EXPECTED[experiment])
    assert len({config_key(v.config) for v in rows}) == len(rows)
    assert len({v.label for v in rows}) == len(rows)
    reference = _flat(base.to_dict())
    for v in rows:
        flat = _flat(v.config.to_dict())
        differ = {k: flat[k] for k in flat if flat[k] != reference[k]}
        if v.key == BASELINE:
            assert v.config is base and not differ  # the main experiment's own runs
            continue
        assert v.config.name == f"calibration-{experiment}"
        assert v.config.eval_trials == 0
        assert v.config.test_trials == base.test_trials  # the main experiment's test
        assert v.config.train_trials == base.train_trials
        expected = EXPECTED[experiment][v.key]
        assert set(v["changes"]) == set(expected)
        assert differ == {"name": v.config.name, "eval_trials": 0, **expected}
        # The configuration round-trips (the store re-reads it).
        assert type(v.config).from_dict(v.config.to_dict()) == v.config


def test_unknown_experiment_is_refused():
    with pytest.raises(ValueError, match="experiment1"):
        variants("experiment3")


def _rows():
    base = EXPERIMENT_1
    return [
        Cell("worse", dataclasses.replace(base, name="x"), label="worse setting"),
        Cell(BASELINE, base, label="the setting"),
    ]


def test_markdown_table_from_synthetic_results():
    success = {"worse": [0.5, 1.0, 0.75], BASELINE: [1.0, 1.0, 0.995]}
    rewarded = {"worse": [0.2, 0.3, 0.25], BASELINE: [0.6, 0.5, 0.55]}
    rows = analyse(_rows(), success, BASELINE, rewarded)
    assert [r.key for r in rows] == ["worse", BASELINE]
    worse, this = rows
    assert worse.success == mean_ci(success["worse"])
    assert worse.difference == difference_ci(success["worse"], success[BASELINE])
    assert this.difference is None
    assert (worse.at_100, this.at_100) == (1, 2)
    assert worse.rewarded == mean_ci(rewarded["worse"])
    assert worse.rewarded_difference == difference_ci(rewarded["worse"], rewarded[BASELINE])
    assert this.rewarded_difference is None
    lines = calibration_table(rows, BASELINE, seeds_at_100=True).splitlines()
    assert len(lines) == 4
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    assert header == [
        "setting",
        "test success, % [95% CI]",
        "per seed, %",
        "minus this config., pp",
        "training trials rewarded, %",
        "seeds at 100 %",
    ]
    assert lines[1] == "|---|---|---|---|---|---|"
    cells = [c.strip() for c in lines[2].strip("|").split("|")]
    assert cells[0] == "worse setting"
    assert cells[1].startswith("75.0 [")
    assert cells[2] == "50.0, 100.0, 75.0"
    assert cells[3] == worse.difference.format() and cells[3].startswith("-24.8 [")
    assert cells[4].startswith("25.0 [")
    assert cells[5] == "1 of 3"
    bold = [c.strip() for c in lines[3].strip("|").split("|")]
    assert all(c.startswith("**") and c.endswith("**") for c in bold)
    assert bold[0] == "**the setting (this configuration)**"
    assert bold[3] == "**—**" and bold[5] == "**2 of 3**"
    # Without rewarded shares and the 100% column (Experiment 2's table).
    plain = calibration_table(analyse(_rows(), success, BASELINE), BASELINE).splitlines()
    assert plain[0].count("|") == 5 and "seeds at 100" not in plain[0]


def test_with_its_trials_a_rows_success_gets_the_interval_for_a_rate():
    """Given each seed's test trials (as calibration_rows gives them), a row's success has
    the interval for a rate: seeds at 100% are not the point [1, 1] the bootstrap gives."""
    from docking.study.stats import rate_ci

    success = {"worse": [0.5, 1.0, 0.75], BASELINE: [1.0, 1.0, 1.0]}
    trials = {"worse": [200] * 3, BASELINE: [200] * 3}
    worse, this = analyse(_rows(), success, BASELINE, trials=trials)
    assert worse.success == rate_ci(success["worse"], 200)
    assert this.success.low < this.success.high == 1.0 == this.success.estimate
    assert mean_ci(success[BASELINE]).low == 1.0  # without the trials: a point


def test_analyse_needs_the_baseline():
    with pytest.raises(ValueError, match="baseline"):
        analyse(_rows()[:1], {"worse": [0.5, 1.0]}, BASELINE)


def test_run_goes_through_the_store_and_resumes(tmp_path, monkeypatch):
    tiny = dataclasses.replace(EXPERIMENT_1, train_trials=2, test_trials=2, eval_trials=0)
    rows = [
        Cell(BASELINE, tiny, label="tiny"),
        Cell(
            "epsQ",
            dataclasses.replace(
                tiny,
                name="calibration-test",
                network=dataclasses.replace(tiny.network, eps_q=0.2),
            ),
            {"changes": ("network.eps_q",)},
            "tiny, eps_Q 0.2",
            BASELINE,
        ),
    ]
    kwargs = dict(variants=rows, seeds=(0, 1), results_dir=tmp_path, workers=1, progress=False)
    first = run("experiment1", **kwargs)
    assert first.design.seeds == (0, 1)
    assert [r.seed for r in first.runs["epsQ"]] == [0, 1]
    assert first.runs["epsQ"][0].config == rows[1].config
    assert (tmp_path / "calibration-test").is_dir() and (tmp_path / tiny.name).is_dir()
    assert first.score("epsQ").shape == (2,) and rewarded_share(first.runs[BASELINE]).shape == (2,)
    assert computing_time(first, BASELINE) > 0

    def refuse(*args, **kwargs):
        raise AssertionError("a stored run was computed again")

    from docking.study.stats import rate_ci

    monkeypatch.setattr("docking.study.kinds.run_experiment", refuse)
    again = run("experiment1", **kwargs)
    for key in ("epsQ", BASELINE):
        np.testing.assert_array_equal(again.score(key), first.score(key))
        for a, b in zip(again.runs[key], first.runs[key], strict=True):
            np.testing.assert_array_equal(a.network.W, b.network.W)
    found = calibration_rows(again, BASELINE)
    trials = [len(log.success) for log in again.logs["epsQ"]]
    by_key = {r.key: r for r in found}
    assert by_key["epsQ"].success == rate_ci(again.score("epsQ"), trials)  # from the logs
    table = calibration_table(found, BASELINE, seeds_at_100=True)
    assert "tiny, eps_Q 0.2" in table and "**tiny (this configuration)**" in table
    # every training trial starts beyond 0 m: the share is each run's training success rate
    expected = [r.train.success_rate for r in again.runs["epsQ"]]
    np.testing.assert_array_equal(rewarded_share(again.runs["epsQ"]), expected)


def test_seeds_are_the_main_experiments():
    for experiment in ("experiment1", "experiment2"):
        assert len(SEEDS[experiment]) >= 5


def test_one_markdown_table_helper_for_every_table():
    from docking.study.report import md_table

    assert (
        md_table(("a", "b"), [(1, "x"), ("", 2.5)]) == "| a | b |\n|---|---|\n| 1 | x |\n|  | 2.5 |"
    )
    assert md_table(("only",), []) == "| only |\n|---|"
    # a pipe in a cell does not split its row (as in the verdict table's claim words)
    header, _, row = md_table(("a", "b"), [("|heading error|", 1)]).splitlines()
    assert row.replace("\\|", "").count("|") == header.count("|")
