"""The report of the equal contest (:mod:`docking.study.designs.equal_contest`, notebook 07): its
verdicts (the lead, non-inferiority at 5 pp, equivalence within +-5 pp, the failure ratio), the
runs each learner spent, the chosen settings, the fragility of each learner's common grid, and
the arrays of its figures. Every function takes the design's results (from the store or the
ledger) and returns arrays, dicts or Markdown.
"""

from __future__ import annotations

import numpy as np

from docking.study.designs import equal_contest as ec
from docking.study.designs import third_edition as te

#: What tables call the worlds and the learners.
WORLD_NAMES = {"sideboard": "sideboard world", "floor": "floor world", "nao": "Nao-like world"}
LEARNER_NAMES = {"paper": "the paper's learner", "linear": "linear SARSA", "ppo": "PPO"}
#: A grid point "docks well" at or above this mean success (the fragility's first count).
WELL = 0.90
#: The published (paper) or default (PPO: skrl's) setting of each learner, marked on the grids:
#: ``(label, {field: value})``. The paper gives beta_a 2; eps_Q 0.1 and eps_W 0.05 are our
#: defaults (the paper gives neither). On the paper's learner's grid eps_Q is fixed otherwise.
PUBLISHED = {
    "paper": ("published beta_a, eps_W", {"beta_a_train": 2.0, "eps_w": 0.05}),
    "linear": ("published beta_a, default eps_Q", {"beta_a_train": 2.0, "eps_q": 0.1}),
    "ppo": ("skrl's defaults", {"learning_rate": 1e-3, "rollouts": 16}),
}


#: The judged runs, the rules' verdicts and the chosen settings: the design's own
#: (:mod:`docking.study.designs.equal_contest`), which its replay reaches.
judged, verdicts, chosen = ec.judged, ec.verdicts, ec.chosen


def spent(results) -> dict[tuple[str, str], dict[str, int]]:
    """``{(world, learner): runs per step}`` (grid, extension, selection, judged)."""
    return {
        (w, learner): ec.SEARCH.spent(results, w, learner)
        for w in ec.WORLDS
        for learner in ec.LEARNERS
    }


def _points(results, world: str, learner: str, stage: str) -> dict[tuple[int, int], np.ndarray]:
    return {
        (c["row"], c["col"]): results.score(c.key)
        for c in results.cells
        if c["world"] == world and c["learner"] == learner and c["stage"].startswith(stage)
    }


def grid_means(results, world: str, learner: str) -> np.ndarray:
    """The common grid's mean held-out success, ``(rows, cols)`` (rungs 0 up)."""
    found = np.full((ec.GRID_ROWS, ec.GRID_COLS), np.nan)
    for (r, c), scores in _points(results, world, learner, "grid").items():
        found[r, c] = float(np.mean(scores))
    return found


def fragility(results) -> dict[tuple[str, str], dict]:
    """Per world and learner, on the common grid (the same points and seeds for every
    learner): ``at_well`` (points at or above :data:`WELL`), ``near_best`` (points within
    :data:`docking.study.designs.equal_contest.MARGIN` of the grid's best), ``points``, the
    grid's ``mean`` and ``best``."""
    found = {}
    for w in ec.WORLDS:
        for learner in ec.LEARNERS:
            means = grid_means(results, w, learner).ravel()
            found[w, learner] = dict(
                at_well=int(np.sum(means >= WELL)),
                near_best=int(np.sum(means >= means.max() - ec.MARGIN)),
                points=len(means),
                mean=float(means.mean()),
                best=float(means.max()),
            )
    return found


def curse(results) -> dict[tuple[str, str], tuple[float, float, float]]:
    """Per world and learner, the chosen setting's mean success on the grid seeds, on the
    selection seeds and on the judged seeds: how much the selection's optimism fades."""
    found = {}
    for w in ec.WORLDS:
        for learner in ec.LEARNERS:
            point = ec.SEARCH.chosen(results, w, learner)
            grid = {**_points(results, w, learner, "grid"), **_points(results, w, learner, "ext")}
            selection = _points(results, w, learner, "selection")
            found[w, learner] = (
                float(np.mean(grid[point])),
                float(np.mean(selection[point])),
                float(np.mean(results.score(f"{w}/{learner}/judged"))),
            )
    return found


def interior(results) -> dict[tuple[str, str], bool]:
    """Per world and learner, whether each chosen value lies strictly inside the values that
    knob took in the search (every lattice neighbour of the chosen point was searched)."""
    return {
        key: all(how == "interior" for how in found.values())
        for key, found in bracketing(results).items()
    }


def bracketing(results) -> dict[tuple[str, str], dict[str, str]]:
    """Per world and learner, how the search brackets each knob's chosen value: ``"interior"``
    (the rungs on both sides of it were searched), ``"at a limit"`` (a rung on one side is not
    a valid configuration, the rules' limits, and the other was searched) or ``"edge"`` (a
    valid rung beside it was never searched: the search stopped short)."""
    found = {}
    for w in ec.WORLDS:
        for learner in ec.LEARNERS:
            e = ec.SEARCH.entrants[learner]
            point = ec.SEARCH.chosen(results, w, learner)
            searched = ec.SEARCH.searched(results, w, learner)
            around = ec.SEARCH.neighbours(point)  # row up, row down, column up, column down
            found[w, learner] = {}
            for field, pair in ((e.row.field, around[:2]), (e.col.field, around[2:])):
                how = [
                    "searched"
                    if p in searched
                    else "limit"
                    if ec.SEARCH.setting(w, learner, p) is None
                    else "edge"
                    for p in pair
                ]
                found[w, learner][field] = (
                    "edge" if "edge" in how else "at a limit" if "limit" in how else "interior"
                )
    return found


def limits_sentence(found: dict) -> str:
    """The chosen values at a limit of their knob (``found``: :func:`bracketing`), a sentence."""
    at = [
        f"{LEARNER_NAMES[learner]}'s {KNOB_WORDS[field]} in the {WORLD_NAMES[w]}"
        for (w, learner), fields in found.items()
        for field, how in fields.items()
        if how == "at a limit"
    ]
    if not at:
        return "No chosen value sits at a limit of its knob: every one is interior."
    return (
        "Chosen at a limit of its knob (the rung beyond is not a valid configuration), so "
        "bracketed by that limit rather than interior: " + "; ".join(at) + "."
    )


#: What sentences call the knobs.
KNOB_WORDS = {
    "beta_a_train": "β_a",
    "eps_w": "ε_W",
    "eps_q": "ε_Q",
    "learning_rate": "learning rate",
    "rollouts": "rollouts per update",
}


def chosen_sentence(picked: dict) -> str:
    """One sentence of the chosen settings (``picked``: :func:`chosen`): per learner, each
    knob's value in each world, in :data:`WORLDS` order joined by ``/``; a knob the rules fix
    per world (the paper's learner's eps_Q) is marked fixed."""
    worlds = "/".join(WORLD_NAMES[w].removesuffix(" world") for w in ec.WORLDS)
    parts = []
    for learner in ec.LEARNERS:
        fixed = set().union(*(ec.SEARCH.entrants[learner].fixed.get(w, {}) for w in ec.WORLDS))
        knobs = []
        for k in picked[ec.WORLDS[0], learner]:
            values = "/".join(f"{picked[w, learner][k]:g}" for w in ec.WORLDS)
            knobs.append(f"{KNOB_WORDS[k]} {values}" + (" (fixed)" if k in fixed else ""))
        parts.append(f"{LEARNER_NAMES[learner]} {', '.join(knobs)}")
    return f"Chosen ({worlds}): " + "; ".join(parts) + "."


def _pct(x: float) -> str:
    return f"{100 * x:.1f}%"


def _pp(x: float) -> str:
    return f"{100 * x:.1f}"


def verdict_table(results) -> str:
    """The Markdown table of the verdicts per world: each learner's mean held-out success, the
    lead of linear SARSA over the paper's learner with its 95% interval, the three tests (Holm
    over the worlds) and the failure ratio."""
    from docking.study.report import md_table

    found, v = judged(results), verdicts(results)
    rows = []
    for w in ec.WORLDS:
        x = v[w]
        rows.append(
            (
                WORLD_NAMES[w],
                _pct(found[w]["paper"].mean()),
                _pct(found[w]["linear"].mean()),
                _pct(found[w]["ppo"].mean()),
                f"{_pp(x['lead'])} pp [{_pp(x['low'])}, {_pp(x['high'])}]",
                f"{x['lead_verdict']} (p {x['p_lead']:.2g})",
                f"{x['noninferiority']} (p {x['p_noninferior']:.2g})",
                f"{x['equivalence']} (p {x['p_tost']:.2g})",
                f"{x['failure_ratio']:.2f}",
            )
        )
    header = (
        "world",
        "the paper's learner",
        "linear SARSA",
        "PPO",
        "linear SARSA's lead (95% interval)",
        "a lead",
        f"paper's learner non-inferior at {ec.MARGIN * 100:g} pp",
        f"equivalent within ±{ec.MARGIN * 100:g} pp (TOST)",
        "failure ratio (paper / linear)",
    )
    return md_table(header, rows)


def chosen_table(results) -> str:
    """Per world and learner: the chosen setting, the runs spent per step, and its mean success
    on the grid, selection and judged seeds (the winner's curse shows as a fall)."""
    from docking.study.report import md_table

    picked, runs, fade = chosen(results), spent(results), curse(results)
    rows = []
    for (w, learner), setting in picked.items():
        s = runs[w, learner]
        rows.append(
            (
                WORLD_NAMES[w],
                LEARNER_NAMES[learner],
                ", ".join(f"{k} {v:g}" for k, v in setting.items()),
                f"{s['grid']} + {s['extension']} + {s['selection']} = "
                f"{s['grid'] + s['extension'] + s['selection']}",
                " → ".join(_pct(x) for x in fade[w, learner]),
            )
        )
    header = (
        "world",
        "learner",
        "chosen setting",
        "selection runs: grid + extension + selection",
        "its success: grid seeds → selection seeds → judged seeds",
    )
    return md_table(header, rows)


def fragility_sentence(found: dict) -> str:
    """The sentence under the fragility figure (``found``: :func:`fragility`)."""
    parts = []
    for w in ec.WORLDS:
        counts = ", ".join(
            f"{LEARNER_NAMES[learner]} {found[w, learner]['at_well']}" for learner in ec.LEARNERS
        )
        parts.append(f"{WORLD_NAMES[w]}: {counts}")
    n = found[ec.WORLDS[0], ec.LEARNERS[0]]["points"]
    return (
        f"Of the {n} points of each learner's common grid (the same two seeds at every point), "
        f"those at or above {100 * WELL:.0f}% held-out success: " + "; ".join(parts) + "."
    )


def fragility_table(found: dict) -> str:
    """Per world and learner: the fragility counts (:func:`fragility`)."""
    from docking.study.report import md_table

    rows = [
        (
            WORLD_NAMES[w],
            LEARNER_NAMES[learner],
            f"{f['at_well']} of {f['points']}",
            f"{f['near_best']} of {f['points']}",
            _pct(f["best"]),
            _pct(f["mean"]),
        )
        for (w, learner), f in found.items()
    ]
    header = (
        "world",
        "learner",
        f"points at or above {100 * WELL:.0f}%",
        f"points within {100 * ec.MARGIN:.0f} pp of the grid's best",
        "the grid's best",
        "the grid's mean",
    )
    return md_table(header, rows)


def grid_panels(results) -> tuple[list[dict], dict]:
    """The fragility figure's panels (:func:`docking.study.figures.fig_landscape`): per world
    (rows of panels) and learner (columns), every point searched on the grid seeds (the common
    grid and the extension's points around it) by its mean held-out success; marks at the
    chosen setting (star) and the published or default one (circle)."""
    from docking.study.arrays import landscape

    panels, marks = [], {}
    picked = chosen(results)
    for w in ec.WORLDS:
        for learner in ec.LEARNERS:
            e = ec.SEARCH.entrants[learner]
            points = {**_points(results, w, learner, "grid"), **_points(results, w, learner, "ext")}
            rows = range(min(r for r, _ in points), max(r for r, _ in points) + 1)
            cols = range(min(c for _, c in points), max(c for _, c in points) + 1)
            row_values = [e.row.ladder.value(r) for r in rows]
            col_values = [e.col.ladder.value(c) for c in cols]
            scores = {
                (e.row.ladder.value(r), e.col.ladder.value(c)): list(s)
                for (r, c), s in points.items()
            }
            fixed = e.fixed.get(w, {})
            title = f"{WORLD_NAMES[w]}: {LEARNER_NAMES[learner]}" + (
                f" (eps_Q {fixed['eps_q']:g})" if "eps_q" in fixed else ""
            )
            panels.append(
                dict(
                    world=w,
                    learner=learner,
                    title=title,
                    row_label=_AXIS[e.row.field],
                    col_label=_AXIS[e.col.field],
                    grid=landscape(scores, row_values, col_values),
                )
            )
            label, published = PUBLISHED[learner]
            marks[w, learner] = [
                ("chosen", (picked[w, learner][e.row.field], picked[w, learner][e.col.field])),
                (label, (published[e.row.field], published[e.col.field])),
            ]
    return panels, marks


_AXIS = {
    "beta_a_train": "beta_a in training (Eq. 4)",
    "eps_w": "eps_W (Eq. 8)",
    "eps_q": "eps_Q (Eq. 7)",
    "learning_rate": "learning rate",
    "rollouts": "rollouts per update",
}


#: The glance figure's learners, in the legend's order.
GLANCE_LEARNERS = (
    "the paper's learner, published settings",
    "the paper's learner, chosen",
    "linear SARSA, chosen",
    "PPO, chosen",
)
GLANCE_YARDSTICKS = (
    ("oracle", "pose oracle"),
    ("centroid", "centroid rule"),
    ("random", "random actions"),
)
#: The caption under the glance figure (the README and the site), its counts from the rules.
GLANCE_CAPTION = (
    f"**The answer per world:** each dot one network's success on {ec.HELDOUT_TRIALS} held-out "
    "start poses, the mean with its 95% interval. Chosen: each learner's setting selected by the "
    f"equal contest (the same {ec.SEARCH.runs_per_learner()} selection runs per learner and "
    f"world), judged on {len(ec.SEEDS)} fresh seeds. Blue: the paper's learner at its published "
    f"settings (the third edition's runs, seeds {te.SEEDS[0]}-{te.SEEDS[-1]}). Lines: the "
    "pose oracle (reads the true pose), the centroid rule, random actions."
)


def glance_data(results, contest) -> tuple[list, list, dict, dict]:
    """The glance figure's arrays (:func:`docking.study.figures.fig_glance`): per world, each
    learner's per-seed held-out success (the chosen learners from ``results``, the equal
    contest's; the published settings and the yardsticks from ``contest``, the third
    edition's contest part) and the yardsticks' means."""
    seeds, yardsticks = {}, {}
    names = {w: WORLD_NAMES[w] for w in ec.WORLDS}
    for w, name in names.items():
        seeds[name, GLANCE_LEARNERS[0]] = contest.score(f"{w}/paper")
        for label, learner in zip(GLANCE_LEARNERS[1:], ec.LEARNERS, strict=True):
            seeds[name, label] = results.score(f"{w}/{learner}/judged")
        for variant, label in GLANCE_YARDSTICKS:
            yardsticks[name, label] = float(np.mean(contest.score(f"{w}/{variant}")))
    return list(names.values()), list(GLANCE_LEARNERS), seeds, yardsticks
