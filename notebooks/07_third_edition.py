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
# # 07 — The study: the equal contest, and the paper's claims
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
# After it: the third edition's worlds and its verdicts on the paper's claims (current). The
# analyses the equal contest supersedes (the third edition's contest with 15 tuning runs per
# learner, its addendum and the bracketing, the replication: searches that were not alike)
# are notebook 10, the study's history, each labelled where it is superseded.

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
from docking.study.designs import measures, third_edition_report
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
# ## The third edition: its worlds, and the paper's claims
#
# The paper's claims were judged by the study's third edition, on fresh seeds (3000-3019; 10
# for the path's intermediate worlds), by rules committed before any of its runs
# (`docking/study/designs/third_edition.py`, commit 396630d; its record,
# `rules/third-edition.json.gz`, is held against the live code by `tests/test_records.py`).
# Its three worlds are the equal contest's: the sideboard world (the one the package's
# choices were calibrated in), the floor world (the landmark on the floor, the camera 30°
# down, a dock 8 cm across), and the **Nao-like world**, fixed from Nao's published
# specifications before any run (the site's guide "The Nao-like world",
# `docs/guide/nao_world.md`, gives each value's source). The same edition's contest of tuned
# learners (15 tuning runs each) is superseded: notebook 10.
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

# %% [markdown] tags=["fold"]
# ## The intervals' coverage at the seed counts used
#
# Every interval the third edition decides by, checked on synthetic studies like it (2000 each):
# seeds whose true success is drawn from a Beta distribution or, as larger feature learning
# rates gave, bimodal (seeds that learn and seeds that do not), each arm measured on 500
# held-out trials. `paired`: a paired difference (the claims, the contest's gaps, the path; the equal contest's verdicts too);
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
mean = lambda key: 100 * float(np.mean(results.score(key)))  # noqa: E731
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
