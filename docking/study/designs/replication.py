"""The replication of the main finding (issue 50), a labelled analysis beside
:mod:`docking.study.designs.bracketing_continued`, judged on seeds no earlier run has used.

**These rules were committed before any of its runs** and are not changed after seeing them
(their record, ``rules/bracketing-replication.*``: the rules text pinned at the rules' commit,
its verdict functions' source as it was then; tests/test_records.py holds the live rules to it
and replays them on the ledger's runs).

Why: the bracketing continued judged both tuned SARSA learners on ten fresh seeds
(7000-7009). In the Nao-like world its interval put the paper's learner ahead, at the edge
of the interval, seen once; in the floor world its gap rule said *closed*. A lead seen once
is not a finding until it replicates, and a verdict resting on one set of ten seeds is worth
a second look on others.

The replication, fixed before its runs:

* **The same runs on new seeds.** The tuned settings are the bracketing continued's
  (:data:`TUNED`, its last incumbents; a test checks them against its ledger), and PPO's
  runs are its matched-step runs (:data:`PPO_STEPS`, the same configurations): each cell
  is a bracketing-continued cell with only the name (so the table) and the seeds changed.
  Nothing is tuned again.
* **Seeds** :data:`SEEDS`: 20 per world, fresh (no run of any earlier design used them).
* **The gap rule, unchanged** (:func:`gap_verdict`, the addendum's): linear SARSA minus the
  paper's learner over the matched seeds, the per-seed differences' Student-t 95% interval;
  *closed* if it lies below :data:`GAP_CLOSED`, *remains* if above, else *undecided*.
* **The lead** (:func:`lead_verdicts`, new here): per world, the two-sided one-sample t-test
  of the per-seed differences against zero; Holm's adjustment over the two worlds at
  :data:`ALPHA`; *the paper's learner ahead* or *linear SARSA ahead* where the adjusted
  p-value is below it, else *no lead shown*.
* **What may be said** (:func:`wording`): a world's gap is called *closed* only where both
  the bracketing continued and the replication say closed, and a learner *ahead* only where
  both put the same learner ahead; otherwise the two verdicts are given side by side and the
  finding is called *not replicated*.

The seeds are matched, not the streams: each learner's run of a seed draws its held-out
start poses and step noise from one generator, so only a seed's first trial shares its start
across learners. The interval is valid because the seeds are matched; it gains little from
pairing (the learners' per-seed rates hardly correlate).

Budget: 120 runs (3 learners x 2 worlds x 20 seeds), about 1.3 h of one process.
"""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
from scipy import stats as sps

from docking.study.design import Cell, Design
from docking.study.designs import addendum as ad
from docking.study.designs.builders import experiment2_in, linear_sarsa, net, variant

NAME = "bracketing-replication"
#: The judged seeds: fresh, 20 per world (no run of the ledger used a seed above 7009).
SEEDS = tuple(range(7100, 7120))
#: The tuned settings of the bracketing continued (its last incumbents), per world and learner.
TUNED = {
    "floor": {
        "paper": {"eps_q": 0.03, "beta_a_train": 100.0, "eps_w": 0.5},
        "linear": {"eps_q": 0.1, "beta_a_train": 10.0},
    },
    "nao": {
        "paper": {"eps_q": 0.3, "beta_a_train": 50.0, "eps_w": 0.5},
        "linear": {"eps_q": 0.03, "beta_a_train": 10.0},
    },
}
#: PPO's training steps per world: the bracketing continued's matched steps (its tuned paper
#: learner's mean training steps on its judged runs, rounded to 16 environments).
PPO_STEPS = {"floor": 19232, "nao": 17888}
#: The gap rule's bound (the addendum's): closed if the interval lies below 5 pp.
GAP_CLOSED = 0.05
#: The level of the gap intervals (95%) and of the leads' family (Holm over the worlds).
ALPHA = 0.05
WORLDS = ("floor", "nao")
LEARNERS = ("paper", "linear")


def learner_config(world: str, learner: str):
    """The tuned ``learner`` (``"paper"``, ``"linear"`` or ``"ppo"``) of ``world``, stored
    under this design's name."""
    if learner == "ppo":
        config = ad.learner_config(
            world, "ppo", steps=PPO_STEPS[world], envs=ad.PPO_ENVS, **ad.PPO_SETTINGS[world]
        )
        return dataclasses.replace(config, name=NAME)
    base = experiment2_in(ad.WORLDS[world], NAME)
    make = linear_sarsa if learner == "linear" else net
    return variant(base, NAME, network=make(base, **TUNED[world][learner]))


def _cell(world: str, learner: str) -> Cell:
    label = (
        f"PPO at {PPO_STEPS[world]} training steps"
        if learner == "ppo"
        else f"{learner}, tuned: {ad.tag(TUNED[world][learner])}"
    )
    return Cell(
        f"{world}/{learner}",
        learner_config(world, learner),
        {"world": world, "learner": learner},
        label,
    )


DESIGN = Design(
    name=NAME,
    title="the main finding replicated: both tuned SARSA learners and PPO on 20 fresh seeds",
    cells=tuple(_cell(w, learner) for w, learner in itertools.product(WORLDS, (*LEARNERS, "ppo"))),
    seeds=SEEDS,
    measure="heldout",
    alpha=ALPHA,
)


# ------------------------------------------------------------------------------------------
# The verdicts (their source is part of the rules).
# ------------------------------------------------------------------------------------------


def gap_interval(linear, paper, confidence=1 - ALPHA):
    """``(mean, low, high)`` of linear SARSA's per-seed success minus the paper's learner's
    over matched seeds: the per-seed differences' Student-t interval."""
    d = np.asarray(linear, dtype=np.float64) - np.asarray(paper, dtype=np.float64)
    if d.ndim != 1 or len(d) < 2:
        raise ValueError(f"gap_interval needs two matched series of 2 or more seeds, got {d!r}")
    half = float(sps.t.ppf(0.5 + confidence / 2, len(d) - 1) * d.std(ddof=1) / np.sqrt(len(d)))
    return float(d.mean()), float(d.mean()) - half, float(d.mean()) + half


def gap_verdict(linear, paper, bound=GAP_CLOSED):
    """The addendum's gap rule: ``"closed"`` if the interval lies below ``bound``,
    ``"remains"`` if above it, else ``"undecided"``."""
    _, low, high = gap_interval(linear, paper)
    return "closed" if high < bound else "remains" if low > bound else "undecided"


def lead_verdicts(pairs, alpha=ALPHA):
    """Per world (``pairs``: ``{world: (linear, paper)}`` per-seed success): the two-sided
    t-test of the differences against zero, Holm-adjusted over the worlds; ``{world:
    (verdict, adjusted p)}`` with verdict ``"paper ahead"``, ``"linear ahead"`` or
    ``"no lead shown"``."""
    worlds = list(pairs)
    diffs = [np.asarray(pairs[w][0], float) - np.asarray(pairs[w][1], float) for w in worlds]
    p = np.array([sps.ttest_1samp(d, 0.0).pvalue for d in diffs])
    order, adjusted, running = np.argsort(p, kind="stable"), np.empty(len(p)), 0.0
    for rank, k in enumerate(order):
        running = max(running, min(1.0, (len(p) - rank) * p[k]))
        adjusted[k] = running
    found = {}
    for w, d, q in zip(worlds, diffs, adjusted, strict=True):
        side = "paper ahead" if d.mean() < 0 else "linear ahead"
        found[w] = (side if q < alpha else "no lead shown", float(q))
    return found


def wording(first_gap, replication_gap, first_lead, replication_lead):
    """What may be said of one world: ``(gap words, lead words)``. ``first_*`` are the
    bracketing continued's verdicts, ``replication_*`` this design's (gap: ``"closed"``,
    ``"remains"``, ``"undecided"``; lead: ``"paper ahead"``, ``"linear ahead"``,
    ``"no lead shown"``)."""
    if first_gap == replication_gap:
        gap = f"{first_gap}, replicated"
    else:
        gap = f"{first_gap} at first, {replication_gap} in the replication: not replicated"
    if first_lead == replication_lead == "no lead shown":
        lead = "no lead shown in either"
    elif first_lead == replication_lead:
        lead = f"{first_lead}, replicated"
    else:
        lead = f"{first_lead} at first, {replication_lead} in the replication: not replicated"
    return gap, lead


def first_lead(interval_low, interval_high):
    """The bracketing continued's lead, read from its 95% interval of linear minus paper
    (it had no lead rule: an interval below zero is read as the paper's learner ahead)."""
    if interval_high < 0:
        return "paper ahead"
    if interval_low > 0:
        return "linear ahead"
    return "no lead shown"


def replayed(results) -> dict:
    """What the rules reach, as data (its record's replay): per world the gap rule's interval
    and verdict and the lead rule's verdict."""
    pairs = {w: (results.score(f"{w}/linear"), results.score(f"{w}/paper")) for w in WORLDS}
    return {
        "gaps": {w: [*gap_interval(*p), gap_verdict(*p)] for w, p in pairs.items()},
        "leads": {w: list(v) for w, v in lead_verdicts(pairs).items()},
    }


#: The constants that are rules (:func:`docking.study.designs.rules_data`).
RULES = "SEEDS TUNED PPO_STEPS GAP_CLOSED ALPHA WORLDS LEARNERS".split()
