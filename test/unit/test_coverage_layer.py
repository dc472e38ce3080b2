"""The coverage layer: the camera's floor wedge, stopped by obstacles, and the cells about a
goal given up."""
import math

import numpy as np

from can_seeker.control.costmap.coverage_layer import CoverageLayer
from can_seeker.control.costmap.grid import GridGeometry
from can_seeker.control.costmap.obstacle_layer import ObstacleLayer
from can_seeker.control.costmap.scan_rays import ScanRays


def test_camera_coverage_is_a_wedge_that_stops_at_obstacles():
    grid = GridGeometry(0.1, 8.0)
    obstacles, coverage = ObstacleLayer(grid), CoverageLayer(grid)
    obstacles.update(ScanRays(grid, (0.0, 0.0), np.array([[1.05, 0.0]]), np.array([True]),
                              0.0, 0.0))
    coverage.mark_wedge((0.0, 0.0), 0.0, math.radians(25.0), 0.3, 2.5, obstacles)
    seen = coverage.seen
    assert seen[grid.cell_of(0.8, 0.0)]
    assert not seen[grid.cell_of(1.8, 0.0)]          # behind the obstacle
    assert seen[grid.cell_of(2.0, 0.6)]              # beside its shadow
    assert not seen[grid.cell_of(0.1, 0.0)]          # nearer than the bottom row
    assert not seen[grid.cell_of(1.0, 1.5)]          # outside the field of view
    assert not seen[grid.cell_of(2.8, 0.0)]          # beyond the range


def test_a_wedge_without_depth_covers_nothing_and_clearing_forgets_the_coverage():
    grid = GridGeometry(0.1, 4.0)
    obstacles, coverage = ObstacleLayer(grid), CoverageLayer(grid)
    coverage.mark_wedge((0.0, 0.0), 0.0, 0.5, 1.0, 1.0, obstacles)
    assert not coverage.seen.any()
    coverage.mark_wedge((0.0, 0.0), 0.0, 0.5, 0.0, 1.0, obstacles)
    assert coverage.seen.sum() > 10
    coverage.clear()
    assert not coverage.seen.any()


def test_a_goal_given_up_covers_the_five_by_five_cells_about_it():
    grid = GridGeometry(0.1, 4.0)
    coverage = CoverageLayer(grid)
    coverage.cover_around(grid.cell_of(0.05, 0.05))
    ix, iy = np.nonzero(coverage.seen)
    assert coverage.seen.sum() == 25
    assert (ix.min(), ix.max(), iy.min(), iy.max()) == (18, 22, 18, 22)
    coverage.cover_around((0, 0))                    # clipped at the grid's edge
    assert coverage.seen.sum() == 25 + 9
