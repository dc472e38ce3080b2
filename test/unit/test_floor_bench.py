"""The floor benchmark's judge and tour: misses, phantoms, the white-balance lock against the
true drift, frame drops on request, and a tour that keeps its clearance."""
import math
import random

import numpy as np
import pytest

from can_seeker.evaluation.floor_bench import (EDGE_BINS, PATH_CLEARANCE_M, RoomResult,
                                               ScanScore, TourDriver, bench_config,
                                               clearance_m, score_scan, summary_rows,
                                               tour_targets, white_balance_score)
from can_seeker.sim.realism import PRESETS, spec_from_config
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


def test_the_white_balance_lock_is_judged_on_the_true_drift_beside_no_correction():
    """Two frames: the lock 0.02 off in log R/G on one, exact on the other, against drifts of
    (0.04, 0.04) and (-0.04, 0.04): RMS error 0.5 bin over both ratios and frames, drift 2
    bins."""
    score = ScanScore()
    score.add(white_balance_score((0.06, 0.04), (0.04, 0.04)))
    score.add(white_balance_score((-0.04, 0.04), (-0.04, 0.04)))
    assert score.frames == 0 and score.wb_frames == 2
    assert score.wb_error_bins == pytest.approx(0.5)
    assert score.wb_drift_bins == pytest.approx(2.0)
    room = RoomResult(7, 'look', 'mount')
    room.score.add(score)
    assert '| 0.50 / 2.00 |' in summary_rows([room])[2]
    assert math.isnan(ScanScore().wb_error_bins)
    assert '| - |' in summary_rows([RoomResult(8, 'look', 'mount')])[2]


def test_the_bench_drops_frames_only_when_asked_and_then_as_the_preset_does():
    assert spec_from_config(bench_config(2000, 'harsh', False, False)).camera_drop_rate == 0.0
    kept = spec_from_config(bench_config(2000, 'harsh', False, False, frame_drops=True))
    assert kept.camera_drop_rate == PRESETS['harsh'].camera_drop_rate > 0.0
    assert kept.camera_latency_s == 0.0
