"""A lens's vignetting, estimated from the images themselves, and undone.

Most small cameras lose light toward the image corners: a uniform floor is a third darker there
than in the middle. The floor model learns the brightness of the reference area at the bottom
of the image, corners included, so without a correction it learns every brightness between the
floor's own and two thirds of it, and a darker wall or box of the floor's hue passes as floor.

The fall-off is a property of the lens, the same in every frame: gain(rho) = 1 - s * rho^2,
rho the distance from the image centre over the half diagonal (the first term of the usual
even polynomial; s = 0.4 loses 40 % in the corners). Every surface of uniform brightness in
view (a floor tile, a wall, a box's side) shows it as a gradient of log brightness pointing to
the centre, d log gain / d rho = -2 s rho / (1 - s rho^2), whatever the surface's own
brightness. :class:`VignettingEstimate` fits s by least squares to the radial gradient of a
quarter-size log-brightness image over the pixels that are neither edges nor clipped nor dark,
summed over frames with exponential forgetting (scene gradients such as a lamp's fall-off
differ from frame to frame and average out; the lens's does not), and undoes it.
"""
from typing import Optional

import cv2
import numpy as np

SCALE = 4
"""The fit runs on an image this many times smaller (area averaging keeps sensor noise and
JPEG blocks out of the gradients)."""
MAX_EDGE_LOG = 0.05
"""Gradient of log brightness (per small-image pixel) above which a pixel is an edge, not a
uniform surface; a 40 % fall-off is 0.03 in the corners of a 320 x 240 image."""
MIN_LEVEL = 30
MAX_LEVEL = 245
"""Small-image pixels outside these grey levels are too dark for a reliable log, or clipped."""
FORGET_RATE = 0.02
"""Weight of each frame's sums in the estimate (about 50 frames of memory)."""
MIN_UNDONE = 0.05
"""An estimate below this is left alone: the floor model's bins tolerate a 5 % fall-off, and
a camera without vignetting keeps its images unchanged."""
MAX_STRENGTH = 0.7


class VignettingEstimate:
    """Online estimate of the fall-off strength s (see the module docstring) of one camera.

    Not thread-safe. ``max_strength`` bounds s (0 turns the estimate and the correction off).
    """

    def __init__(self, max_strength: float = MAX_STRENGTH):
        self.max_strength = max_strength
        self._shape = None
        self.reset()

    def reset(self):
        """Forget the estimate (a new camera)."""
        self.strength = 0.0
        self._numerator = 0.0
        self._denominator = 0.0
        self._gain_key = None

    def _prepare(self, shape):
        if shape[:2] == self._shape:
            return
        height, width = shape[:2]
        small_h, small_w = max(2, height // SCALE), max(2, width // SCALE)
        # Small-image pixel centres in full-image pixels, relative to the centre.
        xs = (np.arange(small_w) + 0.5) * width / small_w - width / 2.0
        ys = (np.arange(small_h) + 0.5) * height / small_h - height / 2.0
        half_diagonal = np.hypot(width, height) / 2.0
        x, y = np.meshgrid(xs / half_diagonal, ys / half_diagonal)
        self._rho = np.hypot(x, y)
        # Unit radial direction, and d rho per small-image pixel.
        with np.errstate(invalid='ignore', divide='ignore'):
            self._radial_x = np.where(self._rho > 0, x / self._rho, 0.0)
            self._radial_y = np.where(self._rho > 0, y / self._rho, 0.0)
        self._rho_per_px = SCALE / half_diagonal
        full_x, full_y = np.meshgrid(np.arange(width) + 0.5 - width / 2.0,
                                     np.arange(height) + 0.5 - height / 2.0)
        self._rho2_full = ((full_x ** 2 + full_y ** 2) / half_diagonal ** 2).astype(np.float32)
        self._shape = shape[:2]
        self.reset()

    def observe(self, bgr: np.ndarray):
        """Add a frame's radial gradients on its uniform surfaces to the estimate."""
        if self.max_strength <= 0.0:
            return
        self._prepare(bgr.shape)
        grey = cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY)
        small = cv2.resize(grey, self._rho.shape[::-1], interpolation=cv2.INTER_AREA)
        usable = (small >= MIN_LEVEL) & (small <= MAX_LEVEL)
        log_level = np.log(np.maximum(small, 1).astype(np.float32))
        gradient_x = cv2.Sobel(log_level, cv2.CV_32F, 1, 0, ksize=3) / 8.0
        gradient_y = cv2.Sobel(log_level, cv2.CV_32F, 0, 1, ksize=3) / 8.0
        usable &= cv2.erode(usable.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
        usable &= np.hypot(gradient_x, gradient_y) < MAX_EDGE_LOG
        usable[0, :] = usable[-1, :] = usable[:, 0] = usable[:, -1] = False
        if np.count_nonzero(usable) < 50:
            return
        radial = ((gradient_x * self._radial_x + gradient_y * self._radial_y)
                  / self._rho_per_px)[usable]
        rho = self._rho[usable]
        # radial = -2 s rho / (1 - s rho^2)  =>  radial (1 - s0 rho^2) = -2 s rho, with s0 the
        # estimate so far (the fit converges over frames).
        numerator = float(np.sum(-radial * (1.0 - self.strength * rho ** 2) * rho)) / 2.0
        denominator = float(np.sum(rho ** 2))
        self._numerator = (1.0 - FORGET_RATE) * self._numerator + FORGET_RATE * numerator
        self._denominator = (1.0 - FORGET_RATE) * self._denominator + FORGET_RATE * denominator
        if self._denominator > 0.0:
            self.strength = min(max(self._numerator / self._denominator, 0.0),
                                self.max_strength)

    def correct(self, bgr: np.ndarray) -> np.ndarray:
        """``bgr`` with the fall-off undone (the same array while the estimate is below
        MIN_UNDONE)."""
        if self.strength < MIN_UNDONE or self._shape != bgr.shape[:2]:
            return bgr
        key = round(self.strength, 3)
        if key != self._gain_key:
            self._inverse_gain = cv2.merge([1.0 / (1.0 - key * self._rho2_full)] * 3)
            self._gain_key = key
        return cv2.multiply(bgr, self._inverse_gain, dtype=cv2.CV_8U)

    def gain(self) -> Optional[np.ndarray]:
        """The current fall-off per full-image pixel (float32), or None before any frame."""
        if self._shape is None:
            return None
        return 1.0 - self.strength * self._rho2_full
