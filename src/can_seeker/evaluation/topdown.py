"""Top-down pictures of a run in the odom frame: walls and obstacles, robot path, robot and can.

:func:`draw_topdown` draws one OpenCV frame (BGR) for the demo video, :func:`plot_trajectory`
writes the trajectory figure with matplotlib (Agg backend, headless). Map convention: odom x to
the right, y up, so a left turn (positive yaw, REP-103) turns counter-clockwise on screen.
"""
import math
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import cv2
import matplotlib
import numpy as np

matplotlib.use('Agg')
from matplotlib import patches, pyplot  # noqa: E402  (the backend must be chosen first)

from can_seeker.sim.scene import Scene  # noqa: E402

BACKGROUND = (255, 255, 255)
GRID = (225, 225, 225)
PATH = (200, 120, 0)
ROBOT = (90, 90, 90)
HEADING = (0, 0, 0)
CAN = (30, 30, 220)
GRID_STEP_M = 0.5
COVERED = (200, 235, 200)
SENSED_OBSTACLE = (60, 60, 60)
SOLID_OUTLINE = (0, 140, 255)
"""Outline of the true walls and obstacles (orange), apart from the robot's sensed ones."""


@dataclass(frozen=True)
class CoverageMap:
    """The robot's own map (nav_msgs/OccupancyGrid layout): ``values`` rows along y from
    ``origin`` (m, odom), ``resolution_m`` per cell; 100 obstacle, 0 covered, -1 not covered."""

    origin_x_m: float
    origin_y_m: float
    resolution_m: float
    values: np.ndarray


@dataclass(frozen=True)
class TopDownView:
    """A square window on the floor: its centre (m), scale (m per px) and side (px)."""

    centre_x_m: float
    centre_y_m: float
    metres_per_px: float
    size_px: int

    @classmethod
    def framing(cls, points: Sequence[Sequence[float]], size_px: int,
                margin_m: float) -> 'TopDownView':
        """The smallest square view holding every (x, y) of ``points`` plus ``margin_m``."""
        xs = [point[0] for point in points]
        ys = [point[1] for point in points]
        span_m = max(max(xs) - min(xs), max(ys) - min(ys)) + 2.0 * margin_m
        return cls((max(xs) + min(xs)) / 2.0, (max(ys) + min(ys)) / 2.0, span_m / size_px,
                   size_px)

    def to_px(self, x_m: float, y_m: float) -> Tuple[int, int]:
        """Pixel (column, row) of a floor point."""
        half = self.size_px / 2.0
        return (int(round(half + (x_m - self.centre_x_m) / self.metres_per_px)),
                int(round(half - (y_m - self.centre_y_m) / self.metres_per_px)))

    def length_px(self, length_m: float) -> int:
        """A length on the floor in pixels (at least 1)."""
        return max(1, int(round(length_m / self.metres_per_px)))


def _draw_grid(image: np.ndarray, view: TopDownView):
    half_span_m = view.size_px * view.metres_per_px / 2.0
    for axis in (0, 1):
        centre = view.centre_x_m if axis == 0 else view.centre_y_m
        first = math.ceil((centre - half_span_m) / GRID_STEP_M)
        last = math.floor((centre + half_span_m) / GRID_STEP_M)
        for index in range(first, last + 1):
            value = index * GRID_STEP_M
            if axis == 0:
                column = view.to_px(value, 0.0)[0]
                cv2.line(image, (column, 0), (column, view.size_px - 1), GRID, 1)
            else:
                row = view.to_px(0.0, value)[1]
                cv2.line(image, (0, row), (view.size_px - 1, row), GRID, 1)


def _draw_coverage(image: np.ndarray, view: TopDownView, coverage: CoverageMap):
    """Covered floor tinted green, sensed obstacle cells dark grey (every pixel looks up the
    cell under its centre)."""
    half = view.size_px / 2.0
    pixels = np.arange(view.size_px)
    xs = view.centre_x_m + (pixels - half) * view.metres_per_px
    ys = view.centre_y_m - (pixels - half) * view.metres_per_px
    columns = np.floor((xs - coverage.origin_x_m) / coverage.resolution_m).astype(int)
    rows = np.floor((ys - coverage.origin_y_m) / coverage.resolution_m).astype(int)
    inside_columns = (columns >= 0) & (columns < coverage.values.shape[1])
    inside_rows = (rows >= 0) & (rows < coverage.values.shape[0])
    values = np.full((view.size_px, view.size_px), -1, int)
    values[np.ix_(inside_rows, inside_columns)] = coverage.values[
        np.ix_(rows[inside_rows], columns[inside_columns])]
    image[(values >= 0) & (values < 50)] = COVERED
    image[values >= 50] = SENSED_OBSTACLE


def scene_points(scene: Optional[Scene]) -> List[Tuple[float, float]]:
    """Floor points (m) a view must hold to show every wall and obstacle of ``scene``."""
    if scene is None:
        return []
    return [tuple(point) for solid in scene.solids for point in solid.footprint()]


def _draw_solids(image: np.ndarray, view: TopDownView, scene: Scene):
    """Walls and obstacles as filled footprints in their own colours, outlined."""
    for solid in scene.solids:
        polygon = np.array([view.to_px(x, y) for x, y in solid.footprint()], np.int32)
        red, green, blue = (int(round(255 * channel)) for channel in scene.colour_of(solid)[:3])
        cv2.fillPoly(image, [polygon], (blue, green, red), cv2.LINE_AA)
        cv2.polylines(image, [polygon], True, SOLID_OUTLINE, 1, cv2.LINE_AA)


def draw_topdown(view: TopDownView, path: Sequence[Sequence[float]],
                 robot_pose: Sequence[float], can_xy: Sequence[float], robot_radius_m: float,
                 can_radius_m: float, caption: str = '',
                 coverage: Optional[CoverageMap] = None,
                 scene: Optional[Scene] = None) -> np.ndarray:
    """A BGR frame: the robot's coverage map when given, grid every 0.5 m, the scene's walls
    and obstacles when given, the path so far, the robot (x, y, yaw) and the can."""
    image = np.full((view.size_px, view.size_px, 3), BACKGROUND, np.uint8)
    if coverage is not None:
        _draw_coverage(image, view, coverage)
    _draw_grid(image, view)
    if scene is not None:
        _draw_solids(image, view, scene)
    if len(path) > 1:
        points = np.array([view.to_px(x, y) for x, y in path], np.int32)
        cv2.polylines(image, [points], False, PATH, 2, cv2.LINE_AA)
    cv2.circle(image, view.to_px(*can_xy), view.length_px(can_radius_m), CAN, -1, cv2.LINE_AA)
    x, y, yaw = robot_pose
    centre = view.to_px(x, y)
    cv2.circle(image, centre, view.length_px(robot_radius_m), ROBOT, 2, cv2.LINE_AA)
    nose = view.to_px(x + robot_radius_m * math.cos(yaw), y + robot_radius_m * math.sin(yaw))
    cv2.line(image, centre, nose, HEADING, 2, cv2.LINE_AA)
    if caption:
        cv2.putText(image, caption, (8, view.size_px - 10), cv2.FONT_HERSHEY_SIMPLEX, 0.45,
                    HEADING, 1, cv2.LINE_AA)
    return image


def side_by_side(left: np.ndarray, right: np.ndarray) -> np.ndarray:
    """``right`` scaled to ``left``'s height and put next to it; even sides for video codecs."""
    height = left.shape[0]
    width = int(round(right.shape[1] * height / right.shape[0]))
    combined = np.hstack([left, cv2.resize(right, (width, height),
                                           interpolation=cv2.INTER_AREA)])
    return combined[:combined.shape[0] // 2 * 2, :combined.shape[1] // 2 * 2]


def plot_trajectory(filename: str, path: Sequence[Sequence[float]],
                    final_pose: Sequence[float], can_xy: Sequence[float], robot_radius_m: float,
                    can_radius_m: float, stop_distance_m: float, title: str,
                    scene: Optional[Scene] = None):
    """Write the trajectory figure: walls and obstacles of ``scene`` when given, path, start
    and final robot outline, the can and the circle on which the robot's centre should stop."""
    figure, axes = pyplot.subplots(figsize=(6.0, 6.0), dpi=100)
    for solid in (scene.solids if scene is not None else ()):
        axes.add_patch(patches.Polygon(solid.footprint(), closed=True,
                                       facecolor=scene.colour_of(solid)[:3],
                                       edgecolor='dimgrey', linewidth=0.8))
    xs = [point[0] for point in path]
    ys = [point[1] for point in path]
    axes.plot(xs, ys, '-', color='tab:blue', label='base_link path')
    axes.add_patch(patches.Circle((0.0, 0.0), robot_radius_m, fill=False,
                                             linestyle=':', color='grey', label='start'))
    x, y, yaw = final_pose
    axes.add_patch(patches.Circle((x, y), robot_radius_m, fill=False, color='black',
                                             label='final pose'))
    axes.plot([x, x + robot_radius_m * math.cos(yaw)], [y, y + robot_radius_m * math.sin(yaw)],
              '-', color='black')
    axes.add_patch(patches.Circle(tuple(can_xy), can_radius_m, color='tab:red',
                                             label='can'))
    axes.add_patch(patches.Circle(
        tuple(can_xy), can_radius_m + stop_distance_m + robot_radius_m, fill=False,
        linestyle='--', color='tab:red', alpha=0.5, label='target for base_link'))
    axes.set_aspect('equal')
    axes.autoscale_view()
    axes.grid(True, alpha=0.3)
    axes.set_xlabel('odom x (m)')
    axes.set_ylabel('odom y (m)')
    axes.set_title(title)
    axes.legend(loc='best', fontsize='small')
    figure.tight_layout()
    figure.savefig(filename)
    pyplot.close(figure)
