"""The third edition's addendum: the contest tuned until every optimum is bracketed (issue 40).

**These rules were committed before any run of the addendum** and are not changed after
seeing its runs (their record, ``rules/third-edition-addendum.*``: the rules text pinned by
digest at the rules' commit, this module's code and the gap rule's as they were then;
tests/test_records.py holds the live rules to it and replays them on the ledger's runs).
A new, labelled analysis beside the third edition
(:mod:`docking.study.designs.third_edition`), whose tables stay as they were run.

The question: once each SARSA learner is tuned on the same knobs of Eq. (4)-(8) (eps_Q, the
exploration temperature beta_a in training, and eps_W where there is a W) by a search that
extends until every chosen value is interior (or a stated limit is reached), does linear
SARSA's lead over the paper's learner remain in the floor and the Nao-like worlds (the rule
of the third edition: closed if its 95% interval lies below :data:`GAP_CLOSED`)? And which
part of the paper's learner breaks: the representation (W's partition of the views) or
learning Q on it (notebook 08's decomposition reads the networks kept here)?

The search (:class:`BracketedTuning`), the same for both learners in each world:

1. *Round 1*: 9 settings of each learner, three log-spaced values per knob
   (:data:`START`): linear SARSA's full 3 x 3 grid; the paper's learner's 3 x 3 x 3 grid
   as its orthogonal 9-run fraction (L9: every pair of two knobs' values once). Each setting
   on :data:`ROUND1_SEEDS` tuning seeds (the paper's learner's seed-to-seed spread is 8.7 pp
   in the third edition's floor world: no setting is ranked on one run).
2. *Extension* (:data:`EXTENSIONS` stages at most): the best setting so far (by its mean
   over its round-1 seeds; ties: the earlier evaluated) is the incumbent; every neighbour of
   it on the knobs' log ladders (:data:`LADDERS`; one rung up or down one knob, the others
   kept) not yet evaluated is evaluated on the same seeds. A stage with no such neighbour
   ends the search (the incumbent is a local optimum on the lattice); a rung outside a
   ladder is a stated limit (:data:`LIMITS`).
3. *Round 2*: the best :data:`ROUND_2` settings train again on further tuning seeds, as
   many as the budget leaves: ``(BUDGET - runs so far) // ROUND_2`` each. The tuned setting
   is the best mean over all its tuning seeds.

Every learner has :data:`BUDGET` training runs per world for tuning (round 2 spends what the
first stages leave, so each learner uses all of it). The tuned learners are judged on
:data:`SEEDS`, fresh, on matched seeds (each run its own seed's held-out stream). PPO is not
tuned again (the budget, see the notebook): its third-edition setting per world
(:data:`PPO_SETTINGS`) trains for as many environment steps as the tuned paper learner's
judged runs took in that world, on average (measured in the last stage). The last stage also
runs the paper's tuned learner with W initialised from views (:data:`PRETRAIN_TRIALS`
random-walk trials of competitive learning, i.e. online k-means, before SARSA) and the same
with W then frozen: SARSA on a fixed partition of the views.

Cut for the budget (20 h): the sideboard world (the gap closed there already), PPO's
tuning, and the yardsticks (the third edition's serve: same worlds, same held-out protocol).
"""

from __future__ import annotations

import dataclasses
import itertools
from typing import TYPE_CHECKING

import numpy as np

from docking.presets import FLOOR_WORLD, NAO_WORLD
from docking.study.design import Cell, Design
from docking.study.designs.builders import experiment2_in, linear_sarsa, net, variant
from docking.study.ppo import PPOConfig

if TYPE_CHECKING:
    from docking.study.designs.addendum_report import Decomposition

NAME = "third-edition-addendum"
#: The judged seeds: fresh (no run of the package used a seed from 4020 up before).
SEEDS = tuple(range(5000, 5010))
#: The tuning seeds (round 1 uses the first :data:`ROUND1_SEEDS`, round 2 the next ones).
TUNING_SEEDS = tuple(range(5900, 5930))
ROUND1_SEEDS = 2
#: Training runs per learner and world for tuning, every stage included.
BUDGET = 66
EXTENSIONS = 5
ROUND_2 = 3
#: The gap rule (the third edition's): closed if linear SARSA's lead over the tuned paper
#: learner has its 95% interval below 5 pp, remains if above.
GAP_CLOSED = 0.05
ALPHA = 0.05
#: Random-walk trials of competitive learning before SARSA (the levers' cells).
PRETRAIN_TRIALS = 200
WORLDS = {"floor": FLOOR_WORLD, "nao": NAO_WORLD}
LEARNERS = ("paper", "linear")
#: Each knob's log-spaced ladder: the values the search may reach.
LADDERS = {
    "eps_q": (0.003, 0.01, 0.03, 0.1, 0.3, 1.0),
    "beta_a_train": (0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0),
    "eps_w": (0.05, 0.15, 0.5, 1.5, 5.0, 15.0, 50.0),
}
#: Why a ladder ends where it does (a value at a ladder's end is "at a stated limit").
LIMITS = {
    "eps_q": (
        "0.003: a tenth of the third edition's smallest value",
        "1.0: one update replaces a winner's Q by its target; normalised LMS diverges past 2",
    ),
    "beta_a_train": (
        "0.5: actions nearly uniform at Q's scale (rewards of 1)",
        "100: the test temperature; beyond it training is as greedy as testing",
    ),
    "eps_w": (
        "0.05: the third edition's default",
        "50: W's rows are renormalised after each update, so beyond this an update replaces "
        "the winner's row by the current input's direction",
    ),
}
#: Round 1's three values per knob (the middle rungs around the third edition's choices).
START = {"eps_q": (0.03, 0.1, 0.3), "beta_a_train": (2.0, 5.0, 10.0), "eps_w": (0.15, 0.5, 1.5)}
KNOBS = {"paper": ("eps_q", "beta_a_train", "eps_w"), "linear": ("eps_q", "beta_a_train")}
#: PPO's third-edition tuned setting in each world (its tables: notebook 07).
PPO_SETTINGS = {
    "floor": dict(learning_rate=1e-3, rollouts=32),
    "nao": dict(learning_rate=3e-4, rollouts=16),
}
#: PPO's copies of the world (its default): its steps are a multiple of it.
PPO_ENVS = 16


def learner_config(world: str, learner: str, **setting):
    """The learner ``learner`` of ``world`` with ``setting`` (knob values)."""
    base = experiment2_in(WORLDS[world], NAME)
    if learner == "ppo":
        from docking.study.designs.builders import HELDOUT_TRIALS

        return PPOConfig(name=NAME, world=WORLDS[world], heldout_trials=HELDOUT_TRIALS, **setting)
    make = linear_sarsa if learner == "linear" else net
    return variant(base, NAME, network=make(base, **setting))


def ppo_matched(world: str, mean_steps: float, name: str) -> Cell:
    """PPO's cell ``{world}/ppo-matched`` of design ``name``: its setting of ``world``
    (:data:`PPO_SETTINGS`) trained for ``mean_steps`` (the tuned paper learner's mean training
    steps) rounded to a multiple of :data:`PPO_ENVS`."""
    steps = PPO_ENVS * int(round(mean_steps / PPO_ENVS))
    config = learner_config(world, "ppo", steps=steps, envs=PPO_ENVS, **PPO_SETTINGS[world])
    return Cell(
        f"{world}/ppo-matched",
        dataclasses.replace(config, name=name),
        {"world": world, "variant": "ppo-matched", "learner": "ppo"},
        f"PPO at the paper learner's {steps} training steps",
    )


def round1_settings(learner: str) -> list[dict]:
    """Round 1's 9 settings: the full grid of two knobs, or the L9 fraction of three."""
    knobs = KNOBS[learner]
    if len(knobs) == 2:
        levels = list(itertools.product(range(3), repeat=2))
    else:  # L9: the third knob's level is the sum of the first two's, mod 3
        levels = [(a, b, (a + b) % 3) for a, b in itertools.product(range(3), repeat=2)]
    return [{k: START[k][i] for k, i in zip(knobs, row, strict=True)} for row in levels]


def tag(setting: dict) -> str:
    """A setting's name in cell keys (``eps_q=0.1,beta_a_train=5``)."""
    return ",".join(f"{k}={v:g}" for k, v in setting.items())


def neighbours(setting: dict) -> list[tuple[dict, str | None]]:
    """Each setting one rung up or down one knob's ladder from ``setting``, with None; or,
    where the ladder ends, ``setting`` itself with the limit's text."""
    found = []
    for knob, value in setting.items():
        ladder = LADDERS[knob]
        i = ladder.index(value)
        for step, end in ((-1, 0), (1, 1)):
            if 0 <= i + step < len(ladder):
                found.append(({**setting, knob: ladder[i + step]}, None))
            else:
                found.append((setting, f"{knob} {LIMITS[knob][end]}"))
    return found


@dataclasses.dataclass(frozen=True)
class BracketedTuning:
    """The addendum's search (see the module docstring) as a design's stages."""

    worlds: tuple[str, ...]
    learners: tuple[str, ...]

    # -- cells ------------------------------------------------------------------------------
    def _cell(self, world, learner, setting, suffix="", seeds=None) -> Cell:
        return Cell(
            f"{world}/tune-{learner}/{tag(setting)}{suffix}",
            learner_config(world, learner, **setting),
            {"world": world, "variant": f"tune-{learner}", "learner": learner, **setting},
            f"{learner} {tag(setting)}",
            seeds=seeds if seeds is not None else TUNING_SEEDS[:ROUND1_SEEDS],
        )

    def round1(self) -> list[Cell]:
        return [
            self._cell(w, learner, s)
            for w in self.worlds
            for learner in self.learners
            for s in round1_settings(learner)
        ]

    # -- reading the results --------------------------------------------------------------
    @staticmethod
    def evaluated(results, world: str, learner: str) -> list[tuple[dict, float]]:
        """Every setting of round 1 and the extensions, in the order evaluated, with its
        mean held-out success over the round-1 seeds."""
        return [
            (
                {k: c.coords[k] for k in KNOBS[learner]},
                float(np.mean(results.score(c.key))),
            )
            for c in results.cells
            if c.coords.get("variant") == f"tune-{learner}"
            and c["world"] == world
            and not c.key.endswith("/round2")
        ]

    @classmethod
    def incumbent(cls, results, world: str, learner: str) -> dict:
        found = cls.evaluated(results, world, learner)
        best = max(range(len(found)), key=lambda i: (found[i][1], -i))
        return found[best][0]

    def runs_used(self, results, world: str, learner: str) -> int:
        return sum(
            len(c.seeds)
            for c in results.cells
            if c.coords.get("variant") == f"tune-{learner}" and c["world"] == world
        )

    # -- stages ---------------------------------------------------------------------------
    def _extend(self, results) -> list[Cell]:
        found = []
        for world, learner in itertools.product(self.worlds, self.learners):
            tried = [s for s, _ in self.evaluated(results, world, learner)]
            used = self.runs_used(results, world, learner)
            for setting, limit in neighbours(self.incumbent(results, world, learner)):
                if limit is None and setting not in tried and used + ROUND1_SEEDS <= BUDGET:
                    used += ROUND1_SEEDS
                    tried.append(setting)
                    found.append(self._cell(world, learner, setting))
        return found

    def round2_seeds(self, results, world: str, learner: str) -> tuple[int, ...]:
        n = (BUDGET - self.runs_used(results, world, learner)) // ROUND_2
        return TUNING_SEEDS[ROUND1_SEEDS : ROUND1_SEEDS + max(n, 0)]

    def _round_2(self, results) -> list[Cell]:
        found = []
        for world, learner in itertools.product(self.worlds, self.learners):
            seeds = self.round2_seeds(results, world, learner)
            ranked = sorted(
                enumerate(self.evaluated(results, world, learner)), key=lambda e: (-e[1][1], e[0])
            )
            if seeds:
                found += [
                    self._cell(world, learner, s, "/round2", seeds)
                    for _, (s, _) in ranked[:ROUND_2]
                ]
        return found

    @staticmethod
    def all_seeds(results, key: str) -> np.ndarray:
        """A tuning setting's success over every tuning seed it ran (rounds 1 and 2)."""
        keys = {c.key for c in results.cells}
        parts = [results.score(key)]
        if f"{key}/round2" in keys:
            parts.append(results.score(f"{key}/round2"))
        return np.concatenate(parts)

    def tuned(self, results, world: str, learner: str) -> dict:
        """The tuned setting: of the round-2 settings, the best mean over all their tuning
        seeds (ties: the better round-1 rank); the incumbent if round 2 had no seeds."""
        finalists = [
            c.key[: -len("/round2")]
            for c in results.cells
            if c.key.endswith("/round2")
            and c["world"] == world
            and c.coords.get("variant") == f"tune-{learner}"
        ]
        if not finalists:
            return self.incumbent(results, world, learner)
        best = max(
            range(len(finalists)),
            key=lambda i: (float(np.mean(self.all_seeds(results, finalists[i]))), -i),
        )
        return {k: results.cell(finalists[best]).coords[k] for k in KNOBS[learner]}

    def _tuned(self, results) -> list[Cell]:
        return [
            Cell(
                f"{world}/{learner}-tuned",
                learner_config(world, learner, **self.tuned(results, world, learner)),
                {"world": world, "variant": f"{learner}-tuned", "learner": learner},
                f"{learner}, tuned: {tag(self.tuned(results, world, learner))}",
            )
            for world, learner in itertools.product(self.worlds, self.learners)
        ]

    def stages(self) -> tuple:
        return (*[self._extend] * EXTENSIONS, self._round_2, self._tuned, _matched_and_levers)


def position(results, world: str, learner: str, knob: str) -> tuple[tuple[float, ...], str]:
    """Where the tuned value of ``knob`` lies: the values tried on the line through the tuned
    setting (the other knobs at their tuned values), and ``"interior"`` (tried values on
    both sides), ``"at its limit: ..."`` (the ladder's end, with :data:`LIMITS`' reason) or
    ``"at the edge: the search stopped"`` (stages or budget ran out first)."""
    tuned = TUNING.tuned(results, world, learner)
    line = sorted(
        {
            s[knob]
            for s, _ in TUNING.evaluated(results, world, learner)
            if all(s[k] == tuned[k] for k in KNOBS[learner] if k != knob)
        }
    )
    value, ladder = tuned[knob], LADDERS[knob]
    if line[0] < value < line[-1]:
        return tuple(line), "interior"
    for end, rung in ((0, ladder[0]), (1, ladder[-1])):
        if value == rung and value == (line[0], line[-1])[end]:
            return tuple(line), f"at its limit: {LIMITS[knob][end]}"
    return tuple(line), "at the edge: the search stopped"


def training_steps(results, key: str) -> np.ndarray:
    """Per seed, the environment steps of a learner cell's training trials."""
    return np.array([int(np.sum(r.train.steps)) for r in results.runs[key]])


def decomposition(results, worlds, n_trials: int = 300, seed: int = 0) -> list[Decomposition]:
    """Per world of ``worlds`` (names of the addendum's worlds):
    :class:`docking.study.designs.addendum_report.Decomposition` from
    the addendum's runs (the networks of ``paper-tuned`` and ``views-frozen``, which its
    ledger table keeps), on the views the pose oracle labels on ``n_trials`` trials of the
    runs' world from its stream ``seed`` (:func:`docking.study.analysis.oracle_views`); the
    oracle-labelled success of each run is kept in the store and the committed ledger
    (:func:`docking.study.derived.oracle_labelled_success`)."""
    from docking.study.analysis import oracle_views, partition_purity
    from docking.study.derived import oracle_labelled_success
    from docking.study.designs.addendum_report import Decomposition

    found = []
    for world in worlds:
        paper, fixed = results.runs[f"{world}/paper-tuned"], results.runs[f"{world}/views-frozen"]
        places = {r.config.world for r in (*paper, *fixed)}
        if len(places) != 1:
            raise ValueError(f"decomposition: the runs of {world!r} were trained in several worlds")
        views = oracle_views(places.pop(), n_trials, seed)

        def labelled(runs, views=views):
            return np.array([oracle_labelled_success(r, n_trials, seed, views) for r in runs])

        found.append(
            Decomposition(
                world,
                results.score(f"{world}/linear-tuned"),
                results.score(f"{world}/paper-tuned"),
                labelled(paper),
                np.array([partition_purity(r.network, views) for r in paper]),
                results.score(f"{world}/views-frozen"),
                labelled(fixed),
            )
        )
    return found


def _matched_and_levers(results) -> list[Cell]:
    """PPO at the tuned paper learner's mean training steps; W initialised from views."""
    found = []
    for world in WORLDS:
        # the paper learner's mean training steps, to a whole number of PPO's world copies
        mean = float(np.mean(training_steps(results, f"{world}/paper-tuned")))
        steps = PPO_ENVS * int(round(mean / PPO_ENVS))
        ppo = learner_config(world, "ppo", steps=steps, envs=PPO_ENVS, **PPO_SETTINGS[world])
        label = f"PPO at the paper learner's {steps} training steps"
        found.append(
            Cell(
                f"{world}/ppo-matched",
                ppo,
                {"world": world, "variant": "ppo-matched", "learner": "ppo"},
                label,
            )
        )
        tuned = results.cell(f"{world}/paper-tuned").config
        views = dataclasses.replace(
            tuned, pretrain_trials=PRETRAIN_TRIALS, pretrain_rule="competitive"
        )
        frozen = dataclasses.replace(views, network=dataclasses.replace(views.network, eps_w=0.0))
        for key, config, label in (
            ("views-init", views, "tuned, W initialised from views (k-means)"),
            ("views-frozen", frozen, "tuned, W from views then frozen"),
        ):
            found.append(
                Cell(
                    f"{world}/{key}",
                    config,
                    {"world": world, "variant": key, "learner": "paper"},
                    label,
                    baseline=f"{world}/paper-tuned",
                )
            )
    return found


TUNING = BracketedTuning(tuple(WORLDS), LEARNERS)

#: The networks kept whole in the ledger's table (the decomposition reads them).
NETWORK_CELLS = ("paper-tuned", "views-init", "views-frozen")

DESIGN = Design(
    name=NAME,
    title="the third edition's addendum: every learner tuned to a bracketed optimum",
    cells=tuple(TUNING.round1()),
    seeds=SEEDS,
    measure="heldout",
    stages=TUNING.stages(),
    alpha=ALPHA,
    networks={f"{w}/{v}": SEEDS for w in WORLDS for v in NETWORK_CELLS},
)


def replayed(results) -> dict:
    """What the rules reach beyond the claims, as data (its record's replay): the gap rule's
    verdicts (:func:`docking.study.report.contest_gaps`)."""
    from docking.study.report import contest_gaps

    return {"gaps": [g.as_data() for g in contest_gaps(results, WORLDS, GAP_CLOSED)]}


#: The constants that are rules (:func:`docking.study.designs.rules_data`).
RULES = (
    "SEEDS TUNING_SEEDS ROUND1_SEEDS BUDGET EXTENSIONS ROUND_2 GAP_CLOSED ALPHA "
    "PRETRAIN_TRIALS LADDERS LIMITS START KNOBS PPO_SETTINGS PPO_ENVS NETWORK_CELLS"
).split()
