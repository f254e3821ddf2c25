# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#       jupytext_version: 1.19.6
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Draft: the third edition's addendum (notebook 07) and its decomposition (notebook 08)
#
# Its sections move into notebooks 07 and 08 once every run of `docking/designs/addendum.py`
# is in the ledger, with the sentences' asserts written from those runs.

# %%
import numpy as np
from IPython.display import Image, Markdown, display

from docking import analysis, figures, report
from docking.claims import rate_interval
from docking.designs import addendum as ad
from docking.designs import third_edition as te
from docking.report import save_named
from docking.stats import t_mean_ci  # noqa: F401

contest = te.DESIGN.run(progress=False)
names = report.CONTEST_WORLDS
pct = lambda ci: ci.format(unit="%")  # noqa: E731
pp = lambda ci: ci.format(unit=" pp")  # noqa: E731


def md_table(header, rows) -> Markdown:
    return Markdown(report.md_table(header, rows))


# %% [markdown]
# ## The addendum: every learner tuned until its optimum is bracketed
#
# The contest above stopped at the edge of its grids: the paper's learner chose the largest
# eps_W of its grid in every world, linear SARSA the largest exploration temperature, and the
# two SARSA learners were not tuned on the same knobs. **The addendum** (a new, labelled
# analysis; the tables above stay as they were run) asks the question again in the two worlds
# where the gap remained. Its rules were committed before any of its runs
# (`docking/designs/addendum.py`, pinned by `tests/test_addendum.py`'s digest, which covers
# the search's code and the gap rule's):
#
# * **The same knobs for both SARSA learners:** eps_Q, the exploration temperature beta_a in
#   training (Eq. 4) and, for the paper's learner, eps_W, each on a log-spaced ladder.
# * **A search that extends until the optimum is inside:** 9 settings on 2 tuning seeds each
#   (linear SARSA's full 3 x 3 grid; the paper's learner's 3 x 3 x 3 grid as its orthogonal
#   L9 fraction); then up to 5 stages that evaluate every untried neighbour of the best setting
#   on the ladders; then the best 3 settings again on as many further seeds as the budget of
#   66 training runs per learner and world leaves.
# * **Judged** as the contest was: fresh seeds 5000-5009, 500 held-out trials each on paired
#   streams, the gap *closed* if its 95% interval lies below 5 pp, *remains* if above.
# * **PPO's budget in environment steps:** its third-edition setting, trained for as many
#   steps as the tuned paper learner's judged runs took on average in that world.
#
# Cut for the budget, and why: the sideboard world (the gap was already closed there), PPO's
# own tuning (it docks in nearly every trial; it bounds the others), the yardsticks (the
# contest's serve, same worlds and protocol).

# %%
added = ad.DESIGN.run(progress=False)
rules_commit, rules_time = report.RULES_COMMITS[ad.NAME]  # tests/test_addendum.py checks it
times = report.computed_times(ad.NAME)
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

# %%
bracketed = report.bracketed_rows(added, ad)
display(Markdown(report.bracketed_table(bracketed)))
for r in bracketed:
    assert r["runs"] == ad.BUDGET or r["runs"] > ad.BUDGET - ad.ROUND_2  # equal budgets
    for knob, (_, where) in r["positions"].items():
        assert where == "interior" or where.startswith("at its limit"), (r["world"], knob, where)

# %% [markdown]
# ### Training steps, and PPO's budget matched to them

# %%
variants = {
    "paper-tuned": "the paper's learner, tuned",
    "linear-tuned": "linear SARSA, tuned",
    "ppo-matched": "PPO (its budget)",
}
steps_rows = report.training_steps_rows(added, ad.WORLDS, variants)
display(Markdown(report.training_steps_table(steps_rows)))
by_row = {(w, label): steps for w, label, _, steps in steps_rows}
for w in ad.WORLDS:
    name = report.CONTEST_WORLDS[w]
    paper_steps = by_row[name, variants["paper-tuned"]].mean()
    assert abs(by_row[name, variants["ppo-matched"]][0] / paper_steps - 1) < 0.05  # within 5%

# %% [markdown]
# ### The gap, tuned to each learner's optimum

# %%
added_gaps = report.contest_gaps(added, ad.WORLDS, ad.GAP_CLOSED)
added_ppo = report.contest_gaps(added, ad.WORLDS, ad.GAP_CLOSED, other="ppo-matched")
display(Markdown(report.gaps_table(added_gaps + added_ppo)))
rows = [
    (
        label,
        *(pct(rate_interval(results, f"{w}/{v}")) for w in ad.WORLDS),
    )
    for label, results, v in (
        ("the paper's learner, tuned (addendum)", added, "paper-tuned"),
        ("the paper's learner, tuned (contest)", contest, "paper-tuned"),
        ("linear SARSA, tuned (addendum)", added, "linear-tuned"),
        ("linear SARSA, tuned (contest)", contest, "linear-tuned"),
        ("PPO, matched steps (addendum)", added, "ppo-matched"),
        ("pose oracle (contest)", contest, "oracle"),
        ("centroid rule (contest)", contest, "centroid"),
    )
]
display(Markdown(report.md_table(("", *(names[w] for w in ad.WORLDS)), rows)))

# %% [markdown]
# ## 7. Which part breaks: the representation, or learning Q on it
#
# The variants above change one part at a time and none closes the gap. The third edition's
# addendum (notebook 07) tuned both SARSA learners until every optimum was bracketed; here its
# networks are taken apart. For each judged network of the tuned paper's learner, its W is
# kept and Q is replaced by the **oracle-labelled Q**: each feature unit takes the action the
# pose oracle takes most often on the views it wins (the views of 300 oracle trials from the
# whole start region, a stream no run uses). What that Q docks is what W's partition of the
# views allows when every part of it gets the best single action; per seed and paired:
#
# * linear SARSA minus the oracle-labelled Q on the paper's W: what the **representation**
#   loses (W puts views that need different actions into one unit);
# * the oracle-labelled Q minus the Q the paper's rule learned: what **learning Q** loses.
#
# The reverse check: SARSA on a fixed partition (W from 200 random-walk trials of competitive
# learning, i.e. online k-means of views, then frozen) against the oracle-labelled Q on the
# same W.

# %%

labelled = {w: analysis.oracle_views(ad.WORLDS[w], 300, seed=0) for w in ad.WORLDS}
parts = {d.world: d for d in report.decomposition(added, labelled)}
columns = [
    "linear SARSA, tuned",
    "paper's W, oracle-labelled Q",
    "paper's learner, tuned",
    "k-means W, oracle-labelled Q",
    "SARSA on k-means W",
]
seeds = {}
for w, d in parts.items():
    for label, values in zip(
        columns, (d.linear, d.labelled, d.paper, d.fixed_labelled, d.fixed), strict=True
    ):
        seeds[report.CONTEST_WORLDS[w], label] = values
split = {
    report.CONTEST_WORLDS[w]: (100 * d.representation.estimate, 100 * d.learning_q.estimate)
    for w, d in parts.items()
}
fig = figures.fig_decomposition([report.CONTEST_WORLDS[w] for w in parts], columns, seeds, split)
display(Image(save_named(fig, "addendum_decomposition")))
display(
    md_table(
        ["world", "gap", "representation", "learning Q", "purity of W's partition"],
        [
            [
                report.CONTEST_WORLDS[w],
                pp(d.gap),
                pp(d.representation),
                pp(d.learning_q),
                f"{100 * d.purity.mean():.0f}%",
            ]
            for w, d in parts.items()
        ],
    )
)

# %% [markdown]
# **The answer** (computed from the runs; the asserts hold the sentence):

# %%
answer = []
for w, d in parts.items():
    share = d.representation.estimate / d.gap.estimate
    larger = "the representation" if share > 0.5 else "learning Q on it"
    answer.append(
        f"In {report.CONTEST_NAMES[w]}, of linear SARSA's lead of {pp(d.gap)} over the tuned "
        f"paper's learner, {pp(d.representation)} ({share:.0%}) is lost in the representation "
        f"(its W with the oracle-labelled Q docks {100 * d.labelled.mean():.1f}%; "
        f"{100 * d.purity.mean():.0f}% of the oracle's views share their unit's majority action) "
        f"and {pp(d.learning_q)} in learning Q on it: **{larger}** breaks the learner there. "
        f"SARSA on a fixed k-means W docks {100 * d.fixed.mean():.1f}% against "
        f"{100 * d.fixed_labelled.mean():.1f}% for the oracle-labelled Q on the same W."
    )
display(Markdown("\n\n".join(answer)))
for d in parts.values():
    assert np.allclose(d.gap.estimate, d.representation.estimate + d.learning_q.estimate)

# %% [markdown]
# The levers the contest had not tried, on the same judged seeds: eps_W past 0.5 and the
# exploration temperature were the search's own knobs (notebook 07's addendum table gives where
# each landed), and W initialised from views (the same k-means start, then learned by Eq. 8):

# %%
levers = []
for w in ad.WORLDS:
    init = report.paired_over_shared_seeds(added, f"{w}/views-init", f"{w}/paper-tuned")
    levers.append(
        [
            report.CONTEST_WORLDS[w],
            pct(rate_interval(added, f"{w}/paper-tuned")),
            pct(rate_interval(added, f"{w}/views-init")),
            pp(init),
        ]
    )
display(
    md_table(
        ["world", "tuned (W uniform random)", "tuned, W from views", "W from views minus random"],
        levers,
    )
)
