"""The answer as the evidence allows it: the README's first screen and its paragraphs,
computed from the runs (the equal contest's, issue 59), and the replication's sentences
(the history notebook 10 keeps).

The first screen (:func:`equal_first_screen`) says, in at most :data:`MAX_SENTENCES` sentences
of at most :data:`MAX_WORDS` words (:func:`words`, :func:`sentences` count them), with at most
three terms that need the glossary:

* the paper's learner at its published settings in the three worlds (held-out success);
* what the equal search chose (β_a, ε_W, and ε_Q held at its earlier tuning), and its effort;
* the verdict, named as the tests it is (the lead, non-inferiority at 5 pp, equivalence
  within ±5 pp);
* relocation as measured: a camera-height change, its world, its seeds, the landmark's shift
  with its sign, the success there;
* the paper's claims that hold and those contradicted, named.

Every number comes from arrays passed in (loaded by the report from the store or the
ledger); the README's text gives each number the first screen gives (tests hold both).
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np

__all__ = [
    "MAX_SENTENCES",
    "MAX_WORDS",
    "Replication",
    "claims_text",
    "effort",
    "equal_first_screen",
    "equal_text",
    "recompute_text",
    "relocation_text",
    "replication",
    "replication_text",
    "sentences",
    "words",
]

#: The first screen's limits (issue 50).
MAX_SENTENCES = 5
MAX_WORDS = 30
#: The tables of the bracketed tuning (the addendum, the bracketing and its continuation).
TUNING_TABLES = ("third-edition-addendum", "addendum-bracketing", "addendum-bracketing-continued")
#: The worlds of the main finding and what the text calls them.
WORLDS = {"floor": "floor world", "nao": "Nao-like world"}
#: The glossary's page, for the first screen's links.
GLOSSARY = "docs/guide/glossary.md"


def words(sentence: str) -> int:
    """The words of ``sentence`` as a reader counts them: Markdown links count their text,
    emphasis marks nothing, a number or symbol with its unit one word."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", sentence)
    text = re.sub(r"[*_`]", "", text)
    return len(text.split())


def sentences(text: str) -> list[str]:
    """The sentences of a first screen ``text`` (one per numbered line)."""
    return [re.sub(r"^\d+\.\s*", "", line).strip() for line in text.splitlines() if line.strip()]


def effort(data: dict) -> dict[tuple[str, str], tuple[int, int]]:
    """Per world and SARSA learner, ``(runs, settings)``: the training runs the bracketed
    tuning spent on tuning seeds (:data:`docking.study.designs.addendum.TUNING_SEEDS`) in the
    tables :data:`TUNING_TABLES` of the ledger's manifest ``data``, and the settings they
    covered."""
    from docking.study.designs import addendum as ad

    found: dict[tuple[str, str], list] = {}
    seeds = set(ad.TUNING_SEEDS)
    for record in data["runs"].values():
        if record["name"] not in TUNING_TABLES or record["seed"] not in seeds:
            continue
        if record["runner"] != "learner":
            continue
        config = record["config"]
        net, world = config["network"], config["world"]
        if config.get("pretrain_trials") or config.get("policy") != "network":
            continue
        which = "nao" if world.get("camera_height") else "floor"
        learner = "linear" if net.get("feature_layer") == "none" else "paper"
        runs, settings = found.setdefault((which, learner), [0, set()])
        found[which, learner][0] = runs + 1
        settings.add((net["eps_q"], net["beta_a_train"], net["eps_w"]))
    return {k: (runs, len(settings)) for k, (runs, settings) in sorted(found.items())}


@dataclasses.dataclass(frozen=True)
class Replication:
    """One world's main finding, judged twice: the bracketing continued's judgement and the
    replication's (per-seed success of each learner, the gap intervals and the verdicts; the
    words they allow are :func:`docking.study.designs.replication.wording`'s, composed where
    they are said)."""

    world: str
    paper: np.ndarray
    linear: np.ndarray
    ppo: np.ndarray
    gap: tuple[float, float, float]
    verdict: str
    lead: str
    lead_p: float
    first_gap: tuple[float, float, float]
    first_verdict: str
    first_lead: str


def replication(first, second) -> dict[str, Replication]:
    """Per world: the bracketing continued's results ``first`` and the replication's
    ``second`` (:class:`docking.design.Results`), judged by the replication's rules."""
    from docking.study.designs import replication as rp

    leads = rp.lead_verdicts(
        {w: (second.score(f"{w}/linear"), second.score(f"{w}/paper")) for w in rp.WORLDS}
    )
    found = {}
    for w in rp.WORLDS:
        paper, linear = second.score(f"{w}/paper"), second.score(f"{w}/linear")
        before = (first.score(f"{w}/linear-bracketed"), first.score(f"{w}/paper-bracketed"))
        first_gap = rp.gap_interval(*before)
        first_verdict, verdict = rp.gap_verdict(*before), rp.gap_verdict(linear, paper)
        first_lead = rp.first_lead(first_gap[1], first_gap[2])
        found[w] = Replication(
            w,
            paper,
            linear,
            second.score(f"{w}/ppo"),
            rp.gap_interval(linear, paper),
            verdict,
            leads[w][0],
            leads[w][1],
            first_gap,
            first_verdict,
            first_lead,
        )
    return found


def _pp(interval: tuple[float, float, float]) -> str:
    mean, low, high = (100 * x for x in interval)
    return f"{mean:.1f} pp [{low:.1f}, {high:.1f}]"


def _pct(x: float) -> str:
    return f"{100 * x:.1f}%"


def replication_text(found: dict[str, Replication], glossary: str | None = GLOSSARY) -> str:
    """The replication's paragraph (notebook 10, the study's history): what it ran, a table of both
    judgements per world (the bracketing continued's first, then the replication's) and what
    it allowed to be said (:func:`docking.study.designs.replication.wording`), its gap rule's
    verdicts named as the test it is (:func:`docking.study.report.gap_words`); ``glossary``:
    the glossary's path its terms link to (None: no links, as in a notebook's output)."""
    from docking.study.designs import replication as rp
    from docking.study.report import gap_words

    gap = f"[gap]({glossary}#gap)" if glossary else "gap"
    n = len(next(iter(found.values())).paper)
    rows = [
        "| world | first judgement: linear SARSA's lead | the paper's learner | linear SARSA | "
        "PPO, matched steps | linear SARSA's lead | a lead (Holm p) | what it allowed |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for w, r in found.items():
        first, now = (gap_words(v, rp.GAP_CLOSED) for v in (r.first_verdict, r.verdict))
        # What the rule allows said, of the verdicts named as the test they are.
        said_gap, said_lead = rp.wording(first, now, r.first_lead, r.lead)
        rows.append(
            f"| {WORLDS[w]} | {_pp(r.first_gap)}, {first}; {r.first_lead} | "
            f"{_pct(r.paper.mean())} | {_pct(r.linear.mean())} | {_pct(r.ppo.mean())} | "
            f"{_pp(r.gap)}, **{now}** | {r.lead} (p {r.lead_p:.2g}) | "
            f"{said_gap}; {said_lead} |"
        )
    return (
        f"**The replication** (*superseded* by the equal contest). The tuned learners of the "
        f"bracketing were judged first on seeds 7000-7009, then again, by rules committed "
        f"before the runs and the same {gap} rule (a one-sided non-inferiority test of the "
        f"paper's learner at 5 pp), on {n} fresh seeds per world "
        f"({min(rp.SEEDS)}-{max(rp.SEEDS)}), with PPO trained for as many steps as the paper's "
        "learner (held-out success, mean over seeds; leads with 95% intervals over matched "
        "seeds):\n\n" + "\n".join(rows)
    )


def relocation_text(relocation: dict) -> str:
    """The README's paragraph on relocation as measured (``relocation``: as
    :func:`equal_first_screen` takes it, with ``"linear home"``, ``"linear camera lower"``,
    ``"linear camera higher"``: linear SARSA's held-out success): a camera-height change, its
    world, its seeds and the landmark's shift in the input with its sign."""
    r, g = relocation, GLOSSARY
    return (
        f"**[Relocation](docs/guide/glossary.md#relocation), as measured** (notebook 09). The "
        f"test is a camera-height change in the {r['world']} world ({r['seeds']} seeds): the "
        f"robot's camera {r['cm']:.0f} cm lower, so the landmark appears "
        f"{abs(r['shift lower']):.2f} of an [input row]({g}#input-row) higher in the input, or "
        f"{r['cm']:.0f} cm higher, so it appears {abs(r['shift higher']):.2f} of a row lower. "
        "The home networks "
        f"dock {_pct(r['camera lower'])} with the camera lower and {_pct(r['camera higher'])} "
        f"with it higher, against {_pct(r['home'])} at home; linear SARSA's go from "
        f"{_pct(r['linear home'])} to {_pct(r['linear camera lower'])} and "
        f"{_pct(r['linear camera higher'])}. The rule committed before the runs (within ±5 pp "
        f"of home) calls the first {r['verdict camera lower']} and the second "
        f"{r['verdict camera higher']} (docking more often than at home lies outside the margin "
        "too). Moved along the floor, the robot sees the same view at every start, so success "
        "there is unchanged by construction, not by learning."
    )


def claims_text(claims: tuple[int, int, int, int, int]) -> str:
    """The README's sentence on the paper's claims (``claims``: as :func:`first_screen`)."""
    return (
        f"**The paper's claims** (notebook 07). Of the paper's {claims[0]} claims judged on "
        f"fresh seeds by the rule committed before the runs (Holm within each claim), "
        f"{claims[1]} hold in at least one world and {claims[2]} are contradicted in at least "
        f"one; judged as one family of all comparisons, the stricter rule, {claims[3]} hold and "
        f"{claims[4]} are contradicted."
    )


# ------------------------------------------------------------------------------------------
# The equal contest's answer (issue 59): the first screen and the summary's paragraph.
# ------------------------------------------------------------------------------------------

#: The worlds of the equal contest, as the first screen names them.
EQUAL_WORLDS = {"sideboard": "sideboard", "floor": "floor", "nao": "Nao-like"}

#: What the first screen calls each claim of the paper (its key in the verdict tables).
CLAIM_WORDS = {
    "features-success": "δ-trained features",
    "delta": "δ-gated feature learning",
    "features-interpretable": "interpretable features",
    "curriculum": "the curriculum",
    "rotation-most": "rotation",
    "rotation-compensated": "rotation",
    "turning-accuracy": "turning",
    "turning-path": "turning",
    "distractor-unseen": "distractors",
    "distractor-mechanism": "distractors",
}


def _values(values: list[float]) -> str:
    """``"200/100/50"`` (one value per world), or one value where all agree."""
    distinct = list(dict.fromkeys(f"{v:g}" for v in values))
    return distinct[0] if len(distinct) == 1 else "/".join(f"{v:g}" for v in values)


def _listed(items: list[str]) -> str:
    items = list(dict.fromkeys(items))
    if len(items) <= 1:
        return "".join(items)
    return ", ".join(items[:-1]) + " and " + items[-1]


def equal_first_screen(
    published: dict[str, float],
    chosen: dict[tuple[str, str], dict],
    runs: int,
    verdicts: dict[str, dict],
    relocation: dict,
    groups: dict[str, list[str]],
) -> str:
    """The first screen's five sentences (numbered lines) from the equal contest.

    Args:
      published: ``{world: the paper's learner's held-out success at its published settings}``
        (sideboard, floor, Nao-like).
      chosen: ``{(world, learner): the chosen setting}``
        (:func:`docking.study.designs.equal_contest.chosen`).
      runs: Selection runs per learner and world.
      verdicts: ``{world: the equal contest's verdicts}``
        (:func:`docking.study.designs.equal_contest.verdicts`).
      relocation: ``{"cm", "world", "seeds", "home", "camera lower", "camera higher", "shift
        lower", "shift higher"}``: the camera-height change, its world and seeds, the home
        networks' held-out success at home and with the camera lower or higher, and the mean
        shift of the landmark in input rows with the camera lower (up: negative rows) and
        higher.
      groups: The paper's claims by verdict (``claim_groups`` under the committed rule).
    """
    g = GLOSSARY
    worlds = list(EQUAL_WORLDS)
    paper = [chosen[w, "paper"] for w in worlds]
    net = _published_network()
    lines = [
        f"At its [published settings]({g}#published-settings) the paper's learner docks "
        f"{_pct(published['sideboard'])} of [held-out]({g}#held-out-trials) trials in our "
        f"sideboard world, {_pct(published['floor'])} on the floor and "
        f"{_pct(published['nao'])} in the Nao-like world (paper: 95%).",
        f"Searched alike ({runs} runs per learner and world), it chose exploration β_a "
        f"{_values([p['beta_a_train'] for p in paper])} (published {net.beta_a_train:g}) and "
        f"feature rate ε_W {_values([p['eps_w'] for p in paper])} ({net.eps_w:g}); value rate "
        f"ε_Q fixed by earlier tuning: {_values([p['eps_q'] for p in paper])} "
        f"({net.eps_q:g}).",
        _equal_verdict(verdicts),
        _relocation_sentence(relocation),
        _claims_sentence(groups),
    ]
    return "\n".join(f"{k + 1}. {line}" for k, line in enumerate(lines))


def _published_network():
    """The paper's learner's network at its published settings (the third edition's cell)."""
    from docking.study.designs import third_edition as te

    return te.DESIGN.cell(f"{te.CONTEST[0]}/paper").config.network


def _equal_verdict(verdicts: dict[str, dict]) -> str:
    """The verdict's sentence: linear SARSA's lead per world (its sign says who leads), where
    a lead is shown, where the paper's learner is non-inferior at the rules' margin, where it
    trails by more (the gap remains) and where the two are equivalent within it."""
    from docking.study.designs import equal_contest as ec

    g, margin = GLOSSARY, f"{100 * ec.MARGIN:g} pp"
    n = next(iter(verdicts.values()))["seeds"]
    leads = "/".join(f"{100 * v['lead']:.1f}" for v in verdicts.values())
    order = "/".join(EQUAL_WORLDS[w] for w in verdicts)

    def where(test) -> str:
        found = [EQUAL_WORLDS[w] for w, v in verdicts.items() if test(v)]
        return "everywhere" if len(found) == len(verdicts) else "/".join(found) or "nowhere"

    text = (
        f"On {n} fresh seeds, linear SARSA's lead ({order}): {leads} pp, shown "
        f"{_in(where(lambda v: v['lead_verdict'] != 'no lead shown'))}; "
        f"[non-inferior]({g}#non-inferior) ({margin}) "
        f"{_in(where(lambda v: v['noninferiority'] == 'non-inferior'))}"
    )
    worse = where(lambda v: v["noninferiority"] == "inferior by more than the margin")
    if worse != "nowhere":
        text += f"; trails >{margin} {_in(worse)}"
    equal = where(lambda v: v["equivalence"] == "equivalent")
    return text + f"; equivalent (±{margin}) {_in(equal)}."


def _in(where: str) -> str:
    return where if where in ("everywhere", "nowhere") else f"in {where}"


def _relocation_sentence(r: dict) -> str:
    verb = "cut" if r["camera lower"] < r["home"] else "raised"
    return (
        f"In the {r['world']} world ({r['seeds']} seeds), a camera {r['cm']:.0f} cm lower "
        f"(landmark {abs(r['shift lower']):.2f} input rows up) {verb} success from "
        f"{_pct(r['home'])} to {_pct(r['camera lower'])}; {r['cm']:.0f} cm higher "
        f"({abs(r['shift higher']):.2f} rows down) gave {_pct(r['camera higher'])}."
    )


def _claims_sentence(groups: dict[str, list[str]]) -> str:
    held = [CLAIM_WORDS.get(c, c) for c in groups.get("supported wherever judged", [])]
    some = [CLAIM_WORDS.get(c, c) for c in groups.get("supported in some worlds only", [])]
    against = [CLAIM_WORDS.get(c, c) for c in groups.get("contradicted in at least one world", [])]
    total = sum(len(v) for v in groups.values())
    return (
        f"Of the paper's {total} claims, {_listed(held) or 'none'} hold wherever judged, "
        f"{_listed(some) or 'none'} in some worlds; {_listed(against) or 'none'} "
        "are contradicted."
    )


def equal_text(
    verdict_table: str,
    chosen: str,
    verdicts: dict[str, dict],
    before: dict[str, float],
    published: dict[str, float],
    glossary: str | None = GLOSSARY,
) -> str:
    """The README's paragraph on the equal contest: the paper's learner at its published
    settings (``published``: per world, the third edition's untuned runs), what the contest
    ran (from its rules), its verdicts per world (``verdict_table``), the chosen settings
    (``chosen``: a sentence or a table, with what each learner spent) and how the answer moved
    from the replication's (``before``: ``{world: linear SARSA's lead over the paper's learner
    in the replication}``, floor and Nao-like)."""
    from docking.study.designs import equal_contest as ec
    from docking.study.designs import third_edition as te

    g = glossary
    link = (lambda text, anchor: f"[{text}]({g}#{anchor})") if g else (lambda text, _: text)
    at = ", ".join(f"{_pct(published[w])} in the {EQUAL_WORLDS[w]} world" for w in published)
    moved = "; ".join(
        f"{EQUAL_WORLDS[w]}: {100 * before[w]:+.1f} pp then, "
        f"{100 * verdicts[w]['lead']:+.1f} pp now"
        for w in before
    )
    net = _published_network()
    seeds, margin = ec.SEEDS, f"{100 * ec.MARGIN:g} pp"
    return (
        f"**The paper's learner as published** (notebook 07). At its "
        f"{link('published settings', 'published-settings')} (β_a {net.beta_a_train:g}, ε_W "
        f"{net.eps_w:g}, ε_Q {net.eps_q:g}: the paper's β_a, our defaults where it gives none) "
        f"it docks {at} of held-out trials (the third edition's runs, seeds "
        f"{te.SEEDS[0]}-{te.SEEDS[-1]}; paper: 95%).\n\n"
        f"**The main finding, from an {link('equal contest', 'equal-contest')}** (notebook 07). "
        f"Every learner (the paper's, linear SARSA, PPO) was selected in every world by one "
        f"procedure with the same {ec.SEARCH.runs_per_learner()} "
        f"{link('selection runs', 'selection-runs')} (a common {ec.GRID_ROWS} x {ec.GRID_COLS} "
        f"grid over its two most influential knobs on the same {len(ec.GRID_SEEDS)} seeds, "
        f"{ec.EXTENSION_STAGES} extension stages beyond the grid's edges, the {ec.TOP_K} best "
        f"bracketed points again on {len(ec.SELECTION_SEEDS)} fresh seeds), then judged on "
        f"{len(seeds)} fresh seeds ({min(seeds)}-{max(seeds)}), {ec.HELDOUT_TRIALS} held-out "
        "trials each, by rules committed before the runs. The verdicts of linear SARSA minus "
        f"the paper's learner ({link('lead', 'lead')}, {link('non-inferior', 'non-inferior')} "
        f"at {margin}, {link('equivalent (TOST)', 'equivalent')} within ±{margin}, each "
        "Holm-adjusted over the worlds):\n\n"
        + verdict_table
        + "\n\n"
        + chosen
        + f"\n\nLinear SARSA's lead after the replication's bracketed tuning, and now: {moved}."
    )


#: The headline numbers and the runs behind each: ``(what, design, cells, seeds)`` (seeds None:
#: every seed the design's cells have).
HEADLINE_RUNS = (
    ("Experiments 1 and 2 (the paper's numbers)", "paper", ("experiment1", "experiment2"), None),
    (
        "the paper's learner at its published settings, per world",
        "third-edition",
        ("sideboard/paper", "floor/paper", "nao/paper"),
        None,
    ),
    (
        "each learner's chosen setting, judged (the equal contest)",
        "equal-contest",
        ("*/judged",),
        None,
    ),
    (
        "the equal contest's floor world: the paper's learner, 5 of its 20 judged seeds",
        "equal-contest",
        ("floor/paper/judged",),
        range(7200, 7205),
    ),
    (
        "relocation: the home networks at home and at each camera height",
        "untested-revisited",
        ("home/paper", "sideboard higher/paper", "sideboard lower/paper"),
        None,
    ),
)


def recompute_text(rows=HEADLINE_RUNS) -> str:
    """The findings page's table of the headline numbers and the command that recomputes the
    runs behind each and compares them with the ledger
    (:func:`docking.study.report.verify_command`; its first line says how many runs and about
    how long)."""
    from docking.study.report import md_table, verify_command

    lines = [
        (what, f"`{verify_command(design, cells, seeds)}`") for what, design, cells, seeds in rows
    ]
    return (
        "**Recompute the runs behind a number.** Each command recomputes the runs behind the "
        "number in a temporary store and compares each with the ledger (its content digest and "
        "its table row); it says first how many runs and about how long:\n\n"
        + md_table(("number", "the command"), lines)
    )
