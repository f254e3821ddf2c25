"""The report of the fragility landscape (:mod:`docking.study.designs.landscape`, notebook
07): its figure's panels and marks (:func:`panels`), and how much of each tuning search docks
within a margin of its best (:func:`shares`, its sentence :func:`shares_sentence`).
"""

from __future__ import annotations

import numpy as np

from docking.study.designs import addendum as ad
from docking.study.designs import landscape as ls
from docking.study.designs import replication as rp


def panels(scores: dict) -> tuple[list[dict], dict]:
    """The figure's panels (:func:`docking.study.figures.fig_landscape`) and marks from the
    runs' scores (:func:`docking.study.designs.landscape.run_scores`): per world, the paper's
    learner over beta_a x eps_W at its tuned eps_Q, linear SARSA over beta_a x eps_Q; the
    tuned setting starred, the published one circled."""
    from docking.study.arrays import landscape

    names = {"floor": "floor world", "nao": "Nao-like world"}
    found, marks = [], {}
    for world in ls.WORLDS:
        for learner in ("paper", "linear"):
            other = ls.EPS_W if learner == "paper" else ls.EPS_Q
            grid = {
                (b, o): ls._scores_of(scores, world, learner, ls.setting(world, learner, b, o))
                for b in ls.BETA_A
                for o in other
            }
            tuned = rp.TUNED[world][learner]
            knob = "eps_w" if learner == "paper" else "eps_q"
            title = (
                f"{names[world]}: the paper's learner (eps_Q {tuned['eps_q']:g})"
                if learner == "paper"
                else f"{names[world]}: linear SARSA"
            )
            found.append(
                dict(
                    world=world,
                    learner=learner,
                    title=title,
                    row_label="beta_a in training (Eq. 4)",
                    col_label="eps_W (Eq. 8)" if learner == "paper" else "eps_Q (Eq. 7)",
                    grid=landscape(grid, ls.BETA_A, other),
                )
            )
            published = (
                "published beta_a, eps_W (at eps_Q 0.1)"
                if learner == "paper"
                else ("published setting")
            )
            marks[world, learner] = [
                ("tuned (bracketed)", (tuned["beta_a_train"], tuned[knob])),
                (published, (ls.PUBLISHED["beta_a_train"], ls.PUBLISHED[knob])),
            ]
    return found, marks


def searched(scores: dict, world: str, learner: str) -> dict[tuple, list[float]]:
    """Every setting on the tuning ladders (:data:`docking.study.designs.addendum.LADDERS`)
    that the tuning tables (:data:`docking.study.designs.landscape.TUNING_TABLES`) ran, with
    its runs' success."""
    import itertools

    knobs = ad.KNOBS[learner]
    found = {}
    for values in itertools.product(*(ad.LADDERS[k] for k in knobs)):
        runs = ls._scores_of(scores, world, learner, dict(zip(knobs, values, strict=True)))
        if runs:
            found[values] = runs
    return found


def shares(folder=None, min_runs: int = 2) -> dict[tuple[str, str], tuple[int, int]]:
    """Per world and learner, ``(k, n)``: of the ``n`` settings the tuning searched with at
    least ``min_runs`` runs, the ``k`` whose mean success lies within
    :data:`docking.study.designs.landscape.MARGIN` of the best of them
    (:func:`docking.study.arrays.share_near_best`)."""
    from docking.study.arrays import share_near_best

    scores = ls.run_scores(ls.TUNING_TABLES, folder)
    found = {}
    for world in ls.WORLDS:
        for learner in ("paper", "linear"):
            means = [
                np.mean(r) for r in searched(scores, world, learner).values() if len(r) >= min_runs
            ]
            found[world, learner] = share_near_best(means, ls.MARGIN)
    return found


def shares_sentence(found: dict) -> str:
    """The sentence under the landscape figure (``found``: :func:`shares`)."""
    names = {"floor": "the floor world", "nao": "the Nao-like world"}
    parts = [
        f"in {names[w]}, {found[w, 'paper'][0]} of the paper's learner's {found[w, 'paper'][1]} "
        f"searched settings and {found[w, 'linear'][0]} of linear SARSA's {found[w, 'linear'][1]}"
        for w in ls.WORLDS
    ]
    return (
        f"Within {100 * ls.MARGIN:.0f} pp of the best setting of its own search (settings run on "
        f"2 seeds or more): " + "; ".join(parts) + "."
    )
