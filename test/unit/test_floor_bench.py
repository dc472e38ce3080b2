"""The floor benchmark's judge and tour: misses, phantoms and a tour that keeps its clearance."""
import math
import random

import numpy as np

from can_seeker.evaluation.floor_bench import (EDGE_BINS, PATH_CLEARANCE_M, TourDriver,
                                               clearance_m, score_scan, tour_targets)
from can_seeker.sim.scene import Scene, Solid, room_walls


def padded(values):
    """``values`` with EDGE_BINS unjudged bins either side."""
    return np.concatenate((np.full(EDGE_BINS, np.inf), values, np.full(EDGE_BINS, np.inf)))


def test_a_wall_the_scan_does_not_report_is_a_miss_and_a_short_range_a_phantom():
    truth = padded([0.6, 0.6, 0.6, 2.0, np.inf, 0.1])
    ranges = padded([0.62, np.inf, np.nan, 1.0, 1.2, 0.1])
    score = score_scan(ranges, truth, range_min_m=0.3, range_max_m=2.5, near_m=1.0,
                       min_missed_bins=2)
    assert score.near_bins == 3            # the 0.1 m truth lies below the visible floor
    assert score.missed == 2               # inf and NaN (hidden) where a wall stands at 0.6 m
    assert score.checked_bins == 5
    assert score.phantoms == 2             # 1.0 for 2.0, and 1.2 where the floor is free to 2.5
    assert score.frames_with_miss == 1


def test_ranges_within_the_tolerance_are_neither_misses_nor_phantoms():
    truth = padded([0.5, 1.0, 3.0, np.inf])
    ranges = padded([0.59, 0.91, 2.6, np.inf])
    score = score_scan(ranges, truth, range_min_m=0.3, range_max_m=3.5, near_m=1.0)
    assert (score.missed, score.phantoms, score.frames_with_miss) == (0, 0, 0)


def test_the_tour_keeps_its_clearance_and_goes_near_things():
    obstacle = Solid('obstacle_0', 'box', 1.0, 1.0, 0.4, 0.4, 0.3, 0.0)
    scene = Scene((-3.0, 3.0, -3.0, 3.0), room_walls(6.0, 6.0), (obstacle,), can_xy=(-1.0, 0.5))
    points = [(0.0, 0.0)]
    targets = tour_targets(scene, random.Random(1))
    for _ in range(60):
        points.append(next(targets))
    clearances = [float(clearance_m(scene, *point)) for point in points[1:]]
    assert min(clearances) >= PATH_CLEARANCE_M
    assert sum(clearance < 0.32 for clearance in clearances) >= 15
    for start, end in zip(points, points[1:]):
        for fraction in np.linspace(0.0, 1.0, 50):
            x = start[0] + fraction * (end[0] - start[0])
            y = start[1] + fraction * (end[1] - start[1])
            assert clearance_m(scene, x, y) >= PATH_CLEARANCE_M - 1e-9


def test_the_driver_turns_toward_its_target_then_drives():
    scene = Scene((-3.0, 3.0, -3.0, 3.0), room_walls(6.0, 6.0))
    driver = TourDriver(scene, random.Random(2))
    target = driver._target
    heading = math.atan2(target[1], target[0])
    linear, angular = driver.command(0.0, 0.0, heading + math.pi / 2.0)
    assert linear == 0.0 and angular < 0.0
    linear, angular = driver.command(0.0, 0.0, heading)
    assert linear > 0.0 and abs(angular) < 1e-9
