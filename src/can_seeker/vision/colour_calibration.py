"""Red-mask thresholds from the colour of a can in the user's own images: pixels -> parameters.

The can's pixels are those inside a box around it whose brightest channel is red and that are
at least a little saturated (:func:`can_pixels`): the floor, walls and the can's silver lid and
rim inside the box fail that. Each threshold keeps the ``low``-th to ``high``-th percentile of
the can's pixels (2nd-98th by default: a few highlights and edge pixels may be lost, the
closing kernel fills them) widened by a margin, and is clipped to the parameter's declared
bounds (DETECTOR_PARAMS).
"""
import math
from typing import Dict, Sequence, Tuple

import cv2
import numpy as np

from can_seeker.vision.detector import DETECTOR_PARAMS

CANDIDATE_SATURATION_MIN = 0.5
"""A pixel in the box is taken for the can when red is its brightest channel and (max - min) /
max is at least this (its other channels at most half its red): red, dark red and crimson cans
under warm, cool and dim light are (0.85 and more), grey floors and white walls under a warm
light (about 0.3), the lid, skin and beige are not. A red the defaults mask (green <= 0.35 red)
always is."""
RATIO_MARGIN = 0.05
"""Added to each chromaticity ratio's high percentile (ratios of red, 1)."""
HUE_MARGIN = 2
"""Added either side of the hue percentiles (OpenCV hue units of 2 deg)."""
SATURATION_MARGIN = 20
"""Taken off the saturation's low percentile (0-255)."""
VALUE_FACTOR = 0.7
"""value_min is this times the brightness's low percentile: a can in shade stays red."""
MIN_PIXELS = 50

THRESHOLD_NAMES = {
    'chromaticity': ('green_max_ratio', 'blue_max_ratio', 'orange_max_ratio', 'value_min'),
    'hsv': ('hue_max', 'hue_min_wrap', 'saturation_min', 'value_min'),
}


class CalibrationError(ValueError):
    """The pixels given cannot be calibrated on (too few can pixels, bad box)."""


def parse_box(text: str) -> Tuple[int, int, int, int]:
    """(x, y, width, height) from "x,y,w,h" (px); raises CalibrationError."""
    try:
        x, y, width, height = (int(part) for part in text.split(','))
    except ValueError:
        raise CalibrationError('box %r: expected x,y,width,height in whole pixels' % text)
    if width <= 0 or height <= 0 or x < 0 or y < 0:
        raise CalibrationError('box %r: expected x, y >= 0 and a positive width and height'
                               % text)
    return x, y, width, height


def clip_box(box, width: int, height: int) -> Tuple[int, int, int, int]:
    """The part of ``box`` inside a ``width`` x ``height`` image; raises CalibrationError when
    none is."""
    x, y, box_width, box_height = box
    x0, y0 = max(0, x), max(0, y)
    x1, y1 = min(width, x + box_width), min(height, y + box_height)
    if x1 <= x0 or y1 <= y0:
        raise CalibrationError('box %s lies outside the %dx%d image' % (box, width, height))
    return x0, y0, x1 - x0, y1 - y0


def widened_box(box, margin_fraction: float, width: int, height: int):
    """``box`` grown by ``margin_fraction`` of its size on every side, clipped to the image."""
    x, y, box_width, box_height = box
    dx = int(math.ceil(margin_fraction * box_width))
    dy = int(math.ceil(margin_fraction * box_height))
    return clip_box((x - dx, y - dy, box_width + 2 * dx, box_height + 2 * dy), width, height)


def can_pixels(bgr: np.ndarray, box) -> np.ndarray:
    """(N, 3) uint8 BGR pixels of the can inside ``box`` (see CANDIDATE_SATURATION_MIN)."""
    x, y, width, height = clip_box(box, bgr.shape[1], bgr.shape[0])
    patch = bgr[y:y + height, x:x + width].reshape(-1, 3).astype(np.int32)
    blue, green, red = patch[:, 0], patch[:, 1], patch[:, 2]
    darkest = np.minimum(blue, green)
    keep = (red > green) & (red > blue) & (red - darkest >= CANDIDATE_SATURATION_MIN * red)
    return patch[keep].astype(np.uint8)


def _bounded(name: str, value):
    spec = next(spec for spec in DETECTOR_PARAMS if spec.name == name)
    if spec.minimum is not None:
        value = max(spec.minimum, value)
    if spec.maximum is not None:
        value = min(spec.maximum, value)
    return type(spec.default)(value)


def chromaticity_thresholds(pixels: np.ndarray, low: float, high: float) -> Dict[str, object]:
    blue, green, red = (pixels[:, channel].astype(np.float64) for channel in range(3))
    red_safe = np.maximum(red, 1.0)
    return {
        'green_max_ratio': _bounded('green_max_ratio', round(float(
            np.percentile(green / red_safe, high)) + RATIO_MARGIN, 3)),
        'blue_max_ratio': _bounded('blue_max_ratio', round(float(
            np.percentile(blue / red_safe, high)) + RATIO_MARGIN, 3)),
        'orange_max_ratio': _bounded('orange_max_ratio', round(float(
            np.percentile(np.maximum(green - blue, 0.0) / red_safe, high)) + RATIO_MARGIN, 3)),
        'value_min': _bounded('value_min', int(VALUE_FACTOR * np.percentile(red, low))),
    }


def hsv_thresholds(pixels: np.ndarray, low: float, high: float) -> Dict[str, object]:
    """Hue is measured about 0 (hues above 90 count as hue - 180), so the two ranges either
    side of the wrap come from one spread; a spread that stays on one side of 0 gives
    hue_max 0 or hue_min_wrap 180 (that range empty but for hue 0)."""
    hsv = cv2.cvtColor(pixels.reshape(-1, 1, 3), cv2.COLOR_BGR2HSV).reshape(-1, 3)
    hue = hsv[:, 0].astype(np.float64)
    signed_hue = np.where(hue >= 90, hue - 180, hue)
    hue_low = float(np.percentile(signed_hue, low)) - HUE_MARGIN
    hue_high = float(np.percentile(signed_hue, high)) + HUE_MARGIN
    return {
        'hue_max': _bounded('hue_max', int(math.ceil(max(0.0, hue_high)))),
        'hue_min_wrap': _bounded('hue_min_wrap', int(math.floor(180 + min(0.0, hue_low)))),
        'saturation_min': _bounded('saturation_min', int(
            np.percentile(hsv[:, 1], low) - SATURATION_MARGIN)),
        'value_min': _bounded('value_min', int(VALUE_FACTOR * np.percentile(hsv[:, 2], low))),
    }


def thresholds(pixels: np.ndarray, colour_model: str, low: float = 2.0,
               high: float = 98.0) -> Dict[str, object]:
    """{param name: value} of ``colour_model``'s thresholds (and colour_model itself) that
    keep the ``low``-``high`` percentile of ``pixels`` ((N, 3) BGR uint8) with a margin.
    Raises CalibrationError with fewer than MIN_PIXELS pixels."""
    if colour_model not in THRESHOLD_NAMES:
        raise CalibrationError('colour model %r: expected one of %s' % (
            colour_model, ', '.join(THRESHOLD_NAMES)))
    if not 0.0 <= low < high <= 100.0:
        raise CalibrationError('percentiles %r-%r: expected 0 <= low < high <= 100' % (low, high))
    if len(pixels) < MIN_PIXELS:
        raise CalibrationError('%d can pixels in the box: at least %d red pixels needed (is '
                               'the can in the box?)' % (len(pixels), MIN_PIXELS))
    rule = chromaticity_thresholds if colour_model == 'chromaticity' else hsv_thresholds
    return dict(colour_model=colour_model, **rule(pixels, low, high))


def params_yaml(values: Dict[str, object], comments: Sequence[str] = ()) -> str:
    """Flat YAML of private parameters ("name: value" lines) for ``rosparam load FILE
    /image_converter`` or ``dynparam load /image_converter FILE``, with # comment lines."""
    lines = ['# %s' % comment for comment in comments]
    for name, value in values.items():
        lines.append('%s: %s' % (name, repr(value) if isinstance(value, float) else value))
    return '\n'.join(lines) + '\n'
