"""The candidate layer: places where the can may stand, remembered once, in view of the camera
unless an obstacle hides them, and given up with a goal near them."""
import math

import numpy as np

from can_seeker.control.costmap.candidate_layer import CandidateLayer
from can_seeker.control.costmap.grid import GridGeometry
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.control.costmap.scan_rays import ScanRays


def make_layers():
    grid = GridGeometry(0.1, 8.0)
    return grid, CandidateLayer(grid), ObstacleLayer(grid)


def test_a_place_is_remembered_once_within_a_cell_and_one_off_the_grid_counts_as_viewed():
    _, candidates, _ = make_layers()
    candidates.add(np.array([[1.5, 0.0], [1.55, 0.05], [2.0, 0.0], [9.0, 0.0]]))
    assert [p.tolist() for p in candidates.points] == [[1.5, 0.0], [2.0, 0.0], [9.0, 0.0]]
    assert candidates.viewed == [False, False, True]
    assert not candidates.is_viewed((1.5, 0.0)) and candidates.is_viewed((3.0, 3.0))
    nearest = candidates.nearest_unviewed(lambda xy: math.hypot(xy[0] - 2.2, xy[1]))
    assert nearest.tolist() == [2.0, 0.0]


def test_a_place_is_in_view_within_the_wedge_unless_an_obstacle_hides_it():
    grid, candidates, obstacles = make_layers()
    candidates.add(np.array([[1.5, 0.0], [0.0, 1.5], [3.0, 0.0], [1.5, 0.8]]))
    obstacles.update(ScanRays(grid, (0.0, 0.0), np.array([[0.7, 0.38]]), np.array([True]),
                              0.0, 0.0))
    candidates.mark_in_view(np.zeros(2), 0.0, math.radians(35.0), 0.3, 2.0, obstacles)
    # ahead: viewed; beside: out of the field of view; too far; hidden behind the obstacle
    assert candidates.viewed == [True, False, False, False]
    candidates.mark_in_view(np.zeros(2), math.pi / 2.0, math.radians(35.0), 0.3, 2.0,
                            obstacles)
    assert candidates.viewed == [True, True, False, False]


def test_the_obstacle_returns_of_the_can_itself_do_not_hide_it():
    grid, candidates, obstacles = make_layers()
    candidates.add(np.array([[1.5, 0.0]]))
    obstacles.update(ScanRays(grid, (0.0, 0.0), np.array([[1.46, 0.0]]), np.array([True]),
                              0.0, 0.0))
    candidates.mark_in_view(np.zeros(2), 0.0, 0.5, 0.3, 2.0, obstacles)
    assert candidates.viewed == [True]


def test_giving_up_a_goal_gives_up_the_places_near_it_and_clearing_forgets_them():
    _, candidates, _ = make_layers()
    candidates.add(np.array([[1.5, 0.0], [2.5, 0.0]]))
    candidates.give_up_near((1.5 + candidates.reach_m * 0.9, 0.0))
    assert candidates.viewed == [True, False]
    assert candidates.nearest_unviewed(lambda xy: 0.0).tolist() == [2.5, 0.0]
    candidates.clear()
    assert candidates.points == [] and candidates.nearest_unviewed(lambda xy: 0.0) is None
