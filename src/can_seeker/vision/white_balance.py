"""Undoing a camera's white-balance drift against a surface known to be in view (the floor).

A white-balance change multiplies each channel by a gain, so in log chromaticity (log R/G,
log B/G) it moves every colour of the image by one shift (von Kries). :class:`WhiteBalanceLock`
keeps a histogram of the reference pixels' log chromaticity and, each frame, predicts the shift
from the last one plus the step between two frames, measured pixel by pixel on the pixels that
still show the same surface; the floor corrects that prediction only by a correlation peak of
its own within ANCHOR_BINS, and, given the floor model's verdict, only where the correction
shows at least MIN_FLOOR_GAIN more of the frame as floor. The shift moves at most a drift's
pace, stays within a bound, and relaxes toward none while nothing measures it.
:func:`undo_shift` applies the inverse gains to an image.

Design, reasons and limits: docs/design/floor-and-camera-scan.md.
"""
from typing import Callable, Optional

import cv2
import numpy as np

CHROMA_BIN = 0.02
"""Width of a log-chromaticity histogram bin (natural log units, about 2 % in a ratio)."""
CHROMA_HALF_RANGE_BINS = 40
"""The histograms span +-0.8 in each log ratio (bins either side of grey)."""
STEP_BINS = 3
"""Largest change of the shift from one frame to the next (bins): a drift's pace, not a
jump to another surface."""
MIN_PIXELS = 200
"""Fewer usable reference pixels than this (a dark floor, a close object) keep the shift."""
MIN_OVERLAP = 0.3
"""The shifted histograms must share at least this much mass (0-1) for the shift to count."""
RELAX_RATE = 0.05
"""Fraction of the shift let go per frame without a measurement (a camera's white balance
pulls its own drift back at about this pace)."""
ANCHOR_BINS = 2
"""With the whole image's step known, the floor corrects the predicted shift only by a
correlation peak within this many bins of it."""
MIN_FLOOR_GAIN = 0.01
"""With the whole image's step known, the floor's correction must show at least this much more
of the frame (0-1) as floor than the predicted shift does to be taken."""
SAME_SURFACE_LOG = 0.1
"""A pixel whose brightness (log green) changed from the last frame by more than this, beyond
the whole frame's median change (exposure), shows another surface now: it says nothing about
the drift."""
MIN_SAME_SURFACE = 0.3
"""At least this share (0-1) of the pixels usable in both frames must show the same surface
for the step to count (a frame that shows a new scene gives none)."""
FRAME_STEP_BINS = 2 * STEP_BINS
"""The step between two frames is looked for within this many bins (twice a drift's usual
pace: a frame may follow a dropped one)."""
MIN_VALUE = 40
"""Pixels darker than this (0-255) have no reliable chromaticity."""
MAX_VALUE = 250
"""Pixels with a channel this bright may be clipped: their chromaticity is not the surface's."""


def _ratio_bin_table() -> np.ndarray:
    """Histogram bin (0-255: 255 for none) of log(a/b) for every pair of levels (a, b)."""
    levels = np.log(np.maximum(np.arange(256, dtype=np.float64), 0.5))
    bins = np.rint((levels[:, None] - levels[None, :]) / CHROMA_BIN) + CHROMA_HALF_RANGE_BINS
    table = np.where((bins >= 0) & (bins <= 2 * CHROMA_HALF_RANGE_BINS), bins, 255)
    table[0, :] = table[:, 0] = 255
    return table.astype(np.uint8)


RATIO_BIN = _ratio_bin_table()
_RATIO_BIN_FLAT = RATIO_BIN.ravel()
LOG_LEVEL = np.log(np.arange(256, dtype=np.float32) + 0.5)
"""Natural log of every level (0-255), half a level up so that black stays finite."""


CHROMA_SIZE = 2 * CHROMA_HALF_RANGE_BINS + 1
"""Bins along each axis of a log-chromaticity histogram."""


def chromaticity_bins(bgr: np.ndarray, min_value: int = MIN_VALUE):
    """(bin, usable) of uint8 BGR pixels (any shape ending in 3): the flat index
    (row log B/G, column log R/G) of each pixel's log-chromaticity histogram bin (int), and
    whether its chromaticity is reliable (brightest channel from ``min_value`` up to under
    MAX_VALUE, both ratios within the histogram)."""
    blue, green, red = bgr[..., 0], bgr[..., 1], bgr[..., 2]
    # One flat lookup of (a << 8) | b: several times faster than RATIO_BIN[a, b].
    rows = _RATIO_BIN_FLAT.take((blue.astype(np.uint16) << 8) | green)
    columns = _RATIO_BIN_FLAT.take((red.astype(np.uint16) << 8) | green)
    brightest = np.maximum(np.maximum(blue, green), red)
    usable = (rows != 255) & (columns != 255) & (brightest >= min_value) & (brightest < MAX_VALUE)
    return rows.astype(np.intp) * CHROMA_SIZE + columns, usable


def log_chromaticity_histogram(bgr_pixels: np.ndarray) -> Optional[np.ndarray]:
    """Normalised, lightly smoothed 2-D histogram (rows log B/G, columns log R/G) of an Nx3
    uint8 array of BGR pixels; None when too few of them have a reliable chromaticity."""
    if len(bgr_pixels) < MIN_PIXELS:
        return None
    bins, usable = chromaticity_bins(bgr_pixels)
    if np.count_nonzero(usable) < MIN_PIXELS:
        return None
    counts = np.bincount(bins[usable], minlength=CHROMA_SIZE * CHROMA_SIZE)
    histogram = cv2.GaussianBlur(counts.reshape(CHROMA_SIZE, CHROMA_SIZE).astype(np.float32),
                                 (5, 5), 1.0)
    return histogram / float(histogram.sum())


def _middle_mean(values: np.ndarray) -> float:
    """Mean of the middle half of ``values`` (between their quartiles): robust as a median to
    the outliers, and unlike the median of levels of 8-bit pixels not stuck on a few values."""
    low, high = np.percentile(values, (25.0, 75.0))
    middle = values[(values >= low) & (values <= high)]
    return float(middle.mean())


def _peak_offset(below: float, peak: float, above: float) -> float:
    """Sub-bin position of a peak from its two neighbours (parabola through three points)."""
    curvature = below - 2.0 * peak + above
    if curvature >= 0.0:
        return 0.0
    return float(np.clip(0.5 * (below - above) / curvature, -0.5, 0.5))


def _climb(surface: np.ndarray, start) -> tuple:
    """The local maximum of ``surface`` reached uphill from ``start`` (row, column): the
    prior only chooses between peaks, it does not move one."""
    row, column = int(start[0]), int(start[1])
    while True:
        top = surface[max(row - 1, 0):row + 2, max(column - 1, 0):column + 2]
        step_row, step_column = np.unravel_index(int(np.argmax(top)), top.shape)
        best_row, best_column = max(row - 1, 0) + step_row, max(column - 1, 0) + step_column
        if surface[best_row, best_column] <= surface[row, column]:
            return row, column
        row, column = best_row, best_column


def _correlation(current: np.ndarray, model: np.ndarray, limit: int) -> tuple:
    """(``current`` padded by ``limit`` bins, the cross-correlation of ``current`` shifted by
    every shift within ``limit`` bins with ``model``: rows log B/G, columns log R/G, the middle
    being no shift)."""
    padded = cv2.copyMakeBorder(current, limit, limit, limit, limit, cv2.BORDER_CONSTANT,
                                value=0.0)
    return padded, cv2.matchTemplate(padded, model, cv2.TM_CCORR)


def _best_shift(surfaces: tuple, model: np.ndarray, limit: int, reach: int, centre,
                own_peak: bool):
    """(shift (log R/G, log B/G) that lays a histogram on ``model`` best within ``reach`` bins
    of ``centre`` (bins) and ``limit`` bins of none, preferring of equal fits the one nearer
    none; the mass they share there), or None when ``own_peak`` and the best fit lies on the
    edge of the reach (the fit would go on beyond it). ``surfaces`` is :func:`_correlation`'s
    (padded histogram, correlation) of it with ``model`` within ``limit``."""
    padded, correlation = surfaces
    shifts = np.arange(-limit, limit + 1)
    near_column = np.abs(shifts - centre[0]) <= reach
    near_row = np.abs(shifts - centre[1]) <= reach
    window = near_row[:, None] & near_column[None, :]
    prior = np.exp(-0.5 * (shifts / (0.5 * limit)) ** 2)
    weighted = np.where(window, correlation * prior[:, None] * prior[None, :], -1.0)
    row, column = _climb(np.where(window, correlation, -1.0),
                         np.unravel_index(int(np.argmax(weighted)), weighted.shape))
    if own_peak and (abs(shifts[column] - centre[0]) == reach
                     or abs(shifts[row] - centre[1]) == reach):
        return None
    size = model.shape[0]
    overlap = float(np.minimum(padded[row:row + size, column:column + size], model).sum())
    column_offset = (_peak_offset(correlation[row, column - 1], correlation[row, column],
                                  correlation[row, column + 1])
                     if 0 < column < 2 * limit else 0.0)
    row_offset = (_peak_offset(correlation[row - 1, column], correlation[row, column],
                               correlation[row + 1, column])
                  if 0 < row < 2 * limit else 0.0)
    shift = np.array((shifts[column] + column_offset, shifts[row] + row_offset)) * CHROMA_BIN
    return shift, overlap


class WhiteBalanceLock:
    """Channel gains that undo the white-balance drift seen on the reference pixels.

    ``shift_log`` is (log R/G, log B/G) now minus when learned; :meth:`gains` undo it.
    """

    def __init__(self, max_shift_log: float):
        self.max_shift_log = max_shift_log
        self.reset()

    def reset(self):
        """Forget the reference chromaticity: the next frame is learned afresh."""
        self.model = None
        self.shift_log = np.zeros(2)
        self.last_frame = None

    def _limit_bins(self) -> int:
        return max(1, int(np.floor(self.max_shift_log / CHROMA_BIN)))

    def track(self, bgr_pixels: np.ndarray, image: Optional[np.ndarray] = None,
              floor_share: Optional[Callable[[np.ndarray], float]] = None):
        """Follow the drift to this frame's floor pixels (Nx3 uint8 BGR, not corrected); with
        ``image`` (the whole frame, HxWx3 uint8 BGR, not corrected) the shift moves by the step
        between frames where the floor fits it at least as well, and the floor corrects it only
        by a peak of its own near it; with ``floor_share`` (a shift (log R/G, log B/G) -> the
        share 0-1 of the frame that is floor with it undone) only where that share grows by
        MIN_FLOOR_GAIN."""
        if self.max_shift_log <= 0.0:
            return
        step = self._frame_step(image) if image is not None else None
        current = log_chromaticity_histogram(bgr_pixels)
        if self.model is None:
            self.model = current
            return
        if current is None:
            if step is not None:
                self.shift_log = self._bounded(self.shift_log + step)
            else:
                self.shift_log *= 1.0 - RELAX_RATE
            return
        surfaces = _correlation(current, self.model, self._limit_bins())
        if image is None:
            if not self._measure(surfaces, STEP_BINS, False):
                self.shift_log *= 1.0 - RELAX_RATE
            return
        if step is not None:
            predicted = self._bounded(self.shift_log + step)
            if self._fit(surfaces[1], predicted) >= self._fit(surfaces[1], self.shift_log):
                self.shift_log = predicted
        predicted = self.shift_log.copy()
        if (self._measure(surfaces, ANCHOR_BINS, True) and floor_share is not None
                and np.any(self.shift_log != predicted)
                and floor_share(self.shift_log) < floor_share(predicted) + MIN_FLOOR_GAIN):
            self.shift_log = predicted

    def _bounded(self, shift_log: np.ndarray) -> np.ndarray:
        return np.clip(shift_log, -self.max_shift_log, self.max_shift_log)

    def _fit(self, correlation: np.ndarray, shift_log: np.ndarray) -> float:
        """How well the floor's histogram shifted back by ``shift_log`` lies on the model: its
        ``correlation`` (see :func:`_correlation`) at the nearest bin."""
        limit = self._limit_bins()
        column, row = np.clip(np.rint(shift_log / CHROMA_BIN).astype(int), -limit, limit) + limit
        return float(correlation[row, column])

    def _frame_step(self, image: np.ndarray) -> Optional[np.ndarray]:
        """The log-chromaticity step (log R/G, log B/G) from the last frame to ``image``: the
        mean of the middle half of every second pixel's chromaticity changes, over the pixels
        usable in both frames that show the same surface in both (see SAME_SURFACE_LOG); None
        when too few pixels are usable, too few show the same surface (another scene) or the
        step exceeds FRAME_STEP_BINS."""
        # Channels as flat arrays of their own: reductions across an interleaved pixel's
        # channels, and indexing rows of an N x 3 array, are several times slower in numpy.
        channels = [channel.ravel() for channel in cv2.split(np.ascontiguousarray(
            image[::2, ::2]))]
        brightest = np.maximum(np.maximum(channels[0], channels[1]), channels[2])
        darkest = np.minimum(np.minimum(channels[0], channels[1]), channels[2])
        usable = (brightest >= MIN_VALUE) & (brightest < MAX_VALUE) & (darkest > 0)
        blue, green, red = (LOG_LEVEL.take(channel) for channel in channels)
        current = (red - green, blue - green, green), usable
        last, self.last_frame = self.last_frame, current
        if last is None or last[1].shape != usable.shape:
            return None
        both = usable & last[1]
        if np.count_nonzero(both) < MIN_PIXELS:
            return None
        change = [now[both] - before[both] for now, before in zip(current[0], last[0])]
        brightness = change[2] - np.median(change[2])
        same = np.abs(brightness) <= SAME_SURFACE_LOG
        if np.count_nonzero(same) < max(MIN_PIXELS, MIN_SAME_SURFACE * change[2].size):
            return None
        step = np.array([_middle_mean(change[axis][same]) for axis in (0, 1)])
        if np.any(np.abs(step) > FRAME_STEP_BINS * CHROMA_BIN):
            return None
        return step.astype(float)

    def _measure(self, surfaces: tuple, reach: int, own_peak: bool) -> bool:
        """Move the shift to where the floor's histogram (``surfaces``: its
        :func:`_correlation` with the model) lies best on the model, within ``reach`` bins of
        the shift now and, of equal fits, nearer none; with ``own_peak`` only to a peak inside
        that reach. False when it fits nowhere near."""
        previous = np.rint(self.shift_log / CHROMA_BIN).astype(int)
        found = _best_shift(surfaces, self.model, self._limit_bins(), reach, previous, own_peak)
        if found is None or found[1] < MIN_OVERLAP:
            return False
        self.shift_log = self._bounded(found[0])
        return True

    def learn(self, bgr_pixels: np.ndarray, rate: float):
        """Blend reference pixels known to be floor, already corrected, into the model."""
        if self.model is None or rate <= 0.0:
            return
        current = log_chromaticity_histogram(bgr_pixels)
        if current is not None:
            self.model = (1.0 - rate) * self.model + rate * current

    def gains(self) -> Optional[np.ndarray]:
        """Per-channel gains (B, G, R) that undo the drift; None while there is none to undo
        (under half a bin either way)."""
        return shift_gains(self.shift_log)

    def correct(self, bgr: np.ndarray) -> np.ndarray:
        """``bgr`` with the drift undone (the same array when there is none)."""
        return undo_shift(bgr, self.shift_log)


def shift_gains(shift_log: np.ndarray) -> Optional[np.ndarray]:
    """Per-channel gains (B, G, R) that undo a log-chromaticity shift (log R/G, log B/G); None
    under half a bin either way."""
    if np.all(np.abs(shift_log) < 0.5 * CHROMA_BIN):
        return None
    return np.array((np.exp(-shift_log[1]), 1.0, np.exp(-shift_log[0])))


def undo_shift(bgr: np.ndarray, shift_log: np.ndarray) -> np.ndarray:
    """An HxWx3 uint8 BGR image with a log-chromaticity shift undone (the same array when it is
    under half a bin)."""
    gains = shift_gains(shift_log)
    if gains is None:
        return bgr
    levels = np.arange(256, dtype=np.float64)[:, None] * gains[None, :]
    table = np.clip(np.rint(levels), 0, 255).astype(np.uint8).reshape(256, 1, 3)
    return cv2.LUT(bgr, table)
