# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#       jupytext_version: 1.19.6
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 10 — The study's history: the editions before the equal contest
#
# **The current finding is the equal contest's (notebook 07)**: every learner selected by one
# procedure with the same number of runs, then judged on 20 fresh seeds. This notebook keeps,
# as they were run and in the order they were run, the analyses it supersedes, each labelled
# where it is superseded, and what each got wrong:
#
# * **The third edition's contest**: every learner tuned by the same 15 runs per world. Its
#   tuning stopped at the edge of its grids, so its finding (a gap of about 36 pp in the floor
#   and Nao-like worlds) **was too strong**.
# * **The addendum, the bracketing and the bracketing continued**: both SARSA learners tuned on
#   the same knobs until each optimum was inside what was searched, then judged on fresh seeds.
# * **The replication**: the bracketed learners judged again on 20 fresh seeds. Its finding
#   (the paper's learner within 5 pp of linear SARSA in both worlds) rested on searches that
#   were not alike (about 200 tuning runs per world for the paper's learner, about 80 for linear
#   SARSA, 15 for PPO); searched alike, it **was too strong in the Nao-like world**.
# * **The fragility landscape of those unequal searches**, and a lead seen once on it (linear
#   SARSA at ε_Q 0.3 in the Nao-like world), which the equal contest's search found again.
#
# The paper's claims, judged by the third edition's rules, are current: notebook 07.

# %%

import numpy as np
from IPython.display import Image, Markdown, display

from docking.study import figures, provenance, report
from docking.study.claims import rate_interval
from docking.study.designs import addendum as ad
from docking.study.designs import addendum_report, bracketing_report, third_edition_report
from docking.study.designs import third_edition as te
from docking.study.report import save_named

pct = lambda ci: ci.format(unit="%")  # noqa: E731
contest = te.DESIGN.run(progress=False)  # every cell of the third edition, read from the ledger

# %% [markdown]
# ## The third edition's contest (*superseded* where it speaks of the gap)
#
# The archived second edition (at 1341e99) found the paper's learner beaten by a one-line
# rule, linear SARSA and PPO in every world but the one tuned towards the paper's numbers. A
# referee contested it: the learner's rates were calibrated in the sideboard world and carried
# unchanged into every other, while PPO ran with library defaults. The third edition's
# **contest**: in each world every learner gets **the same tuning budget** (15 runs), and
# tuned learners are compared with tuned learners, on seeds no earlier run used.
#
# **The rules were committed before any of this edition's runs** (`docking/study/designs/third_edition.py`,
# commit 396630d; its record, `rules/third-edition.json.gz`, is held against the live code by
# `tests/test_records.py`):
#
# * **Worlds:** the sideboard world (the one the package's choices were calibrated in), the
#   floor world (the landmark on the floor, the camera 30° down, a dock 8 cm across), and the
#   **Nao-like world**, fixed from Nao's published specifications before any run
#   (the site's guide "The Nao-like world", `docs/guide/nao_world.md`, gives each value's
#   source).
# * **Tuning, identical for every learner:** a successive halving over a grid of 9 settings
#   (each learner's default first): every setting trained once on tuning seed 3900, the best 3
#   again on seeds 3901 and 3902, the best mean of three the tuned setting: 15 full training
#   runs per learner and world. The selection reads the tuning seeds' own held-out streams,
#   which no judged run uses.
# * **Judged** on 500 held-out trials per network, on fresh seeds 3000-3019 (PPO: 3000-3009
#   tuned, 3000-3004 untuned; yardsticks 3000-3004); intervals are Student-t over seeds.
# * **The finding's rule:** in each world the gap is tuned linear SARSA minus the tuned paper's
#   learner, over matched seeds (each run on its own seed's held-out stream): *closed* if its 95% interval
#   lies below 5 pp, *remains* if it lies above, else undecided (*closed* is a one-sided
#   non-inferiority test of the paper's learner at 5 pp: the glossary's "the gap").
#
# The claims of the paper (the verdicts) are the other part of this edition, under the same
# committed rules; their runs came after the contest's (notebook 07, with the Nao-like world's
# values, its pose oracle and the intervals' coverage).

# %% [markdown]
# ## The tuning, the same for every learner
#
# Per world and learner: the best and the default setting's success in round 1 (one tuning
# seed), the round-2 settings' means over the three tuning seeds, and the setting chosen
# (`#0` is each learner's default).

# %% tags=["fold-output"]
tuning = third_edition_report.tuning_rows(
    contest, te.CONTEST, te.LEARNERS, te.GRIDS, te.TUNING.tuned_setting
)
display(Markdown(third_edition_report.tuning_table(tuning)))
for r in tuning:  # the chosen setting is the best of round 2 by its three-seed mean
    assert r["chosen"] in r["round2"] and r["round2"][r["chosen"]] == max(r["round2"].values())

# %% [markdown]
# ## How hard is each world, tuned against tuned
#
# Held-out success, mean and 95% Student-t interval over seeds (n seeds each), with the
# untuned learners beside the tuned ones and the yardsticks: the pose oracle (the motor
# task's bound), the one-line centroid rule, always-forward and random actions.

# %% tags=["hide-input", "fold-output"]
# the third edition's contest: each learner's held-out success per world (table and figure)
names = third_edition_report.CONTEST_WORLDS  # the worlds' names in tables and figures
display(Markdown(third_edition_report.contest_table(contest, names)))
labels = dict(third_edition_report.CONTEST_COLUMNS)
scores = {
    (w, labels[v]): contest.score(f"{w}/{v}")
    for w in te.CONTEST
    for v, _ in third_edition_report.CONTEST_COLUMNS
    if f"{w}/{v}" in {c.key for c in contest.cells}
}
fig = figures.fig_contest(
    [names[w] for w in te.CONTEST],
    [label for _, label in third_edition_report.CONTEST_COLUMNS],
    {(names[w], label): s for (w, label), s in scores.items()},
)
display(Image(save_named(fig, "third_edition_contest")))

# %% [markdown] tags=["fold"]
# ## The contest's finding: does tuning close the gap? (*superseded*)
#
# *Superseded* by the addendum, the bracketing and the replication (below), then by the equal
# contest (notebook 07): the contest's tuning stopped at the edge of its grids.

# %% tags=["fold-output"]
# the third edition's gaps: linear SARSA and PPO minus the tuned paper's learner
gaps = report.contest_gaps(contest, te.CONTEST, te.GAP_CLOSED)
ppo_gaps = report.contest_gaps(contest, te.CONTEST, te.GAP_CLOSED, other="ppo-tuned")
display(Markdown(report.gaps_table(gaps + ppo_gaps)))

# %% [markdown] tags=["fold"]
# ## What the contest shows (*superseded* where it speaks of the gap)
#
# Each sentence below is computed from the runs; the asserts hold what the sentences say.

# %% tags=["hide-input", "fold-output"]
by_world = {g.world: g for g in gaps}
by_ppo = {g.world: g for g in ppo_gaps}
mean = lambda key: 100 * float(np.mean(contest.score(key)))  # noqa: E731
lines = []
for w in te.CONTEST:
    chosen = {r["learner"]: r["setting"] for r in tuning if r["world"] == w}
    lines.append(
        f"* **{names[w]}:** the paper's learner docks {mean(f'{w}/paper'):.1f}% untuned and "
        f"{mean(f'{w}/paper-tuned'):.1f}% tuned ({', '.join(f'{k} = {v:g}' for k, v in chosen['paper'].items())}); "
        f"linear SARSA {mean(f'{w}/linear'):.1f}% and {mean(f'{w}/linear-tuned'):.1f}%; PPO "
        f"{mean(f'{w}/ppo'):.1f}% and {mean(f'{w}/ppo-tuned'):.1f}%; the pose oracle "
        f"{mean(f'{w}/oracle'):.1f}%, the centroid rule {mean(f'{w}/centroid'):.1f}%. Tuned linear "
        f"SARSA minus the tuned paper's learner: {by_world[w].interval.format(unit=' pp')}, the gap "
        f"rule: **{by_world[w].words}**; tuned PPO minus it: {by_ppo[w].interval.format(unit=' pp')}."
    )
display(Markdown("\n".join(lines)))

# %% [markdown]
# **The contest's finding (*superseded*: too strong; the current finding is notebook 07's).**
# Given the same tuning as the others, the paper's learner improves where it
# was weakest, and in every world the tuned setting has ten times the package's feature
# learning rate (eps_W = 0.5); but linear SARSA on the same pixels gains as much from the same
# budget, so tuning does **not** close the gap in the floor world or in the Nao-like world,
# the one fixed from Nao's published specifications. There, and in the floor world, even the
# one-line centroid rule docks more often than the tuned paper's learner, while PPO docks in
# nearly every trial and the pose oracle shows both worlds solvable. Only in the sideboard
# world, where the package's choices were calibrated, is the gap below the rule's 5 pp, and
# even there linear SARSA and PPO dock more often.

# %% tags=["hide-input", "fold-output"]
paper_gain = {
    w: report.paired_over_shared_seeds(contest, f"{w}/paper-tuned", f"{w}/paper")
    for w in te.CONTEST
}
assert paper_gain["floor"].low > 0 and paper_gain["nao"].low > 0  # tuning helps it there
assert all(r["setting"]["eps_w"] == 0.5 for r in tuning if r["learner"] == "paper")
assert by_world["floor"].verdict == by_world["nao"].verdict == "remains"
assert by_world["sideboard"].verdict == "closed" and by_world["sideboard"].interval.low > 0
assert all(by_ppo[w].interval.low > 0 for w in te.CONTEST)  # PPO ahead everywhere
for w in ("floor", "nao"):  # the centroid rule ahead of the tuned paper's learner
    assert (
        rate_interval(contest, f"{w}/paper-tuned").high
        < rate_interval(contest, f"{w}/centroid").low
    )
assert min(contest.score(f"{w}/oracle").mean() for w in te.CONTEST) >= 0.99  # solvable
display(
    Markdown(
        "Tuning's gain for the paper's learner (tuned minus untuned, matched seeds): "
        + "; ".join(
            f"{third_edition_report.CONTEST_NAMES[w]} {paper_gain[w].format(unit=' pp')}"
            for w in te.CONTEST
        )
        + "."
    )
)

# %% [markdown]
# ## The addendum: every learner tuned until its optimum is bracketed
#
# The contest above stopped at the edge of its grids: the paper's learner chose the largest
# eps_W of its grid in every world, linear SARSA the largest exploration temperature, and the
# two SARSA learners were not tuned on the same knobs. **The addendum** (a new, labelled
# analysis; the tables above stay as they were run) asks the question again in the two worlds
# where the gap remained. Its rules were committed before any of its runs
# (`docking/study/designs/addendum.py`; its record in `rules/` keeps the rules text and the
# search's and the gap rule's code as committed):
#
# * **The same knobs for both SARSA learners:** eps_Q, the exploration temperature beta_a in
#   training (Eq. 4) and, for the paper's learner, eps_W, each on a log-spaced ladder.
# * **A search that extends until the optimum is inside:** 9 settings on 2 tuning seeds each
#   (linear SARSA's full 3 x 3 grid; the paper's learner's 3 x 3 x 3 grid as its orthogonal
#   L9 fraction); then up to 5 stages that evaluate every untried neighbour of the best setting
#   on the ladders; then the best 3 settings again on as many further seeds as the budget of
#   66 training runs per learner and world leaves.
# * **Judged** as the contest was: fresh seeds 5000-5009, 500 held-out trials each on matched
#   seeds, the gap *closed* if its 95% interval lies below 5 pp, *remains* if above.
# * **PPO's budget in environment steps:** its third-edition setting, trained for as many
#   steps as the tuned paper learner's judged runs took on average in that world.
#
# Cut for the budget, and why: the sideboard world (the gap was already closed there), PPO's
# own tuning (it docks in nearly every trial; it bounds the others), the yardsticks (the
# contest's serve, same worlds and protocol).

# %% tags=["hide-input", "fold-output"]
added = ad.DESIGN.run(progress=False)
rules_commit, rules_time = provenance.RULES_COMMITS[ad.NAME]  # tests/test_addendum.py checks it
times = provenance.computed_times(ad.NAME)
n_runs = sum(len(added.runs[c.key]) for c in added.cells if c.trained)
print(
    f"rules committed {rules_time} ({rules_commit[:7]}); the addendum's {len(times)} runs "
    f"computed {min(times):%Y-%m-%d %H:%M} to {max(times):%Y-%m-%d %H:%M} (UTC)"
)
assert len(times) == n_runs and min(times) > report.utc(rules_time)  # every run after its rules

# %% [markdown]
# ### The search: where each tuned value lies
#
# Each tuned value in bold among the values tried on its line (the other knobs at their tuned
# values); *interior* means values on both sides were tried and did worse.

# %% tags=["hide-input", "fold-output"]
bracketed = addendum_report.bracketed_rows(added, ad)
display(Markdown(addendum_report.bracketed_table(bracketed)))
edges = {
    (r["world"], r["learner"], knob): where
    for r in bracketed
    for knob, (_, where) in r["positions"].items()
    if where != "interior"
}
display(
    Markdown(
        "Not bracketed: "
        + "; ".join(
            f"{names[w]}, {learner}'s {knob}: {where}"
            for (w, learner, knob), where in edges.items()
        )
        + ". The search's five extension stages ran out with the paper's learner still moving "
        "(its tuned setting came from round 2, among the best three, whose neighbours were not all "
        "tried): its optimum is not bracketed: at it, the paper's learner may dock more often "
        "than below, and linear SARSA's lead may be smaller. Linear SARSA's every tuned value is interior."
    )
)
for r in bracketed:
    assert r["runs"] == ad.BUDGET or r["runs"] > ad.BUDGET - ad.ROUND_2  # equal budgets
assert edges and {learner for _, learner, _ in edges} == {"paper"}  # linear SARSA bracketed

# %% [markdown] tags=["fold"]
# ### The bracketing: the search continued until each optimum is inside
#
# A second labelled analysis, its rules committed before its runs
# (`docking/study/designs/bracketing.py`; its record in `rules/`): from
# where the addendum stopped, every setting is compared on the same 10 tuning seeds
# (5900-5909), and every neighbour of the best one on the ladders is run on the seeds it
# lacks, stage after stage, until the best setting has every neighbour tried (or 100 runs
# per learner and world, or 5 stages, are spent). The same rule for both learners. A tuned
# setting that changes is judged on the addendum's judged seeds; one that does not keeps
# the addendum's judged runs.

# %% tags=["hide-input", "fold-output"]
from docking.study.designs import bracketing as br  # noqa: E402


def shown_walk(walk):
    """A walk of the bracketing (its design module): its results and rows, its table shown,
    its budget, its "bracketed" and its rules-before-runs asserted."""
    own = walk.DESIGN.run(progress=False)
    rows = bracketing_report.bracketing_rows(own, walk)
    display(Markdown(bracketing_report.bracketing_table(rows)))
    for r in rows:
        assert r["runs"] <= walk.BUDGET
        assert r["bracketed"] == all(
            not w.startswith("at the edge") for _, w in r["positions"].values()
        )
    times = provenance.computed_times(walk.NAME)
    assert min(times) > report.utc(provenance.RULES_COMMITS[walk.NAME][1])  # runs after rules
    return own, rows


walk = br
own, bracketing = shown_walk(br)
assert all(r["bracketed"] for r in bracketing if r["learner"] == "linear")
edges = [r for r in bracketing if not r["bracketed"]]
display(
    Markdown(
        "Not bracketed when its runs ran out: "
        + "; ".join(
            f"{names[r['world']]}, {r['learner']}'s "
            + ", ".join(k for k, (_, w) in r["positions"].items() if w.startswith("at the edge"))
            for r in edges
        )
        + "."
    )
)

# %% [markdown]
# ### The bracketing continued, judged on fresh seeds
#
# A third labelled analysis, written after the bracketing's runs were seen (which is why it
# is a new analysis, not a change of the bracketing's rules), its rules committed before its
# own runs (`docking/study/designs/bracketing_continued.py`; its record in `rules/`): the
# bracketing's walk, unchanged, with a
# further budget of runs per learner and world, the same for both learners; then **both**
# tuned SARSA learners, and PPO at the paper's learner's training steps, judged on fresh
# seeds that no earlier run used (the addendum's judged seeds had had two judged looks).
# From here on, "tuned" means tuned by this walk and judged on these seeds.

# %% tags=["hide-input", "fold-output"]
from docking.study.designs import bracketing_continued as bc  # noqa: E402

walk = bc
own, bracketing = shown_walk(bc)
final = bracketing_report.bracketed_addendum(added, own, bc)  # the tuned learners from here on
for w in ad.WORLDS:  # every tuned learner judged on the fresh seeds
    for v in ("paper-tuned", "linear-tuned", "ppo-matched"):
        assert {r.seed for r in final.runs[f"{w}/{v}"]} == set(bc.SEEDS)

# %% [markdown]
# **How flat the top is.** For each learner, its best settings' mean success over the same 10
# tuning seeds, beside the standard error of one setting's mean (its seeds' spread over
# √10): where the best few lie within about one standard error of each other, which of
# them the search ends on is a draw of its seeds, not a property of the learner.

# %% tags=["hide-input", "fold-output"]
flat = []
for r in bracketing:
    found = walk.scores(own, r["world"], r["learner"])
    means = sorted(walk.WALK.complete(found).values(), reverse=True)
    tuned_seeds = [found[tuple(r["tuned"].items())][s] for s in walk.COMPARE_SEEDS]
    se = float(np.std(tuned_seeds, ddof=1) / np.sqrt(len(tuned_seeds)))
    flat.append(
        (
            names[r["world"]],
            r["learner"],
            " · ".join(f"{100 * m:.1f}" for m in means[:4]),
            f"{100 * se:.1f} pp",
            "bracketed"
            if r["bracketed"]
            else f"stopped: {'its runs' if r['runs'] + 10 > walk.BUDGET else 'its stages'} ran out",
        )
    )
header = ("world", "learner", "the 4 best settings (%)", "one setting's s.e.", "search")
display(Markdown(report.md_table(header, flat)))
display(Markdown(bracketing_report.bracketing_summary(bracketing, final, ad)))

# %% [markdown]
# ### Training steps, and PPO's budget matched to them

# %% tags=["hide-input", "fold-output"]
# training steps per run of each tuned learner, and PPO's budget matched to the paper's
variants = {
    "paper-tuned": "the paper's learner, tuned",
    "linear-tuned": "linear SARSA, tuned",
    "ppo-matched": "PPO (its budget)",
}
steps_rows = addendum_report.training_steps_rows(final, ad.WORLDS, variants)
display(Markdown(addendum_report.training_steps_table(steps_rows)))
by_row = {(w, label): steps for w, label, _, steps in steps_rows}
for w in ad.WORLDS:
    name = third_edition_report.CONTEST_WORLDS[w]
    paper_steps = by_row[name, variants["paper-tuned"]].mean()
    assert abs(by_row[name, variants["ppo-matched"]][0] / paper_steps - 1) < 0.05  # within 5%

# %% [markdown] tags=["fold"]
# ### The gap, tuned to each learner's optimum (the first judgement; replicated below)

# %% tags=["hide-input", "fold-output"]
added_gaps = report.contest_gaps(final, ad.WORLDS, ad.GAP_CLOSED)
added_ppo = report.contest_gaps(final, ad.WORLDS, ad.GAP_CLOSED, other="ppo-matched")
display(Markdown(report.gaps_table(added_gaps + added_ppo)))
rows = [
    (
        label,
        *(pct(rate_interval(results, f"{w}/{v}")) for w in ad.WORLDS),
    )
    for label, results, v in (
        ("the paper's learner, tuned (bracketed, fresh seeds)", final, "paper-tuned"),
        ("the paper's learner, tuned (addendum)", added, "paper-tuned"),
        ("the paper's learner, tuned (contest)", contest, "paper-tuned"),
        ("linear SARSA, tuned (bracketed, fresh seeds)", final, "linear-tuned"),
        ("linear SARSA, tuned (contest)", contest, "linear-tuned"),
        ("PPO, matched steps (fresh seeds)", final, "ppo-matched"),
        ("pose oracle (contest)", contest, "oracle"),
        ("centroid rule (contest)", contest, "centroid"),
    )
]
display(Markdown(report.md_table(("", *(names[w] for w in ad.WORLDS)), rows)))

# %% [markdown] tags=["fold"]
# ### What the addendum shows (its first judgement; the replication below supersedes it)
#
# Each sentence is computed from the runs; the asserts hold what they say.

# %% tags=["hide-input", "fold-output"]
added_by = {g.world: g for g in added_gaps}
contest_by = {g.world: g for g in gaps}
lines = []
for w in ad.WORLDS:
    tuned = {r["learner"]: r["tuned"] for r in bracketing if r["world"] == w}
    lines.append(
        f"* **{names[w]}:** tuned by the addendum's search and its bracketing's walk, the paper's "
        f"learner docks {pct(rate_interval(final, f'{w}/paper-tuned'))} (the contest's tuning: "
        f"{pct(rate_interval(contest, f'{w}/paper-tuned'))}) with "
        f"{', '.join(f'{k} = {v:g}' for k, v in tuned['paper'].items())}; linear SARSA "
        f"{pct(rate_interval(final, f'{w}/linear-tuned'))} with "
        f"{', '.join(f'{k} = {v:g}' for k, v in tuned['linear'].items())}. Linear SARSA's lead: "
        f"{added_by[w].interval.format(unit=' pp')} (the contest's: "
        f"{contest_by[w].interval.format(unit=' pp')}), the gap rule: **{added_by[w].words}**."
    )
display(Markdown("\n".join(lines)))


# %% [markdown]
# ## The replication (*superseded* by the equal contest, notebook 07)
#
# Before the equal contest, the study's answer was the replication's: the contest (whose
# finding, a gap of about 36 pp in the floor and Nao-like worlds, **was too strong**), the
# addendum that tuned both SARSA learners on the same knobs, the bracketing that continued the
# search until each optimum was inside what was searched, and a **replication** on fresh seeds.
# Its searches were not alike (the paper's learner had about 200 tuning runs per world, linear
# SARSA about 80, PPO 15), which is why the equal contest was run; it is kept here as run.
#
# The replication (`docking/study/designs/replication.py`, rules committed in 792adb7 before
# its first run; its record in `rules/`) judges the bracketed learners again, and PPO trained
# for as many steps, on 20 fresh seeds per world by the same gap rule: *closed* (the paper's
# learner non-inferior at 5 pp, a one-sided test: the glossary's "the gap") if linear SARSA's
# lead over the paper's learner has its 95% interval below 5 pp, *remains* if above. A learner's **lead** is named only where the interval (Holm over the two worlds)
# excludes zero in both the first judgement and the replication. Two learners' runs of a seed
# are matched by seed, not paired: one generator draws both the starts and the step noise, so
# only a trial's first start is shared.

# %% tags=["hide-input", "fold-output"]
from docking.study import answer  # noqa: E402
from docking.study.designs import bracketing_continued as bc  # noqa: E402
from docking.study.designs import replication as rp  # noqa: E402

replicated = answer.replication(bc.DESIGN.run(progress=False), rp.DESIGN.run(progress=False))
display(Markdown(answer.replication_text(replicated, glossary=None)))
for r in replicated.values():  # every judged run on the replication's own seeds
    assert len(r.paper) == len(r.linear) == len(rp.SEEDS) >= 20
assert replicated["floor"].verdict == replicated["floor"].first_verdict == "closed"
assert replicated["nao"].verdict == replicated["nao"].first_verdict == "closed"
# linear SARSA's floor lead seen twice: replicated; the paper's Nao-like lead seen once
assert replicated["floor"].first_lead == replicated["floor"].lead == "linear ahead"
assert replicated["nao"].first_lead == "paper ahead" and replicated["nao"].lead == "no lead shown"

# %% [markdown]
# **What the replication said (*superseded*).** Tuned alike to bracketed optima, the paper's learner docks within
# 5 pp of linear SARSA (no feature layer) in both worlds, and that replicates. Linear SARSA's
# small lead in the floor world replicates; the paper's learner's lead in the Nao-like world,
# seen once at the edge of its interval, does not, so it is not a finding. Once both are
# tuned, the feature layer neither buys nor costs much success. What differs is the way
# there: at its published settings the paper's learner docks far less often (the fragility
# landscape, below), and its search took more runs than linear SARSA's (counted here).

# %% tags=["hide-input", "fold-output"]
# the tuning effort, counted from the ledger's records
from docking.study import ledger  # noqa: E402

effort = answer.effort(ledger.manifest())
display(
    Markdown(
        "Tuning runs (and settings) on the tuning seeds: "
        + "; ".join(f"{w}, {who}: {n} ({k})" for (w, who), (n, k) in effort.items())
    )
)
assert all(effort[w, "paper"][0] > 2 * effort[w, "linear"][0] for w in ad.WORLDS)

# %% [markdown]
# ## The fragility landscape of the unequal searches (*superseded* by the equal contest's common grid, notebook 07)
#
# How narrow is each learner's good region? Each panel draws every setting the tuning ran
# (and the landscape's own runs on tuning seeds 5900-5901, `docking/study/designs/landscape.py`,
# rules committed before its runs, where a readable grid needed them), coloured by its mean
# held-out success over the tuning seeds' runs: the paper's learner over β_a in training × ε_W
# at its tuned ε_Q, linear SARSA over β_a × ε_Q. The star is the tuned (bracketed) setting,
# the circle the paper's published one. The sentence under it counts, of the settings each
# learner's search ran on at least two seeds, those within 5 pp of the best of them.

# %% tags=["hide-input", "fold-output"]
from docking.study.designs import landscape as lsc  # noqa: E402
from docking.study.designs import landscape_report as lscr  # noqa: E402

scores = lsc.run_scores()
fig = figures.fig_landscape(*lscr.panels(scores))
display(Image(filename=str(save_named(fig, "fragility_landscape_searches"))))
near = lscr.shares()
display(Markdown(lscr.shares_sentence(near)))
for (w, learner), (k, n) in near.items():
    assert 1 <= k <= n and n >= 10, (w, learner, k, n)  # the best is near itself; a real search
published = {w: contest.score(f"{w}/paper").mean() for w in ad.WORLDS}
tuned_paper = {w: replicated[w].paper.mean() for w in ad.WORLDS}
for w in ad.WORLDS:  # the published settings lie far below the tuned optimum in both worlds
    assert published[w] < tuned_paper[w] - 0.4, (w, published[w], tuned_paper[w])
display(
    Markdown(
        "The paper's learner's mean held-out success at its published settings (the circle; "
        "the contest's runs) and at its tuned ones (the star; the replication's runs): "
        + "; ".join(
            f"{third_edition_report.CONTEST_NAMES[w]} {100 * published[w]:.1f}% and "
            f"{100 * tuned_paper[w]:.1f}%"
            for w in ad.WORLDS
        )
        + "."
    )
)

# %% [markdown]
# **A lead seen once.** In the Nao-like world, linear SARSA at ε_Q 0.3 (its tuned ε_Q was
# lower) docked above its tuned setting's replicated rate at several β_a, on the landscape's
# runs of the tuning seeds. A few runs on two seeds are a lead to test on fresh seeds, not a
# finding: it was reported here and used nowhere else. The equal contest's search, run over
# the same grid for every learner, chose ε_Q 0.3 for linear SARSA in the Nao-like world
# (asserted below), and its judged seeds put linear SARSA ahead there (notebook 07).

# %% tags=["hide-input", "fold-output"]
# the lead: linear SARSA in the Nao-like world at eps_Q 0.3
lead_at = {  # linear SARSA, Nao-like world, eps_Q 0.3: each beta_a's runs on the tuning seeds
    b: runs
    for b in lsc.BETA_A
    if (runs := lsc._scores_of(scores, "nao", "linear", lsc.setting("nao", "linear", b, 0.3)))
}
above = {b: r for b, r in lead_at.items() if np.mean(r) > replicated["nao"].linear.mean()}
display(
    Markdown(
        f"Linear SARSA in the Nao-like world, replicated at its tuned setting: "
        f"{100 * replicated['nao'].linear.mean():.1f}%. At ε_Q 0.3: "
        + "; ".join(
            f"β_a {b:g}: {100 * np.mean(r):.1f}% ({len(r)} runs)" for b, r in lead_at.items()
        )
        + "."
    )
)
assert above and all(len(r) <= 3 for r in above.values())  # above it, on few runs: a lead only
# the equal contest (notebook 07) chose that eps_Q for linear SARSA in the Nao-like world
from docking.study.designs import equal_contest as ec  # noqa: E402
from docking.study.designs import equal_contest_report as ecr  # noqa: E402

assert ecr.chosen(ec.DESIGN.read())["nao", "linear"]["eps_q"] == 0.3
