"""Shared builders of design cells: the held-out protocol, the variants of a configuration,
Experiment 2 in another world, linear SARSA, the distractor, the yardsticks and a tuning budget
(:class:`Tuning`).

Design files build their cells from these, so that a variant means the same thing in every
design (and two designs asking for the same run share it in the store).
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable

import numpy as np

from docking.experiments import Curriculum, ExperimentConfig
from docking.network import NetworkConfig
from docking.presets import EXPERIMENT_2
from docking.scene import Distractor, WorldConfig

#: Seeds of a cell whose verdicts rest on them (at least ten).
SEEDS = tuple(range(10))

#: Seeds of a yardstick cell (a fixed policy: its spread over seeds is small).
YARDSTICK_SEEDS = tuple(range(5))

#: Held-out greedy trials per network.
HELDOUT_TRIALS = 500

#: The red cup of the distractor cells: on the sideboard 0.3 m to the landmark's left (in the
#: floor world on the floor, at the same place).
CUP = Distractor.cup(y=0.30)
FLOOR_CUP = Distractor("cylinder", CUP.size, (CUP.position[0], 0.30, CUP.size[1]))

#: The yardsticks (``ExperimentConfig.policy``) and what tables call them.
YARDSTICK_LABELS = {
    "oracle": "pose oracle",
    "centroid": "centroid rule",
    "forward": "always forward",
    "random": "random",
}


def variant(base: ExperimentConfig, name: str, curve: bool = False, **changes):
    """``base`` as a study run stored under ``name``: :data:`HELDOUT_TRIALS` held-out
    trials, no final test, a learning curve (50 test trials per point) only if ``curve``."""
    settings = dict(heldout_trials=HELDOUT_TRIALS, test_trials=0, eval_trials=50 if curve else 0)
    return dataclasses.replace(base, name=name, **settings, **changes)


def net(base: ExperimentConfig, **changes) -> NetworkConfig:
    """``base``'s network with ``changes``."""
    return dataclasses.replace(base.network, **changes)


def experiment2_in(world: WorldConfig, name: str) -> ExperimentConfig:
    """Experiment 2 in ``world``, stored under ``name``: its curriculum starts 0.12 m beyond
    the start region's near edge (as Experiment 2's does in the sideboard world) and grows
    over 1400 trials."""
    curriculum = Curriculum(far_initial=world.start_near + 0.12, grow_trials=1400)
    return dataclasses.replace(EXPERIMENT_2, name=name, world=world, curriculum=curriculum)


def linear_sarsa(base: ExperimentConfig, **changes) -> NetworkConfig:
    """``base``'s network as linear SARSA on the same pixels (with ``changes``): one feature
    unit per input, no feature layer, so Q reads the input directly."""
    return net(base, n_features=base.network.n_inputs, feature_layer="none", **changes)


def with_cup(world: WorldConfig) -> WorldConfig:
    """``world`` with the red cup (:data:`CUP`, or :data:`FLOOR_CUP` in the floor world)."""
    return dataclasses.replace(
        world, distractors=(CUP if world.scene == "sideboard" else FLOOR_CUP,)
    )


@dataclasses.dataclass(frozen=True)
class Tuning:
    """The same tuning budget for every learner: a successive halving over each learner's
    grid of settings (its default first). Round 1 trains every setting once, on the first
    tuning seed; the best :attr:`keep` (by mean held-out success on the tuning seeds' own
    held-out streams, which no judged run uses; ties: grid order) train again on the other
    tuning seeds (round 2); the best mean over all tuning seeds is the tuned setting, judged
    as the cell ``{world}/{learner}-tuned``.

    Attributes:
      worlds, grids: The worlds tuned in; ``{learner: [setting, ...]}``.
      seeds: The tuning seeds.
      keep: Settings kept for round 2.
      make: ``make(world, learner, **setting)``: the learner's configuration.
      cell: ``cell(world, variant, config, label, seeds=...)``: a design's cell.
      judged_seeds: ``{learner: seeds}`` of a tuned cell with fewer seeds than the design's.
    """

    worlds: tuple[str, ...]
    grids: dict
    seeds: tuple[int, ...]
    keep: int
    make: Callable
    cell: Callable
    judged_seeds: dict = dataclasses.field(default_factory=dict)

    @property
    def runs(self) -> int:
        """Full training runs per learner and world (the same for every learner)."""
        (size,) = {len(g) for g in self.grids.values()}
        return size + self.keep * (len(self.seeds) - 1)

    def round1(self, world: str, learner: str) -> list:
        """Round 1's cells of ``learner`` in ``world``: ``tune-{learner}-{i}``."""
        return [
            self.cell(
                world,
                f"tune-{learner}-{i}",
                self.make(world, learner, **setting),
                f"{learner} {setting}",
                seeds=self.seeds[:1],
            )
            for i, setting in enumerate(self.grids[learner])
        ]

    def stages(self) -> tuple[Callable, Callable]:
        """A design's stages: round 2, then the tuned learners."""
        return (self._round_2, self._tuned)

    def _round_2(self, results) -> list:
        found = []
        for world, learner in itertools.product(self.worlds, self.grids):
            keys = [f"{world}/tune-{learner}-{i}" for i in range(len(self.grids[learner]))]
            ranked = sorted(keys, key=lambda k: (-float(np.mean(results.score(k))), _index(k)))
            for key in ranked[: self.keep]:
                c = results.cell(key)
                found.append(dataclasses.replace(c, key=f"{key}/round2", seeds=self.seeds[1:]))
        return found

    def tuned_setting(self, results, world: str, learner: str) -> int:
        """The index in the learner's grid of its tuned setting in ``world``."""
        keys = [
            c.key[: -len("/round2")]
            for c in results.cells
            if c.key.endswith("/round2")
            and c["world"] == world
            and c["variant"].startswith(f"tune-{learner}-")
        ]

        def mean_all(k):
            return float(np.mean(np.concatenate([results.score(k), results.score(f"{k}/round2")])))

        return _index(sorted(keys, key=lambda k: (-mean_all(k), _index(k)))[0])

    def _tuned(self, results) -> list:
        found = []
        for world, learner in itertools.product(self.worlds, self.grids):
            setting = self.grids[learner][self.tuned_setting(results, world, learner)]
            found.append(
                self.cell(
                    world,
                    f"{learner}-tuned",
                    self.make(world, learner, **setting),
                    f"{learner}, tuned: {setting}",
                    seeds=self.judged_seeds.get(learner),
                )
            )
        return found


def _index(key: str) -> int:
    """The grid index of a tuning cell's key (``.../tune-{learner}-{i}``)."""
    return int(key.rsplit("-", 1)[1])
