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
# # 03 — Experiment 1: docking from close by, 4 feature units, the local rule (Fig. 3)
#
# **The paper's claim** (Sec. III): the robot "is only initialized in close proximity to the
# target, so that the resolution of the visual input is optimal for the extraction of the
# visual features". The network has 4 feature units and learns with the *local* rule
# $\Delta W_{jn} \propto \delta\, s_j I_n$ (Eq. 8 without the bracket; Sec. II-B). "After
# reaching its goal position and receiving a reward for about 25 times, the robot is already
# able to master the simple task successfully in 100 % of the trials." Fig. 3 shows three
# feature units with the landmark's shape as seen from the left, the front and the right, each
# mapped to its action; the fourth unit, like the backward action, stays unstructured.
#
# This notebook runs the experiment for several seeds (the paper reports one run), shows the
# learning curve, regenerates Fig. 3 from the headline seed and sets the numbers beside the
# paper's. Saved runs in `results/experiment1/` are re-used; delete them (or pass
# `force=True`) to train again.

# %%
import numpy as np
from IPython.display import Image, Markdown, display

from docking.analysis import best_actions, feature_change
from docking.experiments import EXPERIMENT_1, SEEDS
from docking.figures import FIGURES_DIR
from docking.report import (
    configuration_table,
    experiment1_rows,
    headline,
    markdown_table,
    save_fig3,
)
from docking.store import run_seeds
from docking.world import ACTION_LETTERS, DockingEnv

config = EXPERIMENT_1

# %% [markdown]
# ## The configuration: every choice the paper leaves open, named
#
# The values below are read from `docking.experiments.EXPERIMENT_1` and the dataclasses it is
# built from, so this table is always the configuration that ran. "Close proximity" is a start
# region 6-18 cm beyond the docking region, one forward step away when the robot is aligned;
# the world's choices (steps, noise, landmark, region) are explained in notebook 02, the
# learning rates under "What the choices do" below.

# %%
display(Markdown(configuration_table(config)))

# %% [markdown]
# ## Run (or load) the experiment
#
# Each seed trains a fresh network for 100 trials and then tests it greedily
# ($\beta^a = 100$, no learning) on 200 trials from the same start region. Seeds run in
# parallel worker processes, one per core.

# %%
results = run_seeds(config, SEEDS[config.name])
main = headline(results)
for r in results:
    print(
        f"seed {r.seed}: test {r.test_successes}/{len(r.test.success)} docked, "
        f"{int(r.train.success.sum())} rewarded training trials, mastered after "
        f"{r.rewarded_until_mastery} rewards ({r.trials_until_mastery} trials); "
        f"{r.wall_time_train + r.wall_time_test:.1f} s"
    )

# %% [markdown]
# ## The learning curve
#
# Every 5 training trials the current network is tested greedily on 50 trials. The paper's
# measure of learning speed is the number of *rewarded* trials until the task is mastered:
# below, the rewarded training trials when the test success first reaches 100 %.

# %%
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(7, 3.2))
for r in results:
    ax.plot(
        r.curve_rewarded,
        100 * r.curve_success,
        lw=2.5 if r.seed == main.seed else 0.8,
        label=f"seed {r.seed}" + (" (headline)" if r.seed == main.seed else ""),
    )
ax.axvline(25, color="k", ls=":", lw=1)
ax.text(25.5, 5, "paper: ~25 rewards", fontsize=8)
ax.set_xlabel("rewarded training trials so far")
ax.set_ylabel("greedy test success (%)")
ax.set_ylim(0, 102)
ax.legend(fontsize=7, ncol=3)
plt.show()

# %% [markdown]
# ## Fig. 3: raw camera images, action and feature receptive fields
#
# The action units' receptive fields are mapped back into the input space as
# $\sum_j Q_{ij} W_j$; the feature units' receptive fields are the rows $W_j$. Strong weights
# are dark, as in the paper.

# %%
save_fig3(main, DockingEnv(config.world, seed=0))  # analysis -> figures.fig3 -> save
display(Image(filename=str(FIGURES_DIR / "fig3_experiment1.png")))

# %%
winners, counts = np.unique(main.test.winners, return_counts=True)
usage = dict(zip(winners.tolist(), counts.tolist(), strict=False))
best = best_actions(main.network.Q)
change = feature_change(main)
for j in range(config.network.n_features):
    print(
        f"unit {j}: wins {usage.get(j, 0):4d} test decisions, best action "
        f"{ACTION_LETTERS[best[j]] if best[j] >= 0 else 'none'}, cosine to its initial weights {change[j]:.2f}"
    )
backward = np.mean(main.test.actions == ACTION_LETTERS.index("B"))
print(f"backward actions in the test trials: {100 * backward:.1f}%")

# %% [markdown]
# The local rule does learn visual features here: on top of its random initial weights, each
# unit that wins test decisions has grown the landmark as seen from its part of the start
# region (left of the dock, in front, right), and is mapped to the action that docks from
# there. The change is visible but not large (cosines to the initial weights of about
# 0.85-0.96 for these units): at $\beta^s = 100$ a small lead in $h_j$ is enough to win. As
# in the paper, one unit stays unstructured and the backward action is hardly ever used.
#
# ## What the choices do
#
# Measured while calibrating (100 training trials, 6 seeds each unless noted; the test
# success is over the final greedy test trials; steps in cm):
#
# | setting | mean test success | seeds at 100 % |
# |---|---|---|
# | 8 / 6 cm steps, start 0.65-0.85 m, 20 cm deep x 8 cm wide region, $\epsilon_Q = 0.5$ (4 seeds) | 51 % | 0 of 4 |
# | 8 / 6 cm steps, start 0.58-0.70 m, $\epsilon_Q = 0.1$ | 95 % | 2 of 6 |
# | 15 / 10 cm steps, start 0.58-0.70 m, $\epsilon_Q = 0.05$ | 97 % | 4 of 6 |
# | **15 / 10 cm steps, start 0.58-0.70 m, $\epsilon_Q = 0.1$ (this configuration)** | **99.8 %** | **5 of 6** |
# | 15 / 10 cm steps, start 0.58-0.70 m, $\epsilon_Q = 0.2$ | 94 % | 3 of 6 |
# | 15 / 10 cm steps, start 0.60-0.80 m, $\epsilon_Q = 0.1$ | 99.7 % | 4 of 6 |
#
# Why: training explores with $\beta^a = 2$ on Q-values below 1, so it is close to a random
# walk, and the greedy test policy is only as good as the ordering of Q-values that this walk
# teaches. Starting close to the region (one step away when aligned) makes rewards frequent
# and the value gaps between actions large; a larger $\epsilon_Q$ makes the ordering
# flip from trial to trial, a smaller one does not settle it within 100 trials.
#
# ## Against the paper

# %%
table = markdown_table(experiment1_rows(results))
display(Markdown(table))

# %% [markdown]
# The claims, checked on these runs (the notebook fails if they do not hold):

# %%
rates = np.array([r.test.success_rate for r in results])
assert len(main.test.success) >= 100
assert main.test.success_rate == 1.0, "headline seed must dock in every test trial"
assert np.sum(rates == 1.0) >= 4, f"at least 4 of 5 seeds must reach 100%, got {rates}"
assert main.rewarded_until_mastery is not None and main.trials_until_mastery <= config.train_trials
print(
    "Experiment 1 reproduces: 100% test success within 100 training trials, "
    f"after {main.rewarded_until_mastery} rewarded trials (paper: about 25)."
)
