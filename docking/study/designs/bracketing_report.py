"""The report of the addendum's bracketing and its continuation
(:mod:`docking.study.designs.bracketing`, :mod:`docking.study.designs.bracketing_continued`,
notebook 10): the walk's rows and table, its sentence, and the addendum's results with the
bracketed learners in place.
"""

from __future__ import annotations

import dataclasses

from docking.study.designs.addendum_report import _knob_lines
from docking.study.designs.third_edition_report import CONTEST_NAMES, CONTEST_WORLDS
from docking.study.report import _pct, contest_gaps, md_table


def bracketing_rows(own, br) -> list[dict]:
    """Per world and learner of the bracketing (``own``: the results of ``br``,
    :mod:`docking.study.designs.bracketing`): the addendum's tuned setting it started from, the
    tuned setting it ended on, the runs it used, whether it is bracketed, each knob's value
    with the compared values on its line through the tuned setting (the other knobs at their
    tuned values; complete settings only) and where it lies, and the tuned setting's mean
    over the compared seeds."""
    ad = br.ad
    rows = []
    for world in ad.WORLDS:
        for learner in ad.LEARNERS:
            found = br.scores(own, world, learner)
            means = br.WALK.complete(found)
            tuned = br.tuned(own, world, learner)
            positions = {}
            for knob, value in tuned.items():
                line = sorted(
                    dict(s)[knob]
                    for s in means
                    if all(dict(s)[k] == v for k, v in tuned.items() if k != knob)
                )
                ladder = ad.LADDERS[knob]
                if line[0] < value < line[-1]:
                    where = "interior"
                elif value in (ladder[0], ladder[-1]) and value in (line[0], line[-1]):
                    where = f"at its limit: {ad.LIMITS[knob][value == ladder[-1]]}"
                else:
                    where = "at the edge: the search stopped"
                positions[knob] = (tuple(line), where)
            rows.append(
                dict(
                    world=world,
                    learner=learner,
                    start=ad.TUNING.tuned(br.addendum(), world, learner),
                    tuned=tuned,
                    changed=br.changed(own, world, learner),
                    runs=br.WALK.runs_used(own, world, learner),
                    bracketed=br.WALK.bracketed(own, world, learner),
                    positions=positions,
                    mean=means[tuple(tuned.items())],
                    n=len(br.COMPARE_SEEDS),
                    design=br.NAME,
                )
            )
    return rows


def bracketing_table(rows: list[dict]) -> str:
    """The Markdown table of :func:`bracketing_rows`."""
    found = []
    for r in rows:
        knobs = _knob_lines(r)
        found.append(
            (
                CONTEST_WORLDS.get(r["world"], r["world"]),
                r["learner"],
                ", ".join(f"{k} = {v:g}" for k, v in r["start"].items()),
                "<br>".join(knobs),
                "changed" if r["changed"] else "the same",
                str(r["runs"]),
                f"{100 * r['mean']:.1f}% (n = {r['n']})",
            )
        )
    header = ("world", "learner", "the addendum's tuned setting", "tuned value: tried on its line")
    return md_table((*header, "tuned setting", "runs", "its tuning success"), found)


def bracketing_summary(rows: list[dict], final, ad) -> str:
    """The README's sentences on the bracketing (``rows``: :func:`bracketing_rows`;
    ``final``: :func:`bracketed_addendum`'s results; ``ad``: the addendum's module): per
    world, where each learner's tuned setting moved and whether it is bracketed, then the
    tuned learners' held-out success on the judged seeds and the gap by the addendum's
    rule."""
    from docking.study.claims import rate_interval

    def setting(values: dict) -> str:
        return ", ".join(f"{k} {v:g}" for k, v in values.items())

    gaps = {g.world: g for g in contest_gaps(final, ad.WORLDS, ad.GAP_CLOSED)}
    parts = []
    for world in ad.WORLDS:
        moves = []
        for r in (r for r in rows if r["world"] == world):
            name = "the paper's learner" if r["learner"] == "paper" else "linear SARSA"
            where = "bracketed" if r["bracketed"] else "not bracketed: the search stopped"
            if r["changed"]:
                moves.append(
                    f"{name} moved from {setting(r['start'])} to {setting(r['tuned'])} ({where})"
                )
            else:
                moves.append(f"{name} stayed at {setting(r['tuned'])} ({where})")
        paper = rate_interval(final, f"{world}/paper-tuned").estimate
        linear = rate_interval(final, f"{world}/linear-tuned").estimate
        parts.append(
            f"in {CONTEST_NAMES[world]} {'; '.join(moves)}; judged, the paper's learner docks "
            f"{_pct(paper)}, linear SARSA {_pct(linear)}, a gap of "
            f"{gaps[world].interval.format(unit=' pp')}, **{gaps[world].words}**"
        )
    return BRACKETING_LEADS[rows[0]["design"]] + "; ".join(parts) + "."


#: The first words of :func:`bracketing_summary` per design of the bracketing's walk.
BRACKETING_LEADS = {
    "addendum-bracketing": (
        "**Bracketed** (the addendum's search continued by a second rule committed before its "
        "runs, notebook 10: every neighbour of the best setting run on the same 10 tuning seeds, "
        "stage after stage, until none did better; the same rule for both learners): "
    ),
    "addendum-bracketing-continued": (
        "**Bracketed, judged on fresh seeds** (the addendum's search continued by the "
        "bracketing's rule, every neighbour of the best setting run on the same 10 tuning "
        "seeds until none did better, the same for both learners, with a further budget under "
        "a third rule committed before its runs, notebook 10; both tuned learners then judged "
        "on seeds no earlier run used): "
    ),
}


def bracketed_addendum(added, own, br):
    """The addendum's results (``added``) with each tuned learner the bracketing (``own``:
    the results of ``br``, :mod:`docking.study.designs.bracketing`) changed in its place: the cell
    ``{world}/{learner}-tuned`` holds the bracketed setting's judged runs, and
    ``{world}/ppo-matched`` PPO's re-matched runs where the bracketing trained PPO again;
    every other cell as the addendum ran it. What notebook 10 reports as the
    tuned learners once the bracketing is in."""

    from docking.study.design import Results

    swap = {}
    for c in own.cells:
        variant = c.coords.get("variant", "")
        if variant.endswith("-bracketed"):
            swap[f"{c['world']}/{variant.removesuffix('-bracketed')}-tuned"] = c.key
        elif variant == "ppo-matched":
            swap[c.key] = c.key
    cells, runs, logs = [], dict(added.runs), dict(added.logs)
    for c in added.cells:
        if c.key in swap:
            mine = own.cell(swap[c.key])
            cells.append(dataclasses.replace(mine, key=c.key, coords=dict(c.coords)))
            runs[c.key], logs[c.key] = own.runs[mine.key], own.logs[mine.key]
        else:
            cells.append(c)
    return Results(added.design, cells, runs, logs)
