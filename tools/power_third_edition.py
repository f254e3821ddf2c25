"""Seeds for the study's third edition from the second edition's effects and spreads.

Reads the verdict table that the archived notebook 07 printed (executed at commit 1341e99,
``archive/07_second_edition.ipynb``), and for each comparison with an interval in
percentage points:

* its spread: the second edition's intervals were Student-t intervals of a difference of
  means over two groups of 10 seeds, so the standard error is the half-width over
  t(0.975, 18), and the standard deviation of a per-seed paired difference, if the two arms
  were uncorrelated, is that standard error times sqrt(10) (pairing by seed can only make
  it smaller when the arms are positively correlated: this is the conservative choice);
* the effect it targets: the second edition's estimate (its absolute value), but at least
  ``--least-effect`` percentage points (a smaller effect is not one a claim rests on);
* its level: ``0.05 / k`` for a claim of ``k`` comparisons (Holm's first step within the
  claim, the strictest), and the seeds at which the paired rule (the interval lies above 0)
  reaches ``--power`` (:func:`seeds_for_power`), at least 10.

Prints a Markdown table. Usage: ``python tools/power_third_edition.py [--power 0.8]``.
"""

from __future__ import annotations

import argparse
import json
import re
import textwrap
from pathlib import Path

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOK = ROOT / "archive" / "07_second_edition.ipynb"
#: One comparison of the verdict table: "world: 9.6 pp [5.4, 13.8]; p ..."
COMPARISON = re.compile(r"([\w ,.-]+): (-?[\d.]+) pp \[(-?[\d.]+), (-?[\d.]+)\]")


def power(n: int, effect: float, sd: float, alpha: float = 0.05) -> float:
    """The power of the paired Student-t rule "the two-sided ``1 - alpha`` interval of the
    mean difference lies above 0" with ``n`` seeds, when the true mean difference is
    ``effect > 0`` and the per-seed differences have standard deviation ``sd``: the
    probability that the lower bound exceeds 0 (noncentral t)."""
    if n < 2 or not effect > 0 or not sd > 0 or not 0 < alpha < 1:
        raise ValueError(
            f"power needs n >= 2, effect > 0, sd > 0, 0 < alpha < 1: {n}, {effect}, {sd}, {alpha}"
        )
    df = n - 1
    critical = stats.t.ppf(1 - alpha / 2, df)
    return float(stats.nct.sf(critical, df, effect / sd * np.sqrt(n)))


def seeds_for_power(
    effect: float,
    sd: float,
    alpha: float = 0.05,
    target: float = 0.8,
    least: int = 10,
    most: int = 200,
) -> int | None:
    """The fewest seeds, at least ``least``, at which :func:`power` reaches ``target``; None
    if even ``most`` seeds do not."""
    for n in range(max(least, 2), most + 1):
        if power(n, effect, sd, alpha) >= target:
            return n
    return None


def verdict_rows(notebook: Path = NOTEBOOK) -> list[tuple[str, list[tuple[str, float, float]]]]:
    """``[(claim, [(world, estimate, half-width), ...]), ...]`` in percentage points, for
    the rows whose comparisons are differences in pp."""
    cells = json.loads(notebook.read_text())["cells"]
    text = ""
    for cell in cells:
        for output in cell.get("outputs", []):
            found = "".join(output.get("data", {}).get("text/markdown", ""))
            if "| claim, in the paper's words |" in found:
                text = found
    rows = []
    for line in text.splitlines()[2:]:
        parts = [p.strip() for p in line.strip("|").split("|")]
        claim, comparisons = parts[0], parts[-1]
        found = [
            (w.strip(), float(e), (float(hi) - float(lo)) / 2)
            for w, e, lo, hi in COMPARISON.findall(comparisons.replace("<br>", "\n"))
        ]
        if found:
            rows.append((claim, found))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--power", type=float, default=0.8, help="the power each row targets")
    parser.add_argument("--least-effect", type=float, default=5.0, help="pp, the smallest effect")
    parser.add_argument("--most", type=int, default=60, help="the most seeds a row may get")
    args = parser.parse_args()
    t = stats.t.ppf(0.975, 18)
    print(
        "| claim | world | 2nd ed. estimate (pp) | per-seed sd (pp) | effect targeted (pp) "
        "| level | seeds for the power | power at 10 seeds | at 20 seeds |\n"
        "|---|---|---|---|---|---|---|---|---|"
    )
    for claim, comparisons in verdict_rows():
        alpha = 0.05 / len(comparisons)
        for world, estimate, half in comparisons:
            sd = half / t * np.sqrt(10)
            effect = max(abs(estimate), args.least_effect)
            seeds = seeds_for_power(effect, sd, alpha, args.power, most=args.most)
            shown = f"> {args.most}" if seeds is None else str(seeds)
            words = textwrap.shorten(claim, 70, placeholder=" ...")
            print(
                f"| {words} | {world} | {estimate:+.1f} | {sd:.1f} | {effect:.1f} | "
                f"{alpha:.3g} | {shown} | {power(10, effect, sd, alpha):.2f} | "
                f"{power(20, effect, sd, alpha):.2f} |"
            )


if __name__ == "__main__":
    main()
