"""The results table: the paper's numbers beside this reproduction's.

``python -m docking.report`` loads the saved runs of both experiments (running any that are
missing) and prints the table in Markdown; the notebooks show the same table.
"""

from __future__ import annotations

import numpy as np

from docking.experiments import (EXPERIMENT_1, EXPERIMENT_2, HEADLINE_SEED, SEEDS,
                                 ExperimentResult, run_seeds)

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


def _pct(x: float) -> str:
    return f"{100 * x:.1f}%"


def experiment1_rows(results: list[ExperimentResult]) -> list[tuple[str, str, str]]:
    """``(quantity, paper, ours)`` rows for Experiment 1."""
    h = headline(results)
    rates = np.array([r.test.success_rate for r in results])
    mastered = [r.rewarded_until_mastery for r in results]
    per_seed = ", ".join(f"{r.seed}: {r.test_successes}/{len(r.test.success)}" for r in results)
    reached = [m for m in mastered if m is not None]
    return [
        ("Exp. 1 test success, headline seed", PAPER["exp1_success"],
         f"{_pct(h.test.success_rate)} ({h.test_successes}/{len(h.test.success)}, seed {h.seed})"),
        ("Exp. 1 seeds with 100% test success", "(one run)",
         f"{int(np.sum(rates == 1.0))} of {len(results)} (mean {_pct(rates.mean())}, "
         f"min {_pct(rates.min())}; {per_seed})"),
        ("Exp. 1 rewarded trials until the test first reaches 100%",
         PAPER["exp1_rewards_to_mastery"],
         f"{h.rewarded_until_mastery} (headline); per seed "
         + ", ".join("never" if m is None else str(m) for m in mastered)
         + (f"; median {int(np.median(reached))}" if reached else "")),
    ]


def experiment2_rows(results: list[ExperimentResult]) -> list[tuple[str, str, str]]:
    """``(quantity, paper, ours)`` rows for Experiment 2."""
    h = headline(results)
    rates = np.array([r.test.success_rate for r in results])
    per_seed = ", ".join(f"{r.seed}: {r.test_successes}/{len(r.test.success)}" for r in results)
    times = np.array([r.wall_time_train + r.wall_time_test for r in results])
    spread = f" ± {_pct(rates.std(ddof=1))} (s.d.)" if len(results) > 1 else ""
    return [
        ("Exp. 2 test success, headline seed", PAPER["exp2_success"],
         f"{_pct(h.test.success_rate)} ({h.test_successes}/{len(h.test.success)}, seed {h.seed})"),
        (f"Exp. 2 test success over {len(results)} seeds", "(one run)",
         f"mean {_pct(rates.mean())}{spread}, min {_pct(rates.min())} ({per_seed})"),
        ("Exp. 2 wall time, 2000 training + 725 test trials", PAPER["exp2_wall_time"],
         f"{times.mean():.0f} s per run (2-core CPU, software rendering; "
         f"{h.wall_time_train:.0f} s training + {h.wall_time_test:.0f} s testing for the "
         f"headline seed)"),
    ]


def markdown_table(rows: list[tuple[str, str, str]]) -> str:
    lines = ["| Quantity | Paper | This reproduction |", "|---|---|---|"]
    lines += [f"| {q} | {p} | {o} |" for q, p, o in rows]
    return "\n".join(lines)


def main() -> None:
    results1 = run_seeds(EXPERIMENT_1, SEEDS[EXPERIMENT_1.name])
    results2 = run_seeds(EXPERIMENT_2, SEEDS[EXPERIMENT_2.name])
    print(markdown_table(experiment1_rows(results1) + experiment2_rows(results2)))


if __name__ == "__main__":
    main()
