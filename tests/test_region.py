"""Tests of docking.region.StartRegion: geometry, containment, sampling, validation, and that
the environment samples from it with the draws in the documented order."""

import dataclasses

import numpy as np
import pytest

from docking.region import StartRegion
from docking.world import WorldConfig


def test_geometry_of_a_30_degree_wedge():
    region = StartRegion(near=0.5, far=2.0, half_angle_deg=30.0, yaw_deg=5.0)
    slope = np.sqrt(3) / 3  # tan 30 deg, written out independently
    assert region.half_width(1.0) == pytest.approx(slope)
    np.testing.assert_allclose(region.half_width(np.array([0.5, 2.0])), [0.5 * slope, 2 * slope])
    np.testing.assert_allclose(
        region.corners(),
        [(-0.5, 0.5 * slope), (-2.0, 2 * slope), (-2.0, -2 * slope), (-0.5, -0.5 * slope)],
    )
    flat = StartRegion(near=0.5, far=0.7, half_angle_deg=0.0)
    assert flat.half_width(0.6) == 0.0 and flat.contains((-0.6, 0.0, 0.0))


def test_contains():
    region = StartRegion(near=0.5, far=2.0, half_angle_deg=30.0)
    slope = np.sqrt(3) / 3
    assert region.contains((-1.0, 0.99 * slope, 0.0))
    assert not region.contains((-1.0, 1.01 * slope, 0.0))
    assert not region.contains((-1.0, -1.01 * slope, 0.0))
    assert not region.contains((-0.49, 0.0, 0.0))  # nearer than the near edge
    assert not region.contains((-2.01, 0.0, 0.0))  # beyond the far edge
    assert not region.contains((1.0, 0.0, 0.0))  # behind the landmark
    for corner in region.corners():
        assert region.contains(corner)


def test_samples_are_uniform_over_the_area_and_seeded():
    region = StartRegion(near=0.5, far=1.5, half_angle_deg=14.0, yaw_deg=5.0)
    rng = np.random.default_rng(0)
    poses = np.array([region.sample(rng) for _ in range(4000)])
    assert all(region.contains(p) for p in poses)
    assert np.all(np.abs(np.degrees(poses[:, 2])) <= 5.0)
    # Uniform over the area: the share beyond the middle distance d_m is
    # (far^2 - d_m^2) / (far^2 - near^2) = (2.25 - 1) / 2 = 0.625, not 0.5.
    assert np.mean(-poses[:, 0] > 1.0) == pytest.approx(0.625, abs=0.03)
    # Lateral position uniform across the width at each distance.
    u = poses[:, 1] / region.half_width(-poses[:, 0])
    assert np.mean(u > 0) == pytest.approx(0.5, abs=0.03)
    assert np.mean(np.abs(u) > 0.5) == pytest.approx(0.5, abs=0.03)
    np.testing.assert_array_equal(
        region.sample(np.random.default_rng(7)), region.sample(np.random.default_rng(7))
    )


def test_sample_draws_distance_then_lateral_then_heading():
    region = StartRegion(near=0.6, far=0.9, half_angle_deg=10.0, yaw_deg=4.0)
    pose = region.sample(np.random.default_rng(3))
    draws = np.random.default_rng(3)
    d = np.sqrt(draws.uniform(0.6**2, 0.9**2))
    y = draws.uniform(-1.0, 1.0) * d * region.tan
    yaw = np.radians(draws.uniform(-4.0, 4.0))
    np.testing.assert_array_equal(pose, [-d, y, yaw])


def test_of_world_and_with_edges():
    world = WorldConfig()
    region = StartRegion.of(world)
    assert (region.near, region.far) == (world.start_near, world.start_far)
    assert (region.half_angle_deg, region.yaw_deg) == (
        world.start_half_angle_deg,
        world.start_yaw_deg,
    )
    assert StartRegion.of(world, far=0.9).far == 0.9
    narrower = region.with_edges(0.6, 0.8)
    assert narrower == dataclasses.replace(region, near=0.6, far=0.8)
    with pytest.raises(dataclasses.FrozenInstanceError):
        region.near = 1.0


@pytest.mark.parametrize(
    "kwargs,field",
    [
        (dict(near=0.0, far=1.0, half_angle_deg=10.0), "StartRegion.near"),
        (dict(near=1.0, far=0.5, half_angle_deg=10.0), "StartRegion.far"),
        (dict(near=0.5, far=1.0, half_angle_deg=45.0), "StartRegion.half_angle_deg"),
        (dict(near=0.5, far=1.0, half_angle_deg=-1.0), "StartRegion.half_angle_deg"),
        (dict(near=0.5, far=1.0, half_angle_deg=10.0, yaw_deg=-1.0), "StartRegion.yaw_deg"),
        (dict(near="0.5", far=1.0, half_angle_deg=10.0), "StartRegion.near"),
    ],
)
def test_bad_fields_are_named(kwargs, field):
    with pytest.raises(ValueError, match=field):
        StartRegion(**kwargs)
