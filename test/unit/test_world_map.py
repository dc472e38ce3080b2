"""The world map: its layers updated together from scans, the camera and the robot's body,
and its queries (OccupancyGrid values, blocked cells, clearing)."""
import math

import numpy as np

from can_seeker.control.costmap.world_map import WorldMap
from test_navigation import nudged


def test_obstacle_values_tell_obstacle_observed_floor_and_unknown_apart():
    world = WorldMap(0.1, 4.0)
    world.update_from_scan((0.0, 0.0), np.array([[1.0, 0.0]]), np.array([True]))

    def value(x_m, y_m):
        ix, iy = world.cell_of(x_m, y_m)
        return world.obstacle_values()[iy, ix]       # rows along y
    assert world.obstacle_values().dtype == np.int8
    assert value(1.0, 0.0) == 100
    assert value(0.5, 0.0) == 0       # the ray passed over it
    assert value(0.5, 1.0) == -1      # nothing looked there
    assert value(-1.0, 0.0) == -1
    world.update_from_footprint((-1.0, 0.0), 0.2)             # the robot's body stood there
    assert value(-1.0, 0.0) == 0

def test_rays_a_few_ulps_off_mark_the_same_cells():
    """Rays from a cell corner to cell boundaries, each a whole number of ray steps long and
    some blind for the first few steps, mark the same cells when their origin and ends move a
    few ulps either way (as a sin or cos from another CPU's SIMD kernels moves them); so does
    the camera's wedge from there."""
    origin = np.array([0.1, -0.2])
    offsets = np.array([[0.6, 0.0], [0.0, 0.5], [-0.3, 0.4], [0.3, -0.4], [0.8, 0.6],
                        [-0.6, -0.8], [0.0, -0.45], [-0.45, 0.0], [0.3, 0.0], [0.0, 0.35]])
    hits = np.array([False, True, False, True, False, True, False, True, True, True])

    def layers(origin_steps, end_steps):
        world = WorldMap(0.1, 4.0)
        for stamp_s in (0.0, 1.0):
            world.update_from_scan(nudged(origin, origin_steps),
                                   nudged(origin + offsets, end_steps), hits, 0.25, stamp_s)
        world.update_from_camera(nudged(origin, origin_steps), nudged(math.pi / 2.0, end_steps),
                                 math.radians(30.0), 0.25, 1.0)
        return (world.obstacles.evidence, world.floor.observed, world.coverage.seen,
                world.obstacles.blind_s, world.floor.blind_disc_s)

    exact = layers(0, 0)
    assert (exact[0] < 0).sum() > 10 and (exact[0] > 0).sum() == hits.sum() and exact[2].sum() > 10
    for steps in (-4, -3, -2, -1, 1, 2, 3, 4):
        for origin_steps, end_steps in ((steps, steps), (steps, -steps), (0, steps)):
            for layer, expected in zip(layers(origin_steps, end_steps), exact):
                np.testing.assert_array_equal(layer, expected)

def test_coverage_values_have_rows_along_y():
    world = WorldMap(0.1, 2.0)
    world.update_from_scan((0.0, 0.0), np.array([[0.55, -0.35]]), np.array([True]))
    world.update_from_camera((0.0, 0.0), math.pi / 2.0, 0.2, 0.0, 0.5)
    values = world.coverage_values()
    ix, iy = world.cell_of(0.55, -0.35)
    assert values[iy, ix] == 100
    ix, iy = world.cell_of(0.0, 0.3)
    assert values[iy, ix] == 0
    assert values[world.cell_of(-0.5, -0.5)[::-1]] == -1


def test_blocked_cells_grow_obstacles_by_the_clearance_and_leave_out_the_excluded():
    world = WorldMap(0.1, 4.0)
    world.update_from_scan((0.0, 0.0), np.array([[1.05, 0.05], [0.05, 1.05]]),
                           np.array([True, True]))
    blocked = world.blocked_cells(0.25)
    assert blocked[world.cell_of(1.05, 0.05)] and blocked[world.cell_of(0.85, 0.05)]
    assert blocked[world.cell_of(1.05, 0.25)] and not blocked[world.cell_of(0.75, 0.05)]
    assert not blocked[world.cell_of(0.85, 0.25)]     # two cells each way: 0.28 m apart
    kept = world.blocked_cells(0.25, exclude_xy=(1.0, 0.0), exclude_radius_m=0.2)
    assert not kept[world.cell_of(1.05, 0.05)] and kept[world.cell_of(0.05, 0.85)]
    assert world.occupied()[world.cell_of(1.05, 0.05)]           # the map keeps it


def test_clearing_forgets_every_layer_and_each_change_is_counted():
    world = WorldMap(0.1, 4.0)
    world.update_from_scan((0.0, 0.0), np.array([[1.0, 0.0]]), np.array([True]), 0.2, 0.0, 'a')
    world.update_from_camera((0.0, 0.0), 0.0, 0.5, 0.0, 1.5)
    world.add_contact((0.0, 1.0))
    world.candidates.add(np.array([[1.5, 1.5]]))
    world.update_from_footprint((9.0, 9.0), 0.2)                   # off the grid: no change
    assert world.changes == 2 and world.covered_count() > 0 and world.is_seen((0.5, 0.0))
    world.clear()
    assert world.changes == 3 and world.scan_s == {} and world.candidates.points == []
    assert not world.occupied().any() and world.covered_count() == 0
    assert not world.floor.observed.any() and not world.known().any()


def test_giving_up_a_goal_covers_its_cells_and_the_places_near_it():
    world = WorldMap(0.1, 4.0)
    world.candidates.add(np.array([[1.5, 0.0]]))
    world.give_up_at((1.45, 0.0))
    assert world.is_seen((1.6, 0.2)) and not world.is_seen((1.8, 0.0))
    assert world.candidates.is_viewed((1.5, 0.0))
