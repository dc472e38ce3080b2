"""The hsv colour model of the red mask: two hue ranges either side of the wrap at 0/180,
minimum saturation and value, chosen by ``colour_model``."""
import cv2
import numpy as np
import pytest

from can_seeker.vision.detector import (DETECTOR_PARAMS, DetectorSettings, MaskScratch,
                                        RedCanDetector, red_mask)

HSV = DetectorSettings(**dict(DetectorSettings.defaults().__dict__, colour_model='hsv',
                              hue_max=10, hue_min_wrap=170, saturation_min=120, value_min=70))


def hsv_patch(hue, saturation, value, shape=(4, 5)):
    """BGR image of one OpenCV HSV colour."""
    hsv = np.full(shape + (3,), (hue, saturation, value), np.uint8)
    return cv2.cvtColor(hsv, cv2.COLOR_HSV2BGR)


def masked(bgr, settings=HSV):
    mask = red_mask(bgr, settings)
    assert set(np.unique(mask)) <= {0, 255}
    return bool(mask.all()), bool(mask.any())


@pytest.mark.parametrize('hue', [0, 2, 10, 170, 178, 179])
def test_red_either_side_of_the_wrap_is_masked(hue):
    assert masked(hsv_patch(hue, 220, 200)) == (True, True), hue


@pytest.mark.parametrize('hue, what', [(15, 'orange'), (11, 'just past hue_max'),
                                       (169, 'just below hue_min_wrap'), (90, 'cyan'),
                                       (150, 'magenta')])
def test_other_hues_are_not(hue, what):
    assert masked(hsv_patch(hue, 220, 200)) == (False, False), what


def test_pink_and_dark_red_fail_on_saturation_and_value():
    assert masked(hsv_patch(178, 80, 230)) == (False, False), 'pink: low saturation'
    assert masked(hsv_patch(2, 220, 60)) == (False, False), 'dark: value below value_min'
    assert masked(hsv_patch(2, 120, 70)) == (True, True), 'at both floors'


def test_grey_has_hue_0_but_no_saturation():
    assert masked(np.full((3, 3, 3), 128, np.uint8)) == (False, False)


def test_the_wrap_follows_its_parameters():
    narrow = DetectorSettings(**dict(HSV.__dict__, hue_max=1, hue_min_wrap=179))
    assert masked(hsv_patch(2, 220, 200), narrow) == (False, False)
    assert masked(hsv_patch(178, 220, 200), narrow) == (False, False)
    assert masked(hsv_patch(179, 220, 200), narrow) == (True, True)
    no_wrap = DetectorSettings(**dict(HSV.__dict__, hue_min_wrap=180))
    assert masked(hsv_patch(178, 220, 200), no_wrap) == (False, False)
    assert masked(hsv_patch(2, 220, 200), no_wrap) == (True, True)


def test_the_model_is_chosen_by_colour_model():
    """A pixel red by hue but with green at 0.4 of red: the hsv model takes it, the
    chromaticity defaults (green <= 0.35 red) do not."""
    bgr = np.full((3, 3, 3), (40, 80, 200), np.uint8)
    hue = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)[0, 0, 0]
    assert hue <= 10
    assert masked(bgr, DetectorSettings.defaults()) == (False, False)
    assert masked(bgr, HSV) == (True, True)


def test_hsv_mask_reuses_the_scratch_buffers():
    scratch = MaskScratch(4, 5)
    mask = red_mask(hsv_patch(2, 220, 200), HSV, scratch)
    assert mask is scratch.mask
    hsv_buffer = scratch.hsv
    red_mask(hsv_patch(90, 220, 200), HSV, scratch)
    assert scratch.hsv is hsv_buffer and not scratch.mask.any()


def test_the_detector_finds_a_disk_with_the_hsv_model():
    image = np.full((120, 160, 3), 128, np.uint8)
    cv2.circle(image, (60, 70), 15, tuple(int(c) for c in hsv_patch(176, 230, 190)[0, 0]), -1)
    blob = RedCanDetector(HSV).detect(image).blob
    assert blob is not None
    assert (blob.centroid_x, blob.centroid_y) == (pytest.approx(60, abs=0.5),
                                                  pytest.approx(70, abs=0.5))


def test_hsv_params_are_declared_with_their_bounds():
    specs = {spec.name: spec for spec in DETECTOR_PARAMS}
    assert specs['colour_model'].choices == ('chromaticity', 'hsv')
    for name in ('hue_max', 'hue_min_wrap'):
        assert (specs[name].minimum, specs[name].maximum) == (0, 180)
    assert (specs['saturation_min'].minimum, specs['saturation_min'].maximum) == (0, 255)
