"""The unknown-floor layer: floor observed by rays and the robot's body, the rest unknown, and
unknown floor in a scan's blind disc taken for floor after the wait, except beside an
obstacle."""
import math

import numpy as np

from can_seeker.control.costmap.grid import GridGeometry
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.control.costmap.scan_rays import ScanRays
from can_seeker.control.costmap.unknown_floor_layer import UnknownFloorLayer


def make_layers(size_m=4.0):
    grid = GridGeometry(0.1, size_m)
    return grid, UnknownFloorLayer(grid), ObstacleLayer(grid)


def scan(grid, layers, ends, hits, clear_from_m=0.0, elapsed_s=0.0):
    rays = ScanRays(grid, (0.0, 0.0), np.array(ends, float), np.array(hits, bool),
                    clear_from_m, elapsed_s)
    for layer in layers:
        layer.update(rays)


def unknown_near(floor, obstacles, xy, wait_s=np.inf, memory_s=np.inf):
    points = floor.unknown_points((0.0, 0.0), 1.2, obstacles, wait_s, memory_s)
    return bool((np.linalg.norm(points - np.asarray(xy), axis=1) < 0.01).any())


def test_a_ray_observes_the_floor_up_to_its_hit_and_the_rest_stays_unknown():
    grid, floor, obstacles = make_layers()
    scan(grid, (floor, obstacles), [[1.0, 0.0]], [True])
    assert not unknown_near(floor, obstacles, (0.525, 0.025))          # along the ray
    assert unknown_near(floor, obstacles, (0.525, 0.425))              # nothing looked there
    assert not unknown_near(floor, obstacles, (1.025, 0.025))          # the obstacle's cell
    observed = floor.observed_cells()
    assert observed[grid.cell_of(0.5, 0.0)] and not observed[grid.cell_of(0.5, 0.4)]


def test_the_robot_s_body_observes_the_floor_under_it():
    grid, floor, obstacles = make_layers()
    assert unknown_near(floor, obstacles, (0.075, 0.075))
    assert floor.mark_disc((0.0, 0.0), 0.165)
    assert not unknown_near(floor, obstacles, (0.075, 0.075))
    assert unknown_near(floor, obstacles, (0.225, 0.025))               # beyond the body
    assert not floor.mark_disc((9.0, 9.0), 0.165)                       # off the grid


def test_unknown_floor_in_the_blind_disc_is_taken_for_floor_after_the_wait():
    grid, floor, obstacles = make_layers()
    angles = np.radians(np.arange(-30.0, 30.5, 1.0))
    ahead = 1.5 * np.stack((np.cos(angles), np.sin(angles)), axis=-1)
    beside, farther = (0.075, 0.325), (0.075, 0.625)       # within 0.45 m, beyond it
    scan(grid, (floor, obstacles), ahead, np.zeros(len(ahead), bool), 0.45)
    for _ in range(4):
        scan(grid, (floor, obstacles), ahead, np.zeros(len(ahead), bool), 0.45, elapsed_s=1.0)
    assert unknown_near(floor, obstacles, beside, wait_s=5.0)
    scan(grid, (floor, obstacles), ahead, np.zeros(len(ahead), bool), 0.45, elapsed_s=1.0)
    assert not unknown_near(floor, obstacles, beside, wait_s=5.0)
    assert unknown_near(floor, obstacles, farther, wait_s=5.0)
    assert unknown_near(floor, obstacles, beside)                        # no wait given


def test_unknown_floor_beside_a_remembered_obstacle_is_not_taken_for_floor_by_waiting():
    grid, floor, obstacles = make_layers()
    scan(grid, (floor, obstacles), [[0.45, 0.25]], [True])
    beside, elsewhere = (0.525, 0.475), (-0.425, -0.325)      # fine cell centres
    for _ in range(8):
        scan(grid, (floor, obstacles), [[0.0, -2.0]], [False], 0.8, elapsed_s=1.0)
    assert unknown_near(floor, obstacles, beside, wait_s=5.0, memory_s=15.0)
    assert not unknown_near(floor, obstacles, elsewhere, wait_s=5.0, memory_s=15.0)
    assert not unknown_near(floor, obstacles, beside, wait_s=5.0, memory_s=8.0)  # let go
    assert math.isclose(floor.blind_disc_s[grid.cell_of(*elsewhere)], 8.0)
