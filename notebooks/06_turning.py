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
# # 06 — Experiment 3, beyond the paper: turning and precision docking
#
# The paper blames its failures on rotation: the movement noise "can lead to a rotation of the
# robot, which currently is not compensated, as no rotation movements are implemented. This
# is actually the reason for most of the unsuccessful trials" (Sec. III). It ends with its
# next step: "a real-world precision approach including turning of Nao" (Sec. IV). No public
# implementation of that step exists; this notebook builds it on the same world, network and
# machinery, and asks two questions:
#
# 1. **Does turning remove the failures the paper blames on rotation?** The learner gets two
#    more actions, turn-left and turn-right (a rotation in place by 10°, with every step's
#    noise), and one more action unit for each.
# 2. **What does precision docking need?** Docked only if, besides the reference point being
#    in the region, the heading is within ±10° of facing the landmark. Without turns a
#    robot whose heading drifted cannot dock.
#
# Experiment 3 is Experiment 2 (same world, network, curriculum, 2000 training trials) in a
# grid: four or six actions × the paper's task or precision docking × heading noise 2° (the
# world's default), 4° and 6° per step. Each cell trains **10 seeds**; each network is judged
# on **500 held-out trials** (the study's streams, the archived notebook 05). The cell "4 actions, paper
# task, 2°" *is* the study's paper configuration (the same runs). Why 4° and 6°, not larger:
# below, the oracle.

# %%

import numpy as np
from IPython.display import Image, Markdown, display

from docking.policies import centroid_offset, oracle, run_episode
from docking.study import analysis, arrays, figures, report
from docking.study.arrays import FAILURE_CLASSES
from docking.study.designs import design, experiment3, experiment3_report
from docking.study.report import save_named
from docking.study.stats import difference_ci
from docking.world import DockingEnv

pct = lambda ci: ci.format(unit="%")  # noqa: E731
pp = lambda ci: ci.format(unit=" pp")  # noqa: E731

# %% [markdown]
# ## The turn and precision docking
#
# A turn is a step of length 0 that rotates the robot by `turn_deg` (10°) about its reference
# point; the same three noise draws as any step displace its target (1 cm per body axis, the
# cell's heading noise). With precision docking the dock's detector, checked at every physics
# step, also asks `|heading_error(pose)| <= 10°`, where the heading error is the heading minus
# the bearing from the reference point to the landmark's centre
# (`docking.world.heading_error`). One oracle trial of the hardest cell, from above:

# %% tags=["hide-input"]
hardest = next(c for c in experiment3.experiment3_cells() if c.key == "6 actions, precision, 6 deg")
env = DockingEnv(hardest.config.world, seed=7)
episode = next(e for e in (run_episode(env, oracle) for _ in range(50)) if 4 in e.actions)
letters = hardest.config.world.action_letters
print("actions:", " ".join(letters[a] for a in episode.actions), "| docked:", episode.success)
display(
    Image(
        save_named(
            figures.fig_trial(
                env.config,
                analysis.floor_plan(env.config),
                episode.poses,
                "oracle, 6 actions, precision, 6°",
            ),
            "experiment3_oracle_trial",
        )
    )
)

# %% [markdown]
# ## The oracle: which cells are solvable?
#
# Before any learner is judged in a cell, the pose-reading oracle must dock in at least 99%
# of its held-out trials from the whole 1.5 m start region: a yardstick run per cell
# (`experiment3.ORACLE`, `python -m docking design run experiment3-oracle`), 5 seeds × 500
# trials on the held-out starts of the learners' first five seeds. With six actions it turns
# towards the landmark whenever its heading is off by more than one turn (and, with precision
# docking, when it stands in the region with the heading outside the tolerance); with four it
# cannot turn. The noise levels were fixed from the oracle alone, before any learner ran (then
# from 1000 trials of one seed): at 8° per step (the suggestion) the six-action oracle
# docked in only about 98% of trials.

# %%
oracle_rates = experiment3_report.oracle_rates(design("experiment3-oracle").run())
rates = [(key, f"{100 * rate:.1f}%") for key, rate in oracle_rates.items()]
display(Markdown(report.md_table(("cell", "oracle success"), rates)))
grid = {c.key: c for c in experiment3.experiment3_cells()}
six = {k: v for k, v in oracle_rates.items() if grid[k]["actions"] == "turning"}
four = {k: v for k, v in oracle_rates.items() if grid[k]["actions"] == "paper"}
assert min(six.values()) >= 0.99, six  # every six-action configuration is solvable
# without turns, precision docking at the largest noise is not solvable even for the oracle
assert four["4 actions, precision, 6 deg"] < 0.95 < six["6 actions, precision, 6 deg"]

# %% [markdown]
# ## Run (or load) the grid
#
# One sweep on the embedded Dask cluster (`python -m docking design run experiment3` from a terminal);
# stored runs are loaded.

# %%
results = design("experiment3").run()
runs = [r for key in results.runs for r in results.runs[key]]
print(
    f"{len(results.cells)} cells x {len(results.runs[results.cells[0].key])} seeds; "
    f"training and held-out trials took {sum(r.wall_time_train + r.wall_time_test for r in runs) / 60:.0f} min "
    "of compute (summed over runs)"
)

# %% [markdown]
# ## Four against six actions
#
# Per task and heading noise: the oracle's bound with four and six actions, the learners'
# held-out success (mean over seeds, 95% interval), six minus four, and the share of the
# four-action learner's failures that are gone with six actions.

# %% tags=["hide-input"]
comparisons = experiment3_report.turning_comparisons(results)
display(Markdown(experiment3_report.turning_table(comparisons, oracle_rates)))
found = {(c.task, c.noise): c for c in comparisons}

tasks, noise = list(experiment3.TASKS), np.array(experiment3.NOISE_DEG)
labels = {"paper": "4 actions", "turning": "6 actions"}
series, seeds, bounds = {}, {}, {}
for actions, label in labels.items():
    keys = [[experiment3.cell_key(actions, t, n) for n in noise] for t in tasks]
    side = "four" if actions == "paper" else "six"
    series[label] = np.array(
        [
            [
                [
                    getattr(found[t, n], side).estimate,
                    getattr(found[t, n], side).low,
                    getattr(found[t, n], side).high,
                ]
                for n in noise
            ]
            for t in tasks
        ]
    )
    seeds[label] = np.array([[results.score(k) for k in row] for row in keys])
    bounds[label] = np.array([[oracle_rates[k] for k in row] for row in keys])
fig = figures.fig_experiment3(noise, tasks, series, seeds, bounds)
display(Image(save_named(fig, "experiment3")))

# %% [markdown]
# **Six actions do worse than four in every cell**, in the paper's task and with precision
# docking, at every heading noise: each "6 minus 4" interval lies below 0 (asserted). The
# oracle shows that this is not the task's doing: with turns it docks in at least 99.8% of
# trials everywhere, and with precision docking at 6° it is the *four*-action oracle that
# cannot (80%). The learner with turns stays far below its bound, and below the four-action
# learner even where the four-action learner's own bound is lower.

# %%
assert all(c.gain.high < 0 for c in found.values()), [c.gain for c in found.values()]
hard = found["precision", 6.0]
assert hard.six.high < oracle_rates["4 actions, precision, 6 deg"] < 0.9

# %% [markdown]
# ## The paper's rotation claim, judged by the remedy it names
#
# If uncorrected rotation were "the reason for most of the unsuccessful trials", a learner
# that can turn should lose most of those failures. The rule, fixed before the runs: in the
# paper's task at the world's 2° heading noise, the share of the four-action learner's
# held-out failures that are gone with six actions is **supported** if its 95% interval lies
# above 50%, **contradicted** if below, **not supported** otherwise. (Notebook 05 judged the
# same claim by removing the heading noise at test instead.)

# %%
verdict, removed = experiment3_report.rotation_verdict(comparisons, experiment3.ROTATION_RULE)
base = found["paper task", 2.0]
display(
    Markdown(
        f"**{verdict}**: with turns the failures do not go, they multiply: six actions fail "
        f"{base.failure_ratio.format(1.0, ' times', 2)} as often as four (held-out success "
        f"{pct(base.four)} with four actions, {pct(base.six)} with six; six minus four "
        f"{pp(base.gain)})."
    )
)
assert verdict == "contradicted" and removed.high < 0

# %% [markdown]
# Is it training time? Six actions are a larger problem for a near-random explorer
# ($\beta^a = 2$): a third of its draws are turns. `python -m docking design run experiment3 --full`
# also trains the six-action learner of the paper's task at 2° twice as long (4000 trials,
# the curriculum stretched in proportion). It is not part of this notebook's runs: with it
# the computation from a fresh clone would no longer fit the CI's 90 minutes.

# %% [markdown]
# ## Where the failures go: the failure taxonomy of every cell
#
# The study's taxonomy (the archived notebook 05, `docking.study.arrays.FAILURE_CLASSES`) of every cell's
# held-out failures, its first five seeds pooled (`experiment3.TAXONOMY_SEEDS`: the ledger
# keeps their failures' paths); a trial can be in several classes. "Heading off in
# region" exists only with precision docking: the reference point reached the region, but the
# heading was outside the tolerance there. Heading drift is measured against facing the
# landmark's wall (yaw 0), so with six actions it includes the robot's own turns.

# %% tags=["hide-input"]
keys = [c.key for c in results.cells]
n_taxonomy = len(experiment3.TAXONOMY_SEEDS)
shares, failures = analysis.failure_shares(results, keys, n_taxonomy)
classes = list(FAILURE_CLASSES)
display(
    Image(
        save_named(
            figures.fig_failure_matrix(keys, classes, shares, failures),
            "experiment3_failures",
        )
    )
)
share = {(k, c): shares[i, j] for i, k in enumerate(keys) for j, c in enumerate(classes)}

# %% [markdown]
# With six actions nearly every failure has turned more than 10° away from the landmark's
# wall, and the failures end turned farther than the four-action learner's; and training is
# rewarded less often (the near-random walk of training spends its actions on turns). Per
# pair of cells, asserted below: the six-action cell's failures are heading-drift failures in
# at least 95% of cases; their median final |yaw| exceeds the four-action cell's; the share of
# rewarded training trials, six minus four, has an interval below 0.

# %% tags=["hide-input"]
lines = []
for c in found.values():
    k4 = experiment3.cell_key("paper", c.task, c.noise)
    k6 = experiment3.cell_key("turning", c.task, c.noise)
    yaw4 = np.median(experiment3_report.final_headings(results, k4, n_taxonomy))
    yaw6 = np.median(experiment3_report.final_headings(results, k6, n_taxonomy))
    rewarded = difference_ci(
        arrays.rewarded_share(results.runs[k6]), arrays.rewarded_share(results.runs[k4])
    )
    drift = f"{100 * share[k4, 'heading_drift']:.0f}% / {100 * share[k6, 'heading_drift']:.0f}%"
    trained = [100 * arrays.rewarded_share(results.runs[k]).mean() for k in (k4, k6)]
    lines.append(
        (c.task, f"{c.noise:g}", drift, f"{yaw4:.1f} / {yaw6:.1f}")
        + (f"{trained[0]:.1f}% / {trained[1]:.1f}%", pp(rewarded))
    )
    assert share[k6, "heading_drift"] >= 0.95 and yaw6 > yaw4 and rewarded.high < 0
header = ("task", "noise (deg)", "failures with heading drift, 4 / 6")
header += ("median final yaw of the failures (deg), 4 / 6", "training trials rewarded, 4 / 6")
display(Markdown(report.md_table(header + ("rewarded, 6 minus 4",), lines)))
# %% [markdown]
# ## What the six action units read
#
# Fig. 3/4 style for one network with turns (the headline seed 0 of six actions with
# precision docking at 2°): above, each action unit's receptive field
# $\sum_j Q_{ij} W_j$; below, the mean input of the views on which it is the greedy action,
# over every pose of the network's 500 held-out trials (re-rendered from the logged poses).

# %% tags=["hide-input"]
headline = results.runs["6 actions, precision, 2 deg"][0]
world = headline.config.world
action_rf, _ = arrays.receptive_fields(headline.network, world.camera.input_shape)
inputs = analysis.mean_winning_inputs(headline.network, world, poses=headline.heldout.poses)
fig = figures.fig_action_fields(
    list(world.action_letters),
    action_rf,
    inputs.action_mean,
    inputs.action_counts,
    f"six action units, {headline.config.name} seed {headline.seed} (precision, 2°)",
)
display(Image(save_named(fig, "experiment3_action_fields")))
turns = [world.action_index("turn-left"), world.action_index("turn-right")]
turn_share = inputs.action_counts[turns].sum() / inputs.action_counts.sum()
print(
    "greedy actions over the held-out poses: "
    + ", ".join(
        f"{letter} {n}"
        for letter, n in zip(world.action_letters, inputs.action_counts, strict=True)
    )
    + f" (turns {100 * turn_share:.1f}%)"
)

# %% [markdown]
# The bottom row says what the network reads as "turn": **turn-left when the landmark lies
# left of the image's centre, turn-right when it lies right** (the centroids of the mean
# inputs, asserted below) — the same cue that drives the sidesteps L and R. From one 32x10
# view a landmark off to one side looks much the same whether the robot stands beside the
# approach axis (a sidestep is right) or is turned away from it (a turn is right); the
# landmark's shape changes with the viewing angle only a little at this resolution. The
# learner resolves the ambiguity towards turning in a share of the views, turns itself away
# from the wall's normal, and then steps diagonally, loses the landmark or ends beside the
# dock (the taxonomy above). The receptive fields $\sum_j Q_{ij} W_j$ in the top row show no
# landmark structure, as in Experiment 2 (notebook 04): W stays close to its random start.

# %%
centroid = dict(zip(world.action_letters, centroid_offset(inputs.action_mean), strict=True))
print("; ".join(f"{k}: {float(v):.1f}" for k, v in centroid.items()))
assert centroid["TL"] < 0 < centroid["TR"] and turn_share > 0.1

# %% [markdown]
# ## What this says about the paper
#
# * The paper's remedy for its failures, turning, does not help this learner: with the
#   same network, rule and training budget, adding turn-left and turn-right *lowers* held-out
#   success in every cell, also where turning is necessary (precision docking at larger
#   noise, where the four-action oracle fails and the six-action oracle does not).
# * So rotation is not shown to be "the reason for most of the unsuccessful trials" by its
#   remedy either; the archived notebook 05 found the same by removing the noise.
# * Precision docking with turning is solvable (the oracle) but not learned well here. What
#   it would take is the paper's own future work; candidates the runs point to: inputs that
#   tell an offset from a rotation (the whole frame, or several frames), or exploration that
#   does not spend a third of its draws on turns.
#
# Compute: the table above cost the summed training and test time printed under "Run";
# `python -m docking design run experiment3` runs the whole grid on the embedded Dask cluster.
