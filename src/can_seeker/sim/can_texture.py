"""A soda can that looks like one, made at run time: the label image and the textured mesh.

The label wraps once around the can: a body in the can's colour, a band of white lettering-like
marks with gaps of body colour between the letters and a thin white ribbon under them, and a
silver neck and lid at the top and a silver base at the bottom. No real brand: the "letters" are
strokes drawn from a fixed seed. The mesh is an OBJ cylinder whose side maps the label once
around (u = angle, v = height, v = 1 at the top) and whose lid and base map to the silver rim.
"""
import math
import random
from typing import Sequence

import cv2
import numpy as np

from can_seeker.can_size import CAN_COLOUR_BOTTOM_M, CAN_HEIGHT_M

LABEL_WIDTH_PX = 512
LABEL_HEIGHT_PX = 256
LID_FRACTION = 0.075
"""Silver neck and lid rim at the top (9 mm of a 122 mm can), as a fraction of the height."""
BASE_FRACTION = CAN_COLOUR_BOTTOM_M / CAN_HEIGHT_M
"""Silver base at the bottom, below where the can's colour begins (CAN_COLOUR_BOTTOM_M, which
the vision's range assumes), as a fraction of the height."""
LETTERING_TOP_FRACTION = 0.3
LETTERING_BOTTOM_FRACTION = 0.52
"""The lettering band, as fractions of the height from the top."""
RIBBON_FRACTION = 0.58
"""Centre of the thin white ribbon under the lettering, from the top."""
SILVER_RGB = (196, 198, 204)
WHITE_RGB = (245, 245, 245)
MESH_SEGMENTS = 48
LETTERING_SEED = 12


def label_image(body_rgb: Sequence[int], width_px: int = LABEL_WIDTH_PX,
                height_px: int = LABEL_HEIGHT_PX) -> np.ndarray:
    """The label as an RGB uint8 image (row 0 = the top of the can)."""
    image = np.empty((height_px, width_px, 3), np.uint8)
    image[:] = tuple(int(channel) for channel in body_rgb)
    lid_rows = int(round(LID_FRACTION * height_px))
    base_rows = int(round(BASE_FRACTION * height_px))
    shade = np.linspace(1.0, 0.85, lid_rows)[:, None, None]
    image[:lid_rows] = (np.array(SILVER_RGB) * shade).astype(np.uint8)
    image[height_px - base_rows:] = SILVER_RGB
    _draw_lettering(image, int(LETTERING_TOP_FRACTION * height_px),
                    int(LETTERING_BOTTOM_FRACTION * height_px))
    ribbon_y = RIBBON_FRACTION * height_px
    xs = np.arange(width_px)
    ys = ribbon_y + 0.03 * height_px * np.sin(2.0 * math.pi * xs / width_px * 2.0)
    points = np.stack([xs, ys], axis=1).round().astype(np.int32)
    cv2.polylines(image, [points], False, WHITE_RGB, max(1, height_px // 100), cv2.LINE_AA)
    return image


def _draw_lettering(image: np.ndarray, top_px: int, bottom_px: int):
    """Two 'words' of script-like white strokes per turn, letters apart by body colour."""
    generator = random.Random(LETTERING_SEED)
    width_px = image.shape[1]
    letter_height = bottom_px - top_px
    stroke = max(2, letter_height // 7)
    x = int(0.04 * width_px)
    for word in range(2):
        letters = generator.randint(5, 7)
        for _ in range(letters):
            letter_width = int(letter_height * generator.uniform(0.45, 0.7))
            left, right = x, x + letter_width
            kind = generator.choice(('loop', 'stem', 'arch'))
            if kind == 'loop':
                cv2.ellipse(image, ((left + right) // 2, (top_px + bottom_px) // 2 + stroke),
                            (letter_width // 2 - stroke // 2, letter_height // 3), 0, 0, 360,
                            WHITE_RGB, stroke, cv2.LINE_AA)
            elif kind == 'stem':
                cv2.line(image, (left + stroke, bottom_px - stroke), (right - stroke,
                                                                     top_px + stroke),
                         WHITE_RGB, stroke, cv2.LINE_AA)
                cv2.line(image, (left + letter_width // 2, top_px + letter_height // 2),
                         (right, top_px + letter_height // 2), WHITE_RGB, stroke, cv2.LINE_AA)
            else:
                cv2.ellipse(image, ((left + right) // 2, bottom_px - stroke),
                            (letter_width // 2 - stroke // 2, letter_height - 2 * stroke), 0,
                            180, 360, WHITE_RGB, stroke, cv2.LINE_AA)
            x = right + int(stroke * generator.uniform(1.0, 1.8))
        x += int(0.12 * width_px) if word == 0 else 0
        if x >= width_px:
            break


def mesh_obj(radius_m: float, height_m: float, segments: int = MESH_SEGMENTS) -> str:
    """An OBJ upright cylinder centred on its origin, with the label's texture coordinates."""
    lines = ['# can: side, lid and base; texture coordinates into the label image']
    half = height_m / 2.0
    for index in range(segments + 1):
        angle = 2.0 * math.pi * index / segments
        x, y = radius_m * math.cos(angle), radius_m * math.sin(angle)
        lines.append('v %.6f %.6f %.6f' % (x, y, -half))
        lines.append('v %.6f %.6f %.6f' % (x, y, half))
        lines.append('vn %.6f %.6f 0' % (math.cos(angle), math.sin(angle)))
        lines.append('vt %.6f 0' % (index / segments))
        lines.append('vt %.6f 1' % (index / segments))
    lid_v = 1.0 - LID_FRACTION / 2.0
    lines += ['v 0 0 %.6f' % -half, 'v 0 0 %.6f' % half, 'vn 0 0 -1', 'vn 0 0 1',
              'vt 0.5 %.6f' % (BASE_FRACTION / 2.0), 'vt 0.5 %.6f' % lid_v]
    bottom_centre, top_centre = 2 * (segments + 1) + 1, 2 * (segments + 1) + 2
    down, up = segments + 2, segments + 3
    base_uv, lid_uv = 2 * (segments + 1) + 1, 2 * (segments + 1) + 2
    for index in range(segments):
        bottom, top = 2 * index + 1, 2 * index + 2
        next_bottom, next_top = bottom + 2, top + 2
        normal, next_normal = index + 1, index + 2
        lines.append('f %d/%d/%d %d/%d/%d %d/%d/%d' % (
            bottom, bottom, normal, next_bottom, next_bottom, next_normal, next_top, next_top,
            next_normal))
        lines.append('f %d/%d/%d %d/%d/%d %d/%d/%d' % (
            bottom, bottom, normal, next_top, next_top, next_normal, top, top, normal))
        lines.append('f %d/%d/%d %d/%d/%d %d/%d/%d' % (
            top_centre, lid_uv, up, top, lid_uv, up, next_top, lid_uv, up))
        lines.append('f %d/%d/%d %d/%d/%d %d/%d/%d' % (
            bottom_centre, base_uv, down, next_bottom, base_uv, down, bottom, base_uv, down))
    return '\n'.join(lines) + '\n'
