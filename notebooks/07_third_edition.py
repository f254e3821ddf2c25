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
# # 07 — The study: the equal contest, and the editions before it
#
# **The current finding is the equal contest's** (this section). The paper's learner, linear
# SARSA (the same SARSA rule on the same pixels without a feature layer) and PPO (a deep-RL
# learner on the same pixels) are each selected in three worlds by **one procedure with the
# same number of runs**, then judged on 20 fresh seeds. The rules were committed before any of
# its runs (`docking/study/designs/equal_contest.py`, commit 319cc64; its record in `rules/`,
# held against the live code by `tests/test_records.py`):
#
# * **A common grid**, 9 x 5 points over each learner's two most influential knobs, every point
#   on the same two seeds (5900-5901): β_a in training (Eq. 4) from 1 to 500 by a 1-2-5 ladder,
#   against ε_W (Eq. 8) for the paper's learner and ε_Q (Eq. 7) for linear SARSA; PPO's
#   learning rate (1e-5 to 5e-3, 1-2-5) against its rollouts per update (8 to 128). The paper's
#   learner's third knob, ε_Q, is held at the value its earlier tuning chose in each world
#   (0.03, 0.03, 0.3): information from a longer search, which favours it.
# * **Extension**: three stages of five points for every learner, the unsearched lattice
#   neighbours of its best points in rank order (beyond the grid's edge where a best point
#   lies on it). A rung that cannot be a run is a limit, never searched: a learning rate above
#   1, fewer than one rollout, and (**amendment 1**, committed after one run was seen and before
#   any run it changes) linear SARSA's ε_Q above 2, where Eq. (7) on unit-length input (the
#   normalised LMS rule) diverges: its first run at ε_Q 3 stopped with Q about to overflow.
# * **Selection**: the three best *bracketed* points (every neighbour searched) on four fresh
#   seeds (6500-6503); the best there is the chosen setting. 132 selection runs per learner and
#   world, the same for each.
# * **Judgement**: each chosen setting on 20 fresh seeds (7200-7219), 500 held-out trials each.
#   Linear SARSA minus the paper's learner over matched seeds: the **lead** (two-sided
#   t-test, Holm over the three worlds), **non-inferiority** of the paper's learner at a 5 pp
#   margin (one-sided, at 0.025, Holm; what the earlier editions called the gap *closed*),
#   **equivalence** within ±5 pp (TOST at 0.05, Holm), and the failure ratio beside them.
#   PPO trains for 50,000 steps, the SARSA learners' allowance (2000 trials of at most 25
#   actions), which favours it; it is judged on the same seeds, without a verdict.
#
# The sections after it keep the study's history in order, each labelled where it is
# superseded: the third edition's contest (15 tuning runs per learner), its addendum and the
# bracketing (unequal searches), the replication.

# %%

import dataclasses
import importlib.util
import subprocess
import sys
from itertools import pairwise
from pathlib import Path

import numpy as np
from IPython.display import Image, Markdown, display

from docking.presets import NAO_WORLD
from docking.study import figures, provenance, report
from docking.study.claims import design_verdicts, judge_family, rate_interval
from docking.study.designs import addendum as ad
from docking.study.designs import addendum_report, bracketing_report, measures, third_edition_report
from docking.study.designs import third_edition as te
from docking.study.report import save_named
from docking.study.stats import rate_ci, t_mean_ci

pct = lambda ci: ci.format(unit="%")  # noqa: E731

# %% [markdown]
# ## The equal contest: the current finding
#
# Per world: each learner's held-out success at its chosen setting (mean over the 20 judged
# seeds), linear SARSA's lead over the paper's learner with its 95% interval, and the three
# tests by the committed rules.

# %% tags=["hide-input"]
from docking.study.designs import equal_contest as ec  # noqa: E402
from docking.study.designs import equal_contest_report as ecr  # noqa: E402

equal = ec.DESIGN.read()  # its runs read from the ledger, never computed
verdicts = ecr.verdicts(equal)
display(Markdown(ecr.verdict_table(equal)))
display(Markdown(provenance.deviations_table(ec.NAME)))
for v in verdicts.values():  # judged on 20 fresh seeds, matched across learners
    assert v["seeds"] == len(ec.SEEDS) >= 20
    assert v["low"] < v["lead"] < v["high"]
    if v["noninferiority"] == "non-inferior":  # at one world: the interval's upper end < 5 pp
        assert v["high"] < ec.MARGIN
fig = figures.fig_glance(*ecr.glance_data(equal, te.DESIGN.run(progress=False)))
display(Image(filename=str(save_named(fig, "equal_contest_glance"))))

# %% [markdown]
# **The same effort, counted from the runs.** Every learner spent the same selection runs in
# every world (grid, extension, selection), and no search stopped short: each chosen value
# lies inside what its search tried (the rungs on both sides of it were run), or at a limit of
# its knob (the rung beyond is not a valid configuration: a learning rate above 1, fewer than
# one rollout, linear SARSA's eps_Q above 2 by amendment 1) with the other side run; the
# sentence under the table names any value at a limit. The last column shows the selection's
# optimism: a chosen setting's success on the seeds that chose it, on the selection seeds,
# and on the fresh judged seeds.

# %% tags=["hide-input"]
display(Markdown(ecr.chosen_table(equal)))
spent = ecr.spent(equal)
assert len({(s["grid"], s["extension"], s["selection"]) for s in spent.values()}) == 1
runs = ec.SEARCH.runs_per_learner()
assert all(s["grid"] + s["extension"] + s["selection"] == runs for s in spent.values())
assert all(s["judged"] == len(ec.SEEDS) for s in spent.values())
bracketed = ecr.bracketing(equal)
assert all(how != "edge" for fields in bracketed.values() for how in fields.values())
print(ecr.limits_sentence(bracketed))

# %% [markdown]
# ## The fragility landscape, on the common grid
#
# How much of each learner's knobs' range docks well? Each panel draws every point the search
# ran on the two grid seeds (the 9 x 5 grid and the extension's points around it), coloured by
# its mean held-out success; the star is the chosen setting, the circle the published (or,
# for PPO, skrl's default) one. The counts are of the 45 grid points, the same points and
# seeds for every learner.

# %% tags=["hide-input"]
fig = figures.fig_landscape(*ecr.grid_panels(equal))
display(Image(filename=str(save_named(fig, "fragility_landscape"))))
fragile = ecr.fragility(equal)
display(Markdown(ecr.fragility_sentence(fragile) + "\n\n" + ecr.fragility_table(fragile)))
for f in fragile.values():
    assert f["points"] == ec.GRID_ROWS * ec.GRID_COLS and 1 <= f["near_best"] <= f["points"]

# %% [markdown]
# ## The replication (*superseded* by the equal contest above)
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
# committed rules; their runs came after the contest's (second half of this notebook).
#
# One label of the rules was corrected after the sideboard world's runs (an erratum, not a
# rule): the distractor-unseen claim's description named its difference with the wrong sign
# ("with a red cup minus without"; the statistic is without minus with). Its rule's margin is
# symmetric, so no decision can move; `tests/test_third_edition.py` checks that this label is
# the only difference from the committed digest.

# %% [markdown] tags=["fold"]
# ## The Nao-like world
#
# Its values, read from the world's configuration (`docking.presets.NAO_WORLD`), beside the
# sideboard world's:

# %% tags=["hide-input", "fold-output"]
side = te.WORLDS["sideboard"][1]
rows = [
    ("forward or backward step (m)", side.step_forward, NAO_WORLD.step_forward),
    ("sidestep (m)", side.step_side, NAO_WORLD.step_side),
    ("camera height (m)", "the asset's 0.48", NAO_WORLD.camera_height),
    ("camera tilt (deg down)", side.camera.tilt_deg, NAO_WORLD.camera.tilt_deg),
    ("vertical field of view (deg)", side.camera.fovy_deg, NAO_WORLD.camera.fovy_deg),
    ("scene", side.scene, NAO_WORLD.scene),
    (
        "docking region, across x deep (m)",
        f"{side.dock_width:g} x {side.dock_depth:g}",
        f"{NAO_WORLD.dock_width:g} x {NAO_WORLD.dock_depth:g}",
    ),
    ("actions per trial", side.max_steps, NAO_WORLD.max_steps),
]
display(Markdown(report.md_table(("quantity", "sideboard world", "Nao-like world"), rows)))
floor = te.WORLDS["floor"][1]
shared = [  # what the Nao-like world takes from the floor world, not from the sideboard world
    f.name
    for f in dataclasses.fields(NAO_WORLD)
    if getattr(NAO_WORLD, f.name) == getattr(floor, f.name) != getattr(side, f.name)
]
display(
    Markdown(
        "**Not independent of the floor world.** The Nao-like world shares with it, and not "
        f"with the sideboard world: {', '.join(shared)}. The floor scene (the landmark on the "
        "floor, seen whole, nothing stopping the robot at the dock) was chosen after the second "
        "edition had shown that it breaks the paper's learner; the Nao-like world's published "
        "values (steps, camera) came after, on that scene. Its results are a second world of the "
        "same kind, not an independent check.\n\n" + provenance.deviations_table(te.NAME)
    )
)
assert "scene" in shared

# %% [markdown]
# The rule fixed with the world: the pose oracle must dock at least 99% of held-out trials
# within the paper's 25 actions, else the trial grows to 30, 35 or 40 actions. The oracle's
# runs in it:

# %%
contest = te.DESIGN.run(progress=False)  # every cell of the edition, the contest's and the claims'
oracle = contest.score("nao/oracle")
print(
    f"pose oracle, Nao-like world, {NAO_WORLD.max_steps} actions: {pct(rate_interval(contest, 'nao/oracle'))} "
    f"per seed {np.round(100 * oracle, 1)}"
)
assert NAO_WORLD.max_steps == 25 and oracle.mean() >= 0.99  # 25 actions are enough

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
# *Superseded* by the addendum, the bracketing and the replication (the current finding, at
# the top of this notebook): the contest's tuning stopped at the edge of its grids.

# %% tags=["fold-output"]
# the third edition's gaps: linear SARSA and PPO minus the tuned paper's learner
gaps = report.contest_gaps(contest, te.CONTEST, te.GAP_CLOSED)
ppo_gaps = report.contest_gaps(contest, te.CONTEST, te.GAP_CLOSED, other="ppo-tuned")
display(Markdown(report.gaps_table(gaps + ppo_gaps)))

# %% [markdown] tags=["fold"]
# ## The intervals' coverage at the seed counts used
#
# Every interval this edition decides by, checked on synthetic studies like it (2000 each):
# seeds whose true success is drawn from a Beta distribution or, as larger feature learning
# rates gave, bimodal (seeds that learn and seeds that do not), each arm measured on 500
# held-out trials. `paired`: a paired difference (the claims, the contest's gaps, the path);
# `interaction`: the distractor's four arms; `share`: the delta method's share of failures
# removed (rotation). The equivalence rule decides by the paired interval too.

# %% tags=["hide-input", "fold-output"]
TOOLS = Path(te.__file__).resolve().parents[3] / "tools"  # scripts beside the package
spec = importlib.util.spec_from_file_location("checks", TOOLS / "interval_coverage.py")
checks = importlib.util.module_from_spec(spec)
spec.loader.exec_module(checks)
COVERAGE_KINDS = checks.COVERAGE_KINDS
counts = (5, 10, 20)
found = {
    (k, n, b): checks.rule_coverage(k, n, b, seed=n)
    for k in COVERAGE_KINDS
    for n in counts
    for b in (False, True)
}
columns = [(n, b) for n in counts for b in (False, True)]
rows = [(k, *(f"{100 * found[k, n, b]:.1f}%" for n, b in columns)) for k in COVERAGE_KINDS]
header = [f"n = {n}, {'bimodal' if b else 'Beta'}" for n, b in columns]
display(Markdown(report.md_table(("interval", *header), rows)))
assert all(0.93 <= v <= 0.97 for v in found.values())  # each within 2 points of 95%

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
        f"**{by_world[w].verdict}**; tuned PPO minus it: {by_ppo[w].interval.format(unit=' pp')}."
    )
display(Markdown("\n".join(lines)))

# %% [markdown]
# **The contest's finding (*superseded*: too strong, see the current finding at the top).**
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
# ### The gap, tuned to each learner's optimum (the first judgement; replicated at the top)

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
# ### What the addendum shows (its first judgement; the replication at the top supersedes it)
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
        f"{contest_by[w].interval.format(unit=' pp')}), the gap **{added_by[w].verdict}**."
    )
display(Markdown("\n".join(lines)))


# %% [markdown]
# ## The fragility landscape of the unequal searches (*superseded* by the common grid above)
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
# **A lead seen once.** In the Nao-like world, linear SARSA at ε_Q 0.3 (its tuned ε_Q is
# lower) docked above its tuned setting's replicated rate at several β_a, on the landscape's
# runs of the tuning seeds. A few runs on two seeds are a lead to test on fresh seeds, not a
# finding: it is reported here and used nowhere else.

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

# %% [markdown]
# ## The paper's claims: the verdicts
#
# Each claim quotes the paper with its section. Every comparison pairs two arms that share
# each seed's networks or held-out streams, by seed (Student-t over the per-seed
# differences). **The decision rule, committed before the runs:** Holm's adjustment within
# each claim over its comparisons (its worlds) at 0.05; a comparison is *supported* or
# *contradicted* when its adjusted p-value is below 0.05, on the side its interval lies, and
# *at the bound* when it is decided but the deciding end of its interval lies within 0.01 of
# the rule's bound in the statistic's units (1 pp of success; 0.01 of a correlation, a degree
# or an action). The reason: the claims are separate sentences of the paper, each a question of its
# own, and one family of every comparison would let the number of other questions decide
# each one. Beside it, one family of every comparison (Holm over all of them). Rotation is
# judged only where the paper's learner docks at least 80% (elsewhere its failures have
# other causes: *not judged*). The SOM and the non-local terms are **findings**: the paper
# says a SOM "could be used" and that the non-local terms were included "mostly because of
# the necessity when performing vanilla gradient descent"; neither sentence claims that one
# is better, so both are measured and shown, not judged. No row re-uses data seen before its
# rules: every run of this edition is on its own fresh seeds.

# %% [markdown] tags=["fold"]
# **How many seeds.** The seeds per row came from a power analysis on the second edition's
# effects and spreads, made before the rules were committed (`tools/power_third_edition.py`,
# which reads the archived second edition's verdict table): each comparison's per-seed
# spread as if its arms were unpaired (pairing by seed can only shrink it when the arms move
# together: the conservative choice), the effect it targets (its estimate, at least 5 pp) at
# Holm's strictest level within its claim, and the seeds at which the paired rule reaches
# 80% power. The budget gave 20 seeds to every learner cell, enough for every row of the
# sideboard world (asserted below); the floor world's rows need more, because its seeds
# differ so much, and its near-zero effects cannot be powered within the budget: there a
# verdict of "not supported" means "not shown", not "shown absent". The path's intermediate
# worlds got 10 seeds: the second edition measured their drops as large.

# %% tags=["hide-input", "fold-output"]
tool = TOOLS / "power_third_edition.py"
power = subprocess.run([sys.executable, tool], capture_output=True, text=True, check=True)
display(Markdown(power.stdout))
needed = {}  # (world, row) -> seeds for 80% power ("> 60": None)
for k, line in enumerate(power.stdout.splitlines()[2:]):
    cols = [c.strip() for c in line.strip("|").split("|")]
    needed[cols[1], k] = None if cols[6].startswith(">") else int(cols[6])
assert all(n is not None and n <= 20 for (w, _), n in needed.items() if w == "sideboard")
assert all(n is None or n >= 10 for n in needed.values()) and len(needed) >= 10

# %% tags=["fold-output"]
# the verdict table: every claim, comparison, interval and p-value
results = contest
per_claim = judge_family(te.CLAIMS, results, alpha=te.ALPHA, per_claim=True)
family = judge_family(te.CLAIMS, results, alpha=te.ALPHA)
display(Markdown(design_verdicts(results)))

# %% tags=["fold-output"]
# Read with care: tests that could not fail, choices made after results, rules before runs
display(Markdown(provenance.candour_text()))  # notebooks 08 and 09 test relocation and coping again

# %% tags=["fold-output"]
# the verdicts as a figure: each comparison's interval against its rule's bound
fig = figures.fig_verdicts(third_edition_report.verdict_panels(te.CLAIMS, results, per_claim))
display(Image(save_named(fig, "third_edition_verdicts")))

# %% [markdown]
# ## Interpretability, in Experiment 1 too
#
# Per network, each winning unit's weights correlated with the mean of the start views it
# wins (units that win at least 20 of 1500 views), averaged over its units: learned W against
# the same seed's random start (W frozen). Mean over seeds, 95% interval:

# %% tags=["hide-input"]
fid = {
    w: (te.fidelity(results, f"{w}/paper"), te.fidelity(results, f"{w}/frozen"))
    for w in ("experiment1", *te.VERDICT_WORLDS)
}
rows = [
    (w, len(a), t_mean_ci(a).format(scale=1.0, digits=3), t_mean_ci(b).format(scale=1.0, digits=3))
    for w, (a, b) in fid.items()
]
header = ("world", "seeds", "learned W", "W frozen (its random start)")
display(Markdown(report.md_table(header, rows)))

# %% [markdown]
# ## Turning: the paper's prediction, on accuracy and path length
#
# Six actions (turn left and right added), trained 4x as long as the four-action learner, in
# the sideboard world: over the held-out trials that docked, the |heading error| at docking
# and the actions per docking, beside held-out success.

# %% tags=["hide-input"]
turning = {
    k: (
        results.score(k),
        measures.heading_error_deg(results, k),
        measures.actions_per_docking(results, k),
    )
    for k in ("sideboard/paper", "sideboard/six-long")
}
rows = [
    (k, pct(rate_interval(results, k)), *(t_mean_ci(v).format(scale=1.0, digits=2) for v in (h, a)))
    for k, (s, h, a) in turning.items()
]
header = ("learner", "held-out success", "abs. heading error at docking (deg)")
display(Markdown(report.md_table((*header, "actions per docking"), rows)))

# %% [markdown]
# ## The path from the sideboard world to the floor world, one factor at a time
#
# The paper's learner (untuned) in each world, and its drop from one world to the next,
# paired by seed (10 seeds). A factor *breaks* the learner if Holm's p-value for "the drop
# exceeds 5 pp" (over the four steps; the two branches towards 8 cm steps a family of their
# own) is below 0.05; it *does not* if the drop's interval lies below 5 pp; else undecided.

# %% tags=["hide-input", "fold-output"]
# the path from the sideboard world to the floor world: each step's cost to each learner
what = {k: v[0] for k, v in te.WORLDS.items()}
steps = third_edition_report.path_steps(results, list(pairwise(te.PATH)), te.BREAK_DROP, te.ALPHA)
branches = third_edition_report.path_steps(results, te.BRANCHES, te.BREAK_DROP, te.ALPHA)
display(Markdown(third_edition_report.path_table(steps + branches, what)))
n = len(te.PATH_SEEDS)
print(
    {
        w: pct(
            rate_ci(
                results.score(f"{w}/paper")[:n],
                [len(log.success) for log in results.logs[f"{w}/paper"][:n]],
            )
        )
        for w in te.WORLDS
    }
)

# %% [markdown]
# ## What the verdicts show
#
# Each sentence below is computed from the runs; the asserts hold the decisions (Holm within
# each claim) and the path's, as the tables above show them.

# %% tags=["hide-input", "fold-output"]
decided = {(d.claim, d.world): d.verdict for d in per_claim}
S, C, NS, B, NJ = "supported", "contradicted", "not supported", "at the bound", "not judged"
assert decided == {
    ("features-success", "sideboard"): S,
    ("features-success", "floor"): S,
    ("features-interpretable", "experiment1"): S,
    ("features-interpretable", "sideboard"): B,
    ("features-interpretable", "floor"): NS,
    ("delta", "sideboard"): S,
    ("delta", "floor"): S,
    ("curriculum", "sideboard"): B,
    ("curriculum", "floor"): S,
    ("rotation-most", "sideboard, 2°"): C,
    ("rotation-most", "sideboard, 4°"): C,
    ("rotation-most", "sideboard, 6°"): NS,
    ("rotation-most", "floor, 2°"): NJ,
    ("rotation-compensated", "sideboard, 2°"): C,
    ("rotation-compensated", "sideboard, 4°"): C,
    ("rotation-compensated", "sideboard, 6°"): C,
    ("rotation-compensated", "floor, 2°"): NJ,
    ("turning-accuracy", "sideboard"): C,
    ("turning-path", "sideboard"): B,
    ("distractor-mechanism", "sideboard"): NS,
    ("distractor-mechanism", "floor"): NS,
    ("distractor-unseen", "sideboard"): C,
    ("distractor-unseen", "floor"): B,
}
assert [s.decision for s in steps] == ["breaks", "undecided", "undecided", "breaks"]
assert [s.decision for s in branches] == ["breaks", "breaks"]
ci = {(d.claim, d.world): d.interval for d in per_claim}
finding = {  # the findings' intervals (not judged)
    (c.key, w): c.interval(results, k)
    for c in te.CLAIMS
    if not c.judged
    for w, (k,) in c.cells.items()
}
pp = lambda i: i.format(unit=" pp")  # noqa: E731
share = lambda i: i.format(unit="%")  # noqa: E731
fi = {w: (a.mean(), b.mean()) for w, (a, b) in fid.items()}
lines = [
    f"* **Feature learning pays, and δ is what makes it pay.** Freezing W at its random start "
    f"costs {pp(ci['features-success', 'sideboard'])} in the sideboard world and "
    f"{pp(ci['features-success', 'floor'])} in the floor world; Eq. 8 with δ permuted across "
    f"the trial costs {pp(ci['delta', 'sideboard'])} and {pp(ci['delta', 'floor'])}.",
    f"* **Interpretable features: Experiment 1 yes, Experiment 2 no.** In Experiment 1 the "
    f"learned units look like the views they win (correlation {fi['experiment1'][0]:.2f}, "
    f"against {fi['experiment1'][1]:.2f} at their random start), as the paper's Fig. 3 shows; "
    f"in Experiment 2's worlds they do not ({fi['sideboard'][0]:.2f} against "
    f"{fi['sideboard'][1]:.2f} in the sideboard world, at the bound; {fi['floor'][0]:.2f} "
    f"against {fi['floor'][1]:.2f} in the floor world).",
    f"* **The curriculum** helps in the floor world ({pp(ci['curriculum', 'floor'])}); in the "
    f"sideboard world its gain is {pp(ci['curriculum', 'sideboard'])}, at the bound.",
    f"* **Rotation is not the reason for most failures.** Without heading noise, the same "
    f"networks lose {share(ci['rotation-most', 'sideboard, 2°'])} of their failures at the "
    f"paper's 2° (contradicted: the interval lies below half) and "
    f"{share(ci['rotation-most', 'sideboard, 4°'])} at 4°; a scripted heading hold removes "
    f"{share(ci['rotation-compensated', 'sideboard, 2°'])}, "
    f"{share(ci['rotation-compensated', 'sideboard, 4°'])} and "
    f"{share(ci['rotation-compensated', 'sideboard, 6°'])} at 2°, 4° and 6°. In the floor "
    f"world the learner docks too rarely for its failures to be judged.",
    f"* **Turning does not bring accuracy.** Six actions, trained four times as long, dock "
    f"{mean('sideboard/six-long'):.1f}% against {mean('sideboard/paper'):.1f}%, and where they "
    f"dock they face the landmark *less* well: four minus six actions' |heading error| is "
    f"{ci['turning-accuracy', 'sideboard'].format(scale=1.0, unit=' deg', digits=2)} "
    f"(contradicted); nor is their path shorter: four minus six actions per docking is "
    f"{ci['turning-path', 'sideboard'].format(scale=1.0, unit=' actions', digits=2)} (six take "
    f"more; at the bound).",
    f"* **Distractors do affect performance.** A red cup never seen in training costs the "
    f"paper's networks {pp(ci['distractor-unseen', 'sideboard'])} in the sideboard world "
    f"(contradicted: the interval lies wholly outside ±2 pp) and "
    f"{pp(ci['distractor-unseen', 'floor'])} in the floor world; that a cup in training costs "
    f"frozen W more than learned W is not shown "
    f"({pp(ci['distractor-mechanism', 'sideboard'])}, {pp(ci['distractor-mechanism', 'floor'])}).",
    f"* **Findings.** The SOM first, then SARSA, docks less often than the paper's network in "
    f"the sideboard world ({pp(finding['som', 'sideboard'])}) and is not distinguishable in the "
    f"floor world ({pp(finding['som', 'floor'])}); the local rule is behind the paper's in the "
    f"sideboard world ({pp(finding['nonlocal', 'sideboard'])}) but far ahead in the floor world "
    f"({pp(finding['nonlocal', 'floor'])}: the paper's rule minus the local rule).",
    f"* **The path.** Two factors break the learner: the landmark on the floor seen from a "
    f"camera 30° down ({pp(steps[0].drop)}) and the ±20° start wedge ({pp(steps[3].drop)}); the "
    f"8 cm dock and the 5 cm sidesteps are undecided; 8 cm steps break it in both worlds "
    f"({pp(branches[0].drop)} and {pp(branches[1].drop)}).",
]
display(Markdown("\n".join(lines)))
assert fi["experiment1"][0] > 0.4 > fi["sideboard"][0] and finding["nonlocal", "floor"].high < 0
assert ci["rotation-most", "sideboard, 2°"].high < te.ROTATION_SHARE
