"""Top-down pictures of a run."""
import math

import cv2
import numpy as np
import pytest

from can_seeker.evaluation.topdown import CAN, COVERED, PATH, SENSED_OBSTACLE, CoverageMap, \
    TopDownView, draw_topdown, plot_trajectory, \
    side_by_side


def test_framing_holds_all_points_with_margin():
    view = TopDownView.framing([(0.0, 0.0), (2.0, -1.0)], 400, 0.5)
    assert view.metres_per_px == pytest.approx(3.0 / 400)
    assert view.to_px(1.0, -0.5) == (200, 200)
    column, row = view.to_px(2.0, -1.0)
    assert 0 < column < 400 and 0 < row < 400


def test_x_right_y_up():
    view = TopDownView(0.0, 0.0, 0.01, 200)
    assert view.to_px(0.5, 0.0) == (150, 100)
    assert view.to_px(0.0, 0.5) == (100, 50)


def test_draw_puts_can_and_path_where_they_are():
    view = TopDownView(0.5, 0.0, 0.01, 200)
    image = draw_topdown(view, [(0.0, 0.0), (0.3, 0.0)], (0.3, 0.0, 0.0), (1.2, 0.4),
                         0.165, 0.033)
    assert image.shape == (200, 200, 3)
    can_column, can_row = view.to_px(1.2, 0.4)
    assert tuple(image[can_row, can_column]) == CAN
    path_column, path_row = view.to_px(0.05, 0.0)
    assert tuple(image[path_row, path_column]) == PATH


def test_side_by_side_matches_height_and_even_size():
    left = np.zeros((241, 321, 3), np.uint8)
    combined = side_by_side(left, np.zeros((200, 200, 3), np.uint8))
    assert combined.shape == (240, 321 + 241, 3)


def test_plot_trajectory_writes_a_png(tmp_path):
    filename = str(tmp_path / 'trajectory.png')
    plot_trajectory(filename, [(0, 0), (0.5, 0.1), (1.0, 0.2)], (1.0, 0.2, math.radians(10)),
                    (1.5, 0.3), 0.165, 0.033, 0.25, 'test run')
    image = cv2.imread(filename)
    assert image is not None and image.shape[0] > 100 and image.std() > 5


def test_coverage_map_is_drawn_under_the_path():
    values = np.full((20, 20), -1, np.int8)
    values[10:12, 12:14] = 100          # obstacle around x 0.2-0.4, y 0.0-0.2
    values[5:10, 5:10] = 0              # covered floor around x -0.5..0, y -0.5..0
    coverage = CoverageMap(-1.0, -1.0, 0.1, values)
    view = TopDownView(0.0, 0.0, 0.01, 200)
    image = draw_topdown(view, [], (0.9, 0.9, 0.0), (0.9, -0.9), 0.05, 0.033,
                         coverage=coverage)
    column, row = view.to_px(0.25, 0.15)
    assert tuple(image[row, column]) == SENSED_OBSTACLE
    column, row = view.to_px(-0.22, -0.27)
    assert tuple(image[row, column]) == COVERED
    column, row = view.to_px(-0.7, 0.7)
    assert tuple(image[row, column]) == (255, 255, 255)


def test_walls_and_obstacles_are_drawn_in_their_colours_where_they_stand():
    from can_seeker.evaluation.topdown import scene_points
    from can_seeker.sim.scene import Scene, Solid, room_walls
    crate = Solid('crate', 'box', 1.0, 1.0, 0.4, 0.2, 0.3, math.radians(90.0))
    scene = Scene((-2.0, 2.0, -2.0, 2.0), room_walls(4.0, 4.0), (crate,),
                  wall_rgba=(0.0, 0.0, 1.0, 1.0), obstacle_rgba=(0.0, 1.0, 0.0, 1.0))
    points = scene_points(scene)
    assert max(x for x, _ in points) == pytest.approx(2.1)
    view = TopDownView.framing([(0.0, 0.0)] + points, 420, 0.0)
    image = draw_topdown(view, [], (0.0, 0.0, 0.0), (-1.0, -1.0), 0.165, 0.033, scene=scene)
    column, row = view.to_px(1.0, 1.15)
    assert tuple(image[row, column]) == (0, 255, 0)
    column, row = view.to_px(1.15, 1.0)
    assert tuple(image[row, column]) != (0, 255, 0)
    column, row = view.to_px(2.05, 0.0)
    assert tuple(image[row, column]) == (255, 0, 0)
    column, row = view.to_px(0.5, 0.5)
    assert tuple(image[row, column]) != (255, 0, 0)


def test_trajectory_plot_with_a_scene(tmp_path):
    from can_seeker.sim.scene import Scene, room_walls
    filename = str(tmp_path / 'room.png')
    plot_trajectory(filename, [(0.0, 0.0), (1.0, 0.5)], (1.0, 0.5, 0.3), (1.5, 0.8), 0.165,
                    0.033, 0.25, 'room', Scene((-2.0, 2.0, -2.0, 2.0), room_walls(4.0, 4.0)))
    assert cv2.imread(filename).shape[:2] == (600, 600)
