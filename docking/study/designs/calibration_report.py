"""The report of the calibration designs (:mod:`docking.study.designs.calibration`,
notebooks 03 and 04): each variant's row against a baseline row.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.study import arrays
from docking.study.stats import Interval, difference_ci, mean_ci, rate_ci


@dataclasses.dataclass(frozen=True)
class Row:
    """One row of a calibration table, computed from per-seed numbers.

    Attributes:
      key, label: As the variant's.
      success: Mean test success over seeds with its 95% bootstrap interval (the per-seed
        values in ``success.values``).
      difference: Mean success minus the baseline row's, with its 95% interval (seeds
        resampled per row); None for the baseline itself.
      at_100: Seeds whose test success is 100%.
      rewarded: Mean share of training trials rewarded, with its interval; None if not given.
      rewarded_difference: That share minus the baseline row's, with its interval (seeds
        resampled per row); None for the baseline or if not given.
    """

    key: str
    label: str
    success: Interval
    difference: Interval | None
    at_100: int
    rewarded: Interval | None = None
    rewarded_difference: Interval | None = None

    @property
    def n_seeds(self) -> int:
        return len(self.success.values)


def analyse(
    rows,
    success: dict[str, np.ndarray],
    baseline: str,
    rewarded: dict[str, np.ndarray] | None = None,
    seed: int = 0,
    trials: dict[str, np.ndarray] | None = None,
) -> list[Row]:
    """The table's rows (cells ``rows``) from per-seed test success (and training trials
    rewarded) per cell key; differences against the row ``baseline``, which ``rows`` must
    hold. With ``trials`` (per cell key, each seed's test trials), a row's success gets the
    interval for a rate (:func:`docking.study.stats.rate_ci`), else the bootstrap's."""
    if baseline not in {v.key for v in rows}:
        raise ValueError(f"the rows must include the baseline {baseline!r}")
    base = np.asarray(success[baseline], dtype=float)
    out = []
    for v in rows:
        x = np.asarray(success[v.key], dtype=float)
        is_base = v.key == baseline
        out.append(
            Row(
                v.key,
                v.label,
                mean_ci(x, seed=seed) if trials is None else rate_ci(x, trials[v.key]),
                None if is_base else difference_ci(x, base, seed=seed),
                int(np.sum(x == 1.0)),
                None if rewarded is None else mean_ci(rewarded[v.key], seed=seed),
                None
                if rewarded is None or is_base
                else difference_ci(rewarded[v.key], rewarded[baseline], seed=seed),
            )
        )
    return out


def calibration_table(rows: list[Row], baseline: str, seeds_at_100: bool = False) -> str:
    """The calibration table in Markdown: the setting; mean test success with its 95%
    interval; the per-seed values; the difference to this configuration with its interval
    (pp); the share of training trials rewarded (if the rows carry it); the seeds at 100%
    (if ``seeds_at_100``). The baseline row is in bold."""
    with_rewarded = all(r.rewarded is not None for r in rows)
    header = ["setting", "test success, % [95% CI]", "per seed, %", "minus this config., pp"]
    if with_rewarded:
        header.append("training trials rewarded, %")
    if seeds_at_100:
        header.append("seeds at 100 %")
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        cells = [
            r.label + (" (this configuration)" if r.key == baseline else ""),
            r.success.format(),
            ", ".join(f"{100 * v:.1f}" for v in r.success.values),
            "—" if r.difference is None else r.difference.format(),
        ]
        if with_rewarded:
            cells.append(r.rewarded.format())
        if seeds_at_100:
            cells.append(f"{r.at_100} of {r.n_seeds}")
        if r.key == baseline:
            cells = [f"**{c}**" for c in cells]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def calibration_rows(results, baseline: str, seed: int = 0) -> list[Row]:
    """The rows (:func:`analyse`) of a calibration design's results against its row
    ``baseline``: test success (with the interval for a rate) and the share of training
    trials rewarded, per seed."""
    return analyse(
        results.cells,
        {c.key: results.score(c.key) for c in results.cells},
        baseline,
        {c.key: arrays.rewarded_share(results.runs[c.key]) for c in results.cells},
        seed=seed,
        trials={c.key: [len(log.success) for log in results.logs[c.key]] for c in results.cells},
    )


def computing_time(results, baseline: str | None = None, key: str | None = None) -> float:
    """Seconds of computing (training and test) of row ``key``'s runs, or of every row's but
    ``baseline`` (a calibration's own cost) if ``key`` is None."""
    keys = [key] if key is not None else [c.key for c in results.cells if c.key != baseline]
    return float(sum(r.wall_time_train + r.wall_time_test for k in keys for r in results.runs[k]))
