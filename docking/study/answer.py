"""The answer as the evidence allows it (issue 50): the README's first screen and the
replication's sentences, computed from the runs.

The first screen says, in at most :data:`MAX_SENTENCES` sentences of at most
:data:`MAX_WORDS` words (:func:`words`, :func:`sentences` count them):

* the paper's learner at its published settings beside the sideboard world's reproduction;
* what tuning changed (beta_a, eps_W) and each learner's tuning effort, and what it reached;
* the main finding, worded by the replication's rule
  (:func:`docking.study.designs.replication.wording`);
* relocation as measured: how far the view moved in input rows, the success there;
* the paper's claims' verdict counts under the committed rule and as one family.

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
    "effort",
    "first_screen",
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
    replication's (per-seed success of each learner, the gap intervals, the verdicts and the
    words they allow, :func:`docking.study.designs.replication.wording`)."""

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
    words: tuple[str, str]


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
            rp.wording(first_verdict, verdict, first_lead, leads[w][0]),
        )
    return found


def _pp(interval: tuple[float, float, float]) -> str:
    mean, low, high = (100 * x for x in interval)
    return f"{mean:.1f} pp [{low:.1f}, {high:.1f}]"


def _pct(x: float) -> str:
    return f"{100 * x:.1f}%"


def replication_text(found: dict[str, Replication]) -> str:
    """The replication's paragraph of the README: per world, both judgements and what may be
    said."""
    from docking.study.designs import replication as rp

    parts = []
    for w, r in found.items():
        gap_words, lead_words = r.words
        parts.append(
            f"in the {WORLDS[w]}, first (seeds 7000-7009) linear SARSA's lead was "
            f"{_pp(r.first_gap)}, **{r.first_verdict}**; replicated on {len(r.paper)} fresh "
            f"seeds ({min(rp.SEEDS)}-{max(rp.SEEDS)}) the paper's learner docks "
            f"{_pct(r.paper.mean())}, linear SARSA {_pct(r.linear.mean())}, PPO at matched "
            f"steps {_pct(r.ppo.mean())}, a lead of {_pp(r.gap)}, **{r.verdict}**; the gap: "
            f"{gap_words}; a lead (Holm over the two worlds, p {r.lead_p:.2g}): {lead_words}"
        )
    return (
        "**The main finding, replicated** (notebook 07: both tuned SARSA learners and PPO on "
        "fresh seeds, the same gap rule, rules committed before the runs): "
        + "; ".join(parts)
        + "."
    )


def first_screen(
    published: dict[str, float],
    sideboard: tuple[float, float],
    tuned: dict[str, dict],
    efforts: dict[tuple[str, str], tuple[int, int]],
    found: dict[str, Replication],
    relocation: dict,
    claims: tuple[int, int, int, int, int],
) -> str:
    """The first screen's sentences (numbered lines).

    Args:
      published: ``{world: the paper's learner's held-out success at its published settings}``.
      sideboard: Experiments 1 and 2's test success in the sideboard world.
      tuned: ``{world: the paper's learner's tuned setting}`` (``beta_a_train``, ``eps_w``).
      efforts: :func:`effort`.
      found: :func:`replication`.
      relocation: ``{"shift": mean |view shift| in input rows, "cm": the landmark's move,
        "home", "higher", "lower": held-out success}``.
      claims: ``(judged, held, contradicted, held as one family, contradicted as one family)``.
    """
    g = GLOSSARY
    floor, nao = found["floor"], found["nao"]
    beta = " and ".join(f"{tuned[w]['beta_a_train']:g}" for w in WORLDS)
    widened = {tuned[w]["eps_w"] / 0.05 for w in WORLDS}
    eps = f"{widened.pop():g}-fold" if len(widened) == 1 else "up"
    runs = " and ".join(str(efforts[w, "paper"][0]) for w in WORLDS)
    linear_runs = " and ".join(str(efforts[w, "linear"][0]) for w in WORLDS)
    lines = [
        f"At its [published settings]({g}#published-settings) the paper's learner docks "
        f"{_pct(published['floor'])} in the floor world and {_pct(published['nao'])} in the "
        f"Nao-like world (our calibrated sideboard world: {_pct(sideboard[1])}; paper: 95%).",
        f"Tuning raised [β_a]({g}#beta_a) from 2 to {beta} and [ε_W]({g}#eps_w) {eps}, over "
        f"{runs} [runs]({g}#tuning-effort) (linear SARSA: {linear_runs}), lifting it to "
        f"{_pct(floor.paper.mean())} and {_pct(nao.paper.mean())}.",
        _finding(floor, nao),
        f"Shifting the view {relocation['shift']:.1f} of an [input row]({g}#input-row) "
        f"(landmark {relocation['cm']:.0f} cm higher or lower) moves success from "
        f"{_pct(relocation['home'])} to {_pct(relocation['higher'])} or "
        f"{_pct(relocation['lower'])}; along the floor nothing changes, by construction.",
        f"Of the paper's {claims[0]} claims judged on fresh seeds, {claims[1]} hold in some "
        f"world and {claims[2]} are contradicted somewhere (as one family: {claims[3]} and "
        f"{claims[4]}).",
    ]
    return "\n".join(f"{k + 1}. {line}" for k, line in enumerate(lines))


#: How the first screen names a learner's lead.
_WHOSE = {"paper ahead": "the paper's", "linear ahead": "linear's"}
_SHORT = {"floor": "floor", "nao": "Nao-like"}


def _finding(floor: Replication, nao: Replication) -> str:
    """The main finding's sentence, as the replication's wording allows it: *within 5 pp*
    only in the worlds where both judgements closed the gap; a lead *replicated* only where
    both judgements saw the same learner ahead, and named as not replicated where one did."""
    g = GLOSSARY
    both = [r for r in (floor, nao) if r.verdict == r.first_verdict == "closed"]
    gaps = f"{100 * floor.gap[0]:.1f}, {100 * nao.gap[0]:.1f} pp"
    n = len(floor.paper)
    if len(both) == 2:
        head = (
            f"Replicated on {n} fresh seeds per world, it stays within 5 pp of linear SARSA "
            f"([gap]({g}#gap) {gaps})"
        )
    elif both:
        head = (
            f"Within 5 pp of linear SARSA replicated in the {WORLDS[both[0].world]} only "
            f"({n} fresh seeds; [gap]({g}#gap) {gaps})"
        )
    else:
        head = (
            f"Within 5 pp of linear SARSA did not replicate ({n} fresh seeds per world; "
            f"[gap]({g}#gap) {gaps})"
        )
    clauses = []
    for r in (floor, nao):
        if r.first_lead == r.lead == "no lead shown":
            continue
        if r.first_lead == r.lead:
            clauses.append(f"{_WHOSE[r.lead]} {_SHORT[r.world]} lead replicated")
        else:
            seen = r.first_lead if r.first_lead != "no lead shown" else r.lead
            clauses.append(f"{_WHOSE[seen]} {_SHORT[r.world]} lead did not")
    if not clauses:
        return head + "; neither learner leads."
    return head + "; " + ", ".join(clauses) + "."


#: The first screen's figure: its learners, in the legend's order.
GLANCE_LEARNERS = (
    "the paper's learner, published settings",
    "the paper's learner, tuned",
    "linear SARSA, tuned",
    "PPO (matched steps; sideboard: tuned)",
)
#: The yardsticks of the figure: ``(variant in the contest, label)``.
GLANCE_YARDSTICKS = (
    ("oracle", "pose oracle"),
    ("centroid", "centroid rule"),
    ("random", "random actions"),
)
#: Each column of the figure: its label, with the tuning its learners had.
GLANCE_WORLDS = {
    "sideboard": "sideboard world\n(calibrated; contest tuning)",
    "floor": "floor world\n(bracketed tuning)",
    "nao": "Nao-like world\n(bracketed tuning)",
}


def glance_data(contest, replicated) -> tuple[list, list, dict, dict]:
    """The first screen's figure's arrays (:func:`docking.study.figures.fig_glance`): per
    world, each learner's per-seed held-out success and the yardsticks' means. The paper's
    learner at its published settings is the contest's untuned one in every world; the tuned
    learners are the replication's (``replicated``: its results) in the floor and Nao-like
    worlds (PPO at the paper learner's training steps) and the contest's in the sideboard world
    (PPO tuned by the contest)."""
    seeds, yardsticks = {}, {}
    for world, name in GLANCE_WORLDS.items():
        seeds[name, GLANCE_LEARNERS[0]] = contest.score(f"{world}/paper")
        if world == "sideboard":
            keys = (f"{world}/paper-tuned", f"{world}/linear-tuned", f"{world}/ppo-tuned")
            source = contest
        else:
            keys = (f"{world}/paper", f"{world}/linear", f"{world}/ppo")
            source = replicated
        for label, key in zip(GLANCE_LEARNERS[1:], keys, strict=True):
            seeds[name, label] = source.score(key)
        for variant, label in GLANCE_YARDSTICKS:
            yardsticks[name, label] = float(np.mean(contest.score(f"{world}/{variant}")))
    return list(GLANCE_WORLDS.values()), list(GLANCE_LEARNERS), seeds, yardsticks


#: The caption under the first screen's figure (the README and the site).
GLANCE_CAPTION = (
    "**The answer per world:** each dot one network's success on 500 held-out start poses, "
    "the mean with its 95% interval. Blue circles: the paper's learner at its published "
    "settings. In the sideboard world every learner had the contest's tuning (15 runs each) "
    "and PPO was tuned; in the floor and Nao-like worlds the SARSA learners were tuned to "
    "bracketed optima and judged on the replication's 20 fresh seeds, and PPO trained for as "
    "many steps as the tuned paper learner (matched steps). Lines: the pose oracle (it reads "
    "the true pose), the centroid rule (steps towards the landmark's centre in the image), "
    "random actions."
)
