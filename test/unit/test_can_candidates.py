"""Small free-standing objects in an all-round scan: where the can may stand."""
import math

import numpy as np

from can_seeker.control import can_candidates
from can_seeker.control.navigation import CameraView, Navigator, Pose2D
from kinematic_world import World


def test_a_can_in_front_of_a_wall_is_a_candidate_and_the_wall_and_a_box_are_not():
    world = World(3.0, [(1.5, 0.0, 0.033), (0.0, 1.5, 0.3)])
    ends, hits = world.scan(count=720, fov_rad=2 * math.pi)
    found = can_candidates.small_objects(ends, hits, (0.0, 0.0))
    assert len(found) == 1
    assert np.linalg.norm(found[0] - (1.5, 0.0)) < 0.03


def test_a_camera_scan_is_not_all_round_and_a_lidar_scan_is():
    angles = np.linspace(-0.5, 0.5, 100)
    camera = np.stack((np.cos(angles), np.sin(angles)), axis=-1)
    assert not can_candidates.all_round(camera, (0.0, 0.0))
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    assert can_candidates.all_round(np.stack((np.cos(angles), np.sin(angles)), axis=-1),
                                    (0.0, 0.0))


def test_the_navigator_remembers_candidates_once_until_the_camera_covers_them():
    world = World(3.0, [(1.5, 1.0, 0.033)])
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    for _ in range(3):
        ends, hits = world.scan(count=720, fov_rad=2 * math.pi)
        navigator.add_scan(ends, hits, (0.0, 0.0), navigator.pose)
    assert len(navigator.world.candidates.points) == 1
    candidate = navigator.unviewed_candidate()
    assert np.linalg.norm(candidate - (1.5, 1.0)) < 0.05
    view = CameraView(0.1, 0.0, 0.0, math.radians(29.0), 0.3, 1.0)
    navigator.mark_seen(view)                                   # 1.7 m away: too far
    assert navigator.unviewed_candidate() is not None
    navigator.pose = Pose2D(0.8, 0.5, math.atan2(0.5, 0.7))
    navigator.mark_seen(view)                                   # 0.76 m away, dead ahead
    assert navigator.unviewed_candidate() is None
    assert navigator.world.candidates.is_viewed(candidate)


def test_an_obstacle_between_the_camera_and_a_candidate_hides_it():
    world = World(3.0, [(1.5, 0.0, 0.033), (0.8, 0.0, 0.1)])
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    navigator.world.candidates.points.append(np.array([1.5, 0.0]))
    navigator.world.candidates.viewed.append(False)
    ends, hits = world.scan(count=100, fov_rad=1.0)             # a camera-like scan: the post
    navigator.add_scan(ends, hits, (0.0, 0.0), navigator.pose)
    navigator.mark_seen(CameraView(0.1, 0.0, 0.0, math.radians(29.0), 0.3, 2.0))
    assert navigator.unviewed_candidate() is not None


def test_a_camera_scan_adds_no_candidates():
    world = World(3.0, [(1.5, 0.0, 0.033)])
    navigator = Navigator(0.1, 10.0, 0.165, 0.15, 0.05)
    navigator.pose = Pose2D(0.0, 0.0, 0.0)
    ends, hits = world.scan(count=100, fov_rad=1.0)
    navigator.add_scan(ends, hits, (0.0, 0.0), navigator.pose)
    assert navigator.world.candidates.points == []
