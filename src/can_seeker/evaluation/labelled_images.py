"""A small labelled set of real and rendered images for the red detector, built from packages.

Nothing here is stored in the repository: photographs come from Debian's ``opencv-doc``
samples, ``python3-skimage``'s shipped data and matplotlib's sample data (tools/apt-packages.txt
installs all three); cans are rendered in our pybullet world in several colours, with white
balance and brightness changed afterwards to mimic warm, cool, dim and bright light.

Labels (image level): ``red`` images hold a red object (boxes (x, y, width, height) in px say
where; a detection counts only when its centroid is in one), ``near-red`` images hold only
orange, pink, magenta, brown or skin and ``none`` images nothing red-like. Rendered red cans
are also labelled ``is_can``: the detector's confidence should be high on them only.
"""
import importlib.util
import math
import os
from dataclasses import dataclass
from typing import Callable, List, Optional, Sequence, Tuple

import cv2
import numpy as np

from can_seeker.vision.detector import DetectorSettings, RedCanDetector
from can_seeker.vision.report import CanModel, can_report

OPENCV_SAMPLES_DIR = '/usr/share/doc/opencv-doc/examples/data'
LABELS = ('red', 'near-red', 'none')


@dataclass(frozen=True)
class LabelledPhoto:
    """One photograph of a package: where it is, its label, the red objects' boxes (px), and
    optionally the part of it used (x, y, width, height; boxes are in the part's pixels)."""

    package: str
    name: str
    label: str
    boxes: Tuple[Tuple[int, int, int, int], ...] = ()
    note: str = ''
    crop: Optional[Tuple[int, int, int, int]] = None


def _opencv_photo(name, label, boxes=(), note='', crop=None):
    return LabelledPhoto('opencv-doc', name, label, tuple(boxes), note, crop)


def _skimage_photo(name, label, boxes=(), note=''):
    return LabelledPhoto('python3-skimage', name, label, tuple(boxes), note)


def _matplotlib_photo(name, label, boxes=(), note=''):
    return LabelledPhoto('python3-matplotlib', name, label, tuple(boxes), note)


# Looked at one by one. Ambiguous images (a brick-red cup, a red-to-magenta gradient, tiny
# red spots) are left out rather than labelled either way.
PHOTOS = (
    _opencv_photo('baboon.jpg', 'red', [(150, 120, 185, 330)], 'mandrill nose'),
    _opencv_photo('messi5.jpg', 'red', [(200, 100, 160, 190)], 'claret shirt and shorts'),
    _opencv_photo('smarties.png', 'red', [(193, 279, 54, 56), (73, 233, 53, 53),
                                          (7, 204, 53, 50), (262, 189, 52, 50),
                                          (109, 300, 50, 55)], 'red sweets among others'),
    _opencv_photo('opencv-logo.png', 'red', [(153, 0, 289, 268)], 'red ring'),
    _opencv_photo('licenseplate_motion.jpg', 'red', [(440, 145, 160, 120), (0, 170, 135, 95)],
                  'tail lights'),
    _opencv_photo('graf1.png', 'red', [(110, 0, 260, 480), (0, 7, 96, 73), (106, 548, 128, 92),
                                       (51, 431, 70, 63), (302, 534, 88, 66)], 'red paint'),
    _skimage_photo('motorcycle_left.png', 'red', [(91, 150, 400, 135), (530, 180, 120, 140)],
                   'red tank, fenders and toolbox'),
    _skimage_photo('astronaut.png', 'red', [(0, 0, 100, 345)], 'flag beside an orange suit'),
    _matplotlib_photo('grace_hopper.jpg', 'red', [(0, 0, 160, 420), (0, 400, 40, 200)],
                      'flag beside skin'),
    _opencv_photo('apple.jpg', 'near-red', note='orange apple'),
    _opencv_photo('fruits.jpg', 'near-red', note='orange and magenta cabbage'),
    _opencv_photo('orange.jpg', 'near-red', note='orange'),
    _opencv_photo('chicky_512.png', 'red', [(305, 0, 50, 80)], 'red stripe of a blanket'),
    _opencv_photo('chicky_512.png', 'near-red', note='pink tongue (below the red stripe)',
                  crop=(0, 100, 512, 412)),
    _opencv_photo('rubberwhale1.png', 'near-red', note='orange toys'),
    _opencv_photo('squirrel_cls.jpg', 'near-red', note='brown-orange fur'),
    _skimage_photo('chelsea.png', 'near-red', note='orange-brown cat'),
    _skimage_photo('ihc.png', 'near-red', note='brown stain'),
    _skimage_photo('logo.png', 'near-red', note='orange'),
    _skimage_photo('retina.jpg', 'near-red', note='orange-red retina'),
    _skimage_photo('hubble_deep_field.jpg', 'near-red', note='pinkish galaxies'),
    _opencv_photo('home.jpg', 'none'),
    _opencv_photo('stuff.jpg', 'none'),
    _opencv_photo('starry_night.jpg', 'none'),
    _opencv_photo('building.jpg', 'none'),
    _opencv_photo('aero3.jpg', 'none'),
    _skimage_photo('rocket.jpg', 'none'),
)


def package_dir(package: str) -> Optional[str]:
    """The folder holding a package's sample images, or None when it is not installed."""
    if package == 'opencv-doc':
        return OPENCV_SAMPLES_DIR if os.path.isdir(OPENCV_SAMPLES_DIR) else None
    if package == 'python3-skimage':
        spec = importlib.util.find_spec('skimage')
        return os.path.join(spec.submodule_search_locations[0], 'data') if spec else None
    if package == 'python3-matplotlib':
        spec = importlib.util.find_spec('matplotlib')
        if spec is None:
            return None
        import matplotlib
        return os.path.join(matplotlib.get_data_path(), 'sample_data')
    raise ValueError('unknown package %r' % (package,))


@dataclass
class LabelledImage:
    """An image with its label; ``is_can`` marks a rendered red can."""

    name: str
    bgr: np.ndarray
    label: str
    boxes: Tuple[Tuple[int, int, int, int], ...]
    note: str
    is_can: bool = False
    pose: object = None
    intrinsics: object = None


def load_photos(photos: Sequence[LabelledPhoto] = PHOTOS) -> List[LabelledImage]:
    """The photographs as BGR images; raises FileNotFoundError naming a missing package."""
    images = []
    for photo in photos:
        folder = package_dir(photo.package)
        path = os.path.join(folder, photo.name) if folder else None
        bgr = cv2.imread(path, cv2.IMREAD_COLOR) if path and os.path.isfile(path) else None
        if bgr is None:
            raise FileNotFoundError('%s from the Debian package %s is missing: install it '
                                    '(tools/apt-packages.txt)' % (photo.name, photo.package))
        if photo.crop is not None:
            x, y, width, height = photo.crop
            bgr = np.ascontiguousarray(bgr[y:y + height, x:x + width])
        images.append(LabelledImage(photo.name + (' (part)' if photo.crop else ''), bgr,
                                    photo.label, photo.boxes, photo.note))
    return images


# Can colours (red, green, blue in 0-1) and their labels.
RED_CANS = (('red', (0.8, 0.05, 0.05)), ('crimson', (0.6, 0.08, 0.15)),
            ('dark red', (0.45, 0.03, 0.04)), ('scarlet', (0.9, 0.15, 0.08)))
NEAR_RED_CANS = (('orange', (1.0, 0.45, 0.05)), ('pink', (1.0, 0.55, 0.65)),
                 ('magenta', (0.8, 0.1, 0.6)), ('brown', (0.45, 0.25, 0.12)),
                 ('skin', (0.9, 0.62, 0.5)))
# White balance (blue, green, red gains) and brightness of the light a render is seen in.
LIGHTS = (('neutral', (1.0, 1.0, 1.0)), ('warm', (0.8, 0.95, 1.1)), ('cool', (1.15, 1.0, 0.85)),
          ('dim', (0.45, 0.45, 0.45)), ('bright', (1.35, 1.35, 1.35)))
# Can centres in base_link (m): near, far, off to the side.
CAN_PLACES = ((0.6, 0.0), (1.2, 0.25), (2.2, -0.35), (0.9, -0.2))


def apply_light(bgr: np.ndarray, gains_bgr: Sequence[float]) -> np.ndarray:
    """The image as seen under light of another colour and brightness (saturating)."""
    lit = bgr.astype(np.float32) * np.array(gains_bgr, np.float32)
    return np.clip(lit, 0, 255).astype(np.uint8)


def render_cans(world, pose, intrinsics) -> List[LabelledImage]:
    """Rendered scenes: every can colour at a few places under a few lights, and empty floors.

    ``world`` is a sim.world.World with the robot at the origin; ``pose`` and ``intrinsics``
    are its camera's (for the geometry check).
    """
    images = []
    for colours, label in ((RED_CANS, 'red'), (NEAR_RED_CANS, 'near-red')):
        for colour_name, rgb in colours:
            world.set_can_color(tuple(rgb) + (1.0,))
            for place_index, place in enumerate(CAN_PLACES):
                world.place_can(*place)
                bgr = world.render('bgr8')
                box = _can_box(bgr) if label == 'red' else None
                lights = LIGHTS[place_index % 2::2] if label == 'red' else \
                    LIGHTS[place_index % 3::3]
                for light_name, gains in lights:
                    images.append(LabelledImage(
                        'render %s can at %.1f, %.1f m, %s light' % (
                            colour_name, place[0], place[1], light_name),
                        apply_light(bgr, gains), label, (box,) if box else (),
                        '%s can' % colour_name, is_can=label == 'red', pose=pose,
                        intrinsics=intrinsics))
    world.place_can(-3.0, 0.0)
    floor = world.render('bgr8')
    for light_name, gains in LIGHTS:
        images.append(LabelledImage('render empty floor, %s light' % light_name,
                                    apply_light(floor, gains), 'none', (), 'floor only',
                                    pose=pose, intrinsics=intrinsics))
    return images


def _can_box(bgr: np.ndarray, margin_px: int = 2):
    """Box (px) of the can in a render: the can is the only saturated thing in our world."""
    hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)
    ys, xs = np.nonzero(hsv[..., 1] > 60)
    if len(xs) == 0:
        return None
    width = int(xs.max() - xs.min()) + 1 + 2 * margin_px
    height = int(ys.max() - ys.min()) + 1 + 2 * margin_px
    return int(xs.min()) - margin_px, int(ys.min()) - margin_px, width, height


def in_boxes(x: float, y: float, boxes) -> bool:
    """Whether the point (px) lies in any of the boxes (x, y, width, height)."""
    return any(bx <= x < bx + bw and by <= y < by + bh for bx, by, bw, bh in boxes)


@dataclass(frozen=True)
class Scores:
    """Image-level counts of a decision and its precision and recall."""

    true_positives: int
    false_positives: int
    false_negatives: int
    true_negatives: int
    near_red_false_positives: int
    near_red_images: int

    @property
    def precision(self) -> float:
        found = self.true_positives + self.false_positives
        return self.true_positives / found if found else math.nan

    @property
    def recall(self) -> float:
        positives = self.true_positives + self.false_negatives
        return self.true_positives / positives if positives else math.nan


def score(images: Sequence[LabelledImage], hits: Sequence[Optional[Tuple[float, float]]],
          positive: Callable[[LabelledImage], bool]) -> Scores:
    """Counts for one decision: ``hits[i]`` is the (x, y) px it found in image i, or None.

    A hit on a positive image counts only inside one of its boxes; a hit elsewhere is both a
    false positive and a false negative.
    """
    tp = fp = fn = tn = near_fp = near = 0
    for image, hit in zip(images, hits):
        near += image.label == 'near-red'
        if positive(image):
            if hit is not None and in_boxes(hit[0], hit[1], image.boxes):
                tp += 1
            else:
                fn += 1
                fp += hit is not None
        elif hit is not None:
            fp += 1
            near_fp += image.label == 'near-red'
        else:
            tn += 1
    return Scores(tp, fp, fn, tn, near_fp, near)


@dataclass(frozen=True)
class Decision:
    """What a detector said about one image: the point it reports (px; None: nothing found)
    and its confidence that it is the can (0-1)."""

    point: Optional[Tuple[float, float]]
    confidence: float


def found_scores(images: Sequence[LabelledImage], decisions: Sequence[Decision]) -> Scores:
    """Scores of "is there a red object, and where": red images are the positives."""
    return score(images, [decision.point for decision in decisions],
                 lambda image: image.label == 'red')


def can_scores(images: Sequence[LabelledImage], decisions: Sequence[Decision],
               min_confidence: float) -> Scores:
    """Scores of "this is the can" (found with confidence >= ``min_confidence``): rendered red
    cans are the positives, every other image (red photographs included) a negative."""
    return score(images, [decision.point if decision.point is not None
                          and decision.confidence >= min_confidence else None
                          for decision in decisions], lambda image: image.is_can)


def build_set(world, pose, intrinsics) -> List[LabelledImage]:
    """The photographs (raises FileNotFoundError naming a missing package) and the renders."""
    return load_photos() + render_cans(world, pose, intrinsics)


def detector_decisions(images: Sequence[LabelledImage],
                       settings: Optional[DetectorSettings] = None) -> List[Decision]:
    """The detector (at ``settings``, else its defaults) and the report, with the camera
    geometry of renders."""
    detector = RedCanDetector(settings)
    decisions = []
    for image in images:
        result = detector.detect(image.bgr)
        height, width = image.bgr.shape[:2]
        report = can_report(result.candidates, width, height, image.pose, image.intrinsics,
                            CanModel())
        decisions.append(Decision((report.centroid_x, report.centroid_y) if report.found
                                  else None, report.confidence))
    return decisions
