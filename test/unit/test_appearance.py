"""Random world looks: the same for a seed, varied over seeds (light and dark floors, plain and
checkered, low-contrast obstacles and walls), and never red."""
import colorsys

import numpy as np

from can_seeker.sim.appearance import MAX_SATURATION, random_appearance
from can_seeker.sim.realism import kelvin_rgb
from can_seeker.vision.detector import DetectorSettings, red_mask

LOOKS = [random_appearance(seed) for seed in range(400)]
WHITE = (1.0, 1.0, 1.0, 1.0)
PYBULLET_LIGHT_BLUE = (173 / 255.0, 199 / 255.0, 239 / 255.0, 1.0)


def luma(rgba):
    return 0.299 * rgba[0] + 0.587 * rgba[1] + 0.114 * rgba[2]


def floor_luma(look):
    if look.floor_rgba is None:
        return (luma(WHITE) + luma(PYBULLET_LIGHT_BLUE)) / 2.0
    return luma(look.floor_rgba)


def share(condition):
    return sum(1 for look in LOOKS if condition(look)) / len(LOOKS)


def test_the_same_seed_gives_the_same_look_and_seeds_differ():
    assert random_appearance(1000) == random_appearance(1000)
    assert len({look.obstacle_rgba for look in LOOKS[:50]}) == 50


def test_floors_are_pybullets_plain_or_checkered_light_and_dark():
    pybullet = share(lambda look: look.floor_rgba is None)
    plain = share(lambda look: look.floor_rgba is not None and look.floor_checker_rgba is None)
    checker = share(lambda look: look.floor_checker_rgba is not None)
    assert 0.12 < pybullet < 0.28 and 0.3 < plain < 0.5 and 0.3 < checker < 0.5
    for kind in (lambda look: look.floor_checker_rgba is None,
                 lambda look: look.floor_checker_rgba is not None):
        assert share(lambda look: look.floor_rgba is not None and kind(look)
                     and luma(look.floor_rgba) < 0.25) > 0.03
        assert share(lambda look: look.floor_rgba is not None and kind(look)
                     and luma(look.floor_rgba) > 0.75) > 0.03


def test_checkers_range_from_faint_to_strong():
    contrasts = [abs(luma(look.floor_rgba) - luma(look.floor_checker_rgba))
                 for look in LOOKS if look.floor_checker_rgba is not None]
    assert min(contrasts) < 0.06 and max(contrasts) > 0.25


def test_obstacles_and_walls_are_sometimes_hardly_darker_or_lighter_than_the_floor():
    low_obstacles = share(lambda look: abs(luma(look.obstacle_rgba) - floor_luma(look)) < 0.08)
    low_walls = share(lambda look: abs(luma(look.wall_rgba) - floor_luma(look)) < 0.08)
    assert 0.2 < low_obstacles < 0.5 and 0.15 < low_walls < 0.45
    assert share(lambda look: luma(look.obstacle_rgba) < floor_luma(look) - 0.3) > 0.1
    assert share(lambda look: luma(look.obstacle_rgba) > floor_luma(look) + 0.3) > 0.05


def test_no_drawn_colour_is_red_to_the_detector_even_under_a_warm_light():
    colours = [rgba for look in LOOKS for rgba in (look.floor_rgba, look.floor_checker_rgba,
                                                   look.wall_rgba, look.obstacle_rgba)
               if rgba is not None]
    assert max(colorsys.rgb_to_hsv(*rgba[:3])[1] for rgba in colours) <= MAX_SATURATION + 0.01
    warm = kelvin_rgb(2700.0) / kelvin_rgb(2700.0).max()
    for light in (np.ones(3), warm):
        rgb = np.clip(np.array([rgba[:3] for rgba in colours]) * light * 255.0, 0, 255)
        bgr = np.ascontiguousarray(rgb[None, :, ::-1].astype(np.uint8))
        assert not red_mask(bgr, DetectorSettings.defaults()).any()
