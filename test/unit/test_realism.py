"""The realism models: noise statistics, exact latency in sim time, drops, odometry drift that
a seed reproduces and that is zero at ideal, actuation, lidar noise, presets and overrides."""
import math
from dataclasses import replace

import numpy as np
import pytest

from can_seeker.camera_geometry import intrinsics_from_vertical_fov
from can_seeker.params import defaults
from can_seeker.sim.realism import (PRESETS, REALISM_PARAMS, Actuation, CameraModel,
                                    FrameDelivery, Realism, RealismSpec, WheelOdometry,
                                    distortion_maps, kelvin_rgb, noisy_ranges, realism_spec,
                                    spec_from_config, trial_key)
from can_seeker.sim.simulation import PARAMS, Simulation, camera_spec, checked_config
from can_seeker.ros.paths import urdf_path
from can_seeker.sim.world import World

INTRINSICS = intrinsics_from_vertical_fov(320, 240, 45.0)
SEPARATION_M = 0.235


def rng(seed=0):
    return np.random.default_rng(seed)


def grey(level=100.0):
    return np.full((240, 320, 3), level, np.uint8)


def camera(**knobs):
    model = CameraModel(RealismSpec(**knobs), INTRINSICS)
    model.new_trial(rng(1))
    return model


def test_ideal_is_the_identity_everywhere():
    realism = Realism(PRESETS['ideal'], INTRINSICS, 'bgr8', SEPARATION_M)
    realism.new_trial((1, 2, 3), (0.0, 0.0, 0.0))
    frame = (np.arange(240 * 320 * 3) % 251).astype(np.uint8).reshape(240, 320, 3)
    assert realism.camera.apply(frame, 0.4, 1.2) is frame
    assert realism.camera.light_direction is None
    ranges = np.array([0.5, np.inf, 3.0], np.float32)
    np.testing.assert_array_equal(realism.scan(ranges), ranges)
    realism.actuation.command(0.2, 0.3, 1.0)
    assert realism.actuation.arrived(1.0) == [(1.0, 0.2, 0.3)]
    assert realism.actuation.wheels(0.001, 0.001) == (0.001, 0.001)
    assert realism.distortion == [0.0] * 5


def test_read_and_shot_noise_have_the_modelled_sigma():
    model = camera(camera_read_noise=4.0, camera_shot_noise=0.5)
    out = model.apply(grey(100.0)).astype(float)
    expected_sigma = math.sqrt(4.0 ** 2 + 0.5 * 100.0)
    assert abs(out.mean() - 100.0) < 0.2
    assert abs(out.std() - expected_sigma) < 0.03 * expected_sigma


def test_noise_is_reproducible_from_the_trial_seed_and_differs_between_seeds():
    spec = replace(PRESETS['realistic'], camera_jpeg_quality=0)
    images = []
    for key in ((5, 1, 1), (5, 1, 1), (6, 1, 1)):
        realism = Realism(spec, INTRINSICS, 'bgr8', SEPARATION_M)
        realism.new_trial(key, (0.0, 0.0, 0.0))
        images.append(realism.camera.apply(grey(120.0)))
    np.testing.assert_array_equal(images[0], images[1])
    assert np.any(images[0] != images[2])


def test_light_colour_temperature_is_what_white_balance_leaves_over():
    warm = kelvin_rgb(2700.0)
    assert warm[0] > 1.2 and warm[2] < 0.6
    np.testing.assert_allclose(kelvin_rgb(6500.0), [1.0, 1.0, 1.0], atol=0.05)
    uncorrected = camera(light_kelvin_min=2700.0, light_kelvin_max=2700.0, camera_awb=0.0)
    corrected = camera(light_kelvin_min=2700.0, light_kelvin_max=2700.0, camera_awb=1.0)
    blue, _, red = uncorrected.apply(grey(100.0)).reshape(-1, 3).mean(axis=0)
    assert red > 1.2 * 100.0 and blue < 0.6 * 100.0
    np.testing.assert_allclose(corrected.apply(grey(100.0)).reshape(-1, 3).mean(axis=0),
                               100.0, atol=0.6)


def test_each_frame_records_the_white_balance_drift_it_was_taken_with():
    """The drift moves on after every frame; the shift recorded for a frame is the one its
    colours show (log R/G and log B/G of a grey frame), the truth a white-balance lock is judged
    on."""
    model = camera(camera_wb_walk=0.05)
    assert np.all(model.frame_wb_shift_log == 0.0)
    shifts = []
    for _ in range(20):
        blue, green, red = model.apply(grey(128.0)).reshape(-1, 3).astype(float).mean(axis=0)
        np.testing.assert_allclose(model.frame_wb_shift_log,
                                   (math.log(red / green), math.log(blue / green)), atol=0.01)
        shifts.append(model.frame_wb_shift_log)
    assert np.abs(np.array(shifts)).max() > 0.05
    assert np.any(model.wb_shift_log() != shifts[-1])


def test_auto_exposure_starts_settled_and_follows_a_change_of_light():
    model = camera(light_intensity_min=0.5, light_intensity_max=0.5)
    assert abs(model.apply(grey(100.0)).mean() - 100.0) < 1.0
    model.intensity = 0.25
    means = [model.apply(grey(100.0)).mean() for _ in range(20)]
    assert abs(means[0] - 50.0) < 1.0
    assert abs(means[-1] - 100.0) < 2.0
    assert all(later >= earlier - 0.5 for earlier, later in zip(means, means[1:]))


def test_vignetting_darkens_the_corners_only():
    out = camera(camera_vignetting=0.4).apply(grey(200.0)).astype(float)
    assert abs(out[120, 160].mean() - 200.0) < 1.0
    assert abs(out[0, 0].mean() - 120.0) < 2.0


def test_motion_blur_smears_along_the_turn():
    frame = np.zeros((240, 320, 3), np.uint8)
    frame[:, 160] = 255
    model = camera(camera_exposure_s=0.02)
    still = model.apply(frame, 0.0, 0.0)
    turning = model.apply(frame, 0.0, 1.0)
    assert np.count_nonzero(still[120, :, 0]) == 1
    expected_px = 0.02 * 1.0 * INTRINSICS.fx
    assert abs(np.count_nonzero(turning[120, :, 0]) - expected_px) <= 1.5
    assert np.count_nonzero(turning[:, 150:170, 0].any(axis=1)) == 240


def test_jpeg_round_trip_changes_the_image_a_little():
    frame = (np.random.default_rng(3).random((240, 320, 3)) * 255).astype(np.uint8)
    out = camera(camera_jpeg_quality=50).apply(frame)
    difference = np.abs(out.astype(float) - frame)
    assert 2.0 < difference.mean() < 60.0


def test_distortion_maps_keep_the_centre_and_pull_in_the_corners():
    map_x, map_y = distortion_maps(INTRINSICS, -0.2, 0.0)
    centre = (int(INTRINSICS.cy + 0.5), int(INTRINSICS.cx + 0.5))
    assert abs(map_x[centre] - centre[1]) < 0.6 and abs(map_y[centre] - centre[0]) < 0.6
    assert map_x[0, 0] < 0.0 and map_y[0, 0] < 0.0


def test_frame_latency_is_exact_and_keeps_the_capture_stamp():
    delivery = FrameDelivery(0.05, 0.0)
    frame = grey()
    delivery.capture(1.0, frame)
    assert delivery.due(1.0499) == []
    due = delivery.due(1.05)
    assert len(due) == 1 and due[0][0] == 1.0 and due[0][1] is frame
    assert delivery.due(2.0) == []


def test_frame_drops_happen_at_the_rate_and_a_seed_repeats_them():
    def kept(seed):
        delivery = FrameDelivery(0.0, 0.2)
        delivery.new_trial(rng(seed))
        pattern = []
        for index in range(5000):
            delivery.capture(float(index), None)
            pattern.append(bool(delivery.due(float(index))))
        return pattern
    pattern = kept(7)
    assert abs(1.0 - sum(pattern) / len(pattern) - 0.2) < 0.02
    assert pattern == kept(7) and pattern != kept(8)


def drive(odometry, steps=2400, dt_s=1.0 / 240.0, linear_mps=0.3, angular_radps=0.4):
    """Drive a true arc; the true final pose."""
    x, y, yaw = 0.0, 0.0, 0.0
    for _ in range(steps):
        yaw += angular_radps * dt_s
        x += linear_mps * dt_s * math.cos(yaw - angular_radps * dt_s / 2.0)
        y += linear_mps * dt_s * math.sin(yaw - angular_radps * dt_s / 2.0)
        odometry.update((x, y, yaw), dt_s)
    return x, y, yaw


def test_odometry_is_the_truth_at_ideal():
    odometry = WheelOdometry(PRESETS['ideal'], SEPARATION_M)
    truth = drive(odometry)
    assert odometry.pose == truth


def test_odometry_without_errors_integrates_the_true_path():
    odometry = WheelOdometry(RealismSpec(odom_slip=1e-12), SEPARATION_M)
    truth = drive(odometry)
    assert math.hypot(odometry.pose[0] - truth[0], odometry.pose[1] - truth[1]) < 1e-6


def test_odometry_drift_is_reproducible_from_a_seed_and_grows_with_the_preset():
    def final_error(preset, seed):
        odometry = WheelOdometry(PRESETS[preset], SEPARATION_M)
        odometry.new_trial(rng(seed), (0.0, 0.0, 0.0))
        truth = drive(odometry)
        return (math.hypot(odometry.pose[0] - truth[0], odometry.pose[1] - truth[1]),
                odometry.pose)
    realistic, pose = final_error('realistic', 11)
    assert final_error('realistic', 11)[1] == pose
    assert final_error('realistic', 12)[1] != pose
    assert 0.0005 < realistic < 0.2
    harsh = np.mean([final_error('harsh', seed)[0] for seed in range(10)])
    assert harsh > np.mean([final_error('realistic', seed)[0] for seed in range(10)])


def test_odometry_does_not_drift_at_rest():
    odometry = WheelOdometry(PRESETS['harsh'], SEPARATION_M)
    odometry.new_trial(rng(2), (1.0, 2.0, 0.5))
    for _ in range(1000):
        odometry.update((1.0, 2.0, 0.5), 1.0 / 240.0)
    assert odometry.pose == (1.0, 2.0, 0.5)
    assert odometry.twist == (0.0, 0.0)


def test_commands_act_after_the_latency_and_slow_wheels_stop_in_the_deadband():
    actuation = Actuation(RealismSpec(cmd_latency_s=0.1, motor_deadband_mps=0.01), SEPARATION_M)
    actuation.command(0.2, 0.0, 1.0)
    assert actuation.arrived(1.0999) == []
    assert actuation.arrived(1.1) == [(1.1, 0.2, 0.0)]
    assert actuation.wheels(0.005, 0.0) == (0.0, 0.0)
    assert actuation.wheels(0.2, 0.0) == (0.2, 0.0)
    linear, angular = actuation.wheels(0.0, 0.05)
    assert (linear, angular) == (0.0, 0.0)


def test_lidar_noise_and_dropouts_have_their_rates():
    ranges = np.full(20000, 2.0, np.float32)
    ranges[:1000] = np.inf
    noisy = noisy_ranges(ranges, 0.02, 0.05, rng(4))
    dropped = np.isnan(noisy)
    assert abs(dropped.mean() - 0.05) < 0.01
    kept = noisy[~dropped & np.isfinite(noisy)]
    assert abs(kept.std() - 0.02) < 0.002 and abs(kept.mean() - 2.0) < 0.001
    assert np.all(np.isposinf(noisy[:1000][~dropped[:1000]]))


def test_knobs_override_the_preset_and_minus_one_keeps_it():
    spec = realism_spec('realistic', {'camera_read_noise': 7.0, 'odom_noise': -1.0,
                                      'camera_jpeg_quality': 0})
    assert spec.camera_read_noise == 7.0
    assert spec.odom_noise == PRESETS['realistic'].odom_noise
    assert spec.camera_jpeg_quality == 0
    assert spec_from_config(defaults(REALISM_PARAMS)) == PRESETS['ideal']
    harsh = defaults(REALISM_PARAMS, {'realism/preset': 'harsh', 'realism/scan_noise_m': 0.5})
    assert spec_from_config(harsh) == realism_spec('harsh', {'scan_noise_m': 0.5})


def test_barrel_distortion_is_a_negative_k1_that_overrides_the_preset():
    """k1 < 0 is barrel distortion (a wide-angle webcam): a real value, not "keep the
    preset", which only -1 itself means for the lens knobs."""
    spec = realism_spec('realistic', {'camera_k1': -0.25, 'camera_k2': 0.06,
                                      'camera_read_noise': -0.5})
    assert (spec.camera_k1, spec.camera_k2) == (-0.25, 0.06)
    assert spec.camera_read_noise == PRESETS['realistic'].camera_read_noise
    kept = realism_spec('realistic', {'camera_k1': -1.0, 'camera_k2': -1.0})
    assert (kept.camera_k1, kept.camera_k2) == (PRESETS['realistic'].camera_k1,
                                               PRESETS['realistic'].camera_k2)


def test_presets_grow_harsher():
    for name in ('camera_read_noise', 'camera_latency_s', 'camera_drop_rate', 'odom_wheel_scale',
                 'cmd_latency_s', 'scan_noise_m'):
        values = [getattr(PRESETS[preset], name) for preset in ('ideal', 'realistic', 'harsh')]
        assert values[0] < values[1] < values[2], name


def test_trial_key_names_the_world_seed_and_can_place():
    assert trial_key(3, (1.2345, -0.5)) == trial_key(3, (1.2345, -0.5))
    assert trial_key(3, (1.2345, -0.5)) != trial_key(4, (1.2345, -0.5))
    assert min(trial_key(0, (-50.0, -50.0))) >= 0


def config_with(**overrides):
    return checked_config(defaults(PARAMS, overrides), print)


def test_simulation_publishes_late_frames_with_their_capture_stamp_and_drifting_odometry():
    config = config_with(width=64, height=48, renderer='tiny', **{
        'realism/preset': 'realistic', 'realism/camera_latency_s': 0.05,
        'realism/camera_drop_rate': 0.0})
    with World(urdf_path(), camera_spec(config), renderer='tiny',
               scene=config.scene) as world:
        simulation = Simulation.from_config(world, config)
        simulation.reset_trial((1.5, 0.0))
        frames = []
        for _ in range(240 * 3):
            simulation.command(0.3, 0.5)
            result = simulation.step()
            if result.image is not None:
                frames.append((result.time_s, result.image_time_s))
        assert frames
        for published_s, captured_s in frames:
            assert published_s - captured_s == pytest.approx(0.05, abs=1e-9)
            assert round(captured_s * 15.0, 6) == round(captured_s * 15.0)
        state = world.robot_state()
        odometry = simulation.odometry()
        drift_m = math.hypot(odometry.x_m - state.position[0], odometry.y_m - state.position[1])
        assert 0.0 < drift_m < 0.1


def test_white_balance_drift_wanders_but_stays_bounded():
    model = camera(camera_wb_walk=0.02)
    spreads = []
    for _ in range(3000):
        model.apply(grey(100.0))
        spreads.append(np.abs(model.log_wb_drift).max())
    assert max(spreads[:5]) < 0.1
    assert 0.02 < np.mean(spreads[1000:]) < 0.2
    assert max(spreads) < 0.4


def test_jitter_of_the_true_motion_is_not_taken_for_slip():
    """The slip grows with the motors' acceleration, not with the step-to-step jitter of the
    physics (which would over-count every wheel turn)."""
    jitter = rng(9)
    spec = RealismSpec(odom_slip=PRESETS['harsh'].odom_slip)
    odometry = WheelOdometry(spec, SEPARATION_M)
    x = 0.0
    for _ in range(2400):
        x += 0.3 / 240.0 + 1e-5 * float(jitter.standard_normal())
        odometry.update((x, 0.0, 0.0), 1.0 / 240.0, (0.0, 0.0))
    assert abs(odometry.pose[0] - x) < 1e-9
    odometry.update((x + 0.01, 0.0, 0.0), 1.0 / 240.0, (1.0, 1.0))
    assert odometry.pose[0] - (x + 0.01) == pytest.approx(0.01 * spec.odom_slip)
