"""Red mask, clean-up, candidate blobs with shape scores and moments centroid on synthetic
images."""
import dataclasses

import cv2
import numpy as np
import pytest

from can_seeker.vision.detector import (DETECTOR_PARAMS, DetectorSettings, MaskScratch,
                                        RedCanDetector, centroid_from_moments, draw_annotation,
                                        red_blobs, red_mask, shape_score)

WIDTH, HEIGHT = 320, 240
SUBPIXEL_BITS = 4


def hsv_colour(hue, saturation, value):
    """BGR tuple of an OpenCV HSV colour."""
    pixel = cv2.cvtColor(np.uint8([[[hue, saturation, value]]]), cv2.COLOR_HSV2BGR)[0, 0]
    return tuple(int(channel) for channel in pixel)


def scene(background=(128, 128, 128), width=WIDTH, height=HEIGHT):
    return np.full((height, width, 3), background, np.uint8)


def draw_disk(image, centre, radius, colour):
    """Anti-aliased disk at a sub-pixel centre (px)."""
    scale = 1 << SUBPIXEL_BITS
    cv2.circle(image, (int(round(centre[0] * scale)), int(round(centre[1] * scale))),
               int(round(radius * scale)), colour, -1, cv2.LINE_AA, SUBPIXEL_BITS)
    return image


def add_noise(image, sigma, seed=0):
    noise = np.random.default_rng(seed).normal(0.0, sigma, image.shape)
    return np.clip(image + noise, 0, 255).astype(np.uint8)


def detect(image):
    return RedCanDetector().detect(image)


@pytest.mark.parametrize('hue', [0, 4, 175, 179])
def test_red_disk_found_with_subpixel_centroid(hue):
    centre = (141.3, 97.6)
    image = add_noise(draw_disk(scene(), centre, 22, hsv_colour(hue, 230, 200)), 6)
    result = detect(image)
    assert result.found
    assert abs(result.blob.centroid_x - centre[0]) <= 0.5
    assert abs(result.blob.centroid_y - centre[1]) <= 0.5
    assert result.blob.area == pytest.approx(np.pi * 22 ** 2, rel=0.08)


def test_bounding_box_encloses_the_disk():
    blob = detect(draw_disk(scene(), (100, 120), 20, (0, 0, 220))).blob
    assert blob.x == pytest.approx(80, abs=1)
    assert blob.y == pytest.approx(100, abs=1)
    assert blob.width == pytest.approx(41, abs=2)
    assert blob.height == pytest.approx(41, abs=2)


@pytest.mark.parametrize('name, bgr', [
    ('dark red in shade', (15, 15, 90)),
    ('crimson', (60, 20, 220)),
    ('washed-out red', (70, 65, 200)),
    ('red in warm light', (20, 55, 240)),
    ('coke red', (36, 30, 228)),
])
def test_shades_of_red_are_found(name, bgr):
    result = detect(add_noise(draw_disk(scene((90, 110, 120)), (200, 60), 25, bgr), 5))
    assert result.found, name
    assert np.hypot(result.blob.centroid_x - 200, result.blob.centroid_y - 60) < 1.0


@pytest.mark.parametrize('name, bgr', [
    ('orange, hue 15', hsv_colour(15, 255, 255)),
    ('red-orange overalls, hue 9', (30, 90, 230)),
    ('tomato (CSS), orange-red', (71, 99, 255)),
    ('pink tongue', (120, 100, 220)),
    ('magenta heather', (150, 60, 170)),
    ('reddish-brown in shade, hue 8', (15, 40, 110)),
    ('magenta, hue 150', hsv_colour(150, 255, 255)),
    ('hot pink', (180, 105, 255)),
    ('saddle brown', (19, 69, 139)),
    ('walnut wood', (43, 67, 93)),
    ('pine wood', (135, 184, 222)),
    ('light skin', (172, 219, 255)),
    ('medium skin', (105, 172, 224)),
    ('dark skin', (36, 85, 141)),
    ('pinkish skin', (148, 160, 229)),
    ('flushed skin', (120, 140, 220)),
    ('pink-ish wall', (200, 200, 235)),
    ('grey', (128, 128, 128)),
    ('white', (255, 255, 255)),
])
def test_non_red_colours_are_not_found(name, bgr):
    image = add_noise(draw_disk(scene((200, 200, 200)), (160, 120), 60, bgr), 6)
    assert not detect(image).found, name


def test_plain_skin_scene_with_lighting_gradient_is_not_found():
    rows = np.linspace(0.55, 1.0, HEIGHT)[:, None, None]
    skin = np.array((120, 160, 225), float) * rows * np.ones((1, WIDTH, 1))
    assert not detect(add_noise(skin, 8)).found


def test_red_object_under_lighting_gradient_is_found_on_it():
    image = scene((60, 90, 110))
    cv2.rectangle(image, (40, 50), (150, 200), (30, 30, 200), -1)
    columns = np.linspace(0.4, 1.0, WIDTH)[None, :, None]
    image = add_noise(image * columns, 6)
    blob = detect(image).blob
    assert blob is not None
    assert 40 <= blob.centroid_x <= 150 and 50 <= blob.centroid_y <= 200


@pytest.mark.parametrize('image', [
    np.zeros((0, 0, 3), np.uint8),
    np.zeros((HEIGHT, WIDTH, 3), np.uint8),
    np.full((HEIGHT, WIDTH, 3), 255, np.uint8),
])
def test_empty_black_or_white_image_is_not_found(image):
    result = RedCanDetector().detect(image, want_edges=True)
    assert not result.found
    assert result.mask.shape == image.shape[:2]
    assert result.edges.shape == image.shape[:2]


def test_speckle_noise_is_removed():
    rng = np.random.default_rng(1)
    image = scene()
    rows, columns = rng.integers(0, HEIGHT, 400), rng.integers(0, WIDTH, 400)
    image[rows, columns] = (0, 0, 255)
    result = detect(image)
    assert not result.found
    assert np.count_nonzero(result.mask) == 0


@pytest.mark.parametrize('open_px, close_px', [(3, 7), (1, 8), (4, 1), (5, 11)])
def test_clean_mask_equals_cleaning_the_whole_image(open_px, close_px):
    """Cleaning only the box around the red pixels gives the full-image result, with blobs
    and speckles anywhere (at the image edges too) and odd or even kernels."""
    rng = np.random.default_rng(open_px * 100 + close_px)
    detector = RedCanDetector(dataclasses.replace(DetectorSettings.defaults(),
                                                  open_kernel_px=open_px,
                                                  close_kernel_px=close_px))
    _, open_kernel, close_kernel = detector._config
    for trial in range(200):
        height, width = (int(side) for side in rng.integers(10, 90, 2))
        mask = np.zeros((height, width), np.uint8)
        for _ in range(int(rng.integers(0, 4))):
            x, y, w, h = (int(value) for value in rng.integers(0, 30, 4))
            mask[y:y + h + 1, x:x + w + 1] = 255
        mask[rng.random((height, width)) < rng.choice([0.0, 0.002, 0.05])] = 255
        expected = mask
        for operation, kernel in ((cv2.MORPH_OPEN, open_kernel), (cv2.MORPH_CLOSE, close_kernel)):
            if kernel is not None:
                expected = cv2.morphologyEx(expected, operation, kernel)
        detector.detect(np.zeros((height, width, 3), np.uint8))
        assert np.array_equal(detector.clean_mask(mask, open_kernel, close_kernel), expected), trial


def test_speckles_do_not_move_the_centroid():
    image = draw_disk(scene(), (250.0, 180.0), 15, (0, 0, 230))
    rng = np.random.default_rng(2)
    image[rng.integers(0, HEIGHT, 300), rng.integers(0, WIDTH, 300)] = (0, 0, 255)
    blob = detect(image).blob
    assert abs(blob.centroid_x - 250.0) <= 0.5 and abs(blob.centroid_y - 180.0) <= 0.5


def test_specular_highlight_inside_the_can_is_filled():
    image = draw_disk(scene(), (160.0, 120.0), 30, (0, 0, 210))
    image[110:113, 150:153] = 255
    blob = detect(image).blob
    assert blob.area == pytest.approx(np.pi * 30 ** 2, rel=0.05)


def test_largest_of_two_blobs_wins():
    image = draw_disk(draw_disk(scene(), (60, 60), 10, (0, 0, 220)), (220, 150), 25, (0, 0, 220))
    blob = detect(image).blob
    assert blob.centroid_x == pytest.approx(220, abs=0.5)
    assert blob.centroid_y == pytest.approx(150, abs=0.5)


def test_blob_below_the_minimum_area_is_ignored():
    image = draw_disk(scene(), (60, 60), 3, (0, 0, 220))
    assert not detect(image).found
    settings = DetectorSettings.defaults()
    detector = RedCanDetector(DetectorSettings(**dict(settings.__dict__, min_area_fraction=0.0)))
    assert detector.detect(image).found


def test_ratios_widen_the_red_range():
    orange_red = draw_disk(scene(), (100, 100), 20, (20, 90, 230))
    assert not detect(orange_red).found
    values = dict(DetectorSettings.defaults().__dict__, green_max_ratio=0.5, orange_max_ratio=0.5)
    blob = RedCanDetector(DetectorSettings(**values)).detect(orange_red).blob
    assert blob.centroid_x == pytest.approx(100, abs=0.5)


def test_settings_can_be_replaced_between_frames():
    image = draw_disk(scene(), (100, 100), 20, hsv_colour(175, 255, 200))
    detector = RedCanDetector()
    assert detector.detect(image).found
    detector.settings = DetectorSettings(**dict(detector.settings.__dict__, blue_max_ratio=0.1))
    assert not detector.detect(image).found


@pytest.mark.parametrize('bgr, red', [
    ((0, 0, 200), True), ((60, 50, 200), True), ((89, 69, 200), True),
    ((91, 40, 200), False), ((30, 71, 200), False), ((0, 41, 200), False),
    ((5, 5, 29), False), ((5, 5, 31), True), ((255, 255, 255), False), ((0, 0, 0), False)])
def test_red_mask_is_the_chromaticity_decision(bgr, red):
    """Defaults: green <= 0.35 R, blue <= 0.45 R, green - blue <= 0.2 R, R >= 30."""
    image = np.full((3, 4, 3), bgr, np.uint8)
    assert np.all(red_mask(image, DetectorSettings.defaults()) == (255 if red else 0)), bgr


def test_red_mask_matches_the_decision_on_random_pixels():
    """Every pixel of random colours is decided as the documented tests say, but for those
    within half a grey level of a threshold (rounding)."""
    settings = DetectorSettings.defaults()
    image = np.random.default_rng(7).integers(0, 256, (120, 160, 3), dtype=np.uint8)
    blue, green, red = (image[..., channel].astype(float) for channel in range(3))
    slack = np.stack([settings.green_max_ratio * red - green,
                      settings.blue_max_ratio * red - blue,
                      settings.orange_max_ratio * red - (green - blue)])
    expected = np.all(slack >= 0, axis=0) & (red >= settings.value_min)
    decided = np.all(np.abs(slack) > 0.5, axis=0)
    mask = red_mask(image, settings)
    assert expected[decided].sum() > 500
    assert np.array_equal(mask[decided] == 255, expected[decided])


def test_red_mask_reuses_its_scratch_buffers_and_reads_strided_images():
    image = draw_disk(scene(), (100, 100), 20, (0, 0, 220))
    scratch = MaskScratch(HEIGHT, WIDTH)
    mask = red_mask(image, DetectorSettings.defaults(), scratch)
    assert mask is scratch.mask
    assert mask[100, 100] == 255 and mask[10, 10] == 0
    padded = np.zeros((HEIGHT, WIDTH + 3, 3), np.uint8)
    padded[:, :WIDTH] = image
    assert np.array_equal(red_mask(padded[:, :WIDTH], DetectorSettings.defaults()), mask)


def test_buffers_follow_a_change_of_image_size():
    detector = RedCanDetector()
    small = detector.detect(draw_disk(scene(), (50, 50), 10, (0, 0, 220))).blob
    large = detector.detect(draw_disk(scene(width=640, height=480), (400, 300), 30,
                                      (0, 0, 220))).blob
    assert (small.centroid_x, large.centroid_x) == (pytest.approx(50, abs=0.5),
                                                    pytest.approx(400, abs=0.5))


@pytest.mark.parametrize('method', ['canny', 'sobel', 'laplacian'])
def test_edges_lie_on_the_disk_outline(method):
    settings = DetectorSettings(**dict(DetectorSettings.defaults().__dict__, edge_method=method))
    image = draw_disk(scene((40, 40, 40)), (160, 120), 40, (220, 220, 220))
    edges = RedCanDetector(settings).detect(image, want_edges=True).edges
    assert edges.dtype == np.uint8 and edges.shape == (HEIGHT, WIDTH)
    rows, columns = np.nonzero(edges > 40)
    radii = np.hypot(columns - 160, rows - 120)
    assert len(radii) > 100
    assert np.all(np.abs(radii - 40) < 3)


def test_edges_are_skipped_unless_wanted():
    assert RedCanDetector().detect(scene()).edges is None


def test_centroid_from_moments_guards_empty_region():
    assert centroid_from_moments(cv2.moments(np.zeros((5, 5), np.uint8))) is None
    region = np.zeros((5, 5), np.uint8)
    region[1, 3] = 1
    assert centroid_from_moments(cv2.moments(region, binaryImage=True)) == (3.0, 1.0)


def test_blobs_of_empty_mask_are_none():
    assert red_blobs(np.zeros((10, 10), np.uint8), 1.0) == []


def can_silhouette(image, left, top, width, height, colour=(0, 0, 220)):
    """An upright can seen from slightly above: a box with an elliptic top and bottom."""
    ends = max(2, width // 5)
    cv2.rectangle(image, (left, top + ends), (left + width - 1, top + height - 1 - ends), colour,
                  -1)
    for row in (top + ends, top + height - 1 - ends):
        cv2.ellipse(image, (left + width // 2, row), (width // 2, ends), 0, 0, 360, colour, -1)
    return image


def test_a_can_silhouette_scores_high_and_other_shapes_low():
    image = scene()
    can_silhouette(image, 40, 60, 30, 58)
    cv2.rectangle(image, (120, 40), (220, 70), (0, 0, 220), -1)           # lying bar
    cv2.circle(image, (270, 180), 25, (0, 0, 220), -1)                     # ball
    ring = cv2.ellipse(np.zeros_like(image), (150, 180), (40, 40), 0, 0, 300, (0, 0, 220), 12)
    image = np.maximum(image, ring)                                        # open ring
    scores = {(round(blob.centroid_x / 10), round(blob.centroid_y / 10)): blob.shape_score
              for blob in detect(image).candidates}
    can = scores.pop((5, 9))
    assert can > 0.9
    assert max(scores.values()) < 0.3, scores


def test_shape_score_parts():
    assert shape_score(1.0, 0.9, 1.85, 0.0, ()) == 1.0
    assert shape_score(0.7, 0.9, 1.85, 0.0, ()) == 0.0         # concave
    assert shape_score(1.0, 0.5, 1.85, 0.0, ()) == 0.0         # does not fill its box
    assert shape_score(1.0, 0.9, 0.9, 0.0, ()) == 0.0          # wider than tall
    assert shape_score(1.0, 0.9, 5.0, 0.0, ()) == 0.0          # a pole
    assert shape_score(1.0, 0.9, 1.85, 35.0, ()) == 0.0        # leaning
    assert shape_score(1.0, 0.9, 1.85, 12.0, ()) == 1.0        # perspective near the side
    assert shape_score(1.0, 0.9, 0.9, 0.0, ('top',)) == pytest.approx(0.75)  # height unknown
    assert shape_score(1.0, 0.9, 3.0, 0.0, ('left', 'bottom')) == pytest.approx(0.5625)


def test_the_foot_of_a_can_cut_at_the_top_is_not_judged_by_its_long_axis():
    """A camera 0.15 m up pitched 35 deg down sees the floor only to 0.68 m: a can 0.45-0.6 m
    away shows its foot, cut at the top and wider than tall, whose long axis lies across (tilt
    90 deg). It scored 0, so the can was never taken for one there; its size is checked against
    its floor range instead."""
    assert shape_score(1.0, 0.93, 0.5, 90.0, ('top',)) == pytest.approx(0.75)
    assert shape_score(1.0, 0.93, 0.5, 90.0, ('bottom',)) == 0.0
    assert shape_score(1.0, 0.93, 0.5, 90.0, ()) == 0.0


def test_tilted_bar_is_not_upright():
    image = scene()
    box = cv2.boxPoints(((160, 120), (24, 70), 45.0)).astype(np.int32)
    cv2.fillPoly(image, [box], (0, 0, 220))
    blob = detect(image).blob
    assert blob.tilt_deg == pytest.approx(45.0, abs=3.0)
    assert blob.shape_score == 0.0


def test_candidates_are_the_largest_first_and_cut_sides_are_named():
    image = draw_disk(scene(), (10, 120), 25, (0, 0, 220))
    can_silhouette(image, 200, 50, 20, 40)
    candidates = detect(image).candidates
    assert [blob.cut for blob in candidates] == [('left',), ()]
    assert candidates[0].area > candidates[1].area


def test_annotation_marks_the_centroid_and_leaves_the_input_alone():
    image = draw_disk(scene(), (160, 120), 30, (0, 0, 220))
    original = image.copy()
    result = detect(image)
    annotated = draw_annotation(image, result, [0.25], 0, 0.42)
    assert np.array_equal(image, original)
    assert annotated.shape == image.shape and annotated.dtype == np.uint8
    assert tuple(annotated[120, 160]) == (0, 255, 0)
    assert not np.array_equal(annotated[0:40, 0:150], image[0:40, 0:150])
    out = np.zeros_like(image)
    assert draw_annotation(image, result, [0.25], 0, 0.42, out=out) is out
    assert np.array_equal(out, annotated)


def test_annotation_writes_every_candidates_score():
    image = draw_disk(draw_disk(scene(), (60, 60), 15, (0, 0, 220)), (220, 150), 25,
                      (0, 0, 220))
    result = detect(image)
    low = draw_annotation(image, result, [0.0, 0.0], None, float('nan'))
    high = draw_annotation(image, result, [0.0, 0.75], None, float('nan'))
    for index, blob in enumerate(result.candidates):
        label = (slice(max(0, blob.y - 16), blob.y), slice(blob.x, blob.x + 40))
        assert np.any(low[label] > 200), blob
        assert np.array_equal(low[label], high[label]) == (index == 0), blob


def test_annotation_without_a_blob_or_range():
    image = scene()
    assert draw_annotation(image, detect(image), [], None, float('nan')).shape == image.shape
    red = draw_disk(scene(), (160, 120), 30, (0, 0, 220))
    assert draw_annotation(red, detect(red), [1.0], 0, float('nan')).shape == image.shape


def test_settings_fields_start_with_the_parameters():
    fields = list(DetectorSettings.__dataclass_fields__)
    assert fields[:len(DETECTOR_PARAMS)] == [spec.name for spec in DETECTOR_PARAMS]
    defaults = DetectorSettings.defaults()
    for spec in DETECTOR_PARAMS:
        assert spec.coerce(getattr(defaults, spec.name)) == spec.default


def test_hole_in_the_blob_is_not_counted():
    image = draw_disk(scene(), (160.0, 120.0), 40, (0, 0, 220))
    draw_disk(image, (160.0, 120.0), 20, (128, 128, 128))
    blob = detect(image).blob
    assert blob.area == pytest.approx(np.pi * (40 ** 2 - 20 ** 2), rel=0.05)
    assert (blob.centroid_x, blob.centroid_y) == (pytest.approx(160.0, abs=0.5),
                                                  pytest.approx(120.0, abs=0.5))


def test_red_can_through_jpeg_compression_is_found_on_it():
    image = scene((70, 100, 120))
    cv2.rectangle(image, (180, 60), (215, 150), (40, 35, 185), -1)
    image[60:150, 195:199] = (200, 200, 235)
    _, encoded = cv2.imencode('.jpg', add_noise(image, 4), [cv2.IMWRITE_JPEG_QUALITY, 40])
    blob = detect(cv2.imdecode(encoded, cv2.IMREAD_COLOR)).blob
    assert blob is not None
    assert abs(blob.centroid_x - 197.5) < 3.0 and abs(blob.centroid_y - 105.0) < 3.0
