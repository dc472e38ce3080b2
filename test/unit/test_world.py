"""The pybullet world: physics, driving, can placement, contact and the rendered camera."""
import math
import pathlib

import numpy as np
import pytest

from can_seeker.camera_geometry import camera_pose_from_mount
from can_seeker.camera_mount import CameraMount
from can_seeker.sim.drive import TwistLimiter
from can_seeker.sim.scene import Scene, Solid, empty_bounds
from can_seeker.sim.world import (CAN_HEIGHT_M, CameraSpec, World, checker_image,
                                  rgba_to_image)

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')
CAMERA = CameraSpec(160, 120, 45.0, CameraMount(0.25, 25.0))


@pytest.fixture(scope='module')
def shared_world():
    with World(URDF, CAMERA, renderer='tiny') as world:
        yield world


@pytest.fixture
def world(shared_world):
    shared_world.reset_robot()
    shared_world.place_can(5.0, 5.0)
    return shared_world


def drive(world, linear_mps, angular_radps, duration_s, limiter=None):
    """Drive at a twist (acceleration-limited) for ``duration_s``, then brake for 1 s."""
    limiter = limiter or TwistLimiter(1.0, 4.0)
    for step in range(int(round((duration_s + 1.0) / world.dt_s))):
        moving = step < round(duration_s / world.dt_s)
        world.set_twist(*limiter.step(linear_mps if moving else 0.0,
                                      angular_radps if moving else 0.0, world.dt_s))
        world.step()


def red_pixels(bgr):
    blue, green, red = (bgr[:, :, channel].astype(int) for channel in range(3))
    return (red > 60) & (red > 2 * green) & (red > 2 * blue)


def project(point_m, camera=CAMERA):
    """Pixel (u, v) of a point given in base_link of a robot at the origin."""
    pose = camera_pose_from_mount(camera.mount)
    x, y, z = pose.rotation.T @ (np.asarray(point_m) - np.asarray(pose.position))
    intrinsics = camera.intrinsics
    return intrinsics.fx * x / z + intrinsics.cx, intrinsics.fy * y / z + intrinsics.cy


def test_robot_starts_level_on_the_floor_at_the_origin(world):
    for _ in range(240):
        world.step()
    state = world.robot_state()
    assert state.position == pytest.approx((0.0, 0.0, 0.0), abs=1e-4)
    assert state.yaw_rad == pytest.approx(0.0, abs=1e-4)
    roll_pitch = 2.0 * np.asarray(state.orientation_xyzw[:2])
    assert np.abs(roll_pitch).max() < 1e-4


def test_driving_straight_covers_speed_times_time(world):
    drive(world, 0.2, 0.0, 1.0)
    state = world.robot_state()
    assert state.position[0] == pytest.approx(0.2, rel=0.01)
    assert state.position[1] == pytest.approx(0.0, abs=0.002)
    assert state.linear_velocity == pytest.approx((0.0, 0.0, 0.0), abs=1e-3)


def test_turning_in_place_covers_rate_times_time(world):
    drive(world, 0.0, 1.0, 1.0)
    state = world.robot_state()
    assert state.yaw_rad == pytest.approx(1.0, rel=0.01)
    assert math.hypot(*state.position[:2]) < 0.002


def test_robot_pose_is_robot_states_pose(world):
    """The odometry reads the pose without the twist: the very numbers robot_state holds."""
    drive(world, 0.2, 0.8, 0.7)
    state = world.robot_state()
    assert world.robot_pose() == (state.position[0], state.position[1], state.yaw_rad)
    assert world.robot_pose()[2] == pytest.approx(0.8 * 0.7, rel=0.02)


def test_twist_is_reported_in_base_link(world):
    limiter = TwistLimiter(1.0, 4.0)
    drive(world, 0.0, 1.0, math.pi / 2, limiter)
    for _ in range(240):
        world.set_twist(*limiter.step(0.2, 0.0, world.dt_s))
        world.step()
    state = world.robot_state()
    assert state.yaw_rad == pytest.approx(math.pi / 2, abs=0.03)
    assert state.linear_velocity[0] == pytest.approx(0.2, rel=0.01)
    assert abs(state.linear_velocity[1]) < 0.005
    assert state.angular_velocity[2] == pytest.approx(0.0, abs=0.01)


def test_a_stopped_robot_does_not_creep(world):
    drive(world, 0.2, 0.0, 0.5)
    before = world.robot_state().position
    for _ in range(5 * 240):
        world.set_twist(0.0, 0.0)
        world.step()
    assert math.dist(before, world.robot_state().position) < 1e-4


def test_reset_puts_the_robot_back_at_rest(world):
    drive(world, 0.3, 0.5, 1.0)
    world.reset_robot()
    state = world.robot_state()
    assert state.position == pytest.approx((0.0, 0.0, 0.0), abs=1e-6)
    assert state.yaw_rad == pytest.approx(0.0, abs=1e-6)
    assert state.linear_velocity == pytest.approx((0.0, 0.0, 0.0), abs=1e-6)


def test_can_stands_where_it_is_placed(world):
    world.place_can(1.2, -0.4)
    for _ in range(240):
        world.step()
    position, orientation = world.can_pose()
    assert position == pytest.approx((1.2, -0.4, CAN_HEIGHT_M / 2.0), abs=1e-3)
    assert abs(orientation[3]) == pytest.approx(1.0, abs=1e-4)
    assert world.can_home == (1.2, -0.4)
    assert not world.robot_touches_can()


def test_a_placed_can_settles_the_same_whatever_it_did_before(world):
    """A trial's start must not depend on how long the can stood before it (the harness's
    warm-up): the engine's remembered contacts made it settle ~1e-10 m differently."""
    def settled_after_standing(steps):
        world.place_can(1.0, 0.0)
        for _ in range(steps):
            world.set_twist(0.0, 0.8)
            world.step()
        world.reset_robot()
        world.place_can(1.0, 0.0)
        for _ in range(480):
            world.step()
        return world.can_pose()

    assert settled_after_standing(288) == settled_after_standing(336)


def test_driving_into_the_can_touches_and_pushes_it(world):
    world.place_can(0.45, 0.0)
    limiter = TwistLimiter(1.0, 4.0)
    touched = False
    for _ in range(3 * 240):
        world.set_twist(*limiter.step(0.2, 0.0, world.dt_s))
        world.step()
        touched = touched or world.robot_touches_can()
    assert touched
    can_x_m = world.can_pose()[0][0]
    robot_x_m = world.robot_state().position[0]
    assert can_x_m > 0.45 + 0.2
    assert can_x_m - robot_x_m == pytest.approx(0.165 + 0.033, abs=0.03)


@pytest.mark.parametrize('linear_mps, front', [(0.2, True), (-0.2, False)])
def test_a_touch_is_on_the_front_half_only_when_the_robot_drives_into_it(world, linear_mps,
                                                                          front):
    """The bumper's half: the can touched ahead of base_link is, one backed into is not."""
    world.place_can(0.45 if front else -0.45, 0.0)
    limiter = TwistLimiter(1.0, 4.0)
    touches = []
    for _ in range(3 * 240):
        world.set_twist(*limiter.step(linear_mps, 0.0, world.dt_s))
        world.step()
        touches.append(world.touches())
    assert any('can' in names for names, _ in touches)
    assert any(on_front for _, on_front in touches) is front
    assert all(names or not on_front for names, on_front in touches)


def test_camera_sees_the_can_where_it_projects(world):
    world.place_can(0.9, 0.2)
    world.step()
    bgr = world.render('bgr8')
    assert bgr.shape == (120, 160, 3) and bgr.dtype == np.uint8
    rows, columns = np.nonzero(red_pixels(bgr))
    u, v = project((0.9, 0.2, CAN_HEIGHT_M / 2.0))
    assert columns.mean() == pytest.approx(u, abs=1.5)
    assert rows.mean() == pytest.approx(v, abs=1.5)
    top_u, top_v = project((0.9 - 0.033, 0.2, CAN_HEIGHT_M))
    bottom_u, bottom_v = project((0.9 - 0.033, 0.2, 0.0))
    assert rows.max() - rows.min() + 1 == pytest.approx(bottom_v - top_v, abs=2.0)


def test_rgb8_swaps_the_red_channel(world):
    world.place_can(0.9, 0.0)
    world.step()
    bgr, rgb = world.render('bgr8'), world.render('rgb8')
    assert red_pixels(bgr).sum() > 50
    assert np.array_equal(rgb, bgr[:, :, ::-1])


def test_can_colour_changes_the_image(world):
    world.place_can(0.9, 0.0)
    world.step()
    world.set_can_color((0.05, 0.8, 0.05, 1.0))
    try:
        assert red_pixels(world.render('bgr8')).sum() == 0
    finally:
        world.set_can_color((0.8, 0.05, 0.05, 1.0))


def test_rgba_to_image_is_the_channels_reversed_or_kept():
    rgba = np.random.default_rng(3).integers(0, 256, (24, 32, 4), dtype=np.uint8)
    assert np.array_equal(rgba_to_image(rgba, 'bgr8'), rgba[:, :, 2::-1])
    assert np.array_equal(rgba_to_image(rgba, 'rgb8'), rgba[:, :, :3])


def test_rgba_to_image_orders_channels():
    rgba = np.zeros((2, 3, 4), np.uint8)
    rgba[..., 0], rgba[..., 1], rgba[..., 2], rgba[..., 3] = 10, 20, 30, 255
    assert rgba_to_image(rgba, 'bgr8')[0, 0].tolist() == [30, 20, 10]
    assert rgba_to_image(rgba, 'rgb8')[0, 0].tolist() == [10, 20, 30]
    with pytest.raises(ValueError):
        rgba_to_image(rgba, 'mono8')


def test_unknown_renderer_is_refused():
    with pytest.raises(ValueError):
        World(URDF, CAMERA, renderer='vulkan')


def test_auto_renderer_produces_a_scene():
    with World(URDF, CameraSpec(64, 48, 45.0, CameraMount(0.25, 25.0)), renderer='auto') as world:
        assert world.renderer_name in ('egl', 'tiny')
        world.place_can(0.9, 0.0)
        assert red_pixels(world.render('bgr8')).sum() > 5


def test_missing_egl_plugin_falls_back_to_tinyrenderer(monkeypatch):
    monkeypatch.setattr('can_seeker.sim.world.importlib.util.find_spec', lambda name: None)
    small = CameraSpec(64, 48, 45.0, CameraMount(0.25, 25.0))
    with World(URDF, small, renderer='auto') as world:
        assert world.renderer_name == 'tiny'
        world.place_can(0.9, 0.0)
        assert red_pixels(world.render('bgr8')).sum() > 5
    with pytest.raises(RuntimeError):
        World(URDF, small, renderer='egl')


def test_a_checker_floor_shows_both_colours_in_1_m_squares(world):
    dark, light = (0.2, 0.3, 0.25, 1.0), (0.6, 0.55, 0.5, 1.0)
    world.set_scene(Scene(empty_bounds(), can_xy=(5.0, 5.0), floor_rgba=dark,
                          floor_checker_rgba=light))
    try:
        image = world.render('bgr8').astype(int)
    finally:
        world.set_scene(Scene(empty_bounds(), can_xy=(1.0, 0.0)))
    near_row = image[CAMERA.height - 10]
    left, right = near_row[CAMERA.width // 8], near_row[7 * CAMERA.width // 8]
    # floor from x 0 to 1 m: the square at y 0 to 1 m (left) is light, the one right of it dark
    light_bgr, dark_bgr = (128, 140, 153), (64, 76, 51)
    assert np.abs(left - light_bgr).max() < 20 and np.abs(right - dark_bgr).max() < 20
    texture = checker_image(dark, light)
    assert tuple(texture[0, 0]) == dark_bgr and tuple(texture[0, -1]) == light_bgr


def test_a_new_mount_moves_the_camera_and_its_images(world):
    """The can projects where the new mount's camera sees it (a world per trial may draw one)."""
    default = world.camera
    world.set_mount(CameraMount(0.33, 34.0))
    try:
        assert world.camera.mount == CameraMount(0.33, 34.0)
        position, _ = world.camera_pose()
        assert position[2] == pytest.approx(0.33, abs=1e-3)
        world.place_can(0.9, 0.2)
        world.step()
        rows, columns = np.nonzero(red_pixels(world.render('bgr8')))
        u, v = project((0.9, 0.2, CAN_HEIGHT_M / 2.0), world.camera)
        assert columns.mean() == pytest.approx(u, abs=1.5)
        assert rows.mean() == pytest.approx(v, abs=1.5)
        assert abs(v - project((0.9, 0.2, CAN_HEIGHT_M / 2.0), default)[1]) > 5.0
    finally:
        world.set_mount(default.mount)


GLASS = Solid('glass', 'box', 0.875, 0.0, 0.05, 1.2, 0.4, rgba=(0.8, 0.9, 0.9, 0.0))
"""A pane of alpha 0 across the robot's way 0.69 m ahead of its front."""


def frames_along(world, xs_m):
    """Three frames in a row from each robot x (m) of ``xs_m`` on the x axis."""
    frames = []
    for x_m in xs_m:
        world.reset_robot(x_m)
        world.step()
        frames.extend(world.render('bgr8') for _ in range(3))
    return frames


@pytest.mark.parametrize('renderer', ['tiny', 'egl'])
def test_a_solid_of_alpha_0_is_in_no_image_but_stops_the_robot(renderer):
    """No pixel of any frame shows the pane, its shadow neither (the EGL renderer draws a
    transparent body's shadow from the second frame on), yet the robot drives into it. One
    world at a time: with two EGL worlds open in one process, neither image showed the
    shadow."""
    xs_m = (0.0, 0.3, 0.45, 0.55)
    try:
        world = World(URDF, CAMERA, renderer=renderer,
                      scene=Scene(empty_bounds(), obstacles=(GLASS,), can_xy=(-5.0, 5.0)))
    except RuntimeError:
        pytest.skip('no EGL renderer here')
    with world:
        with_pane = frames_along(world, xs_m)
        world.reset_robot()
        limiter = TwistLimiter(1.0, 4.0)
        touches = []
        for _ in range(5 * 240):
            world.set_twist(*limiter.step(0.2, 0.0, world.dt_s))
            world.step()
            touches.append(world.touches())
        assert any(names == {'glass'} and front for names, front in touches)
        assert world.robot_state().position[0] == pytest.approx(0.85 - 0.165, abs=0.01)
    with World(URDF, CAMERA, renderer=renderer,
               scene=Scene(empty_bounds(), can_xy=(-5.0, 5.0))) as without:
        alone = frames_along(without, xs_m)
    assert all(np.array_equal(*pair) for pair in zip(with_pane, alone))
