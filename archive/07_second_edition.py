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
# # 07 — The study, second edition: verdicts that measure the claims, not our worlds
#
# The first edition (notebook 05) was read by a referee: in the sideboard world a one-line
# pixel rule, linear SARSA and an off-the-shelf PPO all beat the paper's learner; the floor
# world changed six things at once; several rules tested something narrower than the claim.
# This edition measures every world before any learner, walks from one world to the other
# one factor at a time, and re-states each verdict.
#
# **Its rules were committed before any of its runs**: `docking/designs/second_edition.py`
# (commit 2371ece; the pixel-level bound's cells added in 344fd9a, before any PPO run), pinned
# by a digest in `tests/test_second_edition.py`, so a rule changed after the runs fails the
# tests. What this notebook asserts of the runs was written after them; where it adds an
# analysis the rules do not name, it says so.
#
# Every learner cell runs **10 seeds** (the yardsticks and PPO 5); every network or policy is
# judged greedily on **500 held-out trials** from random streams that training never uses.

# %%
import numpy as np
from IPython.display import Image, Markdown, display

from docking import analysis, claims, figures, stats
from docking.designs import second_edition as se
from docking.experiments import initial_network
from docking.report import save_named

# %% [markdown]
# ## The intervals: their coverage at ten seeds, checked first
#
# Synthetic seeds like the study's (each seed's true success drawn from a Beta, measured on
# 500 binomial trials; two groups of ten, a true difference of 5 pp): how often does a 95%
# interval cover the truth? The first edition's percentile bootstrap against Student-t
# (Welch), this edition's choice (400 synthetic studies per row).

# %%
SETTINGS = ((0.85, 0.08), (0.95, 0.03), (0.5, 0.15))
coverage = {
    (mean, spread, method): stats.coverage(method, mean=mean, spread=spread, repeats=400)
    for mean, spread in SETTINGS
    for method in ("t", "percentile")
}
display(
    Markdown(
        "| true mean, s.d. over seeds | Welch t | percentile bootstrap |\n|---|---|---|\n"
        + "\n".join(
            f"| {m:.2f}, {sd:.2f} | {coverage[m, sd, 't']:.3f} | "
            f"{coverage[m, sd, 'percentile']:.3f} |"
            for m, sd in SETTINGS
        )
    )
)
# The choice rests on this: t covers within Monte Carlo error of 0.95 (+-0.022 at 400
# repeats); the bootstrap under-covers.
assert all(coverage[m, sd, "t"] >= 0.92 for m, sd in SETTINGS)
assert all(coverage[m, sd, "percentile"] < coverage[m, sd, "t"] for m, sd in SETTINGS)

# %% [markdown]
# ## The runs
#
# `python -m docking design run second-edition` from a terminal (a Dask cluster with
# `--scheduler`); here they are loaded from the results store or the committed ledger.

# %%
results = se.DESIGN.run()
worlds = [key for key, *_ in se.PATH]
mean = {c.key: float(np.mean(results.score(c.key))) for c in results.cells}

# %% [markdown]
# ## How hard is each world? The yardsticks, before any learner
#
# Held-out success (mean and 95% Student-t interval over seeds) of the pose-reading oracle
# (the motor task's bound: it reads the robot's pose, not the pixels), PPO on the 320 pixels
# (the pixel-level bound: skrl's PPO, the paper's budget of 2000 trials x 25 steps, 5 seeds),
# linear SARSA on the pixels, the paper's learner, the one-line centroid rule, always-forward
# and random actions, in every world of the path (what each world changes: the second
# column; each from the row above it, the last two from the sideboard and the floor world).

# %%
display(Markdown(se.world_table(results)))

# %% [markdown]
# What the table shows, each statement asserted below:
#
# * Every world but one is solvable to at least 99%: the oracle docks that often. The
#   exception is the floor world with 8 cm steps: there the oracle docks in about 95% of
#   trials, and **every one of its failures runs out of the 25 actions** a trial allows (the
#   paper's limit, kept in every world). The oracle is a scripted policy, not an optimal one:
#   PPO, taking shorter paths, docks more often than it there. So that world's bound is the
#   action limit, and it is solvable to at least PPO's success.
# * **The pixels suffice in every world**: PPO, a generic learner from a maintained library,
#   reaches at least 90% from the same 320 pixels within the paper's budget, in every world
#   of the path and both branches.
# * Linear SARSA on the raw pixels (no feature layer) does better than the paper's learner in
#   every world; in the floor world by more than 40 pp.
# * In the floor world the paper's learner docks less often than the one-line centroid rule.

# %%
assert all(mean[f"{w}/oracle"] >= 0.99 for w in worlds if w != "floor-step8")
assert mean["floor-step8/oracle"] < min(0.99, mean["floor-step8/ppo"])
limit = results.cell("floor-step8/oracle").world.max_steps
for log in results.logs["floor-step8/oracle"]:
    failed = ~np.asarray(log.success)
    assert failed.any() and np.all(np.asarray(log.steps)[failed] == limit)
assert all(mean[f"{w}/ppo"] >= se.PIXELS_SUFFICE for w in worlds)
assert all(mean[f"{w}/linear"] > mean[f"{w}/paper"] for w in worlds)
assert mean["floor/linear"] - mean["floor/paper"] > 0.40
assert mean["floor/paper"] < mean["floor/centroid"]

# %% [markdown]
# ## The path: which factor breaks the paper's learner?
#
# The rule (fixed before the runs): a factor *breaks* the learner if its drop from the
# previous world (Welch's t, Holm over the path's four steps) is significant at 0.05 and
# larger than 5 pp; *the pixels suffice* in a world where the pixel-level bound (PPO)
# reaches 90%. The two branches to 8 cm steps are judged the same way, as a family of their
# own (an analysis added after the runs: the rules name the path's steps, not the branches).

# %%
steps = se.path_steps(results)
branches = se.path_steps(results, se.BRANCHES)
display(Markdown(se.path_table(steps + branches)))
fig = figures.fig_path(
    [se.PATH_LABELS[w] for w in worlds],
    {
        label: [results.score(f"{w}/{name}") for w in worlds]
        for name, label in se.WORLD_COLUMNS
        if name in ("oracle", "ppo", "linear", "paper", "centroid")
    },
    se.PIXELS_SUFFICE,
    branches=len(worlds) - len(se.MAIN_PATH),
)
display(Image(save_named(fig, "second_edition_path")))

# %% [markdown]
# **The finding** (asserted below): no single factor breaks the paper's learner; it loses
# at nearly every step while the pixels suffice throughout. By the rule, three of the path's
# four factors break it: the landmark on the floor seen by a tilted camera without the
# sideboard's funnel (the largest drop, about 30 pp), the narrower dock, and the start
# wedge; the 5 cm sidesteps cost it about 5 pp, not decided after Holm. Nao-like 8 cm steps
# break it in both branches (more than 40 pp in the sideboard world). Linear SARSA, which
# loses far less along the path, stays ahead of the paper's learner at every step; PPO docks in at least 95% of trials in
# every world.

# %%
assert [s.breaks for s in steps] == [True, True, False, True]
assert [s.breaks for s in branches] == [True, True]
assert all(s.pixels_suffice for s in steps + branches)
assert steps[0].drop.estimate == max(s.drop.estimate for s in steps) > 0.25
assert branches[0].drop.estimate > 0.40  # 8 cm steps in the sideboard world
assert min(mean[f"{w}/ppo"] for w in worlds) > 0.95

# %% [markdown]
# ## The verdicts, one family
#
# Every judged comparison's 95% Student-t interval (unadjusted), its p-value against the
# rule's bound, and Holm's adjustment over all of them at 0.05: a comparison is decided
# (*supported* or *contradicted*, by its side of the bound) only if its Holm-adjusted
# p-value is below 0.05, so an interval that excludes the bound can still be *not
# supported*; a decided comparison whose deciding interval end lies within 1 pp of the bound
# is reported *at the bound*. Differences are the paper's configuration minus the variant
# (percentage points of held-out success), the rotation rows the share of the paper's
# networks' failures that go, interpretability a difference of mean correlations.

# %%
decisions = claims.judge_family(se.CLAIMS, results, alpha=se.ALPHA)
verdicts = claims.family_verdicts(se.CLAIMS, decisions)
display(Markdown(claims.family_table(se.CLAIMS, decisions)))
decided = {(d.claim, d.world): d.verdict for d in decisions}

# %% [markdown]
# The verdicts in words (asserted below):
#
# * **Features, success**: learning W helps where the sideboard funnels the robot (supported
#   there), not in the floor world (not supported).
# * **Features, interpretable**: not supported in either world at the paper's eps_W; the
#   learned units are barely more like what they respond to than random ones (the finding
#   below shows what a larger eps_W does).
# * **Delta** (a permuted delta) and the **alternative** (a SOM first): in the sideboard world
#   the paper's rule is ahead by 5.6 and 9.1 pp with 95% intervals that exclude 0, but not
#   after Holm's correction over the family's 25 comparisons: *not supported*, which is not
#   *contradicted*; ten seeds are too few to decide them with family-wise control. In the
#   floor world the SOM learner is ahead of the paper's (an interval below 0, not decided
#   after Holm).
# * **Curriculum** (growing against none): not supported in either world.
# * **Rotation**: heading noise is not the reason for most failures. Removing it removes
#   about a fifth to a quarter of the paper's networks' failures in the sideboard world
#   (every interval ends below 50%; not supported), under 5% in the floor world
#   (contradicted); a scripted heading hold, the compensation the paper names, removes 11% at
#   2 deg (contradicted) and about a third at 4 and 6 deg (not supported).
# * **Turning learned**: the six-action learner, trained four times as long, stays 17.6 pp
#   below the four-action one (contradicted).
# * **Distractor, the mechanism** (a cup present in training costs frozen W more than
#   learned W): in the sideboard world 6.7 pp in the claim's direction, not decided after
#   Holm; in the floor world no difference. **Distractor, out of distribution** (a cup never
#   seen in training): it costs the paper's networks more than the 2 pp margin in the
#   sideboard world (contradicted), undecided in the floor world.
# * **Non-local terms** "needed for the harder task": in the floor world, the harder task,
#   the local rule does 25 pp *better* (contradicted); in the sideboard world no difference.

# %%
per_world = {claim: found[1] for claim, found in verdicts.items()}
S, N, C = claims.SUPPORTED, claims.NOT_SUPPORTED, claims.CONTRADICTED
assert per_world == {
    "features-success": {"sideboard": S, "floor": N},
    "features-interpretable": {"sideboard": N, "floor": N},
    "delta": {"sideboard": N, "floor": N},
    "curriculum": {"sideboard": N, "floor": N},
    "rotation-most": {
        "sideboard, 2 deg": N,
        "sideboard, 4 deg": N,
        "sideboard, 6 deg": N,
        "floor, 2 deg": C,
    },
    "rotation-compensated": {
        "sideboard, 2 deg": C,
        "sideboard, 4 deg": N,
        "sideboard, 6 deg": N,
        "floor, 2 deg": C,
    },
    "turning-learned": {"sideboard": C},
    "distractor-mechanism": {"sideboard": N, "floor": N},
    "distractor-unseen": {"sideboard": C, "floor": N},
    "alternative": {"sideboard": N, "floor": N},
    "nonlocal": {"sideboard": N, "floor": C},
}, per_world
interval = {(d.claim, d.world): d.interval for d in decisions}
# Delta and the SOM: intervals above 0 before Holm, not decided after it.
for claim in ("delta", "alternative"):
    assert interval[claim, "sideboard"].low > 0 and decided[claim, "sideboard"] == N
assert interval["alternative", "floor"].high < 0  # the SOM ahead in the floor world
assert all(interval["rotation-most", w].high < 0.5 for w in per_world["rotation-most"])
assert interval["nonlocal", "floor"].high < -0.15
assert len(decisions) == 25

# %% [markdown]
# ## Findings (reported, not verdicts)
#
# Comparisons the rules report with their numbers but do not judge (outside the family):
# training only near the dock (never growing the region), interpretability at larger feature
# learning rates, the two-stage learner with plain competitive learning, and linear SARSA.

# %%
display(Markdown(se.findings_table(results)))
finding = {
    (c.key, w): c.interval(results, e)
    for c in se.CLAIMS
    if not c.judged
    for w, entries in c.cells.items()
    for e in entries
}

# %% [markdown]
# What the findings show (asserted below): training only near the dock and never growing the
# region does better on the full region than the paper's growing curriculum in the floor
# world (a finding about that world, not a test of the paper's procedure; in the sideboard
# world its interval ends within 1 pp of 0: at the bound, not asserted); plain competitive
# learning first is far behind the paper's rule in the sideboard world and far ahead of it in
# the floor world; linear SARSA on the raw pixels is ahead in both; and a larger feature
# learning rate makes the features measurably more interpretable, a hundred times the
# paper's eps_W by far the most.

# %%
assert finding["near-only", "floor"].high < -0.05
assert finding["competitive", "sideboard"].low > 0 > finding["competitive", "floor"].high
assert all(finding["linear", w].high < 0 for w in ("sideboard", "floor"))
x10, x100 = (finding["interpretable-larger-epsW", f"sideboard, eps_W x{k}"] for k in (10, 100))
assert 0 < x10.low and x10.high < x100.low

# %% [markdown]
# ## Fig. 4 again: are the features recognisable at any feature learning rate?
#
# The interpretability measure, per seed: for every feature unit that wins at least 20 of the
# views of the network's first 100 held-out trials, the correlation of its weights with the
# mean view it wins, averaged over those units. The paper's eps_W, ten and a hundred times
# it, and W frozen at its random start (the sideboard world); then Fig. 4 redrawn from the
# setting that measures most interpretable, beside its own random start (panel C).

# %%
settings = {
    "W frozen (random start)": "sideboard/frozen",
    "the paper's eps_W": "sideboard/paper",
    "eps_W x10": "sideboard/epsW-x10",
    "eps_W x100": "sideboard/epsW-x100",
}
fidelity = {label: se.fidelity(results, key) for label, key in settings.items()}
success = {label: results.score(key) for label, key in settings.items()}
display(
    Markdown(
        "| setting | interpretability (mean correlation, 95% interval) | held-out success |\n"
        "|---|---|---|\n"
        + "\n".join(
            f"| {label} | {stats.t_mean_ci(fidelity[label]).format(scale=1, digits=3)} | "
            f"{stats.t_mean_ci(success[label]).format(unit='%')} |"
            for label in settings
        )
    )
)
best = max(list(settings)[1:], key=lambda label: np.mean(fidelity[label]))
run = results.runs[settings[best]][0]
net, shape = run.network, run.config.world.camera.input_shape
action_rf, feature_rf = analysis.receptive_fields(net, shape)
start = initial_network(run.config, run.seed)  # the same run's W at its random start
fig = figures.fig4(
    run.config,
    run.seed,
    action_rf,
    feature_rf,
    analysis.mean_winning_inputs(net, run.config.world, n=1500),
    analysis.strongest_units(net.Q),
    initial_rf=analysis.receptive_fields(start, shape)[1],
)
display(Image(save_named(fig, "second_edition_fig4")))

# %% [markdown]
# **Recognisable only at a hundred times the paper's eps_W** (asserted below). At the
# paper's rate the learned units are scarcely more like what they respond to than random ones
# (the features row of the verdicts; notebook 04's Fig. 4, whose units look like their random
# start), and ten times the rate adds little. At a hundred times, most units that win views
# carry a dark blob where the landmark lies in the views they win (block A against block
# C): features a reader can recognise. The price is success: at that rate the learner docks
# far less often than at the paper's.

# %%
assert best == "eps_W x100"
assert stats.t_mean_ci(fidelity["eps_W x100"]).low > stats.t_mean_ci(fidelity["eps_W x10"]).high
assert np.mean(success["eps_W x100"]) < np.mean(success["the paper's eps_W"]) - 0.15

# %% [markdown]
# ## Sample efficiency: training trials to 90% greedy success
#
# The rule's measure for the learners with a learning curve: per seed, the training trials
# at the first curve point (50 greedy trials from the full region every 100 training trials)
# at or above 90%. PPO has no such curve; beside it, with a measure of its own: the training
# episodes until 50 consecutive ones succeed at 90% (its exploring policy, not greedy).

# %%
efficiency = se.efficiency(results)
display(Markdown(se.efficiency_table(efficiency)))

# %% [markdown]
# The paper's learner reaches 90% on its learning curve only in the two sideboard worlds,
# within 200 training trials; in no floor world, in any seed, within its 2000 trials. Linear
# SARSA reaches it in every world but the floor world with 8 cm steps; PPO (by its own
# measure) in every world, in every seed (asserted).

# %%
reached = {key: int(np.sum(~np.isnan(t))) for key, t in efficiency.items()}
floor_worlds = ("floor-view", "dock", "sidestep", "floor", "floor-step8")
assert all(reached[w, "paper"] == 0 for w in floor_worlds)
assert np.nanmax(efficiency["sideboard", "paper"]) <= 200
assert all(reached[w, "linear"] == 10 for w in worlds if w not in ("floor", "floor-step8"))
assert all(reached[w, "ppo"] == len(se.PPO_SEEDS) for w in worlds)

# %% [markdown]
# With 8 cm steps in the sideboard world the paper's learner *unlearns*: its greedy success
# from the full region peaks within the first 400 trials, while its training region is still
# small, and falls as the region grows (asserted: the peak above 80%, the last quarter of
# its curve below 65%). Seen after the runs; the rules do not name it.

# %%
step8 = np.mean([r.curve_success for r in results.runs["sideboard-step8/paper"]], axis=0)
q8 = len(step8) // 4
print(
    f"sideboard world, 8 cm steps: peak {100 * step8[: q8 + 1].max():.0f}% in the first "
    f"quarter, last quarter {100 * step8[-q8:].mean():.1f}%"
)
assert step8[: q8 + 1].max() > 0.80 and step8[-q8:].mean() < 0.65

# %% [markdown]
# ## Does the six-action learner's curve flatten?
#
# The rotation family's "this learner learns turning" row trains the six-action learner
# four times as long as the paper's (8000 trials, its curriculum stretched in proportion).
# Flat, by the rule: the mean of its learning curve's last quarter within 2 pp of its third
# quarter's.

# %%
six = results.runs["sideboard/six-long"]
flat = analysis.curve_flatness(six)
trials = six[0].curve_trials
curve = np.mean([r.curve_success for r in six], axis=0)
q = len(curve) // 4
print(
    f"last quarter minus third quarter of its curve: {100 * flat:.2f} pp (the rule: flat "
    f"within {100 * se.FLAT_PP:.0f} pp); its peak {100 * curve.max():.0f}% at trial "
    f"{trials[curve.argmax()]:.0f}, its last quarter {100 * curve[-q:].mean():.1f}% (greedy, "
    "the full region, mean over seeds)"
)

# %% [markdown]
# The six-action learner's greedy success from the full region peaks early, while its
# training region is still small, and *falls* as the region grows; over its last two
# quarters it changes by about 2 pp, at the rule's bound, so whether it is "flat" is reported
# at the bound, not asserted. Either way, four times the training does not bring it near
# the four-action learner (the turning row above). Asserted: the early peak above 90% and
# the last quarter below 88%.

# %%
assert curve[: len(curve) // 4].max() > 0.90
assert curve[-q:].mean() < 0.88

# %% [markdown]
# ## What this edition shows
#
# Measured against yardsticks in every world, the paper's learner is not the bottleneck of
# the pixels: a generic deep-RL learner (PPO) and linear SARSA on the same 32x10 input dock
# more often in every world, and in the floor worlds mostly reach 90% in training where the
# paper's learner never does. Of the paper's claims, judged as one family with Holm's
# correction at ten seeds: learning the features helps success where the sideboard funnels
# the robot; the features become recognisable only at a hundred times the paper's learning
# rate, at a cost in success; the non-local terms are contradicted in the harder world;
# that rotation causes most failures is nowhere supported and in the floor world
# contradicted, and a scripted compensation removes a minority of them; the six-action
# learner does not learn turning in four times the training. Delta's modulation, the SOM alternative, the curriculum and the distractor
# mechanism are not decided by these runs: the directions of the first two agree with the
# paper in the sideboard world, but not after the family-wise correction.
