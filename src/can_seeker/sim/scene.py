"""The world's description without a physics engine: robot and can geometry, floor bounds, walls,
obstacles, where the can stands, and the free-space questions asked about them.

One place for this geometry: the simulator builds it in pybullet, the top-down view draws it and
the trial judge measures against it. Frame: odom, the robot starts at its origin facing +x.
Every solid (wall or obstacle) stands on the floor: a box (sides along its yaw) or an upright
cylinder. A scene is written and read as a plain dict (the YAML world-file format, also what the
simulator publishes), so a scene survives a round trip through a file or a topic.
"""
import math
import random
from dataclasses import dataclass, replace
from typing import Optional, Sequence, Tuple

import cv2
import numpy as np

from can_seeker.camera_geometry import CameraIntrinsics, CameraPose
from can_seeker.can_size import CAN_DIAMETER_M, CAN_HEIGHT_M

ROBOT_RADIUS_M = 0.165
"""Radius of the robot body about base_link (m)."""
WHEEL_RADIUS_M = 0.036
WHEEL_SEPARATION_M = 0.235
CAN_RADIUS_M = CAN_DIAMETER_M / 2.0
CAN_MASS_KG = 0.37

EMPTY_FLOOR_HALF_SIDE_M = 100.0
"""The empty world's floor (pybullet's plane: a 200 m square box) reaches this far from the
origin along x and y (m)."""
WALL_THICKNESS_M = 0.1
WALL_HEIGHT_M = 0.5
OBSTACLE_SIDE_RANGE_M = (0.1, 0.5)
"""Random obstacles: box sides and cylinder diameters are drawn from this range (m)."""
OBSTACLE_HEIGHT_RANGE_M = (0.15, 0.5)
"""Random obstacle heights (m): all taller than the lidar plane, as real clutter mostly is."""
START_CLEARANCE_M = 0.5
"""No obstacle comes closer than this to the robot start (m): the body (0.165 m) plus room to
turn in place and drive off in any direction."""
CAN_CLEARANCE_M = 0.4
"""A random can keeps this much free floor between its surface and any wall or obstacle (m)."""
GRID_STEP_M = 0.05
"""Cell side of the free-space grid that checks a random can is reachable (m)."""
REACH_MARGIN_M = 0.05
"""Extra clearance a robot path keeps from solids in the reachability check (m)."""
REACH_GAP_M = 0.3
"""A can counts as reachable when the robot body can get this close to its surface (m)."""
MAX_PLACEMENT_TRIES = 20000
SIGHT_STEP_M = 0.01
"""Spacing of the points tested along a line of sight (m)."""
SIGHT_HEIGHTS = (0.1, 0.3, 0.5, 0.7, 0.9)
"""Points on the can's near side, as fractions of its height, tested for visibility."""

RGBA = Tuple[float, float, float, float]
WALL_RGBA = (0.85, 0.82, 0.75, 1.0)
OBSTACLE_RGBA = (0.12, 0.12, 0.14, 1.0)
SHAPES = ('box', 'cylinder')


@dataclass(frozen=True)
class Solid:
    """A box or upright cylinder on the floor: centre (m), footprint sides along its yaw (m; a
    cylinder's diameter in both), height (m), yaw (rad) and its own colour (None: the scene's
    colour for walls or obstacles)."""

    name: str
    shape: str
    x_m: float
    y_m: float
    size_x_m: float
    size_y_m: float
    height_m: float
    yaw_rad: float = 0.0
    rgba: Optional[RGBA] = None

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise ValueError('%s: shape must be box or cylinder, got %r' % (self.name, self.shape))
        if min(self.size_x_m, self.size_y_m, self.height_m) <= 0.0:
            raise ValueError('%s: sizes must be positive' % self.name)

    @property
    def bounding_radius_m(self) -> float:
        """Radius of the smallest circle about the centre holding the footprint (m)."""
        if self.shape == 'cylinder':
            return self.size_x_m / 2.0
        return math.hypot(self.size_x_m, self.size_y_m) / 2.0

    def distance_m(self, x_m, y_m):
        """Signed distance (m) from floor point(s) to the footprint: negative inside. Takes
        floats or numpy arrays."""
        dx, dy = np.subtract(x_m, self.x_m), np.subtract(y_m, self.y_m)
        if self.shape == 'cylinder':
            return np.hypot(dx, dy) - self.size_x_m / 2.0
        cos_yaw, sin_yaw = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        over_x = np.abs(cos_yaw * dx + sin_yaw * dy) - self.size_x_m / 2.0
        over_y = np.abs(-sin_yaw * dx + cos_yaw * dy) - self.size_y_m / 2.0
        outside = np.hypot(np.maximum(over_x, 0.0), np.maximum(over_y, 0.0))
        return outside + np.minimum(np.maximum(over_x, over_y), 0.0)

    def footprint(self, points: int = 32) -> np.ndarray:
        """The footprint outline as N x 2 floor points (m), counter-clockwise."""
        if self.shape == 'cylinder':
            angles = np.linspace(0.0, 2.0 * math.pi, points, endpoint=False)
            radius = self.size_x_m / 2.0
            return np.stack([self.x_m + radius * np.cos(angles),
                             self.y_m + radius * np.sin(angles)], axis=1)
        half = np.array([(1, 1), (-1, 1), (-1, -1), (1, -1)]) * (self.size_x_m / 2.0,
                                                                  self.size_y_m / 2.0)
        cos_yaw, sin_yaw = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        rotation = np.array(((cos_yaw, -sin_yaw), (sin_yaw, cos_yaw)))
        return half @ rotation.T + (self.x_m, self.y_m)

    def as_dict(self) -> dict:
        """The world-file entry of this solid."""
        entry = {'name': self.name, 'shape': self.shape, 'x': self.x_m, 'y': self.y_m,
                 'height': self.height_m}
        if self.shape == 'cylinder':
            entry['radius'] = self.size_x_m / 2.0
        else:
            entry['size'] = [self.size_x_m, self.size_y_m]
            entry['yaw_deg'] = math.degrees(self.yaw_rad)
        if self.rgba is not None:
            entry['rgba'] = list(self.rgba)
        return entry


@dataclass(frozen=True)
class Scene:
    """Everything in the world but the robot: the usable floor (x_min, x_max, y_min, y_max, m),
    walls, obstacles, the can's centre (m) and the colours (floor None: pybullet's checker;
    with ``floor_checker_rgba`` too, a checker of the two in 1 m squares, as pybullet's)."""

    bounds: Tuple[float, float, float, float]
    walls: Tuple[Solid, ...] = ()
    obstacles: Tuple[Solid, ...] = ()
    can_xy: Optional[Tuple[float, float]] = None
    floor_rgba: Optional[RGBA] = None
    wall_rgba: RGBA = WALL_RGBA
    obstacle_rgba: RGBA = OBSTACLE_RGBA
    floor_checker_rgba: Optional[RGBA] = None

    @property
    def solids(self) -> Tuple[Solid, ...]:
        """Walls and obstacles."""
        return self.walls + self.obstacles

    def colour_of(self, solid: Solid) -> RGBA:
        """The colour a solid is drawn in."""
        if solid.rgba is not None:
            return solid.rgba
        return self.wall_rgba if solid in self.walls else self.obstacle_rgba

    def clearance_m(self, x_m, y_m):
        """Distance (m) from floor point(s) to the nearest wall or obstacle (inf if none);
        negative inside one. Takes floats or numpy arrays."""
        nearest = np.full(np.shape(x_m), np.inf)
        for solid in self.solids:
            nearest = np.minimum(nearest, solid.distance_m(x_m, y_m))
        return nearest if np.ndim(nearest) else float(nearest)

    def inside_bounds(self, x_m: float, y_m: float, margin_m: float = 0.0) -> bool:
        """Whether (x, y) lies on the usable floor at least ``margin_m`` from its edge."""
        x_min, x_max, y_min, y_max = self.bounds
        return (x_min + margin_m <= x_m <= x_max - margin_m
                and y_min + margin_m <= y_m <= y_max - margin_m)

    def can_place_problem(self, x_m: float, y_m: float) -> Optional[str]:
        """Why the can cannot stand with its axis at (x, y) (off the floor, inside a wall or an
        obstacle), or None when it can."""
        if not (math.isfinite(x_m) and math.isfinite(y_m)):
            return 'can position (%r, %r) is not finite' % (x_m, y_m)
        if not self.inside_bounds(x_m, y_m, CAN_RADIUS_M):
            return ('can at (%.3f, %.3f) is off the floor (x %.2f to %.2f, y %.2f to %.2f m)'
                    % ((x_m, y_m) + tuple(self.bounds)))
        for solid in self.solids:
            if solid.distance_m(x_m, y_m) < CAN_RADIUS_M:
                return 'can at (%.3f, %.3f) would overlap %s' % (x_m, y_m, solid.name)
        return None

    def with_can(self, can_xy: Tuple[float, float]) -> 'Scene':
        """This scene with the can at ``can_xy`` (m)."""
        return replace(self, can_xy=(float(can_xy[0]), float(can_xy[1])))

    def as_dict(self) -> dict:
        """The scene in the world-file format (see :func:`scene_from_dict`)."""
        data = {'bounds': list(self.bounds), 'wall_rgba': list(self.wall_rgba),
                'obstacle_rgba': list(self.obstacle_rgba),
                'walls': [wall.as_dict() for wall in self.walls],
                'obstacles': [obstacle.as_dict() for obstacle in self.obstacles]}
        if self.floor_rgba is not None:
            data['floor_rgba'] = list(self.floor_rgba)
            if self.floor_checker_rgba is not None:
                data['floor_checker_rgba'] = list(self.floor_checker_rgba)
        if self.can_xy is not None:
            data['can'] = {'x': self.can_xy[0], 'y': self.can_xy[1]}
        return data


def line_of_sight_clear(scene: Scene, start_m: Sequence[float], end_m: Sequence[float]) -> bool:
    """Whether the segment between two 3-D points (m) passes through no wall or obstacle."""
    start, end = np.asarray(start_m, float), np.asarray(end_m, float)
    count = max(2, int(math.ceil(np.linalg.norm(end - start) / SIGHT_STEP_M)) + 1)
    points = start + np.linspace(0.0, 1.0, count)[:, None] * (end - start)
    for solid in scene.solids:
        inside = (solid.distance_m(points[:, 0], points[:, 1]) < 0.0) & (
            points[:, 2] < solid.height_m)
        if np.any(inside):
            return False
    return True


def can_visible(scene: Scene, pose: CameraPose, intrinsics: CameraIntrinsics) -> bool:
    """Whether part of the can's near side is in the image of a camera (``pose``: its optical
    frame in the world frame) and not hidden behind a wall or obstacle."""
    position = np.asarray(pose.position, float)
    can_x, can_y = scene.can_xy
    towards = np.array((position[0] - can_x, position[1] - can_y))
    towards = towards / max(np.linalg.norm(towards), 1e-9)
    for fraction in SIGHT_HEIGHTS:
        point = np.array((can_x + CAN_RADIUS_M * towards[0], can_y + CAN_RADIUS_M * towards[1],
                          fraction * CAN_HEIGHT_M))
        x, y, z = pose.rotation.T @ (point - position)
        if z <= 0.0:
            continue
        u = intrinsics.fx * x / z + intrinsics.cx
        v = intrinsics.fy * y / z + intrinsics.cy
        if (-0.5 <= u <= intrinsics.width - 0.5 and -0.5 <= v <= intrinsics.height - 0.5
                and line_of_sight_clear(scene, position, point)):
            return True
    return False


def empty_bounds() -> Tuple[float, float, float, float]:
    """The empty world's floor (m)."""
    half = EMPTY_FLOOR_HALF_SIDE_M
    return (-half, half, -half, half)


def room_walls(length_m: float, width_m: float) -> Tuple[Solid, ...]:
    """Four walls around the room x in [-length/2, length/2], y in [-width/2, width/2] (m)."""
    thickness, height = WALL_THICKNESS_M, WALL_HEIGHT_M
    half_x, half_y = length_m / 2.0, width_m / 2.0
    outer_x, outer_y = length_m + 2.0 * thickness, width_m + 2.0 * thickness
    return (
        Solid('wall_front', 'box', half_x + thickness / 2.0, 0.0, thickness, outer_y, height),
        Solid('wall_back', 'box', -half_x - thickness / 2.0, 0.0, thickness, outer_y, height),
        Solid('wall_left', 'box', 0.0, half_y + thickness / 2.0, outer_x, thickness, height),
        Solid('wall_right', 'box', 0.0, -half_y - thickness / 2.0, outer_x, thickness, height),
    )


def random_can_position(seed: int, min_distance_m: float,
                        max_distance_m: float) -> Tuple[float, float]:
    """Can centre (x, y) (m) at a uniformly random bearing and distance from the origin."""
    generator = random.Random(seed)
    distance_m = generator.uniform(min_distance_m, max_distance_m)
    bearing_rad = generator.uniform(-math.pi, math.pi)
    return distance_m * math.cos(bearing_rad), distance_m * math.sin(bearing_rad)


def random_obstacles(generator: random.Random, count: int,
                     bounds: Tuple[float, float, float, float],
                     keep_clear: Sequence[Tuple[Sequence[float], float]] = ()
                     ) -> Tuple[Solid, ...]:
    """Up to ``count`` boxes and cylinders of random size and pose inside ``bounds``, apart from
    each other, START_CLEARANCE_M from the robot start at the origin and ``radius`` from each
    ((x, y), radius) of ``keep_clear``. Fewer when no place is found for the next one."""
    keep_clear = [((0.0, 0.0), START_CLEARANCE_M)] + list(keep_clear)
    obstacles = []
    for index in range(count):
        for _ in range(MAX_PLACEMENT_TRIES):
            shape = generator.choice(SHAPES)
            size_x = generator.uniform(*OBSTACLE_SIDE_RANGE_M)
            size_y = size_x if shape == 'cylinder' else generator.uniform(*OBSTACLE_SIDE_RANGE_M)
            height = generator.uniform(*OBSTACLE_HEIGHT_RANGE_M)
            yaw = generator.uniform(-math.pi, math.pi) if shape == 'box' else 0.0
            x = generator.uniform(bounds[0], bounds[1])
            y = generator.uniform(bounds[2], bounds[3])
            candidate = Solid('obstacle_%d' % index, shape, x, y, size_x, size_y, height, yaw)
            radius = candidate.bounding_radius_m
            if (Scene(bounds).inside_bounds(x, y, radius)
                    and all(candidate.distance_m(*point) >= clear_m
                            for point, clear_m in keep_clear)
                    and all(math.hypot(x - other.x_m, y - other.y_m)
                            >= radius + other.bounding_radius_m for other in obstacles)):
                obstacles.append(candidate)
                break
        else:
            break
    return tuple(obstacles)


def reachable_floor(scene: Scene, start_xy: Sequence[float] = (0.0, 0.0),
                    robot_radius_m: float = ROBOT_RADIUS_M):
    """(xs, ys, mask): cell centres of a GRID_STEP_M grid over the bounds and which cells the
    robot's centre can reach from ``start_xy`` without any solid coming closer than the body
    radius ``robot_radius_m`` plus REACH_MARGIN_M."""
    x_min, x_max, y_min, y_max = scene.bounds
    xs = np.arange(x_min + GRID_STEP_M / 2.0, x_max, GRID_STEP_M)
    ys = np.arange(y_min + GRID_STEP_M / 2.0, y_max, GRID_STEP_M)
    grid_x, grid_y = np.meshgrid(xs, ys)
    free = (scene.clearance_m(grid_x, grid_y) >= robot_radius_m + REACH_MARGIN_M)
    _, labels = cv2.connectedComponents(free.astype(np.uint8), connectivity=8)
    column = int(np.clip(np.searchsorted(xs, start_xy[0]), 0, xs.size - 1))
    row = int(np.clip(np.searchsorted(ys, start_xy[1]), 0, ys.size - 1))
    start_label = labels[row, column]
    if start_label == 0:
        return xs, ys, np.zeros_like(free)
    return xs, ys, labels == start_label


def random_free_can_position(generator: random.Random, scene: Scene, min_distance_m: float,
                             start_xy: Sequence[float] = (0.0, 0.0),
                             robot_radius_m: float = ROBOT_RADIUS_M) -> Tuple[float, float]:
    """A can centre anywhere on the floor with CAN_CLEARANCE_M of free floor around the can, at
    least ``min_distance_m`` from the start and reachable by a robot of ``robot_radius_m``
    (ValueError if none)."""
    xs, ys, reachable = reachable_floor(scene, start_xy, robot_radius_m)
    reach_m = CAN_RADIUS_M + robot_radius_m + REACH_GAP_M
    reachable_x = np.meshgrid(xs, ys)[0][reachable]
    reachable_y = np.meshgrid(xs, ys)[1][reachable]
    x_min, x_max, y_min, y_max = scene.bounds
    for _ in range(MAX_PLACEMENT_TRIES):
        x, y = generator.uniform(x_min, x_max), generator.uniform(y_min, y_max)
        if (math.hypot(x - start_xy[0], y - start_xy[1]) >= min_distance_m
                and scene.inside_bounds(x, y, CAN_RADIUS_M + CAN_CLEARANCE_M)
                and scene.clearance_m(x, y) >= CAN_RADIUS_M + CAN_CLEARANCE_M
                and np.any(np.hypot(reachable_x - x, reachable_y - y) <= reach_m)):
            return x, y
    raise ValueError('no free, reachable floor for the can')


def _floats(value, count: int, what: str) -> Tuple[float, ...]:
    try:
        numbers = tuple(float(number) for number in value)
    except (TypeError, ValueError):
        raise ValueError('%s: expected %d numbers, got %r' % (what, count, value))
    if len(numbers) != count or not all(math.isfinite(number) for number in numbers):
        raise ValueError('%s: expected %d finite numbers, got %r' % (what, count, value))
    return numbers


def _rgba(value, what: str) -> RGBA:
    rgba = _floats(value, 4, what)
    if not all(0.0 <= channel <= 1.0 for channel in rgba):
        raise ValueError('%s: colour channels must be in 0-1, got %r' % (what, value))
    return rgba


def _number(entry: dict, key: str, what: str, default=None) -> float:
    if key not in entry:
        if default is None:
            raise ValueError('%s: missing %r' % (what, key))
        return default
    return _floats([entry[key]], 1, '%s %s' % (what, key))[0]


def _solid(entry, default_name: str, default_height_m: float) -> Solid:
    if not isinstance(entry, dict):
        raise ValueError('%s: expected a mapping, got %r' % (default_name, entry))
    name = str(entry.get('name', default_name))
    height = _number(entry, 'height', name, default_height_m)
    rgba = _rgba(entry['rgba'], name + ' rgba') if 'rgba' in entry else None
    if 'from' in entry or 'to' in entry:
        start = _floats(entry.get('from'), 2, name + ' from')
        end = _floats(entry.get('to'), 2, name + ' to')
        thickness = _number(entry, 'thickness', name, WALL_THICKNESS_M)
        length = math.hypot(end[0] - start[0], end[1] - start[1])
        return Solid(name, 'box', (start[0] + end[0]) / 2.0, (start[1] + end[1]) / 2.0,
                     length + thickness, thickness, height,
                     math.atan2(end[1] - start[1], end[0] - start[0]), rgba)
    shape = entry.get('shape', 'box')
    if shape not in SHAPES:
        raise ValueError('%s: shape must be box or cylinder, got %r' % (name, shape))
    x, y = _number(entry, 'x', name), _number(entry, 'y', name)
    if shape == 'cylinder':
        diameter = 2.0 * _number(entry, 'radius', name)
        return Solid(name, shape, x, y, diameter, diameter, height, 0.0, rgba)
    size = _floats(entry.get('size'), 2, name + ' size')
    yaw = math.radians(_number(entry, 'yaw_deg', name, 0.0))
    return Solid(name, shape, x, y, size[0], size[1], height, yaw, rgba)


def scene_from_dict(data: dict, floor_rgba: Optional[RGBA] = None, wall_rgba: RGBA = WALL_RGBA,
                    obstacle_rgba: RGBA = OBSTACLE_RGBA,
                    floor_checker_rgba: Optional[RGBA] = None) -> Scene:
    """A scene from the world-file format; ValueError saying what is wrong otherwise. The
    colours given here apply where the file sets none (a file that colours the floor sets its
    checker colour too, or none).

    Keys (all optional): ``room: {length, width}`` (four walls around the start),
    ``walls``/``obstacles``: lists of solids (``{shape: box, x, y, size: [sx, sy], yaw_deg,
    height, rgba}``, ``{shape: cylinder, x, y, radius, height}``; a wall may be given as
    ``{from: [x, y], to: [x, y], thickness}``), ``can: {x, y}``, ``bounds: [x_min, x_max, y_min,
    y_max]`` (default: the box around the walls, or the empty floor), ``floor_rgba``,
    ``floor_checker_rgba`` (with ``floor_rgba``: a checker floor), ``wall_rgba``,
    ``obstacle_rgba``. A solid of alpha 0 is solid but invisible: no camera image shows it
    or its shadow.
    """
    if not isinstance(data, dict):
        raise ValueError('a world is a mapping, got %r' % (data,))
    known = {'room', 'walls', 'obstacles', 'can', 'bounds', 'floor_rgba', 'floor_checker_rgba',
             'wall_rgba', 'obstacle_rgba'}
    unknown = sorted(set(data) - known)
    if unknown:
        raise ValueError('unknown world keys: %s' % ', '.join(map(str, unknown)))
    walls = []
    if 'room' in data:
        room = data['room'] if isinstance(data['room'], dict) else {}
        walls.extend(room_walls(_number(room, 'length', 'room'), _number(room, 'width', 'room')))
    for index, entry in enumerate(data.get('walls') or ()):
        walls.append(_solid(entry, 'wall_%d' % (index + len(walls)), WALL_HEIGHT_M))
    obstacles = tuple(_solid(entry, 'obstacle_%d' % index, OBSTACLE_HEIGHT_RANGE_M[1])
                      for index, entry in enumerate(data.get('obstacles') or ()))
    if 'bounds' in data:
        bounds = _floats(data['bounds'], 4, 'bounds')
    elif walls:
        corners = np.concatenate([wall.footprint() for wall in walls])
        bounds = (corners[:, 0].min(), corners[:, 0].max(),
                  corners[:, 1].min(), corners[:, 1].max())
    else:
        bounds = empty_bounds()
    if bounds[0] >= bounds[1] or bounds[2] >= bounds[3]:
        raise ValueError('bounds: expected x_min < x_max and y_min < y_max, got %r' % (bounds,))
    colours = {'floor_rgba': floor_rgba, 'wall_rgba': wall_rgba, 'obstacle_rgba': obstacle_rgba,
               'floor_checker_rgba': floor_checker_rgba}
    if 'floor_checker_rgba' in data and 'floor_rgba' not in data:
        raise ValueError('floor_checker_rgba needs floor_rgba: a checker has two colours')
    if 'floor_rgba' in data:
        colours['floor_checker_rgba'] = None
    colours.update({key: _rgba(data[key], key) for key in colours if key in data})
    scene = Scene(tuple(float(value) for value in bounds), tuple(walls), obstacles, **colours)
    names = [solid.name for solid in scene.solids]
    if len(set(names)) != len(names):
        raise ValueError('solid names must be unique, got %s' % ', '.join(names))
    if 'can' in data:
        can = data['can'] if isinstance(data['can'], dict) else {}
        can_xy = (_number(can, 'x', 'can'), _number(can, 'y', 'can'))
        problem = scene.can_place_problem(*can_xy)
        if problem:
            raise ValueError(problem)
        scene = scene.with_can(can_xy)
    return scene
