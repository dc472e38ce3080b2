"""Thresholds from the can's own pixels: they mask the sampled red and not the orange beside it,
whatever the light, and stay within the parameters' declared bounds."""
import cv2
import numpy as np
import pytest
import yaml

from can_seeker.evaluation.labelled_images import LIGHTS, apply_light
from can_seeker.vision.colour_calibration import (CalibrationError, can_pixels, params_yaml,
                                                  parse_box, thresholds, widened_box)
from can_seeker.vision.detector import DETECTOR_PARAMS, DetectorSettings, red_mask

RED_BOX = (40, 60, 50, 90)
ORANGE_BOX = (160, 60, 50, 90)
GAINS = dict(LIGHTS)


def scene(light='neutral', red_bgr=(20, 25, 200), seed=0):
    """Grey floor, a red patch (shaded left to right, with noise) and an orange one beside it,
    seen under ``light`` (labelled_images.LIGHTS)."""
    rng = np.random.default_rng(seed)
    image = np.full((240, 320, 3), (130, 135, 140), np.float64)
    for box, bgr in ((RED_BOX, red_bgr), (ORANGE_BOX, (20, 120, 235))):
        x, y, width, height = box
        shade = np.linspace(0.6, 1.0, width)[None, :, None]
        image[y:y + height, x:x + width] = np.array(bgr, np.float64) * shade
    image += rng.normal(0.0, 4.0, image.shape)
    bgr = np.clip(image, 0, 255).astype(np.uint8)
    return apply_light(bgr, GAINS[light])


def fraction_masked(image, values, box):
    settings = DetectorSettings(**dict(DetectorSettings.defaults().__dict__, **values))
    x, y, width, height = box
    return red_mask(image, settings)[y:y + height, x:x + width].mean() / 255.0


@pytest.mark.parametrize('model', ['chromaticity', 'hsv'])
@pytest.mark.parametrize('light', ['neutral', 'warm', 'dim'])
def test_thresholds_mask_the_sampled_red_and_not_the_orange_beside_it(model, light):
    image = scene(light)
    values = thresholds(can_pixels(image, widened_box(RED_BOX, 0.2, 320, 240)), model)
    assert values['colour_model'] == model
    assert fraction_masked(image, values, RED_BOX) >= 0.95
    assert fraction_masked(image, values, ORANGE_BOX) <= 0.01
    floor = (0, 0, 320, 50)
    assert fraction_masked(image, values, floor) == 0.0


def test_a_crimson_can_gets_a_hue_range_across_the_wrap():
    crimson = (60, 15, 190)   # blue above green: hue just below 180
    image = scene(red_bgr=crimson)
    values = thresholds(can_pixels(image, RED_BOX), 'hsv')
    assert values['hue_min_wrap'] < 180
    assert fraction_masked(image, values, RED_BOX) >= 0.95
    assert fraction_masked(image, values, ORANGE_BOX) <= 0.01


@pytest.mark.parametrize('light', ['neutral', 'warm', 'cool', 'dim', 'bright'])
def test_the_box_background_is_not_taken_for_the_can(light):
    """Not even the grey floor under a warm light, whose red is its brightest channel."""
    image = scene(light)
    inside = can_pixels(image, RED_BOX)
    widened = can_pixels(image, widened_box(RED_BOX, 0.5, 320, 240))
    assert len(widened) == len(inside) == RED_BOX[2] * RED_BOX[3]


def test_percentiles_follow_the_can_and_values_stay_in_bounds():
    dark = scene(red_bgr=(4, 6, 60))
    values = thresholds(can_pixels(dark, RED_BOX), 'chromaticity')
    assert values['value_min'] < 40
    greenish = np.tile(np.array([[0, 250, 255]], np.uint8), (100, 1))  # green 0.98 of red
    clipped = thresholds(greenish, 'chromaticity')
    specs = {spec.name: spec for spec in DETECTOR_PARAMS}
    for name in ('green_max_ratio', 'blue_max_ratio', 'orange_max_ratio', 'value_min'):
        assert specs[name].minimum <= clipped[name] <= specs[name].maximum, name
    assert clipped['green_max_ratio'] == 1.0
    assert isinstance(clipped['value_min'], int)


def test_too_few_can_pixels_is_an_error():
    with pytest.raises(CalibrationError, match='can pixels'):
        thresholds(can_pixels(scene(), (0, 0, 30, 30)), 'hsv')


def test_boxes_are_parsed_and_checked():
    assert parse_box('1,2,30,40') == (1, 2, 30, 40)
    for text in ('1,2,3', 'a,b,c,d', '0,0,0,5', '-1,0,5,5'):
        with pytest.raises(CalibrationError):
            parse_box(text)
    with pytest.raises(CalibrationError, match='outside'):
        can_pixels(scene(), (400, 0, 10, 10))


def test_yaml_is_the_flat_private_parameter_form():
    values = thresholds(can_pixels(scene(), RED_BOX), 'hsv')
    text = params_yaml(values, ['from test'])
    assert text.startswith('# from test\n')
    loaded = yaml.safe_load(text)
    assert loaded == values
    assert {type(value) for value in loaded.values()} <= {str, int, float}


def test_hsv_of_pixels_matches_opencv_of_the_image():
    """can_pixels keeps BGR order: the hsv rule sees the hue OpenCV gives the image."""
    image = scene()
    pixels = can_pixels(image, RED_BOX)
    x, y, width, height = RED_BOX
    hue = cv2.cvtColor(image[y:y + height, x:x + width], cv2.COLOR_BGR2HSV)[..., 0]
    values = thresholds(pixels, 'hsv')
    wrapped = np.where(hue >= 90, hue.astype(int) - 180, hue.astype(int))
    assert values['hue_max'] >= np.percentile(wrapped, 98)
