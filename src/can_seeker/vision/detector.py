"""Red object detection in one BGR image: red mask (chromaticity or HSV), clean-up, candidate
blobs with moments and shape scores, edges, annotation.

Colour (``colour_model`` chromaticity, the default): a pixel is red when red clearly dominates
both other channels, measured as ratios to the red channel (so the decision does not change
with brightness):
``green <= green_max_ratio * red``, ``blue <= blue_max_ratio * red``, ``green - blue <=
orange_max_ratio * red`` and ``red >= value_min``. Orange, yellow and skin fail on green (or on
green above blue), pink, magenta and purple on blue; grey, white and black on all. The ratios
were chosen on the labelled set of evaluation/labelled_images.py (photographs from Debian
packages and rendered cans under warm, cool, dim and bright light), in the middle of the range
where every red object was still found and the fewest near-red ones were.

Colour (``colour_model`` hsv, the tutorial's mask): OpenCV's 8-bit HSV (hue 0-180), red where
``hue <= hue_max`` or ``hue >= hue_min_wrap`` (the two ranges either side of the wrap at
0/180), ``saturation >= saturation_min`` and ``value >= value_min`` (for a pixel of red hue V
is its red channel, so ``value_min`` means the same in both models).

Shape: every red blob above the minimum area is a candidate, scored 0-1 for how much it looks
like an upright can's silhouette (convex, filling its box, taller than wide, upright).
"""
import math
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import cv2
import numpy as np

from can_seeker.params import Param

EDGE_METHODS = ('canny', 'sobel', 'laplacian')
COLOUR_MODELS = ('chromaticity', 'hsv')
MAX_CANDIDATES = 8
"""Blobs scored per frame, largest first (more are ignored)."""
CUT_FACTOR = 0.75
"""Shape score factor per image axis along which a blob is cut by the image edge."""

DETECTOR_PARAMS = (
    Param('colour_model', 'chromaticity', 'which test makes a pixel red: chromaticity (ratios '
          'of green and blue to red) or hsv (two hue ranges either side of 0/180, minimum '
          'saturation and value)', choices=COLOUR_MODELS),
    Param('green_max_ratio', 0.35, 'a red pixel has green <= this x red, which rejects orange, '
          'yellow, skin and pink (1)', 0.0, 1.0),
    Param('blue_max_ratio', 0.45, 'a red pixel has blue <= this x red, which rejects pink, magenta '
          'and purple (1)', 0.0, 1.0),
    Param('orange_max_ratio', 0.2, 'a red pixel has green - blue <= this x red, which rejects '
          'red-orange and orange (1)', 0.0, 1.0),
    Param('value_min', 30, 'minimum red channel (brightness) of a red pixel, in both models '
          '(hsv: V, which is the red channel of a pixel of red hue) (0-255)', 0, 255),
    Param('hue_max', 4, 'hsv: a red pixel has hue <= this, or >= ~hue_min_wrap '
          '(OpenCV hue, 0-180)', 0, 180),
    Param('hue_min_wrap', 170, 'hsv: a red pixel has hue >= this, or <= ~hue_max '
          '(OpenCV hue, 0-180)', 0, 180),
    Param('saturation_min', 170, 'hsv: minimum saturation of a red pixel, which '
          'rejects pink, skin and grey (0-255)', 0, 255),
)
"""The colour test's thresholds: the room's light and the can's red set them
(calibrate_colour measures them); the node's parameters, tunable live with
dynamic_reconfigure."""

MIN_AREA_FRACTION = 0.0005
"""Smallest red blob reported, as a fraction of the image area: 38 px of 320 x 240, the can's
size about 4 m away through a 45 deg vertical field of view."""
OPEN_KERNEL_PX = 3
"""Side of the opening kernel that removes red speckles (px, 1 = off)."""
CLOSE_KERNEL_PX = 7
"""Side of the closing kernel that fills highlights and holes in the blob (px, 1 = off): a
label's lettering and the light's reflection on the metal."""
EDGE_METHOD = 'canny'
"""Edge detector of the ~edges debug image: canny, sobel or laplacian."""
CANNY_LOW = 50
"""Canny hysteresis low threshold of the ~edges image (grey levels)."""
CANNY_HIGH = 150
"""Canny hysteresis high threshold of the ~edges image (grey levels): three times the low one,
within the 2:1 to 3:1 Canny proposed."""


@dataclass(frozen=True)
class DetectorSettings:
    """Validated thresholds of :class:`RedCanDetector`: DETECTOR_PARAMS (see there for units)
    and the blob and edge constants above (their defaults here; benches and tests vary them)."""

    colour_model: str
    green_max_ratio: float
    blue_max_ratio: float
    orange_max_ratio: float
    value_min: int
    hue_max: int
    hue_min_wrap: int
    saturation_min: int
    min_area_fraction: float = MIN_AREA_FRACTION
    open_kernel_px: int = OPEN_KERNEL_PX
    close_kernel_px: int = CLOSE_KERNEL_PX
    edge_method: str = EDGE_METHOD
    canny_low: int = CANNY_LOW
    canny_high: int = CANNY_HIGH

    @classmethod
    def defaults(cls):
        """Settings at the DETECTOR_PARAMS defaults."""
        return cls(**{spec.name: spec.default for spec in DETECTOR_PARAMS})

    @classmethod
    def from_values(cls, values):
        """Settings from any object with one attribute per DETECTOR_PARAMS name; the others
        keep their constants."""
        return cls(**{spec.name: getattr(values, spec.name) for spec in DETECTOR_PARAMS})


class MaskScratch:
    """Buffers of :func:`red_mask` for one image size, reused from frame to frame: the three
    channels and the mask, four image planes (fewer planes keep a frame's passes in the CPU
    cache); the HSV image only once the hsv model runs."""

    def __init__(self, height: int, width: int):
        self.shape = (height, width)
        self.channels = [np.empty((height, width), np.uint8) for _ in range(3)]
        self.mask = np.empty((height, width), np.uint8)
        self._hsv = None

    @property
    def hsv(self) -> np.ndarray:
        if self._hsv is None:
            self._hsv = np.empty(self.shape + (3,), np.uint8)
        return self._hsv


def red_mask(bgr: np.ndarray, settings, scratch: Optional[MaskScratch] = None) -> np.ndarray:
    """mono8 mask of a BGR uint8 image: 255 where a pixel is red by the colour model of
    ``settings`` (any object with DETECTOR_PARAMS' colour attributes, e.g.
    :class:`DetectorSettings`), else 0. No clean-up.

    With ``scratch`` (a :class:`MaskScratch` of the image's size) no memory is allocated and
    the mask returned is ``scratch.mask``, overwritten by the next call.
    """
    height, width = bgr.shape[:2]
    if scratch is None or scratch.shape != (height, width):
        scratch = MaskScratch(height, width)
    if settings.colour_model == 'hsv':
        return hsv_red_mask(bgr, settings, scratch)
    return chromaticity_red_mask(bgr, settings, scratch)


def chromaticity_red_mask(bgr: np.ndarray, settings, scratch: MaskScratch) -> np.ndarray:
    """The chromaticity model's mask (green_max_ratio, blue_max_ratio, orange_max_ratio,
    value_min) into ``scratch``."""
    blue, green, red = scratch.channels
    passed = scratch.mask
    cv2.split(bgr, scratch.channels)
    # Each test's margin is nonzero exactly where the pixel passes it: saturate(ratio * red -
    # channel + 1), saturate(red - value_min + 1); ``passed`` keeps the smallest. A channel
    # holds its own margin once no later test reads it. Green above blue is saturated at 0
    # first: where green <= blue the orange test passes either way.
    cv2.addWeighted(red, settings.green_max_ratio, green, -1.0, 1.0, dst=passed)
    cv2.subtract(green, blue, dst=green)
    cv2.addWeighted(red, settings.orange_max_ratio, green, -1.0, 1.0, dst=green)
    cv2.min(passed, green, dst=passed)
    cv2.addWeighted(red, settings.blue_max_ratio, blue, -1.0, 1.0, dst=blue)
    cv2.min(passed, blue, dst=passed)
    cv2.subtract(red, settings.value_min - 1.0, dst=red)
    cv2.min(passed, red, dst=passed)
    return cv2.threshold(passed, 0, 255, cv2.THRESH_BINARY, dst=passed)[1]


def hsv_red_mask(bgr: np.ndarray, settings, scratch: MaskScratch) -> np.ndarray:
    """The hsv model's mask (hue_max, hue_min_wrap, saturation_min, value_min) into
    ``scratch``: OpenCV 8-bit HSV, hue 0-179."""
    hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV, dst=scratch.hsv)
    low_floor = (settings.saturation_min, settings.value_min)
    cv2.inRange(hsv, (0,) + low_floor, (settings.hue_max, 255, 255), dst=scratch.mask)
    wrapped = scratch.channels[0]
    cv2.inRange(hsv, (settings.hue_min_wrap,) + low_floor, (180, 255, 255), dst=wrapped)
    return cv2.bitwise_or(scratch.mask, wrapped, dst=scratch.mask)


@dataclass(frozen=True)
class Blob:
    """A red blob: centroid from its image moments (px), area (px^2), bbox (px), its shape
    measures and their score (0-1, how much it looks like an upright can's silhouette).

    The bounding box is inclusive of ``x``/``y`` and ``width``/``height`` pixels wide/high.
    ``cut`` names the image sides the blob touches ('left', 'right', 'top', 'bottom'): its
    size along those is unknown. ``solidity`` is area / convex hull area, ``fill`` area / area
    of the smallest rotated rectangle around it (perspective leans a can near the image side),
    ``aspect`` height / width of the box, ``tilt_deg`` the angle of its long axis from
    the vertical.
    """

    centroid_x: float
    centroid_y: float
    area: float
    x: int
    y: int
    width: int
    height: int
    solidity: float = 1.0
    fill: float = 1.0
    aspect: float = 1.0
    tilt_deg: float = 0.0
    cut: Tuple[str, ...] = ()
    shape_score: float = 1.0
    contour: Optional[np.ndarray] = field(default=None, compare=False, repr=False)


@dataclass
class VisionResult:
    """One frame's output: red blobs above the minimum area (largest first) and the images.

    ``mask``/``edges`` are the detector's buffers: valid until the next call of
    :meth:`RedCanDetector.detect` (copy them to keep them).
    """

    candidates: List[Blob]
    mask: np.ndarray
    edges: Optional[np.ndarray]

    @property
    def found(self) -> bool:
        """Whether any red object was seen."""
        return bool(self.candidates)

    @property
    def blob(self) -> Optional[Blob]:
        """The largest red blob (None when there is none)."""
        return self.candidates[0] if self.candidates else None


def centroid_from_moments(moments):
    """(x, y) centroid of image moments, or None when the region is empty (m00 == 0)."""
    m00 = moments['m00']
    if m00 == 0:
        return None
    return moments['m10'] / m00, moments['m01'] / m00


def _kernel(side_px, shape=cv2.MORPH_ELLIPSE):
    return cv2.getStructuringElement(shape, (side_px, side_px)) if side_px > 1 else None


class RedCanDetector:
    """Finds red blobs in BGR images; reuses its buffers while the size is unchanged."""

    def __init__(self, settings: Optional[DetectorSettings] = None):
        self._shape = None
        self.settings = settings if settings is not None else DetectorSettings.defaults()

    @property
    def settings(self) -> DetectorSettings:
        return self._config[0]

    @settings.setter
    def settings(self, settings: DetectorSettings):
        """Replace all thresholds at once: a frame in progress in another thread keeps the
        settings and kernels it started with."""
        # A square closing kernel costs half an elliptic one (OpenCV separates it) and fills
        # the same highlights; the small opening kernel stays round.
        self._config = (settings, _kernel(settings.open_kernel_px),
                        _kernel(settings.close_kernel_px, cv2.MORPH_RECT))

    def _buffers(self, shape):
        if shape[:2] != self._shape:
            height, width = shape[:2]
            self._scratch = MaskScratch(height, width)
            self._clean_mask = np.empty((height, width), np.uint8)
            self._grey = np.empty((height, width), np.uint8)
            self._edges = np.empty((height, width), np.uint8)
            self._shape = shape[:2]

    def red_mask(self, bgr: np.ndarray, settings: DetectorSettings) -> np.ndarray:
        """:func:`red_mask` into this detector's buffers."""
        self._buffers(bgr.shape)
        return red_mask(bgr, settings, self._scratch)

    def clean_mask(self, mask: np.ndarray, open_kernel, close_kernel) -> np.ndarray:
        """Opening removes speckles, closing fills highlights and holes inside the blob
        (a kernel of None skips that step).

        Both run only on the box around the mask's red pixels, widened by twice the kernels'
        sides: outside it the cleaned mask is 0, inside it the same as cleaning the whole
        image (OpenCV pads the box as it pads an image, and the margin keeps that padding too
        far from any red to change a pixel). A frame with little or no red costs a fraction
        of the full-image passes.
        """
        kernels = [kernel for kernel in (open_kernel, close_kernel) if kernel is not None]
        if not kernels:
            return mask
        cleaned = self._clean_mask
        cleaned.fill(0)
        x, y, width, height = cv2.boundingRect(mask)
        if width == 0:
            return cleaned
        margin = 2 * sum(max(kernel.shape) for kernel in kernels)
        rows = slice(max(0, y - margin), min(mask.shape[0], y + height + margin))
        columns = slice(max(0, x - margin), min(mask.shape[1], x + width + margin))
        box, box_cleaned = mask[rows, columns], cleaned[rows, columns]
        if open_kernel is not None:
            cv2.morphologyEx(box, cv2.MORPH_OPEN, open_kernel, dst=box_cleaned)
            box = box_cleaned
        if close_kernel is not None:
            cv2.morphologyEx(box, cv2.MORPH_CLOSE, close_kernel, dst=box_cleaned)
        return cleaned

    def edges(self, bgr: np.ndarray, settings: DetectorSettings) -> np.ndarray:
        """mono8 edge image of the input's grey levels by the selected method."""
        self._buffers(bgr.shape)
        cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY, dst=self._grey)
        if settings.edge_method == 'canny':
            return cv2.Canny(self._grey, settings.canny_low, settings.canny_high, edges=self._edges)
        if settings.edge_method == 'sobel':
            gradient_x = cv2.Sobel(self._grey, cv2.CV_16S, 1, 0)
            gradient_y = cv2.Sobel(self._grey, cv2.CV_16S, 0, 1)
            return cv2.addWeighted(cv2.convertScaleAbs(gradient_x), 0.5,
                                   cv2.convertScaleAbs(gradient_y), 0.5, 0, dst=self._edges)
        return cv2.convertScaleAbs(cv2.Laplacian(self._grey, cv2.CV_16S), dst=self._edges)

    def detect(self, bgr: np.ndarray, want_edges: bool = False) -> VisionResult:
        """Red blobs of a BGR uint8 image, largest first (empty when none is big enough)."""
        settings, open_kernel, close_kernel = self._config
        if bgr.size == 0:
            empty = np.zeros(bgr.shape[:2], np.uint8)
            return VisionResult([], empty, empty.copy() if want_edges else None)
        mask = self.clean_mask(self.red_mask(bgr, settings), open_kernel, close_kernel)
        min_area_px = max(1.0, settings.min_area_fraction * mask.shape[0] * mask.shape[1])
        candidates = red_blobs(mask, min_area_px)
        edges = self.edges(bgr, settings) if want_edges else None
        return VisionResult(candidates, mask, edges)


def _ramp(value: float, zero_at: float, one_at: float) -> float:
    """0 at ``zero_at``, 1 at ``one_at``, linear between, clipped to 0-1."""
    return min(1.0, max(0.0, (value - zero_at) / (one_at - zero_at)))


def shape_score(solidity: float, fill: float, aspect: float, tilt_deg: float,
                cut: Tuple[str, ...]) -> float:
    """How much a blob looks like an upright can's silhouette (0-1): the product of four
    scores, each 1 for a can seen by a level or downward-pitched camera and 0 well outside.

    A can's silhouette is convex (solidity 1; 0.8 and below is not a can), a box with rounded
    ends (fill of its rotated box ~0.9; 0.6 and below is not), upright (long axis within 15 deg
    of vertical, as perspective leans a can near the image side; 35 deg is not) and taller than
    wide: a 12 oz can (122 x 66 mm) seen from the side to 75 deg from above is 1.4-2.2 times
    as tall as wide, so 1.4-2.6 scores 1, 1.0 or 4.0 scores 0.
    Measures along a cut side are not judged, and each cut axis (left/right, top/bottom)
    multiplies the score by CUT_FACTOR: a partly seen silhouette is a weaker sign of a can.
    The tilt of a blob cut only at the top is not judged (see below).
    """
    score = convexity_score(solidity, fill)
    cut_across = 'left' in cut or 'right' in cut
    cut_along = 'top' in cut or 'bottom' in cut
    if not (cut_across or cut_along):
        score *= min(_ramp(aspect, 1.0, 1.4), _ramp(-aspect, -4.0, -2.6))
    elif cut_across and not cut_along:
        score *= _ramp(aspect, 1.0, 1.4)
    score *= CUT_FACTOR ** (int(cut_across) + int(cut_along))
    if cut == ('top',):
        # The can's foot seen by a low camera pitched down: wider than tall farther away, so
        # its long axis lies across whatever the can's lean; its size is checked against its
        # floor range instead (report.geometry_score).
        return score
    return score * _ramp(-tilt_deg, -35.0, -15.0)


def convexity_score(solidity: float, fill: float) -> float:
    """The part of :func:`shape_score` that judges a blob's solidity and fill (0-1)."""
    return _ramp(solidity, 0.8, 0.93) * _ramp(fill, 0.6, 0.8)


def _cut_sides(x, y, width, height, image_width, image_height):
    sides = []
    if x <= 0:
        sides.append('left')
    if y <= 0:
        sides.append('top')
    if x + width >= image_width:
        sides.append('right')
    if y + height >= image_height:
        sides.append('bottom')
    return tuple(sides)


def _tilt_deg(moments) -> float:
    """Angle of the long axis of a region from the vertical (deg, 0-90); 0 when the region
    is round (no long axis)."""
    mu20, mu02, mu11 = moments['mu20'], moments['mu02'], moments['mu11']
    spread = math.hypot(mu20 - mu02, 2.0 * mu11)
    if spread <= 0.1 * (mu20 + mu02):
        return 0.0
    axis_from_x_deg = math.degrees(0.5 * math.atan2(2.0 * mu11, mu20 - mu02))
    return 90.0 - abs(axis_from_x_deg)


def solidity_and_fill(contour: np.ndarray, area_px: float) -> Tuple[float, float]:
    """(solidity, fill) of a region of ``area_px`` pixels inside ``contour``: its area over
    its convex hull's, and over its rotated bounding box's (a pixel wider each way, as the
    pixels' own extent), each at most 1."""
    hull_area = cv2.contourArea(cv2.convexHull(contour))
    solidity = min(1.0, area_px / hull_area) if hull_area > 0 else 1.0
    (_, _), (side_a, side_b), _ = cv2.minAreaRect(contour)
    return solidity, min(1.0, area_px / max(1.0, (side_a + 1.0) * (side_b + 1.0)))


def red_blobs(mask: np.ndarray, min_area_px: float,
              max_candidates: int = MAX_CANDIDATES) -> List[Blob]:
    """The 8-connected regions of a binary mask with at least ``min_area_px`` pixels, largest
    first (at most ``max_candidates``), each with its shape measures and score.

    Regions are ranked by the area inside their outer contour (cheap on a cleaned mask); the
    area and centroid come from the image moments of their own pixels, holes excluded.
    """
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    areas = [cv2.contourArea(contour) for contour in contours]
    order = sorted(range(len(contours)), key=areas.__getitem__, reverse=True)
    image_height, image_width = mask.shape[:2]
    blobs = []
    for index in order[:max_candidates]:
        contour = contours[index]
        x, y, width, height = cv2.boundingRect(contour)
        region = np.zeros((height, width), np.uint8)
        cv2.drawContours(region, [contour], -1, 1, cv2.FILLED, offset=(-x, -y))
        cv2.bitwise_and(region, mask[y:y + height, x:x + width], dst=region)
        moments = cv2.moments(region, binaryImage=True)
        centroid = centroid_from_moments(moments)
        if centroid is None or moments['m00'] < min_area_px:
            continue
        solidity, fill = solidity_and_fill(contour, moments['m00'])
        aspect = height / float(width)
        tilt = _tilt_deg(moments)
        cut = _cut_sides(x, y, width, height, image_width, image_height)
        blobs.append(Blob(x + centroid[0], y + centroid[1], float(moments['m00']), x, y, width,
                          height, solidity, fill, aspect, tilt, cut,
                          shape_score(solidity, fill, aspect, tilt, cut), contour))
    blobs.sort(key=lambda blob: blob.area, reverse=True)
    return blobs


MASK_TINT_BGR = (0, 110, 0, 0)
CONTOUR_BGR = (0, 255, 255)
OTHER_CONTOUR_BGR = (255, 0, 255)
BOX_BGR = (255, 128, 0)
CENTROID_BGR = (0, 255, 0)
FONT = cv2.FONT_HERSHEY_SIMPLEX


def _disc(diameter_px):
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (diameter_px, diameter_px))


def _put_text(image, text, origin, scale, thickness):
    """White text ``thickness`` px wide with a black outline 1 px around it, anti-aliased.

    The letters are drawn once, 1 px wide, into a patch around the text; grey-level dilation
    by a disc widens them to the fill and the outline (thick anti-aliased strokes directly
    cost ten times as much: 0.2 ms for the range label at 640x480). Clipped to the image.
    """
    (width, height), baseline = cv2.getTextSize(text, FONT, scale, thickness)
    pad = thickness + 2
    x0, y0 = max(0, origin[0] - pad), max(0, origin[1] - height - pad)
    x1 = min(image.shape[1], origin[0] + width + pad)
    y1 = min(image.shape[0], origin[1] + baseline + pad)
    if x1 <= x0 or y1 <= y0:
        return
    strokes = np.zeros((y1 - y0, x1 - x0), np.uint8)
    cv2.putText(strokes, text, (origin[0] - x0, origin[1] - y0), FONT, scale, 255, 1,
                cv2.LINE_AA)
    # A 1 px line covers each pixel only in part: doubled, its middle is opaque.
    cv2.add(strokes, strokes, dst=strokes)
    fill = cv2.dilate(strokes, _disc(thickness)) if thickness > 1 else strokes
    # A square reaches into the corners of the letters as a round pen of that width does.
    outline = cv2.dilate(strokes, np.ones((thickness + 2, thickness + 2), np.uint8))
    # Alpha blending: black where the outline covers, then white where the fill does.
    patch = image[y0:y1, x0:x1]
    cv2.multiply(patch, cv2.cvtColor(cv2.bitwise_not(outline), cv2.COLOR_GRAY2BGR), dst=patch,
                 scale=1.0 / 255.0)
    fill_bgr = cv2.cvtColor(fill, cv2.COLOR_GRAY2BGR)
    cv2.multiply(patch, cv2.bitwise_not(fill_bgr), dst=patch, scale=1.0 / 255.0)
    cv2.add(patch, fill_bgr, dst=patch)


def draw_annotation(bgr: np.ndarray, result: VisionResult, confidences, chosen: Optional[int],
                    range_m: float, out: Optional[np.ndarray] = None) -> np.ndarray:
    """The input with the red mask tinted green, every candidate's contour and confidence
    (0-1), the chosen one's box and centroid, and the range ("range ? m" when unknown).

    ``confidences`` holds one value per candidate of ``result`` and ``chosen`` the index of the
    one reported (None: nothing found). Drawn into ``out`` when given (same shape as ``bgr``),
    else into a new image.
    """
    if out is None:
        annotated = bgr.copy()
    else:
        annotated = out
        np.copyto(annotated, bgr)
    x, y, width, height = cv2.boundingRect(result.mask)
    if width and height:
        # Tinted only where the mask has pixels: the rest of a full-frame pass would add 0.
        tinted = annotated[y:y + height, x:x + width]
        cv2.add(tinted, MASK_TINT_BGR, dst=tinted, mask=result.mask[y:y + height, x:x + width])
    scale = max(0.35, annotated.shape[0] / 480.0)
    thickness = max(1, int(round(scale * 2)))
    for index, (blob, confidence) in enumerate(zip(result.candidates, confidences)):
        colour = CONTOUR_BGR if index == chosen else OTHER_CONTOUR_BGR
        if blob.contour is not None:
            cv2.drawContours(annotated, [blob.contour], -1, colour, thickness)
        _put_text(annotated, '%.2f' % confidence,
                  (blob.x, max(int(14 * scale), blob.y - int(4 * scale))), 0.6 * scale,
                  max(1, thickness - 1))
    if chosen is None:
        label = 'no red object'
    else:
        blob = result.candidates[chosen]
        cv2.rectangle(annotated, (blob.x, blob.y),
                      (blob.x + blob.width - 1, blob.y + blob.height - 1), BOX_BGR, thickness)
        centre = (int(round(blob.centroid_x)), int(round(blob.centroid_y)))
        cv2.circle(annotated, centre, max(2, 3 * thickness), CENTROID_BGR, -1)
        label = 'range ? m' if not np.isfinite(range_m) else 'range %.2f m' % range_m
    _put_text(annotated, label, (int(8 * scale), int(24 * scale)), 0.7 * scale, thickness)
    return annotated
