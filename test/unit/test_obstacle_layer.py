"""The obstacle layer: hits remembered with their points, cleared by rays through them, kept
in the blind zone, aged there, and contacts no ray clears."""
import numpy as np

from can_seeker.control.costmap.grid import GridGeometry
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.control.costmap.scan_rays import ScanRays


def make_layer(size_m=4.0):
    grid = GridGeometry(0.1, size_m)
    return grid, ObstacleLayer(grid)


def scan(grid, layer, ends, hits, clear_from_m=0.0, elapsed_s=0.0, origin=(0.0, 0.0)):
    layer.update(ScanRays(grid, origin, np.array(ends, float), np.array(hits, bool),
                          clear_from_m, elapsed_s))


def occupied(grid, layer, x_m, y_m):
    return bool(layer.occupied_at(*grid.cell_of(x_m, y_m)))


def test_a_scan_marks_its_hit_and_clears_the_floor_before_it():
    grid, layer = make_layer()
    scan(grid, layer, [[1.0, 0.0]], [True])
    assert occupied(grid, layer, 1.0, 0.0)
    assert layer.evidence[grid.cell_of(0.5, 0.0)] < 0
    assert not occupied(grid, layer, 0.85, 0.0)


def test_a_hit_is_remembered_then_cleared_by_rays_through_it():
    grid, layer = make_layer()
    for _ in range(3):
        scan(grid, layer, [[1.0, 0.0]], [True])
    for _ in range(3):
        scan(grid, layer, [[1.6, 0.0]], [False])
    assert occupied(grid, layer, 1.0, 0.0)              # a few misses do not erase it
    for _ in range(10):
        scan(grid, layer, [[1.6, 0.0]], [False])
    assert not occupied(grid, layer, 1.0, 0.0)
    assert layer.points_near((0.0, 0.0), 2.0, np.inf).size == 0


def test_a_scan_does_not_clear_what_is_remembered_in_its_blind_zone():
    grid, layer = make_layer()
    scan(grid, layer, [[0.3, 0.0]], [True])
    for _ in range(5):
        scan(grid, layer, [[2.0, 0.0]], [False], clear_from_m=0.5)
    assert occupied(grid, layer, 0.3, 0.0)
    assert not occupied(grid, layer, 1.0, 0.0)


def test_of_several_hits_in_a_cell_the_nearest_to_the_sensor_is_remembered():
    grid, layer = make_layer()
    scan(grid, layer, [[0.58, 0.02], [0.52, 0.03], [0.55, 0.08]], [True, True, True])
    assert layer.points_near((0.0, 0.0), 1.0, np.inf).tolist() == [[0.52, 0.03]]


def test_an_obstacle_in_the_blind_zone_ages_and_is_left_out_once_too_old():
    grid, layer = make_layer()
    scan(grid, layer, [[0.3, 0.0]], [True])
    for _ in range(4):
        scan(grid, layer, [[0.0, 2.0]], [False], clear_from_m=0.5, elapsed_s=1.0)
    assert layer.blind_s[grid.cell_of(0.3, 0.0)] == 4.0
    assert len(layer.points_near((0.0, 0.0), 1.0, 5.0)) == 1
    assert len(layer.points_near((0.0, 0.0), 1.0, 4.0)) == 0       # dropped, still occupied
    assert occupied(grid, layer, 0.3, 0.0)
    scan(grid, layer, [[0.3, 0.0]], [True], clear_from_m=0.1, elapsed_s=1.0)
    assert layer.blind_s[grid.cell_of(0.3, 0.0)] == 0.0           # a hit starts it again


def test_a_hit_at_the_blind_zone_s_edge_keeps_the_remembered_cells_along_its_ray():
    grid, layer = make_layer()
    scan(grid, layer, [[0.25, 0.0]], [True])
    scan(grid, layer, [[0.405, 0.0]], [True], clear_from_m=0.4, elapsed_s=3.0)
    assert layer.blind_s[grid.cell_of(0.25, 0.0)] == 0.0
    scan(grid, layer, [[0.6, 0.0]], [True], clear_from_m=0.4, elapsed_s=3.0)
    assert layer.blind_s[grid.cell_of(0.25, 0.0)] == 3.0


def test_a_contact_stays_whatever_rays_pass_through_it_until_cleared():
    grid, layer = make_layer()
    cell = grid.cell_of(0.5, 0.0)
    layer.add_contact(cell, (0.52, 0.01))
    for _ in range(20):
        scan(grid, layer, [[1.5, 0.0]], [False], elapsed_s=1.0)
    assert layer.occupied_at(*cell) and layer.evidence[cell] < 0
    assert layer.points_near((0.0, 0.0), 1.0, 0.0).tolist() == [[0.52, 0.01]]
    layer.clear()
    assert not layer.occupied_at(*cell)


def test_cells_near_a_recent_obstacle_are_found_within_the_reach():
    grid, layer = make_layer()
    scan(grid, layer, [[0.45, 0.05]], [True])
    cx, cy = np.meshgrid(np.arange(grid.cells), np.arange(grid.cells), indexing='ij')
    near = layer.near_recent(cx, cy, 0.3, np.inf)
    assert near[grid.cell_of(0.45, 0.3)] and near[grid.cell_of(0.7, 0.05)]
    assert not near[grid.cell_of(0.45, 0.45)] and not near[grid.cell_of(0.0, 0.0)]
    assert not layer.near_recent(cx, cy, 0.3, 0.0).any()         # too old for any
