"""The camera scan's ranges to a wall through a distorting lens, against the truth, without ROS.

The simulator's camera applies plumb_bob distortion (``~camera_k1``, ``~camera_k2``) and
publishes it in camera_info's D. Here the robot stands in front of a room's wall at a few
distances and headings, so the wall's base crosses the whole image width; each rendered frame
(the lens only: no noise, exposure or white balance) goes through the CameraScanner a few times
(the floor model settles) with the intrinsics camera_info gives, either honouring D or, as
before the geometry undid it, K alone. Every scan bin but the EDGE_BINS at either end is
compared with a ray cast just above the floor from the robot's centre in the bin's direction;
the relative error is |scan - truth| / truth over the bins where both are finite.
"""
import argparse
import math
from dataclasses import dataclass
from typing import List, Sequence, Tuple

import numpy as np

from can_seeker.camera_geometry import camera_pose_from_mount, intrinsics_from_camera_info
from can_seeker.camera_mount import CameraMount
from can_seeker.evaluation.floor_bench import EDGE_BINS, TRUTH_BEAMS, TRUTH_HEIGHT_M
from can_seeker.ros.paths import urdf_path
from can_seeker.sim.lidar import LidarSpec
from can_seeker.sim.realism import CameraModel, RealismSpec
from can_seeker.sim.scene import Scene, room_walls
from can_seeker.sim.world import CameraSpec, World
from can_seeker.vision.camera_scan import CameraScanner

ROOM_SIDE_M = 6.0
VIEWS = ((0.6, 0.0), (0.6, 15.0), (0.9, 0.0), (0.9, 15.0), (1.3, 0.0), (1.3, 15.0))
"""(distance m from the robot's centre to the wall's face, heading deg from the wall's normal)."""
SETTLE_FRAMES = 8
"""Scans of each frame before the one judged: the adaptive floor model learns the floor."""


@dataclass(frozen=True)
class ViewError:
    """Relative range errors (1) of one view's judged bins with a finite scan and truth."""

    distance_m: float
    heading_deg: float
    judged_bins: int
    errors: np.ndarray

    @property
    def measured_bins(self) -> int:
        return int(self.errors.size)

    def percentile(self, q: float) -> float:
        return float(np.percentile(self.errors, q)) if self.errors.size else math.nan


def wall_views(urdf: str, k1: float, k2: float, honour_distortion: bool = True,
               mount: CameraMount = CameraMount(0.25, 25.0), size: Tuple[int, int] = (320, 240),
               fov_deg: float = 45.0, views: Sequence[Tuple[float, float]] = VIEWS,
               renderer: str = 'tiny') -> List[ViewError]:
    """The scan's relative range errors to the room's front wall for each of ``views``, with a
    lens of (k1, k2); the scanner's intrinsics keep camera_info's D when
    ``honour_distortion``, else only K (the pinhole geometry of a raw image)."""
    camera = CameraSpec(size[0], size[1], fov_deg, mount)
    rendered = camera.intrinsics
    lens = CameraModel(RealismSpec(camera_k1=k1, camera_k2=k2), rendered)
    distortion = [k1, k2, 0.0, 0.0, 0.0] if honour_distortion else [0.0] * 5
    intrinsics = intrinsics_from_camera_info(size[0], size[1], rendered.K, distortion,
                                             rendered.P, 'plumb_bob')
    pose = camera_pose_from_mount(mount)
    truth_lidar = LidarSpec(TRUTH_BEAMS, 0.17, 8.0, TRUTH_HEIGHT_M)
    half_side = ROOM_SIDE_M / 2.0
    results = []
    with World(urdf, camera, renderer=renderer,
               scene=Scene((-half_side, half_side, -half_side, half_side),
                           room_walls(ROOM_SIDE_M, ROOM_SIDE_M))) as world:
        world.place_can(-half_side + 0.5, -half_side + 0.5)
        for distance_m, heading_deg in views:
            world.reset_robot(half_side - distance_m, 0.0, math.radians(heading_deg))
            frame = lens.apply(world.render('bgr8', None, lens.render_margin_px))
            scanner = CameraScanner()
            for _ in range(SETTLE_FRAMES + 1):
                scan = scanner.scan(frame, pose, intrinsics)
            geometry = scanner.geometry
            beams = world.scan(truth_lidar)
            angles = geometry.angle_min + geometry.angle_increment * np.arange(geometry.bins)
            index = np.round((angles - truth_lidar.angle_min_rad)
                             / truth_lidar.angle_increment_rad).astype(int) % TRUTH_BEAMS
            ranges = scan.ranges[EDGE_BINS:-EDGE_BINS].astype(np.float64)
            truth = beams[index][EDGE_BINS:-EDGE_BINS].astype(np.float64)
            both = np.isfinite(ranges) & np.isfinite(truth)
            results.append(ViewError(distance_m, heading_deg, int(ranges.size),
                                     np.abs(ranges[both] - truth[both]) / truth[both]))
    return results


def table(rows: List[Tuple[str, List[ViewError]]]) -> List[str]:
    """Markdown rows: per geometry and view, the bins measured and the median, 95th percentile
    and largest relative error."""
    lines = ['| geometry | wall at | heading | bins measured | median | p95 | max |',
             '|---|---|---|---|---|---|---|']
    for label, views in rows:
        for view in views:
            lines.append('| %s | %.1f m | %.0f deg | %d / %d | %.2f %% | %.2f %% | %.2f %% |' % (
                label, view.distance_m, view.heading_deg, view.measured_bins, view.judged_bins,
                100 * view.percentile(50), 100 * view.percentile(95),
                100 * view.percentile(100)))
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--k1', type=float, default=-0.25)
    parser.add_argument('--k2', type=float, default=0.06)
    args = parser.parse_args(argv)
    rows = [('K and D', wall_views(urdf_path(), args.k1, args.k2, True)),
            ('K only', wall_views(urdf_path(), args.k1, args.k2, False))]
    print('\n'.join(table(rows)))


if __name__ == '__main__':
    main()
