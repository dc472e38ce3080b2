"""vision_quality: precision and recall of the red detector on the labelled set.

Builds the set of evaluation/labelled_images.py (photographs from Debian's opencv-doc,
python3-skimage and matplotlib sample data; cans rendered in the pybullet world under several
lights) and prints, for the detector with each colour model (chromaticity, hsv) and for the
previous detector's HSV box (hue 168-6, saturation >= 130, value >= 50, largest blob), how well
``found`` answers "is there a red object, and where", and how well ``found and confidence >=
MIN_CONFIDENCE`` (the confidence can_stopper acts on) answers "this is the can". ``--param
NAME=VALUE`` sets a detector parameter for both models (e.g. saturation_min=100); ``--list``
names the images each gets wrong.
"""
import argparse
import sys

import cv2

from can_seeker.camera_geometry import camera_pose_from_mount
from can_seeker.camera_mount import CameraMount
from can_seeker.control.tuning import MIN_CONFIDENCE
from can_seeker.evaluation.labelled_images import (Decision, build_set, can_scores,
                                                   detector_decisions, found_scores, in_boxes)
from can_seeker.params import read_params
from can_seeker.ros.paths import urdf_path
from can_seeker.sim.world import CameraSpec, World
from can_seeker.vision.detector import (COLOUR_MODELS, DETECTOR_PARAMS, DetectorSettings,
                                        red_blobs)

PREVIOUS_HSV_RANGES = (((168, 130, 50), (179, 255, 255)), ((0, 130, 50), (6, 255, 255)))
PREVIOUS_KERNELS = (cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3)),
                    cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5)))


def previous_decisions(images):
    """The previous detector: one HSV box, opening 3 px, closing 5 px, the largest blob."""
    open_kernel, close_kernel = PREVIOUS_KERNELS
    decisions = []
    for image in images:
        hsv = cv2.cvtColor(image.bgr, cv2.COLOR_BGR2HSV)
        mask = cv2.bitwise_or(*[cv2.inRange(hsv, low, high) for low, high in PREVIOUS_HSV_RANGES])
        mask = cv2.morphologyEx(cv2.morphologyEx(mask, cv2.MORPH_OPEN, open_kernel),
                                cv2.MORPH_CLOSE, close_kernel)
        blobs = red_blobs(mask, max(1.0, 0.0005 * mask.size))
        decisions.append(Decision((blobs[0].centroid_x, blobs[0].centroid_y) if blobs else None,
                                  1.0))
    return decisions


def detector_settings(pairs):
    """{colour model: DetectorSettings} at the defaults with the NAME=VALUE overrides (an
    unknown name or a bad value is an error: a measurement must run what was asked for)."""
    overrides = {}
    known = {spec.name for spec in DETECTOR_PARAMS}
    for pair in pairs:
        name, _, value = pair.partition('=')
        name = name.strip()
        if name not in known or name == 'colour_model':
            raise SystemExit('vision_quality: --param %s: expected one of %s' % (
                pair, ', '.join(sorted(known - {'colour_model'}))))
        overrides['~' + name] = value.strip()

    def refuse(text):
        raise SystemExit('vision_quality: ' + text)

    values = read_params(DETECTOR_PARAMS, lambda name, default: overrides.get(name, default),
                         refuse)
    return {model: DetectorSettings(**dict(DetectorSettings.from_values(values).__dict__,
                                           colour_model=model)) for model in COLOUR_MODELS}


def wrong(images, decisions, min_confidence):
    """Names of images a decision gets wrong, with what it said."""
    lines = []
    for image, decision in zip(images, decisions):
        point = decision.point
        right_place = point is not None and in_boxes(point[0], point[1], image.boxes)
        if image.label == 'red' and not right_place:
            lines.append('missed or elsewhere: %s (%s) at %s' % (image.name, image.note, point))
        elif image.label != 'red' and point is not None:
            lines.append('false red: %s (%s)' % (image.name, image.note))
        if image.is_can and (not right_place or decision.confidence < min_confidence):
            lines.append('can not accepted: %s, confidence %.2f' % (image.name,
                                                                    decision.confidence))
    return lines


def scores_row(name, subset, scores):
    return '| %s | %s | %d | %d | %d | %.2f | %.2f | %d / %d |' % (
        name, subset, scores.true_positives, scores.false_positives, scores.false_negatives,
        scores.precision, scores.recall, scores.near_red_false_positives, scores.near_red_images)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--min-confidence', type=float,
                        default=MIN_CONFIDENCE,
                        help='the confidence can_stopper acts on (default %(default)s)')
    parser.add_argument('--list', action='store_true', help='list the images each gets wrong')
    parser.add_argument('--param', action='append', default=[], metavar='NAME=VALUE',
                        help='set a detector parameter for both colour models (repeatable), '
                             'e.g. hue_max=8')
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    settings = detector_settings(args.param)
    camera = CameraSpec(320, 240, 45.0, CameraMount(0.25, 25.0))
    with World(urdf_path(), camera) as world:
        images = build_set(world, camera_pose_from_mount(camera.mount), camera.intrinsics)
    photos = [image for image in images if image.pose is None]
    renders = [image for image in images if image.pose is not None]
    print('Labelled set: %d photographs (%d red, %d near-red, %d none), %d renders (%d red cans, '
          '%d near-red cans, %d empty floors)' % (
              len(photos), sum(image.label == 'red' for image in photos),
              sum(image.label == 'near-red' for image in photos),
              sum(image.label == 'none' for image in photos), len(renders),
              sum(image.is_can for image in renders),
              sum(image.label == 'near-red' for image in renders),
              sum(image.label == 'none' for image in renders)))
    print('| decision | images | TP | FP | FN | precision | recall | near-red FP |')
    print('|---|---|---|---|---|---|---|---|')
    decisions = {'previous HSV box': previous_decisions(images)}
    for model in COLOUR_MODELS:
        decisions[model] = detector_decisions(images, settings[model])
    for name in decisions:
        for subset_name, subset in (('photographs', photos), ('renders', renders)):
            chosen = [decisions[name][images.index(image)] for image in subset]
            print(scores_row('found, ' + name, subset_name, found_scores(subset, chosen)))
    print(scores_row('the can: found, previous HSV box (no confidence)', 'all',
                     can_scores(images, decisions['previous HSV box'], 0.0)))
    for model in COLOUR_MODELS:
        print(scores_row('the can: found and confidence >= %.2f, %s' % (args.min_confidence,
                                                                         model), 'all',
                         can_scores(images, decisions[model], args.min_confidence)))
    if args.list:
        for name in decisions:
            print('\n%s:' % name)
            for line in wrong(images, decisions[name], args.min_confidence):
                print('- ' + line)
