"""The paper's Experiments 1 and 2 (notebooks 03 and 04) as a design: each preset
(:data:`~docking.presets.EXPERIMENT_1`, :data:`~docking.presets.EXPERIMENT_2`) for the seeds
of :data:`~docking.presets.SEEDS`, measured by its test trials; the report is the README's
results table, the paper's numbers beside ours
(:func:`docking.study.designs.paper_report.results_table`).

``python -m docking design run paper`` (or ``python -m docking run experiment1``, which also
takes any field as an option).
"""

from __future__ import annotations

from docking.presets import EXPERIMENT_1, EXPERIMENT_2, HEADLINE_SEED, SEEDS
from docking.study.design import Cell, Design, Results

if SEEDS["experiment1"] != SEEDS["experiment2"]:  # one design, one seed list
    raise ValueError("docking.presets.SEEDS must give both experiments the same seeds")


def _report(results: Results) -> str:
    from docking.study.designs.paper_report import results_table

    return results_table(results.runs["experiment1"], results.runs["experiment2"])


DESIGN = Design(
    name="paper",
    title="the paper's Experiments 1 and 2, as published, for five seeds each",
    cells=(
        Cell(
            "experiment1",
            EXPERIMENT_1,
            {"experiment": "Experiment 1"},
            "Experiment 1: near the dock, 4 units, local rule",
        ),
        Cell(
            "experiment2",
            EXPERIMENT_2,
            {"experiment": "Experiment 2"},
            "Experiment 2: 36 units, Eq. (8), growing region",
        ),
    ),
    seeds=SEEDS["experiment1"],
    measure="test",
    report=_report,
    # Figs. 3-5 draw the headline runs; notebooks 03-04 read every seed's network and test
    # winners, and classify the test failures (their paths).
    whole={"experiment1": (HEADLINE_SEED,), "experiment2": (HEADLINE_SEED,)},
    keep=frozenset({"paths", "networks", "winners"}),
)
