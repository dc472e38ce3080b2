"""The camera obstacle scan against the truth, frame by frame, without ROS.

A closed-loop trial says whether the robot touched something, but one trial is a chain of
decisions: a change to the floor model moves the path, and the next trial meets other walls.
This benchmark holds the path still. The robot drives a scripted tour of a room (legs to random
points with a clear straight line, some of them close to a wall or an obstacle, each ending in a
turn on the spot to a random heading), driven on the simulator's true pose, so every floor
model sees the same frames. Every camera frame (with the realism preset's camera: noise,
exposure, white balance, vignetting, blur, JPEG) goes through the CameraScanner in order, as
obstacle_scan sees them, and each scan bin is compared with a ray cast just above the floor
from the robot's centre in the bin's direction:

- a **miss** is an obstacle base within ``near_m`` that the scan puts more than the tolerance
  farther away, or not at all: what lets a robot drive into a wall;
- a **phantom** is a bin whose range is more than the tolerance short of the truth (or of the
  farthest floor in view): what keeps a robot from driving where it could;
- with a camera whose white balance drifts, the floor model's white-balance lock is judged on
  the drift each frame was taken with (the camera model's, not an estimate): its RMS error, in
  bins of the lock's histogram (0.02 in log R/G and log B/G), beside the RMS of the drift
  itself (the error of no correction at all).

Frame latency is turned off (the camera and the pose stay matched), and frame drops unless
asked for; everything else comes from the realism preset.
"""
import math
import random
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Callable, Iterator, List, Optional, Tuple

import numpy as np

from can_seeker.camera_geometry import camera_pose_from_mount
from can_seeker.params import defaults
from can_seeker.sim.lidar import LidarSpec
from can_seeker.sim.scene import CAN_RADIUS_M
from can_seeker.sim.simulation import PARAMS, Simulation, camera_spec, checked_config
from can_seeker.sim.world import World
from can_seeker.vision.camera_scan import CameraScanner
from can_seeker.vision.floor import FloorSettings
from can_seeker.vision.white_balance import CHROMA_BIN

ROBOT_RADIUS_M = 0.165
PATH_CLEARANCE_M = 0.21
"""Least distance (m) from the robot's centre to any solid along the tour: 4.5 cm of gap."""
NEAR_TARGET_SHARE = 0.5
"""Share of the legs that end close to a wall or an obstacle (clearance below 0.32 m)."""
CRUISE_MPS = 0.3
TURN_RADPS = 1.0
TRUTH_BEAMS = 2048
"""Ray casts of the truth over 360 deg: 0.18 deg apart, about a camera column at 320 px."""
TRUTH_HEIGHT_M = 0.02
EDGE_BINS = 3
"""Bins this close to either end of the scan are not judged (partial columns)."""


def tolerance_m(range_m):
    """How far a scan range may be off the truth before it counts as a miss or a phantom."""
    return np.maximum(0.1, 0.15 * np.asarray(range_m))


@dataclass
class ScanScore:
    """Counts over judged scan bins (see the module docstring)."""

    near_bins: int = 0
    missed: int = 0
    checked_bins: int = 0
    phantoms: int = 0
    frames: int = 0
    frames_with_miss: int = 0
    wb_frames: int = 0
    wb_error_sq: float = 0.0
    wb_drift_sq: float = 0.0

    def add(self, other: 'ScanScore'):
        for name in vars(self):
            setattr(self, name, getattr(self, name) + getattr(other, name))

    @property
    def miss_rate(self) -> float:
        return self.missed / self.near_bins if self.near_bins else 0.0

    @property
    def phantom_rate(self) -> float:
        return self.phantoms / self.checked_bins if self.checked_bins else 0.0

    @property
    def wb_error_bins(self) -> float:
        """RMS error of the white-balance lock over both log ratios (bins), NaN unjudged."""
        return _rms_bins(self.wb_error_sq, self.wb_frames)

    @property
    def wb_drift_bins(self) -> float:
        """RMS of the true drift over both log ratios (bins), NaN unjudged."""
        return _rms_bins(self.wb_drift_sq, self.wb_frames)


def _rms_bins(sum_sq_log: float, frames: int) -> float:
    if not frames:
        return math.nan
    return math.sqrt(sum_sq_log / (2 * frames)) / CHROMA_BIN


def white_balance_score(lock_shift_log, true_shift_log) -> ScanScore:
    """Judge one frame's white-balance shift (log R/G, log B/G) against the drift the frame was
    taken with."""
    lock, truth = np.asarray(lock_shift_log, float), np.asarray(true_shift_log, float)
    return ScanScore(wb_frames=1, wb_error_sq=float(np.sum((lock - truth) ** 2)),
                     wb_drift_sq=float(np.sum(truth ** 2)))


def score_scan(ranges_m: np.ndarray, truth_m: np.ndarray, range_min_m: float,
               range_max_m: float, near_m: float, min_missed_bins: int = 1) -> ScanScore:
    """Judge one scan (``ranges_m``, NaN/inf allowed) against the true obstacle ranges of the
    same bins (``truth_m``, inf where nothing is hit). Bins whose truth is nearer than the
    scan's nearest visible floor (plus 5 cm) are not judged. A frame counts as one with a miss
    when at least ``min_missed_bins`` bins are missed."""
    ranges = np.asarray(ranges_m, np.float64)[EDGE_BINS:-EDGE_BINS]
    truth = np.asarray(truth_m, np.float64)[EDGE_BINS:-EDGE_BINS]
    visible = truth >= range_min_m + 0.05
    seen = np.where(np.isnan(ranges), np.inf, ranges)
    near = visible & (truth <= near_m)
    missed = near & (seen > truth + tolerance_m(truth))
    expected = np.minimum(truth, range_max_m)
    phantom = visible & np.isfinite(seen) & (seen < expected - tolerance_m(expected))
    missed_count = int(missed.sum())
    return ScanScore(int(near.sum()), missed_count, int(visible.sum()), int(phantom.sum()), 1,
                     int(missed_count >= min_missed_bins))


def clearance_m(scene, x_m, y_m):
    """Distance (m) from floor point(s) to the nearest solid or the can's side."""
    clearance = scene.clearance_m(x_m, y_m)
    if scene.can_xy is None:
        return clearance
    return np.minimum(clearance, np.hypot(np.asarray(x_m) - scene.can_xy[0],
                                          np.asarray(y_m) - scene.can_xy[1]) - CAN_RADIUS_M)


def _segment_clear(scene, start, end, least_m: float) -> bool:
    length = math.hypot(end[0] - start[0], end[1] - start[1])
    steps = max(2, int(length / 0.05) + 1)
    xs = np.linspace(start[0], end[0], steps)
    ys = np.linspace(start[1], end[1], steps)
    return bool(np.all(clearance_m(scene, xs, ys) >= least_m))


def tour_targets(scene, rng: random.Random, start=(0.0, 0.0)) -> Iterator[Tuple[float, float]]:
    """Endless random tour points reachable in a straight line from the previous one, some
    close to a wall or an obstacle (see NEAR_TARGET_SHARE)."""
    x_min, x_max, y_min, y_max = scene.bounds
    here = start
    while True:
        near = rng.random() < NEAR_TARGET_SHARE
        for _ in range(2000):
            point = (rng.uniform(x_min, x_max), rng.uniform(y_min, y_max))
            clearance = float(clearance_m(scene, *point))
            if clearance < PATH_CLEARANCE_M or (near and clearance > 0.32):
                continue
            if math.hypot(point[0] - here[0], point[1] - here[1]) > 0.3 and _segment_clear(
                    scene, here, point, PATH_CLEARANCE_M):
                break
        else:
            point = here
        here = point
        yield point


def _wrap(angle_rad: float) -> float:
    return math.atan2(math.sin(angle_rad), math.cos(angle_rad))


class TourDriver:
    """Twist commands that drive the tour on the true pose: turn toward the next point, drive
    to it, then turn on the spot to a random heading."""

    def __init__(self, scene, rng: random.Random):
        self._targets = tour_targets(scene, rng)
        self._rng = rng
        self._target = next(self._targets)
        self._final_heading = None

    def command(self, x_m: float, y_m: float, yaw_rad: float) -> Tuple[float, float]:
        if self._final_heading is not None:
            error = _wrap(self._final_heading - yaw_rad)
            if abs(error) < 0.05:
                self._final_heading = None
                self._target = next(self._targets)
                return 0.0, 0.0
            return 0.0, math.copysign(min(TURN_RADPS, 2.0 * abs(error)), error)
        dx, dy = self._target[0] - x_m, self._target[1] - y_m
        distance = math.hypot(dx, dy)
        if distance < 0.03:
            self._final_heading = self._rng.uniform(-math.pi, math.pi)
            return 0.0, 0.0
        error = _wrap(math.atan2(dy, dx) - yaw_rad)
        if abs(error) > 0.25:
            return 0.0, math.copysign(min(TURN_RADPS, 2.0 * abs(error)), error)
        return min(CRUISE_MPS, 1.5 * distance), 2.0 * error


@dataclass
class RoomResult:
    seed: int
    look: str
    mount: str
    score: ScanScore = field(default_factory=ScanScore)


def bench_config(seed: int, realism: str, randomize_appearance: bool,
                 randomize_mount: bool, frame_drops: bool = False) -> SimpleNamespace:
    """The simulator configuration of a room trial of ``seed``, without frame latency, and
    without frame drops unless ``frame_drops`` (then the preset's)."""
    values = {'world': 'room', 'seed': seed, 'realism/preset': realism,
              'randomize_appearance': randomize_appearance, 'randomize_mount': randomize_mount,
              'realism/camera_latency_s': 0.0, 'scan_rate': 0.0, 'lockstep': False}
    if not frame_drops:
        values['realism/camera_drop_rate'] = 0.0
    return checked_config(defaults(PARAMS, values), lambda text: None)


def look_text(scene) -> str:
    """The floor, wall and obstacle colours of ``scene``, for a table."""
    def rgb(rgba):
        return 'pybullet' if rgba is None else ' '.join('%.2f' % value for value in rgba[:3])
    floor = rgb(scene.floor_rgba)
    if scene.floor_checker_rgba is not None:
        floor += ' / ' + rgb(scene.floor_checker_rgba)
    return 'floor %s, wall %s, obstacles %s' % (floor, rgb(scene.wall_rgba),
                                                rgb(scene.obstacle_rgba))


def mount_text(mount) -> str:
    """The camera mount's height and pitch, for a table."""
    return 'height %.2f m, pitch %.1f deg' % (mount.height_m, mount.pitch_deg)


def run_room(urdf_path: str, seed: int, floor_settings: FloorSettings, duration_s: float,
             realism: str = 'harsh', randomize_appearance: bool = False,
             randomize_mount: bool = False, near_m: float = 1.0, min_missed_bins: int = 5,
             on_frame: Optional[Callable] = None, frame_drops: bool = False) -> RoomResult:
    """Drive the tour of the room of ``seed`` for ``duration_s`` (sim) and score every scan
    (with the preset's frame drops when ``frame_drops``). ``on_frame(image, scan, truth)`` sees
    each frame when given."""
    config = bench_config(seed, realism, randomize_appearance, randomize_mount, frame_drops)
    camera = camera_spec(config)
    pose = camera_pose_from_mount(camera.mount)
    intrinsics = camera.intrinsics
    truth_lidar = LidarSpec(TRUTH_BEAMS, ROBOT_RADIUS_M + 0.005, 8.0, TRUTH_HEIGHT_M)
    result = RoomResult(seed, look_text(config.scene), mount_text(camera.mount))
    scanner = CameraScanner(floor_settings)
    with World(urdf_path, camera, config.physics_rate, config.renderer,
               can_rgba=config.can_color, scene=config.scene,
               can_texture=config.can_texture) as world:
        simulation = Simulation.from_config(world, config)
        driver = TourDriver(config.scene, random.Random('tour %d' % seed))
        for _ in range(int(round(duration_s * config.physics_rate))):
            state = world.robot_state()
            simulation.command(*driver.command(state.position[0], state.position[1],
                                               state.yaw_rad))
            step = simulation.step()
            if step.image is None:
                continue
            scan = scanner.scan(step.image, pose, intrinsics)
            geometry = scanner.geometry
            if scan.ranges is None:
                continue
            beams = world.scan(truth_lidar)
            bin_angles = geometry.angle_min + geometry.angle_increment * np.arange(
                geometry.bins)
            index = np.round((bin_angles - truth_lidar.angle_min_rad)
                             / truth_lidar.angle_increment_rad).astype(int) % TRUTH_BEAMS
            truth = beams[index].astype(np.float64)
            result.score.add(score_scan(scan.ranges, truth, geometry.range_min,
                                        geometry.range_max, near_m, min_missed_bins))
            if simulation.realism.spec.camera_wb_walk > 0.0:
                result.score.add(white_balance_score(scanner.floor.white_balance.shift_log,
                                                     simulation.realism.camera.frame_wb_shift_log))
            if on_frame is not None:
                on_frame(step.image, scan, truth)
    return result


def _white_balance_text(score: ScanScore) -> str:
    if not score.wb_frames:
        return '-'
    return '%.2f / %.2f' % (score.wb_error_bins, score.wb_drift_bins)


def summary_rows(results: List[RoomResult]) -> List[str]:
    """Markdown rows: one per room, then the total."""
    rows = ['| seed | near bins missed | frames with a miss | bins phantom '
            '| white balance off, lock / none (bins RMS) | look | mount |',
            '|---|---|---|---|---|---|---|']
    total = ScanScore()
    for room in results:
        score = room.score
        total.add(score)
        rows.append('| %d | %.2f %% | %d / %d | %.2f %% | %s | %s | %s |' % (
            room.seed, 100.0 * score.miss_rate, score.frames_with_miss, score.frames,
            100.0 * score.phantom_rate, _white_balance_text(score), room.look, room.mount))
    rows.append('| all | %.2f %% | %d / %d | %.2f %% | %s | | |' % (
        100.0 * total.miss_rate, total.frames_with_miss, total.frames,
        100.0 * total.phantom_rate, _white_balance_text(total)))
    return rows
