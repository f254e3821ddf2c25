"""What makes it learn: the paper's claims as variants of its experiments (notebook 05).

Every *cell* of the study is an :class:`~docking.experiments.ExperimentConfig` (a variant of
Experiment 1 or 2, in the sideboard world or the floor world) run for :data:`STUDY_SEEDS`,
each network judged on :data:`HELDOUT_TRIALS` held-out trials: start poses, step noise and
action draws from random streams that training, the learning curve and the main test never
use (:func:`docking.experiments.heldout_trials`). A *test-only* cell trains nothing: it
judges the networks of another cell in another world (with a distractor, or without heading
noise) on the same held-out draws, so the comparison is paired. The cells are data; running
them is :func:`run_study` (one sweep, :mod:`docking.sweep`); the statistics are
:mod:`docking.stats`; the verdicts are computed and asserted in the notebook.

Choices named here:

* Experiment 2 variants keep the paper's 2000 training trials; they skip the final 725-trial
  test (``test_trials = 0``: the held-out trials are the measure) and the learning curve,
  except the curriculum cells, whose curves are part of the claim.
* The *core* cells back every verdict of notebook 05 and run in ``make reproduce`` and CI
  (about 130 runs of Experiment 2's size); :func:`cells` with ``full=True`` adds the
  sensitivity cells (eps_W x10, beta_s 10 and 30, the local rule and the distractor
  variants in the floor world, the distractor with W frozen), ``python -m docking study
  --full``.
* ``beta_s`` 10 and 30: the rule absorbs the exact gradient's factor ``beta_s`` into
  ``eps_w`` (notebook 01), so the gradient step is ``eps_w / beta_s``; these cells keep it at
  the paper configuration's ``0.05 / 100`` (``eps_w = 0.005`` and ``0.015``).
* The unmodulated control replaces delta in Eq. (8) by a constant equal to the mean
  ``|delta|`` of the paper configuration's training steps (measured, then run).
* The two-stage learner pre-trains W on the frames of 200 random-walk trials by
  winner-take-all competitive learning (rate 0.05), then runs SARSA with W frozen.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from docking.experiments import (
    Curriculum,
    ExperimentConfig,
    ExperimentResult,
    TrialLog,
    heldout_trials,
)
from docking.network import NetworkConfig
from docking.presets import EXPERIMENT_1, EXPERIMENT_2, FLOOR_WORLD
from docking.world import Distractor, WorldConfig

__all__ = [
    "Cell",
    "FLOOR_EXPERIMENT_2",
    "HELDOUT_TRIALS",
    "STUDY_SEEDS",
    "cells",
    "control_cell",
    "heldout_success",
    "mean_abs_delta",
    "run_cells",
    "run_study",
    "share_verdict",
]

#: Seeds of every cell (verdicts rest on them: at least ten).
STUDY_SEEDS = tuple(range(10))

#: Held-out greedy trials per network.
HELDOUT_TRIALS = 500

#: The red cup of the distractor cells: on the sideboard 0.3 m to the landmark's left (in the
#: floor world on the floor, at the same place).
_CUP = Distractor.cup(y=0.30)
_FLOOR_CUP = Distractor("cylinder", _CUP.size, (_CUP.position[0], 0.30, _CUP.size[1]))

#: Experiment 2 in the floor world: the paper's configuration, its curriculum starting 0.12 m
#: beyond the start region's near edge as in the sideboard world.
FLOOR_EXPERIMENT_2 = dataclasses.replace(
    EXPERIMENT_2,
    name="experiment2-floor",
    world=FLOOR_WORLD,
    curriculum=Curriculum(far_initial=FLOOR_WORLD.start_near + 0.12, grow_trials=1400),
)


@dataclasses.dataclass(frozen=True)
class Cell:
    """One variant of the study.

    Attributes:
      key: Short identifier (``"frozen"``, ``"floor/local"``, ...).
      claim: Which claim of the paper it tests (a key of the notebook's claim table).
      label: What it is, for tables and figures.
      config: The run that trains its networks.
      baseline: The key of the cell it is compared with (the paper's configuration in the same
        world and experiment), or None for that cell itself.
      test_world: For a test-only cell: the world its (the baseline's) networks are judged in;
        None: judged in ``config.heldout_world`` (or ``config.world``) by the run itself.
      core: Part of the study that backs the notebook's verdicts (else a sensitivity cell).
    """

    key: str
    claim: str
    label: str
    config: ExperimentConfig
    baseline: str | None
    test_world: WorldConfig | None = None
    core: bool = True


def _variant(base: ExperimentConfig, name: str, curve: bool = False, **changes):
    """``base`` as a study run: held-out trials, no final test, a curve only if asked."""
    settings = dict(heldout_trials=HELDOUT_TRIALS, test_trials=0, eval_trials=50 if curve else 0)
    return dataclasses.replace(base, name=name, **settings, **changes)


def _net(base: ExperimentConfig, **changes) -> NetworkConfig:
    return dataclasses.replace(base.network, **changes)


def _with_cup(world: WorldConfig) -> WorldConfig:
    cup = _CUP if world.scene == "sideboard" else _FLOOR_CUP
    return dataclasses.replace(world, distractors=(cup,))


def _experiment2_cells(world_key: str, base: ExperimentConfig) -> list[Cell]:
    """The Experiment 2 variants in one world."""
    floor = world_key != "sideboard"
    p = f"{world_key}/" if floor else ""
    name = f"study-{world_key}"
    paper = f"{p}paper"
    near = base.curriculum.far_initial
    eps_w, beta_s = base.network.eps_w, base.network.beta_s
    paper_config = _variant(base, name, True)
    cup_world = _with_cup(base.world)

    def cell(key, claim, label, config, core=True, test_world=None):
        return Cell(f"{p}{key}", claim, label, config, paper, test_world, core)

    def trained(**changes):
        return _variant(base, name, **changes)

    return [
        Cell(paper, "features", "the paper's rule (Eq. 8, non-local)", paper_config, None),
        cell("frozen", "features", "W frozen (eps_W = 0)", trained(network=_net(base, eps_w=0))),
        cell(
            "local",
            "features",
            "local rule (Eq. 8 without the bracket)",
            trained(network=_net(base, rule="local")),
        ),
        cell(
            "none",
            "curriculum",
            "no curriculum (full region from trial 0)",
            _variant(base, name, True, curriculum=Curriculum(near, grow_trials=0)),
        ),
        cell(
            "near-only",
            "curriculum",
            f"trained only near ({base.world.start_near:.2f}-{near:.2f} m)",
            _variant(base, name, True, curriculum=Curriculum(near, far_final=near)),
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
        Cell(
            f"{p}cup-test-frozen",
            "distractor",
            "W frozen, tested with a red cup",
            trained(network=_net(base, eps_w=0)),
            f"{p}frozen",
            cup_world,
            core=not floor,
        ),
        cell(
            "cup-frozen",
            "distractor",
            "red cup in training and test, W frozen",
            trained(world=cup_world, network=_net(base, eps_w=0)),
            core=False,
        ),
        cell(
            "epsW-x10",
            "features",
            f"eps_W x10 ({10 * eps_w:g})",
            trained(network=_net(base, eps_w=10 * eps_w)),
            core=False,
        ),
        cell(
            "beta-10",
            "features",
            "beta_s = 10 (eps_W / beta_s kept)",
            trained(network=_net(base, beta_s=10.0, eps_w=eps_w * 10 / beta_s)),
            core=False,
        ),
        cell(
            "beta-30",
            "features",
            "beta_s = 30 (eps_W / beta_s kept)",
            trained(network=_net(base, beta_s=30.0, eps_w=eps_w * 30 / beta_s)),
            core=False,
        ),
        cell(
            "two-stage",
            "alternative",
            "two-stage: competitive features first, then SARSA",
            trained(network=_net(base, eps_w=0), pretrain_trials=200),
            core=not floor,
        ),
        cell(
            "linear",
            "alternative",
            "linear SARSA on the 320 pixels",
            trained(network=_net(base, n_features=base.network.n_inputs, feature_layer="none")),
            core=not floor,
        ),
    ]


def _experiment1_cells() -> list[Cell]:
    base, name = EXPERIMENT_1, "study-experiment1"
    paper = "exp1/local"
    return [
        Cell(
            paper, "features", "Exp. 1, local rule (the paper's)", _variant(base, name, True), None
        ),
        Cell(
            "exp1/frozen",
            "features",
            "Exp. 1, W frozen",
            _variant(base, name, True, network=_net(base, eps_w=0)),
            paper,
        ),
        Cell(
            "exp1/nonlocal",
            "features",
            "Exp. 1, non-local rule",
            _variant(base, name, True, network=_net(base, rule="nonlocal")),
            paper,
        ),
    ]


def cells(full: bool = False) -> list[Cell]:
    """The study's cells but the unmodulated control (:func:`control_cell`, which needs a
    measured constant): Experiment 2 in the sideboard world, Experiment 1, Experiment 2 in the
    floor world; the core cells only unless ``full``."""
    found = (
        _experiment2_cells("sideboard", EXPERIMENT_2)
        + _experiment1_cells()
        + _experiment2_cells("floor", FLOOR_EXPERIMENT_2)
    )
    return [c for c in found if full or c.core]


def control_cell(constant: float) -> Cell:
    """Eq. (8) with delta replaced by ``constant`` (the paper configuration's mean |delta|)."""
    base = EXPERIMENT_2
    return Cell(
        "constant-delta",
        "delta",
        f"Eq. 8 with a constant {constant:.3g} in place of delta",
        _variant(base, "study-sideboard", network=_net(base, feature_delta=float(constant))),
        "paper",
    )


def mean_abs_delta(results: list[ExperimentResult]) -> float:
    """The mean |delta| over every training step of ``results``."""
    return float(np.mean(np.abs(np.concatenate([r.train.deltas for r in results]))))


def heldout_success(logs: list[TrialLog]) -> np.ndarray:
    """Per seed, the held-out success rate."""
    return np.array([log.success_rate for log in logs])


@dataclasses.dataclass
class StudyResults:
    """What :func:`run_study` returns.

    Attributes:
      cells: Every cell run, the control with its measured constant last.
      runs: ``{cell key: runs in seed order}`` (a test-only cell: its baseline's runs).
      heldout: ``{cell key: held-out trial logs in seed order}``.
    """

    cells: list[Cell]
    runs: dict[str, list[ExperimentResult]]
    heldout: dict[str, list[TrialLog]]

    def cell(self, key: str) -> Cell:
        return next(c for c in self.cells if c.key == key)

    def success(self, key: str) -> np.ndarray:
        """Per seed, the held-out success rate of cell ``key``."""
        return heldout_success(self.heldout[key])


def run_cells(
    batch: list[Cell],
    seeds=STUDY_SEEDS,
    results_dir=None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    desc: str = "study",
) -> StudyResults:
    """Run (or load) the cells of ``batch`` for ``seeds`` in one sweep (:mod:`docking.sweep`;
    stored runs are loaded, not rerun), then judge the test-only cells' networks (their
    baselines', which must be in ``batch``) in their worlds."""
    from docking.sweep import run_configs

    trained = {c.key: c.config for c in batch if c.test_world is None}
    runs = run_configs(
        trained,
        seeds,
        results_dir,
        scheduler=scheduler,
        workers=workers,
        progress=progress,
        desc=desc,
    )
    return _judged(batch, runs)


def _judged(batch: list[Cell], runs: dict[str, list[ExperimentResult]]) -> StudyResults:
    """The results of ``batch`` from the runs of its trained cells: their held-out trials,
    and the test-only cells' held-out trials of their baselines' networks in their worlds."""
    runs, heldout = dict(runs), {}
    for c in batch:
        if c.test_world is None:
            heldout[c.key] = [r.heldout for r in runs[c.key]]
        else:
            runs[c.key] = runs[c.baseline]
            heldout[c.key] = [
                heldout_trials(r.config, r.seed, r.network, c.test_world) for r in runs[c.key]
            ]
    return StudyResults(list(batch), runs, heldout)


def run_study(
    full: bool = False,
    results_dir=None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
) -> StudyResults:
    """Run (or load) every cell for :data:`STUDY_SEEDS` in one sweep (:func:`run_cells`),
    then the unmodulated control, whose constant is the mean |delta| of the paper
    configuration's runs; then judge the test-only cells' networks in their worlds."""
    options = dict(results_dir=results_dir, scheduler=scheduler, workers=workers)
    trained = [c for c in cells(full) if c.test_world is None]
    first = run_cells(trained, progress=progress, **options)
    control = control_cell(mean_abs_delta(first.runs["paper"]))
    second = run_cells([control], progress=progress, desc="study (control)", **options)
    return _judged(cells(full) + [control], {**first.runs, **second.runs})


# ------------------------------------------------------------------------------------------
# Claims and verdicts.
# ------------------------------------------------------------------------------------------

#: Half-width of the equivalence margin for "does not affect performance" (percentage points
#: of held-out success, as a fraction): a distractor's effect counts as none if the whole 95%
#: interval of the difference lies within +-2 pp. Our choice, fixed before the runs.
EQUIVALENCE_MARGIN = 0.02

#: The share of failures that must go when heading noise is removed at test, for "most
#: failures come from uncorrected rotation": more than half ("most").
ROTATION_SHARE = 0.5


@dataclasses.dataclass(frozen=True)
class Claim:
    """A claim of the paper, in its words, and how a cell tests it.

    Attributes:
      key: Identifier (the cells' ``claim``).
      words: The paper's words.
      source: Where the paper says it.
      test: How the study tests it (the variant and the rule of the verdict).
    """

    key: str
    words: str
    source: str
    test: str


CLAIMS = (
    Claim(
        "features",
        "the delta signal modulates not only the action but at the same time the feature "
        "weights ... the network learns interpretable visual features",
        "Abstract; Sec. II-A, III",
        "held-out success of the paper's rule minus W frozen (eps_W = 0): supported if the 95% "
        "interval lies above 0",
    ),
    Claim(
        "delta",
        "the feature layer learns only when there is learning progress ... unimportant "
        "components of the data are not correlated with the learning progress",
        "Sec. II-A",
        "the paper's rule minus Eq. 8 with delta replaced by a constant of the same mean "
        "magnitude: supported if the interval lies above 0",
    ),
    Claim(
        "curriculum",
        "the region is incrementally enlarged during learning ... Learning from Easy Missions",
        "Sec. II-C",
        "the paper's growing region minus no curriculum (the full region from trial 0) and "
        "minus never growing (trained near, tested on the full region): supported if both "
        "intervals lie above 0, contradicted if either lies below 0",
    ),
    Claim(
        "rotation",
        "this noise can lead to a rotation of the robot, which currently is not compensated "
        "... This is actually the reason for most of the unsuccessful trials",
        "Sec. III, Fig. 5",
        f"the share of the paper's networks' held-out failures that go when the same trials "
        f"run without heading noise: supported if its interval lies above {ROTATION_SHARE:.0%}",
    ),
    Claim(
        "distractor",
        "noise (e.g. other red objects within the visual field) should not affect performance. "
        "This criterion is also fulfilled by our model",
        "Sec. IV",
        f"the paper's networks tested with a red cup beside the landmark minus without: "
        f"supported if the interval lies within +-{100 * EQUIVALENCE_MARGIN:.0f} pp",
    ),
    Claim(
        "alternative",
        "a self-organizing map could be used to first learn the visual features ... they would "
        "be separate parts that would need to be linked ad hoc",
        "Sec. IV",
        "the paper's rule minus a two-stage learner (competitive features first, then SARSA): "
        "supported (the united architecture does better) if the interval lies above 0",
    ),
)

#: The cells each claim's verdict rests on, per world (each compared with its baseline, the
#: paper's configuration in that world). With several cells in a world, the claim is
#: supported there only if every comparison supports it, and contradicted if any contradicts
#: it.
VERDICT_CELLS = {
    "features": {"sideboard": ("frozen",), "floor": ("floor/frozen",)},
    "delta": {"sideboard": ("constant-delta",)},
    "curriculum": {"sideboard": ("none", "near-only"), "floor": ("floor/none", "floor/near-only")},
    "rotation": {"sideboard": ("no-yaw-noise",), "floor": ("floor/no-yaw-noise",)},
    "distractor": {"sideboard": ("cup-test",), "floor": ("floor/cup-test",)},
    "alternative": {"sideboard": ("two-stage",)},
}


def difference(study: StudyResults, key: str, seed: int = 0):
    """``(paper - cell)`` held-out success with its bootstrap interval (seeds resampled per
    group), for the cell ``key`` and its baseline."""
    from docking.stats import difference_ci

    cell = study.cell(key)
    return difference_ci(study.success(cell.baseline), study.success(key), seed=seed)


def rotation_share(study: StudyResults, key: str, seed: int = 0):
    """The share of the baseline's held-out failures that are gone when the same trials run
    without heading noise (cell ``key``), with a bootstrap interval over seeds (the seeds
    resampled jointly: the trials are paired)."""
    from docking.stats import removed_share_ci

    base = 1 - study.success(study.cell(key).baseline)
    quiet = 1 - study.success(key)
    return removed_share_ci(quiet, base, paired=True, seed=seed)


def share_verdict(ci) -> str:
    """The rotation claim's rule on a share of failures removed (an interval): "supported" if
    it lies above :data:`ROTATION_SHARE` ("most"), "contradicted" if below, else "not
    supported"."""
    if ci.low > ROTATION_SHARE:
        return "supported"
    return "contradicted" if ci.high < ROTATION_SHARE else "not supported"


def verdict(claim: str, study: StudyResults, key: str) -> str:
    """The verdict of ``claim`` from cell ``key``: ``"supported"``, ``"not supported"`` (the
    interval does not decide it either way) or ``"contradicted"`` (the interval lies on the
    other side of the claim's bound), by the rule in :data:`CLAIMS`."""
    if claim == "rotation":
        return share_verdict(rotation_share(study, key))
    ci = difference(study, key)
    if claim == "distractor":
        m = EQUIVALENCE_MARGIN
        if -m <= ci.low and ci.high <= m:
            return "supported"
        return "contradicted" if ci.low > 0 or ci.high < 0 else "not supported"
    if ci.low > 0:
        return "supported"
    return "contradicted" if ci.high < 0 else "not supported"


def overall(verdicts: dict[str, str]) -> str:
    """One verdict from the per-world verdicts ``{world: verdict}``: the common one, or
    "supported only in the ... world" when they differ."""
    values = set(verdicts.values())
    if len(values) == 1:
        return values.pop()
    where = [w for w, v in verdicts.items() if v == "supported"]
    if where:
        return f"supported only in the {' and '.join(where)} world"
    return "; ".join(f"{v} ({w} world)" for w, v in verdicts.items())


def verdicts(study: StudyResults) -> dict[str, tuple[str, dict[str, str], list[str]]]:
    """Per claim: the overall verdict, the verdict per world, and the evidence (each
    comparison's number with its 95% interval, as text)."""
    out = {}
    for claim in CLAIMS:
        per_world, evidence = {}, []
        for world, keys in VERDICT_CELLS[claim.key].items():
            found = [verdict(claim.key, study, key) for key in keys]
            if all(v == "supported" for v in found):
                per_world[world] = "supported"
            elif "contradicted" in found:
                per_world[world] = "contradicted"
            else:
                per_world[world] = "not supported"
            for key in keys:
                if claim.key == "rotation":
                    number = f"{rotation_share(study, key).format(unit='%')} of the failures go"
                else:
                    number = f"{difference(study, key).format(unit=' pp')} vs {key}"
                evidence.append(f"{world}: {number}")
        out[claim.key] = (overall(per_world), per_world, evidence)
    return out


def verdict_table(study: StudyResults) -> str:
    """The Markdown table of the claims, their verdicts and the numbers behind them."""
    found = verdicts(study)
    rows = [
        f"| {c.words} ({c.source}) | {found[c.key][0]} | {'; '.join(found[c.key][2])} |"
        for c in CLAIMS
    ]
    header = "| claim, in the paper's words | verdict | the number (95% interval) |\n|---|---|---|"
    return header + "\n" + "\n".join(rows)
