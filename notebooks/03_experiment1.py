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

from docking.presets import EXPERIMENT_1
from docking.study.analysis import example_views, feature_change
from docking.study.arrays import best_actions, learning_curves
from docking.study.designs import calibration, design
from docking.study.designs.calibration_report import (
    calibration_rows,
    calibration_table,
    computing_time,
)
from docking.study.designs.paper_report import PAPER_COLUMNS, experiment1_rows, headline, save_fig3
from docking.study.figures import FIGURES_DIR, fig_rewards, to_png
from docking.study.report import configuration_table, md_table
from docking.world import ACTION_LETTERS, DockingEnv

config = EXPERIMENT_1

# %% [markdown]
# ## The configuration: every choice the paper leaves open, named
#
# The values below are read from `docking.presets.EXPERIMENT_1` and the dataclasses it is
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
experiments = design("paper").run()  # Experiments 1 and 2, the seeds of docking.presets.SEEDS
results = experiments.runs[config.name]
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
display(Image(data=to_png(fig_rewards(learning_curves(results), main.seed))))

# %% [markdown]
# ## Fig. 3: raw camera images, action and feature receptive fields
#
# The action units' receptive fields are mapped back into the input space as
# $\sum_j Q_{ij} W_j$; the feature units' receptive fields are the rows $W_j$. Strong weights
# are dark, as in the paper.

# %%
views = example_views(DockingEnv(config.world, seed=0))  # the run's world renders the views
save_fig3(main, views)  # receptive fields, decisions -> figures.fig3 -> save
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
winning = [j for j in range(config.network.n_features) if usage.get(j, 0)]
print(
    f"cosines to the initial weights of the units that win: {change[winning].min():.2f}-"
    f"{change[winning].max():.2f}"
)
assert len(winning) == config.network.n_features - 1  # one unit never wins a test decision
assert backward < 0.01

# %% [markdown]
# The local rule does learn visual features here: on top of its random initial weights, each
# unit that wins test decisions has grown the landmark as seen from its part of the start
# region (left of the dock, in front, right), and is mapped to the action that docks from
# there. The change is visible but not large (the cosines to the initial weights printed
# above): at $\beta^s = 100$ a small lead in $h_j$ is enough to win. As in the paper, one
# unit stays unstructured (it never wins a test decision) and the backward action is hardly
# ever used (below 1% of the test actions; both asserted above).
#
# ## What the choices do
#
# Each row below changes one or two of this configuration's choices (where the calibration
# started, shorter steps, $\epsilon_Q$ halved and doubled, a start region further out) and
# runs it for the same seeds, paired with the runs above (the same initial weights and random
# streams), each network tested greedily as above on the test trials of its own start region;
# the bold row *is* the runs above. `docking.study.designs.calibration` defines the rows and says why these.
# Intervals are 95% bootstrap intervals over seeds; the difference to this configuration
# resamples each row's seeds independently. "Training trials rewarded" is the share of the
# 100 training trials that ended in the dock.

# %%
calib = design(f"calibration-{config.name}").run(full=True)
rows = {r.key: r for r in calibration_rows(calib, calibration.BASELINE)}
display(Markdown(calibration_table(list(rows.values()), calibration.BASELINE, seeds_at_100=True)))
print(
    f"computing time of the {len(rows) - 1} variants: {computing_time(calib, calibration.BASELINE):.0f} s"
)

# %% [markdown]
# What the table shows (each statement is asserted below, from these runs):
#
# * **Where the calibration started** (short steps, starts further out, the docking region
#   read as 20 cm deep and 8 cm wide, $\epsilon_Q = 0.5$) docks in fewer test trials than
#   this configuration (the interval of the difference lies below 0), and no seed reaches
#   100 %.
# * **Shorter steps (8 / 6 cm), or starts further out (0.60-0.80 m), each cost test
#   success**: the interval of the difference lies below 0 in both rows.
# * **$\epsilon_Q$ between 0.05 and 0.2 makes no difference these seeds can resolve**: both
#   intervals of the difference contain 0. At $\epsilon_Q = 0.05$ every seed docks in every
#   test trial. (An earlier, hand-typed version of this table had both below this
#   configuration and explained why; these runs do not show it.)
# * **Every row that docks less than this configuration is rewarded less often in
#   training**: for each row whose difference in test success lies below 0, the difference
#   in the share of training trials rewarded lies below 0 too.


# %%
start = rows["start"]
assert start.difference.high < 0 and start.at_100 == 0, start
for key in ("short-steps", "start-0.60-0.80"):
    assert rows[key].difference.high < 0, rows[key]
for key in ("epsQ-0.05", "epsQ-0.2"):
    assert not rows[key].difference.excludes_zero(), rows[key]
assert rows["epsQ-0.05"].at_100 == rows["epsQ-0.05"].n_seeds
worse = [r for r in rows.values() if r.difference is not None and r.difference.high < 0]
for r in worse:
    assert r.rewarded_difference.high < 0, r
lines = [
    f"* {r.label}: test success {r.difference.format(unit=' pp')} against this "
    f"configuration; training trials rewarded {r.rewarded_difference.format(unit=' pp')}"
    for r in worse
] + [
    f"* {rows[key].label}: test success {rows[key].difference.format(unit=' pp')}"
    for key in ("epsQ-0.05", "epsQ-0.2")
]
display(Markdown("\n".join(lines)))

# %% [markdown]
# **Why, as we read it** (an explanation; its measured parts are printed below): training
# chooses actions by the softmax of Eq. 4 with $\beta^a = 2$ on Q-values that stay small, so
# no action is much more likely than another and training is close to a random walk; the
# greedy test policy ($\beta^a = 100$) is only as good as the ordering of Q-values that this
# walk teaches, and a walk that reaches the dock more often teaches it better. The rewarded
# column is the measured half of this: it is lower in every row that docks less.

# %%
spread = max(float(r.network.Q.max() - r.network.Q.min()) for r in results)
ratio = np.exp(config.network.beta_a_train * spread)
assert ratio < 10
print(
    f"final Q over the {len(results)} seeds: largest minus smallest weight {spread:.2f}, so in "
    f"training (beta_a = {config.network.beta_a_train:g}) no action is more than {ratio:.1f} "
    "times as likely as another, whatever the image"
)

# %% [markdown]
# ## Against the paper

# %%
table = md_table(PAPER_COLUMNS, experiment1_rows(results))
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
