"""sensor_msgs/Image and sensor_msgs/CompressedImage payloads -> BGR array, every field checked.

cv_bridge accepts too much data silently, ignores row padding (rows come back scrambled) and
raises on unknown encodings from deep inside; here each problem is a clear
:class:`ImageDecodeError` so a node can log it and skip the frame. No rospy needed: the
fields are passed in (a message, or one read from a bag, has them all).
"""
from dataclasses import dataclass

import cv2
import numpy as np

from can_seeker.params import Param

# Encodings a colour detector can read, with channels and the conversion to BGR (None: as is).
COLOUR_ENCODINGS = {
    'bgr8': (3, None),
    'rgb8': (3, cv2.COLOR_RGB2BGR),
    'bgra8': (4, cv2.COLOR_BGRA2BGR),
    'rgba8': (4, cv2.COLOR_RGBA2BGR),
}
# Valid images without colour: the frame is readable but red cannot be seen in it.
GREY_ENCODINGS = ('mono8',)
# Codecs of image_transport's "compressed" plugin (and of plain "jpeg"/"png" formats).
COMPRESSED_CODECS = ('jpeg', 'jpg', 'png')


class ImageDecodeError(ValueError):
    """The message is not an image this detector can read; the reason is the message text.

    ``kind`` names the fault (one of FAULT_KINDS) so a node can throttle its log per kind of
    fault rather than per text: frames cut to ever different lengths are one fault.
    """

    def __init__(self, message: str, kind: str):
        super().__init__(message)
        self.kind = kind


class NoColourError(ImageDecodeError):
    """A valid single-channel image: a colour detector cannot see red in it."""

    def __init__(self, message: str):
        super().__init__(message, 'no colour')


# The kinds of fault an ImageDecodeError reports.
FAULT_KINDS = ('no colour', 'encoding', 'size', 'step', 'data length', 'format', 'corrupt',
               'depth')


def _check_layout(encoding: str, height: int, width: int, step: int, data_bytes: int,
                  channels: int) -> None:
    """Raise ImageDecodeError unless the sizes describe a non-empty image whose rows of
    ``width * channels`` bytes (padded to ``step``) fill exactly ``height * step`` bytes."""
    if height <= 0 or width <= 0:
        raise ImageDecodeError('empty image: %d x %d px' % (width, height), 'size')
    row_bytes = width * channels
    if step < row_bytes:
        raise ImageDecodeError('%s step is %d bytes, less than width %d x %d = %d' % (
            encoding, step, width, channels, row_bytes), 'step')
    if data_bytes != height * step:
        raise ImageDecodeError('data has %d bytes, expected height %d x step %d = %d' % (
            data_bytes, height, step, height * step), 'data length')


def decode_bgr(encoding: str, height: int, width: int, step: int, data) -> np.ndarray:
    """BGR uint8 array (height, width, 3) of an image message's fields.

    For bgr8 the array is a read-only view on ``data`` (rows padded to ``step`` bytes stay a
    strided view); other encodings are converted into a new array. Raises NoColourError for a
    well-formed mono8 image and ImageDecodeError for anything unreadable: other encodings,
    zero size, a step shorter than a row, or data that is not exactly height * step bytes.
    """
    if encoding in GREY_ENCODINGS:
        _check_layout(encoding, height, width, step, len(data), 1)
        raise NoColourError('%s image: no colour, a red can cannot be seen (send bgr8, rgb8, '
                            'bgra8 or rgba8)' % encoding)
    if encoding not in COLOUR_ENCODINGS:
        raise ImageDecodeError('unsupported encoding %r: expected one of %s' % (
            encoding, ', '.join(sorted(COLOUR_ENCODINGS))), 'encoding')
    channels, conversion = COLOUR_ENCODINGS[encoding]
    _check_layout(encoding, height, width, step, len(data), channels)
    rows = np.frombuffer(data, np.uint8).reshape(height, step)
    if step != width * channels:
        rows = rows[:, :width * channels]
    pixels = rows.reshape(height, width, channels)
    if conversion is None:
        return pixels
    return cv2.cvtColor(pixels, conversion)


def decode_image_msg(msg) -> np.ndarray:
    """:func:`decode_bgr` of a sensor_msgs/Image (live or read from a bag)."""
    return decode_bgr(msg.encoding, msg.height, msg.width, msg.step, msg.data)


def compressed_codec(image_format: str) -> str:
    """Codec of a CompressedImage ``format`` whose payload is 8-bit colour or grey.

    Formats are a bare codec ("jpeg", "png") or image_transport's
    "<encoding>; <codec> compressed <payload encoding>" (older: "<encoding>; <codec>"). Raises
    ImageDecodeError for depth formats ("16UC1; compressedDepth"), other codecs and payloads
    that are not 8-bit colour or grey (16-bit or float encodings).
    """
    parts = [part.strip() for part in image_format.split(';')]
    words = parts[-1].split()
    if any(word.lower() == 'compresseddepth' for word in words):
        raise ImageDecodeError('unsupported compressed format %r: a depth image, no colour' %
                               image_format, 'format')
    codec = words[0].lower() if words else ''
    if codec not in COMPRESSED_CODECS:
        raise ImageDecodeError('unsupported compressed format %r: expected a %s codec' % (
            image_format, ' or '.join(COMPRESSED_CODECS)), 'format')
    payload_encoding = words[2] if words[1:2] == ['compressed'] and len(words) > 2 else (
        parts[0] if len(parts) > 1 else None)
    if payload_encoding is not None and payload_encoding not in COLOUR_ENCODINGS and \
            payload_encoding not in GREY_ENCODINGS:
        raise ImageDecodeError('unsupported compressed format %r: %s is not an 8-bit colour or '
                               'grey encoding' % (image_format, payload_encoding), 'format')
    return codec


def decode_compressed_bgr(image_format: str, data) -> np.ndarray:
    """BGR uint8 array (height, width, 3) of a CompressedImage's fields (grey comes back grey).

    Raises ImageDecodeError for a format :func:`compressed_codec` rejects, empty data, data
    cv2.imdecode cannot read (corrupt, or a truncated PNG; libjpeg only warns about a JPEG cut
    short and fills its missing rows with grey) and images that decode to more than 8 bits per
    channel (a 16-bit PNG under a bare "png" format).
    """
    codec = compressed_codec(image_format)
    if len(data) == 0:
        raise ImageDecodeError('empty %s image: no data' % codec, 'size')
    bgr = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR | cv2.IMREAD_ANYDEPTH)
    if bgr is None:
        raise ImageDecodeError('corrupt %s image: %d bytes cv2.imdecode cannot read' % (
            codec, len(data)), 'corrupt')
    if bgr.dtype != np.uint8:
        raise ImageDecodeError('unsupported %s image depth: %s pixels, expected 8-bit' % (
            codec, bgr.dtype), 'depth')
    return bgr


def decode_compressed_msg(msg) -> np.ndarray:
    """:func:`decode_compressed_bgr` of a sensor_msgs/CompressedImage (live or read from a bag)."""
    return decode_compressed_bgr(msg.format, msg.data)


# The decoder of each image message type, by its ROS type name (a message's ``_type``).
MESSAGE_DECODERS = {
    'sensor_msgs/Image': decode_image_msg,
    'sensor_msgs/CompressedImage': decode_compressed_msg,
}

# The message type of each ~image_transport (image_transport's names for the raw and
# compressed plugins).
TRANSPORT_MESSAGE_TYPES = {
    'raw': 'sensor_msgs/Image',
    'compressed': 'sensor_msgs/CompressedImage',
}
IMAGE_TRANSPORT_PARAMS = (
    Param('image_transport', 'raw', 'input images: raw (sensor_msgs/Image on image) or '
          'compressed (sensor_msgs/CompressedImage, jpeg or png, on image/compressed, as '
          "raspicam_node and image_transport's compressed plugin publish)",
          choices=tuple(TRANSPORT_MESSAGE_TYPES)),
)
"""How an image node takes its images."""


def transport_topic(image_topic: str, transport: str) -> str:
    """The topic a ``transport`` subscriber of the resolved ``image_topic`` reads, as
    image_transport names it: the topic itself (raw) or ``<image_topic>/compressed``."""
    if transport == 'raw':
        return image_topic
    return image_topic.rstrip('/') + '/' + transport


@dataclass(frozen=True)
class DecodedImage:
    """A decoded image message: the header it came with (outputs carry it) and its BGR pixels,
    whose size stands in for the width and height a CompressedImage does not have."""

    header: object
    bgr: np.ndarray

    @property
    def width(self) -> int:
        return self.bgr.shape[1]

    @property
    def height(self) -> int:
        return self.bgr.shape[0]
