"""Random looks of the simulated world: floor, wall and obstacle colours drawn from a seed, so a
batch of trials covers light and dark floors, plain and checkered ones, and scenes where an
obstacle or the walls hardly stand out from the floor.

The draw has a random stream of its own (not the one that places the obstacles and the can), so
a seed's geometry is the same whether its looks are drawn or not. No colour is saturated enough
to pass the red detector's test, even under a warm light: the can stays the only red thing.
"""
import colorsys
import random
from dataclasses import dataclass
from typing import Optional, Tuple

RGBA = Tuple[float, float, float, float]

FLOOR_KINDS = (('pybullet', 0.2), ('plain', 0.4), ('checker', 0.4))
"""Floors and how often each is drawn: pybullet's blue and white checker, one colour, or a
checker of two drawn colours (1 m squares, as pybullet's)."""
MAX_SATURATION = 0.35
"""HSV saturation of every drawn colour: its smallest channel is at least 65 % of its largest,
so green stays above 0.35 x red (the red test's limit) also under a 2700 K light."""
FLOOR_VALUE_RANGE = (0.12, 0.92)
"""Brightness (HSV value) of a drawn floor: from dark slate to light beige."""
PYBULLET_FLOOR_VALUE = 0.9
"""Brightness of pybullet's checker floor (light blue and white), for the contrast draws."""
CHECKER_CONTRAST_RANGE = (0.04, 0.35)
"""Brightness difference of a checker's two colours: from barely visible to strong."""
LOW_CONTRAST = 0.06
"""A low-contrast obstacle or wall is within this brightness of the floor, of a similar hue."""
LOW_CONTRAST_OBSTACLES = 0.3
LOW_CONTRAST_WALLS = 0.25
"""How often obstacles, and walls, are drawn in low contrast to the floor."""
OBSTACLE_VALUE_RANGE = (0.05, 0.95)
WALL_VALUE_RANGE = (0.3, 0.95)
HUE_SPREAD = 0.05
"""Hue difference (fraction of the circle) of a low-contrast colour or a checker's second one."""


@dataclass(frozen=True)
class Appearance:
    """The colours of one world: ``floor_rgba`` None is pybullet's checker floor, otherwise
    one colour, or a checker of it and ``floor_checker_rgba``."""

    floor_rgba: Optional[RGBA]
    floor_checker_rgba: Optional[RGBA]
    wall_rgba: RGBA
    obstacle_rgba: RGBA


@dataclass(frozen=True)
class _Colour:
    hue: float
    saturation: float
    value: float

    def rgba(self) -> RGBA:
        return tuple(round(channel, 3) for channel in colorsys.hsv_to_rgb(
            self.hue % 1.0, self.saturation, self.value)) + (1.0,)


def _clamp(value: float, low: float, high: float) -> float:
    return min(high, max(low, value))


def _random_colour(rng: random.Random, value_range: Tuple[float, float]) -> _Colour:
    return _Colour(rng.random(), rng.uniform(0.0, MAX_SATURATION), rng.uniform(*value_range))


def _near(rng: random.Random, colour: _Colour, value_delta: float,
          value_range: Tuple[float, float]) -> _Colour:
    """A colour like ``colour`` with its brightness moved by ``value_delta`` (the other way
    when that leaves ``value_range``)."""
    value = colour.value + value_delta
    if not value_range[0] <= value <= value_range[1]:
        value = colour.value - value_delta
    return _Colour(colour.hue + rng.uniform(-HUE_SPREAD, HUE_SPREAD),
                   _clamp(colour.saturation + rng.uniform(-0.05, 0.05), 0.0, MAX_SATURATION),
                   _clamp(value, *value_range))


def _contrasting(rng: random.Random, floor: _Colour, low_contrast_share: float,
                 value_range: Tuple[float, float]) -> _Colour:
    """A colour that stands out from ``floor`` as any random one does or, with probability
    ``low_contrast_share``, one within LOW_CONTRAST of its brightness."""
    if rng.random() < low_contrast_share:
        return _near(rng, floor, rng.uniform(-LOW_CONTRAST, LOW_CONTRAST), (0.0, 1.0))
    return _random_colour(rng, value_range)


def random_appearance(seed: int) -> Appearance:
    """The colours of the world of ``seed`` (the same for the same seed, on every machine)."""
    rng = random.Random('appearance %d' % seed)
    kinds, weights = zip(*FLOOR_KINDS)
    kind = rng.choices(kinds, weights)[0]
    if kind == 'pybullet':
        floor = _Colour(0.6, 0.15, PYBULLET_FLOOR_VALUE)
        floor_rgba, checker_rgba = None, None
    else:
        floor = _random_colour(rng, FLOOR_VALUE_RANGE)
        floor_rgba = floor.rgba()
        checker_rgba = None
        if kind == 'checker':
            checker_rgba = _near(rng, floor, rng.uniform(*CHECKER_CONTRAST_RANGE),
                                 (0.0, 1.0)).rgba()
    obstacle = _contrasting(rng, floor, LOW_CONTRAST_OBSTACLES, OBSTACLE_VALUE_RANGE)
    wall = _contrasting(rng, floor, LOW_CONTRAST_WALLS, WALL_VALUE_RANGE)
    return Appearance(floor_rgba, checker_rgba, wall.rgba(), obstacle.rgba())
