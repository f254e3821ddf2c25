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
# # The findings of notebook 08 (draft: joins the notebook when their runs are in the ledger)
#
# `make test` does not execute `drafts/`.

# %%
import numpy as np
from IPython.display import Image, Markdown, display

from docking import analysis, figures, report
from docking.designs import third_edition as te
from docking.designs import untested as ut
from docking.designs.builders import with_cup
from docking.experiments import initial_network
from docking.report import save_named
from docking.stats import t_mean_ci, t_paired_ci

pct = lambda ci: ci.format(unit="%")  # noqa: E731
pp = lambda ci: ci.format(unit=" pp")  # noqa: E731


def md_table(header: list[str], rows: list[list[str]]) -> Markdown:
    """A Markdown table of ``rows`` under ``header``."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return Markdown("\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows]))


# %% [markdown]
# ## 4. Population coding (a finding)
#
# > "This 'population' coding might be useful for resolving ambiguities" (Sec. III)
#
# beta_s from the paper's 100 (nearly winner-take-all) down to 30, 10 and 3 (soft), with
# eps_W / beta_s held at the paper's (the gradient of Eq. 8 scales with beta_s), and a forced
# single winner (the feature layer's softmax replaced by a one-hot of its largest input): the
# held-out success of each, ten seeds, in the sideboard and the floor worlds. And the
# ambiguities that population coding might resolve: of 1500 start views per world, those whose
# 32x10 input another start pose shares (*shared*), and of them those the pose oracle answers
# with another action (*ambiguous*, in groups of one input each).

# %%
findings = ut.part("findings").run(progress=False)
fmean = lambda key: t_mean_ci(findings.score(key))  # noqa: E731
variants = ["paper", "winner", *(f"beta{b:g}" for b in ut.BETAS)]
population = {
    (w, v): report.paired_over_shared_seeds(findings, f"{w}/{v}", f"{w}/paper")
    for w in ut.WORLDS
    for v in variants[1:]
}
display(
    md_table(
        ["variant"] + [f"{w}: {h}" for w in ut.WORLDS for h in ("held-out", "minus the paper's")],
        [
            [v]
            + [
                x
                for w in ut.WORLDS
                for x in (pct(fmean(f"{w}/{v}")), pp(population[w, v]) if v != "paper" else "")
            ]
            for v in variants
        ],
    )
)
ambiguity = {w: analysis.ambiguous_views(world, n=1500) for w, world in ut.WORLDS.items()}
display(
    Markdown(
        "| world | start views | sharing an input | ambiguous (the oracle acts differently) "
        "| groups |\n|---|---|---|---|---|\n"
        + "\n".join(
            f"| {w} | {a.views} | {a.shared} | {a.ambiguous} | {len(a.groups)} |"
            for w, a in ambiguity.items()
        )
    )
)

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence):

# %%
softer = {w: [population[w, f"beta{b:g}"] for b in ut.BETAS] for w in ut.WORLDS}
display(
    Markdown(
        "* **Softer is worse.** beta_s 3 changes held-out success by "
        + ", ".join(f"{pp(population[w, 'beta3'])} in the {w} world" for w in ut.WORLDS)
        + "; beta_s 10 "
        + ", ".join(f"{pp(population[w, 'beta10'])}" for w in ut.WORLDS)
        + ". A population code wider than the paper's does not help.\n"
        "* **A forced single winner** changes it by "
        + ", ".join(f"{pp(population[w, 'winner'])} ({w})" for w in ut.WORLDS)
        + ". With s one-hot, Eq. (8)'s non-local bracket is zero, so W also stays at its "
        "random start: the difference measures the hard winner and frozen features together "
        "(W frozen alone, under the softmax, is notebook 07's features-success claim).\n"
        "* **Ambiguities** are few: "
        + ", ".join(
            f"{a.ambiguous} of {a.views} start views in the {w} world" for w, a in ambiguity.items()
        )
        + " share their input with a pose the oracle answers otherwise; a population code has "
        "little to resolve in these worlds."
    )
)
assert all(population[w, "beta3"].high < 0 and population[w, "beta10"].high < 0 for w in ut.WORLDS)
assert all(a.ambiguous <= 0.05 * a.views for a in ambiguity.values())


# %% [markdown]
# ## 5. Neglecting the irrelevant (a finding)
#
# > "learns to neglect irrelevant parts of the input" (Sec. I, II-A)
#
# Where the winning units put their weight (`analysis.weight_mass`): the shares of |W| on the
# landmark's pixels, the red cup's and the background's, weighted by how often each unit wins,
# over 1500 start views of the world with the cup. For networks trained with and without the
# cup, after 250, 1000 and 2000 training trials, against the same seeds' random start (W
# frozen). The first five seeds (`ut.NEGLECT_SEEDS`), whose networks the ledger keeps.

# %%
cup_world = with_cup(ut.WORLDS["sideboard"])
neglect = {}
for trained in ("without", "with"):
    for n, cell in ((250, "trained250"), (1000, "trained1000"), (2000, "paper")):
        cell = cell if trained == "without" else ("cup" if cell == "paper" else f"cup-{cell}")
        runs = findings.runs[f"sideboard/{cell}"][: len(ut.NEGLECT_SEEDS)]
        neglect[trained, n] = np.array([analysis.weight_mass(r.network, cup_world) for r in runs])
runs = findings.runs["sideboard/paper"][: len(ut.NEGLECT_SEEDS)]
frozen = np.array(
    [analysis.weight_mass(initial_network(r.config, r.seed), cup_world) for r in runs]
)
share = lambda m: [f"{100 * m[:, k].mean():.2f}%" for k in range(3)]  # noqa: E731
gain = {k: t_paired_ci(m[:, 0], frozen[:, 0]) for k, m in neglect.items()}  # landmark share
display(
    md_table(
        ["trained", "trials", *analysis.MASS_PARTS, "landmark minus the random start"],
        [["(random start)", "0", *share(frozen), ""]]
        + [[f"{t} the cup", str(n), *share(m), pp(gain[t, n])] for (t, n), m in neglect.items()],
    )
)

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence):

# %%
largest = max(max(abs(g.low), abs(g.high)) for g in gain.values())
display(
    Markdown(
        "The winning units' weight on the landmark's pixels does not move: after every "
        "number of training trials, with and without the cup, it lies within "
        f"{100 * largest:.2f} pp of the same seeds' random start (the landmark's share of "
        f"|W| is {100 * frozen[:, 0].mean():.2f}% at the start). W barely leaves its random "
        "start in this world (as notebook 07's interpretability claim found), so what the learner "
        "neglects, it neglects in Q, not in the features: the paper's \"learns to neglect "
        'irrelevant parts of the input" is not visible in W here.'
    )
)
assert largest < 0.005  # within half a percentage point, every trained state


# %% [markdown]
# ## 6. The mechanism of the failure (exploratory)
#
# In the floor world the paper's learner docks far less often than linear SARSA on the same
# pixels (notebook 07). One part of the paper's learner varied at a time: the number of
# feature units (144, 576 against 36), the action layer's rate eps_Q (0.03, 0.3 against 0.1),
# beta_s and a forced single winner (above), and the pairs `ut.PAIRS` (the local feature rule
# is the third edition's finding: 17 pp better in the floor world). Each variant minus the
# paper's learner, paired by seed over ten seeds, with linear SARSA's lead dotted: a variant
# closes the gap where its interval reaches linear SARSA's line.

# %%
(mechanism,) = [c for c in ut.CLAIMS if c.key == "mechanism"]
(panel,) = report.verdict_panels([mechanism], findings, [])
by_world = []
for w in ut.WORLDS:
    rows = [r for r in panel["rows"] if r[0].startswith(f"{w}:")]
    lead = report.paired_over_shared_seeds(findings, f"{w}/linear", f"{w}/paper")
    by_world.append(
        dict(panel, title=f"{w} world", rows=rows, reference=(lead.estimate, "linear SARSA"))
    )
display(Image(save_named(figures.fig_verdicts(by_world), "untested_mechanism")))

# %% [markdown]
# Which part closes the gap, by the third edition's contest rule (committed before these
# runs): a variant *closes* it if linear SARSA minus the variant, paired by seed, has its 95%
# interval below 5 pp; the gap *remains* if the interval lies above 5 pp; else undecided.

# %%
mechanism_variants = ["paper", "winner", *(f"beta{b:g}" for b in ut.BETAS)]
mechanism_variants += [k.split("/", 1)[1] for _, k in mechanism.cells["floor"]]
gap = {}
for w in ut.WORLDS:
    for v in mechanism_variants:
        ci = report.paired_over_shared_seeds(findings, f"{w}/linear", f"{w}/{v}")
        closed = ci.high < te.GAP_CLOSED
        gap[w, v] = ci, "closed" if closed else "remains" if ci.low > te.GAP_CLOSED else "undecided"
display(
    md_table(
        ["variant"] + [f"{w}: linear SARSA minus it" for w in ut.WORLDS],
        [
            [v] + [f"{pp(gap[w, v][0])} {gap[w, v][1]}" for w in ut.WORLDS]
            for v in mechanism_variants
        ],
    )
)

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence):

# %%
closes = {w: [v for v in mechanism_variants if gap[w, v][1] == "closed"] for w in ut.WORLDS}
display(
    Markdown(
        "\n".join(
            f"* **{w} world:** linear SARSA leads the paper's learner by "
            f"{pp(gap[w, 'paper'][0])} ({gap[w, 'paper'][1]}); the gap is closed by "
            + (", ".join(v for v in closes[w] if v != "paper") or "no variant")
            + "."
            for w in ut.WORLDS
        )
    )
)
