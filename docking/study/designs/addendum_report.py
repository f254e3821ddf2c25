"""The report of the third edition's addendum (:mod:`docking.study.designs.addendum`,
notebooks 10 and 08): the tuned settings and where each lies in its ladder, the training steps,
the decomposition of the gap (notebook 08), and its sentence.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.study.designs.third_edition_report import CONTEST_NAMES, CONTEST_WORLDS
from docking.study.report import _pct, contest_gaps, md_table
from docking.study.stats import Interval


def bracketed_rows(results, ad) -> list[dict]:
    """Per world and learner of the addendum (``ad``: :mod:`docking.study.designs.addendum`, or a
    module like it): the settings
    its search tried, the training runs it used, the tuned setting, each knob's value with
    the values tried on its line through the tuned setting and where it lies (interior, at
    a stated limit, or at the edge where the search stopped), and the tuned setting's mean
    over its tuning seeds."""
    rows = []
    for world in ad.WORLDS:
        for learner in ad.LEARNERS:
            tried = ad.TUNING.evaluated(results, world, learner)
            tuned = ad.TUNING.tuned(results, world, learner)
            key = f"{world}/tune-{learner}/{ad.tag(tuned)}"
            rows.append(
                dict(
                    world=world,
                    learner=learner,
                    settings=len(tried),
                    extended=len(tried) - len(ad.round1_settings(learner)),
                    runs=ad.TUNING.runs_used(results, world, learner),
                    tuned=tuned,
                    tuning_seeds=ad.TUNING.all_seeds(results, key),
                    positions={k: ad.position(results, world, learner, k) for k in tuned},
                )
            )
    return rows


def _knob_lines(row: dict) -> list[str]:
    """Per knob of ``row`` (:func:`bracketed_rows`' or :func:`bracketing_rows`'): its tuned
    value in bold among the values tried on its line, and where it lies."""
    found = []
    for knob, value in row["tuned"].items():
        line, where = row["positions"][knob]
        shown = " · ".join(f"**{v:g}**" if v == value else f"{v:g}" for v in line)
        found.append(f"{knob}: {shown} ({where})")
    return found


def bracketed_table(rows: list[dict]) -> str:
    """The Markdown table of :func:`bracketed_rows`: each tuned value in bold among the
    values tried on its line, and where it lies."""
    found = []
    for r in rows:
        knobs = _knob_lines(r)
        found.append(
            (
                CONTEST_WORLDS.get(r["world"], r["world"]),
                r["learner"],
                f"{r['settings']} ({r['extended']} by extension)",
                r["runs"],
                "<br>".join(knobs),
                f"{100 * r['tuning_seeds'].mean():.1f}% (n = {len(r['tuning_seeds'])})",
            )
        )
    header = ("world", "learner", "settings tried", "training runs", "tuned value: tried")
    return md_table((*header, "its tuning success"), found)


def training_steps_rows(results, worlds, variants) -> list[tuple]:
    """Per world and variant (``{variant: label}``): the environment steps of training per
    run (mean, min-max over seeds; PPO: its budget)."""
    rows = []
    for world in worlds:
        for variant, label in variants.items():
            key = f"{world}/{variant}"
            if key not in {c.key for c in results.cells}:
                continue
            runs = results.runs[key]
            if hasattr(runs[0], "train"):
                steps = np.array([int(np.sum(r.train.steps)) for r in runs])
            else:  # a PPO run: the budget it trained for
                steps = np.array([r.config.steps for r in runs])
            rows.append((CONTEST_WORLDS.get(world, world), label, len(runs), steps))
    return rows


def training_steps_table(rows: list[tuple]) -> str:
    """The Markdown table of :func:`training_steps_rows`."""
    return md_table(
        ("world", "learner", "runs", "training steps per run: mean (min-max)"),
        [
            (w, label, n, f"{steps.mean():,.0f} ({steps.min():,}-{steps.max():,})")
            for w, label, n, steps in rows
        ],
    )


@dataclasses.dataclass(frozen=True)
class Decomposition:
    """One world's gap between linear SARSA and the paper's tuned learner (:attr:`gap`, paired
    by seed) beside the per-seed arrays that the addendum's rules meant to split it with (the
    paper's W with the oracle-labelled Q, and W's purity), as
    :func:`docking.study.designs.addendum.decomposition` computes them from the runs and the
    pose oracle's views. The runs show that the oracle-labelled Q is no bound on what W
    allows, so notebook 08 draws and tabulates the arrays and no split of the gap.

    Attributes:
      world: The world's key.
      linear, paper: Per-seed held-out success of the tuned learners.
      labelled: Per seed, the paper's W with the oracle-labelled Q
        (:func:`docking.study.analysis.oracle_labelled`).
      purity: Per seed, the share of the oracle's views whose action is their unit's
        majority action (:func:`docking.study.analysis.partition_purity`).
      fixed, fixed_labelled: The same for SARSA on a fixed partition (W from views, then
        frozen): its own success and its W with the oracle-labelled Q.
    """

    world: str
    linear: np.ndarray
    paper: np.ndarray
    labelled: np.ndarray
    purity: np.ndarray
    fixed: np.ndarray
    fixed_labelled: np.ndarray

    @property
    def gap(self) -> Interval:
        """Linear SARSA minus the paper's tuned learner (paired Student-t)."""
        from docking.study.stats import t_paired_ci

        return t_paired_ci(self.linear, self.paper)


def addendum_summary(added, contest, ad) -> str:
    """The README's sentences on the third edition's addendum (``added``: its results;
    ``contest``: the third edition's; ``ad``: :mod:`docking.study.designs.addendum`): per world,
    the tuned learners' held-out success after the bracketed search, the gap and the rule's
    verdict, beside the contest's gap."""
    from docking.study.stats import t_mean_ci

    gaps = {g.world: g for g in contest_gaps(added, ad.WORLDS, ad.GAP_CLOSED)}
    before = {g.world: g for g in contest_gaps(contest, ad.WORLDS, ad.GAP_CLOSED)}
    parts = []
    for world in ad.WORLDS:
        paper = t_mean_ci(added.score(f"{world}/paper-tuned"))
        linear = t_mean_ci(added.score(f"{world}/linear-tuned"))
        parts.append(
            f"in {CONTEST_NAMES[world]} the paper's learner docks {_pct(paper.estimate)} "
            f"(contest: {_pct(float(np.mean(contest.score(f'{world}/paper-tuned'))))}), linear "
            f"SARSA {_pct(linear.estimate)}; the gap is {gaps[world].interval.format(unit=' pp')}"
            f" (contest: {before[world].interval.estimate * 100:.1f} pp), "
            f"**{gaps[world].words}**"
        )
    return (
        "**Tuned further** (the addendum, notebook 10: both SARSA learners tuned on the same "
        "knobs of Eq. 4-8 by a search extending until every chosen value was bracketed or its "
        "five stages ran out, "
        f"{ad.BUDGET} training runs each per world, fresh seeds): " + "; ".join(parts) + "."
    )
