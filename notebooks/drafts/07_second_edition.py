# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#       format_version: '1.3'
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 07 — The study, second edition: verdicts that measure the claims, not our worlds
#
# **A draft.** It moves to `notebooks/` (and into `make test`) when its runs are in the
# ledger; its assertions of what the runs show are written then, after the runs, while its
# *rules* were committed before them (`docking/designs/second_edition.py`, pinned by
# `tests/test_second_edition.py`).
#
# The first edition (notebook 05) was read by a referee: in the sideboard world a one-line
# pixel rule, linear SARSA and an off-the-shelf PPO all beat the paper's learner; the floor
# world changed six things at once; several rules tested something narrower than the claim.
# This edition measures every world before any learner, walks from one world to the other
# one factor at a time, and re-states each verdict by the rules below.

# %%
import numpy as np
from IPython.display import Image, Markdown, display

from docking import analysis, claims, figures, stats
from docking.designs import second_edition as se
from docking.report import save_named

# %% [markdown]
# ## The intervals: their coverage at ten seeds, checked first
#
# Synthetic seeds like the study's (each seed's true success drawn from a Beta, measured on
# 500 binomial trials; two groups of ten, a true difference of 5 pp): how often does a 95%
# interval cover the truth? The first edition's percentile bootstrap against Student-t
# (Welch), the second edition's choice.

# %%
coverage = {
    (mean, spread, method): stats.coverage(method, mean=mean, spread=spread, repeats=400)
    for mean, spread in ((0.85, 0.08), (0.95, 0.03), (0.5, 0.15))
    for method in ("t", "percentile")
}
display(
    Markdown(
        "| true mean, s.d. over seeds | Welch t | percentile bootstrap |\n|---|---|---|\n"
        + "\n".join(
            f"| {m:.2f}, {sd:.2f} | {coverage[m, sd, 't']:.3f} | "
            f"{coverage[m, sd, 'percentile']:.3f} |"
            for m, sd in ((0.85, 0.08), (0.95, 0.03), (0.5, 0.15))
        )
    )
)
# The choice rests on this: t covers within Monte Carlo error of 0.95; the bootstrap does not.
assert all(coverage[m, sd, "t"] >= 0.92 for m, sd in ((0.85, 0.08), (0.95, 0.03), (0.5, 0.15)))

# %% [markdown]
# ## Run (or load) the design
#
# `python -m docking design run second-edition` from a terminal (a Dask cluster with
# `--scheduler`); stored runs, and the first edition's runs of the same configurations, are
# loaded.

# %%
results = se.DESIGN.run()
cells = {c.key: c for c in results.cells}
pct = lambda ci: ci.format(unit="%")  # noqa: E731

# %% [markdown]
# ## How hard is each world? The yardsticks, before any learner
#
# Held-out success (mean and 95% t interval over seeds) of the pose-reading oracle (the motor
# task's bound), PPO on the 320 pixels (the pixel-level bound: skrl's PPO, 50,000 steps, 5
# seeds), linear SARSA on the pixels, the paper's learner, the one-line centroid rule,
# always-forward and random actions, in every world of the path.

# %%
worlds = [key for key, *_ in se.PATH]
display(Markdown(se.world_table(results)))
oracle = {w: stats.t_mean_ci(results.score(f"{w}/oracle")) for w in worlds}
assert all(oracle[w].estimate >= 0.99 for w in worlds)  # every world is solvable

# %% [markdown]
# ## The path: which factor breaks the paper's learner?
#
# The rule (fixed before the runs): a factor *breaks* the learner if its drop from the
# previous world (Welch's t, Holm over the path's steps) is significant at 0.05 and larger
# than 5 pp; *the pixels suffice* in a world where the pixel-level bound (PPO) reaches 90%.

# %%
path = worlds[:5]
drops = analysis.path_drops([results.score(f"{w}/paper") for w in path])
adjusted = stats.holm([d.p_value(0.0) for d in drops])
display(
    Markdown(
        "| step | drop of the paper's learner (pp) | Holm p | breaks it |\n|---|---|---|---|\n"
        + "\n".join(
            f"| {a} -> {b} | {d.format(unit=' pp')} | {p:.3g} | "
            f"{'yes' if p < se.ALPHA and d.estimate > se.BREAK_DROP else 'no'} |"
            for a, b, d, p in zip(path[:-1], path[1:], drops, adjusted, strict=True)
        )
    )
)
fig = figures.fig_path(
    worlds,
    {
        label: [results.score(f"{w}/{name}") for w in worlds]
        for name, label in se.WORLD_COLUMNS
        if name in ("ppo", "paper", "linear", "centroid")
    },
    se.PIXELS_SUFFICE,
    branches=len(worlds) - len(path),
)
display(Image(save_named(fig, "second_edition_path")))

# %% [markdown]
# ## The verdicts, one family
#
# Every judged comparison's interval (Student-t), its p-value against the rule's bound, and
# Holm's adjustment over all of them; "at the bound" where a decided interval ends within
# 1 pp of the bound.

# %%
decisions = claims.judge_family(se.CLAIMS, results, alpha=se.ALPHA)
verdicts = claims.family_verdicts(se.CLAIMS, decisions)
words = {c.key: c for c in se.CLAIMS}
display(
    Markdown(
        "| claim | verdict | comparison | interval | p | Holm p |\n|---|---|---|---|---|---|\n"
        + "\n".join(
            f"| {d.claim} | {verdicts[d.claim][0]} | {d.world}: {d.key} | "
            f"{d.interval.format(unit='%' if isinstance(words[d.claim].rule, claims.ShareAbove) else ' pp')}"
            f" | {d.p:.3g} | {d.p_adjusted:.3g} |"
            for d in decisions
        )
    )
)
display(
    Markdown("\n".join(f"* **{c.key}** ({c.source}): {c.test}." for c in se.CLAIMS if c.judged))
)

# %% [markdown]
# ## Findings (reported, not verdicts)

# %%
for c in se.CLAIMS:
    if not c.judged:
        found = [
            f"{w}: {c.evidence(results, e)}" for w, entries in c.cells.items() for e in entries
        ]
        print(f"{c.key}: " + "; ".join(found))

# %% [markdown]
# ## Sample efficiency: training trials to 90% greedy success
#
# The rule's measure for the learners with a learning curve (50 greedy trials from the full
# region every 100 training trials). PPO has no such curve; beside it, as a finding with a
# measure of its own: its training episodes until 50 consecutive ones succeed at 90%.

# %%
for w in worlds:
    episodes = []
    for run in results.runs[f"{w}/ppo"]:
        window = np.convolve(run.train_success, np.ones(50) / 50, mode="valid")
        hits = np.flatnonzero(window >= se.EFFICIENCY_LEVEL)
        episodes.append(hits[0] + 50 if len(hits) else np.nan)
    print(f"{w:16s} ppo     training episodes to 90% over 50: {episodes}")
for w in worlds:
    for name in ("paper", "linear"):
        t = analysis.trials_to_level(results.runs[f"{w}/{name}"], se.EFFICIENCY_LEVEL)
        reached = t[~np.isnan(t)]
        print(
            f"{w:16s} {name:7s} reached by {len(reached)}/{len(t)} seeds"
            + (f", median {np.median(reached):.0f} trials" if len(reached) else "")
        )

# %% [markdown]
# ## Does the six-action learner's curve flatten?

# %%
flat = analysis.curve_flatness(results.runs["sideboard/six-long"])
print(
    f"last quarter minus third quarter of its curve: {100 * flat:.1f} pp (flat within "
    f"{100 * se.FLAT_PP:.0f} pp: {abs(flat) <= se.FLAT_PP})"
)
