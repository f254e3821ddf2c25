"""-0 is 0 (issue 60): ``--network.eps-w -0`` was keyed apart from ``--network.eps-w 0`` (the
configuration's JSON held ``-0.0``), two keys for one run. Every real field is checked by
``docking.validate.check_real``, which returns ``0.0`` for ``-0.0``, so a configuration never
holds a negative zero."""

from __future__ import annotations

import dataclasses
import math

import pytest

from docking.experiments import Curriculum
from docking.network import NetworkConfig
from docking.presets import EXPERIMENT_2
from docking.study import kinds
from docking.study.cli import parse
from docking.validate import check_real


def test_check_real_returns_a_positive_zero():
    for value in (-0.0, 0.0, 0, -0, 0.0 * -1):
        found = check_real("X", "y", value, lo=0)
        assert found == 0.0 and math.copysign(1.0, found) == 1.0, value
    assert check_real("X", "y", -0.5) == -0.5  # a negative number keeps its sign


@pytest.mark.parametrize(
    "make",
    [
        lambda z: dataclasses.replace(EXPERIMENT_2, network=NetworkConfig(eps_w=z)),
        lambda z: dataclasses.replace(EXPERIMENT_2, network=NetworkConfig(eps_q=z)),
        lambda z: dataclasses.replace(EXPERIMENT_2, pretrain_rate=z),
        lambda z: dataclasses.replace(
            EXPERIMENT_2, world=dataclasses.replace(EXPERIMENT_2.world, step_noise_xy=z)
        ),
    ],
    ids=["eps_w", "eps_q", "pretrain_rate", "world.step_noise_xy"],
)
def test_a_negative_zero_field_is_the_configuration_of_zero(make):
    negative, zero = make(-0.0), make(0.0)
    assert kinds.config_json(negative) == kinds.config_json(zero)
    assert "-0.0" not in kinds.config_json(negative)


def test_the_command_lines_minus_zero_is_keyed_as_zero():
    negative = parse(["run", "experiment2", "--network.eps-w", "-0"]).experiment
    zero = parse(["run", "experiment2", "--network.eps-w", "0"]).experiment
    assert math.copysign(1.0, negative.network.eps_w) == 1.0
    assert kinds.run_key(negative, 0) == kinds.run_key(zero, 0)


def test_a_curriculum_of_minus_zero_is_refused_as_zero_is():
    """Where zero is outside a field's range (open at 0), -0 is refused as 0 is."""
    for value in (0.0, -0.0):
        with pytest.raises(ValueError, match="Curriculum.far_initial must be in"):
            Curriculum(far_initial=value)
