"""The lens fall-off estimated from the images: found on uniform surfaces whatever their
brightness, left alone without one, bounded, and undone."""
import numpy as np
import pytest

from can_seeker.vision.vignetting import MIN_UNDONE, VignettingEstimate

WIDTH, HEIGHT = 320, 240


def fall_off(strength):
    """The gain 1 - strength * rho^2 per pixel (rho over the half diagonal)."""
    columns, rows = np.meshgrid(np.arange(WIDTH) + 0.5 - WIDTH / 2.0,
                                np.arange(HEIGHT) + 0.5 - HEIGHT / 2.0)
    return 1.0 - strength * (columns ** 2 + rows ** 2) / ((WIDTH ** 2 + HEIGHT ** 2) / 4.0)


def tiles(step, strength, sigma=3.0):
    """Big tiles of two brightnesses moving across the view, seen through the fall-off, with
    sensor noise."""
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH]
    second = ((columns + 7 * step) // 90 + (rows + 5 * step) // 70) % 2 == 1
    level = np.where(second, 120.0, 220.0) * fall_off(strength)
    level = level + np.random.default_rng(step).normal(0.0, sigma, level.shape)
    grey = np.clip(level + 0.5, 0, 255).astype(np.uint8)
    return np.dstack((grey, grey, grey))


@pytest.mark.parametrize('strength', [0.2, 0.4])
def test_the_fall_off_is_found_on_tiles_of_any_brightness_and_undone(strength):
    estimate = VignettingEstimate()
    for step in range(80):
        estimate.observe(tiles(step, strength))
    assert estimate.strength == pytest.approx(strength, abs=0.04)
    corrected = estimate.correct(tiles(80, strength, sigma=0.0)).astype(float)[:, :, 0]
    flat = tiles(80, 0.0, sigma=0.0).astype(float)[:, :, 0]
    assert np.abs(corrected - flat)[10:-10, 10:-10].mean() < 4.0
    assert np.abs(tiles(80, strength, sigma=0.0)[:, :, 0] - flat).mean() > 8.0


def test_a_camera_without_fall_off_keeps_its_images():
    estimate = VignettingEstimate()
    for step in range(80):
        estimate.observe(tiles(step, 0.0))
    assert estimate.strength < MIN_UNDONE
    image = tiles(80, 0.0)
    assert estimate.correct(image) is image


def test_the_estimate_is_bounded_and_can_be_off():
    bounded = VignettingEstimate(max_strength=0.25)
    off = VignettingEstimate(max_strength=0.0)
    for step in range(60):
        bounded.observe(tiles(step, 0.5))
        off.observe(tiles(step, 0.5))
    assert bounded.strength == pytest.approx(0.25)
    assert off.strength == 0.0
    image = tiles(60, 0.5)
    assert off.correct(image) is image


def test_reset_forgets_the_estimate():
    estimate = VignettingEstimate()
    for step in range(40):
        estimate.observe(tiles(step, 0.4))
    estimate.reset()
    assert estimate.strength == 0.0
