"""Camera scan: per-column obstacle bases -> LaserScan ranges, on synthetic masks and on images
rendered by the simulator's pybullet world with obstacles of known geometry."""
import math
import pathlib

import cv2
import numpy as np
import pybullet
import pytest

from can_seeker.camera_geometry import (CameraPose, camera_pose_from_mount, floor_point,
                                        intrinsics_from_vertical_fov, project_floor_points)
from can_seeker.camera_mount import CameraMount
from can_seeker.sim.world import CameraSpec, World
from can_seeker.vision.camera_scan import (FREE_SPAN_TOLERANCE_M, SCAN_DEFAULTS, CameraScanner,
                                           draw_obstacles, lowest_obstacle_rows, robot_pixels,
                                           scan_geometry, scan_ranges)
from can_seeker.vision.floor import FloorSettings

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')
MOUNT = CameraMount(0.25, 25.0)
WIDTH, HEIGHT = 320, 240
POSE = camera_pose_from_mount(MOUNT)
INTRINSICS = intrinsics_from_vertical_fov(WIDTH, HEIGHT, 45.0)


def bin_angles(geometry):
    return geometry.angle_min + np.arange(geometry.bins) * geometry.angle_increment


def test_geometry_spans_the_view_and_the_visible_floor():
    geometry = scan_geometry(POSE, INTRINSICS, 4.0)
    half_fov = math.atan((WIDTH / 2) / INTRINSICS.fx)
    assert -half_fov <= geometry.angle_min < -0.9 * half_fov
    assert 0.9 * half_fov < geometry.angle_max <= half_fov
    assert geometry.bins == pytest.approx(WIDTH, abs=3)
    bottom = floor_point(POSE, INTRINSICS, INTRINSICS.cx, HEIGHT - 0.5)
    assert geometry.range_min == pytest.approx(math.hypot(*bottom), abs=1e-6)
    assert 3.8 < geometry.range_max <= 4.0
    assert scan_geometry(POSE, INTRINSICS, 0.1) is None
    level = camera_pose_from_mount(CameraMount(0.25, -30.0))
    assert scan_geometry(level, INTRINSICS, 4.0) is None


def test_a_level_camera_over_the_scan_origin_has_one_bin_per_column():
    """Level, every row's columns span the same angles about the camera's own floor point, so
    the view is exactly as many bins wide as the centre row's columns, whatever the last bits
    of each row's arctan2."""
    level = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    for width, height in ((320, 240), (640, 480)):
        intrinsics = intrinsics_from_vertical_fov(width, height, 45.0)
        for height_m in (0.1, 0.2, 0.25, 0.3, 0.5):
            geometry = scan_geometry(CameraPose((0.0, 0.0, height_m), level), intrinsics, 4.0)
            assert geometry.bins == width


def test_column_base_range_is_the_floor_ray_of_its_lower_edge():
    geometry = scan_geometry(POSE, INTRINSICS, 4.0)
    obstacles = np.zeros((HEIGHT, WIDTH), np.uint8)
    obstacles[50:130, 200:210] = 255     # obstacle standing on row 129
    obstacles[20:40, 205:206] = 255      # something farther up the same column: hidden
    rows = lowest_obstacle_rows(obstacles, geometry.in_range)
    assert rows[205] == 129 and rows[100] == -1
    ranges = scan_ranges(geometry, rows)
    x, y = floor_point(POSE, INTRINSICS, 205.0, 129.5)
    angle = math.atan2(y, x)
    index = int(round((angle - geometry.angle_min) / geometry.angle_increment))
    assert ranges[index] == pytest.approx(math.hypot(x, y), rel=0.01)
    covered = np.flatnonzero(np.isfinite(ranges))
    assert covered.size == pytest.approx(10, abs=2)
    assert np.all(np.diff(covered) == 1)
    assert np.all(bin_angles(geometry)[covered] < 0.0)   # right of the optical axis


def test_bottom_row_obstacle_is_at_most_the_nearest_floor_and_far_ones_are_cut():
    geometry = scan_geometry(POSE, INTRINSICS, 2.0)
    obstacles = np.zeros((HEIGHT, WIDTH), np.uint8)
    obstacles[150:, :100] = 255
    obstacles[:10, 200:] = 255           # beyond 2 m
    ranges = scan_ranges(geometry, lowest_obstacle_rows(obstacles, geometry.in_range))
    left, right = ranges[bin_angles(geometry) > 0.1], ranges[bin_angles(geometry) < -0.1]
    # image columns >= 200: only obstacles beyond 2 m
    assert np.all(np.isinf(right[geometry.free_bins[bin_angles(geometry) < -0.1]]))
    assert np.all(np.isnan(right[~geometry.free_bins[bin_angles(geometry) < -0.1]]))
    assert np.nanmin(left) >= geometry.range_min - 1e-6
    assert np.nanmin(left) < geometry.range_min + 0.1


def test_a_column_taken_for_floor_up_past_the_horizon_measures_nothing():
    """A camera pitched 10 deg down sees the horizon 51 rows above the image centre. A column
    the floor model takes for floor up to above it holds something of the floor's colour
    standing somewhere along it (no floor lies there): NaN, not free floor, also where a band
    of it just above the horizon is an obstacle (its shading). A column whose obstacle pixels
    reach down to the horizon (a wall it tells from the floor, beyond range) is free up to
    range_max, and one with an obstacle in range is measured."""
    pose = camera_pose_from_mount(CameraMount(0.3, 10.0))
    geometry = scan_geometry(pose, INTRINSICS, 4.0)
    horizon_row = INTRINSICS.cy - INTRINSICS.fy * math.tan(math.radians(10.0))
    assert not geometry.sky[int(horizon_row) + 1:].any()
    assert geometry.sky[:int(horizon_row) - 3].all()
    obstacles = np.zeros((HEIGHT, WIDTH), np.uint8)
    obstacles[:int(horizon_row) - 1, :100] = 255         # a wall told from the floor
    obstacles[120:150, 100:140] = 255                    # an obstacle in range
    obstacles[int(horizon_row) - 6:int(horizon_row) - 3, 300:] = 255   # shading
    rows = lowest_obstacle_rows(obstacles, geometry.in_range, sky=geometry.sky)
    ranges = scan_ranges(geometry, rows)
    angles = bin_angles(geometry)
    wall = angles > math.atan2(WIDTH / 2 - 95, INTRINSICS.fx)
    unjudged = angles < math.atan2(WIDTH / 2 - 145, INTRINSICS.fx)
    assert np.all(np.isinf(ranges[wall & geometry.free_bins]))
    assert np.all(np.isnan(ranges[unjudged]))
    assert np.isfinite(ranges).sum() == pytest.approx(40, abs=3)
    # without the horizon, floor up to the top of the image reads as free floor
    assert not np.isnan(scan_ranges(geometry, lowest_obstacle_rows(
        obstacles, geometry.in_range))[geometry.free_bins]).any()



@pytest.mark.parametrize('height_m,pitch_deg', [
    (0.25, 25.0), (0.32, 30.0), (0.15, 15.0), (0.15, 35.0), (0.35, 15.0), (0.35, 35.0)])
def test_free_rays_lie_in_the_image_from_range_min_to_range_max(height_m, pitch_deg):
    """A ray read +inf says the floor along it is free from range_min to range_max: every
    point of it must be in the image. The image's floor is a trapezoid seen from ahead of
    base_link, so near the scan's sides a ray leaves the image long before the range the
    corners reach (a camera 0.32 m up pitched 30 deg sees 0.4 m along its outermost rays,
    not the 2.8 m of its top corners); those rays are NaN."""
    pose = camera_pose_from_mount(CameraMount(height_m, pitch_deg))
    geometry = scan_geometry(pose, INTRINSICS, 4.0)
    ranges = scan_ranges(geometry, np.full(WIDTH, -1))
    free = np.isinf(ranges)
    assert free.sum() > 0.75 * geometry.bins
    assert np.all(np.isnan(ranges[~free]))
    tolerance = FREE_SPAN_TOLERANCE_M + 0.01
    along = np.arange(geometry.range_min + tolerance, geometry.range_max - tolerance, 0.01)
    angles = bin_angles(geometry)[free]
    assert_in_image(pose, angles, along[None, :].repeat(angles.size, axis=0))
    # A range says the floor before it is free too: a wall across the image at row 150.
    obstacles = np.zeros((HEIGHT, WIDTH), np.uint8)
    obstacles[:151] = 255
    ranges = scan_ranges(geometry, lowest_obstacle_rows(obstacles, geometry.in_range))
    hit = np.isfinite(ranges)
    assert hit.sum() > 0.75 * geometry.bins
    hit &= ranges > geometry.range_min + 2 * tolerance
    fractions = np.linspace(0.0, 1.0, 50)
    along = geometry.range_min + tolerance + np.outer(ranges[hit] - 2 * tolerance
                                                      - geometry.range_min, fractions)
    assert_in_image(pose, bin_angles(geometry)[hit], along)


def assert_in_image(pose, angles, along):
    """Floor points at ``along`` (rows per angle, m) on rays at ``angles`` (rad) from base_link
    all lie in the image."""
    points = np.stack((np.cos(angles)[:, None] * along, np.sin(angles)[:, None] * along,
                       np.zeros(along.shape)), axis=-1).reshape(-1, 3)
    u, v = project_floor_points(pose, INTRINSICS, points).T
    assert u.size == points.shape[0]
    assert np.all((u >= -0.5) & (u <= WIDTH - 0.5) & (v >= -0.5) & (v <= HEIGHT - 0.5))


@pytest.mark.parametrize('bearing_rad', [0.52, 0.56])
def test_an_obstacle_beside_the_view_is_not_scanned_as_free_floor(bearing_rad):
    """A low box at the image's left edge, 2.2 m off, from a camera 0.32 m up pitched 30 deg:
    its corner shows in the outermost 4 columns (a sliver the floor model drops), or it is
    just beyond the edge. No ray reads +inf through it: base_link's outermost rays run through
    it, outside the image or in that sliver."""
    mount = CameraMount(0.32, 30.0)
    pose = camera_pose_from_mount(mount)
    with World(URDF, CameraSpec(WIDTH, HEIGHT, 45.0, mount)) as world:
        client = world._client
        centre = 2.2 * np.array((math.cos(bearing_rad), math.sin(bearing_rad)))
        shape = client.createVisualShape(pybullet.GEOM_BOX, halfExtents=(0.15, 0.15, 0.08),
                                         rgbaColor=(0.12, 0.12, 0.14, 1))
        client.createMultiBody(0, -1, shape, (centre[0], centre[1], 0.08),
                               pybullet.getQuaternionFromEuler((0.0, 0.0, bearing_rad)))
        world.place_can(8.0, 8.0)
        scanner = CameraScanner()
        ranges = scanner.scan(world.render(), pose, INTRINSICS).ranges
    geometry = scanner.geometry
    along = np.arange(geometry.range_min, geometry.range_max, 0.01)
    angles = bin_angles(geometry)
    points = np.stack((np.cos(angles), np.sin(angles)), axis=-1)[:, None, :] * along[None, :, None]
    local = (points - centre) @ np.array(((math.cos(bearing_rad), -math.sin(bearing_rad)),
                                          (math.sin(bearing_rad), math.cos(bearing_rad))))
    through_box = np.any(np.all(np.abs(local) <= 0.15, axis=-1), axis=1)
    assert through_box.any()
    assert not np.any(np.isinf(ranges[through_box]))


# Rendered scenes: boxes (centre x, y, half sizes x, y, height) and cylinders (x, y, radius,
# height) on a uniform floor, in base_link of the robot at the origin.
BOXES = ((2.3, -0.2, 0.1, 0.6, 0.4), (1.1, 0.45, 0.15, 0.1, 0.25))
CYLINDERS = ((1.7, -0.55, 0.12, 0.3),)


def ray_to_obstacles(angle_rad):
    """Distance (m) from the origin along a floor ray to the nearest obstacle footprint."""
    direction = np.array((math.cos(angle_rad), math.sin(angle_rad)))
    best = math.inf
    for x, y, half_x, half_y, _ in BOXES:
        with np.errstate(divide='ignore'):
            low = (np.array((x - half_x, y - half_y))) / direction
            high = (np.array((x + half_x, y + half_y))) / direction
        near, far = np.max(np.minimum(low, high)), np.min(np.maximum(low, high))
        if near <= far and near > 0:
            best = min(best, near)
    for x, y, radius, _ in CYLINDERS:
        along = direction @ (x, y)
        miss = (x * x + y * y) - along * along
        if miss <= radius * radius and along > 0:
            best = min(best, along - math.sqrt(radius * radius - miss))
    return best


@pytest.fixture(scope='module')
def room():
    """A world with the scene's obstacles, floor and obstacle colours set per test."""
    with World(URDF, CameraSpec(WIDTH, HEIGHT, 45.0, MOUNT)) as world:
        client = world._client
        bodies = []
        for x, y, half_x, half_y, height in BOXES:
            shape = client.createVisualShape(pybullet.GEOM_BOX,
                                             halfExtents=(half_x, half_y, height / 2))
            bodies.append(client.createMultiBody(0, -1, shape, (x, y, height / 2)))
        for x, y, radius, height in CYLINDERS:
            shape = client.createVisualShape(pybullet.GEOM_CYLINDER, radius=radius,
                                             length=height)
            bodies.append(client.createMultiBody(0, -1, shape, (x, y, height / 2)))
        world.place_can(8.0, 8.0)

        def paint(floor_rgba, obstacle_rgba):
            client.changeVisualShape(0, -1, rgbaColor=floor_rgba, textureUniqueId=-1)
            for body in bodies:
                client.changeVisualShape(body, -1, rgbaColor=obstacle_rgba)
            return world

        yield paint


def test_one_opencv_thread_scans_what_the_default_threads_scan(room):
    """obstacle_scan runs OpenCV on one thread: its masks and ranges stay the very same."""
    frames = [room(floor, (0.6, 0.45, 0.3, 1)).render()
              for floor in ((0.3, 0.45, 0.6, 1), (0.32, 0.46, 0.58, 1))]
    default_threads = cv2.getNumThreads()
    results = []
    try:
        for threads in (default_threads, 1):
            cv2.setNumThreads(threads)
            scanner = CameraScanner()
            results.append([scanner.scan(frame, POSE, INTRINSICS) for frame in frames])
    finally:
        cv2.setNumThreads(default_threads)
    assert np.isfinite(results[0][-1].ranges).any()
    for default, single in zip(*results):
        assert np.array_equal(default.obstacles, single.obstacles)
        assert np.array_equal(default.ranges, single.ranges, equal_nan=True)


@pytest.mark.parametrize('floor,obstacle', [
    ((0.75, 0.72, 0.65, 1), (0.12, 0.12, 0.12, 1)),   # dark obstacles on a light floor
    ((0.15, 0.13, 0.12, 1), (0.85, 0.85, 0.8, 1)),    # light obstacles on a dark floor
    ((0.3, 0.45, 0.6, 1), (0.6, 0.45, 0.3, 1)),       # colour contrast only
])
def test_rendered_scan_matches_the_obstacle_geometry(room, floor, obstacle):
    image = room(floor, obstacle).render()
    scanner = CameraScanner()
    result = scanner.scan(image, POSE, INTRINSICS)
    angles = bin_angles(scanner.geometry)
    truth = np.array([ray_to_obstacles(angle) for angle in angles])
    near = truth <= 2.5
    seen = near & np.isfinite(result.ranges)
    assert seen.sum() >= 0.9 * near.sum()
    error = np.abs(result.ranges[seen] - truth[seen]) / truth[seen]
    assert np.median(error) < 0.02
    assert np.percentile(error, 90) < 0.06
    # Free directions (not within 0.03 rad of an obstacle's side, where the silhouette of a
    # pitched camera's view of a tall obstacle leans past its footprint) are +inf.
    free = np.convolve(np.isfinite(truth), np.ones(27), 'same') == 0
    assert free.sum() > 15
    assert np.all(np.isinf(result.ranges[free & scanner.geometry.free_bins]))
    annotated = draw_obstacles(image, result, scanner.floor.reference_corners)
    assert annotated.shape == image.shape and np.any(annotated != image)


def test_red_can_is_an_obstacle_unless_excluded(room):
    """By default the scan reports the can like any obstacle (as a lidar does): a consumer
    that leaves it out must know it is its target (can_stopper does, only while it approaches
    it); excluded, the red blob is neither floor nor obstacle."""
    world = room((0.75, 0.72, 0.65, 1), (0.12, 0.12, 0.12, 1))
    world.place_can(0.8, -0.1)
    try:
        image = world.render()
    finally:
        world.place_can(8.0, 8.0)
    can_angle = math.atan2(-0.1, 0.8)
    for scanner, expect_can in ((CameraScanner(exclude_can=True), False),
                                (CameraScanner(exclude_can=False), True),
                                (CameraScanner(), True)):
        ranges = scanner.scan(image, POSE, INTRINSICS).ranges
        index = int(round((can_angle - scanner.geometry.angle_min)
                          / scanner.geometry.angle_increment))
        near_can = ranges[index - 2:index + 3]
        assert np.any(np.abs(near_can - (math.hypot(0.8, 0.1) - 0.033)) < 0.05) == expect_can


def test_nothing_in_view_is_free_everywhere(room):
    world = room((0.75, 0.72, 0.65, 1), (0.12, 0.12, 0.12, 1))
    world.place_can(-8.0, 8.0)
    scanner = CameraScanner()
    for floor_model in ('adaptive', 'dark'):
        scanner.floor = type(scanner.floor)(FloorSettings(floor_model=floor_model))
        # Look away from the obstacles: the camera pose turned by 180 degrees about z.
        turned = type(POSE)(POSE.position, np.diag((-1.0, -1.0, 1.0)) @ POSE.rotation)
        client = world._client
        robot_yaw = pybullet.getQuaternionFromEuler((0.0, 0.0, math.pi))
        client.resetBasePositionAndOrientation(world._robot, (0.0, 0.0, 0.05), robot_yaw)
        image = world.render()
        world.reset_robot()
        ranges = scanner.scan(image, turned, INTRINSICS).ranges
        assert np.all(np.isinf(ranges[scanner.geometry.free_bins])), floor_model
        assert np.all(np.isnan(ranges[~scanner.geometry.free_bins])), floor_model
    world.place_can(8.0, 8.0)


def banded_can_scene(width=WIDTH, height=HEIGHT):
    """A grey floor and a can drawn as a soda can: silver lid, red top, white band with dark
    marks, red bottom, silver base; its base on row 150 in columns 150-165."""
    rng = np.random.default_rng(2)
    image = np.clip(rng.normal(150.0, 3.0, (height, width, 3)), 0, 255).astype(np.uint8)
    columns = slice(150, 166)
    image[100:103, columns] = (200, 200, 205)          # lid
    image[103:118, columns] = (30, 25, 200)            # red
    image[118:128, columns] = (245, 245, 245)          # band
    image[121:125, 153:163:3] = (40, 40, 40)           # lettering-like marks
    image[128:148, columns] = (30, 25, 200)            # red
    image[148:151, columns] = (190, 190, 195)          # base
    return image


def test_banded_can_with_rims_is_not_an_obstacle():
    image = banded_can_scene()
    scanner = CameraScanner(exclude_can=True)
    excluded = scanner.scan(image, POSE, INTRINSICS)
    assert not excluded.obstacles.any()
    assert np.all(np.isinf(excluded.ranges[scanner.geometry.free_bins]))
    included = CameraScanner(exclude_can=False).scan(image, POSE, INTRINSICS)
    assert included.obstacle_rows[155] == 150


def test_floor_hidden_behind_the_can_is_not_measured():
    """A wall touching the top of the can: its base behind the can is NaN, beside it a range."""
    image = banded_can_scene()
    image[40:101, :] = (40, 40, 40)                     # a wall standing on row 100
    result = CameraScanner(exclude_can=True).scan(image, POSE, INTRINSICS)
    geometry = CameraScanner().geometry_for(POSE, INTRINSICS)
    angles = bin_angles(geometry)
    can_left, can_right = (math.atan2(*floor_point(POSE, INTRINSICS, u, 150.5)[::-1])
                           for u in (149.5, 165.5))
    hidden = (angles < can_left - 0.01) & (angles > can_right + 0.01)
    assert hidden.any() and np.all(np.isnan(result.ranges[hidden]))
    beside = (angles > can_left + 0.05) | (angles < can_right - 0.05)
    wall_x = floor_point(POSE, INTRINSICS, INTRINSICS.cx, 100.5)[0]   # a row is a line x = c
    beside &= np.abs(angles) < 0.4
    assert np.allclose(result.ranges[beside], wall_x / np.cos(angles[beside]), rtol=0.01)
    clear = banded_can_scene()
    clear[40:80, :] = (40, 40, 40)                      # floor seen between can and wall
    ranges = CameraScanner(exclude_can=True).scan(clear, POSE, INTRINSICS).ranges
    assert not np.isnan(ranges[geometry.free_bins]).any() and np.isfinite(ranges[hidden]).all()


def test_rendered_textured_can_is_never_an_obstacle():
    """The simulator's soda can (silver lid and base, white lettering band) at 0.45-3 m, ahead
    and to the sides: no obstacle bin anywhere. Up to 1.5 m the floor is seen over it; at 3 m
    the ray over its lid meets the floor beyond max_range, so what lies behind it is NaN."""
    with World(URDF, CameraSpec(WIDTH, HEIGHT, 45.0, MOUNT), can_texture='textured') as world:
        scanner = CameraScanner(exclude_can=True)
        for distance in (0.45, 0.8, 1.5, 3.0):
            for bearing in (-0.3, 0.0, 0.3):
                world.place_can(distance * math.cos(bearing), distance * math.sin(bearing))
                ranges = scanner.scan(world.render(), POSE, INTRINSICS).ranges
                assert not np.isfinite(ranges).any(), (distance, bearing)
                behind = np.isnan(ranges[scanner.geometry.free_bins]).any()
                assert behind == (distance > 2.0), (distance, bearing)


def test_the_excluded_can_is_the_most_can_like_red_blob_not_the_largest():
    """A red poster larger than the can stands left of it: the can (image_converter's choice)
    is left out and the poster is an obstacle."""
    with World(URDF, CameraSpec(WIDTH, HEIGHT, 45.0, MOUNT), can_texture='textured') as world:
        world.place_can(0.8, -0.15)
        image = world.render()
    image[70:112, 10:130] = (30, 25, 200)               # the poster stands on row 111
    result = CameraScanner(exclude_can=True).scan(image, POSE, INTRINSICS)
    geometry = CameraScanner().geometry_for(POSE, INTRINSICS)
    angles = bin_angles(geometry)
    can_angle = math.atan2(-0.15, 0.8)
    near_can = np.abs(angles - can_angle) < 0.03
    assert near_can.any() and not np.isfinite(result.ranges[near_can]).any()
    poster_left, poster_right = (math.atan2(*floor_point(POSE, INTRINSICS, u, 111.5)[::-1])
                                 for u in (20.0, 120.0))
    behind_poster = (angles < poster_left) & (angles > poster_right)
    poster_x = floor_point(POSE, INTRINSICS, INTRINSICS.cx, 111.5)[0]
    assert np.allclose(result.ranges[behind_poster], poster_x / np.cos(angles[behind_poster]),
                       rtol=0.02)


LOW_STEEP_MOUNT = CameraMount(0.15, 35.0)
"""A camera low and steep enough to see the front of the robot's top (0.15 m up, 35 deg down)."""


def test_a_low_steep_camera_sees_its_robot_where_the_body_model_says():
    """Rendered with the robot's body green, the green pixels at the bottom of the image are
    the ones whose rays meet the body's top (~robot_radius, ~robot_height) before the floor
    (the renderer's cylinder is a polygon: the model's circle reaches a little wider beside its
    front); the default mount sees none of it, and no robot pixel measures floor."""
    pose = camera_pose_from_mount(LOW_STEEP_MOUNT)
    with World(URDF, CameraSpec(WIDTH, HEIGHT, 45.0, LOW_STEEP_MOUNT)) as world:
        client = world._client
        client.changeVisualShape(world._robot, -1, rgbaColor=(0.0, 1.0, 0.0, 1))
        world.place_can(8.0, 8.0)
        image = world.render().astype(int)
    green = (image[..., 1] > image[..., 2] + 40) & (image[..., 1] > image[..., 0] + 40)
    body = robot_pixels(pose, INTRINSICS, SCAN_DEFAULTS.robot_radius, SCAN_DEFAULTS.robot_height)
    assert green.sum() > 500
    assert (green & body).sum() >= 0.9 * green.sum()
    assert body.sum() <= 2.0 * green.sum()
    assert not robot_pixels(POSE, INTRINSICS, SCAN_DEFAULTS.robot_radius,
                            SCAN_DEFAULTS.robot_height).any()
    geometry = scan_geometry(pose, INTRINSICS, 4.0, SCAN_DEFAULTS.robot_radius,
                             SCAN_DEFAULTS.robot_height)
    assert np.array_equal(geometry.robot, body) and not geometry.in_range[body].any()


def test_the_robots_own_body_is_not_learned_as_floor():
    """A low steep camera has the robot's light grey top in the floor model's reference area:
    learned as floor, it made a box of that grey ahead floor too. Left out, the box is an
    obstacle and the body itself is neither obstacle nor floor."""
    pose = camera_pose_from_mount(LOW_STEEP_MOUNT)
    rng = np.random.default_rng(0)
    floor = np.clip(60.0 + rng.normal(0.0, 2.0, (HEIGHT, WIDTH, 3)), 0, 255).astype(np.uint8)
    body = robot_pixels(pose, INTRINSICS, SCAN_DEFAULTS.robot_radius, SCAN_DEFAULTS.robot_height)
    floor[body] = (130, 130, 130)
    ahead = floor.copy()
    ahead[60:120, 120:200] = (130, 130, 130)
    box = np.zeros(body.shape, bool)
    box[60:120, 120:200] = True
    for radius_m, found in ((SCAN_DEFAULTS.robot_radius, True), (0.0, False)):
        scanner = CameraScanner(robot_radius_m=radius_m)
        scanner.scan(floor, pose, INTRINSICS)
        result = scanner.scan(ahead, pose, INTRINSICS)
        recall = (result.obstacles[box] > 0).mean()
        assert (recall > 0.98) if found else (recall < 0.1)
        assert not (result.obstacles[body] > 0).any()
