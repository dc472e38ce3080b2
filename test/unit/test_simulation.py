"""Simulator parameters, can placement, step scheduling, command timeout and services' logic."""
import math
import pathlib

import numpy as np
import pytest

from can_seeker.params import defaults, read_params
from can_seeker.sim.scene import CAN_HEIGHT_M, CAN_RADIUS_M, Solid
from can_seeker.sim.simulation import (MIN_CAN_CLEARANCE_M, PARAMS, RateSchedule, Simulation,
                                       camera_spec, checked_config, mount_for, parse_rgba,
                                       random_can_position, scene_for)
from can_seeker.camera_mount import (RANDOM_HEIGHT_RANGE_M, RANDOM_PITCH_RANGE_DEG, CameraMount,
                                     random_mount)
from can_seeker.sim.world import World

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')


def config_with(**overrides):
    warnings = []
    return checked_config(defaults(PARAMS, overrides), warnings.append), warnings


def test_defaults_are_the_documented_robot():
    declared = {spec.name: spec.default for spec in PARAMS}
    assert (declared['width'], declared['height'], declared['fov_deg']) == (320, 240, 45.0)
    assert (declared['camera_rate'], declared['physics_rate']) == (15.0, 240.0)
    assert (declared['camera_height'], declared['camera_pitch_deg']) == (0.25, 25.0)
    assert declared['cmd_timeout'] == 0.5
    assert declared['gui'] is False
    for spec in PARAMS:
        assert spec.coerce(spec.default) == spec.default
        assert spec.doc


def test_bad_parameter_values_fall_back_to_defaults():
    raw = {'~width': -5, '~renderer': 'vulkan', '~camera_rate': 'fast', '~seed': 3}
    warnings = []
    params = read_params(PARAMS, lambda name, default: raw.get(name, default), warnings.append)
    assert (params.width, params.renderer, params.camera_rate) == (320, 'auto', 15.0)
    assert params.seed == 3
    assert len(warnings) == 3


def test_parse_rgba():
    assert parse_rgba('0.8 0.05 0.05 1') == (0.8, 0.05, 0.05, 1.0)
    assert parse_rgba('1,0,0.5,1') == (1.0, 0.0, 0.5, 1.0)
    for bad in ('red', '1 0 0', '1 0 0 1 1', '2 0 0 1', '-0.1 0 0 1'):
        with pytest.raises(ValueError):
            parse_rgba(bad)


def test_random_can_position_is_repeatable_and_in_range():
    assert random_can_position(7, 0.8, 2.0) == random_can_position(7, 0.8, 2.0)
    positions = [random_can_position(seed, 0.8, 2.0) for seed in range(200)]
    distances = [math.hypot(x, y) for x, y in positions]
    assert min(distances) >= 0.8 and max(distances) <= 2.0
    quadrants = {(x > 0, y > 0) for x, y in positions}
    assert len(quadrants) == 4
    assert len(set(positions)) == 200


def test_checked_config_places_the_can():
    config, warnings = config_with(can_placement='fixed', can_x=1.5, can_y=-0.5)
    assert config.can_position == (1.5, -0.5) and not warnings
    config, warnings = config_with(seed=4)
    assert config.can_position == random_can_position(4, 0.5, 3.0) and not warnings
    assert config.can_color == (0.8, 0.05, 0.05, 1.0)


def test_checked_config_repairs_inconsistent_values():
    config, warnings = config_with(can_rgba='pink', can_min_distance=1.5, can_max_distance=1.0)
    assert config.can_color == (0.8, 0.05, 0.05, 1.0)
    assert config.can_max_distance == 1.5
    assert math.hypot(*config.can_position) == pytest.approx(1.5)
    assert len(warnings) == 2
    config, warnings = config_with(can_placement='fixed', can_x=0.1, can_y=0.0)
    assert config.can_position == (1.0, 0.0) and len(warnings) == 1
    config, warnings = config_with(physics_rate=100.0, camera_rate=200.0, state_rate=150.0)
    assert (config.camera_rate, config.state_rate) == (100.0, 100.0) and len(warnings) == 2


def test_in_lockstep_a_scan_comes_every_whole_number_of_physics_steps():
    config, warnings = config_with(lockstep=True, scan_rate=7.0)
    assert config.scan_rate == pytest.approx(240.0 / 34) and len(warnings) == 1
    assert '34.286 physics steps' in warnings[0]
    for overrides in ({'lockstep': True, 'scan_rate': 10.0}, {'scan_rate': 7.0},
                      {'lockstep': True, 'scan_rate': 0.0}):
        config, warnings = config_with(**overrides)
        assert config.scan_rate == overrides['scan_rate'] and not warnings


def test_camera_spec_from_parameters():
    config, _ = config_with(width=640, height=480, camera_height=0.3, camera_pitch_deg=20.0)
    spec = camera_spec(config)
    assert (spec.width, spec.height) == (640, 480)
    assert (spec.mount.height_m, spec.mount.pitch_deg) == (0.3, 20.0)
    assert spec.intrinsics.fx == pytest.approx(579.411, abs=1e-3)


def test_random_mounts_are_repeatable_spread_over_the_ranges_and_apart_from_the_scene():
    mounts = [random_mount(seed) for seed in range(200)]
    assert mounts == [random_mount(seed) for seed in range(200)]
    heights = np.array([mount.height_m for mount in mounts])
    pitches = np.array([mount.pitch_deg for mount in mounts])
    assert RANDOM_HEIGHT_RANGE_M[0] <= heights.min() < 0.17 and 0.33 < heights.max() <= 0.35
    assert RANDOM_PITCH_RANGE_DEG[0] <= pitches.min() < 17.0 and 33.0 < pitches.max() <= 35.0
    fixed, _ = config_with(world='room', seed=5)
    drawn, _ = config_with(world='room', seed=5, randomize_mount=True)
    assert camera_spec(fixed).mount == CameraMount(0.25, 25.0)
    assert camera_spec(drawn).mount == random_mount(5) == mount_for(drawn, 5)
    assert mount_for(fixed, 5) == CameraMount(0.25, 25.0)
    assert scene_for(fixed, 9, print) == scene_for(drawn, 9, print)


def test_rate_schedule_divides_the_physics_rate():
    schedule = RateSchedule(15.0, 240.0)
    due = [step for step in range(1, 241) if schedule.due(step)]
    assert due == list(range(16, 241, 16))


def test_rate_schedule_does_not_drift_at_uneven_rates():
    schedule = RateSchedule(7.0, 240.0)
    due = [step for step in range(1, 2401) if schedule.due(step)]
    assert len(due) == 70
    assert all(abs(step - (index + 1) * 240.0 / 7.0) < 1.0 for index, step in enumerate(due))


def test_rate_schedule_counts_from_a_restart():
    schedule = RateSchedule(15.0, 240.0)
    assert [step for step in range(1, 24) if schedule.due(step)] == [16]
    schedule.restart(23)
    assert [step for step in range(24, 80) if schedule.due(step)] == [39, 55, 71]


@pytest.fixture(scope='module')
def simulation():
    config, _ = config_with(width=64, height=48, renderer='tiny')
    with World(URDF, camera_spec(config), renderer='tiny') as world:
        yield Simulation.from_config(world, config)


@pytest.fixture(scope='module')
def room_sim():
    config, _ = config_with(width=64, height=48, renderer='tiny', world='room', seed=3)
    with World(URDF, camera_spec(config), renderer='tiny', scene=config.scene) as world:
        yield Simulation.from_config(world, config)


@pytest.fixture
def sim(simulation):
    simulation.reset()
    simulation.world.place_can(5.0, 5.0)
    return simulation


def test_frames_and_state_come_at_their_rates(sim):
    start_s = sim.time_s
    results = [sim.step() for _ in range(240)]
    assert sim.time_s == pytest.approx(start_s + 1.0)
    frames = [result for result in results if result.image is not None]
    assert len(frames) == 15
    assert frames[0].image.shape == (48, 64, 3)
    assert sum(result.state_due for result in results) == 50
    assert frames[1].time_s - frames[0].time_s == pytest.approx(1.0 / 15.0)


def test_clock_ticks_every_step_by_default_else_at_its_rate_and_with_every_message(sim):
    assert all(sim.step().clock_due for _ in range(48))
    config, _ = config_with(width=64, height=48, renderer='tiny', clock_rate=20.0)
    with World(URDF, camera_spec(config), renderer='tiny') as world:
        sparse = Simulation.from_config(world, config)
        results = [sparse.step() for _ in range(240)]
    ticks = [result for result in results if result.clock_due]
    messages = [result for result in results if result.image is not None
                or result.state_due or result.scan is not None]
    assert set(map(id, messages)) <= set(map(id, ticks))
    assert len(messages) < len(ticks) < 100
    assert sum(1 for step, result in enumerate(results, 1) if step % 12 == 0
               and result.clock_due) == 20


def test_a_stale_command_brakes_the_robot(sim):
    sim.command(0.2, 0.0)
    stopped_s = None
    for _ in range(2 * 240):
        result = sim.step()
        if stopped_s is None and sim.executed_twist == (0.0, 0.0):
            stopped_s = result.time_s
    start_offset_s = stopped_s - (sim.time_s - 2.0)
    assert start_offset_s == pytest.approx(0.5 + 0.2, abs=0.01)
    assert sim.world.robot_state().position[0] == pytest.approx(0.1, rel=0.02)


def test_fresh_commands_keep_the_robot_moving(sim):
    for step in range(2 * 240):
        if step % 24 == 0:
            sim.command(0.0, 1.0)
        sim.step()
    assert sim.executed_twist == (0.0, 1.0)
    for _ in range(240):
        sim.step()
    assert sim.executed_twist == (0.0, 0.0)


def test_contact_is_reported_with_the_state(sim):
    sim.place_can(0.4, 0.0)
    touches = []
    for _ in range(2 * 240):
        sim.command(0.2, 0.0)
        result = sim.step()
        if result.state_due:
            assert result.touched <= {'can'}
            touches.append('can' in result.touched)
        else:
            assert not result.touched
    first_touch = touches.index(True)
    assert first_touch > 5
    assert not any(touches[:first_touch])
    assert sum(touches) > len(touches) // 4


def test_place_can_refuses_overlap_and_bad_numbers(sim):
    assert sim.place_can(1.0, 0.5)[0]
    assert sim.world.can_home == (1.0, 0.5)
    success, message = sim.place_can(MIN_CAN_CLEARANCE_M - 0.01, 0.0)
    assert not success and 'overlap' in message
    assert not sim.place_can(math.nan, 0.0)[0]
    assert sim.world.can_home == (1.0, 0.5)


def test_place_can_refuses_points_off_the_floor(sim):
    for x_m, y_m in ((150.0, 0.0), (0.0, -100.01), (1e6, 1e6)):
        success, message = sim.place_can(x_m, y_m)
        assert not success and 'off the floor' in message
    assert sim.world.can_home == (5.0, 5.0)
    for _ in range(240):
        sim.step()
    assert sim.world.can_pose()[0][2] == pytest.approx(CAN_HEIGHT_M / 2.0, abs=1e-3)


def test_a_room_refuses_cans_outside_its_walls_and_inside_obstacles(room_sim):
    scene = room_sim.world.scene
    obstacle = scene.obstacles[0]
    for x_m, y_m in ((3.2, 0.0), (0.0, -3.0), (obstacle.x_m, obstacle.y_m)):
        success, message = room_sim.place_can(x_m, y_m)
        assert not success, message
    assert room_sim.place_can(obstacle.x_m, obstacle.y_m)[1].endswith(obstacle.name)
    assert room_sim.place_can(2.8, 2.8)[0]


def test_driving_into_a_wall_reports_the_wall(room_sim):
    room_sim.set_scene(room_sim.world.scene)
    touched = set()
    for _ in range(30 * 240):
        room_sim.command(0.0, 0.0) if touched else room_sim.command(0.4, 0.0)
        result = room_sim.step()
        touched |= result.touched
        if touched and result.state_due:
            break
    assert touched == {'wall_front'}
    assert room_sim.world.robot_state().position[0] == pytest.approx(3.0 - 0.165, abs=0.02)


def expected_ranges(lidar, solids, surface_m=0.0):
    """Range of each beam of a lidar at the origin to the nearest solid grown by surface_m."""
    expected = np.full(lidar.beams, np.inf)
    distances = np.arange(lidar.range_min_m, lidar.range_max_m, 0.001)
    for solid in solids:
        for index, angle in enumerate(lidar.angles_rad()):
            inside = solid.distance_m(distances * math.cos(angle),
                                      distances * math.sin(angle)) <= surface_m
            if inside.any():
                expected[index] = min(expected[index], distances[np.argmax(inside)])
    return expected


def test_no_scan_is_cast_while_unwanted_and_the_rest_of_the_step_is_the_same(room_sim):
    room_sim.reset()
    wanted = [room_sim.step() for _ in range(48)]
    room_sim.reset()
    room_sim.scan_wanted = False
    try:
        unwanted = [room_sim.step() for _ in range(48)]
    finally:
        room_sim.scan_wanted = True
    assert sum(result.scan is not None for result in wanted) == 2
    assert all(result.scan is None for result in unwanted)
    assert [(result.state_due, result.image is None) for result in wanted] == [
        (result.state_due, result.image is None) for result in unwanted]


def test_the_scan_sees_walls_obstacles_and_can_where_they_are(room_sim):
    room_sim.set_scene(room_sim.world.scene)
    scans = [result.scan for result in (room_sim.step() for _ in range(240))
             if result.scan is not None]
    assert len(scans) == 10
    ranges = scans[-1]
    scene = room_sim.world.scene
    can = Solid('can', 'cylinder', *scene.can_xy, 2 * CAN_RADIUS_M, 2 * CAN_RADIUS_M,
                CAN_HEIGHT_M)
    solids = scene.solids + (can,)
    near, far = (expected_ranges(room_sim.lidar, solids, surface_m)
                 for surface_m in (0.003, -0.003))
    grazing = far - near > 0.01
    assert np.all(np.isfinite(ranges))
    assert grazing.sum() < 20
    assert np.abs(ranges - expected_ranges(room_sim.lidar, solids))[~grazing].max() < 0.003
    assert np.all((ranges[grazing] > near[grazing] - 0.003)
                  & (ranges[grazing] < far[grazing] + 0.003))
    assert ranges[room_sim.lidar.beams // 2] == pytest.approx(3.0, abs=0.002)


def test_reset_restores_robot_and_can(sim):
    sim.place_can(0.5, 0.0)
    for _ in range(2 * 240):
        sim.command(0.3, 0.0)
        sim.step()
    assert sim.world.can_pose()[0][0] > 0.55
    sim.reset()
    assert sim.executed_twist == (0.0, 0.0)
    assert sim.world.robot_state().position[0] == pytest.approx(0.0, abs=1e-6)
    assert sim.world.can_pose()[0][:2] == pytest.approx((0.5, 0.0))


def test_reset_trial_puts_robot_at_start_and_can_where_asked_in_one_call(sim):
    for _ in range(240):
        sim.command(0.3, 0.2)
        sim.step()
    success, _ = sim.reset_trial((-1.2, 0.4))
    assert success
    assert sim.executed_twist == (0.0, 0.0)
    assert sim.world.robot_state().position[:2] == pytest.approx((0.0, 0.0), abs=1e-6)
    assert sim.world.can_pose()[0][:2] == pytest.approx((-1.2, 0.4))
    assert sim.reset_trial(None)[0]
    assert sim.world.can_pose()[0][:2] == pytest.approx((-1.2, 0.4))


def test_reset_trial_refuses_a_can_on_the_robot_and_keeps_the_last_placement(sim):
    sim.place_can(1.0, 0.5)
    success, message = sim.reset_trial((0.1, 0.0))
    assert not success and 'overlap' in message
    assert sim.world.can_home == (1.0, 0.5)


def test_reset_forgets_a_touch_before_it(sim):
    sim.place_can(0.4, 0.0)
    for _ in range(240):
        sim.command(0.3, 0.0)
        sim.step()
    sim.reset_trial((1.0, 0.0))
    touches = [bool(result.touched) for result in (sim.step() for _ in range(24))
               if result.state_due]
    assert touches and not any(touches)


def test_a_reset_trial_sees_its_frames_one_period_after_the_reset(sim):
    for _ in range(5):
        sim.step()
    sim.reset_trial((1.0, 0.0))
    reset_step = sim.steps
    frames = [sim.steps for result in (sim.step() for _ in range(40)) if result.image is not None]
    assert frames == [reset_step + 16, reset_step + 32]


def _trial_after(history_steps, history_twist):
    """The robot's pose after a fixed trial that follows ``history_steps`` of driving at
    ``history_twist`` and a new scene, in a fresh world."""
    config, _ = config_with(width=32, height=24, renderer='tiny')
    with World(URDF, camera_spec(config), renderer='tiny', scene=config.scene) as world:
        simulation = Simulation.from_config(world, config)
        for _ in range(history_steps):
            simulation.command(*history_twist)
            simulation.step()
        simulation.set_scene(scene_for(config, 100, print))
        simulation.reset_trial((0.8, -0.2))
        for step in range(200):
            if step % 16 == 0:
                simulation.command(*((0.2, -0.3) if step > 32 else (0.0, 0.0)))
            simulation.step()
        return world.robot_state().position


def test_a_trial_does_not_depend_on_what_the_world_did_before_it():
    reference = _trial_after(64, (0.0, 0.0))
    assert reference[0] > 0.05
    for history in ((152, (0.0, 0.0)), (100, (0.3, 0.5))):
        assert _trial_after(*history) == pytest.approx(reference, abs=1e-9)
