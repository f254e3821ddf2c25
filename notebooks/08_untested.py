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
# # 08 — The claims nobody had tested, and the paper's future work
#
# Six statements of the paper had no test in this package. This notebook judges the three
# that its rules decide, and measures the three it names findings:
#
# 1. that the learned laws carry the robot to the landmark wherever it stands (**relocation**);
# 2. that the model "can cope easily" with changes of the object, sensors or actuators
#    (**coping**);
# 3. the paper's next step, **continuous actions**: "even more accuracy and a shorter path";
# 4. that "population" coding "might" resolve ambiguities (**population coding**, a finding);
# 5. that the learner "learns to neglect irrelevant parts of the input" (**neglect**, a
#    finding);
# 6. why the learner fails where the pixels suffice (**the mechanism**, exploratory).
#
# Points 1-3 are the design's judged part (`ut.part("judged")`), points 4-6 its findings
# part (`ut.part("findings")`, ten seeds per cell): the same design, the same rules.
#
# **The rules were committed before any of these runs** (`docking/study/designs/untested.py`,
# its record in `rules/`, held to the live code by `tests/test_records.py`; two amendments before
# any run, named there), on seeds no earlier run used (4000-4019). The judged claims
# (relocation, coping, continuous accuracy and path) are decided by Holm's adjustment within
# each claim at 0.05, on paired Student-t intervals over seeds, with the verdicts of the
# earlier editions: *supported*, *contradicted*, *not supported* (undecided), *at the bound*
# (decided, but the deciding end of the interval lies within 0.01 of the bound, in the
# statistic's own units).

# %%
import dataclasses

import gymnasium
import numpy as np
from gymnasium.utils.env_checker import check_env
from IPython.display import Image, Markdown, display

import docking.gym_ids  # noqa: F401  (registers the Gymnasium ids)
from docking.experiments import initial_network
from docking.scene import scene_facts
from docking.study import analysis, arrays, figures, provenance, report
from docking.study.claims import design_verdicts, judge_family, rate_interval
from docking.study.designs import addendum as ad
from docking.study.designs import measures, third_edition_report
from docking.study.designs import third_edition as te
from docking.study.designs import untested as ut
from docking.study.designs.builders import with_cup
from docking.study.report import save_named
from docking.study.stats import t_mean_ci, t_paired_ci

results = ut.part("judged").run(progress=False)
per_claim = judge_family(results.design.claims, results, alpha=ut.ALPHA, per_claim=True)
decided = {(d.claim, d.world): d for d in per_claim}
pct = lambda ci: ci.format(unit="%")  # noqa: E731
mean = lambda key: rate_interval(results, key)  # noqa: E731
pp = lambda ci: ci.format(unit=" pp")  # noqa: E731


def md_table(header, rows) -> Markdown:
    """The Markdown table of ``rows`` under ``header`` (:func:`docking.study.report.md_table`)."""
    return Markdown(report.md_table(header, rows))


# %% [markdown]
# **Read again, two of these tests could not fail** (issue 42), and their verdicts stay in the
# tables as they were run but outside every count of supported claims: relocation *holds by
# construction* (no place changes a start view: section 1), and coping's verdicts are
# *limited by its measure's resolution* (a curve point every 100 trials: section 2).
# Notebook 09 tests both again by rules that can fail. Deviations from the rules' order in
# this design's history, each checked against the history by `tests/test_provenance.py`:

# %%
display(Markdown(provenance.deviations_table(ut.NAME)))
assert {c: third_edition_report.OUTSIDE_COUNTS[c] for c in ("relocation", "coping")}

# %% [markdown]
# ## 1. Relocation
#
# > "once the sensorimotor laws have been learned ... the robot is able to navigate to any
# > position, where a landmark with the same geometrical properties is located" (Sec. IV)
#
# The home networks (trained in the sideboard world) are tested without retraining with the
# landmark, its sideboard and its dock moved **along the wall**, turned onto **another
# wall**, and into a **second room** (other walls, floor and furniture, the same landmark):
# `docking.presets.RELOCATIONS`, in the table below. Rule: home minus the new place within
# ±`ut.RELOCATION_MARGIN` (equivalence, paired by seed).
#
# Measured before any run (`tests/test_untested.py`): the robot's camera draws only the red
# objects and what could hide them, and its pipeline keeps only red, so none of the three
# places changes a single start view. The rule therefore tests what else a place changes: the
# physics of the walk. Beside each learner's success, how many of its held-out trials end
# otherwise (docked against not) or take another number of actions than the same trial at home.

# %% tags=["hide-input", "fold-output"]
display(
    Markdown(
        f"{len(results.score('home/paper'))} seeds; equivalence margin "
        f"±{100 * ut.RELOCATION_MARGIN:g} pp."
    ),
    md_table(
        ("place", "room", "landmark moved by (x m, y m, turned °)"),
        [(p, w.room, ", ".join(f"{v:g}" for v in w.room_shift)) for p, w in ut.RELOCATIONS.items()],
    ),
)
moved = {}
for place in ut.RELOCATIONS:
    for learner in ("paper", "linear"):
        here, home = results.logs[f"{place}/{learner}"], results.logs[f"home/{learner}"]
        pairs = list(zip(here, home, strict=True))
        moved[place, learner] = (
            sum(int((a.success != b.success).sum()) for a, b in pairs),
            sum(int((a.steps != b.steps).sum()) for a, b in pairs),
            sum(len(a) for a, _ in pairs),
        )
rows = [("home", pct(mean("home/paper")), "", pct(mean("home/linear")), "", "")]
for place in ut.RELOCATIONS:
    p, q = moved[place, "paper"], moved[place, "linear"]
    rows.append(
        (place, pct(mean(f"{place}/paper")), f"{p[0]} / {p[1]} of {p[2]}")
        + (pct(mean(f"{place}/linear")), f"{q[0]} / {q[1]} of {q[2]}", pct(mean(f"{place}/oracle")))
    )
other = "its trials ending otherwise / of another length"
header = ("place", "the paper's learner", other, "linear SARSA", other, "pose oracle")
display(md_table(header, rows))
display(
    md_table(
        ("place", "home minus the place (paper's learner, paired)", "verdict"),
        [
            (p, pp(decided["relocation", p].interval), decided["relocation", p].verdict)
            for p in ut.RELOCATIONS
        ],
    )
)

# %% [markdown]
# **What the runs show** (each sentence computed from the runs; the asserts hold it):

# %% tags=["hide-input"]
other, along = moved["along the wall", "paper"][1:], decided["relocation", "along the wall"]
display(
    Markdown(
        "The paper's sentence holds in all three places, and the pose oracle docks in each "
        f"(at least {100 * min(mean(f'{p}/oracle').estimate for p in ut.RELOCATIONS):.1f}%), "
        "so each place is solvable. But it holds on an input that cannot tell the places "
        "apart. Against another wall and in the second room every held-out trial of both "
        "learners is the trial at home, bit for bit: nothing the robot computes changes. "
        f"Along the wall the walk itself differs ({other[0]} of {other[1]} trials take "
        f"another number of actions), yet success moves by {pp(along.interval)}. The "
        '"clear advantage compared to models that rely on a world model" is therefore '
        "structural: the input carries nothing of the surroundings, so no learner of these "
        "pixels, the paper's or linear SARSA, can be confused by them. What the sentence "
        "would need to be tested against, a place whose surroundings reach the input (other "
        "red objects, another light), is the distractor claim of notebook 07."
    )
)
for place in ut.RELOCATIONS:
    assert decided["relocation", place].verdict == "supported"
    assert mean(f"{place}/oracle").estimate >= 0.99  # the place is solvable
for place in ("another wall", "second room"):  # the runs at home, bit for bit
    assert all(moved[place, learner][:2] == (0, 0) for learner in ("paper", "linear"))
assert other[0] > 0.2 * other[1] and abs(along.interval.estimate) < 0.01

# %% [markdown]
# Where the walk differs along the wall: the robot touches no furniture in the start region
# or on the straight walk from a start to the dock, in any place (checked on 60 starts and
# their walks per place, `docking.study.analysis.furniture_contacts`); but the shifted table stands
# where a robot that wanders off that walk reaches it (the trials that differ begin to
# diverge near (-1.20, 0.70) m).

# %% tags=["hide-input"]
places = {
    p: dataclasses.replace(ut.WORLDS["sideboard"], room=m.room, room_shift=m.room_shift)
    for p, m in ut.RELOCATIONS.items()
}
touched = {
    p: int(analysis.furniture_contacts(w, analysis.walking_poses(w, 60)).sum())
    for p, w in places.items()
}
at_table = analysis.furniture_contacts(places["along the wall"], [[-1.2, 0.7, 0.0]])
print("; ".join(f"{p}: {n} of 600 walking poses touch furniture" for p, n in touched.items()))
assert not any(touched.values()) and at_table.all()

# %% [markdown]
# ## 2. Coping with change
#
# > "the proposed model can cope easily with changes of the object, sensors or actuators of
# > the robot" (Sec. IV)
#
# After one change, the home network keeps learning in the changed world; a fresh network
# learns it from scratch on the same seed's streams; and the home network is also tested in
# the changed world without learning (the transfer). The changes (`ut.CHANGES`, in the
# table below): the **object** (the landmark without its post, a slab), the **sensor** (the
# camera lower) and the **actuators** (shorter forward steps).
#
# Measure: the training trials until the learning curve (greedy trials every
# `eval_every` training trials) reaches `ut.REGAIN` of the same seed's held-out success at
# home (never: `ut.CENSORED`). **Rule** ("easily"):
# re-learning takes at most half the fresh network's trials, paired by seed (half the fresh
# trials minus the re-learning trials above zero). Linear SARSA does the same, as a finding.
#
# The measure's resolution is the learning curve's: a point every 100 training trials. Where
# the home network transfers above the level without learning, it scores 0 trials; where a
# fresh network regains at the first point, it scores 100; the rule then passes or fails at
# its floor. The table says how often.

# %% tags=["hide-input"]
home_world, curve = ut.WORLDS["sideboard"], results.cell("sensor/paper-fresh").config
shown = lambda name, v: (  # noqa: E731
    f"the asset's {scene_facts().camera_height:g} m" if name == "camera_height" and v is None else v
)
changed = [
    (
        change,
        f.name,
        shown(f.name, getattr(home_world, f.name)),
        shown(f.name, getattr(world, f.name)),
    )
    for change, world in ut.CHANGES.items()
    for f in dataclasses.fields(world)
    if getattr(world, f.name) != getattr(home_world, f.name)
]
display(
    Markdown(
        f"Learning curve: {curve.eval_trials} greedy trials every {curve.eval_every} training "
        f"trials; level {ut.REGAIN:.0%} of home; never regained counts {ut.CENSORED}."
    ),
    md_table(("change", "what", "home", "changed"), changed),
)
coping = {change: decided["coping", change] for change in ut.CHANGES}
lines = []
regained = {}
(coping_linear,) = [c for c in results.design.claims if c.key == "coping-linear"]
for change in ut.CHANGES:
    for learner in ("paper", "linear"):
        fresh = ut.regain_trials(results, f"{change}/{learner}-fresh")
        on = ut.regain_trials(results, f"{change}/{learner}-relearn")
        regained[change, learner] = fresh, on
        if learner == "paper":
            d = decided["coping", change]
            interval, verdict = d.interval, d.verdict
        else:  # a finding: the same statistic, not judged
            interval, verdict = (
                coping_linear.interval(results, f"{change}/linear-relearn"),
                "finding",
            )
        lines.append(
            (change, learner, pct(mean(f"{change}/{learner}-transfer")))
            + (f"{fresh.min():.0f}-{fresh.max():.0f} (mean {fresh.mean():.0f})",)
            + (f"{on.min():.0f}-{on.max():.0f} (mean {on.mean():.0f})",)
            + (interval.format(scale=1.0, digits=0), verdict)
        )
header = ("change", "learner", "home network, no learning", "fresh: trials to regain")
header += ("home network learning on: trials", "half the fresh minus learning on", "verdict")
display(md_table(header, lines))
curves = {
    (change, learner, kind): (
        results.runs[f"{change}/{learner}-{kind}"][0].curve_trials,
        np.array([r.curve_success for r in results.runs[f"{change}/{learner}-{kind}"]]),
    )
    for change in ut.CHANGES
    for learner in ("paper", "linear")
    for kind in ("fresh", "relearn")
}
levels = {
    learner: ut.REGAIN * float(np.mean(results.score(f"home/{learner}")))
    for learner in ("paper", "linear")
}
display(Image(save_named(figures.fig_coping(list(ut.CHANGES), curves, levels), "untested_coping")))

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence). Beside the rule, the
# held-out success after the 2000 training trials in the changed world: learning on is not
# free.

# %% tags=["hide-input"]
home = {learner: mean(f"home/{learner}").estimate for learner in ("paper", "linear")}
transfer = {(c, learner): mean(f"{c}/{learner}-transfer") for c in ut.CHANGES for learner in home}
after = {  # held-out success after learning on, minus without learning (paired by seed)
    (c, learner, kind): t_paired_ci(
        results.score(f"{c}/{learner}-{kind}"), results.score(f"{c}/{learner}-transfer")
    )
    for c in ut.CHANGES
    for learner in home
    for kind in ("relearn", "fresh")
}
fresh_s, on_s = regained["sensor", "paper"]
display(
    Markdown(
        f"* **Object and actuators.** The home networks transfer without learning "
        f"({pct(transfer['object', 'paper'])} and {pct(transfer['actuator', 'paper'])}, "
        f"against {100 * home['paper']:.1f}% at home), above the level to regain, so they score "
        "0 trials, and the rule passes at its floor: it says the changes are small for this "
        "learner, not that it re-learns fast.\n"
        f"* **Sensor.** The camera 6 cm lower is a real change (transfer "
        f"{pct(transfer['sensor', 'paper'])}). Learning on, the home network regains in "
        f"{on_s.mean():.0f} trials on average, a fresh network in {fresh_s.mean():.0f}; both "
        f"within {max(on_s.max(), fresh_s.max()):.0f}. Re-learning is not faster than half the "
        "fresh learner's trials: **contradicted** by the committed rule, at a resolution of "
        "one curve point per 100 trials. The world is learnt from scratch almost as fast as "
        "it is re-learnt.\n"
        f"* **Learning on can cost.** With 10 cm steps, the home network's held-out success "
        f"after 2000 more training trials is {pp(after['actuator', 'paper', 'relearn'])} "
        f"against not learning at all, and a fresh network's after 2000 trials "
        f"{pp(after['actuator', 'paper', 'fresh'])}; linear SARSA's "
        f"{pp(after['actuator', 'linear', 'relearn'])} and "
        f"{pp(after['actuator', 'linear', 'fresh'])}. The figure's curves peak within the "
        "first few hundred trials and fall as training goes on, while the curriculum adds "
        "the far starts, which need more of the shorter steps (the curve is measured on the "
        "whole start region throughout).\n"
        '* So "cope easily" holds for what does not change the input much, and not beyond '
        "it: where the input changes, the old network is no head start at the measure's "
        "resolution."
    )
)
assert [coping[c].verdict for c in ut.CHANGES] == ["supported", "contradicted", "supported"]
for c in ("object", "actuator"):  # at the floor: the home network needs no learning
    assert transfer[c, "paper"].estimate >= ut.REGAIN * home["paper"]
    assert np.median(regained[c, "paper"][1]) == 0
assert transfer["sensor", "paper"].high < ut.REGAIN * home["paper"]  # a real change
assert max(on_s.max(), fresh_s.max()) <= 200
assert (
    after["actuator", "paper", "relearn"].high < 0 and after["actuator", "paper", "fresh"].high < 0
)

# %% [markdown]
# ## 3. Continuous actions, the paper's next step
#
# > "Future work aims at allowing continuous actions. This should result in even more accuracy
# > and a shorter path due to exact and oriented movements." (Sec. V)
#
# `docking/Continuous-v0` is Experiment 2's world with a `Box` action space: a step vector
# (forward and sideways, each within the discrete steps' limits, `step_forward` and
# `step_side`), with the same walking noise; its turning variant adds a turn within
# ±`turn_deg`. The paper's network has no
# natural continuous read-out (its action layer picks one of four units by Eq. 4, and a
# weighted mean of the four steps would be a different policy, not a read-out), so none is
# added. Its competitors carry the prediction instead: the **pose oracle** (with the discrete
# steps, and with the step that points straight at the dock's centre, clipped to the limits;
# with and without turns) and **PPO** (skrl; a categorical policy for the discrete steps, a
# Gaussian one for the step vector; without turns), in the sideboard and the Nao-like worlds.
#
# Rule: each of the paper's two measures lower with continuous actions (discrete minus
# continuous above zero, paired by seed), Holm within each claim: **accuracy**, the final
# distance of the reference point from the dock's centre over the docked held-out trials;
# **path**, the metres walked per docking. The heading error at docking and the actions per
# docking are shown beside them, not judged.

# %% tags=["hide-input", "fold-output"]
env = gymnasium.make("docking/Continuous-v0")
check_env(env.unwrapped)  # Gymnasium's own checks of the Box action space
env.close()
lines = []
continuous = {}
for group in ut.CONTINUOUS_GROUPS:
    for learner in ("oracle", "ppo"):
        for space in ("discrete", "continuous"):
            key = f"{group}/{space}" if learner == "oracle" else f"{group}/ppo-{space}"
            if key not in {c.key for c in results.cells}:
                continue  # PPO learns without turns only
            m = {
                name: t_mean_ci(f(results, key))
                for name, f in (
                    ("distance", measures.final_error_m),
                    ("heading", measures.heading_error_deg),
                    ("actions", measures.actions_per_docking),
                    ("metres", measures.metres_per_docking),
                )
            }
            continuous[group, learner, space] = m
            lines.append(
                (group, learner, space, pct(mean(key)), m["distance"].format(scale=100.0))
                + (m["heading"].format(scale=1.0), m["actions"].format(scale=1.0, digits=2))
                + (m["metres"].format(scale=1.0, digits=2),)
            )
header = ("world", "learner", "actions", "held-out success", "final distance (cm)")
header += ("heading error at docking (°)", "actions per docking", "metres per docking")
display(md_table(header, lines))
cm = lambda d: d.claim.endswith("accuracy")  # noqa: E731
display(
    md_table(
        ("claim", "comparison", "discrete minus continuous", "verdict"),
        [
            (d.claim, d.key)
            + (
                d.interval.format(scale=100.0 if cm(d) else 1.0, digits=2)
                + (" cm" if cm(d) else " m"),
            )
            + (d.verdict,)
            for d in per_claim
            if d.claim.startswith("continuous")
        ],
    )
)

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence):

# %% tags=["hide-input"]
by = {(d.claim.split("-")[1], d.key): d for d in per_claim if d.claim.startswith("continuous")}
oracle_keys = [f"{g}/continuous" for g in ut.CONTINUOUS_GROUPS]
ppo_keys = list(dict.fromkeys(k for _, k in by if "ppo" in k))
span = lambda kind, keys, scale, digits: (  # noqa: E731
    f"{scale * min(by[kind, k].interval.estimate for k in keys):.{digits}f}-"
    f"{scale * max(by[kind, k].interval.estimate for k in keys):.{digits}f}"
)
heading = {
    (g, learner): continuous[g, learner, "discrete"]["heading"].estimate
    - continuous[g, learner, "continuous"]["heading"].estimate
    for g in ut.CONTINUOUS_GROUPS
    for learner in ("oracle", "ppo")
    if (g, learner, "continuous") in continuous
}
display(
    Markdown(
        f"* **Path.** With a step vector the pose oracle walks {span('path', oracle_keys, 1, 2)} m "
        "less per docking, in both worlds, with and without turns (supported in every group). "
        "PPO does not: in the sideboard world its path is as long "
        f"({by['path', 'sideboard/ppo-continuous'].interval.format(scale=1.0, digits=3)} m), "
        "in the Nao-like world longer "
        f"({by['path', 'nao/ppo-continuous'].interval.format(scale=1.0, digits=3)} m, "
        "contradicted), though in fewer actions: a learned step vector is not an exact one.\n"
        f"* **Accuracy.** The oracle ends {span('accuracy', oracle_keys, 1000, 1)} mm closer to "
        f"the dock's centre, PPO {span('accuracy', ppo_keys, 1000, 1)} mm: decided in the "
        "predicted direction everywhere, but *at the bound* where the difference is under a "
        "centimetre, the rule's resolution (`NEAR_BOUND`, 0.01 in metres), so only PPO in the "
        "sideboard world is *supported*. The heading error at docking (not judged) falls with "
        f"continuous actions in every group, by {min(heading.values()):.1f}-"
        f"{max(heading.values()):.1f}°.\n"
        "* So the paper's prediction holds for exact movements (the oracle's shorter path), "
        "and a learner that has to find the step vector gets the accuracy but not the path."
    )
)
assert all(by["path", k].verdict == "supported" for k in oracle_keys)
assert by["path", "sideboard/ppo-continuous"].verdict == "not supported"
assert by["path", "nao/ppo-continuous"].verdict == "contradicted"
assert continuous["nao", "ppo", "continuous"]["actions"].high < (
    continuous["nao", "ppo", "discrete"]["actions"].low
)
assert all(by["accuracy", k].interval.low > 0 for k in oracle_keys + ppo_keys)
assert [k for k in oracle_keys + ppo_keys if by["accuracy", k].verdict == "supported"] == [
    "sideboard/ppo-continuous"
]
assert all(v > 0 for v in heading.values())

# %% [markdown]
# ## The verdicts
#
# The judged claims of this notebook, Holm within each claim (the README's verdict table
# carries relocation and coping beside the third edition's claims), and one family of all
# their comparisons beside it.

# %% tags=["fold-output"]
# the verdict table: every comparison, its interval, its p-value and its verdict
display(Markdown(design_verdicts(results)))

# %%
fig = figures.fig_verdicts(
    third_edition_report.verdict_panels(results.design.claims, results, per_claim)
)
display(Image(save_named(fig, "untested_verdicts")))

# %% [markdown]
# ## 4. Population coding (a finding)
#
# > "This 'population' coding might be useful for resolving ambiguities" (Sec. III)
#
# beta_s from the paper's 100 (nearly winner-take-all) down to 30, 10 and 3 (soft), with
# eps_W / beta_s held at the paper's (the gradient of Eq. 8 scales with beta_s), and a forced
# single winner (the feature layer's softmax replaced by a one-hot of its largest input): the
# held-out success of each, ten seeds, in the sideboard and the floor worlds. And the
# ambiguities that population coding might resolve: of 1500 start views per world, those whose
# 32x10 input another start pose shares (*shared*), and of them those the pose oracle answers
# with another action (*ambiguous*, in groups of one input each).

# %% tags=["hide-input"]
findings = ut.part("findings").run(progress=False)
fmean = lambda key: rate_interval(findings, key)  # noqa: E731
variants = ["paper", "winner", *(f"beta{b:g}" for b in ut.BETAS)]
population = {
    (w, v): report.paired_over_shared_seeds(findings, f"{w}/{v}", f"{w}/paper")
    for w in ut.WORLDS
    for v in variants[1:]
}
display(
    md_table(
        ["variant"] + [f"{w}: {h}" for w in ut.WORLDS for h in ("held-out", "minus the paper's")],
        [
            [v]
            + [
                x
                for w in ut.WORLDS
                for x in (pct(fmean(f"{w}/{v}")), pp(population[w, v]) if v != "paper" else "")
            ]
            for v in variants
        ],
    )
)
ambiguity = {w: analysis.ambiguous_views(world, n=1500) for w, world in ut.WORLDS.items()}
header = ("world", "start views", "sharing an input", "ambiguous (the oracle acts differently)")
display(
    md_table(
        (*header, "groups"),
        [(w, a.views, a.shared, a.ambiguous, len(a.groups)) for w, a in ambiguity.items()],
    )
)

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence):

# %% tags=["hide-input"]
softer = {w: [population[w, f"beta{b:g}"] for b in ut.BETAS] for w in ut.WORLDS}
display(
    Markdown(
        "* **Softer is worse.** beta_s 3 changes held-out success by "
        + ", ".join(f"{pp(population[w, 'beta3'])} in the {w} world" for w in ut.WORLDS)
        + "; beta_s 10 "
        + ", ".join(f"{pp(population[w, 'beta10'])}" for w in ut.WORLDS)
        + ". A population code wider than the paper's does not help.\n"
        "* **A forced single winner** changes it by "
        + ", ".join(f"{pp(population[w, 'winner'])} ({w})" for w in ut.WORLDS)
        + ". With s one-hot, Eq. (8)'s non-local bracket is zero, so W also stays at its "
        "random start: the difference measures the hard winner and frozen features together "
        "(W frozen alone, under the softmax, is notebook 07's features-success claim).\n"
        "* **Ambiguities** are few: "
        + ", ".join(
            f"{a.ambiguous} of {a.views} start views in the {w} world" for w, a in ambiguity.items()
        )
        + " share their input with a pose the oracle answers otherwise; a population code has "
        "little to resolve in these worlds."
    )
)
assert all(population[w, "beta3"].high < 0 and population[w, "beta10"].high < 0 for w in ut.WORLDS)
assert all(a.ambiguous <= 0.05 * a.views for a in ambiguity.values())


# %% [markdown]
# ## 5. Neglecting the irrelevant (a finding)
#
# > "learns to neglect irrelevant parts of the input" (Sec. I, II-A)
#
# Where the winning units put their weight (`analysis.weight_mass`): the shares of |W| on the
# landmark's pixels, the red cup's and the background's, weighted by how often each unit wins,
# over 1500 start views of the world with the cup. For networks trained with and without the
# cup, after 250, 1000 and 2000 training trials, against the same seeds' random start (W
# frozen). The first five seeds (`ut.NEGLECT_SEEDS`), whose networks the ledger keeps.

# %% tags=["hide-input", "fold-output"]
cup_world = with_cup(ut.WORLDS["sideboard"])
neglect = {}
for trained in ("without", "with"):
    for n, cell in ((250, "trained250"), (1000, "trained1000"), (2000, "paper")):
        cell = cell if trained == "without" else ("cup" if cell == "paper" else f"cup-{cell}")
        runs = findings.runs[f"sideboard/{cell}"][: len(ut.NEGLECT_SEEDS)]
        neglect[trained, n] = np.array([analysis.weight_mass(r.network, cup_world) for r in runs])
runs = findings.runs["sideboard/paper"][: len(ut.NEGLECT_SEEDS)]
frozen = np.array(
    [analysis.weight_mass(initial_network(r.config, r.seed), cup_world) for r in runs]
)
share = lambda m: [f"{100 * m[:, k].mean():.2f}%" for k in range(3)]  # noqa: E731
gain = {k: t_paired_ci(m[:, 0], frozen[:, 0]) for k, m in neglect.items()}  # landmark share
display(
    md_table(
        ["trained", "trials", *arrays.MASS_PARTS, "landmark minus the random start"],
        [["(random start)", "0", *share(frozen), ""]]
        + [[f"{t} the cup", str(n), *share(m), pp(gain[t, n])] for (t, n), m in neglect.items()],
    )
)

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence):

# %% tags=["hide-input"]
largest = max(max(abs(g.low), abs(g.high)) for g in gain.values())
display(
    Markdown(
        "The winning units' weight on the landmark's pixels does not move: after every "
        "number of training trials, with and without the cup, it lies within "
        f"{100 * largest:.2f} pp of the same seeds' random start (the landmark's share of "
        f"|W| is {100 * frozen[:, 0].mean():.2f}% at the start). W barely leaves its random "
        "start in this world (as notebook 07's interpretability claim found), so what the learner "
        "neglects, it neglects in Q, not in the features: the paper's \"learns to neglect "
        'irrelevant parts of the input" is not visible in W here.'
    )
)
assert largest < 0.005  # within half a percentage point, every trained state


# %% [markdown] tags=["fold"]
# ## 6. The mechanism of the failure (exploratory)
#
# In the floor world the paper's learner docks far less often than linear SARSA on the same
# pixels (notebook 07). One part of the paper's learner varied at a time: the number of
# feature units (144, 576 against 36), the action layer's rate eps_Q (0.03, 0.3 against 0.1),
# beta_s and a forced single winner (above), and the pairs `ut.PAIRS` (the local feature rule
# is the third edition's finding: 17 pp better in the floor world). Each variant minus the
# paper's learner, paired by seed over ten seeds, with linear SARSA's lead dotted: a variant
# closes the gap where its interval reaches linear SARSA's line.

# %%
(mechanism,) = [c for c in ut.CLAIMS if c.key == "mechanism"]
(panel,) = third_edition_report.verdict_panels([mechanism], findings, [])
by_world = []
for w in ut.WORLDS:
    rows = [r for r in panel["rows"] if r[0].startswith(f"{w}:")]
    lead = report.paired_over_shared_seeds(findings, f"{w}/linear", f"{w}/paper")
    by_world.append(
        dict(panel, title=f"{w} world", rows=rows, reference=(lead.estimate, "linear SARSA"))
    )
display(Image(save_named(figures.fig_verdicts(by_world), "untested_mechanism")))

# %% [markdown]
# Which part closes the gap, by the third edition's contest rule (committed before these
# runs): a variant *closes* it if linear SARSA minus the variant, paired by seed, has its 95%
# interval below 5 pp; the gap *remains* if the interval lies above 5 pp; else undecided.

# %% tags=["hide-input", "fold-output"]
mechanism_variants = ["paper", "winner", *(f"beta{b:g}" for b in ut.BETAS)]
mechanism_variants += [k.split("/", 1)[1] for _, k in mechanism.cells["floor"]]
gap = {}
for w in ut.WORLDS:
    for v in mechanism_variants:
        ci = report.paired_over_shared_seeds(findings, f"{w}/linear", f"{w}/{v}")
        closed = ci.high < te.GAP_CLOSED
        gap[w, v] = ci, "closed" if closed else "remains" if ci.low > te.GAP_CLOSED else "undecided"
display(
    md_table(
        ["variant"] + [f"{w}: linear SARSA minus it" for w in ut.WORLDS],
        [
            [v] + [f"{pp(gap[w, v][0])} {gap[w, v][1]}" for w in ut.WORLDS]
            for v in mechanism_variants
        ],
    )
)

# %% [markdown]
# **What the runs show** (computed; the asserts hold each sentence):

# %% tags=["hide-input"]
closes = {w: [v for v in mechanism_variants if gap[w, v][1] == "closed"] for w in ut.WORLDS}
display(
    Markdown(
        "\n".join(
            f"* **{w} world:** linear SARSA leads the paper's learner by "
            f"{pp(gap[w, 'paper'][0])} ({gap[w, 'paper'][1]}); the gap is closed by "
            + (", ".join(v for v in closes[w] if v != "paper") or "no variant")
            + "."
            for w in ut.WORLDS
        )
    )
)
best = min(mechanism_variants, key=lambda v: gap["floor", v][0].estimate)
display(
    Markdown(
        f"In the floor world no single part and no pair tested closes the gap: the closest is "
        f"{best}, whose lead for linear SARSA is still {pp(gap['floor', best][0])}. The "
        "softer or harder feature layers widen it. What breaks the learner there is not one "
        "of these parts alone; 576 units with the local rule together recover "
        f"{1 - gap['floor', best][0].estimate / gap['floor', 'paper'][0].estimate:.0%} of it."
    )
)
assert all(gap["floor", v][1] == "remains" for v in mechanism_variants)
assert best == "units576+local"
assert gap["floor", best][0].estimate < 0.6 * gap["floor", "paper"][0].estimate

# %% [markdown] tags=["fold"]
# ## 7. Which part breaks: the representation, or learning Q on it
#
# The variants above change one part at a time and none closes the gap. The third edition's
# addendum (notebook 07) tuned both SARSA learners until every optimum was bracketed; here its
# networks are taken apart. For each judged network of the tuned paper's learner, its W is
# kept and Q is replaced by the **oracle-labelled Q**: each feature unit takes the action the
# pose oracle takes most often on the views it wins (the views of 300 oracle trials from the
# whole start region, a stream no run uses). What that Q docks is what W's partition of the
# views allows when every part of it gets the best single action; per seed and paired:
#
# * linear SARSA minus the oracle-labelled Q on the paper's W: what the **representation**
#   loses (W puts views that need different actions into one unit);
# * the oracle-labelled Q minus the Q the paper's rule learned: what **learning Q** loses.
#
# The reverse check: SARSA on a fixed partition (W from 200 random-walk trials of competitive
# learning, i.e. online k-means of views, then frozen) against the oracle-labelled Q on the
# same W.

# %% tags=["hide-input"]
added = ad.DESIGN.run(progress=False)
parts = {d.world: d for d in ad.decomposition(added, ad.WORLDS, 300, seed=0)}
columns = [
    "linear SARSA, tuned",
    "paper's W, oracle-labelled Q",
    "paper's learner, tuned",
    "k-means W, oracle-labelled Q",
    "SARSA on k-means W",
]
seeds = {}
for w, d in parts.items():
    for label, values in zip(
        columns, (d.linear, d.labelled, d.paper, d.fixed_labelled, d.fixed), strict=True
    ):
        seeds[third_edition_report.CONTEST_WORLDS[w], label] = values
# no split of the gap: the runs show the oracle-labelled Q is no bound (below)
fig = figures.fig_decomposition(
    [third_edition_report.CONTEST_WORLDS[w] for w in parts], columns, seeds
)
display(Image(save_named(fig, "addendum_decomposition")))
display(
    md_table(
        ["world", "gap", "purity of W's partition"],
        [
            [
                third_edition_report.CONTEST_WORLDS[w],
                pp(d.gap),
                f"{100 * d.purity.mean():.0f}%",
            ]
            for w, d in parts.items()
        ],
    )
)

# %% [markdown]
# **The answer** (computed from the runs; the asserts hold the sentence):

# %% tags=["hide-input"]
answer = []
for w, d in parts.items():
    learned = t_paired_ci(d.paper, d.labelled)
    answer.append(
        f"In {third_edition_report.CONTEST_NAMES[w]} the Q the paper's rule learned docks {learned.format(unit=' pp')} "
        f"more often than the oracle-labelled Q on the same W ({100 * d.paper.mean():.1f}% against "
        f"{100 * d.labelled.mean():.1f}%; {100 * d.purity.mean():.0f}% of the oracle's views share their "
        f"unit's majority action), and linear SARSA's lead over it is {pp(d.gap)}. SARSA on a fixed "
        f"k-means W docks {100 * d.fixed.mean():.1f}%, the oracle-labelled Q on that W "
        f"{100 * d.fixed_labelled.mean():.1f}%."
    )
answer.append(
    "**So the oracle-labelled Q is no bound on what a partition allows, and this decomposition, "
    "committed before the runs, cannot split the gap:** W's units hold views on which the oracle "
    "acts differently, and a Q learned on-policy picks, per unit, the action that works from "
    "where the learner's own policy brings it, which the oracle's majority action is not. What "
    "broke the paper's learner in these worlds was not a part of it but its exploration "
    "temperature: tuned (notebook 07's addendum), linear SARSA's lead falls to the intervals "
    "above (the contest's gaps: notebook 07)."
)
for d in parts.values():
    assert t_paired_ci(d.paper, d.labelled).low > 0  # the learned Q beats the oracle's labels
    assert d.gap.high < 0.06  # the gap after tuning is a few points at most
display(Markdown("\n\n".join(answer)))

# %% [markdown]
# The levers the contest had not tried, on the same judged seeds: eps_W past 0.5 and the
# exploration temperature were the search's own knobs (notebook 07's addendum table gives where
# each landed), and W initialised from views (the same k-means start, then learned by Eq. 8):

# %% tags=["hide-input"]
levers = []
for w in ad.WORLDS:
    init = report.paired_over_shared_seeds(added, f"{w}/views-init", f"{w}/paper-tuned")
    levers.append(
        [
            third_edition_report.CONTEST_WORLDS[w],
            pct(rate_interval(added, f"{w}/paper-tuned")),
            pct(rate_interval(added, f"{w}/views-init")),
            pp(init),
        ]
    )
display(
    md_table(
        ["world", "tuned (W uniform random)", "tuned, W from views", "W from views minus random"],
        levers,
    )
)
