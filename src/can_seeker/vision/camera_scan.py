"""Camera obstacle scan: the floor/obstacle mask of one image -> a planar laser scan.

For every image column the lowest obstacle pixel (scanning up from the bottom through floor)
marks where an obstacle stands on the floor; the floor ray through that pixel's lower edge
gives the point, binned by its angle about the scan frame's origin (a frame on the floor, z up,
e.g. base_link), each bin keeping its nearest point, as depthimage_to_laserscan does.

Conventions (REP-117, REP-103): ranges are horizontal distances (m) from the scan frame's origin
to the obstacle's base, angles increase to the left. A scan vouches for free floor only where
the image shows it: range_min is the nearest floor in view, range_max the range that vouches
for the most floor (capped by ``max_range``), +inf means the image shows the floor free along
the ray from range_min to range_max (within :data:`FREE_SPAN_TOLERANCE_M`), and NaN means not
measured (a ray the image does not show, behind the can, "floor" above the horizon).

Design, reasons and limits: docs/design/floor-and-camera-scan.md.
"""
import dataclasses
import math
from dataclasses import dataclass
from typing import Optional

import cv2
import numpy as np

from can_seeker import lattice
from can_seeker.camera_geometry import (CAMERA_INFO_PARAMS, CameraIntrinsics, CameraPose,
                                        normalized_points)
from can_seeker.frames import BASE_FRAME
from can_seeker.params import Param, defaults
from can_seeker.vision.detector import Blob, RedCanDetector
from can_seeker.vision.floor import FLOOR_PARAMS, FloorClassifier, FloorSettings
from can_seeker.vision.image_decode import IMAGE_TRANSPORT_PARAMS
from can_seeker.vision.report import CanModel, rank_candidates

SCAN_PARAMS = (
    Param('max_range', 4.0, 'obstacles standing farther than this from the scan frame origin '
          'are not reported; also caps the scan\'s range_max (m)', 0.1, 100.0),
    Param('scan_frame', BASE_FRAME.default, 'frame of the scan, on the floor with z up (REP-103); the '
          'camera pose is looked up in TF from it'),
    Param('robot_radius', 0.165, 'radius of the robot body about the scan frame origin (m): '
          'pixels whose ray meets the body\'s top (at ~robot_height) before the floor show the '
          'robot itself, and are neither obstacle nor floor, nor taught to the floor model '
          '(0 = the camera never sees the robot)', 0.0, 5.0),
    Param('robot_height', 0.085, 'height of the top of the robot body above the floor (m), '
          'for ~robot_radius', 0.0, 5.0),
    Param('exclude_can', False, 'leave the red can (the red blob image_converter reports as '
          'the most can-like, with the red stacked on it, its lid, base and band) out of the '
          'scan, for a consumer that does not know its target; can_stopper needs it in: it '
          'leaves out only the can it approaches, and avoids every other red object'),
)
SCAN_DEFAULTS = defaults(SCAN_PARAMS)
PARAMS = FLOOR_PARAMS + SCAN_PARAMS + CAMERA_INFO_PARAMS + IMAGE_TRANSPORT_PARAMS
"""Every parameter of the obstacle_scan node."""
CAN_MARGIN = 0.25
"""The can's box is widened by this fraction of its height up and down (lid, base) and of its
width sideways, so a can's silver rims and white band are not obstacles either."""
HORIZON_MARGIN_RAD = math.radians(0.5)
"""Pixels whose ray points this far above the horizontal or more see no floor: at 0.5 deg below
it, the floor lies 34 m from a camera 0.3 m up, farther than any room's wall."""
FREE_SPAN_TOLERANCE_M = 0.05
"""How much of a ray's span from range_min to range_max the image may miss at either end while
the ray still reads +inf: about a pixel's floor footprint far off, and half the finest map
cell a consumer keeps (can_stopper's observed floor)."""
MIN_SKY_FLOOR_PX = 3
"""Pixels above the horizon taken for floor that make a column unjudged: a few (one or two at
a wall's top edge may be blur), right above the floor the column shows (a wall of the floor's
colour up past the horizon)..."""
MIN_SKY_FLOOR_SHARE = 0.5
"""... or this share of all of them (an obstacle region within such a wall, from its shading,
must not make the rest count for nothing)."""


@dataclass(frozen=True)
class ScanGeometry:
    """Per-pixel floor geometry of one camera pose and image size, in the scan frame.

    ``range_m``/``angle_rad`` (H x W) are the range and angle of the floor point under each
    pixel's lower edge (NaN where the ray misses the floor or is beyond ``range_max``);
    ``edge_angle_rad`` (H x W+1) the angles at the pixels' left/right edges. Scan bins are
    ``angle_min + i * angle_increment`` (rad), ``bins`` of them. ``sky`` (H x W) marks the
    pixels whose ray points at least HORIZON_MARGIN_RAD above the horizontal; ``robot`` (H x W)
    the pixels that show the robot's own body (see :func:`robot_pixels`), out of range.
    ``near_bins`` (bins) marks the bins whose floor the image holds from ``range_min`` on,
    ``free_bins`` those where it holds it up to ``range_max`` too (see the module docstring and
    :func:`vouched_span`).
    """

    range_m: np.ndarray
    angle_rad: np.ndarray
    edge_angle_rad: np.ndarray
    in_range: np.ndarray
    angle_min: float
    angle_increment: float
    bins: int
    range_min: float
    range_max: float
    sky: np.ndarray
    robot: np.ndarray
    near_bins: np.ndarray
    free_bins: np.ndarray

    @property
    def angle_max(self) -> float:
        return self.angle_min + (self.bins - 1) * self.angle_increment


def _rays(pose: CameraPose, intrinsics: CameraIntrinsics, u, v) -> np.ndarray:
    """Ray directions (..., 3) through pixel coordinates (u, v) (px), in the scan frame, the
    lens distortion undone (the tables are built once per pose and intrinsics)."""
    x, y = normalized_points(intrinsics, u, v)
    return np.stack((x, y, np.ones_like(x)), axis=-1) @ pose.rotation.T


def _floor_polar(pose: CameraPose, intrinsics: CameraIntrinsics, u, v, plane_height_m=0.0):
    """(range, angle) arrays of the points where the rays through pixel coordinates (u, v)
    (px) meet the floor, or the level plane ``plane_height_m`` above it (NaN: they do not)."""
    rays = _rays(pose, intrinsics, u, v)
    with np.errstate(divide='ignore', invalid='ignore'):
        scale = np.where(rays[..., 2] < 0.0, (plane_height_m - pose.height_m) / rays[..., 2],
                         np.nan)
    x = pose.position[0] + scale * rays[..., 0]
    y = pose.position[1] + scale * rays[..., 1]
    return np.hypot(x, y), np.arctan2(y, x)


def robot_pixels(pose: CameraPose, intrinsics: CameraIntrinsics, radius_m: float,
                 top_m: float) -> np.ndarray:
    """H x W bool: the pixels whose ray (through the pixel's centre) meets the robot body's
    top, a disc of ``radius_m`` about the scan frame's origin at ``top_m`` above the floor,
    before it reaches the floor. A camera mounted low and pitched steeply sees its robot's
    front there: what it shows is no obstacle and no floor (none from a camera not above the
    top)."""
    u, v = np.meshgrid(np.arange(intrinsics.width, dtype=np.float64),
                       np.arange(intrinsics.height, dtype=np.float64))
    if radius_m <= 0.0 or pose.height_m <= top_m:
        return np.zeros(u.shape, bool)
    with np.errstate(invalid='ignore'):
        return _floor_polar(pose, intrinsics, u, v, top_m)[0] <= radius_m


def border_px(settings: FloorSettings, width: int, height: int) -> int:
    """How many pixels from the image's side and top edges cannot show floor free: an
    obstacle cut by the edge shows only a sliver, which the floor model drops when narrower
    than the regions it keeps (its 3 px opening, and the side of a square of
    ``min_obstacle_area``)."""
    return max(3, int(math.ceil(math.sqrt(settings.min_obstacle_area * width * height))))


def scan_geometry(pose: CameraPose, intrinsics: CameraIntrinsics, max_range_m: float,
                  robot_radius_m: float = 0.0, robot_height_m: float = 0.0,
                  border: int = 0) -> Optional[ScanGeometry]:
    """The floor geometry of the image, or None when the camera sees no floor within range.
    Pixels that show the robot's body (``robot_radius_m``, ``robot_height_m``: see
    :func:`robot_pixels`) measure no floor; those within ``border`` px of the image's side or
    top edge (see :func:`border_px`) vouch for no free floor."""
    if pose is None or intrinsics is None or pose.height_m <= 0.0:
        return None
    width, height = intrinsics.width, intrinsics.height
    columns = np.arange(width, dtype=np.float64)
    rows = np.arange(height, dtype=np.float64) + 0.5
    u, v = np.meshgrid(columns, rows)
    range_m, angle = _floor_polar(pose, intrinsics, u, v)
    edge_u, edge_v = np.meshgrid(np.arange(width + 1, dtype=np.float64) - 0.5, rows)
    edge_range, edge_angle = _floor_polar(pose, intrinsics, edge_u, edge_v)
    robot = robot_pixels(pose, intrinsics, robot_radius_m, robot_height_m)
    in_range = np.isfinite(range_m) & (range_m <= max_range_m) & ~robot
    edge_in_range = np.isfinite(edge_range) & (edge_range <= max_range_m)
    if not in_range.any():
        return None
    edge_angles = edge_angle[edge_in_range]
    angle_min, angle_max = float(edge_angles.min()), float(edge_angles.max())
    # One bin per column at the optical centre: the columns' mean angular width there.
    centre_row = min(height - 1, max(0, int(round(intrinsics.cy))))
    centre_edges = edge_angle[centre_row]
    if np.isfinite(centre_edges).all():
        increment = abs(float(centre_edges[0] - centre_edges[-1])) / width
    else:
        increment = (angle_max - angle_min) / width
    bins = max(1, int(lattice.ceil((angle_max - angle_min) / increment)))
    centre_rays = _rays(pose, intrinsics, u, v - 0.5)
    sky = (centre_rays[..., 2] / np.linalg.norm(centre_rays, axis=-1)
           >= math.sin(HORIZON_MARGIN_RAD))
    geometry = ScanGeometry(np.where(in_range, range_m, np.nan),
                            np.where(in_range, angle, np.nan),
                            np.where(edge_in_range, edge_angle, np.nan), in_range,
                            angle_min + increment / 2.0, increment, bins,
                            float(np.nanmin(range_m[in_range])),
                            float(np.nanmax(range_m[in_range])), sky, robot,
                            np.ones(bins, bool), np.ones(bins, bool))
    inner = np.zeros(in_range.shape, bool)
    inner[border:, border:width - border] = True
    near_m, far_m = bin_floor_spans(geometry, inner)
    with np.errstate(invalid='ignore'):
        near_bins = near_m <= geometry.range_min + FREE_SPAN_TOLERANCE_M
    range_max, free_bins = vouched_span(near_bins, far_m, geometry.range_min)
    return dataclasses.replace(geometry, range_max=range_max or geometry.range_max,
                               near_bins=near_bins, free_bins=free_bins)


def bin_floor_spans(geometry: ScanGeometry, pixels: np.ndarray):
    """(near m, far m) per bin: the nearest and farthest range of the floor in range that the
    ``pixels`` (H x W bool) cover along the bin (each pixel covers the bins between its edges'
    angles, as an obstacle base does in :func:`scan_ranges`); NaN for a bin none covers."""
    rows, columns = np.nonzero(geometry.in_range & pixels)
    first, last, valid = _column_bins(geometry, rows, columns)
    bins, owners = _spread(first, last)
    ranges = geometry.range_m[rows, columns][valid][owners]
    near = np.full(geometry.bins, np.inf)
    far = np.full(geometry.bins, -np.inf)
    np.minimum.at(near, bins, ranges)
    np.maximum.at(far, bins, ranges)
    covered = np.isfinite(near)
    return np.where(covered, near, np.nan), np.where(covered, far, np.nan)


def vouched_span(near_ok: np.ndarray, far_m: np.ndarray, range_min_m: float):
    """(range_max m, free bins) of a scan whose bins see the floor up to ``far_m`` each, from
    range_min where ``near_ok``: the range_max that vouches for the most floor area, counting
    those bins that see up to it within :data:`FREE_SPAN_TOLERANCE_M`, and those bins
    ((None, none) when no bin sees beyond range_min from there)."""
    with np.errstate(invalid='ignore'):
        candidates = np.unique(far_m[near_ok & (far_m > range_min_m)])
        if candidates.size == 0:
            return None, np.zeros(far_m.shape, bool)
        reaching = far_m[None, :] >= candidates[:, None] - FREE_SPAN_TOLERANCE_M
        counts = np.count_nonzero(reaching & near_ok[None, :], axis=1)
    best = int(np.argmax(counts * (candidates ** 2 - range_min_m ** 2)))
    return float(candidates[best]), reaching[best] & near_ok


HIDDEN = -2
"""Obstacle row of a column whose floor right behind the target can is hidden by the can."""
UNJUDGED = -3
"""Obstacle row of a column whose floor the floor model cannot tell from what stands on it."""


def _lowest_rows(candidates: np.ndarray) -> np.ndarray:
    """Per column, the lowest row (px) where ``candidates`` is true, -1 if none."""
    rows = candidates.shape[0] - 1 - np.argmax(candidates[::-1], axis=0)
    return np.where(candidates.any(axis=0), rows, -1)


def lowest_obstacle_rows(obstacles: np.ndarray, in_range: np.ndarray,
                         can_box=None, sky: Optional[np.ndarray] = None) -> np.ndarray:
    """Per column, the lowest row (px) holding an obstacle pixel within range, -1 if none.

    Columns through ``can_box`` (x0, y0, x1, y1, inclusive; its pixels are no obstacle) with
    nothing nearer than the can are HIDDEN when what lies right behind the can is not seen:
    an obstacle touches the box's top, or the box reaches beyond the range or the image top.
    Other columns without an obstacle are UNJUDGED when the floor model takes their ``sky``
    pixels (H x W bool) for floor: at least MIN_SKY_FLOOR_PX of them right above the floor
    (below the column's lowest obstacle pixel), or at least MIN_SKY_FLOOR_PX and
    MIN_SKY_FLOOR_SHARE of them anywhere.
    """
    obstacle = obstacles > 0
    rows = _lowest_rows(obstacle & in_range)
    if sky is not None:
        below = np.arange(obstacle.shape[0])[:, None] > _lowest_rows(obstacle)[None, :]
        floor_sky = np.count_nonzero(sky & ~obstacle, axis=0)
        unjudged = ((np.count_nonzero(sky & below, axis=0) >= MIN_SKY_FLOOR_PX)
                    | ((floor_sky >= MIN_SKY_FLOOR_PX)
                       & (floor_sky >= MIN_SKY_FLOOR_SHARE * np.count_nonzero(sky, axis=0))))
        rows = np.where((rows == -1) & unjudged, UNJUDGED, rows)
    if can_box is not None:
        x0, y0, x1, _ = can_box
        columns = slice(x0, x1 + 1)
        behind = rows[columns] < y0
        if y0 > 0:
            behind &= (obstacles[y0 - 1, columns] > 0) | ~in_range[y0 - 1, columns]
        rows[columns] = np.where(behind, HIDDEN, rows[columns])
    return rows


def _column_bins(geometry: ScanGeometry, rows: np.ndarray, columns: np.ndarray):
    """(first, last) scan bins covered by each column's pixel at ``rows``: the bins between the
    angles of its left and right edges, at least the bin of its centre. Positions in bins are
    snapped to millionths of a bin first (:mod:`can_seeker.lattice`): an edge meant to lie on a
    bin's centre, or a centre on a bin's edge, lies exactly there whatever the last bits of the
    arctan2 that placed it."""
    edges = np.stack((geometry.edge_angle_rad[rows, columns],
                      geometry.edge_angle_rad[rows, columns + 1]))
    centre = (geometry.angle_rad[rows, columns] - geometry.angle_min) / geometry.angle_increment
    with np.errstate(invalid='ignore'):
        first = lattice.ceil((np.nanmin(edges, axis=0) - geometry.angle_min)
                             / geometry.angle_increment)
        last = lattice.floor((np.nanmax(edges, axis=0) - geometry.angle_min)
                             / geometry.angle_increment)
        nearest = np.round(lattice.snapped(centre))
    first = np.where(np.isfinite(first), np.minimum(first, nearest), nearest)
    last = np.where(np.isfinite(last), np.maximum(last, nearest), nearest)
    valid = np.isfinite(nearest)
    first = np.clip(first[valid], 0, geometry.bins - 1).astype(np.int64)
    last = np.clip(last[valid], 0, geometry.bins - 1).astype(np.int64)
    return first, last, valid


def _spread(first, last):
    """(bin, column index) pairs of every bin from first to last of each column."""
    spans = last - first + 1
    owners = np.repeat(np.arange(first.size), spans)
    offsets = np.arange(owners.size) - np.repeat(np.cumsum(spans) - spans, spans)
    return first[owners] + offsets, owners


def scan_ranges(geometry: ScanGeometry, obstacle_rows: np.ndarray,
                can_bottom_row: int = -1) -> np.ndarray:
    """LaserScan ranges (m, float32) from per-column obstacle rows: +inf = no obstacle in view
    up to range_max, NaN = hidden behind the can (HIDDEN columns, seen at ``can_bottom_row``)
    or UNJUDGED (all the bins their floor in range spans), or a bin whose floor the image does
    not hold from range_min to range_max, and nothing else seen in that direction within
    range_max; NaN also where the image does not hold the floor from range_min on.

    Each column's base point covers the bins between the angles of its left and right pixel
    edges (at least the bin of its centre), so a wall gives a scan without gaps.
    """
    ranges = np.full(geometry.bins, np.inf, np.float64)
    unmeasured = np.zeros(geometry.bins, bool)
    hidden = np.flatnonzero(obstacle_rows == HIDDEN)
    if hidden.size and can_bottom_row >= 0:
        first, last, _ = _column_bins(geometry, np.full(hidden.size, can_bottom_row), hidden)
        unmeasured[_spread(first, last)[0]] = True
    unjudged = np.flatnonzero(obstacle_rows == UNJUDGED)
    if unjudged.size:
        in_range = geometry.in_range[:, unjudged]
        seen = in_range.any(axis=0)
        for rows in (_lowest_rows(in_range), np.argmax(in_range, axis=0)):
            first, last, _ = _column_bins(geometry, rows[seen], unjudged[seen])
            unmeasured[_spread(first, last)[0]] = True
    columns = np.flatnonzero(obstacle_rows >= 0)
    if columns.size:
        rows = obstacle_rows[columns]
        first, last, valid = _column_bins(geometry, rows, columns)
        bins, owners = _spread(first, last)
        np.minimum.at(ranges, bins, geometry.range_m[rows, columns][valid][owners])
    ranges[ranges > geometry.range_max] = np.inf
    ranges[~geometry.near_bins] = np.nan
    ranges[(unmeasured | ~geometry.free_bins) & np.isinf(ranges)] = np.nan
    return ranges.astype(np.float32)


def can_box(mask: np.ndarray, blob: Blob):
    """(x0, y0, x1, y1) (px, inclusive) of the target can: the blob's box joined with the red
    regions stacked on it (a band across the can splits its red in two), then widened by
    CAN_MARGIN for the lid and the base."""
    x0, y0 = blob.x, blob.y
    x1, y1 = blob.x + blob.width - 1, blob.y + blob.height - 1
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    for contour in contours:
        x, y, width, height = cv2.boundingRect(contour)
        overlaps_columns = x <= blob.x + blob.width - 1 and x + width - 1 >= blob.x
        gap_rows = max(y - (blob.y + blob.height - 1), blob.y - (y + height - 1))
        if overlaps_columns and gap_rows <= blob.height:
            x0, y0 = min(x0, x), min(y0, y)
            x1, y1 = max(x1, x + width - 1), max(y1, y + height - 1)
    margin_x = int(math.ceil(CAN_MARGIN * (x1 - x0 + 1)))
    margin_y = int(math.ceil(CAN_MARGIN * (y1 - y0 + 1)))
    height, width = mask.shape[:2]
    return (max(0, x0 - margin_x), max(0, y0 - margin_y), min(width - 1, x1 + margin_x),
            min(height - 1, y1 + margin_y))


def can_region(shape, box) -> np.ndarray:
    """mono8 of the image ``shape``, 255 inside ``box`` (x0, y0, x1, y1, inclusive)."""
    region = np.zeros(shape[:2], np.uint8)
    cv2.rectangle(region, box[:2], box[2:], 255, cv2.FILLED)
    return region


@dataclass
class CameraScan:
    """One frame's result: obstacle mask (mono8), per-column base rows (px, -1 = none,
    HIDDEN = behind the can), scan ranges (m; None when the camera geometry is unknown), the
    can region (mono8, or None)."""

    obstacles: np.ndarray
    obstacle_rows: np.ndarray
    ranges: Optional[np.ndarray]
    can: Optional[np.ndarray]


class CameraScanner:
    """BGR images + camera geometry -> obstacle masks and scans; caches the geometry tables."""

    def __init__(self, floor_settings: Optional[FloorSettings] = None, max_range_m: float = 4.0,
                 exclude_can: bool = False, can_detector: Optional[RedCanDetector] = None,
                 can_model: Optional[CanModel] = None,
                 robot_radius_m: float = SCAN_DEFAULTS.robot_radius,
                 robot_height_m: float = SCAN_DEFAULTS.robot_height):
        self.floor = FloorClassifier(floor_settings)
        self.max_range_m = max_range_m
        self.robot_radius_m = robot_radius_m
        self.robot_height_m = robot_height_m
        self.exclude_can = exclude_can
        self.can_detector = can_detector if can_detector is not None else RedCanDetector()
        self.can_model = can_model if can_model is not None else CanModel()
        self._geometry_key = None
        self.geometry = None
        self._robot_mono8 = None

    def geometry_for(self, pose: Optional[CameraPose],
                     intrinsics: Optional[CameraIntrinsics]) -> Optional[ScanGeometry]:
        """The scan geometry of this pose and intrinsics (recomputed only when they change)."""
        key = None if pose is None or intrinsics is None else (
            tuple(pose.position), pose.rotation.tobytes(), intrinsics)
        if key != self._geometry_key:
            self.geometry = None if key is None else scan_geometry(
                pose, intrinsics, self.max_range_m, self.robot_radius_m, self.robot_height_m,
                border_px(self.floor.settings, intrinsics.width, intrinsics.height))
            self._robot_mono8 = (np.where(self.geometry.robot, 255, 0).astype(np.uint8)
                                 if self.geometry is not None and self.geometry.robot.any()
                                 else None)
            self._geometry_key = key
        return self.geometry

    def scan(self, bgr: np.ndarray, pose: Optional[CameraPose],
             intrinsics: Optional[CameraIntrinsics]) -> CameraScan:
        """Classify the frame and, with a known camera geometry of the same size, scan it.
        The pixels that show the robot's body are neither obstacle nor floor."""
        box = None
        if self.exclude_can:
            # The can is the blob image_converter reports: the most can-like, not the largest.
            result = self.can_detector.detect(bgr)
            chosen, _ = rank_candidates(result.candidates, pose, intrinsics, self.can_model)
            if chosen is not None:
                box = can_box(result.mask, result.candidates[chosen])
        can = None if box is None else can_region(bgr.shape, box)
        geometry = self.geometry_for(pose, intrinsics)
        ignore = can
        robot = self._robot_mono8
        if robot is not None and robot.shape == bgr.shape[:2]:
            ignore = robot if can is None else robot | can
        obstacles = self.floor.classify(bgr, ignore)
        if geometry is None or geometry.range_m.shape != obstacles.shape:
            rows = lowest_obstacle_rows(obstacles, np.ones(obstacles.shape, bool), box)
            return CameraScan(obstacles, rows, None, can)
        rows = lowest_obstacle_rows(obstacles, geometry.in_range, box, geometry.sky)
        ranges = scan_ranges(geometry, rows, -1 if box is None else box[3])
        return CameraScan(obstacles, rows, ranges, can)


OBSTACLE_TINT_BGR = (255, 0, 255)
BASE_BGR = (0, 255, 255)
REFERENCE_BGR = (0, 200, 0)
CAN_BGR = (0, 0, 255)


def draw_obstacles(bgr: np.ndarray, result: CameraScan, reference_corners=None) -> np.ndarray:
    """A new BGR image: obstacles tinted magenta with their outlines, each column's obstacle
    base as a yellow dot, the floor reference area in green and the excluded can in red."""
    annotated = bgr.copy()
    tinted = annotated.copy()
    tinted[result.obstacles > 0] = OBSTACLE_TINT_BGR
    cv2.addWeighted(tinted, 0.4, annotated, 0.6, 0, dst=annotated)
    contours, _ = cv2.findContours(result.obstacles, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    cv2.drawContours(annotated, contours, -1, OBSTACLE_TINT_BGR, 1)
    columns = np.flatnonzero(result.obstacle_rows >= 0)
    annotated[result.obstacle_rows[columns], columns] = BASE_BGR
    if reference_corners is not None:
        cv2.polylines(annotated, [reference_corners.reshape(-1, 1, 2)], True, REFERENCE_BGR, 1)
    if result.can is not None:
        can_contours, _ = cv2.findContours(result.can, cv2.RETR_EXTERNAL,
                                           cv2.CHAIN_APPROX_SIMPLE)
        cv2.drawContours(annotated, can_contours, -1, CAN_BGR, 1)
    if result.ranges is not None:
        finite = result.ranges[np.isfinite(result.ranges)]
        label = 'nearest %.2f m' % finite.min() if finite.size else 'no obstacle in view'
        scale = max(0.35, annotated.shape[0] / 480.0)
        cv2.putText(annotated, label, (int(8 * scale), annotated.shape[0] - int(10 * scale)),
                    cv2.FONT_HERSHEY_SIMPLEX, 0.6 * scale, (255, 255, 255), 1, cv2.LINE_AA)
    return annotated

