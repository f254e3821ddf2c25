"""Where the robot can collide with the room's furniture (issue 42): never in the start
region or on the straight walk from a start to the dock, at home or in any place of
relocation; but the table of "along the wall" stands where a wandering robot can reach it."""

import dataclasses

import numpy as np
import pytest

from docking.presets import EXPERIMENT_2, RELOCATIONS
from docking.study import analysis

HOME = EXPERIMENT_2.world
PLACES = {
    "home": HOME,
    **{
        p: dataclasses.replace(HOME, room=m.room, room_shift=m.room_shift)
        for p, m in RELOCATIONS.items()
    },
}


@pytest.mark.parametrize("place", PLACES)
def test_no_furniture_in_the_start_region_or_on_the_way_to_the_dock(place):
    poses = analysis.walking_poses(PLACES[place], 60)
    assert len(poses) == 600
    assert not analysis.furniture_contacts(PLACES[place], poses).any()


def test_along_the_wall_the_table_stands_where_a_wandering_robot_walks():
    """The held-out trials that differ from home along the wall begin to diverge near
    (-1.20, 0.70): off the way to the dock, at the shifted table's edge."""
    contact = analysis.furniture_contacts(PLACES["along the wall"], [[-1.2, 0.7, 0.0]])
    at_home = analysis.furniture_contacts(HOME, [[-1.2, 0.7, 0.0]])
    assert contact.tolist() == [True] and at_home.tolist() == [False]


def test_a_pose_inside_the_sideboard_is_a_contact():
    assert analysis.furniture_contacts(HOME, np.array([[-0.05, 0.0, 0.0]])).all()
