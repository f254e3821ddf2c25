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
# # 05 — What makes it learn: the paper's claims, tested
#
# Notebooks 03 and 04 reproduce the paper's numbers. This notebook asks which of the paper's
# *claims* hold. Each claim is stated in the paper's words, tested by variants of its
# experiments (`docking.study`: the variants are data), and given a verdict computed from
# the runs by a rule fixed before they ran:
#
# * **supported**: the 95% bootstrap interval lies on the claim's side of its bound;
# * **contradicted**: it lies on the other side;
# * **not supported**: the interval straddles the bound — the runs do not show it.
#
# Every cell runs **10 seeds**; every network is judged on **500 held-out trials** whose
# start poses, step noise and action draws come from random streams that training, the
# learning curve and the main test never use. Intervals are 95% percentile bootstraps over
# seeds (`scipy.stats.bootstrap`); differences resample the seeds of each cell separately.
# Test-only variants (a red cup, no heading noise) judge the paper configuration's networks
# in another world on the held-out streams of the same seeds, so those comparisons are paired
# by seed (the same network). They are not paired trial by trial: one world generator draws
# both the start poses and every step's noise, so after the first trial the starts differ as
# soon as a trial ends sooner or later.
#
# Two worlds. The **sideboard world** of notebooks 02–04, where the sideboard's front funnels
# the robot into the dock; and a **floor world**, closer to the paper's scene and harder to
# game: the landmark stands on the floor, nothing stops the robot at the dock, the camera
# looks 30° down so the landmark's image moves vertically with distance. The floor world was
# calibrated on the yardsticks only (oracle ≥ 99%, always-forward ≤ 15%), never on a learner.
#
# The verdicts come first; the evidence follows.
#
# **A second edition** (notebook 07) re-states these verdicts by rules committed before its
# runs: yardsticks and a pixel-level bound (PPO) in every world, the path from the sideboard
# world to the floor world one factor at a time, rules that test the paper's words rather
# than a narrower question, Student-t intervals and Holm's correction over the family. This
# notebook stays the first edition, its rules unchanged.

# %%

import numpy as np
from IPython.display import Image, Markdown, display

from docking import analysis, figures, study
from docking.experiments import initial_network
from docking.presets import EXPERIMENT_2, FLOOR_WORLD
from docking.report import save_named
from docking.stats import mean_ci
from docking.world import DockingEnv

results = study.run_study()
cells = {c.key: c for c in results.cells}
diff = {k: study.difference(results, k) for k, c in cells.items() if c.baseline}
pp = lambda ci: ci.format(unit=" pp")  # noqa: E731  difference in percentage points
pct = lambda ci: ci.format(unit="%")  # noqa: E731

# %% [markdown]
# ## The verdicts

# %%
display(Markdown(study.verdict_table(results)))
verdicts = {claim: found[0] for claim, found in study.verdicts(results).items()}
# What these runs show; the notebook fails if a rerun shows otherwise.
assert verdicts == {
    "features": "supported only in the sideboard world",
    "delta": "supported",
    "curriculum": "contradicted",
    "rotation": "contradicted",
    "distractor": "contradicted",
    "alternative": "supported",
}, verdicts

# %% [markdown]
# How each verdict is decided (the differences are the paper's configuration minus the
# variant, in percentage points of held-out success):

# %%
display(Markdown("\n".join(f"* **{c.key}**: {c.test}." for c in study.CLAIMS)))

# %% [markdown]
# ## Yardsticks: what the worlds give away
#
# Before any learner: the pose-reading oracle (the bound), a one-line pixel rule (step towards
# the side of the image where the red is, forward when centred), always-forward and random
# actions, in both worlds: yardstick runs (`study.YARDSTICKS`, `python -m docking design run
# study-yardsticks`), 5 seeds × 500 held-out trials on the held-out starts of the learners'
# first five seeds. A world in which always-forward docks often cannot tell learners apart.

# %%
found = study.YARDSTICKS.run()
yardsticks = {(c["world"], c["policy"]): float(np.mean(found.score(c.key))) for c in found.cells}
display(
    Markdown(
        "| policy | sideboard world | floor world |\n|---|---|---|\n"
        + "\n".join(
            f"| {label} | {100 * yardsticks['sideboard', name]:.1f}% | "
            f"{100 * yardsticks['floor', name]:.1f}% |"
            for name, label in study.YARDSTICK_LABELS.items()
        )
    )
)
assert yardsticks["sideboard", "oracle"] >= 0.99 and yardsticks["floor", "oracle"] >= 0.99
assert yardsticks["floor", "forward"] <= 0.15  # the floor world's calibration bound
assert yardsticks["sideboard", "forward"] > 3 * yardsticks["floor", "forward"]

# %% [markdown]
# The floor world (with the red cup of the distractor cells beside the landmark), Fig. 2
# style: the robot at the dock, its camera (the crop dotted), the input; the views from the
# left, the front and the right.

# %%
floor_env = DockingEnv(cells["floor/cup-test"].test_world, seed=0)
# The robot 0.9 m from the landmark, 0.25 m to its left, in front of it, 0.25 m to its right.
poses = {"left": (-0.9, 0.25, 0.0), "front": (-0.9, 0.0, 0.0), "right": (-0.9, -0.25, 0.0)}
views = analysis.example_views(floor_env, poses)
fig = figures.fig2_scene(FLOOR_WORLD.camera, views, analysis.overview(floor_env, views.poses[1]))
display(Image(save_named(fig, "study_floor_world")))

# %% [markdown]
# ## All cells
#
# Held-out success of every cell (A: mean, interval, one dot per seed) and its baseline minus
# the cell (B; the sign of the verdict table: positive where the baseline does better). The
# baseline is the paper's configuration in the same world and experiment, or for "W frozen,
# tested with a red cup" W frozen. Red where the rule of the cell's claim decides the
# comparison (for the rules above 0: where the interval excludes 0); shaded, behind the rows
# whose rule has one, the ±2 pp margin of "does not affect performance".

# %%
order = list(cells)
groups = {k: f"{c['world']} world, {c['experiment']}" for k, c in cells.items()}
order = sorted(order, key=lambda k: list(dict.fromkeys(groups.values())).index(groups[k]))
# A row is drawn red where the rule of its cell's claim decides its comparison (supported or
# contradicted), grey where it does not: the claim objects' rules, not the figure's own.
claims = {c.key: c for c in study.CLAIMS}
decided = [
    k in diff
    and claims[cells[k].claim].rule.decide(claims[cells[k].claim].interval(results, k))
    != "not supported"
    for k in order
]
success = {k: mean_ci(results.success(k)) for k in order}
nan3 = [np.nan] * 3
fig = figures.fig_forest(
    labels=[cells[k].label for k in order],
    groups=[groups[k] for k in order],
    seeds=[results.success(k) for k in order],
    success=np.array([[s.estimate, s.low, s.high] for s in (success[k] for k in order)]),
    difference=np.array(
        [[(d := diff[k]).estimate, d.low, d.high] if k in diff else nan3 for k in order]
    ),
    margins=[
        getattr(claims[cells[k].claim].rule, "margin", None) if k in diff else None for k in order
    ],
    decided=decided,
)
display(Image(save_named(fig, "study_forest")))
display(
    Markdown(
        "| cell | held-out success | its baseline minus the cell |\n|---|---|---|\n"
        + "\n".join(
            f"| {cells[k].label} ({k}) | {pct(success[k])} | "
            f"{pp(diff[k]) if k in diff else '(baseline)'} |"
            for k in order
        )
    )
)
assert all(len(results.success(k)) >= 10 for k in order)
assert all(len(log) >= 500 for logs in results.heldout.values() for log in logs)

# %% [markdown]
# ## Claim 1 — feature learning matters
#
# The paper's networks against the same networks with W frozen at its random start
# (eps_W = 0), and the local rule; Experiment 1 too. *What* did W learn? The cosine between
# W before and after training (notebook 04) says little: at β_s = 100 a tiny change of W
# moves the boundaries between units. The measure here is the share of 500 start views whose
# winning unit (and whose greedy action) differs between W at the start and at the end of
# training, with the final Q reading both.

# %%
views_sideboard = analysis.start_views(EXPERIMENT_2.world, 500, seed=2024)
views_floor = analysis.start_views(FLOOR_WORLD, 500, seed=2024)
changes = {}
for key, views_k in (("paper", views_sideboard), ("floor/paper", views_floor)):
    pairs = [
        analysis.winner_change(initial_network(r.config, r.seed), r.network, views_k)
        for r in results.runs[key]
    ]
    changes[key] = (mean_ci([p[0] for p in pairs]), mean_ci([p[1] for p in pairs]))
    print(
        f"{key}: winner differs for {pct(changes[key][0])} of start views, "
        f"greedy action for {pct(changes[key][1])}"
    )
for key in ("frozen", "local", "floor/frozen", "floor/local", "exp1/frozen", "exp1/nonlocal"):
    print(f"paper minus '{cells[key].label}' ({key}): {pp(diff[key])}")
assert all(changes[k][0].low > 0.05 for k in changes)  # W's small move redraws the winners
assert diff["frozen"].low > 0  # freezing W costs success in the sideboard world ...
assert diff["floor/frozen"].low < 0 < diff["floor/frozen"].high  # ... not detectably on the floor
assert diff["floor/local"].high < 0  # where the local rule does far better than the paper's

# %%
headline = results.runs["paper"][0]
start = initial_network(headline.config, headline.seed)
fig = figures.fig_weight_change(
    start.W,
    headline.network.W,
    headline.config.world.camera.input_shape,
    f"Experiment 2, seed {headline.seed}: where each feature unit's weights changed in 2000 trials",
)
display(Image(save_named(fig, "study_weight_change")))

# %% [markdown]
# ## Claim 2 — it is the TD error that trains the features
#
# The control keeps Eq. (8) but replaces δ by a constant equal to the mean |δ| of the paper
# configuration's training steps: plain competitive Hebbian feature learning alongside SARSA.

# %%
constant = cells["constant-delta"].config.network.feature_delta
print(f"constant = mean |delta| of the paper configuration's training = {constant:.4f}")
print(f"paper minus constant: {pp(diff['constant-delta'])}")

# %% [markdown]
# ## Claim 3 — Learning from Easy Missions makes Experiment 2 learnable
#
# The paper's growing start region against no curriculum (the full region from the first
# trial) and against training only near the dock (never growing), tested on the full region.
# The curves are greedy success on the full region during training (50 trials every 100).

# %%
fig = figures.fig_study_curves(
    {
        f"{world} world": {
            c.label: analysis.learning_curves(results.runs[c.key])
            for variant in ("paper", "none", "near-only")
            for c in results.where(world=world, experiment="Experiment 2", variant=variant)
        }
        for world in ("sideboard", "floor")
    }
)
display(Image(save_named(fig, "study_curriculum")))
for key in ("none", "near-only", "floor/none", "floor/near-only"):
    print(f"paper minus '{cells[key].label}' ({key}): {pp(diff[key])}")
# Growing beats no curriculum in the sideboard world, but never growing beats growing in both.
assert diff["none"].low > 0 and diff["near-only"].high < 0 and diff["floor/near-only"].high < 0

# %% [markdown]
# ## Claim 4 — most failures come from uncorrected rotation
#
# The paper's networks run the same held-out trials without heading noise: the share of
# failures that disappear. And a taxonomy of the failures from the logged poses and actions
# (`docking.analysis.FAILURE_CLASSES`; a trial can be in several classes).

# %%
taxonomy_cells = ["paper", "no-yaw-noise", "floor/paper", "floor/no-yaw-noise"]
shares, counts = [], []
for key in taxonomy_cells:
    env = DockingEnv(cells[key].test_world or cells[key].config.world, seed=0)
    flags = [
        analysis.failure_taxonomy(log, env, trials=np.flatnonzero(~log.success))
        for log in results.heldout[key]
    ]
    failed = np.concatenate([~log.success for log in results.heldout[key]])
    counts.append(int(failed.sum()))
    shares.append(
        [
            np.concatenate([f[c] for f in flags])[failed].mean() if failed.any() else 0.0
            for c in analysis.FAILURE_CLASSES
        ]
    )
fig = figures.fig_failures(
    [f"{cells[k]['world']} world: {cells[k].label}" for k in taxonomy_cells],
    list(analysis.FAILURE_CLASSES),
    np.array(shares),
    counts,
)
display(Image(save_named(fig, "study_failures")))
for key in ("no-yaw-noise", "floor/no-yaw-noise"):
    print(f"{key}: {study.rotation_share(results, key).format(unit='%')} of the failures go")
# Without heading noise most failures remain: rotation is not their main cause here.
assert all(
    study.rotation_share(results, k).high < 0.5 for k in ("no-yaw-noise", "floor/no-yaw-noise")
)

# %% [markdown]
# ## Claim 5 — other red objects do not affect performance
#
# A red cup (7 cm across, 9 cm high) 0.3 m to the landmark's left: at test only (the paper
# configuration's networks, paired trials), and in training and test.

# %%
for key in ("cup-test", "cup", "floor/cup-test"):
    print(f"paper minus '{cells[key].label}': {pp(diff[key])}")
print(f"W frozen minus 'W frozen, tested with a red cup': {pp(diff['cup-test-frozen'])}")
# The cup costs success in both worlds, with learned and with frozen features.
assert (
    diff["cup-test"].low > 0 and diff["floor/cup-test"].low > 0 and diff["cup-test-frozen"].low > 0
)

# %% [markdown]
# ## Claim 6 — the united architecture against the alternative the paper names
#
# A two-stage learner (features first by winner-take-all competitive learning on the frames
# of 200 random-walk trials, then SARSA with W frozen), and a linear SARSA on the raw 320
# pixels with no feature layer at all.

# %%
for key in ("two-stage", "linear"):
    print(f"{cells[key].label:55s} {pct(success[key])}; paper minus it: {pp(diff[key])}")
# The united architecture beats the two-stage learner, but a linear SARSA on the pixels,
# with no feature layer at all, beats the paper's network in the sideboard world.
assert diff["two-stage"].low > 0 and diff["linear"].high < 0

# %% [markdown]
# ## The second world and the paper's 95%
#
# In the floor world the paper's configuration stays far below the paper's 95% and below the
# one-line pixel rule. This is reported, not tuned away: the world was calibrated on the
# yardsticks before any learner ran.

# %%
print(
    f"floor world, the paper's configuration: {pct(success['floor/paper'])}; "
    f"centroid rule {100 * yardsticks['floor', 'centroid']:.1f}%"
)
assert success["floor/paper"].high < 0.95
assert success["floor/paper"].high < yardsticks["floor", "centroid"]
