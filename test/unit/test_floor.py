"""Floor / obstacle classification on synthetic images: light and dark floors, texture,
adaptation, and the tutorial's dark-threshold baseline."""
import cv2
import numpy as np
import pytest

from can_seeker.vision.floor import (VALUE_BIN_LUT, VALUE_BINS, FloorClassifier, FloorSettings,
                                     fill_holes, floor_blends, reference_trapezoid)

WIDTH, HEIGHT = 320, 240
BOX = (120, 60, 200, 140)
"""An obstacle well above the reference area: x0, y0, x1, y1 (px, exclusive ends)."""


def floor_image(floor_bgr, sigma=4.0, seed=0):
    rng = np.random.default_rng(seed)
    image = np.asarray(floor_bgr, np.float64) + rng.normal(0.0, sigma, (HEIGHT, WIDTH, 3))
    return np.clip(image, 0, 255).astype(np.uint8)


def with_box(image, colour, box=BOX):
    x0, y0, x1, y1 = box
    image = image.copy()
    image[y0:y1, x0:x1] = colour
    return image


def box_recall_and_false_rate(mask, box=BOX, blur_px=2):
    """Fraction of the box found as obstacle, fraction of the floor (farther than the
    smoothing's reach ``blur_px`` from the box) wrongly marked."""
    x0, y0, x1, y1 = box
    inside = np.zeros(mask.shape, bool)
    inside[y0:y1, x0:x1] = True
    near = np.zeros(mask.shape, bool)
    near[max(0, y0 - blur_px):y1 + blur_px, max(0, x0 - blur_px):x1 + blur_px] = True
    return (mask[inside] > 0).mean(), (mask[~near] > 0).mean()


@pytest.mark.parametrize('floor,obstacle', [
    ((200, 200, 195), (40, 40, 40)),      # dark box on a light floor (the tutorial's case)
    ((45, 40, 40), (220, 220, 215)),      # light box on a dark floor
    ((60, 110, 160), (160, 110, 60)),     # blue box on a brown floor of the same brightness
    ((150, 150, 150), (60, 170, 60)),     # green box on a grey floor
])
def test_adaptive_model_finds_obstacles_of_any_contrast(floor, obstacle):
    mask = FloorClassifier().classify(with_box(floor_image(floor), obstacle))
    recall, false_rate = box_recall_and_false_rate(mask)
    assert recall > 0.98
    assert false_rate < 0.002


def test_textured_floor_is_floor():
    """A fine two-colour carpet pattern with noise: both colours are floor, the box is not."""
    rng = np.random.default_rng(3)
    pattern = rng.random((HEIGHT // 4, WIDTH // 4)) < 0.5
    pattern = np.kron(pattern, np.ones((4, 4), bool))
    image = floor_image((90, 120, 150), sigma=8.0)
    image[pattern] = floor_image((150, 160, 170), sigma=8.0, seed=1)[pattern]
    mask = FloorClassifier().classify(with_box(image, (30, 30, 110)))
    recall, false_rate = box_recall_and_false_rate(mask)
    assert recall > 0.95
    assert false_rate < 0.005


def test_dark_baseline_misses_light_obstacles_on_a_dark_floor():
    dark = FloorClassifier(FloorSettings(floor_model='dark'))
    light_floor_mask = dark.classify(with_box(floor_image((200, 200, 195)), (40, 40, 40)))
    assert box_recall_and_false_rate(light_floor_mask) == (pytest.approx(1.0), 0.0)
    dark_floor_mask = dark.classify(with_box(floor_image((45, 40, 40)), (220, 220, 215)))
    assert box_recall_and_false_rate(dark_floor_mask)[1] > 0.9


def test_ignored_pixels_are_never_obstacles():
    image = with_box(floor_image((200, 200, 195)), (40, 40, 40))
    ignore = np.zeros((HEIGHT, WIDTH), np.uint8)
    ignore[:, :160] = 255
    mask = FloorClassifier().classify(image, ignore)
    assert not mask[:, :160].any()
    assert mask[60:140, 165:200].all()


def test_small_specks_are_noise():
    image = floor_image((200, 200, 195))
    for x, y in ((50, 50), (100, 200), (300, 20), (160, 120)):
        image[y:y + 2, x:x + 2] = 0
    assert not FloorClassifier().classify(image).any()


def reference_mask():
    import cv2
    mask = np.zeros((HEIGHT, WIDTH), np.uint8)
    cv2.fillConvexPoly(mask, reference_trapezoid(WIDTH, HEIGHT, 0.2), 255)
    return mask > 0


def test_model_adapts_to_slow_lighting_changes():
    classifier = FloorClassifier()
    for step in range(80):
        brightness = 200 - step
        image = with_box(floor_image((brightness,) * 3, seed=step), (40, 40, 40))
        mask = classifier.classify(image)
    recall, false_rate = box_recall_and_false_rate(mask)
    assert recall > 0.98 and false_rate < 0.002
    assert FloorClassifier(FloorSettings(adapt_rate=0.0)).classify(
        floor_image((200,) * 3)).sum() == 0


def test_an_obstacle_in_the_reference_area_is_never_learned():
    """A wall creeping into the bottom of the image stays an obstacle frame after frame."""
    classifier = FloorClassifier()
    classifier.classify(floor_image((200, 200, 195)))
    reference = reference_mask()
    for step in range(60):
        bottom = 170 + step
        image = with_box(floor_image((200, 200, 195), seed=step), (60, 60, 60),
                         (0, 0, WIDTH, bottom))
        mask = classifier.classify(image)
        assert mask[:bottom - 1].all()
        assert not mask[bottom + 2:].any()
    in_reference = reference[:bottom].sum() / reference.sum()
    assert in_reference > 0.3
    assert not classifier.model_updated


def _corner_shading(image, darkening):
    """``image`` darkened smoothly toward the top-right corner by up to ``darkening`` (a
    vignetting-like fall-off: a few grey levels per pixel at most)."""
    height, width = image.shape[:2]
    rows, columns = np.mgrid[0:height, 0:width]
    radius = np.hypot(rows / height, (width - 1 - columns) / width)
    gain = 1.0 - darkening * np.clip(1.0 - radius / 0.7, 0.0, 1.0) ** 2
    return np.clip(image * gain[:, :, None], 0, 255).astype(np.uint8)


def test_smooth_shading_is_floor_but_an_object_of_the_same_darkness_is_not():
    floor = np.full((240, 320, 3), (235, 238, 240), np.uint8)
    classifier = FloorClassifier()
    classifier.classify(floor)
    shaded = _corner_shading(floor.astype(float), 0.35)
    assert shaded[0, -1].mean() < 160
    assert not classifier.classify(shaded).any()
    boxed = floor.copy()
    boxed[10:60, 250:310] = shaded[10:60, 250:310].mean(axis=(0, 1))
    assert classifier.classify(boxed)[20:50, 260:300].all()
    off = FloorClassifier(FloorSettings(min_edge_contrast=0.0))
    off.classify(floor)
    assert off.classify(shaded).any()


def test_a_wall_with_floor_coloured_seams_is_an_obstacle():
    """A wall 9 grey levels darker than a plain floor, its edge soft over 4 rows, with
    rendered seams a few levels off the floor along it (as pybullet draws a wall head-on): the
    seams are holes in the wall's region, and their faint outlines must not outweigh the
    wall's own edge with the floor, or the whole wall is dismissed as shading."""
    floor = np.full((HEIGHT, WIDTH, 3), 56, np.uint8)
    classifier = FloorClassifier()
    classifier.classify(floor)
    rows = np.arange(HEIGHT, dtype=np.float64)[:, None, None]
    image = np.clip(47.0 + (rows - 100.0) * 9.0 / 4.0, 47.0, 56.0) * np.ones((1, WIDTH, 3))
    for row in range(10, 90, 8):
        for column in range(5, WIDTH - 5, 16):
            image[row:row + 2, column:column + 10] = 52.0
    mask = classifier.classify(image.round().astype(np.uint8))
    wall = np.ones((95, WIDTH), bool)
    for row in range(10, 90, 8):
        wall[row - 1:row + 3] = False
    assert (mask[:95][wall] > 0).mean() > 0.98
    assert not mask[106:].any()


def test_fill_holes_fills_what_the_border_cannot_reach():
    ring = np.zeros((20, 20), np.uint8)
    ring[4:16, 4:16] = 255
    ring[8:12, 8:12] = 0
    cup = ring.copy()
    cup[8:20, 8:12] = 0
    assert (fill_holes(ring)[4:16, 4:16] == 255).all()
    assert (fill_holes(ring)[:4] == 0).all()
    assert np.array_equal(fill_holes(cup), cup)


def test_a_pale_wall_under_a_warm_cast_is_an_obstacle_though_as_bright_as_the_floor():
    """A pale wall that a warm light lifts just over the saturation at which a pixel has a hue
    (sat 68, the floor's 20) differs from a grey floor of the same brightness only by that hue:
    it must stay an obstacle (a pale floor tile looks the same, and stays one too)."""
    classifier = FloorClassifier()
    classifier.classify(floor_image((150, 165, 160)))
    image = with_box(floor_image((150, 165, 160), seed=1), (110, 140, 150))
    mask = classifier.classify(image)
    wall_found, false_rate = box_recall_and_false_rate(mask)
    assert wall_found > 0.98
    assert false_rate < 0.002


def reference_colour_gradient(bgr):
    """The colour gradient as first written: float32 Sobel of the blurred image, magnitude and
    channel maximum over the whole image."""
    import cv2
    blurred = cv2.GaussianBlur(bgr, (5, 5), 0).astype(np.float32)
    gradient_x = cv2.Sobel(blurred, cv2.CV_32F, 1, 0, ksize=3, scale=0.125)
    gradient_y = cv2.Sobel(blurred, cv2.CV_32F, 0, 1, ksize=3, scale=0.125)
    return np.sqrt(gradient_x * gradient_x + gradient_y * gradient_y).max(axis=2)


@pytest.mark.parametrize('seed', range(5))
def test_colour_gradient_is_bit_for_bit_the_float_computation(seed):
    import cv2
    from can_seeker.vision.floor import colour_gradient
    rng = np.random.default_rng(seed)
    bgr = cv2.GaussianBlur(rng.integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8), (0, 0),
                           0.5 + seed)
    bgr[BOX[1]:BOX[3], BOX[0]:BOX[2]] = 255 * (seed % 2)
    where = rng.random((HEIGHT, WIDTH)) < 0.1
    reference = reference_colour_gradient(bgr)
    assert np.array_equal(colour_gradient(bgr), reference)
    assert np.array_equal(colour_gradient(bgr, where), reference[where])


def _checker(first_bgr, second_bgr, gains_bgr=(1.0, 1.0, 1.0), offset_px=0, seed=0):
    """A two-tile checker floor (40 px tiles) seen through channel gains, with noise."""
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH]
    second = ((columns + offset_px) // 40 + rows // 40) % 2 == 1
    image = np.where(second[:, :, None], np.array(second_bgr, float), np.array(first_bgr, float))
    image = image * np.asarray(gains_bgr)[None, None, :]
    image += np.random.default_rng(seed).normal(0.0, 4.0, image.shape)
    return np.clip(image, 0, 255).astype(np.uint8)


def test_a_drifting_white_balance_does_not_turn_a_pale_tile_into_an_obstacle():
    """The camera's blue gain creeps up 20 % and its red gain down 16 % in 3 s while the robot
    drives over a white and pale lavender checker: the lavender's saturation crosses the line at
    which it has a hue, and without undoing the drift its tiles become obstacles; a dark box
    stays one."""
    white, lavender = (205, 205, 200), (200, 170, 180)
    locked = FloorClassifier(FloorSettings(max_colour_shift=0.3))
    unlocked = FloorClassifier(FloorSettings(max_colour_shift=0.0))
    for classifier in (locked, unlocked):
        classifier.classify(_checker(white, lavender))
    for step in range(1, 46):
        drift_log = 0.18 * step / 45
        gains = (np.exp(drift_log), 1.0, np.exp(-drift_log))
        image = with_box(_checker(white, lavender, gains, 3 * step, step), (60, 60, 60))
        locked_mask, unlocked_mask = locked.classify(image), unlocked.classify(image)
        recall, false_rate = box_recall_and_false_rate(locked_mask)
        assert recall > 0.98 and false_rate < 0.002
    assert box_recall_and_false_rate(unlocked_mask)[1] > 0.3


def test_an_obstacle_filling_the_reference_area_does_not_move_the_white_balance():
    """A darker wall (value 133, the floor's 165) of nearly the floor's chromaticity (5 %
    redder) creeps over the reference area until it covers most of it: it is an obstacle by its
    brightness, so it never tells the white balance where the floor's colours went (measured on
    every reference pixel, the shift followed the wall to 0.047), and the floor keeps its
    colour."""
    classifier = FloorClassifier(FloorSettings(max_colour_shift=0.3))
    classifier.classify(floor_image((150, 165, 160)))
    for step in range(80):
        bottom = min(170 + step, 225)
        image = with_box(floor_image((150, 165, 160), seed=step), (120, 130, 133),
                         (0, 0, WIDTH, bottom))
        mask = classifier.classify(image)
        assert np.abs(classifier.white_balance.shift_log).max() < 0.01
        assert mask[:bottom - 1].all()
        assert not mask[bottom + 2:].any()


def wall_on_checker(first_bgr, second_bgr, wall_bgr, settings):
    """(recall, false rate) of a wall box on a two-tile checker, for a classifier with
    ``settings`` that has driven over the checker for 10 frames."""
    classifier = FloorClassifier(settings)
    for step in range(10):
        classifier.classify(_checker(first_bgr, second_bgr, offset_px=4 * step, seed=step))
    image = with_box(_checker(first_bgr, second_bgr, offset_px=40, seed=11), wall_bgr)
    return box_recall_and_false_rate(classifier.classify(image))


def test_a_wall_with_one_tiles_hue_and_the_others_brightness_is_an_obstacle():
    """On a floor of a bright tan tile and a mid-grey one, a tan wall as dark as the grey tile
    has a common hue and a common brightness: only the pair of them is new to the floor."""
    tan, grey, wall = (150, 200, 235), (150, 150, 150), (95, 125, 150)
    recall, false_rate = wall_on_checker(tan, grey, wall, FloorSettings(min_joint_fraction=0.002))
    assert recall > 0.98 and false_rate < 0.002
    assert wall_on_checker(tan, grey, wall, FloorSettings(min_joint_fraction=0.0,
                                                          min_chroma_joint_fraction=0.0))[0] < 0.1


def test_a_pinkish_grey_wall_on_a_greenish_grey_floor_is_an_obstacle():
    """A checker of greenish greys (saturation about 55 of 255) and a pinkish grey wall
    (saturation 24) as bright as the light tile. Noise drops some floor pixels under the
    saturation at which hue is judged finely; as "grey" they teach the model the wall's bin, so
    without faint colours the wall is floor. Judged on the faint colours' coarse hue bins, the
    wall is pink and the floor green."""
    light, dark, wall = (92, 104, 80), (75, 84, 65), (96, 96, 106)
    recall, false_rate = wall_on_checker(light, dark, wall,
                                         FloorSettings(min_faint_saturation=16))
    assert recall > 0.98 and false_rate < 0.002
    assert wall_on_checker(light, dark, wall, FloorSettings(min_faint_saturation=50,
                                                            min_chroma_fraction=0.0))[0] < 0.1


def test_a_wall_with_one_tiles_chromaticity_and_the_others_brightness_is_an_obstacle():
    """A checker of a light pink tile and a mid pinkish grey one, and a pink wall as bright as
    the mid tile. All three share a hue bin; the wall's chromaticity (log R/G 0.32) is near the
    light tile's (0.27), its brightness the mid tile's: only the pair of them is new to the
    floor, so only the joint test finds the wall."""
    light, mid, wall = (166, 167, 219), (117, 121, 147), (112, 112, 154)
    recall, false_rate = wall_on_checker(light, mid, wall,
                                         FloorSettings(min_chroma_joint_fraction=0.002))
    assert recall > 0.98 and false_rate < 0.002
    assert wall_on_checker(light, mid, wall, FloorSettings(min_chroma_joint_fraction=0.0))[0] < 0.1


def test_a_cream_wall_on_a_checker_of_white_and_pale_blue_is_an_obstacle_by_its_chromaticity():
    """Harsh realism with the white balance undone: a cream wall and a white and a pale blue
    tile are all too pale to have a hue (saturation under 50 of 255) and equally bright, so by
    hue and brightness the wall is floor. Their log chromaticities lie 0.15 apart (cream warm,
    pale blue cool, white between): the wall is new to the floor's."""
    white, pale_blue, cream = (215, 215, 215), (225, 200, 185), (175, 200, 215)
    recall, false_rate = wall_on_checker(white, pale_blue, cream,
                                         FloorSettings(min_chroma_fraction=0.002))
    assert recall > 0.98 and false_rate < 0.002
    assert wall_on_checker(white, pale_blue, cream,
                           FloorSettings(min_chroma_fraction=0.0))[0] < 0.1


@pytest.mark.parametrize('floor', [(128, 128, 128), (60, 62, 58), (200, 196, 204)])
def test_a_noisy_floor_is_floor_by_its_chromaticity_too(floor):
    """Noise spreads a floor's chromaticity, the darker the more; the model learns that
    spread from the reference area's 5x5 medians, so no floor pixel is rare in it, and a box of
    a clear colour still is an obstacle."""
    classifier = FloorClassifier(FloorSettings(min_chroma_fraction=0.002))
    for seed in range(5):
        classifier.classify(floor_image(floor, sigma=6.0, seed=seed))
    recall, false_rate = box_recall_and_false_rate(
        classifier.classify(with_box(floor_image(floor, sigma=6.0, seed=9), (40, 140, 200))))
    assert recall > 0.98 and false_rate < 0.002


@pytest.mark.parametrize('floor', [(128, 128, 128), (60, 62, 58), (200, 196, 204)])
def test_a_noisy_grey_floor_is_floor_whatever_hue_its_noise_gives_faint_pixels(floor):
    """Noise gives the pixels of a neutral floor faint colours of every hue: the model learns
    them all from the reference area, so none is an obstacle, and a box of a clear colour
    still is."""
    classifier = FloorClassifier(FloorSettings(min_faint_saturation=16))
    for seed in range(5):
        classifier.classify(floor_image(floor, sigma=6.0, seed=seed))
    recall, false_rate = box_recall_and_false_rate(
        classifier.classify(with_box(floor_image(floor, sigma=6.0, seed=9), (40, 140, 200))))
    assert recall > 0.98 and false_rate < 0.002


def test_a_grey_floor_whose_white_balance_drifts_to_a_faint_colour_stays_floor():
    """Harsh realism: the white balance drifts the pybullet checker's greys to faint oranges and
    blues within seconds. Judged by hue, every such tile would be an obstacle in some frames;
    on a floor that is mostly grey faint colours count as grey. (The chromaticity test is off:
    without the white-balance lock a drift moves the floor's chromaticity as well; the lock is
    off, the jumps are not a drift's pace.)"""
    classifier = FloorClassifier(FloorSettings(min_faint_saturation=16, min_chroma_fraction=0.0,
                                               max_colour_shift=0.0))
    for seed in range(5):
        classifier.classify(floor_image((140, 140, 140), sigma=2.0, seed=seed))
    for gains in ((0.9, 1.0, 1.1), (1.1, 1.0, 0.9)):
        drifted = floor_image((140, 140, 140), sigma=2.0, seed=7) * np.array(gains)
        assert not classifier.classify(np.clip(drifted, 0, 255).astype(np.uint8)).any()


def test_the_lens_fall_off_is_undone_before_a_dark_box_of_the_floors_hue_is_judged():
    """A tan floor seen through a 40 % fall-off teaches the model every brightness down to 60 %
    of its own; a tan box at 65 % of the floor's brightness passes as floor unless the fall-off
    is estimated and undone."""
    columns, rows = np.meshgrid(np.arange(WIDTH) + 0.5 - WIDTH / 2.0,
                                np.arange(HEIGHT) + 0.5 - HEIGHT / 2.0)
    gain = 1.0 - 0.4 * (columns ** 2 + rows ** 2) / ((WIDTH ** 2 + HEIGHT ** 2) / 4.0)

    def seen(image):
        return np.clip(image * gain[:, :, None] + 0.5, 0, 255).astype(np.uint8)

    tan = (150, 200, 235)
    corrected = FloorClassifier(FloorSettings(max_vignetting=0.7))
    plain = FloorClassifier(FloorSettings(max_vignetting=0.0))
    for step in range(40):
        for classifier in (corrected, plain):
            classifier.classify(seen(floor_image(tan, seed=step).astype(float)))
    box = tuple(int(0.65 * channel) for channel in tan)
    image = with_box(floor_image(tan, seed=50), box).astype(float)
    image = seen(image)
    image[BOX[1]:BOX[3], BOX[0]:BOX[2]] = box
    recall, false_rate = box_recall_and_false_rate(corrected.classify(image))
    assert recall > 0.98 and false_rate < 0.002
    assert box_recall_and_false_rate(plain.classify(image))[0] < 0.1


def _blurred_tiles(first_bgr, second_bgr, tile_px=160, seed=0, offset_px=0, sigma=1.0,
                   blur_px=7):
    """Large checker tiles whose edges are blurred over ``blur_px`` - 1 px, with noise."""
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH]
    second = ((columns + offset_px) // tile_px + rows // tile_px) % 2 == 1
    image = np.where(second[:, :, None], np.array(second_bgr, float),
                     np.array(first_bgr, float))
    image = cv2.blur(image, (blur_px, blur_px))
    image += np.random.default_rng(seed).normal(0.0, sigma, image.shape)
    return np.clip(image, 0, 255).astype(np.uint8)


TEAL_LIGHT, TEAL_DARK = (184, 180, 150), (115, 114, 88)


@pytest.mark.parametrize('sigma', [1.0, 6.0])
def test_the_blurred_edge_between_two_floor_tiles_is_floor(sigma):
    """Where a light and a dark tile meet, the renderer's filtering or a turn's motion blur
    blends them over a few pixels into colours neither tile has; the blend is floor, not a line
    of obstacle along every tile edge (a clean camera, and one as noisy as the harsh
    preset's). The model learned both tiles from frames whose edges were sharp."""
    classifier = FloorClassifier()
    for step in range(10):
        classifier.classify(_blurred_tiles(TEAL_LIGHT, TEAL_DARK, offset_px=6 * step,
                                           seed=step, sigma=sigma, blur_px=1))
    mask = classifier.classify(_blurred_tiles(TEAL_LIGHT, TEAL_DARK, offset_px=30, seed=20,
                                              sigma=sigma))
    assert (mask > 0).mean() < 0.0005


def _slanted_tiles(first_bgr, second_bgr, tile_px=120, angle_deg=35.0, blur_px=13, seed=0):
    """Large checker tiles turned by ``angle_deg`` (slanted edges, and the corner where four
    tiles meet in view) whose edges are blurred over ``blur_px`` - 1 px, with noise."""
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH].astype(float)
    angle = np.radians(angle_deg)
    along = (columns - 150) * np.cos(angle) + (rows - 130) * np.sin(angle)
    across = -(columns - 150) * np.sin(angle) + (rows - 130) * np.cos(angle)
    second = (np.floor(along / tile_px) + np.floor(across / tile_px)) % 2 == 1
    image = np.where(second[:, :, None], np.array(second_bgr, float),
                     np.array(first_bgr, float))
    image = cv2.blur(image, (blur_px, blur_px))
    image += np.random.default_rng(seed).normal(0.0, 1.0, image.shape)
    return np.clip(image, 0, 255).astype(np.uint8)


def test_slanted_tile_edges_blurred_wide_and_the_corner_of_four_tiles_are_floor():
    """A camera low and steep over the floor sees a tile edge magnified, blurred over 12 px of
    320 and slanted across the image, and the corner where four tiles meet, where every
    straight line through the blend joins two tiles of the same colour. Neither is a line or a
    cross of obstacle (the scan took the cross at the image bottom for an obstacle 0.3 m
    ahead, and the robot planned around it). The model learned both tiles from sharp frames."""
    classifier = FloorClassifier()
    for step in range(10):
        classifier.classify(_slanted_tiles(TEAL_LIGHT, TEAL_DARK, blur_px=1, seed=step))
    mask = classifier.classify(_slanted_tiles(TEAL_LIGHT, TEAL_DARK, seed=20))
    assert (mask > 0).mean() < 0.0005


@pytest.mark.parametrize('x0', [50, 77])
def test_a_thin_pole_on_a_tile_or_across_a_tile_edge_stays_an_obstacle(x0):
    """A 5 px pole of its own colour is no blend of the floor on its sides, on one tile
    (x0 50) or on the edge between a light and a dark tile (x0 77)."""
    classifier = FloorClassifier()
    for step in range(10):
        classifier.classify(_blurred_tiles(TEAL_LIGHT, TEAL_DARK, seed=step))
    pole = (x0, 20, x0 + 5, 150)
    image = with_box(_blurred_tiles(TEAL_LIGHT, TEAL_DARK, seed=20), (60, 40, 90), pole)
    recall, false_rate = box_recall_and_false_rate(classifier.classify(image), pole)
    assert recall > 0.9 and false_rate < 0.0005


def test_a_blend_is_a_colour_on_the_line_between_the_floor_on_its_two_sides():
    floor = np.ones((5, 9), bool)
    floor[:, 3:6] = False
    image = np.zeros((5, 9, 3), np.uint8)
    image[:, :4] = (200, 100, 50)
    image[:, 4] = (150, 100, 75)
    image[:, 5:] = (100, 100, 100)
    assert floor_blends(image, floor, reach_px=5)[2, 4]
    image[:, 4] = (40, 200, 200)
    assert not floor_blends(image, floor, reach_px=5)[2, 4]


def test_a_wall_twelve_levels_above_a_dark_floor_is_an_obstacle():
    """Shading multiplies brightness, so the intensity bins are narrower on a dark floor: a grey
    wall 12 levels above a grey floor at level 56 (8-level bins with a neighbour tolerated
    took it for floor) is an obstacle, and the floor's own noise is not."""
    floor = floor_image((56, 57, 58), sigma=1.5)
    mask = FloorClassifier().classify(with_box(floor, (68, 69, 70)))
    recall, false_rate = box_recall_and_false_rate(mask)
    assert recall > 0.95
    assert false_rate < 0.002


def test_intensity_bins_are_narrow_on_dark_floors_and_eight_levels_on_light_ones():
    """Every grey level has a bin, in order, 5 levels wide at the dark end and 8 at the light."""
    widths = np.bincount(VALUE_BIN_LUT, minlength=VALUE_BINS)
    assert (np.diff(VALUE_BIN_LUT.astype(int)) >= 0).all() and widths.min() >= 5
    assert widths[:14].tolist() == [5] * 14
    assert (widths[VALUE_BIN_LUT[96]:-1] == 8).all() and widths.max() == 8
