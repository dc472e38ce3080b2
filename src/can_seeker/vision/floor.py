"""Which pixels are floor: an adaptive floor appearance model, and the tutorial's dark threshold.

:class:`FloorClassifier` takes BGR uint8 images of one camera in order and returns, per
frame, a mono8 mask that is 255 on obstacle pixels. ``adaptive`` follows Ulrich & Nourbakhsh
2000: a reference trapezoid at the bottom of the image is assumed to be floor and fills
histograms of (colour, intensity) and of log chromaticity; a pixel the floor holds too little
of is an obstacle. The model learns only from reference pixels it classifies as floor, and not
from a frame whose reference area looks obstructed. Before classifying it undoes the lens's
vignetting (:mod:`can_seeker.vision.vignetting`) and the white balance's drift
(:mod:`can_seeker.vision.white_balance`). Blends of two floor colours at a tile seam, small
regions and regions without an edge to the floor are no obstacle. ``dark``: every pixel
darker than ``~dark_threshold`` is an obstacle.

Parameters: FLOOR_PARAMS. Design, reasons and limits: docs/design/floor-and-camera-scan.md.
"""
from dataclasses import dataclass
from typing import Optional

import cv2
import numpy as np

from can_seeker.params import Param
from can_seeker.vision.vignetting import VignettingEstimate
from can_seeker.vision.white_balance import (CHROMA_SIZE, WhiteBalanceLock, chromaticity_bins,
                                             undo_shift)

FLOOR_MODELS = ('adaptive', 'dark')

HUE_BINS = 30
"""Colour histogram bins over OpenCV's hue (0-179): 12 degrees each."""
FAINT_HUE_BINS = 12
"""Bins over the hue of faintly coloured pixels (see MIN_FAINT_SATURATION): 30 degrees
each, after the HUE_BINS; the bin after them is grey."""
GREY_BIN = HUE_BINS + FAINT_HUE_BINS
FAINT_MAX_GREY_SHARE = 0.25
"""Faint colours are judged by their hue only while less than this share of the floor model is
grey: on a grey floor, noise and a drifting white balance give the floor's own pixels faint
colours of any hue, so there they count as grey."""
VALUE_BIN_FRACTION = 0.08
VALUE_BIN_MIN_LEVELS = 5
VALUE_BIN_MAX_LEVELS = 8
"""Intensity histogram bins over HSV value 0-255 are VALUE_BIN_FRACTION of their lowest grey
level wide, between these many levels: light falling off, the exposure and lens shading
multiply a floor's brightness, so a dark floor's shading spans fewer levels than a light
one's, and a wall a few levels off a dark floor must fall in another bin."""


def _value_bin_lut() -> np.ndarray:
    """uint8 lookup of each grey level's intensity bin (see VALUE_BIN_FRACTION)."""
    starts = [0]
    while starts[-1] < 256:
        width = min(VALUE_BIN_MAX_LEVELS,
                    max(VALUE_BIN_MIN_LEVELS, int(round(VALUE_BIN_FRACTION * starts[-1]))))
        starts.append(starts[-1] + width)
    return (np.searchsorted(starts, np.arange(256), side='right') - 1).astype(np.uint8)


VALUE_BIN_LUT = _value_bin_lut()
VALUE_BINS = int(VALUE_BIN_LUT[-1]) + 1
CHROMA_SATURATION_MIN = 50
"""Pixels less saturated than this (0-255) have a hue the fine bins cannot trust: they count as
faintly coloured, or grey (see MIN_FAINT_SATURATION)."""
CHROMA_VALUE_MIN = 40
"""Pixels darker than this (0-255) have no reliable hue: they count as grey."""
BIN_TOLERANCE = 1
"""A pixel is floor-like when its bin or a neighbour (hue wraps around) is common in the model:
tolerates shading across the floor."""
JOINT_HUE_TOLERANCE = 1
JOINT_VALUE_TOLERANCE = 2
"""The joint test sums the model's mass over this many colour bins either side (hue wraps
around; grey has no neighbours) and intensity bins either side of a pixel's (colour,
intensity) bin: +-10 grey levels on the darkest floors, +-16 on light ones, tolerate the
exposure's walk and the light's fall-off."""
JOINT_BINS = (GREY_BIN + 1) * VALUE_BINS
BLEND_REACH_FRACTION = 0.025
"""A blend of two floor colours is looked for across at most this fraction of the image width
(8 px of 320) either side of a pixel, to the nearest solid floor (floor whose 3x3
neighbourhood is floor): a tile edge blurred over up to 15 px of 320 (a camera low and steep
over the floor magnifies a texture's edge, and defocus widens it in proportion to the image)."""
BLEND_DIRECTIONS = ((0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (-1, -1), (1, -1), (-1, 1))
"""(row, column) steps along which a pixel's nearest floor is looked for. A blend lies between
the floor colours found in two of them: on opposite sides across an edge, upright or slanted,
or in two neighbouring directions at the corner where four tiles meet (there every straight
line through the corner joins two tiles of the same colour)."""
BLEND_TOLERANCE = 12.0
"""Largest distance (BGR grey levels, after a 3x3 mean) of a blend's colour from the line
between the floor colours on its two sides: sensor noise and JPEG blocks."""
BLEND_MIN_CONTRAST = 3.0 * BLEND_TOLERANCE
"""Two floor colours blend only when they differ by at least this much (BGR grey levels): with
the same floor on both sides, a pixel that is not floor is an object, not a blend."""
BLEND_MARGIN = 0.1
"""A blend lies between its two floor colours, at least this fraction of the way from either:
a pixel of one side's colour is that side's, not a mix."""
CHROMA_MEDIAN_PX = 5
"""The chromaticity test judges each pixel's 5x5 median (per channel): sensor noise shrinks,
and a tile edge stays sharp, so a pixel beside it keeps its tile's colour."""
CHROMA_TOLERANCE_BINS = 2
"""The chromaticity test sums the floor's mass over this many log-chromaticity bins (0.02
each) either side of a pixel's in both ratios: +-4 % in R/G and B/G."""
MIN_CHROMA_PIXELS = 200
"""A chromaticity model needs at least this many usable floor pixels (a dark floor has none)."""
CHROMA_MIN_VALUE = 60
"""Pixels (medians) whose brightest channel is darker than this are not judged on their
chromaticity: a few grey levels of noise are too large a ratio there."""
CHROMA_JOINT_VALUE_TOLERANCE = JOINT_VALUE_TOLERANCE
"""The joint chromaticity test sums the floor's mass over this many intensity bins (of a
median's brightest channel) either side of a pixel's, besides the CHROMA_TOLERANCE_BINS: the
same +-10 to 16 grey levels as the joint hue test."""

MIN_BIN_FRACTION = 0.004
"""A colour or intensity histogram bin holding less than this fraction of the floor model marks
its pixels as obstacles: rarer than JPEG noise and shading put on a floor's own pixels."""
ADAPT_RATE = 0.005
"""Weight of each frame's reference floor pixels in the floor model (per frame; 0 would keep
the first frame's model): a time constant of 200 frames (13 s at 15 Hz), so the model follows
a slow change of light, not an object in the reference area for a few frames."""
REFERENCE_HEIGHT = 0.2
"""Height of the reference trapezoid at the bottom of the image that is assumed to be floor, as
a fraction of the image height: the floor just in front of the robot, which it drove over or
will reach first."""
SUSPECT_FRACTION = 0.3
"""The floor model is not updated from a frame whose reference area is more than this fraction
obstacle pixels: an object in front of the robot must not be learnt as floor."""
MIN_OBSTACLE_AREA = 0.001
"""Obstacle regions smaller than this fraction of the image area are ignored as noise."""
MAX_COLOUR_SHIFT = 0.3
"""Largest white-balance drift the floor model undoes: the log-chromaticity shift (natural log
of a channel ratio to green), followed from frame to frame over the whole image and held to the
reference area's colours, undone on the whole image before classifying (0 = off)."""
MIN_JOINT_FRACTION = 0.002
"""A pixel whose (colour, intensity) bin and its neighbours (a colour bin and two intensity
bins, 10-16 grey levels, either side) hold less than this fraction of the floor model is an
obstacle, even when its colour and its intensity are each common on the floor: on a floor of
two tiles, a wall with the hue of one and the brightness of the other (0 = off)."""
MIN_FAINT_SATURATION = 50
"""Pixels at least this saturated (HSV, 0-255) but less than CHROMA_SATURATION_MIN have a faint
colour, judged on coarse hue bins of 30 degrees, so a pinkish grey wall is no greenish grey
floor; less saturated pixels are grey (CHROMA_SATURATION_MIN = faint colours are grey too)."""
MIN_CHROMA_FRACTION = 0.002
"""A pixel whose log chromaticity (log R/G and log B/G of its 5x5 median, brightest channel
CHROMA_MIN_VALUE or more) and its neighbours within 0.04 in each hold less than this fraction of
the floor's is an obstacle: a cream wall is no white or pale blue floor tile, though all are
too pale to have a hue; on a camera whose white balance drifts, it needs MAX_COLOUR_SHIFT
(0 = off)."""
MIN_CHROMA_JOINT_FRACTION = 0.002
"""A pixel whose log chromaticity (as for MIN_CHROMA_FRACTION) within 0.04 in each ratio and
brightness (its median's brightest channel) within two intensity bins (10-16 grey levels)
together hold less than this fraction of the floor's is an obstacle, even when its chromaticity
alone is common: on a floor of a light and a mid tile, a wall with the light tile's
chromaticity and the mid tile's brightness (0 = off; needs MIN_CHROMA_FRACTION)."""
MAX_VIGNETTING = 0.7
"""Largest lens fall-off the floor model estimates from the images and undoes before
classifying: the fraction of brightness lost in the image corners (an estimate under 0.05
leaves the image alone; 0 = off)."""
MIN_EDGE_CONTRAST = 1.5
"""Obstacle regions whose outline (away from the image border) has a mean colour gradient below
this are floor shading (vignetting, light fall-off), not objects (grey levels per pixel, after
a 5x5 Gaussian blur; 0 = keep every region)."""

FLOOR_PARAMS = (
    Param('floor_model', 'adaptive', 'floor classifier: adaptive (floor appearance histograms '
          'learned from the reference area in front of the robot) or dark (the tutorial: '
          'pixels darker than ~dark_threshold are obstacles)', choices=FLOOR_MODELS),
    Param('dark_threshold', 60, 'grey level below which a pixel is an obstacle when '
          '~floor_model is dark (0-255)', 0, 255),
)
"""The floor classifier's parameters: which model, and the dark model's threshold for a room;
the adaptive model's heuristics are the constants above."""


@dataclass(frozen=True)
class FloorSettings:
    """Validated settings of :class:`FloorClassifier`: FLOOR_PARAMS and the adaptive model's
    constants above (their defaults here; benches and tests vary them)."""

    floor_model: str = 'adaptive'
    dark_threshold: int = 60
    min_bin_fraction: float = MIN_BIN_FRACTION
    adapt_rate: float = ADAPT_RATE
    reference_height: float = REFERENCE_HEIGHT
    suspect_fraction: float = SUSPECT_FRACTION
    min_obstacle_area: float = MIN_OBSTACLE_AREA
    max_colour_shift: float = MAX_COLOUR_SHIFT
    min_joint_fraction: float = MIN_JOINT_FRACTION
    min_faint_saturation: int = MIN_FAINT_SATURATION
    min_chroma_fraction: float = MIN_CHROMA_FRACTION
    min_chroma_joint_fraction: float = MIN_CHROMA_JOINT_FRACTION
    max_vignetting: float = MAX_VIGNETTING
    min_edge_contrast: float = MIN_EDGE_CONTRAST

    @classmethod
    def from_values(cls, values):
        """Settings from any object with one attribute per FLOOR_PARAMS name (the node's read
        parameters); the other settings keep their constants."""
        return cls(**{spec.name: getattr(values, spec.name) for spec in FLOOR_PARAMS})


def reference_trapezoid(width: int, height: int, height_fraction: float) -> np.ndarray:
    """Corners (px, int32) of the reference area: the bottom ``height_fraction`` of the image,
    90 % of the width at the bottom narrowing to 50 % at the top, like the floor in front of a
    robot seen in perspective."""
    top = int(round((height - 1) * (1.0 - height_fraction)))
    bottom = height - 1
    centre = (width - 1) / 2.0
    return np.array(((centre - 0.45 * width, bottom), (centre + 0.45 * width, bottom),
                     (centre + 0.25 * width, top), (centre - 0.25 * width, top)),
                    np.float64).round().astype(np.int32)


def _hue_bin_lut(bins: int, first: int = 0) -> np.ndarray:
    hues = np.arange(256)
    return (first + np.where(hues < 180, hues * bins // 180, 0)).astype(np.uint8)


HUE_BIN_LUT = _hue_bin_lut(HUE_BINS)
FAINT_HUE_BIN_LUT = _hue_bin_lut(FAINT_HUE_BINS, HUE_BINS)


def _tolerant(common: np.ndarray, wrap: bool) -> np.ndarray:
    """Bins within BIN_TOLERANCE of a common bin (hue bins wrap around 0/179)."""
    widened = common.copy()
    for shift in range(1, BIN_TOLERANCE + 1):
        if wrap:
            widened |= np.roll(common, shift) | np.roll(common, -shift)
        else:
            widened[shift:] |= common[:-shift]
            widened[:-shift] |= common[shift:]
    return widened


def _joint_neighbourhood(model: np.ndarray) -> np.ndarray:
    """(GREY_BIN + 1) x VALUE_BINS: the joint model's mass within JOINT_HUE_TOLERANCE colour
    bins (hue rows only, wrapping around) and JOINT_VALUE_TOLERANCE intensity bins of each
    bin."""
    along_value = cv2.boxFilter(model, -1, (2 * JOINT_VALUE_TOLERANCE + 1, 1), normalize=False,
                                borderType=cv2.BORDER_CONSTANT)
    summed = along_value.copy()
    for rows in (slice(0, HUE_BINS), slice(HUE_BINS, GREY_BIN)):
        hues = along_value[rows]
        for shift in range(1, JOINT_HUE_TOLERANCE + 1):
            summed[rows] += np.roll(hues, shift, axis=0) + np.roll(hues, -shift, axis=0)
    return summed


class FloorClassifier:
    """Per-frame floor / obstacle classification of BGR images (keeps the floor model).

    Not thread-safe: one frame at a time. The model is learned from the first frame and kept
    while the image size stays the same.
    """

    def __init__(self, settings: Optional[FloorSettings] = None):
        self.settings = settings if settings is not None else FloorSettings()
        self.white_balance = WhiteBalanceLock(self.settings.max_colour_shift)
        self.vignetting = VignettingEstimate(self.settings.max_vignetting)
        self._shape = None
        self.model = None
        self._obstacle_bins_model = None
        self._obstacle_bins = None
        self.chroma_model = None
        self.model_updated = False

    def reset(self):
        """Forget the floor model: the next frame's reference area is learned afresh."""
        self.model = None
        self.chroma_model = None
        self.white_balance.reset()
        self.vignetting.reset()

    def _prepare(self, shape):
        if shape == self._shape:
            return
        height, width = shape[:2]
        self._reference = np.zeros((height, width), np.uint8)
        corners = reference_trapezoid(width, height, self.settings.reference_height)
        cv2.fillConvexPoly(self._reference, corners, 255)
        self.reference_corners = corners
        self._reference_pixels = self._reference > 0
        self._shape = shape
        self.reset()

    def classify(self, bgr: np.ndarray, ignore: Optional[np.ndarray] = None) -> np.ndarray:
        """mono8 mask, 255 where a pixel belongs to an obstacle region, 0 on the floor.

        ``ignore`` (mono8, nonzero = ignore) marks pixels that are neither floor nor obstacle,
        e.g. the target can: they are never obstacles and never teach the floor model.
        """
        self._prepare(bgr.shape)
        if self.settings.floor_model == 'dark':
            grey = cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY)
            raw = np.where(grey < self.settings.dark_threshold, 255, 0).astype(np.uint8)
            self.model_updated = False
        else:
            reference = self._reference_pixels
            if ignore is not None:
                reference = reference & (ignore == 0)
            bgr, raw = self._appearance_obstacles(bgr, reference)
            raw[floor_blends(bgr, raw == 0)] = 0
        if ignore is not None:
            raw[ignore > 0] = 0
        return self._obstacle_regions(raw, bgr)

    def _features(self, bgr):
        """Image of (colour bin, intensity bin) indices, colour * VALUE_BINS + intensity
        (uint16), of ``bgr``."""
        hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)
        hue, saturation, value = cv2.split(hsv)
        colour = cv2.LUT(hue, HUE_BIN_LUT)
        if self.settings.min_faint_saturation < CHROMA_SATURATION_MIN:
            faint = saturation < CHROMA_SATURATION_MIN
            colour[faint] = cv2.LUT(hue, FAINT_HUE_BIN_LUT)[faint]
        grey = (saturation < self.settings.min_faint_saturation) | (value < CHROMA_VALUE_MIN)
        colour[grey] = GREY_BIN
        return colour.astype(np.uint16) * VALUE_BINS + cv2.LUT(value, VALUE_BIN_LUT)

    @staticmethod
    def _histogram(features, where):
        """The (GREY_BIN + 1) x VALUE_BINS histogram of the features where ``where``, normalised
        (None when there are none)."""
        counts = np.bincount(features[where], minlength=JOINT_BINS).astype(np.float64)
        total = counts.sum()
        return (counts / total).reshape(GREY_BIN + 1, VALUE_BINS) if total > 0 else None

    def _appearance_obstacles(self, bgr, reference):
        """(image with the white-balance drift undone, raw obstacle pixels); updates the
        models. The lens's fall-off is undone first; the drift is measured on the reference
        pixels that are floor with the last frame's correction: an obstacle in front of the
        robot never moves it."""
        self.vignetting.observe(bgr)
        bgr = self.vignetting.correct(bgr)
        # The chromaticity test's medians, taken before any drift is undone: a channel's median
        # commutes with its gain (undo_shift is a monotone lookup per channel).
        median = (cv2.medianBlur(bgr, CHROMA_MEDIAN_PX) if self.settings.min_chroma_fraction > 0.0
                  else None)
        if self.model is None:
            self.white_balance.track(bgr[reference], bgr)
            features = self._features(bgr)
            self.model = self._histogram(features, reference)
            if self.model is None:
                self.reset()
                self.model_updated = False
                return bgr, np.zeros(bgr.shape[:2], np.uint8)
            raw = self._obstacle_pixels(features)
        else:
            if self.white_balance.max_shift_log > 0.0:
                top = int(self.reference_corners[:, 1].min())
                features = self._features(self.white_balance.correct(bgr[top:]))
                floor_before = reference[top:] & (self._obstacle_pixels(features) == 0)
                self.white_balance.track(bgr[top:][floor_before], bgr,
                                         self._floor_share(bgr, median))
                bgr = self.white_balance.correct(bgr)
                if median is not None:
                    median = self.white_balance.correct(median)
            features = self._features(bgr)
            raw = self._obstacle_pixels(features)
        chroma = None
        if median is not None:
            chroma = chroma_features(median)
            if self.chroma_model is None:
                self._set_chroma_model(self._chroma_histogram(chroma, reference))
            appearance_floor = raw == 0
            raw[self._chroma_obstacles(chroma)] = 255
        floor = self._update_model(features, raw, reference)
        if floor is not None:
            self.white_balance.learn(bgr[floor], self.settings.adapt_rate)
            if chroma is not None:
                self._learn_chroma(chroma, reference & appearance_floor)
        return bgr, raw

    @staticmethod
    def _chroma_histogram(chroma, where):
        """The normalised histogram (CHROMA_SIZE x CHROMA_SIZE x VALUE_BINS: log B/G, log R/G,
        brightness) of the usable pixels of ``chroma`` (see :func:`chroma_features`) where
        ``where``, or None with too few."""
        bins, usable = chroma
        selected = bins[where & usable]
        if selected.size < MIN_CHROMA_PIXELS:
            return None
        counts = np.bincount(selected, minlength=CHROMA_SIZE * CHROMA_SIZE * VALUE_BINS)
        return (counts / float(selected.size)).reshape(CHROMA_SIZE, CHROMA_SIZE, VALUE_BINS)

    def _set_chroma_model(self, model):
        """Keep ``model`` and, per joint bin, whether its pixels are rare on the floor: by
        chromaticity alone (MIN_CHROMA_FRACTION) or by chromaticity and brightness together
        (MIN_CHROMA_JOINT_FRACTION)."""
        self.chroma_model = model
        if model is None:
            return
        side = 2 * CHROMA_TOLERANCE_BINS + 1
        near = cv2.boxFilter(model.sum(axis=2), -1, (side, side), normalize=False,
                             borderType=cv2.BORDER_CONSTANT)
        rare = (near < self.settings.min_chroma_fraction)[:, :, None]
        if self.settings.min_chroma_joint_fraction > 0.0:
            rare = rare | (_chroma_joint_neighbourhood(model)
                           < self.settings.min_chroma_joint_fraction)
        self._chroma_rare = np.broadcast_to(rare, model.shape).ravel()

    def _chroma_obstacles(self, chroma) -> np.ndarray:
        """Boolean image: usable pixels whose chromaticity, or chromaticity and brightness
        together, the floor holds too little of (none while the floor has no chromaticity
        model)."""
        bins, usable = chroma
        if self.chroma_model is None:
            return np.zeros(usable.shape, bool)
        return usable & self._chroma_rare[np.where(usable, bins, 0)]

    def _learn_chroma(self, chroma, floor):
        """Blend the chromaticity of ``floor`` (reference pixels of a frame that teaches the
        model, floor by colour and intensity) into its model; the first usable one is the
        model. A floor colour the first frames did not show (the other tile of a checker) is
        learned once it is in the reference area, as long as most of that area is floor."""
        current = self._chroma_histogram(chroma, floor)
        if current is None:
            return
        if self.chroma_model is None:
            self._set_chroma_model(current)
            return
        # In place: the model (2 MB) learns every frame.
        rate = self.settings.adapt_rate
        model = self.chroma_model
        model *= 1.0 - rate
        current *= rate
        model += current
        self._set_chroma_model(model)

    def _floor_share(self, bgr, median):
        """shift (log R/G, log B/G) -> the share (0-1) of the frame ``bgr`` (every second pixel)
        the floor models take for floor with that shift undone. ``median`` is the chromaticity
        test's 5x5 median of ``bgr`` (None without that test)."""
        sample = bgr[::2, ::2]

        def share(shift_log):
            obstacle = self._obstacle_pixels(self._features(undo_shift(sample, shift_log))) != 0
            if median is not None and self.chroma_model is not None:
                chroma = chroma_features(undo_shift(median[::2, ::2], shift_log))
                obstacle |= self._chroma_obstacles(chroma)
            return 1.0 - float(np.count_nonzero(obstacle)) / obstacle.size
        return share

    def _obstacle_pixels(self, features):
        """mono8, 255 where a pixel's colour or intensity bin is rare in the floor model, or
        (with MIN_JOINT_FRACTION) the pair of them (see :meth:`_obstacle_bins_of`)."""
        if self._obstacle_bins_model is not self.model:
            self._obstacle_bins = self._obstacle_bins_of(self.model)
            self._obstacle_bins_model = self.model
        return np.take(self._obstacle_bins, features)

    def _obstacle_bins_of(self, model):
        """uint8 per joint bin of ``model``, 255 where its pixels are obstacles: a frame
        classifies its pixels several times against one model (the model is replaced, never
        changed in place, when it learns). Faint colours count as grey while
        :data:`FAINT_MAX_GREY_SHARE` of the floor is grey."""
        threshold = self.settings.min_bin_fraction
        faint_as_grey = model[GREY_BIN].sum() >= FAINT_MAX_GREY_SHARE
        if faint_as_grey:
            model = model.copy()
            model[GREY_BIN] += model[HUE_BINS:GREY_BIN].sum(axis=0)
            model[HUE_BINS:GREY_BIN] = 0.0
        colour_model = model.sum(axis=1)
        colour_floor = np.empty(GREY_BIN + 1, bool)
        colour_floor[:HUE_BINS] = _tolerant(colour_model[:HUE_BINS] >= threshold, True)
        colour_floor[HUE_BINS:GREY_BIN] = _tolerant(colour_model[HUE_BINS:GREY_BIN] >= threshold,
                                                    True)
        colour_floor[GREY_BIN] = colour_model[GREY_BIN] >= threshold
        value_floor = _tolerant(model.sum(axis=0) >= threshold, False)
        floor = colour_floor[:, None] & value_floor[None, :]
        if self.settings.min_joint_fraction > 0.0:
            floor &= _joint_neighbourhood(model) >= self.settings.min_joint_fraction
        if faint_as_grey:
            floor[HUE_BINS:GREY_BIN] = floor[GREY_BIN]
        return np.where(floor.ravel(), 0, 255).astype(np.uint8)

    def _update_model(self, features, raw, reference):
        """Blend the reference area's floor pixels into the model unless the area is suspect;
        those pixels (a boolean image), or None when the model was not updated."""
        self.model_updated = False
        rate = self.settings.adapt_rate
        in_reference = int(np.count_nonzero(reference))
        if rate <= 0.0 or in_reference == 0:
            return None
        floor = reference & (raw == 0)
        floor_count = int(np.count_nonzero(floor))
        if floor_count == 0 or 1.0 - floor_count / in_reference > self.settings.suspect_fraction:
            return None
        self.model = (1.0 - rate) * self.model + rate * self._histogram(features, floor)
        self.model_updated = True
        return floor

    def _obstacle_regions(self, raw, bgr):
        """Speckles opened away; connected regions of at least the minimum area whose outline
        is an edge (see :func:`outline_contrast`)."""
        opened = cv2.morphologyEx(raw, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
        count, labels, stats, _ = cv2.connectedComponentsWithStats(opened, connectivity=8)
        if count <= 1:
            return opened
        min_area_px = self.settings.min_obstacle_area * raw.shape[0] * raw.shape[1]
        keep = stats[:, cv2.CC_STAT_AREA] >= max(1.0, min_area_px)
        if self.settings.min_edge_contrast > 0.0:
            contrast = outline_contrast(bgr, opened, labels, count)
            keep &= ~(contrast < self.settings.min_edge_contrast)
        keep[0] = False
        if keep[1:].all():
            return opened
        return np.where(keep[labels], 255, 0).astype(np.uint8)


def chroma_features(median_bgr: np.ndarray):
    """(bin, usable) of uint8 BGR pixels (5x5 medians): the flat index of each pixel's
    (log B/G, log R/G, brightness) bin, brightness being the brightest channel in VALUE_BINS,
    and whether its chromaticity is reliable (see :func:`chromaticity_bins`)."""
    bins, usable = chromaticity_bins(median_bgr, CHROMA_MIN_VALUE)
    blue, green, red = cv2.split(median_bgr)
    brightest = cv2.max(cv2.max(blue, green), red)
    return bins * VALUE_BINS + cv2.LUT(brightest, VALUE_BIN_LUT), usable


def _chroma_joint_neighbourhood(model: np.ndarray) -> np.ndarray:
    """CHROMA_SIZE x CHROMA_SIZE x VALUE_BINS: the joint chromaticity model's mass within
    CHROMA_TOLERANCE_BINS in either ratio and CHROMA_JOINT_VALUE_TOLERANCE intensity bins of each
    bin (outside the histogram counts as none)."""
    value_side = 2 * CHROMA_JOINT_VALUE_TOLERANCE + 1
    along_value = cv2.boxFilter(model.reshape(-1, VALUE_BINS), -1, (value_side, 1),
                                normalize=False, borderType=cv2.BORDER_CONSTANT)
    side = 2 * CHROMA_TOLERANCE_BINS + 1
    return cv2.boxFilter(along_value.reshape(model.shape), -1, (side, side), normalize=False,
                         borderType=cv2.BORDER_CONSTANT)


def _floor_along(floor_u8: np.ndarray, step, reach_px: int) -> np.ndarray:
    """uint8 image: 1 where a floor pixel lies 1 to ``reach_px`` steps of ``step`` (row,
    column) away."""
    kernel = np.zeros((2 * reach_px + 1, 2 * reach_px + 1), np.uint8)
    for distance in range(1, reach_px + 1):
        kernel[reach_px + distance * step[0], reach_px + distance * step[1]] = 1
    return cv2.dilate(floor_u8, kernel, anchor=(reach_px, reach_px),
                      borderType=cv2.BORDER_CONSTANT, borderValue=0)


def _floor_in_two_directions(floor: np.ndarray, reach_px: int) -> np.ndarray:
    """Boolean image: pixels with a floor pixel within ``reach_px`` steps along at least two of
    BLEND_DIRECTIONS (the only pixels that can be blends; the inside of a region wider than
    that never is)."""
    floor_u8 = floor.astype(np.uint8)
    directions = np.zeros(floor.shape, np.uint8)
    for step in BLEND_DIRECTIONS:
        directions += _floor_along(floor_u8, step, reach_px)
    return directions >= 2


def blend_reach_px(width_px: int) -> int:
    """How far (px) a blend's floor is looked for in an image ``width_px`` wide."""
    return max(1, int(round(BLEND_REACH_FRACTION * width_px)))


def _nearest_floor(padded_floor: np.ndarray, padded_colours: np.ndarray, padded_width: int,
                   start: np.ndarray, step, reach_px: int):
    """(found, colour): whether each pixel (``start``: its flat index in the padded image) has
    a floor pixel 1 to ``reach_px`` steps of ``step`` (row, column) away, and the colour of the
    nearest one. ``padded_floor`` and ``padded_colours`` (flat) have a border of ``reach_px``
    non-floor pixels (no bounds checks); each step looks only at the pixels that found none
    yet."""
    stride = step[0] * padded_width + step[1]
    found = np.zeros(start.size, bool)
    colour = np.zeros((start.size, 3), padded_colours.dtype)
    looking = np.arange(start.size)
    for distance in range(1, reach_px + 1):
        index = start + distance * stride
        hit = padded_floor[index]
        if hit.any():
            which = looking[hit]
            found[which] = True
            colour[which] = padded_colours[index[hit]]
            keep = ~hit
            looking, start = looking[keep], start[keep]
            if looking.size == 0:
                break
    return found, colour


def _contrasted(smooth: np.ndarray, floor: np.ndarray, rows: np.ndarray, columns: np.ndarray,
                reach_px: int, min_contrast: float):
    """(rows, columns) of those pixels that see floor colours at least ``min_contrast`` apart
    within ``reach_px`` rows and columns: each channel's extremes over the floor's ``smooth``
    colours (uint8 3x3 means) in that square bound the colours along BLEND_DIRECTIONS, so no
    two of those differ by more. A pixel beside one floor colour is no blend; two dilations
    spare it the search."""
    square = np.ones((2 * reach_px + 1, 2 * reach_px + 1), np.uint8)
    mask = floor.astype(np.uint8)
    brightest = cv2.dilate(cv2.bitwise_and(smooth, smooth, mask=mask), square,
                           borderType=cv2.BORDER_CONSTANT, borderValue=0)
    inverse = cv2.bitwise_not(smooth)
    darkest = 255 - cv2.dilate(cv2.bitwise_and(inverse, inverse, mask=mask), square,
                               borderType=cv2.BORDER_CONSTANT, borderValue=0)[rows, columns]
    spread = np.maximum(brightest[rows, columns].astype(np.int32) - darkest, 0)
    keep = np.einsum('ij,ij->i', spread, spread) >= min_contrast * min_contrast
    return rows[keep], columns[keep]


def floor_blends(bgr: np.ndarray, floor: np.ndarray, reach_px: Optional[int] = None,
                 tolerance: float = BLEND_TOLERANCE,
                 min_contrast: float = BLEND_MIN_CONTRAST) -> np.ndarray:
    """Boolean image: the non-floor pixels of ``bgr`` (uint8) whose colour is a mix of the floor
    around them. For each pixel the nearest solid floor pixel (its 3x3 neighbourhood all
    ``floor``: speckles of floor inside an object are not its sides) within ``reach_px`` steps
    (:func:`blend_reach_px` of the image's width by default) is found along each of
    BLEND_DIRECTIONS; when the colours (3x3 means) of two of them differ by at least
    ``min_contrast`` and the pixel's colour is within ``tolerance`` of the segment between
    them, and BLEND_MARGIN inside it, it is a blend of them."""
    if reach_px is None:
        reach_px = blend_reach_px(floor.shape[1])
    blends = np.zeros(floor.shape, bool)
    floor = cv2.erode(floor.astype(np.uint8), np.ones((3, 3), np.uint8),
                      borderType=cv2.BORDER_CONSTANT, borderValue=1).astype(bool)
    rows, columns = np.nonzero(~floor & _floor_in_two_directions(floor, reach_px))
    if rows.size == 0:
        return blends
    smooth = cv2.blur(bgr, (3, 3))
    rows, columns = _contrasted(smooth, floor, rows, columns, reach_px, min_contrast)
    if rows.size == 0:
        return blends
    pixel = smooth[rows, columns].astype(np.float32)
    height, width = floor.shape
    padded_width = width + 2 * reach_px
    padded_floor = np.zeros((height + 2 * reach_px, padded_width), bool)
    padded_floor[reach_px:reach_px + height, reach_px:reach_px + width] = floor
    padded_colours = cv2.copyMakeBorder(smooth, reach_px, reach_px, reach_px, reach_px,
                                        cv2.BORDER_CONSTANT, value=0).reshape(-1, 3)
    start = (rows + reach_px) * padded_width + (columns + reach_px)
    ends = [_nearest_floor(padded_floor.ravel(), padded_colours, padded_width, start, step,
                           reach_px) for step in BLEND_DIRECTIONS]
    # Channels as rows (one contiguous array each): the per-pair arithmetic below is on them.
    pixel = np.ascontiguousarray(pixel.T)
    colours = [np.ascontiguousarray(colour.T).astype(np.float32) for _, colour in ends]
    undecided = np.ones(rows.size, bool)
    for first in range(len(ends)):
        for second in range(first + 1, len(ends)):
            both = np.flatnonzero(undecided & ends[first][0] & ends[second][0])
            if both.size == 0:
                continue
            start = colours[first][:, both]
            span = colours[second][:, both] - start
            length_sq = span[0] * span[0] + span[1] * span[1] + span[2] * span[2]
            contrasted = length_sq >= min_contrast * min_contrast
            both, start, span = both[contrasted], start[:, contrasted], span[:, contrasted]
            length_sq = length_sq[contrasted]
            offset = pixel[:, both] - start
            along = ((offset[0] * span[0] + offset[1] * span[1] + offset[2] * span[2])
                     / np.maximum(length_sq, 1e-6))
            off_line = offset - along * span
            blend = ((off_line[0] * off_line[0] + off_line[1] * off_line[1]
                      + off_line[2] * off_line[2] <= tolerance * tolerance)
                     & (along >= BLEND_MARGIN) & (along <= 1.0 - BLEND_MARGIN))
            decided = both[blend]
            blends[rows[decided], columns[decided]] = True
            undecided[decided] = False
    return blends


def colour_gradient(bgr: np.ndarray, where: Optional[np.ndarray] = None) -> np.ndarray:
    """Per-pixel colour gradient magnitude (grey levels per pixel, float32): the largest over
    the three channels of a 5x5 Gaussian-blurred image (the blur keeps sensor noise and JPEG
    blocks out; a blue obstacle on a white floor differs in red and green, not in brightness).

    With ``where`` (a boolean image), only the pixels it marks, in row order (the same values
    as ``colour_gradient(bgr)[where]``, without the magnitude of every other pixel)."""
    blurred = cv2.GaussianBlur(bgr, (5, 5), 0)
    # Sobel sums of whole grey levels are whole numbers: exact in int16, and exactly the float
    # results once scaled by 1/8 (a power of two).
    gradient_x = cv2.Sobel(blurred, cv2.CV_16S, 1, 0, ksize=3)
    gradient_y = cv2.Sobel(blurred, cv2.CV_16S, 0, 1, ksize=3)
    if where is not None:
        gradient_x, gradient_y = gradient_x[where], gradient_y[where]
    gradient_x = gradient_x.astype(np.float32) * np.float32(0.125)
    gradient_y = gradient_y.astype(np.float32) * np.float32(0.125)
    magnitude = np.sqrt(gradient_x * gradient_x + gradient_y * gradient_y)
    # The channels' largest as two elementwise maxima: a reduction along the last axis of a
    # pixel-interleaved array is several times slower in numpy.
    return np.maximum(np.maximum(magnitude[..., 0], magnitude[..., 1]), magnitude[..., 2])


def fill_holes(mask: np.ndarray) -> np.ndarray:
    """mono8 ``mask`` with every hole filled: the zero pixels no path of zero pixels
    (4-connected) joins to the image border become 255."""
    height, width = mask.shape
    outside = np.ones((height + 2, width + 2), np.uint8)
    outside[1:-1, 1:-1] = mask == 0
    reached = np.zeros((height + 4, width + 4), np.uint8)
    cv2.floodFill(outside, reached, (0, 0), 2, flags=4)
    return np.where(outside[1:-1, 1:-1] == 2, 0, 255).astype(np.uint8)


def outline_contrast(bgr: np.ndarray, mask: np.ndarray, labels: np.ndarray,
                     count: int) -> np.ndarray:
    """Mean colour gradient (grey levels per pixel) along each labelled region's outer outline
    away from the image border; NaN for a region whose whole outline is on the border (it says
    nothing either way, and is kept). Holes do not count: floor-coloured speckles inside an
    object (lettering, a rendered seam along a wall) are bounded by the object's own shading,
    and their many pixels would outweigh the edge that sets the object off from the floor."""
    solid = fill_holes(mask)
    outline = cv2.subtract(solid, cv2.erode(solid, np.ones((3, 3), np.uint8)))
    outline[0, :] = outline[-1, :] = 0
    outline[:, 0] = outline[:, -1] = 0
    on_outline = outline > 0
    region = labels[on_outline]
    gradient = colour_gradient(bgr, on_outline)
    lengths = np.bincount(region, minlength=count).astype(np.float64)
    # A filled hole pixel diagonal to the outside can lie on the outline with no region label.
    lengths[0] = 0.0
    sums = np.bincount(region, weights=gradient, minlength=count)
    with np.errstate(invalid='ignore', divide='ignore'):
        return np.where(lengths > 0, sums / lengths, np.nan)
