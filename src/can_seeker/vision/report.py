"""The image_converter's parameters and its per-frame answer: red blobs + camera geometry ->
report with the most can-like blob and the confidence that it is the can.

Confidence (0-1) = the blob's shape score (detector.shape_score) x its geometry score: when
the camera pose and intrinsics are known and the blob's floor range is, the box a 66 mm x
122 mm can would fill at that range and bearing is compared with the blob's box (sides cut by
the image edge are not compared); the score is 1 while both sizes are within
``size_tolerance`` of the can's, falling to 0 at twice that. Without geometry it is 1.

The shape score takes a can's silhouette for convex, which its red side is only when the
camera looks at it from the side: from above, the lid (not red) cuts an ellipse into the top
of the red, up to a third of its height close below a steep camera, and the red's solidity
and fill fall with it (0.85 and 0.74 at 0.34 m below a camera 0.33 m up pitched 35 deg down,
where a silhouette scores 0.27, below the controller's threshold). With the floor
range known, a whole blob's solidity and fill are therefore judged against those of the red
side an upright can shows at that range and bearing (its rims projected, the lid cut out while
the camera is above it; see :func:`can_side_measures`).

Shared by the ROS node and the offline bag tool so both give the same numbers.
"""
import math
from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import cv2
import numpy as np

from can_seeker.camera_geometry import (CAMERA_INFO_PARAMS, can_image_box, can_range_bearing,
                                        can_rims_px)
from can_seeker.can_size import CAN_COLOUR_BOTTOM_M, CAN_DIAMETER_M, CAN_HEIGHT_M
from can_seeker.frames import BASE_FRAME
from can_seeker.params import Param
from can_seeker.vision.detector import (DETECTOR_PARAMS, Blob, convexity_score,
                                        solidity_and_fill)
from can_seeker.vision.image_decode import IMAGE_TRANSPORT_PARAMS

SIZE_PREFERENCE_EXPONENT = 0.25
"""Candidates are ranked by confidence x (area / largest area) ** this: among equally
can-like blobs the larger wins, but a can-like blob beats a larger shapeless one."""

SIZE_TOLERANCE = 0.3
"""Size check: confidence is kept while the blob's width and height are within this fraction
of the can's at its floor range, and falls to 0 at twice it: the range from the floor, the
blob's outline and a tilted camera each err by a few per cent."""
WINDOW_WIDTH_PX = 640
"""Width of each ~show window: images are scaled to it, keeping their aspect ratio."""

REPORT_PARAMS = DETECTOR_PARAMS + (BASE_FRAME,) + CAMERA_INFO_PARAMS + (
    Param('show', False, 'open OpenCV windows (origin, result, edges); only when the display '
          'can be opened, headless with a warning otherwise'),
)
"""What the report of a frame and its windows take (the offline bag tool reads them too)."""
PARAMS = REPORT_PARAMS + IMAGE_TRANSPORT_PARAMS
"""Every parameter of the image_converter node."""


@dataclass(frozen=True)
class CanModel:
    """Size of the can (m), the relative size error the geometry check tolerates (1) and the
    height where its colour begins (m); the nodes' can is the defaults
    (:mod:`can_seeker.can_size`)."""

    diameter_m: float = CAN_DIAMETER_M
    height_m: float = CAN_HEIGHT_M
    size_tolerance: float = SIZE_TOLERANCE
    colour_bottom_m: float = CAN_COLOUR_BOTTOM_M


@dataclass(frozen=True)
class CanReport:
    """What one frame says about the can: the fields of can_seeker/CanDetection.

    Pixel values are 0 when not found; range (m) and bearing (rad, left positive) are NaN when
    not found or when the camera geometry is unknown. ``range_method`` is 'floor', 'width' or
    'none' (see camera_geometry.can_range_bearing). ``confidence`` (0-1) is that of the blob
    reported, ``confidences`` one per candidate, ``chosen`` the reported candidate's index.
    """

    found: bool
    centroid_x: float
    centroid_y: float
    area: float
    bbox: tuple
    image_width: int
    image_height: int
    range_m: float
    bearing_rad: float
    range_method: str
    confidence: float = 0.0
    confidences: Tuple[float, ...] = ()
    chosen: Optional[int] = None


def geometry_score(blob: Blob, pose, intrinsics, range_m: float, bearing: float,
                   method: str, can: CanModel) -> float:
    """1 when the blob has the size of the can at its floor range (within the tolerance),
    falling to 0 at twice the tolerance; 1 when that cannot be checked (no geometry, or a
    range from the width itself)."""
    if method != 'floor' or pose is None or intrinsics is None:
        return 1.0
    expected = can_image_box(pose, intrinsics, range_m, bearing, can.diameter_m, can.height_m)
    if expected is None:
        return 1.0
    errors = [0.0]
    if 'left' not in blob.cut and 'right' not in blob.cut and expected[0] > 0:
        errors.append(abs(blob.width / expected[0] - 1.0))
    if 'top' not in blob.cut and expected[1] > 0:
        errors.append(abs(blob.height / expected[1] - 1.0))
    error = max(errors)
    tolerance = can.size_tolerance
    return min(1.0, max(0.0, 2.0 - error / tolerance))


def can_side_measures(pose, intrinsics, range_m: float, bearing: float,
                      can: CanModel) -> Optional[Tuple[float, float]]:
    """(solidity, fill) (see :func:`detector.solidity_and_fill`) of the red side of an upright
    can seen at ``range_m`` (to its near surface) and ``bearing`` (rad): the outline of its
    rims, less the lid's ellipse while the camera is above the can, drawn at the image's own
    scale. None when the can is not entirely in front of the camera."""
    rims = can_rims_px(pose, intrinsics, range_m, bearing, can.diameter_m, can.height_m)
    if rims is None:
        return None
    points = np.concatenate(rims)
    origin = np.floor(points.min(axis=0)) - 1.0
    size = np.ceil(points.max(axis=0) - origin).astype(int) + 2
    side = np.zeros((size[1], size[0]), np.uint8)
    cv2.fillPoly(side, [cv2.convexHull(np.rint(points - origin).astype(np.int32))], 1)
    if pose.position[2] > can.height_m:
        cv2.fillPoly(side, [np.rint(rims[1] - origin).astype(np.int32)], 0)
    contours, _ = cv2.findContours(side, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    if not contours:
        return None
    return solidity_and_fill(max(contours, key=cv2.contourArea), float(np.count_nonzero(side)))


def _shape(blob: Blob, pose, intrinsics, range_m: float, bearing: float, method: str,
           can: CanModel) -> float:
    """The blob's shape score with its solidity and fill judged against those of the can's
    red side at its floor range, where the blob is whole and that range is known (see the
    module); a blob they rule out stays ruled out."""
    convexity = convexity_score(blob.solidity, blob.fill)
    if (method != 'floor' or pose is None or intrinsics is None or blob.cut
            or convexity <= 0.0):
        return blob.shape_score
    expected = can_side_measures(pose, intrinsics, range_m, bearing, can)
    if expected is None:
        return blob.shape_score
    return blob.shape_score * convexity_score(min(1.0, blob.solidity / expected[0]),
                                              min(1.0, blob.fill / expected[1])) / convexity


def _measure(blob: Blob, pose, intrinsics, can: CanModel):
    """(confidence, (range_m, bearing_rad, range_method)) of one blob."""
    range_m, bearing, method = can_range_bearing(
        pose, intrinsics, (blob.centroid_x, blob.centroid_y),
        (blob.x, blob.y, blob.width, blob.height), can.diameter_m,
        None if blob.contour is None else blob.contour.reshape(-1, 2), can.colour_bottom_m)
    confidence = (_shape(blob, pose, intrinsics, range_m, bearing, method, can)
                  * geometry_score(blob, pose, intrinsics, range_m, bearing, method, can))
    return confidence, (range_m, bearing, method)


def rank_candidates(candidates: Sequence[Blob], pose, intrinsics, can: CanModel):
    """(index of the most can-like blob, [(confidence, (range_m, bearing_rad, range_method) or
    None when not measured) per blob]) of a frame's red blobs (largest first; empty: index
    None). The decision of image_converter's report: every node that needs "the can" asks
    this."""
    if not candidates:
        return None, []
    largest_area = max(blob.area for blob in candidates)
    measured = []
    for blob in candidates:
        # A shapeless blob has confidence 0 whatever its size: its geometry waits until chosen.
        measured.append(_measure(blob, pose, intrinsics, can) if blob.shape_score > 0.0
                        else (0.0, None))
    chosen = max(range(len(candidates)), key=lambda index: measured[index][0] * (
        candidates[index].area / largest_area) ** SIZE_PREFERENCE_EXPONENT)
    return chosen, measured


def can_report(candidates: Sequence[Blob], image_width: int, image_height: int, pose,
               intrinsics, can: CanModel) -> CanReport:
    """Report of a frame's red blobs (largest first; empty: not found) seen with this camera
    geometry: the most can-like blob, its range, bearing and confidence."""
    chosen, measured = rank_candidates(candidates, pose, intrinsics, can)
    if chosen is None:
        return CanReport(False, 0.0, 0.0, 0.0, (0, 0, 0, 0), image_width, image_height,
                         math.nan, math.nan, 'none')
    blob = candidates[chosen]
    confidence, geometry = measured[chosen]
    range_m, bearing, method = geometry if geometry is not None else _measure(
        blob, pose, intrinsics, can)[1]
    return CanReport(True, blob.centroid_x, blob.centroid_y, blob.area,
                     (blob.x, blob.y, blob.width, blob.height), image_width, image_height,
                     range_m, bearing, method, confidence,
                     tuple(entry[0] for entry in measured), chosen)
