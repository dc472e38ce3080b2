"""How plainly the camera can see each wall and obstacle of a room: the contrast it renders
them with against the floor beside them.

A floor model, or any test on the image, can only find what differs from the floor in the
image. Random looks (``--randomize-appearance``) draw some walls and obstacles close to the
floor's colour on purpose, and the light can bring a vertical face's shade to the floor's: a
wall a third brighter than the floor may render within two grey levels of it. This measures,
per object, how far (grey levels, 0-255, the largest channel difference) its pixels along
its outline lie from the floor right beside them, seen from places where its foot lies
mid-image; the least over those views is the object's contrast: from that side nothing in the
image tells it from the floor but that much.
"""
import math
from dataclasses import dataclass, field
from typing import Dict, Iterator, List, Optional, Sequence, Tuple

import cv2
import numpy as np

from can_seeker.evaluation.floor_bench import bench_config, look_text, mount_text
from can_seeker.sim.scene import Solid
from can_seeker.sim.simulation import camera_spec
from can_seeker.sim.world import World

OUTLINE_REACH_PX = 4
"""An object's pixels with floor within this many pixels form its outline, and the floor
pixels within this of one are the floor beside it."""
MIN_OUTLINE_PIXELS = 20
"""Fewer object pixels along the outline than this is no view of the object."""
WALL_VIEW_OFFSETS_M = (-1.0, 0.0, 1.0)
"""A wall is viewed from in front of its middle and this far along it either side (m)."""
OBSTACLE_VIEW_SIDES = 6
"""An obstacle is viewed from this many sides, evenly around it, the first from the start."""
CAN_AWAY_XY = (50.0, 50.0)
"""Where the can stands while a room is measured: out of every view (m)."""
MIN_VIEW_DISTANCE_M = 0.25
MAX_VIEW_DISTANCE_M = 1.2
"""Distance (m) of the camera from an object's foot: where the optical axis meets the floor,
within these (a camera pitched little looks far)."""


def outline_contrast_levels(image: np.ndarray, object_mask: np.ndarray,
                            floor_mask: np.ndarray) -> Optional[float]:
    """Median, over the object's pixels along its outline with the floor in ``image`` (HxWxC),
    of the largest channel difference (levels) from the mean of the floor pixels around each:
    on a checker the floor beside an object is one tile, not the mix of both. None where
    object and floor share too little outline to judge."""
    side = 2 * OUTLINE_REACH_PX + 1
    floor = floor_mask.astype(np.float64)
    floor_count = cv2.boxFilter(floor, -1, (side, side), normalize=False,
                                borderType=cv2.BORDER_CONSTANT)
    outline = object_mask & (floor_count > 0)
    if np.count_nonzero(outline) < MIN_OUTLINE_PIXELS:
        return None
    pixels = image.astype(np.float64).reshape(image.shape[:2] + (-1,))
    differences = []
    for channel in range(pixels.shape[2]):
        floor_sum = cv2.boxFilter(pixels[:, :, channel] * floor, -1, (side, side),
                                  normalize=False, borderType=cv2.BORDER_CONSTANT)
        local_floor = floor_sum[outline] / floor_count[outline]
        differences.append(np.abs(pixels[:, :, channel][outline] - local_floor))
    return float(np.median(np.max(differences, axis=0)))


def view_distance_m(camera_height_m: float, camera_pitch_rad: float) -> float:
    """Floor distance (m) from the camera at which its optical axis meets the floor, within
    MIN_VIEW_DISTANCE_M and MAX_VIEW_DISTANCE_M."""
    if camera_pitch_rad <= 0.0:
        return MAX_VIEW_DISTANCE_M
    distance = camera_height_m / math.tan(camera_pitch_rad)
    return min(MAX_VIEW_DISTANCE_M, max(MIN_VIEW_DISTANCE_M, distance))


def wall_views(wall: Solid, distance_m: float,
               camera_x_m: float) -> Iterator[Tuple[float, float, float]]:
    """Robot poses (x m, y m, yaw rad) that put a camera ``camera_x_m`` ahead of base_link
    ``distance_m`` from the inner face of ``wall`` (of a room about the origin), facing it."""
    along_x = abs(wall.x_m) >= abs(wall.y_m)
    centre = wall.x_m if along_x else wall.y_m
    thickness = wall.size_x_m if along_x else wall.size_y_m
    sign = math.copysign(1.0, centre)
    base = sign * (abs(centre) - thickness / 2.0 - distance_m - camera_x_m)
    yaw = (0.0 if along_x else math.pi / 2.0) + (math.pi if sign < 0.0 else 0.0)
    for offset in WALL_VIEW_OFFSETS_M:
        if along_x:
            yield base, wall.y_m + offset, yaw
        else:
            yield wall.x_m + offset, base, yaw


def obstacle_views(obstacle: Solid, distance_m: float, camera_x_m: float,
                   start_xy: Sequence[float] = (0.0, 0.0)
                   ) -> Iterator[Tuple[float, float, float]]:
    """Robot poses (x m, y m, yaw rad) facing the centre of ``obstacle`` from
    OBSTACLE_VIEW_SIDES sides, the first from ``start_xy``, with the camera ``camera_x_m``
    ahead of base_link ``distance_m`` outside its bounding circle."""
    first = math.atan2(start_xy[1] - obstacle.y_m, start_xy[0] - obstacle.x_m)
    reach = obstacle.bounding_radius_m + distance_m + camera_x_m
    for side in range(OBSTACLE_VIEW_SIDES):
        direction = first + 2.0 * math.pi * side / OBSTACLE_VIEW_SIDES
        yield (obstacle.x_m + reach * math.cos(direction),
               obstacle.y_m + reach * math.sin(direction), direction + math.pi)


def least_contrast(levels: Sequence[Optional[float]]) -> Optional[float]:
    """The least of the judged views' contrasts (None when no view judged the object)."""
    judged = [level for level in levels if level is not None]
    return min(judged) if judged else None


@dataclass
class RoomContrast:
    """One room's objects and their least rendered contrast (levels; None: never in view)."""

    seed: int
    mount: str
    look: str
    walls: Dict[str, Optional[float]] = field(default_factory=dict)
    obstacles: Dict[str, Optional[float]] = field(default_factory=dict)

    @staticmethod
    def least(objects: Dict[str, Optional[float]]) -> Tuple[Optional[str], Optional[float]]:
        """(name, contrast) of the object of ``objects`` rendered closest to the floor."""
        judged = [(level, name) for name, level in objects.items() if level is not None]
        if not judged:
            return None, None
        level, name = min(judged)
        return name, level


def summary_rows(results: List[RoomContrast], thresholds: Sequence[float]) -> List[str]:
    """Markdown rows: one per room (its faintest wall and obstacle), then per threshold how
    many rooms hold a wall, an obstacle or either rendered within it of the floor."""
    def text(name, level):
        return '-' if name is None else '%s %.1f' % (name, level)

    rows = ['| seed | faintest wall (levels) | faintest obstacle (levels) | look | mount |',
            '|---|---|---|---|---|']
    for result in results:
        rows.append('| %d | %s | %s | %s | %s |' % (
            result.seed, text(*result.least(result.walls)),
            text(*result.least(result.obstacles)), result.look, result.mount))
    rows += ['', '| within (levels) | rooms with a wall | with an obstacle | with either |',
             '|---|---|---|---|']

    def within(objects, threshold):
        level = RoomContrast.least(objects)[1]
        return level is not None and level <= threshold

    for threshold in thresholds:
        walls = {result.seed for result in results if within(result.walls, threshold)}
        obstacles = {result.seed for result in results if within(result.obstacles, threshold)}
        rows.append('| %g | %d | %d | %d: %s |' % (
            threshold, len(walls), len(obstacles), len(walls | obstacles),
            ' '.join(str(seed) for seed in sorted(walls | obstacles)) or '-'))
    return rows


def measure_room(urdf_path: str, seed: int, randomize_appearance: bool = False,
                 randomize_mount: bool = False) -> RoomContrast:
    """Render every wall and obstacle of the room trial ``seed`` from its views (the can
    moved out of the way) and keep each one's least contrast."""
    config = bench_config(seed, 'ideal', randomize_appearance, randomize_mount)
    camera = camera_spec(config)
    mount = camera.mount
    result = RoomContrast(seed, mount_text(mount), look_text(config.scene))
    distance_m = view_distance_m(mount.height_m, math.radians(mount.pitch_deg))
    camera_x_m = float(mount.translation_m[0])
    with World(urdf_path, camera, config.physics_rate, config.renderer,
               can_rgba=config.can_color, scene=config.scene,
               can_texture=config.can_texture) as world:
        world.place_can(*CAN_AWAY_XY)
        for solid in config.scene.solids:
            is_wall = solid.name.startswith('wall')
            views = (wall_views(solid, distance_m, camera_x_m) if is_wall
                     else obstacle_views(solid, distance_m, camera_x_m))
            levels = []
            for pose in views:
                world.reset_robot(*pose)
                image, masks = world.render_segmented()
                if solid.name in masks and 'floor' in masks:
                    levels.append(outline_contrast_levels(image, masks[solid.name],
                                                          masks['floor']))
            (result.walls if is_wall else result.obstacles)[solid.name] = least_contrast(levels)
    return result
