"""What a real robot's senses and motors add to a perfect simulation: camera noise, exposure,
white balance, vignetting, motion blur, JPEG, latency and frame drops; wheel odometry that
drifts; command latency and a motor deadband; lidar range noise and dropouts.

One preset, ``~realism/preset`` (``ideal``, ``realistic``, ``harsh``), sets every knob; each knob
is also a parameter of its own in the same namespace, ``~realism/<knob>``, that overrides the
preset (-1 keeps the preset's value). Every random draw comes from generators seeded per trial
(:meth:`Realism.new_trial`), one stream per sensor, so a trial in lockstep is the same whatever
ran before it, and a camera setting does not change the odometry's noise. At ``ideal`` every
model is the identity: images, ranges and commands pass through unchanged and the odometry is
the true pose.
"""
import math
from collections import deque
from dataclasses import dataclass, fields, replace
from typing import Deque, List, Optional, Sequence, Tuple

import cv2
import numpy as np

from can_seeker.camera_geometry import UNDISTORT_CRITERIA, CameraIntrinsics
from can_seeker.params import Param

REALISM_PRESETS = ('ideal', 'realistic', 'harsh')
ZOOM_BLUR_DEPTH_M = 1.0
"""Depth (m) at which forward motion blur is modelled: the floor ahead of a small robot's
camera is about this far; nearer things blur more, farther less."""
AE_RATE = 0.3
"""Fraction of its log exposure error the auto-exposure corrects each frame."""
AWB_RATE = 0.05
"""Fraction of its drift the auto white balance corrects each frame: the drift wanders slowly
(seconds) but stays bounded (stationary spread about 3.2 x the per-frame walk)."""
MAX_AE_LOG_GAIN = math.log(8.0)


@dataclass(frozen=True)
class RealismSpec:
    """Every knob of the realism models (units in the names; 0 turns a model off)."""

    camera_read_noise: float = 0.0
    camera_shot_noise: float = 0.0
    camera_exposure_s: float = 0.0
    camera_ae_walk: float = 0.0
    camera_wb_walk: float = 0.0
    camera_awb: float = 1.0
    camera_vignetting: float = 0.0
    camera_jpeg_quality: int = 0
    camera_latency_s: float = 0.0
    camera_drop_rate: float = 0.0
    camera_k1: float = 0.0
    camera_k2: float = 0.0
    light_kelvin_min: float = 6500.0
    light_kelvin_max: float = 6500.0
    light_intensity_min: float = 1.0
    light_intensity_max: float = 1.0
    light_elevation_min_deg: float = 0.0
    light_elevation_max_deg: float = 0.0
    odom_wheel_scale: float = 0.0
    odom_track_scale: float = 0.0
    odom_slip: float = 0.0
    odom_noise: float = 0.0
    odom_yaw_drift: float = 0.0
    cmd_latency_s: float = 0.0
    motor_deadband_mps: float = 0.0
    scan_noise_m: float = 0.0
    scan_dropout: float = 0.0

    @property
    def odometry_is_true(self) -> bool:
        """Whether /odom is the true pose (no odometry error at all)."""
        return not (self.odom_wheel_scale or self.odom_track_scale or self.odom_slip
                    or self.odom_noise or self.odom_yaw_drift)


PRESETS = {
    'ideal': RealismSpec(),
    'realistic': RealismSpec(
        camera_read_noise=2.0, camera_shot_noise=0.05, camera_exposure_s=0.01,
        camera_ae_walk=0.02, camera_wb_walk=0.01, camera_awb=0.8, camera_vignetting=0.2,
        camera_jpeg_quality=80, camera_latency_s=0.05, camera_drop_rate=0.02,
        light_kelvin_min=3000.0, light_kelvin_max=6500.0, light_intensity_min=0.7,
        light_intensity_max=1.2, light_elevation_min_deg=35.0, light_elevation_max_deg=85.0,
        odom_wheel_scale=0.001, odom_track_scale=0.01, odom_slip=0.02, odom_noise=0.001,
        odom_yaw_drift=0.0005, cmd_latency_s=0.03, motor_deadband_mps=0.004,
        scan_noise_m=0.01, scan_dropout=0.01),
    'harsh': RealismSpec(
        camera_read_noise=6.0, camera_shot_noise=0.2, camera_exposure_s=0.03,
        camera_ae_walk=0.05, camera_wb_walk=0.02, camera_awb=0.5, camera_vignetting=0.4,
        camera_jpeg_quality=50, camera_latency_s=0.12, camera_drop_rate=0.1,
        light_kelvin_min=2700.0, light_kelvin_max=6500.0, light_intensity_min=0.4,
        light_intensity_max=1.5, light_elevation_min_deg=20.0, light_elevation_max_deg=85.0,
        odom_wheel_scale=0.005, odom_track_scale=0.03, odom_slip=0.05, odom_noise=0.004,
        odom_yaw_drift=0.002, cmd_latency_s=0.1, motor_deadband_mps=0.008,
        scan_noise_m=0.03, scan_dropout=0.05),
}

_KNOB_DOCS = {
    'camera_read_noise': ('Gaussian read noise of the camera (8-bit levels, standard deviation)',
                          255.0),
    'camera_shot_noise': ('shot noise: variance added per level of signal (levels)', 10.0),
    'camera_exposure_s': ('exposure time: motion blur from the robot\'s own turn and forward '
                          'speed over it (s)', 0.5),
    'camera_ae_walk': ('auto-exposure gain random walk per frame (standard deviation of the '
                       'log gain)', 1.0),
    'camera_wb_walk': ('white-balance drift: random walk per frame of each channel\'s log gain '
                       '(the white balance pulls it back by 5 % a frame)', 1.0),
    'camera_awb': ('fraction of the light\'s colour cast the auto white balance removes (0-1)',
                   1.0),
    'camera_vignetting': ('brightness lost in the image corners (fraction, 0-1)', 1.0),
    'camera_jpeg_quality': ('JPEG round trip at this quality (1-100; 0: none)', 100.0),
    'camera_latency_s': ('frame latency: a frame keeps its capture stamp and is published this '
                         'much later (s, sim time)', 2.0),
    'camera_drop_rate': ('fraction of frames dropped at random (0-1)', 1.0),
    'camera_k1': ('radial lens distortion k1 (plumb_bob, published in camera_info D)', 1.0),
    'camera_k2': ('radial lens distortion k2 (plumb_bob, published in camera_info D)', 1.0),
    'light_kelvin_min': ('lowest colour temperature of the light drawn per trial (K; 2700 warm, '
                         '6500 daylight, the renderer\'s white)', 20000.0),
    'light_kelvin_max': ('highest colour temperature of the light drawn per trial (K)', 20000.0),
    'light_intensity_min': ('dimmest light drawn per trial (fraction of the renderer\'s)', 10.0),
    'light_intensity_max': ('brightest light drawn per trial (fraction of the renderer\'s)',
                            10.0),
    'light_elevation_min_deg': ('lowest elevation of the light direction drawn per trial (deg; '
                                '0 with the maximum 0: the renderer\'s fixed light)', 90.0),
    'light_elevation_max_deg': ('highest elevation of the light direction drawn per trial (deg)',
                                90.0),
    'odom_wheel_scale': ('wheel odometry: standard deviation of each wheel\'s radius error, '
                         'drawn per trial (fraction)', 0.5),
    'odom_track_scale': ('wheel odometry: standard deviation of the wheel separation error, '
                         'drawn per trial (fraction; heading drift when turning)', 0.5),
    'odom_slip': ('wheel odometry: wheel travel over-counted per m/s^2 of wheel acceleration '
                  '(fraction per m/s^2)', 1.0),
    'odom_noise': ('wheel odometry: random travel error per wheel (m per square root of m)',
                   1.0),
    'odom_yaw_drift': ('wheel odometry: standard deviation of a heading drift rate drawn per '
                       'trial (rad/s)', 1.0),
    'cmd_latency_s': ('command latency: a velocity command acts this much later (s, sim time)',
                      2.0),
    'motor_deadband_mps': ('motor deadband: a wheel commanded slower than this at its rim does '
                           'not turn (m/s)', 1.0),
    'scan_noise_m': ('lidar range noise (m, standard deviation)', 1.0),
    'scan_dropout': ('fraction of lidar beams that return nothing (NaN, REP-117)', 1.0),
}

KEEP_PRESET = -1.0
"""A knob's parameter at this value keeps the ~realism/preset value."""
SIGNED_KNOBS = frozenset(('camera_k1', 'camera_k2'))
"""Knobs whose negative values mean something (barrel distortion): only KEEP_PRESET itself
keeps the preset, and they range over (-1, 1]; any other knob below 0 keeps the preset."""

REALISM_NAMESPACE = 'realism'
"""The simulator's private namespace of the preset and the knobs: ``~realism/preset``,
``~realism/camera_read_noise``, ..."""
REALISM_PARAMS = (
    Param(REALISM_NAMESPACE + '/preset', 'ideal', 'sensor and actuator realism preset: ideal '
          '(perfect camera, odometry and motors), realistic (a small base with a webcam) or '
          'harsh; the knobs beside it in ~realism/ override it', choices=REALISM_PRESETS),
) + tuple(
    Param('%s/%s' % (REALISM_NAMESPACE, knob.name),
          KEEP_PRESET if knob.type is float else int(KEEP_PRESET),
          '%s; -1: the ~realism/preset value' % _KNOB_DOCS[knob.name][0],
          KEEP_PRESET, _KNOB_DOCS[knob.name][1])
    for knob in fields(RealismSpec))


def _overrides(value, name: str) -> bool:
    return value != KEEP_PRESET if name in SIGNED_KNOBS else value >= 0


def realism_spec(preset: str, overrides: Optional[dict] = None) -> RealismSpec:
    """The preset's knobs with every override put in: 0 or more, or for SIGNED_KNOBS anything
    but KEEP_PRESET (a negative one, or KEEP_PRESET, keeps the preset's value)."""
    spec = PRESETS[preset]
    chosen = {name: value for name, value in (overrides or {}).items()
              if _overrides(value, name)}
    return replace(spec, **chosen)


def spec_from_config(config) -> RealismSpec:
    """The :class:`RealismSpec` of a simulator configuration (its ``realism`` namespace: the
    preset and the knobs)."""
    realism = config.realism
    return realism_spec(realism.preset, {knob.name: getattr(realism, knob.name)
                                         for knob in fields(RealismSpec)})


def kelvin_rgb(kelvin: float) -> np.ndarray:
    """Relative (r, g, b) of a black body at ``kelvin`` (K), green = 1 (Tanner Helland's fit of
    the CIE colour matching data, 1000-40000 K); 6500 K is close to (1, 1, 1)."""
    t = kelvin / 100.0
    red = 255.0 if t <= 66 else 329.698727446 * (t - 60) ** -0.1332047592
    green = (99.4708025861 * math.log(t) - 161.1195681661 if t <= 66
             else 288.1221695283 * (t - 60) ** -0.0755148492)
    blue = (255.0 if t >= 66 else 0.0 if t <= 19
            else 138.5177312231 * math.log(t - 10) - 305.0447927307)
    rgb = np.clip(np.array([red, green, blue]), 1.0, 255.0)
    return rgb / rgb[1]


def light_direction(azimuth_rad: float, elevation_deg: float) -> Tuple[float, float, float]:
    """Unit vector toward the light (world frame, z up)."""
    elevation = math.radians(elevation_deg)
    return (math.cos(elevation) * math.cos(azimuth_rad),
            math.cos(elevation) * math.sin(azimuth_rad), math.sin(elevation))


def distortion_maps(intrinsics: CameraIntrinsics, k1: float, k2: float, margin_px: int = 0):
    """(map_x, map_y) for cv2.remap that turn a pinhole render into the plumb_bob image of the
    same K with D = (k1, k2, 0, 0, 0): each distorted pixel samples its undistorted point, in a
    render of the same focal length ``margin_px`` larger on every side."""
    camera = np.array([[intrinsics.fx, 0.0, intrinsics.cx], [0.0, intrinsics.fy, intrinsics.cy],
                       [0.0, 0.0, 1.0]])
    columns, rows = np.meshgrid(np.arange(intrinsics.width, dtype=np.float64),
                                np.arange(intrinsics.height, dtype=np.float64))
    pixels = np.stack((columns.ravel(), rows.ravel()), axis=1).reshape(-1, 1, 2)
    ideal = cv2.undistortPointsIter(pixels, camera, np.array([k1, k2, 0.0, 0.0, 0.0]), None,
                                    camera, UNDISTORT_CRITERIA)
    ideal = ideal.reshape(intrinsics.height, intrinsics.width, 2).astype(np.float32) + margin_px
    return ideal[:, :, 0], ideal[:, :, 1]


def render_margin_px(intrinsics: CameraIntrinsics, k1: float, k2: float) -> int:
    """How many pixels beyond each side of the image a pinhole render must reach for the
    plumb_bob image of (k1, k2) to sample scene everywhere: a barrel lens sees past the
    pinhole view of its K (0 for a lens that sees less)."""
    map_x, map_y = distortion_maps(intrinsics, k1, k2)
    beyond = max(-float(map_x.min()), float(map_x.max()) - (intrinsics.width - 1),
                 -float(map_y.min()), float(map_y.max()) - (intrinsics.height - 1), 0.0)
    return int(math.ceil(beyond)) + 1 if beyond > 0.0 else 0


class CameraModel:
    """Turns the renderer's perfect frame into a camera's: optics (distortion, motion blur,
    vignetting), light (colour temperature, intensity) and the camera's answer to it (auto
    exposure, auto white balance with drift), the sensor's noise, and a JPEG round trip.
    ``render_margin_px`` is how far beyond each side of the image it wants the render (a
    barrel lens sees past the pinhole view)."""

    def __init__(self, spec: RealismSpec, intrinsics: CameraIntrinsics, encoding: str = 'bgr8'):
        self.spec = spec
        self.intrinsics = intrinsics
        self.encoding = encoding
        self.identity = (spec.camera_read_noise == 0 and spec.camera_shot_noise == 0
                         and spec.camera_exposure_s == 0 and spec.camera_ae_walk == 0
                         and spec.camera_wb_walk == 0 and spec.camera_vignetting == 0
                         and spec.camera_jpeg_quality == 0 and spec.camera_k1 == 0
                         and spec.camera_k2 == 0 and spec.light_kelvin_min == 6500.0
                         and spec.light_kelvin_max == 6500.0
                         and spec.light_intensity_min == 1.0 and spec.light_intensity_max == 1.0)
        distorted = bool(spec.camera_k1 or spec.camera_k2)
        self.render_margin_px = (render_margin_px(intrinsics, spec.camera_k1, spec.camera_k2)
                                 if distorted else 0)
        self._maps = (distortion_maps(intrinsics, spec.camera_k1, spec.camera_k2,
                                      self.render_margin_px) if distorted else None)
        self._vignette = self._vignette_gain() if spec.camera_vignetting else None
        self._noise = self._sigma = None
        self.new_trial(np.random.default_rng(0))

    def _vignette_gain(self) -> np.ndarray:
        """Per-pixel gain (HxWx3, the same for each channel) 1 at the principal point down to
        1 - vignetting in the corners (a cos^4-like fall-off, quadratic in the radius)."""
        intrinsics = self.intrinsics
        columns, rows = np.meshgrid(np.arange(intrinsics.width) - intrinsics.cx,
                                    np.arange(intrinsics.height) - intrinsics.cy)
        radius2 = columns ** 2 + rows ** 2
        gain = 1.0 - self.spec.camera_vignetting * radius2 / radius2.max()
        return np.repeat(gain.astype(np.float32)[:, :, None], 3, axis=2)

    def new_trial(self, rng: np.random.Generator):
        """Draw this trial's light and restart white balance from ``rng``; the exposure starts
        settled on the light."""
        spec = self.spec
        self._rng = rng
        self.kelvin = float(rng.uniform(spec.light_kelvin_min, spec.light_kelvin_max))
        self.intensity = float(rng.uniform(spec.light_intensity_min, spec.light_intensity_max))
        azimuth_rad = float(rng.uniform(-math.pi, math.pi))
        elevation_deg = float(rng.uniform(spec.light_elevation_min_deg,
                                          spec.light_elevation_max_deg))
        self.light_direction = (light_direction(azimuth_rad, elevation_deg)
                                if spec.light_elevation_max_deg > 0.0 else None)
        # The camera ran before the trial: its exposure has settled on this light.
        self.log_exposure_gain = -math.log(self.intensity)
        self.log_wb_drift = np.zeros(3)
        self.frame_wb_shift_log = np.zeros(2)

    def channel_gains(self) -> np.ndarray:
        """Gain of each image channel (in the image's channel order) from the light, the
        exposure and the white balance now."""
        cast_rgb = kelvin_rgb(self.kelvin) ** (1.0 - self.spec.camera_awb)
        gains_rgb = (self.intensity * math.exp(self.log_exposure_gain) * cast_rgb
                     * np.exp(self.log_wb_drift))
        return (gains_rgb[::-1] if self.encoding == 'bgr8' else gains_rgb).astype(np.float32)

    def wb_shift_log(self) -> np.ndarray:
        """The white-balance drift now as a log-chromaticity shift (log R/G, log B/G) from the
        trial's start: what the floor model's white-balance lock should find.
        ``frame_wb_shift_log`` holds it as it was for the last frame taken."""
        drift = self.log_wb_drift
        return np.array((drift[0] - drift[1], drift[2] - drift[1]))

    def _motion_blur(self, image: np.ndarray, linear_mps: float,
                     angular_radps: float) -> np.ndarray:
        exposure_s = self.spec.camera_exposure_s
        length_px = int(round(abs(angular_radps) * exposure_s * self.intrinsics.fx))
        if length_px >= 2:
            image = cv2.blur(image, (length_px, 1))
        zoom = abs(linear_mps) * exposure_s / ZOOM_BLUR_DEPTH_M
        steps = int(math.ceil(zoom * max(self.intrinsics.width, self.intrinsics.height) / 2.0))
        if steps >= 2:
            centre = (self.intrinsics.cx, self.intrinsics.cy)
            size = (self.intrinsics.width, self.intrinsics.height)
            total = image.copy()
            for index in range(1, steps):
                warp = cv2.getRotationMatrix2D(centre, 0.0, 1.0 + zoom * index / (steps - 1))
                total += cv2.warpAffine(image, warp, size, borderMode=cv2.BORDER_REPLICATE)
            image = total / steps
        return image

    def apply(self, frame: np.ndarray, linear_mps: float = 0.0,
              angular_radps: float = 0.0) -> np.ndarray:
        """The camera's image (HxWx3 uint8) of the rendered ``frame`` (of the image's focal
        length, :attr:`render_margin_px` larger on every side) taken while the robot moved at
        (``linear_mps``, ``angular_radps``); advances exposure and white balance."""
        if self.identity:
            return frame
        spec = self.spec
        image = frame.astype(np.float32)
        if self._maps is not None:
            image = cv2.remap(image, self._maps[0], self._maps[1], cv2.INTER_LINEAR,
                              borderMode=cv2.BORDER_CONSTANT)
        if spec.camera_exposure_s > 0.0:
            image = self._motion_blur(image, linear_mps, angular_radps)
        # From here on in place, through OpenCV on a one-channel view of the image (an OpenCV
        # scalar on a three-channel image would reach the first channel only).
        levels = image.reshape(image.shape[0], -1)
        if self._vignette is not None:
            cv2.multiply(image, self._vignette, dst=image)
        scene_mean = cv2.mean(levels)[0] * self.intensity
        cv2.multiply(image, tuple(float(gain) for gain in self.channel_gains()) + (0.0,),
                     dst=image)
        self.frame_wb_shift_log = self.wb_shift_log()
        if spec.camera_read_noise or spec.camera_shot_noise:
            self._add_noise(levels)
        cv2.add(levels, 0.5, dst=levels)
        cv2.max(levels, 0.0, dst=levels)
        cv2.min(levels, 255.0, dst=levels)
        out = image.astype(np.uint8)
        self._expose(scene_mean, cv2.mean(out.reshape(out.shape[0], -1))[0])
        if spec.camera_jpeg_quality > 0:
            ok, encoded = cv2.imencode('.jpg', out, [cv2.IMWRITE_JPEG_QUALITY,
                                                     int(spec.camera_jpeg_quality)])
            if ok:
                out = cv2.imdecode(encoded, cv2.IMREAD_COLOR)
        return out

    def _add_noise(self, levels: np.ndarray):
        """Add the sensor's noise to ``levels`` (float32, one channel, in place): Gaussian with
        variance shot noise x signal + read noise^2 at each pixel. The standard normal draws
        come from OpenCV's generator, seeded per frame from the trial's camera stream."""
        spec = self.spec
        if self._noise is None or self._noise.shape != levels.shape:
            self._noise = np.empty_like(levels)
            self._sigma = np.empty_like(levels)
        noise, sigma = self._noise, self._sigma
        cv2.setRNGSeed(int(self._rng.integers(1, 2 ** 31)))
        cv2.randn(noise, 0.0, 1.0)
        # The signal is never negative here: the render, the vignetting and the gains are not.
        cv2.addWeighted(levels, spec.camera_shot_noise, levels, 0.0,
                        spec.camera_read_noise ** 2, dst=sigma)
        cv2.sqrt(sigma, dst=sigma)
        cv2.multiply(noise, sigma, dst=noise)
        cv2.add(levels, noise, dst=levels)

    def _expose(self, scene_mean: float, image_mean: float):
        """Auto exposure and white balance for the next frame: the exposure moves a fraction
        of the way to the gain that brings the image back to the render's brightness, and both
        random-walk."""
        spec, rng = self.spec, self._rng
        if scene_mean > 1.0 and image_mean > 1.0:
            reference = scene_mean / self.intensity
            self.log_exposure_gain += AE_RATE * math.log(reference / image_mean)
        if spec.camera_ae_walk:
            self.log_exposure_gain += spec.camera_ae_walk * float(rng.standard_normal())
        self.log_exposure_gain = min(max(self.log_exposure_gain, -MAX_AE_LOG_GAIN),
                                     MAX_AE_LOG_GAIN)
        if spec.camera_wb_walk:
            self.log_wb_drift = ((1.0 - AWB_RATE) * self.log_wb_drift
                                 + spec.camera_wb_walk * rng.standard_normal(3))
            self.log_wb_drift -= self.log_wb_drift[1]


class FrameDelivery:
    """Frames from capture to publication: some dropped at random, the rest published
    ``latency_s`` later in sim time with their capture time kept as their stamp."""

    def __init__(self, latency_s: float, drop_rate: float):
        self.latency_s = latency_s
        self.drop_rate = drop_rate
        self._pending: Deque[Tuple[float, float, np.ndarray]] = deque()
        self.dropped = 0
        self.new_trial(np.random.default_rng(0))

    def new_trial(self, rng: np.random.Generator):
        """Forget frames on their way and draw drops from ``rng``."""
        self._rng = rng
        self._pending.clear()

    def capture(self, time_s: float, image: np.ndarray):
        """A frame taken at ``time_s`` (s, sim time)."""
        if self.drop_rate and self._rng.random() < self.drop_rate:
            self.dropped += 1
            return
        self._pending.append((time_s + self.latency_s, time_s, image))

    def due(self, now_s: float) -> List[Tuple[float, np.ndarray]]:
        """(capture time, image) of every frame due for publication at ``now_s``, oldest
        first (a frame is due once ``latency_s`` passed since its capture)."""
        ready = []
        while self._pending and self._pending[0][0] <= now_s + 1e-9:
            _, captured_s, image = self._pending.popleft()
            ready.append((captured_s, image))
        return ready


class WheelOdometry:
    """Odometry integrated from the wheels of a differential-drive base, as its firmware does:
    each wheel's travel with a radius error, over-counted while the wheel accelerates (slip),
    with random error, through a wheel separation that is off, plus a heading drift rate.

    The true travel of each wheel comes from the true motion of the base between two updates;
    the errors are drawn per trial. At zero errors the odometry is the truth itself.
    """

    def __init__(self, spec: RealismSpec, wheel_separation_m: float):
        self.spec = spec
        self.wheel_separation_m = wheel_separation_m
        self.new_trial(np.random.default_rng(0), (0.0, 0.0, 0.0))

    def new_trial(self, rng: np.random.Generator, true_pose: Tuple[float, float, float]):
        """Start at ``true_pose`` (x m, y m, yaw rad) and draw this trial's errors."""
        spec = self.spec
        self._rng = rng
        self.left_scale = 1.0 + spec.odom_wheel_scale * float(rng.standard_normal())
        self.right_scale = 1.0 + spec.odom_wheel_scale * float(rng.standard_normal())
        self.separation_scale = 1.0 + spec.odom_track_scale * float(rng.standard_normal())
        self.yaw_drift_radps = spec.odom_yaw_drift * float(rng.standard_normal())
        self.pose = tuple(true_pose)
        self.twist = (0.0, 0.0)
        self._last_true = tuple(true_pose)

    def update(self, true_pose: Tuple[float, float, float], dt_s: float,
               wheel_accels_mps2: Tuple[float, float] = (0.0, 0.0)):
        """Integrate the motion from the last true pose to ``true_pose`` over ``dt_s`` (s);
        ``wheel_accels_mps2`` are the (left, right) rim accelerations the motors are driven at
        now (the slip grows with them)."""
        if self.spec.odometry_is_true:
            self.pose = tuple(true_pose)
            self._last_true = tuple(true_pose)
            return
        last_x, last_y, last_yaw = self._last_true
        x, y, yaw = true_pose
        turn_rad = math.atan2(math.sin(yaw - last_yaw), math.cos(yaw - last_yaw))
        heading = last_yaw + turn_rad / 2.0
        forward_m = (x - last_x) * math.cos(heading) + (y - last_y) * math.sin(heading)
        half_turn_m = turn_rad * self.wheel_separation_m / 2.0
        travels = []
        for true_m, scale, accel_mps2 in ((forward_m - half_turn_m, self.left_scale,
                                           wheel_accels_mps2[0]),
                                          (forward_m + half_turn_m, self.right_scale,
                                           wheel_accels_mps2[1])):
            measured_m = true_m * scale * (1.0 + self.spec.odom_slip * abs(accel_mps2))
            if self.spec.odom_noise and true_m:
                measured_m += (self.spec.odom_noise * math.sqrt(abs(true_m))
                               * float(self._rng.standard_normal()))
            travels.append(measured_m)
        self._last_true = tuple(true_pose)
        moving = forward_m != 0.0 or turn_rad != 0.0
        distance_m = (travels[0] + travels[1]) / 2.0
        odom_turn_rad = ((travels[1] - travels[0])
                         / (self.wheel_separation_m * self.separation_scale)
                         + (self.yaw_drift_radps * dt_s if moving else 0.0))
        odom_x, odom_y, odom_yaw = self.pose
        mid = odom_yaw + odom_turn_rad / 2.0
        self.pose = (odom_x + distance_m * math.cos(mid), odom_y + distance_m * math.sin(mid),
                     math.atan2(math.sin(odom_yaw + odom_turn_rad),
                                math.cos(odom_yaw + odom_turn_rad)))
        self.twist = (distance_m / dt_s, odom_turn_rad / dt_s)


class Actuation:
    """Between the velocity command and the wheels: the command acts ``cmd_latency_s`` later,
    and a wheel commanded slower than the motor deadband at its rim does not turn."""

    def __init__(self, spec: RealismSpec, wheel_separation_m: float):
        self.latency_s = spec.cmd_latency_s
        self.deadband_mps = spec.motor_deadband_mps
        self.wheel_separation_m = wheel_separation_m
        self._pending: Deque[Tuple[float, float, float]] = deque()

    def reset(self):
        """Drop commands on their way."""
        self._pending.clear()

    def command(self, linear_mps: float, angular_radps: float, now_s: float):
        """A command received at ``now_s`` (s, sim time)."""
        self._pending.append((now_s + self.latency_s, linear_mps, angular_radps))

    def arrived(self, now_s: float) -> List[Tuple[float, float, float]]:
        """(time it acts, linear, angular) of every command that acts by ``now_s``."""
        ready = []
        while self._pending and self._pending[0][0] <= now_s + 1e-9:
            ready.append(self._pending.popleft())
        return ready

    def wheels(self, linear_mps: float, angular_radps: float) -> Tuple[float, float]:
        """The twist the wheels make of (``linear_mps``, ``angular_radps``) with the
        deadband."""
        if not self.deadband_mps:
            return linear_mps, angular_radps
        half_track_mps = angular_radps * self.wheel_separation_m / 2.0
        left, right = linear_mps - half_track_mps, linear_mps + half_track_mps
        left = 0.0 if abs(left) < self.deadband_mps else left
        right = 0.0 if abs(right) < self.deadband_mps else right
        return (left + right) / 2.0, (right - left) / self.wheel_separation_m


def noisy_ranges(ranges_m: np.ndarray, noise_m: float, dropout: float,
                 rng: np.random.Generator) -> np.ndarray:
    """Lidar ranges with Gaussian noise on every return and dropped beams as NaN (REP-117: an
    erroneous reading); +inf (nothing within range) stays inf unless dropped."""
    ranges = np.asarray(ranges_m, dtype=np.float32)
    if not (noise_m or dropout):
        return ranges
    noisy = ranges + (noise_m * rng.standard_normal(ranges.shape)).astype(np.float32)
    noisy = np.where(np.isfinite(ranges), noisy, ranges)
    if dropout:
        noisy = np.where(rng.random(ranges.shape) < dropout, np.float32(np.nan), noisy)
    return noisy.astype(np.float32)


class Realism:
    """Every realism model of one simulated robot, with per-trial random streams."""

    def __init__(self, spec: RealismSpec, intrinsics: CameraIntrinsics, encoding: str,
                 wheel_separation_m: float):
        self.spec = spec
        self.camera = CameraModel(spec, intrinsics, encoding)
        self.frames = FrameDelivery(spec.camera_latency_s, spec.camera_drop_rate)
        self.odometry = WheelOdometry(spec, wheel_separation_m)
        self.actuation = Actuation(spec, wheel_separation_m)
        self._scan_rng = np.random.default_rng(0)

    @property
    def distortion(self) -> Sequence[float]:
        """camera_info D (plumb_bob: k1, k2, t1, t2, k3)."""
        return [self.spec.camera_k1, self.spec.camera_k2, 0.0, 0.0, 0.0]

    def new_trial(self, key: Sequence[int], true_pose: Tuple[float, float, float]):
        """Reseed every model from ``key`` (non-negative integers naming the trial) and start
        the odometry at ``true_pose``."""
        camera, frames, odometry, scan = (np.random.default_rng(child) for child in
                                          np.random.SeedSequence(list(key)).spawn(4))
        self.camera.new_trial(camera)
        self.frames.new_trial(frames)
        self.odometry.new_trial(odometry, true_pose)
        self.actuation.reset()
        self._scan_rng = scan

    def scan(self, ranges_m: np.ndarray) -> np.ndarray:
        """The lidar's reading of the true ``ranges_m``."""
        return noisy_ranges(ranges_m, self.spec.scan_noise_m, self.spec.scan_dropout,
                            self._scan_rng)


def trial_key(seed: int, can_xy: Tuple[float, float]) -> Tuple[int, int, int]:
    """Seed words naming a trial: the world seed and where the can stands (mm, offset to stay
    non-negative)."""
    offset_mm = 10 ** 6
    return (int(seed), int(round(can_xy[0] * 1000.0)) + offset_mm,
            int(round(can_xy[1] * 1000.0)) + offset_mm)
