"""What makes it learn: the paper's claims as variants of its experiments (notebook 05; the
study's first edition).

Every cell is a variant of Experiment 1 or 2, in the sideboard world or the floor world, run
for :data:`STUDY_SEEDS`, each network judged on :data:`HELDOUT_TRIALS` held-out trials
(:func:`docking.experiments.heldout_trials`). A *test-only* cell trains nothing: it judges its
baseline's networks in another world (with a distractor, or without heading noise).

Choices named here:

* Experiment 2 variants keep the paper's 2000 training trials; they skip the final 725-trial
  test (the held-out trials are the measure) and the learning curve, except the curriculum
  cells, whose curves are part of the claim.
* The *core* cells back every verdict; ``full=True`` adds the sensitivity cells (eps_W x10,
  beta_s 10 and 30, the local rule and the distractor variants in the floor world, the
  distractor with W frozen).
* ``beta_s`` 10 and 30 keep the gradient step ``eps_w / beta_s`` at the paper
  configuration's ``0.05 / 100`` (the rule absorbs ``beta_s`` into ``eps_w``, notebook 01).
* The unmodulated control (a stage: it needs the paper's runs first) replaces delta in
  Eq. (8) by a constant equal to the mean ``|delta|`` of the paper configuration's training
  steps.
* The two-stage learner pre-trains W on the frames of 200 random-walk trials by
  winner-take-all competitive learning (rate 0.05), then runs SARSA with W frozen.
* The rules below (:data:`CLAIMS`) were fixed before the first edition's verdicts; the
  curriculum's "or" (near-only) arrived after the first verdict commit, as the second edition
  notes (:mod:`docking.designs.second_edition`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.claims import Above, Claim, ShareAbove, Within, claim_of
from docking.claims import verdict_table as _table
from docking.design import Cell, Design, Results, run_design, yardstick_config
from docking.experiments import Curriculum, ExperimentConfig, ExperimentResult, TrialLog
from docking.network import NetworkConfig
from docking.presets import EXPERIMENT_1, EXPERIMENT_2, FLOOR_WORLD
from docking.scene import Distractor, WorldConfig

#: Seeds of every cell (verdicts rest on them: at least ten).
STUDY_SEEDS = tuple(range(10))

#: Held-out greedy trials per network.
HELDOUT_TRIALS = 500

#: The red cup of the distractor cells: on the sideboard 0.3 m to the landmark's left (in the
#: floor world on the floor, at the same place).
CUP = Distractor.cup(y=0.30)
FLOOR_CUP = Distractor("cylinder", CUP.size, (CUP.position[0], 0.30, CUP.size[1]))

#: Experiment 2 in the floor world: the paper's configuration, its curriculum starting 0.12 m
#: beyond the start region's near edge as in the sideboard world.
FLOOR_EXPERIMENT_2 = dataclasses.replace(
    EXPERIMENT_2,
    name="experiment2-floor",
    world=FLOOR_WORLD,
    curriculum=Curriculum(far_initial=FLOOR_WORLD.start_near + 0.12, grow_trials=1400),
)

#: Half-width of the equivalence margin for "does not affect performance" (percentage points
#: of held-out success, as a fraction). Our choice, fixed before the runs.
EQUIVALENCE_MARGIN = 0.02

#: The share of failures that must go when heading noise is removed at test, for "most
#: failures come from uncorrected rotation": more than half ("most").
ROTATION_SHARE = 0.5


def variant(base: ExperimentConfig, name: str, curve: bool = False, **changes):
    """``base`` as a study run: held-out trials, no final test, a curve only if asked."""
    settings = dict(heldout_trials=HELDOUT_TRIALS, test_trials=0, eval_trials=50 if curve else 0)
    return dataclasses.replace(base, name=name, **settings, **changes)


def net(base: ExperimentConfig, **changes) -> NetworkConfig:
    return dataclasses.replace(base.network, **changes)


def with_cup(world: WorldConfig) -> WorldConfig:
    return dataclasses.replace(
        world, distractors=(CUP if world.scene == "sideboard" else FLOOR_CUP,)
    )


def _experiment2_cells(world: str, base: ExperimentConfig) -> list[Cell]:
    """The Experiment 2 variants in one world."""
    p = "" if world == "sideboard" else f"{world}/"
    name, floor = f"study-{world}", world != "sideboard"
    near = base.curriculum.far_initial
    eps_w, beta_s = base.network.eps_w, base.network.beta_s
    paper_config = variant(base, name, True)
    cup_world = with_cup(base.world)

    def cell(key, claim, label, config, core=True, test_world=None, baseline="paper"):
        coords = {"world": world, "experiment": "Experiment 2", "variant": key}
        return Cell(f"{p}{key}", config, coords, label, p + baseline, test_world, core, claim)

    def trained(**changes):
        return variant(base, name, **changes)

    frozen = net(base, eps_w=0)
    return [
        dataclasses.replace(
            cell("paper", "features", "the paper's rule (Eq. 8, non-local)", paper_config),
            baseline=None,
        ),
        cell("frozen", "features", "W frozen (eps_W = 0)", trained(network=frozen)),
        cell(
            "local",
            "features",
            "local rule (Eq. 8 without the bracket)",
            trained(network=net(base, rule="local")),
        ),
        cell(
            "none",
            "curriculum",
            "no curriculum (full region from trial 0)",
            variant(base, name, True, curriculum=Curriculum(near, grow_trials=0)),
        ),
        cell(
            "near-only",
            "curriculum",
            f"trained only near ({base.world.start_near:.2f}-{near:.2f} m)",
            variant(base, name, True, curriculum=Curriculum(near, far_final=near)),
        ),
        cell(
            "no-yaw-noise",
            "rotation",
            "the paper's networks tested without heading noise",
            paper_config,
            test_world=dataclasses.replace(base.world, step_noise_yaw_deg=0.0),
        ),
        cell(
            "cup-test",
            "distractor",
            "the paper's networks tested with a red cup",
            paper_config,
            test_world=cup_world,
        ),
        cell(
            "cup", "distractor", "red cup in training and test", trained(world=cup_world), not floor
        ),
        cell(
            "cup-test-frozen",
            "distractor",
            "W frozen, tested with a red cup",
            trained(network=frozen),
            core=not floor,
            test_world=cup_world,
            baseline="frozen",
        ),
        cell(
            "cup-frozen",
            "distractor",
            "red cup in training and test, W frozen",
            trained(world=cup_world, network=frozen),
            core=False,
        ),
        cell(
            "epsW-x10",
            "features",
            f"eps_W x10 ({10 * eps_w:g})",
            trained(network=net(base, eps_w=10 * eps_w)),
            core=False,
        ),
        cell(
            "beta-10",
            "features",
            "beta_s = 10 (eps_W / beta_s kept)",
            trained(network=net(base, beta_s=10.0, eps_w=eps_w * 10 / beta_s)),
            core=False,
        ),
        cell(
            "beta-30",
            "features",
            "beta_s = 30 (eps_W / beta_s kept)",
            trained(network=net(base, beta_s=30.0, eps_w=eps_w * 30 / beta_s)),
            core=False,
        ),
        cell(
            "two-stage",
            "alternative",
            "two-stage: competitive features first, then SARSA",
            trained(network=frozen, pretrain_trials=200),
            core=not floor,
        ),
        cell(
            "linear",
            "alternative",
            "linear SARSA on the 320 pixels",
            trained(network=net(base, n_features=base.network.n_inputs, feature_layer="none")),
            core=not floor,
        ),
    ]


def _experiment1_cells() -> list[Cell]:
    base, name = EXPERIMENT_1, "study-experiment1"

    def cell(key, label, config, baseline="exp1/local"):
        coords = {"world": "sideboard", "experiment": "Experiment 1", "variant": key}
        return Cell(f"exp1/{key}", config, coords, label, baseline, claim="features")

    return [
        cell("local", "Exp. 1, local rule (the paper's)", variant(base, name, True), None),
        cell("frozen", "Exp. 1, W frozen", variant(base, name, True, network=net(base, eps_w=0))),
        cell(
            "nonlocal",
            "Exp. 1, non-local rule",
            variant(base, name, True, network=net(base, rule="nonlocal")),
        ),
    ]


def cells(full: bool = False) -> list[Cell]:
    """The study's cells but the unmodulated control (:func:`control_cell`): Experiment 2 in
    the sideboard world, Experiment 1, Experiment 2 in the floor world; the core cells only
    unless ``full``."""
    return DESIGN.select(full)


def control_cell(constant: float) -> Cell:
    """Eq. (8) with delta replaced by ``constant`` (the paper configuration's mean |delta|)."""
    base = EXPERIMENT_2
    config = variant(base, "study-sideboard", network=net(base, feature_delta=float(constant)))
    coords = {"world": "sideboard", "experiment": "Experiment 2", "variant": "constant-delta"}
    label = f"Eq. 8 with a constant {constant:.3g} in place of delta"
    return Cell("constant-delta", config, coords, label, "paper", claim="delta")


def mean_abs_delta(results: list[ExperimentResult]) -> float:
    """The mean |delta| over every training step of ``results``."""
    return float(np.mean(np.abs(np.concatenate([r.train.deltas for r in results]))))


def _control(results: Results) -> list[Cell]:
    return [control_cell(mean_abs_delta(results.runs["paper"]))]


CLAIMS = (
    Claim(
        "features",
        "the delta signal modulates not only the action but at the same time the feature "
        "weights ... the network learns interpretable visual features",
        "Abstract; Sec. II-A, III",
        "held-out success of the paper's rule minus W frozen (eps_W = 0)",
        Above(0.0),
        {"sideboard": ("frozen",), "floor": ("floor/frozen",)},
    ),
    Claim(
        "delta",
        "the feature layer learns only when there is learning progress ... unimportant "
        "components of the data are not correlated with the learning progress",
        "Sec. II-A",
        "the paper's rule minus Eq. 8 with delta replaced by a constant of the same mean magnitude",
        Above(0.0),
        {"sideboard": ("constant-delta",)},
    ),
    Claim(
        "curriculum",
        "the region is incrementally enlarged during learning ... Learning from Easy Missions",
        "Sec. II-C",
        "the paper's growing region minus no curriculum (the full region from trial 0) and "
        "minus never growing (trained near, tested on the full region); both must be "
        "supported, either contradicted contradicts",
        Above(0.0),
        {"sideboard": ("none", "near-only"), "floor": ("floor/none", "floor/near-only")},
    ),
    Claim(
        "rotation",
        "this noise can lead to a rotation of the robot, which currently is not compensated "
        "... This is actually the reason for most of the unsuccessful trials",
        "Sec. III, Fig. 5",
        "the share of the paper's networks' held-out failures that go when the same trials "
        "run without heading noise",
        ShareAbove(ROTATION_SHARE),
        {"sideboard": ("no-yaw-noise",), "floor": ("floor/no-yaw-noise",)},
    ),
    Claim(
        "distractor",
        "noise (e.g. other red objects within the visual field) should not affect performance. "
        "This criterion is also fulfilled by our model",
        "Sec. IV",
        "the paper's networks tested with a red cup beside the landmark minus without",
        Within(EQUIVALENCE_MARGIN),
        {"sideboard": ("cup-test",), "floor": ("floor/cup-test",)},
    ),
    Claim(
        "alternative",
        "a self-organizing map could be used to first learn the visual features ... they would "
        "be separate parts that would need to be linked ad hoc",
        "Sec. IV",
        "the paper's rule minus a two-stage learner (competitive features first, then SARSA); "
        "supported means the united architecture does better",
        Above(0.0),
        {"sideboard": ("two-stage",)},
    ),
)

DESIGN = Design(
    name="study",
    title="the paper's claims as variants of its experiments (first edition)",
    cells=tuple(
        _experiment2_cells("sideboard", EXPERIMENT_2)
        + _experiment1_cells()
        + _experiment2_cells("floor", FLOOR_EXPERIMENT_2)
    ),
    seeds=STUDY_SEEDS,
    measure="heldout",
    claims=CLAIMS,
    stages=(_control,),
)

#: Seeds of the yardstick runs (no learning: seeds only resample start poses and noise; the
#: first of the learners' seeds, so the yardsticks face the same held-out starts).
YARDSTICK_SEEDS = tuple(range(5))

#: The yardsticks (``ExperimentConfig.policy``) and what tables call them.
YARDSTICK_LABELS = {
    "oracle": "pose oracle",
    "centroid": "centroid rule",
    "forward": "always forward",
    "random": "random",
}

#: The yardsticks (``ExperimentConfig.policy``): the pose oracle, the one-line centroid rule,
#: always-forward, random actions.
YARDSTICK_POLICIES = tuple(YARDSTICK_LABELS)

#: What the two worlds give away, before any learner (notebook 05): every yardstick in the
#: sideboard and the floor world, :data:`HELDOUT_TRIALS` held-out trials per seed.
YARDSTICKS = Design(
    name="study-yardsticks",
    title="the yardsticks of the study's two worlds (pose oracle, centroid rule, forward, random)",
    cells=tuple(
        Cell(
            f"{world}/{policy}",
            yardstick_config(base, policy, HELDOUT_TRIALS),
            {"world": world, "policy": policy},
            f"{YARDSTICK_LABELS[policy]} ({world} world)",
        )
        for world, base in (("sideboard", EXPERIMENT_2), ("floor", FLOOR_EXPERIMENT_2))
        for policy in YARDSTICK_POLICIES
    ),
    seeds=YARDSTICK_SEEDS,
    measure="heldout",
)

#: The designs of this file (``python -m docking design run study|study-yardsticks``).
DESIGNS = {DESIGN.name: DESIGN, YARDSTICKS.name: YARDSTICKS}

#: The results of the study (the design layer's one shape).
StudyResults = Results


#: Run (or load) the study: :meth:`Design.run` of :data:`DESIGN` (``full``: with its
#: sensitivity cells; ``results_dir``, ``scheduler``, ``workers``, ``progress``).
run_study = DESIGN.run


def run_cells(
    batch,
    seeds=STUDY_SEEDS,
    results_dir=None,
    scheduler=None,
    workers=None,
    progress=True,
    desc="study",
):
    """Run (or load) the cells ``batch`` as a design of their own (for designs that reuse
    the study's cells)."""
    design = Design(desc, desc, tuple(batch), tuple(seeds), "heldout")
    return run_design(
        design,
        full=True,
        results_dir=results_dir,
        scheduler=scheduler,
        workers=workers,
        progress=progress,
    )


def difference(results: Results, key: str, seed: int = 0):
    """``(baseline - cell)`` held-out success with its bootstrap interval, for cell ``key``."""
    cell = results.cell(key)
    return Above().statistic(results.score(cell.baseline), results.score(key), seed=seed)


def rotation_share(results: Results, key: str, seed: int = 0):
    """The share of the baseline's held-out failures gone in cell ``key`` (paired seeds)."""
    return claim_of(CLAIMS, "rotation").interval(results, key, seed=seed)


def share_verdict(ci) -> str:
    """The rotation claim's rule on a share of failures removed (an interval)."""
    return claim_of(CLAIMS, "rotation").rule.decide(ci)


def verdicts(results: Results) -> dict[str, tuple[str, dict[str, str], list[str]]]:
    """Per claim: the overall verdict, the verdict per world, and the evidence."""
    return {c.key: c.verdict(results) for c in CLAIMS}


def verdict_table(results: Results) -> str:
    """The Markdown table of the claims, their verdicts and the numbers behind them."""
    return _table(CLAIMS, results)


def heldout_success(logs: list[TrialLog]) -> np.ndarray:
    """Per seed, the held-out success rate."""
    return np.array([log.success_rate for log in logs])
