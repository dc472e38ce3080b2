"""Red can detection in one BGR image: HSV red mask, clean-up, largest blob, moments, edges.

Hue is in OpenCV units (0-179, degrees / 2). Red straddles hue 0, so the hue range wraps:
``hue_min > hue_max`` means hue >= hue_min OR hue <= hue_max (two ranges OR-ed), as in
opencv_apps' hsv_color_filter. The defaults are chosen so that red objects from pure red to
crimson (hue ~168-179 and 0-6) are found under varied lighting while red-orange and orange
(hue 7 and up: orange overalls, reddish-brown fur, wood, skin in warm light), brown,
pink-ish walls, magenta and grey are not; the saturation minimum rejects pale skin and pink.
"""
from dataclasses import dataclass
from typing import Optional

import cv2
import numpy as np

from can_seeker.params import Param

EDGE_METHODS = ('canny', 'sobel', 'laplacian')

# Thresholds of the detector; all of them are tunable live with dynamic_reconfigure.
DETECTOR_PARAMS = (
    Param('hue_min', 168, 'lower hue bound of red (OpenCV hue units 0-179 = degrees/2); '
          'hue_min > hue_max wraps around 0', 0, 179),
    Param('hue_max', 6, 'upper hue bound of red (OpenCV hue units 0-179 = degrees/2)', 0, 179),
    Param('saturation_min', 130, 'minimum HSV saturation of a red pixel (0-255)', 0, 255),
    Param('value_min', 50, 'minimum HSV value (brightness) of a red pixel (0-255)', 0, 255),
    Param('min_area_fraction', 0.0005, 'smallest blob accepted as the can, as a fraction of '
          'the image area (1)', 0.0, 1.0),
    Param('open_kernel_px', 3, 'side of the opening kernel that removes red speckles (px, '
          '1 = off)', 1, 31),
    Param('close_kernel_px', 5, 'side of the closing kernel that fills highlights and '
          'holes in the blob (px, 1 = off)', 1, 31),
    Param('edge_method', 'canny', 'edge detector of the ~edges image: canny, sobel or '
          'laplacian', choices=EDGE_METHODS),
    Param('canny_low', 50, 'Canny hysteresis low threshold (grey levels)', 0, 1000),
    Param('canny_high', 150, 'Canny hysteresis high threshold (grey levels)', 0, 1000),
)


@dataclass(frozen=True)
class DetectorSettings:
    """Validated thresholds of :class:`RedCanDetector` (see DETECTOR_PARAMS for units)."""

    hue_min: int
    hue_max: int
    saturation_min: int
    value_min: int
    min_area_fraction: float
    open_kernel_px: int
    close_kernel_px: int
    edge_method: str
    canny_low: int
    canny_high: int

    @classmethod
    def defaults(cls):
        """Settings at the DETECTOR_PARAMS defaults."""
        return cls(**{spec.name: spec.default for spec in DETECTOR_PARAMS})

    @classmethod
    def from_values(cls, values):
        """Settings from any object with one attribute per DETECTOR_PARAMS name."""
        return cls(**{spec.name: getattr(values, spec.name) for spec in DETECTOR_PARAMS})


@dataclass(frozen=True)
class Blob:
    """The largest red blob: centroid from its image moments (px), area (px^2), bbox (px).

    The bounding box is inclusive of ``x``/``y`` and ``width``/``height`` pixels wide/high.
    """

    centroid_x: float
    centroid_y: float
    area: float
    x: int
    y: int
    width: int
    height: int


@dataclass
class VisionResult:
    """One frame's output. ``mask``/``edges`` are the detector's buffers: valid until the next
    call of :meth:`RedCanDetector.detect` (copy them to keep them)."""

    blob: Optional[Blob]
    mask: np.ndarray
    edges: Optional[np.ndarray]

    @property
    def found(self) -> bool:
        return self.blob is not None


def centroid_from_moments(moments):
    """(x, y) centroid of image moments, or None when the region is empty (m00 == 0)."""
    m00 = moments['m00']
    if m00 == 0:
        return None
    return moments['m10'] / m00, moments['m01'] / m00


def _kernel(side_px):
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (side_px, side_px)) if side_px > 1 else None


class RedCanDetector:
    """Finds the largest red blob in BGR images; reuses its buffers while the size is unchanged."""

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
        self._config = (settings, _kernel(settings.open_kernel_px),
                        _kernel(settings.close_kernel_px))

    def _buffers(self, shape):
        if shape != self._shape:
            height, width = shape[:2]
            self._hsv = np.empty((height, width, 3), np.uint8)
            self._mask = np.empty((height, width), np.uint8)
            self._wrap_mask = np.empty((height, width), np.uint8)
            self._clean_mask = np.empty((height, width), np.uint8)
            self._grey = np.empty((height, width), np.uint8)
            self._edges = np.empty((height, width), np.uint8)
            self._shape = shape

    def red_mask(self, bgr: np.ndarray, settings: DetectorSettings) -> np.ndarray:
        """255 where a pixel is red (wrapped hue range, saturation and value minima), else 0."""
        self._buffers(bgr.shape)
        cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV, dst=self._hsv)
        low_sv = (settings.saturation_min, settings.value_min)
        if settings.hue_min > settings.hue_max:
            cv2.inRange(self._hsv, (settings.hue_min,) + low_sv, (179, 255, 255), dst=self._mask)
            cv2.inRange(self._hsv, (0,) + low_sv, (settings.hue_max, 255, 255), dst=self._wrap_mask)
            cv2.bitwise_or(self._mask, self._wrap_mask, dst=self._mask)
        else:
            cv2.inRange(self._hsv, (settings.hue_min,) + low_sv, (settings.hue_max, 255, 255),
                        dst=self._mask)
        return self._mask

    def clean_mask(self, mask: np.ndarray, open_kernel, close_kernel) -> np.ndarray:
        """Opening removes speckles, closing fills highlights and holes inside the blob
        (a kernel of None skips that step)."""
        cleaned = mask
        if open_kernel is not None:
            cleaned = cv2.morphologyEx(cleaned, cv2.MORPH_OPEN, open_kernel, dst=self._clean_mask)
        if close_kernel is not None:
            cleaned = cv2.morphologyEx(cleaned, cv2.MORPH_CLOSE, close_kernel, dst=self._clean_mask)
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
        """Largest red blob of a BGR uint8 image (None when there is none big enough)."""
        settings, open_kernel, close_kernel = self._config
        if bgr.size == 0:
            empty = np.zeros(bgr.shape[:2], np.uint8)
            return VisionResult(None, empty, empty.copy() if want_edges else None)
        mask = self.clean_mask(self.red_mask(bgr, settings), open_kernel, close_kernel)
        min_area_px = max(1.0, settings.min_area_fraction * mask.shape[0] * mask.shape[1])
        blob = largest_blob(mask, min_area_px)
        edges = self.edges(bgr, settings) if want_edges else None
        return VisionResult(blob, mask, edges)


def largest_blob(mask: np.ndarray, min_area_px: float) -> Optional[Blob]:
    """The largest 8-connected region of a binary mask, or None if it is below ``min_area_px``.

    The region is picked by the area inside its outer contour (cheap on a cleaned mask); its
    area and centroid come from the image moments of its own pixels, holes excluded.
    """
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    if not contours:
        return None
    contour = max(contours, key=cv2.contourArea)
    x, y, width, height = cv2.boundingRect(contour)
    region = np.zeros((height, width), np.uint8)
    cv2.drawContours(region, [contour], -1, 1, cv2.FILLED, offset=(-x, -y))
    cv2.bitwise_and(region, mask[y:y + height, x:x + width], dst=region)
    moments = cv2.moments(region, binaryImage=True)
    centroid = centroid_from_moments(moments)
    if centroid is None or moments['m00'] < min_area_px:
        return None
    return Blob(x + centroid[0], y + centroid[1], float(moments['m00']), x, y, width, height)


def blob_contour(mask: np.ndarray, blob: Blob):
    """Outer contour of the blob (OpenCV point array in image coordinates) for drawing."""
    region = mask[blob.y:blob.y + blob.height, blob.x:blob.x + blob.width]
    contours, _ = cv2.findContours(region, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE,
                                   offset=(blob.x, blob.y))
    return max(contours, key=cv2.contourArea) if contours else None


MASK_TINT_BGR = (0, 255, 0)
CONTOUR_BGR = (0, 255, 255)
BOX_BGR = (255, 128, 0)
CENTROID_BGR = (0, 255, 0)
TEXT_BGR = (255, 255, 255)


def draw_annotation(bgr: np.ndarray, result: VisionResult, range_m: float) -> np.ndarray:
    """A new BGR image: the input with the mask tinted, the blob's contour, box, centroid and
    the range written on it ("range ? m" when unknown)."""
    annotated = bgr.copy()
    tinted = annotated.copy()
    tinted[result.mask > 0] = MASK_TINT_BGR
    cv2.addWeighted(tinted, 0.35, annotated, 0.65, 0, dst=annotated)
    scale = max(0.35, annotated.shape[0] / 480.0)
    thickness = max(1, int(round(scale * 2)))
    if result.blob is None:
        label = 'no red can'
    else:
        blob = result.blob
        contour = blob_contour(result.mask, blob)
        if contour is not None:
            cv2.drawContours(annotated, [contour], -1, CONTOUR_BGR, thickness)
        cv2.rectangle(annotated, (blob.x, blob.y),
                      (blob.x + blob.width - 1, blob.y + blob.height - 1), BOX_BGR, thickness)
        centre = (int(round(blob.centroid_x)), int(round(blob.centroid_y)))
        cv2.circle(annotated, centre, max(2, 3 * thickness), CENTROID_BGR, -1)
        label = 'range ? m' if not np.isfinite(range_m) else 'range %.2f m' % range_m
    origin = (int(8 * scale), int(24 * scale))
    cv2.putText(annotated, label, origin, cv2.FONT_HERSHEY_SIMPLEX, 0.7 * scale, (0, 0, 0),
                thickness + 2, cv2.LINE_AA)
    cv2.putText(annotated, label, origin, cv2.FONT_HERSHEY_SIMPLEX, 0.7 * scale, TEXT_BGR,
                thickness, cv2.LINE_AA)
    return annotated
