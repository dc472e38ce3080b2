"""sensor_msgs/Image payload -> BGR array, with every field checked first.

cv_bridge accepts too much data silently, ignores row padding (rows come back scrambled) and
raises on unknown encodings from deep inside; here each problem is a clear
:class:`ImageDecodeError` so a node can log it and skip the frame. No rospy needed: the
fields are passed in (a message, or one read from a bag, has them all).
"""
import cv2
import numpy as np

# Encodings a colour detector can read, with channels and the conversion to BGR (None: as is).
COLOUR_ENCODINGS = {
    'bgr8': (3, None),
    'rgb8': (3, cv2.COLOR_RGB2BGR),
    'bgra8': (4, cv2.COLOR_BGRA2BGR),
    'rgba8': (4, cv2.COLOR_RGBA2BGR),
}
# Valid images without colour: the frame is readable but red cannot be seen in it.
GREY_ENCODINGS = ('mono8',)


class ImageDecodeError(ValueError):
    """The message is not an image this detector can read; the reason is the message text."""


class NoColourError(ImageDecodeError):
    """A valid single-channel image: a colour detector cannot see red in it."""


def decode_bgr(encoding: str, height: int, width: int, step: int, data) -> np.ndarray:
    """BGR uint8 array (height, width, 3) of an image message's fields.

    For bgr8 the array is a read-only view on ``data``; other encodings are converted into a new
    array. Raises NoColourError for mono8 and ImageDecodeError for anything unreadable: other
    encodings, zero size, a step that is not exactly width * bytes per pixel (padded rows are
    not supported), or data that is not exactly height * step bytes.
    """
    if encoding in GREY_ENCODINGS:
        raise NoColourError('%s image: no colour, a red can cannot be seen (send bgr8, rgb8, '
                            'bgra8 or rgba8)' % encoding)
    if encoding not in COLOUR_ENCODINGS:
        raise ImageDecodeError('unsupported encoding %r: expected one of %s' % (
            encoding, ', '.join(sorted(COLOUR_ENCODINGS))))
    if height <= 0 or width <= 0:
        raise ImageDecodeError('empty image: %d x %d px' % (width, height))
    channels, conversion = COLOUR_ENCODINGS[encoding]
    row_bytes = width * channels
    if step != row_bytes:
        raise ImageDecodeError('%s step is %d bytes, expected width %d x %d = %d (padded rows '
                               'are not supported)' % (encoding, step, width, channels, row_bytes))
    if len(data) != height * step:
        raise ImageDecodeError('data has %d bytes, expected height %d x step %d = %d' % (
            len(data), height, step, height * step))
    pixels = np.frombuffer(data, np.uint8).reshape(height, width, channels)
    if conversion is None:
        return pixels
    return cv2.cvtColor(pixels, conversion)


def decode_image_msg(msg) -> np.ndarray:
    """:func:`decode_bgr` of a sensor_msgs/Image (live or read from a bag)."""
    return decode_bgr(msg.encoding, msg.height, msg.width, msg.step, msg.data)
