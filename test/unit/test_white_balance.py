"""White-balance lock: the log-chromaticity shift of a drifting camera, found on the floor
whatever the mix of its colours, bounded in pace and size."""
import numpy as np
import pytest

from can_seeker.vision.white_balance import (CHROMA_BIN, RELAX_RATE, STEP_BINS, WhiteBalanceLock,
                                             undo_shift)

WHITE_TILE = (205, 205, 200)
LAVENDER_TILE = (200, 170, 180)
"""BGR: a pale lavender tile (saturation 38, hue 130) and an off-white one."""


def tile_pixels(lavender_fraction, gains_bgr=(1.0, 1.0, 1.0), count=12000, seed=0):
    """Nx3 uint8 reference pixels of a two-tile floor seen through channel gains, with noise."""
    rng = np.random.default_rng(seed)
    lavender = rng.random(count) < lavender_fraction
    pixels = np.where(lavender[:, None], np.array(LAVENDER_TILE, float),
                      np.array(WHITE_TILE, float))
    pixels = pixels * np.asarray(gains_bgr)[None, :] + rng.normal(0.0, 4.0, pixels.shape)
    return np.clip(np.rint(pixels), 0, 255).astype(np.uint8)


def drift_gains(red_log, blue_log):
    return (np.exp(blue_log), 1.0, np.exp(red_log))


@pytest.mark.parametrize('learned_mix,current_mix', [(0.5, 0.5), (0.2, 0.8), (0.8, 0.1)])
def test_the_shift_is_the_drift_whatever_the_mix_of_floor_colours(learned_mix, current_mix):
    lock = WhiteBalanceLock(0.3)
    lock.track(tile_pixels(learned_mix))
    red_log, blue_log = 0.0, 0.0
    for step in range(1, 21):
        red_log, blue_log = 0.006 * step, -0.004 * step
        lock.track(tile_pixels(current_mix, drift_gains(red_log, blue_log), seed=step))
    assert lock.shift_log == pytest.approx((red_log, blue_log), abs=0.006)
    corrected = lock.correct(tile_pixels(current_mix, drift_gains(red_log, blue_log))[None])
    assert corrected[0].mean(axis=0) == pytest.approx(
        tile_pixels(current_mix)[None][0].mean(axis=0), abs=1.0)


@pytest.mark.parametrize('wall_red_log', [0.25, 0.45])
def test_a_surface_of_another_colour_filling_the_reference_area_is_not_taken_for_drift(
        wall_red_log):
    """A wall 25 % or 57 % redder than the floor, in view all at once, is farther than a drift
    moves in a frame: it shares no colour with the floor near the last shift, and the shift
    stays where the floor left it."""
    lock = WhiteBalanceLock(0.3)
    lock.track(tile_pixels(0.0))
    for step in range(30):
        lock.track(tile_pixels(0.0, drift_gains(wall_red_log, 0.0), seed=step))
        assert np.abs(lock.shift_log).max() < 0.5 * CHROMA_BIN


def test_the_shift_moves_at_a_drift_pace_and_within_its_bound():
    lock = WhiteBalanceLock(0.2)
    lock.track(tile_pixels(0.5))
    shifts = []
    for step in range(1, 40):
        lock.track(tile_pixels(0.5, drift_gains(0.02 * step, 0.0), seed=step))
        shifts.append(lock.shift_log.copy())
    steps = np.abs(np.diff(np.array([(0.0, 0.0)] + shifts), axis=0))
    assert steps.max() <= (STEP_BINS + 0.5) * CHROMA_BIN
    assert np.abs(np.array(shifts)).max() == pytest.approx(0.2)


def test_no_drift_leaves_the_image_untouched():
    lock = WhiteBalanceLock(0.3)
    for step in range(5):
        lock.track(tile_pixels(0.3 + 0.1 * step, seed=step))
    image = tile_pixels(0.5)[None]
    assert lock.gains() is None
    assert lock.correct(image) is image
    off = WhiteBalanceLock(0.0)
    off.track(tile_pixels(0.5))
    off.track(tile_pixels(0.5, drift_gains(0.1, 0.0)))
    assert off.gains() is None


def test_a_shift_nothing_measures_is_let_go():
    """Lost (the floor out of view or out of reach of a frame's drift), the shift relaxes to
    none at the white balance's own pace instead of holding a correction nothing confirms."""
    lock = WhiteBalanceLock(0.3)
    lock.track(tile_pixels(0.5))
    for step in range(1, 8):
        lock.track(tile_pixels(0.5, drift_gains(0.02 * step, 0.0), seed=step))
    held = lock.shift_log.copy()
    assert held[0] == pytest.approx(0.14, abs=0.01)
    for step in range(20):
        lock.track(np.zeros((0, 3), np.uint8))
    assert lock.shift_log == pytest.approx(held * (1.0 - RELAX_RATE) ** 20)
    wall = tile_pixels(0.0, drift_gains(-0.3, 0.3))
    lock.track(wall)
    assert lock.shift_log == pytest.approx(held * (1.0 - RELAX_RATE) ** 21)


def test_a_dark_floor_teaches_nothing():
    """A dark floor has no reliable chromaticity: nothing is learned, nothing corrected."""
    lock = WhiteBalanceLock(0.3)
    dark = np.full((5000, 3), 20, np.uint8)
    lock.track(dark)
    lock.track(np.clip(dark * 1.3, 0, 255).astype(np.uint8))
    assert lock.model is None and lock.gains() is None


GREEN_GREY_TILE = (158, 168, 138)
SAGE_TILE = (184, 210, 164)
"""BGR: two greenish grey tiles 0.05 apart in log R/G and 0.07 in log B/G, as near as a
drift of a few frames."""


def near_tiles(sage_fraction, gains_bgr=(1.0, 1.0, 1.0), count=12000, seed=0):
    """Nx3 uint8 pixels of a floor of the two near tiles, with noise."""
    rng = np.random.default_rng(seed)
    sage = rng.random(count) < sage_fraction
    pixels = np.where(sage[:, None], np.array(SAGE_TILE, float), np.array(GREEN_GREY_TILE, float))
    pixels = pixels * np.asarray(gains_bgr)[None, :] + rng.normal(0.0, 2.0, pixels.shape)
    return np.clip(np.rint(pixels), 0, 255).astype(np.uint8)


def scene(sage_fraction, gains_bgr=(1.0, 1.0, 1.0), seed=0):
    """A whole 120x160 frame of that floor (its mix of tiles is the scene's)."""
    return near_tiles(sage_fraction, gains_bgr, 120 * 160, seed).reshape(120, 160, 3)


def test_driving_over_tiles_of_near_colours_is_no_drift():
    """The lock learned one tile; the robot drives over a checker of it and another tile within
    a drift's reach, the reference area filled by one and then the other every 6 frames. The
    reference area alone cannot tell the other tile from a drift (laid on the known tile, it
    fits best) and the shift jumped to it at every tile; the whole image, whose colours did not
    move, tells, and the shift stays none. (A long stay on a tile the floor model has not
    learned still pulls the shift toward it: only the floor's colours anchor it.)"""
    def reference(step):
        return near_tiles(0.9 if (step // 6) % 2 else 0.1, seed=step)

    lock = WhiteBalanceLock(0.3)
    alone = WhiteBalanceLock(0.3)
    lock.track(near_tiles(0.0), scene(0.5))
    alone.track(near_tiles(0.0))
    alone_largest = 0.0
    for step in range(1, 61):
        lock.track(reference(step), scene(0.5, seed=step))
        alone.track(reference(step))
        assert np.abs(lock.shift_log).max() < 0.5 * CHROMA_BIN
        alone_largest = max(alone_largest, np.abs(alone.shift_log).max())
    assert alone_largest > 3 * CHROMA_BIN


def test_with_the_whole_image_the_shift_follows_a_drift_and_a_jump_the_floor_refutes_is_not_taken():
    """A drift moves the whole image and the floor alike: the shift follows it. A scene change
    that looks like one (the frame turns redder as a whole) while the floor stays is no drift."""
    lock = WhiteBalanceLock(0.3)
    lock.track(near_tiles(0.5), scene(0.5))
    red_log, blue_log = 0.0, 0.0
    for step in range(1, 21):
        red_log, blue_log = 0.006 * step, -0.004 * step
        gains = drift_gains(red_log, blue_log)
        lock.track(near_tiles(0.5, gains, seed=step), scene(0.5, gains, seed=step))
    assert lock.shift_log == pytest.approx((red_log, blue_log), abs=0.006)
    held = lock.shift_log.copy()
    gains = drift_gains(red_log, blue_log)
    lock.track(near_tiles(0.5, gains, seed=99), scene(0.5, drift_gains(red_log + 0.08, blue_log)))
    assert lock.shift_log == pytest.approx(held, abs=0.006)


BROWN_TILE = (129, 141, 170)
PINK_TILE = (161, 177, 220)
"""BGR: a brown and a pink tile 0.03 apart in log R/G, within the floor's reach of each other."""


def brown_pink(pink_fraction, count, gains_bgr=(1.0, 1.0, 1.0), seed=0):
    """Nx3 uint8 pixels of a brown and pink floor seen through channel gains, with noise."""
    rng = np.random.default_rng(seed)
    pink = rng.random(count) < pink_fraction
    pixels = np.where(pink[:, None], np.array(PINK_TILE, float), np.array(BROWN_TILE, float))
    pixels = pixels * np.asarray(gains_bgr)[None, :] + rng.normal(0.0, 2.0, pixels.shape)
    return np.clip(np.rint(pixels), 0, 255).astype(np.uint8)


def known_tiles_share(scene, known=(BROWN_TILE, PINK_TILE)):
    """The verdict of a floor model that knows the ``known`` tiles (BGR): shift -> the share of
    ``scene`` (HxWx3 uint8 BGR) within two bins of a tile's log chromaticity with the shift
    undone."""
    def log_chromaticity(bgr):
        levels = np.maximum(bgr.astype(float), 0.5)
        return np.stack((np.log(levels[..., 2] / levels[..., 1]),
                         np.log(levels[..., 0] / levels[..., 1])), axis=-1)
    tiles = log_chromaticity(np.array(known, float))

    def share(shift_log):
        colours = log_chromaticity(undo_shift(scene, shift_log).reshape(-1, 3))
        distance = np.abs(colours[:, None, :] - tiles[None, :, :]).max(axis=2).min(axis=1)
        return float(np.mean(distance <= 2 * CHROMA_BIN))
    return share


def test_a_floor_correction_that_turns_known_floor_into_obstacle_is_not_taken():
    """The lock learned a mostly brown floor; the reference area then holds only the pink tile
    while the frame shows both, and nothing drifts. Laid on the model's larger brown peak, the
    pink pulls the shift 1.3 bins, and the brown in view would leave the floor's colours; with
    the floor model's verdict the lock refuses that correction and the shift stays none."""
    shifts = {}
    for judged in (False, True):
        lock = WhiteBalanceLock(0.3)
        lock.track(brown_pink(0.2, 6000), brown_pink(0.5, 120 * 160).reshape(120, 160, 3))
        for step in range(1, 11):
            scene = brown_pink(0.5, 120 * 160, seed=step).reshape(120, 160, 3)
            lock.track(brown_pink(1.0, 6000, seed=100 + step), scene,
                       known_tiles_share(scene) if judged else None)
        shifts[judged] = lock.shift_log
    assert np.abs(shifts[False]).max() > CHROMA_BIN
    assert np.abs(shifts[True]).max() < 0.25 * CHROMA_BIN


def test_with_the_floor_models_verdict_the_floor_still_corrects_a_drift():
    """A drift lays the floor back on its colours where it is undone, so the verdict takes the
    floor's correction. Each frame shows a wall of another colour beside the floor, so two
    frames in a row share too little for a step between them: the floor alone follows."""
    walls = ((200, 90, 60), (60, 160, 80))
    lock = WhiteBalanceLock(0.3)
    lock.track(brown_pink(0.5, 6000), brown_pink(0.5, 120 * 160).reshape(120, 160, 3))
    red_log, blue_log = 0.0, 0.0
    for step in range(1, 21):
        red_log, blue_log = -0.006 * step, 0.004 * step
        gains = drift_gains(red_log, blue_log)
        scene = brown_pink(0.5, 120 * 160, gains, seed=step).reshape(120, 160, 3)
        scene[:, :80] = walls[step % 2]
        lock.track(brown_pink(0.5, 6000, gains, seed=100 + step), scene,
                   known_tiles_share(scene))
    assert lock.shift_log == pytest.approx((red_log, blue_log), abs=0.006)


DARK_GREEN_TILE = (85, 102, 87)
LIGHT_GREEN_TILE = (150, 181, 147)
GREEN_TILES = (DARK_GREEN_TILE, LIGHT_GREEN_TILE)
"""BGR: a dark and a light green tile 0.05 apart in log R/G (a checker seen up close)."""


def turning_over_tiles(light_columns, gains_bgr=(1.0, 1.0, 1.0), seed=0):
    """A 120x160 frame of two large tiles: light from column ``light_columns`` on, dark left of
    it, seen through channel gains, with noise."""
    rng = np.random.default_rng(seed)
    frame = np.empty((120, 160, 3))
    frame[:, :light_columns] = DARK_GREEN_TILE
    frame[:, light_columns:] = LIGHT_GREEN_TILE
    frame = frame * np.asarray(gains_bgr)[None, None, :] + rng.normal(0.0, 2.0, frame.shape)
    return np.clip(np.rint(frame), 0, 255).astype(np.uint8)


def turning(edges, drift_per_frame_log=(0.0, 0.0)):
    """A lock that learned the two tiles half and half, then followed a turn over them that
    moves their edge to each of ``edges`` (columns) under a drift of so much a frame, while an
    object covers the reference area (no floor pixels in it): only the steps between frames
    move the shift. Returns (the lock, the largest shift on the way in bins, the drift)."""
    lock = WhiteBalanceLock(0.3)
    frame = turning_over_tiles(80)
    lock.track(frame[60:].reshape(-1, 3), frame)
    largest, drift = 0.0, np.zeros(2)
    for step, edge in enumerate(edges, start=1):
        drift = step * np.asarray(drift_per_frame_log, float)
        lock.track(np.zeros((0, 3), np.uint8), turning_over_tiles(edge, drift_gains(*drift),
                                                                   seed=step))
        largest = max(largest, float(np.abs(lock.shift_log).max()) / CHROMA_BIN)
    return lock, largest, drift


def test_turning_over_large_tiles_of_near_colours_is_no_step():
    """The robot turns on the spot over two large tiles of near colours: their edge sweeps
    across the image, so the mix of the two colours in view goes from mostly dark to mostly
    light and back while nothing drifts. The whole image's histogram moves as under a drift
    (steps read from it would add up to 1.4 bins); the pixels that stay on their tile do not
    change colour, and the shift stays under a third of a bin."""
    sweep = list(range(150, 10, -7)) + list(range(10, 150, 7))
    assert turning(sweep * 2)[1] < 0.35


def test_turning_over_large_tiles_the_steps_follow_a_drift():
    """The same turn under a drift of 0.3 bin a frame: the pixels that stay on their tile carry
    it, and the shift follows (steps read from the whole image's histogram would end 3 bins
    off)."""
    lock, _, drift = turning(range(150, 10, -7), (0.006, -0.004))
    assert lock.shift_log == pytest.approx(drift, abs=0.5 * CHROMA_BIN)


def test_a_floor_correction_the_floor_models_verdict_cannot_tell_from_none_is_not_taken():
    """Nothing drifts; the robot turns over two large tiles of near colours and the reference
    area in front of it shows mostly the dark one, then mostly the light one. Their histograms
    overlap, so the mix pulls the floor's peak off the model's by up to 1.4 bins, and the lock
    learns the pixels it corrects (the pull then builds on itself). The floor model's verdict
    is the same with or without each correction (its bins are coarser than the pull): a
    correction that shows no more of the frame as floor is not taken, and the shift stays under
    a third of a bin."""
    lock = WhiteBalanceLock(0.3)
    frame = turning_over_tiles(80)
    lock.track(frame[60:].reshape(-1, 3), frame)
    largest = 0.0
    sweep = list(range(150, 10, -7)) + list(range(10, 150, 7))
    for step, edge in enumerate(sweep * 3, start=1):
        frame = turning_over_tiles(edge, seed=step)
        lock.track(frame[60:].reshape(-1, 3), frame, lambda shift_log: 1.0)
        lock.learn(lock.correct(frame)[60:].reshape(-1, 3), 0.005)
        largest = max(largest, float(np.abs(lock.shift_log).max()) / CHROMA_BIN)
    assert largest < 0.35
