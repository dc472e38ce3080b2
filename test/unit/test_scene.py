"""The world description: rooms, random obstacles and cans, world files, free space, sight."""
import math
import pathlib

import numpy as np
import pytest
import yaml

from can_seeker.camera_geometry import camera_pose_from_mount
from can_seeker.camera_mount import CameraMount
from can_seeker.params import defaults
from can_seeker.sim.appearance import random_appearance
from can_seeker.sim.lidar import LidarSpec
from can_seeker.sim.scene import (CAN_CLEARANCE_M, CAN_RADIUS_M, OBSTACLE_RGBA, ROBOT_RADIUS_M,
                                  START_CLEARANCE_M, Scene, Solid, can_visible, empty_bounds,
                                  reachable_floor, room_walls, scene_from_dict)
from can_seeker.sim.simulation import PARAMS, checked_config, scene_for
from can_seeker.sim.world import CameraSpec

WORLDS = pathlib.Path(__file__).resolve().parents[2] / 'worlds'


def config_with(**overrides):
    warnings = []
    return checked_config(defaults(PARAMS, overrides), warnings.append,
                          [str(WORLDS)]), warnings


def test_box_and_cylinder_distances():
    box = Solid('b', 'box', 1.0, 0.0, 0.4, 0.2, 0.3, math.radians(90.0))
    assert box.distance_m(1.0, 0.5) == pytest.approx(0.3)
    assert box.distance_m(1.3, 0.0) == pytest.approx(0.2)
    assert box.distance_m(1.0, 0.0) == pytest.approx(-0.1)
    assert box.distance_m(1.2, 0.3) == pytest.approx(math.hypot(0.1, 0.1))
    cylinder = Solid('c', 'cylinder', 0.0, 2.0, 0.5, 0.5, 0.3)
    assert cylinder.distance_m(np.array([0.0, 1.0]), np.array([1.0, 2.0])) == pytest.approx(
        [0.75, 0.75])


def test_room_walls_enclose_the_room():
    scene = Scene((-3.0, 3.0, -2.0, 2.0), room_walls(6.0, 4.0))
    assert scene.clearance_m(0.0, 0.0) == pytest.approx(2.0)
    assert scene.clearance_m(2.9, 0.0) == pytest.approx(0.1)
    for x_m, y_m in ((3.05, 0.0), (-3.05, 1.0), (0.0, 2.05), (1.0, -2.05), (3.05, 2.05)):
        assert scene.clearance_m(x_m, y_m) < 0.0


@pytest.mark.parametrize('seed', range(60))
def test_random_rooms_keep_the_start_and_the_can_clear(seed):
    config, warnings = config_with(world='room', seed=seed)
    scene = config.scene
    assert not warnings
    assert len(scene.walls) == 4 and len(scene.obstacles) == 6
    for obstacle in scene.obstacles:
        assert obstacle.distance_m(0.0, 0.0) >= START_CLEARANCE_M
        assert 0.1 <= obstacle.size_x_m <= 0.5 and 0.1 <= obstacle.size_y_m <= 0.5
        assert scene.inside_bounds(obstacle.x_m, obstacle.y_m, obstacle.bounding_radius_m)
    can_x, can_y = scene.can_xy
    assert scene.clearance_m(can_x, can_y) >= CAN_RADIUS_M + CAN_CLEARANCE_M - 1e-9
    assert math.hypot(can_x, can_y) >= 0.5
    xs, ys, reachable = reachable_floor(scene)
    grid_x, grid_y = np.meshgrid(xs, ys)
    assert np.hypot(grid_x - can_x, grid_y - can_y)[reachable].min() <= (
        CAN_RADIUS_M + ROBOT_RADIUS_M + 0.3)
    assert scene_for(config, seed, warnings.append) == scene


def test_random_cans_go_everywhere_in_the_room():
    cans = np.array([config_with(world='room', seed=seed)[0].scene.can_xy
                     for seed in range(100)])
    assert np.abs(cans).max() > 2.3
    assert np.hypot(*cans.T).max() > 3.0
    assert {(x > 0, y > 0) for x, y in cans} == {(a, b) for a in (1, 0) for b in (1, 0)}


def test_a_fixed_can_is_kept_clear_of_the_obstacles():
    for seed in range(30):
        config, warnings = config_with(world='room', seed=seed, can_placement='fixed',
                                       can_x=1.5, can_y=-1.0, obstacles=20)
        assert config.scene.can_xy == (1.5, -1.0) and not warnings
        assert config.scene.clearance_m(1.5, -1.0) >= CAN_RADIUS_M + CAN_CLEARANCE_M


def test_the_empty_world_keeps_the_old_can_placement():
    config, _ = config_with(seed=4)
    assert config.scene.bounds == empty_bounds() and not config.scene.solids
    assert 0.5 <= math.hypot(*config.can_position) <= 3.0


def test_can_place_problems():
    scene = Scene((-3.0, 3.0, -3.0, 3.0), room_walls(6.0, 6.0),
                  (Solid('crate', 'box', 1.0, 1.0, 0.4, 0.4, 0.3),))
    assert scene.can_place_problem(2.0, -2.0) is None
    assert 'off the floor' in scene.can_place_problem(3.5, 0.0)
    assert 'off the floor' in scene.can_place_problem(0.0, -2.99)
    assert scene.can_place_problem(1.0, 1.2).endswith('crate')
    assert 'not finite' in scene.can_place_problem(math.inf, 0.0)


def test_world_files_load_and_round_trip():
    for path in sorted(WORLDS.glob('*.yaml')):
        data = yaml.safe_load(path.read_text())
        scene = scene_from_dict(data)
        assert scene.walls, path
        assert scene_from_dict(yaml.safe_load(yaml.safe_dump(scene.as_dict()))) == scene
    living_room, _ = config_with(world='living_room')
    assert living_room.scene.can_xy == (1.2, 1.6)
    assert {obstacle.name for obstacle in living_room.scene.obstacles} >= {'sofa', 'table'}
    corridor, warnings = config_with(world='corridor.yaml', seed=5)
    assert not warnings and corridor.scene.floor_rgba == (0.22, 0.22, 0.24, 1.0)
    assert corridor.scene.clearance_m(*corridor.scene.can_xy) >= CAN_RADIUS_M + CAN_CLEARANCE_M


def test_a_wall_segment_is_a_box_along_it():
    scene = scene_from_dict({'walls': [{'from': [0.0, 0.0], 'to': [0.0, 2.0],
                                        'thickness': 0.2}]})
    wall = scene.walls[0]
    assert (wall.x_m, wall.y_m) == (0.0, 1.0)
    assert wall.distance_m(0.5, 1.0) == pytest.approx(0.4)
    assert wall.distance_m(0.0, 2.5) == pytest.approx(0.4)
    assert scene.bounds == pytest.approx((-0.1, 0.1, -0.1, 2.1))


@pytest.mark.parametrize('data,message', [
    ({'obstacles': [{'shape': 'cone', 'x': 1, 'y': 1}]}, 'shape'),
    ({'obstacles': [{'shape': 'cylinder', 'x': 1, 'y': 1}]}, 'radius'),
    ({'obstacles': [{'shape': 'box', 'x': 1, 'y': 1, 'size': [0.1]}]}, 'size'),
    ({'obstacles': [{'shape': 'box', 'x': 1, 'size': [0.1, 0.1]}]}, "'y'"),
    ({'room': {'length': 4, 'width': 4}, 'can': {'x': 5, 'y': 0}}, 'off the floor'),
    ({'floor_rgba': [2, 0, 0, 1]}, 'floor_rgba'),
    ({'floor_checker_rgba': [0.5, 0.5, 0.5, 1]}, 'needs floor_rgba'),
    ({'furniture': []}, 'unknown world keys'),
    ([1, 2], 'mapping'),
])
def test_bad_world_files_are_refused_with_a_reason(data, message):
    with pytest.raises(ValueError, match=message):
        scene_from_dict(data)


def test_a_missing_or_broken_world_file_falls_back_to_the_empty_world(tmp_path):
    config, warnings = config_with(world='no_such_world')
    assert config.world == 'empty' and 'no world file' in warnings[0]
    broken = tmp_path / 'broken.yaml'
    broken.write_text('obstacles: [{shape: box, x: 1}]\n')
    config, warnings = config_with(world=str(broken))
    assert config.world == 'empty' and "missing 'y'" in warnings[0]


def test_colours_come_from_the_parameters():
    config, warnings = config_with(world='room', floor_rgba='0.2 0.2 0.2 1',
                                   obstacle_rgba='0.9 0.9 0.9 1', wall_rgba='purple')
    scene = config.scene
    assert scene.floor_rgba == (0.2, 0.2, 0.2, 1.0)
    assert scene.colour_of(scene.obstacles[0]) == (0.9, 0.9, 0.9, 1.0)
    assert scene.colour_of(scene.walls[0]) == (0.85, 0.82, 0.75, 1.0)
    assert len(warnings) == 1 and 'wall_rgba' in warnings[0]
    assert config_with()[0].scene.floor_rgba is None


def test_randomized_colours_come_from_the_seed_and_leave_the_geometry_alone():
    plain, _ = config_with(world='room', seed=7)
    drawn, warnings = config_with(world='room', seed=7, randomize_appearance=True,
                                  floor_rgba='0.2 0.2 0.2 1')
    assert not warnings
    assert (drawn.scene.obstacles, drawn.scene.walls, drawn.scene.can_xy) == (
        plain.scene.obstacles, plain.scene.walls, plain.scene.can_xy)
    look = random_appearance(7)
    assert (drawn.scene.floor_rgba, drawn.scene.floor_checker_rgba, drawn.scene.wall_rgba,
            drawn.scene.obstacle_rgba) == (look.floor_rgba, look.floor_checker_rgba,
                                           look.wall_rgba, look.obstacle_rgba)
    new_world = scene_for(drawn, 8, warnings.append)
    assert new_world.obstacle_rgba == random_appearance(8).obstacle_rgba
    assert plain.scene.obstacle_rgba == OBSTACLE_RGBA and plain.scene.floor_checker_rgba is None


def test_a_checker_floor_survives_a_round_trip_and_a_plain_floor_of_a_file_has_none():
    scene = Scene(empty_bounds(), floor_rgba=(0.2, 0.2, 0.2, 1.0),
                  floor_checker_rgba=(0.5, 0.4, 0.4, 1.0))
    assert scene_from_dict(scene.as_dict()) == scene
    plain = scene_from_dict({'floor_rgba': [0.3, 0.3, 0.3, 1]}, floor_rgba=(0.2, 0.2, 0.2, 1.0),
                            floor_checker_rgba=(0.5, 0.4, 0.4, 1.0))
    assert plain.floor_rgba == (0.3, 0.3, 0.3, 1.0) and plain.floor_checker_rgba is None


def test_can_visibility_from_the_start_camera():
    camera = CameraSpec(320, 240, 45.0, CameraMount(0.25, 25.0))
    pose, intrinsics = camera_pose_from_mount(camera.mount), camera.intrinsics
    open_floor = Scene(empty_bounds())
    assert can_visible(open_floor.with_can((1.5, 0.2)), pose, intrinsics)
    assert not can_visible(open_floor.with_can((-1.5, 0.0)), pose, intrinsics)
    assert not can_visible(open_floor.with_can((1.0, 1.5)), pose, intrinsics)
    assert not can_visible(open_floor.with_can((0.25, 0.0)), pose, intrinsics)
    blocked = Scene(empty_bounds(), obstacles=(Solid('crate', 'box', 1.0, 0.0, 0.2, 0.6, 0.3),))
    assert not can_visible(blocked.with_can((1.8, 0.0)), pose, intrinsics)
    low = Scene(empty_bounds(), obstacles=(Solid('step', 'box', 1.0, 0.0, 0.2, 0.6, 0.02),))
    assert can_visible(low.with_can((1.8, 0.0)), pose, intrinsics)


def test_lidar_beams_and_ranges():
    lidar = LidarSpec(beams=4, range_min_m=0.1, range_max_m=5.0, height_m=0.2)
    assert lidar.angles_rad() == pytest.approx([-math.pi, -math.pi / 2, 0.0, math.pi / 2])
    assert lidar.angle_max_rad == pytest.approx(math.pi / 2)
    starts, ends = lidar.rays(1.0, 2.0, math.pi / 2)
    assert starts[2] == pytest.approx((1.0, 2.1, 0.2))
    assert ends[3] == pytest.approx((-4.0, 2.0, 0.2))
    ranges = lidar.ranges([0.0, 0.5, 1.0, 0.999])
    assert ranges[:2] == pytest.approx([0.1, 2.55])
    assert np.isinf(ranges[2]) and ranges[3] < 5.0
