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
# # 04 — Experiment 2: 36 feature units, the non-local rule, Learning from Easy Missions (Figs. 4, 5)
#
# **The paper's claim** (Sec. III): "the possible initialization region of the robot is
# gradually increased" until it spans 1.5 m; with 36 feature units and the non-local rule
# (Eq. 8 with the bracket, "mostly because of the necessity when performing vanilla gradient
# descent"), "after training (2000 trials, ≈ 2 days) it is able to reach the goal position in
# 95 % of the cases (690 out of 725 trials)". The receptive fields (Fig. 4) "are not clearly
# reflecting the shape of the landmark anymore"; several feature units now contribute to one
# action ("population coding"). Most failures come from uncorrected rotation of the robot
# (Fig. 5).
#
# This notebook runs the experiment for several seeds, regenerates Figs. 4 and 5 and the
# learning curves of both experiments from the saved runs, and sets the numbers beside the
# paper's. Saved runs in `results/` are re-used.

# %%
import numpy as np
from IPython.display import Image, Markdown, display

from docking.experiments import initial_network
from docking.presets import EXPERIMENT_1, EXPERIMENT_2
from docking.study.analysis import (
    failure_taxonomy,
    feature_change,
    floor_plan,
    mean_winning_inputs,
    start_fields,
    start_views,
)
from docking.study.arrays import FAILURE_CLASSES, rewarded_share, winner_change
from docking.study.designs import calibration, design
from docking.study.designs.calibration_report import (
    calibration_rows,
    calibration_table,
    computing_time,
)
from docking.study.designs.paper_report import (
    PAPER_COLUMNS,
    experiment2_rows,
    headline,
    save_fig4,
    save_fig5,
    save_learning_curves,
)
from docking.study.figures import FIGURES_DIR
from docking.study.report import configuration_table, md_table
from docking.study.stats import difference_ci
from docking.world import ACTION_LETTERS, DockingEnv

config = EXPERIMENT_2

# %% [markdown]
# ## The configuration
#
# Read from `docking.presets.EXPERIMENT_2`; everything not named as the paper's is ours.

# %% tags=["fold-output"]
display(Markdown(configuration_table(config)))

# %% [markdown]
# ## Run (or load)

# %%
experiments = design("paper").run()  # Experiments 1 and 2, the seeds of docking.presets.SEEDS
results = experiments.runs[config.name]
main = headline(results)
for r in results:
    print(
        f"seed {r.seed}: test {r.test_successes}/{len(r.test.success)} docked "
        f"({100 * r.test.success_rate:.1f}%), training {r.wall_time_train:.0f} s, "
        f"testing {r.wall_time_test:.0f} s"
    )

# %% [markdown]
# ## Learning curves of both experiments
#
# Success of greedy test trials from the *full* start region while training proceeds, and
# the start region's far edge (the curriculum). Experiment 1's runs are loaded (or run, a few
# seconds) for the left column.

# %%
results1 = experiments.runs[EXPERIMENT_1.name]
save_learning_curves(results1, results)  # arrays.learning_curves -> figure -> save
display(Image(filename=str(FIGURES_DIR / "learning_curves.png")))

# %% [markdown]
# Measured against the paper's story, one thing stands out: greedy success on the *full*
# 1.5 m region is already high after the first 100 training trials, when the robot has only
# started close to the dock (the numbers below, asserted: at least 90% on average, from a far
# edge within 0.8 m). The law it learns close by (centre the landmark in the image, then walk
# forward) carries to far starts, where the landmark is smaller but in the same place; the
# curriculum's later stages mostly keep it from degrading rather than teach it (the archived notebook 05
# tested the curriculum claim with ten seeds).

# %%
early = np.array([r.curve_success[list(r.curve_trials).index(100)] for r in results])
early_far = config.curriculum.far_at(100, config.world.start_far)
print(
    f"after 100 training trials (far edge {early_far:.2f} m): greedy success on the full "
    f"region {100 * early.mean():.1f}% on average (seeds: "
    + ", ".join(f"{100 * x:.0f}%" for x in early)
    + ")"
)
assert early.mean() >= 0.9 and early_far < 0.8

# %% [markdown]
# ## Fig. 4: receptive fields of the action and feature units

# %%
inputs = mean_winning_inputs(main.network, main.config.world, n=1500)  # over rendered start views
save_fig4(main, inputs, start_fields(main))  # receptive fields -> figures.fig4 -> save
display(Image(filename=str(FIGURES_DIR / "fig4_experiment2.png")))

# %% [markdown]
# **What the feature layer learned — a finding that differs from the paper.** With the
# paper's $\beta^s = 100$ the softmax of Eq. 2 has a clear winner for almost every image, and
# the non-local update $\delta\, s_j I_n (Q_{ij} - \sum_k Q_{ik} s_k)$ vanishes at a clear
# winner (Sec. II-B; notebook 01 shows it). So in our runs the feature weights hardly move
# from their random start:

# %% tags=["hide-input"]
for r in results:
    change = feature_change(r)
    print(
        f"seed {r.seed}: cosine between initial and final W_j: min {change.min():.3f}, "
        f"median {np.median(change):.3f}; {len(np.unique(r.test.winners))} of "
        f"{config.network.n_features} units win test decisions"
    )
print(
    "Experiment 1 (local rule), headline seed: median cosine "
    f"{np.median(feature_change(headline(results1))):.2f}"
)

# %% [markdown]
# A cosine this close to 1 does **not** make the units a fixed random partition of image
# space, as an earlier version of this notebook said. At $\beta^s = 100$ the winner of Eq. 2
# is decided by small differences of $h_j$, so a tiny move of $W$ shifts the boundaries
# between the units' territories. The measure that matters is how many inputs change their
# winning unit: over 500 start views, the share whose winner differs between $W$ at the start
# and at the end of training, and the share whose greedy action differs (the final $Q$
# reading the features of either $W$):

# %%
views = start_views(config.world, 500, seed=2024)
moved = np.array(
    [winner_change(initial_network(r.config, r.seed), r.network, views) for r in results]
)
for r, (winners, actions) in zip(results, moved, strict=True):
    print(
        f"seed {r.seed}: winner differs for {100 * winners:.1f}% of start views, "
        f"greedy action for {100 * actions:.1f}%"
    )
assert moved[:, 0].min() > 0.05  # the partition moved, in every seed

# %% [markdown]
# So learning $W$ redraws the partition for a sizeable share of views, and changes some
# decisions. Whether that matters for success is a question for an ablation, not for a
# cosine: the archived notebook 05 (archive/05_what_matters.py) runs the same configuration with $W$ frozen at its random start
# ($\epsilon_W = 0$), ten seeds each, and gives the verdict with its confidence interval.
# The weights themselves (left half of Fig. 4) show no landmark structure, where the paper's
# Fig. 4 shows faint landmark shapes. What the units respond to is shown in the right half:
# the mean input over 1500 start views for which each action is chosen and each unit wins.
# There the sensorimotor law is plain: the landmark left in the image means step left,
# centred means forward, right means step right; several units feed each action, the
# "population coding" of the paper.
#
# ## Fig. 5: sample test trajectories

# %%
save_fig5(main, floor_plan(main.config.world))  # arrays.trajectory_sample -> figures.fig5 -> save
display(Image(filename=str(FIGURES_DIR / "fig5_trajectories.png")))

# %% [markdown]
# **Why trials fail.** Each failed test trial of every seed, classified from its logged poses
# and actions by `docking.study.analysis.failure_taxonomy` (a trial can fall in several classes):

# %% tags=["hide-input", "fold-output"]
env = DockingEnv(config.world, seed=0)
flags = [failure_taxonomy(r.test, env, trials=np.flatnonzero(~r.test.success)) for r in results]
failed = [~r.test.success for r in results]
n_failed = int(sum(f.sum() for f in failed))
rows = [
    (name, int(sum(np.sum(fl[name] & f) for fl, f in zip(flags, failed, strict=True))), text)
    for name, text in FAILURE_CLASSES.items()
]
shares = [(n, c, f"{100 * c / max(n_failed, 1):.0f}%", t) for n, c, t in rows]
display(Markdown(f"{n_failed} failed test trials over {len(results)} seeds"))
display(Markdown(md_table(("class", "failures", "share", "definition"), shares)))

# %%
actions = np.bincount(main.test.actions, minlength=4) / len(main.test.actions)
print(
    "test action frequencies: "
    + ", ".join(f"{ACTION_LETTERS[i]} {100 * a:.0f}%" for i, a in enumerate(actions))
)

# %% [markdown]
# ## What the choices do
#
# Each row below changes one choice of this configuration (8 cm forward steps instead of
# 15 cm; $\epsilon_Q$ 0.03 and 0.2; $\epsilon_W$ 20 times larger) and runs it for the same
# seeds, paired with the runs above (the same initial weights and random streams), each
# network tested greedily on 725 trials from the full region; the bold row *is* the runs
# above, and $\epsilon_W$ is this configuration's unless a row names it. `docking.study.designs.calibration`
# defines the rows and says why these ($\epsilon_W = 0$ is the archived notebook 05's, with ten seeds).
# Intervals are 95% bootstrap intervals over seeds; the difference to this configuration
# resamples each row's seeds independently. "Training trials rewarded" is the share of the
# 2000 training trials that ended in the dock.

# %% tags=["fold-output"]
calib = design(f"calibration-{config.name}").run(full=True)
rows = {r.key: r for r in calibration_rows(calib, calibration.BASELINE)}
display(Markdown(calibration_table(list(rows.values()), calibration.BASELINE)))
print(
    f"computing time of the {len(rows) - 1} variants: {computing_time(calib, calibration.BASELINE):.0f} s"
)

# %% [markdown]
# What the table shows (each statement is asserted below, from these runs):
#
# * **The step length decides it**: test success with 15 cm forward steps minus with 8 cm has
#   a 95% interval above 0.
# * **No learning rate tried makes a difference five seeds resolve**: for $\epsilon_Q$ 0.03
#   and 0.2, and for $\epsilon_W$ 20 times larger, the interval of the difference to this
#   configuration contains 0. (An
#   earlier, hand-typed version of this table had $\epsilon_Q = 0.03$ clearly below this
#   configuration; with five seeds these runs cannot tell it apart.)
# * **With 8 cm steps most of the loss is in the far starts**: the interval of the difference
#   in test success for trials that start beyond 1 m lies wholly below the interval for
#   nearer starts.
# * **With 8 cm steps training is rewarded less often, and from beyond 1 m hardly at all**:
#   the differences in the share of rewarded training trials, over all trials and over those
#   that start beyond 1 m, lie below 0.

# %% tags=["hide-input"]
short = calib.runs["8cm-steps"]
paper = calib.runs[calibration.BASELINE]


def by_start(runs, far: bool) -> np.ndarray:
    """Per seed, the test success of the trials that start beyond 1 m (or within)."""
    out = []
    for r in runs:
        beyond = -r.test.starts[:, 0] > 1.0
        out.append(r.test.success[beyond if far else ~beyond].mean())
    return np.array(out)


step_gain = rows["8cm-steps"].difference.negated()  # 15 cm minus 8 cm
assert step_gain.low > 0, step_gain
for key in ("epsQ-0.03", "epsQ-0.2", "epsW-1"):
    assert not rows[key].difference.excludes_zero(), rows[key]
far_loss = difference_ci(by_start(short, True), by_start(paper, True))
near_loss = difference_ci(by_start(short, False), by_start(paper, False))
assert far_loss.high < near_loss.low, (far_loss, near_loss)
rewarded_far = difference_ci(rewarded_share(short, 1.0), rewarded_share(paper, 1.0))
assert rows["8cm-steps"].rewarded_difference.high < 0 and rewarded_far.high < 0
lines = [f"* test success, 15 cm minus 8 cm forward steps: {step_gain.format(unit=' pp')}"]
lines += [
    f"* {rows[key].label}: {rows[key].difference.format(unit=' pp')} against this configuration"
    for key in ("epsQ-0.03", "epsQ-0.2", "epsW-1")
]
lines += [
    f"* 8 cm minus 15 cm steps, test success from beyond 1 m: {far_loss.format(unit=' pp')}; "
    f"from within 1 m: {near_loss.format(unit=' pp')}",
    "* training trials rewarded, 8 cm steps: "
    f"{rows['8cm-steps'].rewarded.format(unit='%')} of all (15 cm: "
    f"{rows[calibration.BASELINE].rewarded.format(unit='%')}); of those starting beyond 1 m "
    f"{rewarded_share(short, 1.0).mean():.1%} (15 cm: "
    f"{rewarded_share(paper, 1.0).mean():.1%}), difference "
    f"{rewarded_far.format(unit=' pp')}",
]
display(Markdown("\n".join(lines)))

# %% [markdown]
# **Why, as we read it** (an explanation; its measured parts are printed above and below):
# training chooses actions by the softmax of Eq. 4 with $\beta^a = 2$ on Q-values of order
# 1, so it explores broadly, and from the far edge of the region a short-stepped robot needs
# many forward moves in a row out of its action budget, which such a walk rarely produces:
# far starts are almost never rewarded, their states keep small values whose ordering the
# greedy test ($\beta^a = 100$) cannot rely on, and the test walk from there wanders. With
# 15 cm steps the walk reaches the dock from far often enough that the values, and the greedy
# policy, carry out to 1.5 m.

# %% tags=["hide-input"]
spread = max(float(r.network.Q.max() - r.network.Q.min()) for r in paper)
world = config.world
dock_edge = world.dock_center + world.dock_depth / 2
for row in ("8cm-steps", calibration.BASELINE):
    step = calib.cell(row).config.world.step_forward
    moves = int(np.ceil((world.start_far - dock_edge) / step))
    print(
        f"{100 * step:.0f} cm forward steps: {moves} forward moves from the region's far edge "
        f"({world.start_far:g} m) to the dock, of {world.max_steps} actions"
    )
print(
    f"final Q of this configuration: largest minus smallest weight {spread:.2f}; in training "
    f"(beta_a = {config.network.beta_a_train:g}) no action is more than "
    f"{np.exp(config.network.beta_a_train * spread):.1f} times as likely as another"
)

# %% [markdown]
# ## Against the paper

# %%
display(Markdown(md_table(PAPER_COLUMNS, experiment2_rows(results))))

# %%
rates = np.array([r.test.success_rate for r in results])
assert len(main.test.success) == 725
assert main.test.success_rate >= 0.95, f"headline seed: {main.test.success_rate:.3f} < 0.95"
print(
    f"Experiment 2 reproduces the paper's 95%: headline {main.test_successes}/725; "
    f"mean over {len(results)} seeds {100 * rates.mean():.1f}% (min {100 * rates.min():.1f}%)."
)
