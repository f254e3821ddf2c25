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
# # 09 — Relocation and coping, revisited: tests that can fail
#
# Notebook 08 judged two of the paper's Sec. IV claims by tests that, read again, could not
# have failed:
#
# * **Relocation** moved the room (walls, floor, furniture, light) about the landmark. The
#   robot's camera draws only the red group under its own headlight, so no place changed a
#   single start view; in two of the three places every held-out trial was the trial at
#   home, bit for bit. Its verdict *holds by construction*: it stays in the tables as it was
#   run, outside every count of supported claims.
# * **Coping** counted the trials to regain 90% of home success on a learning curve
#   measured every 100 trials, where a fresh network already passes at the first point: the
#   rule could see no head start. Its verdicts are *limited by the measure's resolution*,
#   and stay outside the counts too.
#
# This notebook is their revisit: a new, labelled analysis whose **rules were committed
# before any of its runs** (`docking/study/designs/revisited.py`; its record in `rules/` keeps
# the rules text and the code of the measure and of the judging functions as committed), on
# fresh seeds 6000-6009.
#
# * **Relocation to another height:** the landmark on a sideboard 3 cm lower or higher (a
#   common difference between pieces of furniture), everything else the same. Since the
#   camera draws only the red group, this is exactly the image of the home landmark from a
#   camera 3 cm higher or lower, which is how the place is built. Rule: the home networks'
#   held-out success at home minus in the new place, paired by seed, within ±5 pp
#   (equivalence).
# * **Coping at trial resolution:** after each change of notebook 08 (object, sensor,
#   actuators), the home network learning on and a fresh network each train 200 trials in
#   the changed world, with a learning-curve point every 10 trials (50 greedy trials each,
#   from streams training never uses). Measure: the *early failure*, the share of failed
#   greedy trials averaged over the 21 points from trial 0 to 200. Rule ("cope easily"):
#   the fresh network's early failure minus the home network's lies above 0 (a head start);
#   below 0 contradicts (the old network is a handicap). Beside it, not a verdict: trials
#   to regain 90% of home success, compared within each seed's pair by the sign test, so
#   that "never within 200 trials" enters only as later than any observed value.
#
# Verdicts are decided by Holm's adjustment within each claim at 0.05, on paired Student-t
# intervals over seeds; a decided verdict whose deciding end lies within 1 pp of the bound
# is "at the bound".

# %%
import numpy as np
from IPython.display import Image, Markdown, display

from docking.study import figures, provenance, report
from docking.study.claims import design_verdicts, rate_interval
from docking.study.designs import revisited as rv
from docking.study.designs import revisited_report
from docking.study.report import save_named

results = rv.DESIGN.run(progress=False)
rows = revisited_report.revisited_rows(results, rv, rv.changed_views())  # rendered here
verdict = rows["verdict"]
pct = lambda ci: ci.format(unit="%")  # noqa: E731
rules_commit, rules_time = provenance.RULES_COMMITS[rv.NAME]  # tests/test_provenance.py checks it
times = provenance.computed_times(rv.NAME)
print(
    f"rules committed {rules_time} ({rules_commit[:7]}); the {len(times)} runs computed "
    f"{min(times):%Y-%m-%d %H:%M} to {max(times):%Y-%m-%d %H:%M} (UTC)"
)
assert min(times) > report.utc(rules_time)  # every run after its rules

# %% [markdown]
# ## 1. Relocation: the landmark at another height
#
# Each place's start views are counted against home (300 start poses of the home world,
# rendered in both), then the home networks are tested there without retraining on the
# same held-out streams as at home. The pose oracle, which reads the true pose, shows that
# each place is solvable.

# %%
table = [("home", "", pct(rate_interval(results, "home/paper")), "", "")]
table[0] = table[0][:3] + (pct(rate_interval(results, "home/linear")), "")
for place, r in rows["places"].items():
    d = next(d for d in rows["decisions"] if d.claim == "relocation-height" and d.world == place)
    table.append(
        (
            place,
            f"{r['views'][0]} of {r['views'][1]}",
            f"{pct(r['there'])} ({d.interval.format(unit=' pp')} below home: {d.verdict})",
            pct(rate_interval(results, f"{place}/linear")),
            pct(r["oracle"]),
        )
    )
header = ("place", "start views changed", "the paper's learner", "linear SARSA")
display(Markdown(report.md_table((*header, "pose oracle"), table)))

# %% [markdown]
# ## 2. Coping at trial resolution
#
# The curves: greedy success every 10 training trials in the changed world, mean over the
# seeds, of the home network learning on (solid) and a fresh network (dashed); the dotted
# line is 90% of home success.

# %%
curves = {
    (change, learner, kind): (
        results.runs[f"{change}/{learner}-{kind}"][0].curve_trials,
        np.array([r.curve_success for r in results.runs[f"{change}/{learner}-{kind}"]]),
    )
    for change in rv.untested.CHANGES
    for learner in rv.LEARNERS
    for kind in ("fresh", "relearn")
}
levels = {
    learner: rv.REGAIN * float(np.mean(results.score(f"home/{learner}"))) for learner in rv.LEARNERS
}
fig = figures.fig_coping(list(rv.untested.CHANGES), curves, levels)
display(Image(save_named(fig, "revisited_coping")))
table = []
for change, r in rows["changes"].items():
    d = next(d for d in rows["decisions"] if d.claim == "coping-early" and d.world == change)
    sooner, signed, p = r["regain"]
    table.append(
        (
            change,
            f"{100 * r['relearn']:.1f}%",
            f"{100 * r['fresh']:.1f}%",
            f"{d.interval.format(scale=100, unit=' pp')}: {d.verdict}",
            f"{sooner} of {signed} (p {p:.2g})",
        )
    )
header = ("change", "early failure: home network learning on", "fresh network")
header += ("fresh minus learning on", "sooner to regain 90% (pairs with a sign; sign test)")
display(Markdown(report.md_table(header, table)))

# %% [markdown]
# ## The verdicts
#
# Both claims, and linear SARSA's as findings, in the verdict table's form (the README's
# verdict table carries the two judged rows).

# %%
display(Markdown(design_verdicts(results)))

# %% [markdown]
# ## What the revisit shows
#
# Each sentence is computed from the runs; the asserts hold what they say.

# %%
decided = {(d.claim, d.world): d for d in rows["decisions"]}
for d in rows["decisions"]:  # intervals that do not degenerate
    assert d.interval.high > d.interval.low, d
for r in rows["places"].values():
    assert r["views"][0] > 0  # a test that can fail: the place changes what the robot sees
    assert r["oracle"].low > 0.9  # and the place is solvable from the true pose
lines = []
for place, r in rows["places"].items():
    d = decided["relocation-height", place]
    if r["there"].estimate > r["home"].estimate:
        why = (
            "it docks *more* often there than at home; the committed rule is two-sided "
            f"(within ±{100 * rv.RELOCATION_MARGIN:.0f} pp), so a gain it cannot bound below "
            f"{100 * rv.RELOCATION_MARGIN:.0f} pp does not support the claim either"
        )
    else:
        why = f"{d.interval.format(unit=' pp')} below home"
    lines.append(
        f"* **{place}:** the paper's learner's home networks dock {pct(r['there'])} "
        f"against {pct(r['home'])} at home ({why}): **{d.verdict}**. The pose oracle docks "
        f"{pct(r['oracle'])}, so the place is solvable"
        + ("." if r["there"].estimate > r["home"].estimate else "; what fails is what was learned.")
    )
for change, r in rows["changes"].items():
    d = decided["coping-early", change]
    lines.append(
        f"* **{change}:** over the first {rv.EARLY_TRIALS} trials the home network learning on "
        f"fails {100 * r['relearn']:.1f}% of its greedy trials, a fresh network "
        f"{100 * r['fresh']:.1f}%: a head start of {d.interval.format(scale=100, unit=' pp')}, "
        f"**{d.verdict}**."
    )
display(Markdown("\n".join(lines)))
higher = rows["places"]["sideboard higher"]
assert decided["relocation-height", "sideboard higher"].verdict == "contradicted"
assert higher["there"].high < higher["home"].low  # a 3 cm higher landmark breaks the mapping
assert decided["coping-early", "object"].verdict == "supported"

# %% [markdown]
# **What changed from notebook 08's readings.** Relocation, which notebook 08 counted as
# supported wherever judged, is contradicted by the first test that could fail: with the
# landmark higher, the home networks of both learners lose a large share of their dockings
# (the table above), though the pose oracle still docks every time. "Any position where a
# landmark with the same geometrical properties is located" does not hold for a landmark at
# another height. A likely reason, not tested here: the features are tuned to where the
# landmark lies in the 32x10 image, and a higher landmark lies elsewhere in it. Coping, which
# notebook 08 read as contradicted for the sensor change on a 100-trial grid, shows a head
# start at trial resolution after the object and actuator changes, and none that the rule
# can decide after the sensor change, where a fresh network also learns within a few dozen
# trials (the curves above).
