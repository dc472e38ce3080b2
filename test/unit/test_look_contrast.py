"""The look-contrast measure: an object's outline against the floor right beside it (one tile of
a checker, not their mix), the views that face walls and obstacles, the summary's counts, and
a random room whose walls render within a few grey levels of its floor."""
import math
import pathlib

import numpy as np
import pytest

from can_seeker.evaluation.look_contrast import (MAX_VIEW_DISTANCE_M, MIN_VIEW_DISTANCE_M,
                                                 OBSTACLE_VIEW_SIDES, RoomContrast,
                                                 least_contrast, measure_room, obstacle_views,
                                                 outline_contrast_levels, summary_rows,
                                                 view_distance_m, wall_views)
from can_seeker.camera_mount import CameraMount
from can_seeker.sim.scene import Scene, Solid, room_walls
from can_seeker.sim.world import CameraSpec, World

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')


def test_an_object_three_levels_off_a_plain_floor_has_a_contrast_of_three():
    image = np.full((60, 80, 3), 100, np.uint8)
    image[:, 40:] = (103, 101, 100)
    object_mask = np.zeros((60, 80), bool)
    object_mask[:, 40:] = True
    assert outline_contrast_levels(image, object_mask, ~object_mask) == pytest.approx(3.0)


def test_on_a_checker_the_object_is_judged_against_the_tile_beside_it():
    image = np.zeros((60, 80, 3), np.uint8)
    image[:30] = 50
    image[30:] = 150
    image[:, 40:] = 100                      # an object halfway between the two tiles
    object_mask = np.zeros((60, 80), bool)
    object_mask[:, 40:] = True
    # The floor's median over both tiles is 100, the object's colour: against the tile
    # beside each of its outline pixels it is 50 levels off.
    assert outline_contrast_levels(image, object_mask, ~object_mask) == pytest.approx(50.0)


def test_an_object_that_does_not_meet_the_floor_is_not_judged():
    image = np.full((60, 80, 3), 100, np.uint8)
    object_mask = np.zeros((60, 80), bool)
    object_mask[:, 60:] = True
    floor_mask = np.zeros((60, 80), bool)
    floor_mask[:, :20] = True
    assert outline_contrast_levels(image, object_mask, floor_mask) is None
    assert least_contrast([None, None]) is None
    assert least_contrast([None, 7.0, 4.5]) == 4.5


def test_the_view_distance_is_where_the_optical_axis_meets_the_floor_within_limits():
    assert view_distance_m(0.25, math.radians(25.0)) == pytest.approx(0.25 / math.tan(
        math.radians(25.0)))
    assert view_distance_m(0.15, math.radians(35.0)) == MIN_VIEW_DISTANCE_M
    assert view_distance_m(0.35, math.radians(15.0)) == MAX_VIEW_DISTANCE_M
    assert view_distance_m(0.25, 0.0) == MAX_VIEW_DISTANCE_M


@pytest.mark.parametrize('wall', room_walls(6.0, 4.0), ids=lambda wall: wall.name)
def test_wall_views_put_the_camera_at_the_distance_facing_the_wall(wall):
    camera_x_m, distance_m = 0.12, 0.5
    along_x = abs(wall.x_m) >= abs(wall.y_m)
    face = (abs(wall.x_m) - wall.size_x_m / 2.0) if along_x else (abs(wall.y_m)
                                                                   - wall.size_y_m / 2.0)
    views = list(wall_views(wall, distance_m, camera_x_m))
    assert len(views) == 3
    for x, y, yaw in views:
        camera = (x + camera_x_m * math.cos(yaw), y + camera_x_m * math.sin(yaw))
        towards = camera[0] if along_x else camera[1]
        assert face - abs(towards) == pytest.approx(distance_m)
        heading = (math.cos(yaw), math.sin(yaw))
        outward = ((math.copysign(1.0, wall.x_m), 0.0) if along_x
                   else (0.0, math.copysign(1.0, wall.y_m)))
        assert heading[0] * outward[0] + heading[1] * outward[1] == pytest.approx(1.0)


def test_obstacle_views_face_its_centre_from_every_side_the_first_from_the_start():
    box = Solid('obstacle_0', 'box', 1.0, -2.0, 0.4, 0.2, 0.3, 0.5)
    camera_x_m, distance_m = 0.12, 0.6
    views = list(obstacle_views(box, distance_m, camera_x_m))
    assert len(views) == OBSTACLE_VIEW_SIDES
    first = views[0]
    towards_view = math.atan2(first[1] + 2.0, first[0] - 1.0)
    towards_start = math.atan2(0.0 + 2.0, 0.0 - 1.0)
    assert math.cos(towards_view - towards_start) == pytest.approx(1.0)
    for x, y, yaw in views:
        assert math.hypot(x - 1.0, y + 2.0) == pytest.approx(
            box.bounding_radius_m + distance_m + camera_x_m)
        bearing = math.atan2(-2.0 - y, 1.0 - x)
        assert math.cos(bearing - yaw) == pytest.approx(1.0)


def test_the_summary_names_the_faintest_objects_and_counts_rooms_within_each_level():
    rooms = [RoomContrast(1, 'mount', 'look', {'wall_left': 2.0, 'wall_right': 30.0},
                          {'obstacle_0': 12.0}),
             RoomContrast(2, 'mount', 'look', {'wall_left': 40.0}, {'obstacle_0': 0.0,
                                                                    'obstacle_1': None}),
             RoomContrast(3, 'mount', 'look', {'wall_left': None}, {})]
    rows = summary_rows(rooms, (3.0, 20.0))
    assert '| 1 | wall_left 2.0 | obstacle_0 12.0 | look | mount |' in rows
    assert '| 2 | wall_left 40.0 | obstacle_0 0.0 | look | mount |' in rows
    assert '| 3 | - | - | look | mount |' in rows
    assert '| 3 | 1 | 1 | 2: 1 2 |' in rows
    assert '| 20 | 1 | 2 | 2: 1 2 |' in rows


def test_a_room_whose_walls_render_as_its_floor_is_found_and_its_obstacles_are_not():
    # Random look 3170: walls a third brighter than the floor, which their shade brings back
    # to the floor's grey levels; obstacles of another colour.
    room = measure_room(URDF, 3170, randomize_appearance=True, randomize_mount=True)
    assert set(room.walls) == {'wall_front', 'wall_back', 'wall_left', 'wall_right'}
    assert max(room.walls.values()) <= 4.0
    assert len(room.obstacles) == 6
    assert min(room.obstacles.values()) >= 10.0


def test_the_robot_is_placed_at_a_pose_and_the_segmented_render_names_what_it_shows():
    walls = room_walls(6.0, 6.0)
    with World(URDF, CameraSpec(320, 240, 45.0, CameraMount(0.25, 25.0))) as world:
        world.set_scene(Scene((-3.0, 3.0, -3.0, 3.0), walls, can_xy=(-2.0, -2.0)))
        world.reset_robot(2.0, 2.0, math.pi / 2.0)
        state = world.robot_state()
        assert state.position[:2] == pytest.approx((2.0, 2.0), abs=1e-6)
        assert state.yaw_rad == pytest.approx(math.pi / 2.0, abs=1e-6)
        image, masks = world.render_segmented()
    facing = max(walls, key=lambda wall: wall.y_m).name      # the wall at +y
    assert image.shape == (240, 320, 3)
    assert {'floor', facing} <= set(masks) and 'can' not in masks
    assert sum(np.count_nonzero(mask) for mask in masks.values()) <= 240 * 320
    assert np.count_nonzero(masks[facing][:40]) > 0.9 * 40 * 320   # the wall fills the top
    assert np.count_nonzero(masks['floor'][-40:]) > 0.9 * 40 * 320  # the floor the bottom
