"""The detector on the labelled set: real photographs from Debian packages and rendered cans.

The set is small (see evaluation/labelled_images.py); these are floors under what the
detector does on it today, so a change that loses red objects or takes near-red ones (orange,
pink, magenta, brown, skin) for the can fails here. `rosrun can_seeker vision_quality --list`
prints the full table.
"""
import pathlib

import pytest

from can_seeker.camera_geometry import camera_pose_from_mount
from can_seeker.camera_mount import CameraMount
from can_seeker.evaluation.labelled_images import (PHOTOS, can_scores, detector_decisions,
                                                   found_scores, in_boxes, load_photos,
                                                   render_cans)
from can_seeker.sim.world import CameraSpec, World

URDF = str(pathlib.Path(__file__).resolve().parents[2] / 'urdf' / 'can_seeker_robot.urdf')
CAMERA = CameraSpec(320, 240, 45.0, CameraMount(0.25, 25.0))


@pytest.fixture(scope='module')
def photos():
    """The photographs; skipped (saying which package is missing) on a machine set up without
    tools/apt-packages.txt, e.g. through rosdep."""
    try:
        return load_photos()
    except FileNotFoundError as error:
        pytest.skip(str(error))


@pytest.fixture(scope='module')
def renders():
    with World(URDF, CAMERA) as world:
        return render_cans(world, camera_pose_from_mount(CAMERA.mount), CAMERA.intrinsics)


def test_every_photo_is_installed_and_labelled(photos):
    assert len(photos) == len(PHOTOS)
    assert {photo.label for photo in PHOTOS} == {'red', 'near-red', 'none'}
    for photo, image in zip(PHOTOS, photos):
        height, width = image.bgr.shape[:2]
        assert (photo.label == 'red') == bool(photo.boxes), photo.name
        for x, y, box_width, box_height in photo.boxes:
            assert 0 <= x < width and 0 <= y < height, photo.name


def test_boxes_hold_points_inside_only():
    assert in_boxes(10, 10, [(5, 5, 10, 10)]) and not in_boxes(15, 10, [(5, 5, 10, 10)])


def test_rendered_red_cans_are_boxed_and_near_red_cans_are_not(renders):
    assert len([image for image in renders if image.is_can]) == 40
    assert all(image.boxes for image in renders if image.is_can)
    labels = {image.label for image in renders}
    assert labels == {'red', 'near-red', 'none'}


def test_red_photographs_are_found_on_the_red_object(photos):
    scores = found_scores(photos, detector_decisions(photos))
    assert scores.recall == 1.0
    assert scores.near_red_false_positives <= 2, 'more near-red photographs taken for red'
    assert scores.false_positives <= 2


def test_rendered_cans_are_found_and_near_red_cans_are_not(renders):
    scores = found_scores(renders, detector_decisions(renders))
    assert (scores.recall, scores.false_positives) == (1.0, 0)


def test_only_rendered_cans_are_taken_for_the_can(photos, renders):
    images = photos + renders
    scores = can_scores(images, detector_decisions(images), 0.5)
    assert scores.recall >= 0.95
    assert scores.false_positives == 0
