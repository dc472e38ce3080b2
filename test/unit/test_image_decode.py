"""Image and CompressedImage fields -> BGR array, and a clear error for every kind of bad
message."""
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from can_seeker.vision.image_decode import (IMAGE_TRANSPORT_PARAMS, MESSAGE_DECODERS,
                                            DecodedImage, ImageDecodeError, NoColourError,
                                            decode_bgr, decode_compressed_bgr,
                                            decode_compressed_msg, decode_image_msg,
                                            transport_topic)

HEIGHT, WIDTH = 4, 6


@pytest.fixture
def bgr():
    rng = np.random.default_rng(0)
    return rng.integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8)


def fields(array, encoding):
    height, width = array.shape[:2]
    channels = array.shape[2] if array.ndim == 3 else 1
    return dict(encoding=encoding, height=height, width=width,
                step=width * channels * array.itemsize, data=array.tobytes())


def test_bgr8_is_read_as_is(bgr):
    assert np.array_equal(decode_bgr(**fields(bgr, 'bgr8')), bgr)


def test_rgb8_is_swapped_to_bgr(bgr):
    decoded = decode_bgr(**fields(bgr[:, :, ::-1].copy(), 'rgb8'))
    assert np.array_equal(decoded, bgr)


def test_bgra8_and_rgba8_drop_alpha(bgr):
    alpha = np.full((HEIGHT, WIDTH, 1), 77, np.uint8)
    assert np.array_equal(decode_bgr(**fields(np.concatenate((bgr, alpha), 2), 'bgra8')), bgr)
    rgba = np.concatenate((bgr[:, :, ::-1], alpha), 2)
    assert np.array_equal(decode_bgr(**fields(rgba, 'rgba8')), bgr)


def test_red_stays_red_in_every_colour_encoding():
    red = np.zeros((2, 2, 3), np.uint8)
    red[..., 2] = 255
    for encoding, array in (('bgr8', red), ('rgb8', red[..., ::-1].copy()),
                            ('bgra8', np.dstack((red, np.full((2, 2), 255, np.uint8)))),
                            ('rgba8', np.dstack((red[..., ::-1], np.full((2, 2), 255, np.uint8))))):
        assert decode_bgr(**fields(array, encoding))[0, 0].tolist() == [0, 0, 255], encoding


def test_mono8_is_valid_but_has_no_colour():
    with pytest.raises(NoColourError, match='mono8'):
        decode_bgr(**fields(np.zeros((HEIGHT, WIDTH), np.uint8), 'mono8'))


@pytest.mark.parametrize('encoding, array', [
    ('16UC1', np.zeros((HEIGHT, WIDTH), np.uint16)),
    ('32FC1', np.zeros((HEIGHT, WIDTH), np.float32)),
    ('yuv422', np.zeros((HEIGHT, WIDTH, 2), np.uint8)),
    ('', np.zeros((HEIGHT, WIDTH, 3), np.uint8)),
])
def test_other_encodings_are_rejected_by_name(encoding, array):
    with pytest.raises(ImageDecodeError, match='unsupported encoding') as error:
        decode_bgr(**fields(array, encoding))
    assert not isinstance(error.value, NoColourError)


def test_short_and_long_data_are_rejected(bgr):
    good = fields(bgr, 'bgr8')
    for data in (good['data'][:-1], good['data'] + b'\0', b''):
        with pytest.raises(ImageDecodeError, match='data has %d bytes' % len(data)):
            decode_bgr(**dict(good, data=data))


@pytest.mark.parametrize('encoding, convert', [
    ('bgr8', None), ('rgb8', cv2.COLOR_BGR2RGB), ('bgra8', cv2.COLOR_BGR2BGRA),
    ('rgba8', cv2.COLOR_BGR2RGBA)])
def test_padded_step_is_decoded(bgr, encoding, convert):
    """Rows padded beyond width * bytes per pixel are legal in sensor_msgs/Image."""
    pixels = bgr if convert is None else cv2.cvtColor(bgr, convert)
    row_bytes = pixels.shape[1] * pixels.shape[2]
    for padding in (1, 2, 13):
        padded = np.full((HEIGHT, row_bytes + padding), 0xAB, np.uint8)
        padded[:, :row_bytes] = pixels.reshape(HEIGHT, -1)
        decoded = decode_bgr(encoding, HEIGHT, WIDTH, row_bytes + padding, padded.tobytes())
        assert np.array_equal(decoded, bgr), (encoding, padding)


def test_short_step_is_rejected(bgr):
    good = fields(bgr, 'bgr8')
    with pytest.raises(ImageDecodeError, match='step is 15 bytes, less than') as error:
        decode_bgr(**dict(good, step=WIDTH * 3 - 3, data=good['data'][:HEIGHT * (WIDTH * 3 - 3)]))
    assert error.value.kind == 'step'


def test_padded_data_must_fill_every_padded_row(bgr):
    padded = np.zeros((HEIGHT, WIDTH * 3 + 2), np.uint8).tobytes()
    with pytest.raises(ImageDecodeError, match='data has') as error:
        decode_bgr('bgr8', HEIGHT, WIDTH, WIDTH * 3 + 2, padded[:-2])
    assert error.value.kind == 'data length'


@pytest.mark.parametrize('height, width, data', [
    (0, 0, b''), (100000, 100000, b'\0' * 300), (HEIGHT, WIDTH, b'\0' * (HEIGHT * WIDTH - 1))],
    ids=['0x0 no data', '100000x100000 300 bytes', 'one byte short'])
def test_malformed_mono8_is_rejected_not_taken_as_grey(height, width, data):
    with pytest.raises(ImageDecodeError) as error:
        decode_bgr('mono8', height, width, width, data)
    assert not isinstance(error.value, NoColourError)
    assert error.value.kind in ('size', 'data length')


def test_every_fault_has_a_kind(bgr):
    good = fields(bgr, 'bgr8')
    kinds = {}
    for name, bad in (('encoding', dict(good, encoding='yuv422')),
                      ('size', dict(good, height=0, data=b'')),
                      ('step', dict(good, step=5)),
                      ('data length', dict(good, data=good['data'][:7])),
                      ('other data length', dict(good, data=good['data'][:9])),
                      ('no colour', dict(good, encoding='mono8', step=WIDTH,
                                         data=good['data'][:HEIGHT * WIDTH]))):
        with pytest.raises(ImageDecodeError) as error:
            decode_bgr(**bad)
        kinds[name] = error.value.kind
    assert kinds == {'encoding': 'encoding', 'size': 'size', 'step': 'step',
                     'data length': 'data length', 'other data length': 'data length',
                     'no colour': 'no colour'}


@pytest.mark.parametrize('height, width', [(0, 0), (0, WIDTH), (HEIGHT, 0)])
def test_zero_sized_images_are_rejected(height, width):
    with pytest.raises(ImageDecodeError, match='empty image'):
        decode_bgr('bgr8', height, width, width * 3, b'')


def red_square_image():
    """Black 320x240 BGR image with a pure red 40x30 px square at columns 150-189, rows 100-129."""
    image = np.zeros((240, 320, 3), np.uint8)
    image[100:130, 150:190] = (0, 0, 255)
    return image


def encoded(image, extension, *params):
    ok, buffer = cv2.imencode(extension, image, list(params))
    assert ok
    return buffer.tobytes()


@pytest.mark.parametrize('image_format, extension, params', [
    ('jpeg', '.jpg', (cv2.IMWRITE_JPEG_QUALITY, 90)),
    ('rgb8; jpeg compressed bgr8', '.jpg', (cv2.IMWRITE_JPEG_QUALITY, 90)),
    ('png', '.png', ()),
    ('bgr8; png compressed bgr8', '.png', ()),
])
def test_compressed_red_square_stays_red_where_it_was(image_format, extension, params):
    image = red_square_image()
    decoded = decode_compressed_bgr(image_format, encoded(image, extension, *params))
    assert decoded.shape == image.shape and decoded.dtype == np.uint8
    blue, green, red = (decoded[..., channel].astype(int) for channel in range(3))
    red_pixels = (red > 200) & (green < 50) & (blue < 50)
    rows, columns = np.nonzero(red_pixels)
    assert (rows.min(), rows.max(), columns.min(), columns.max()) == (100, 129, 150, 189)
    assert red_pixels.sum() >= 0.9 * 30 * 40
    if extension == '.png':
        assert np.array_equal(decoded, image)


def test_compressed_grey_comes_back_as_grey_bgr():
    grey = np.full((8, 10), 77, np.uint8)
    decoded = decode_compressed_bgr('mono8; png compressed mono8', encoded(grey, '.png'))
    assert decoded.shape == (8, 10, 3)
    assert np.all(decoded == 77)


def test_compressed_message_fields_are_read():
    message = SimpleNamespace(format='png', data=encoded(red_square_image(), '.png'))
    assert np.array_equal(decode_compressed_msg(message), red_square_image())
    assert MESSAGE_DECODERS['sensor_msgs/CompressedImage'] is decode_compressed_msg
    assert MESSAGE_DECODERS['sensor_msgs/Image'] is decode_image_msg


@pytest.mark.parametrize('image_format, extension', [('jpeg', '.jpg'), ('png', '.png')])
def test_corrupt_compressed_data_is_rejected(image_format, extension):
    data = encoded(red_square_image(), extension)
    flipped = data[:200] + bytes(byte ^ 0xff for byte in data[200:400]) + data[400:]
    for corrupt in (flipped, data[:20], bytes(range(256)) * 4):
        with pytest.raises(ImageDecodeError, match='corrupt %s image: %d bytes' % (
                image_format, len(corrupt))):
            decode_compressed_bgr(image_format, corrupt)


def test_truncated_png_is_rejected():
    data = encoded(red_square_image(), '.png')
    with pytest.raises(ImageDecodeError, match='corrupt png image'):
        decode_compressed_bgr('png', data[:len(data) // 2])


def test_empty_compressed_data_is_rejected():
    with pytest.raises(ImageDecodeError, match='empty jpeg image'):
        decode_compressed_bgr('rgb8; jpeg compressed bgr8', b'')


@pytest.mark.parametrize('image_format', [
    '16UC1; compressedDepth', '32FC1; compressedDepth png', '16UC1; compressedDepth rvl'])
def test_compressed_depth_is_rejected(image_format):
    depth = np.full((8, 10), 1000, np.uint16)
    with pytest.raises(ImageDecodeError, match='depth image, no colour'):
        decode_compressed_bgr(image_format, b'\0' * 12 + encoded(depth, '.png'))


@pytest.mark.parametrize('image_format', [
    'bgr16; png compressed bgr16', 'mono16; png compressed mono16', '16UC1; png'])
def test_16_bit_compressed_formats_are_rejected_by_name(image_format):
    with pytest.raises(ImageDecodeError, match='not an 8-bit colour or grey encoding'):
        decode_compressed_bgr(image_format, encoded(np.zeros((8, 10), np.uint16), '.png'))


def test_16_bit_png_under_a_bare_format_is_rejected():
    with pytest.raises(ImageDecodeError, match='image depth: uint16'):
        decode_compressed_bgr('png', encoded(np.full((8, 10, 3), 1000, np.uint16), '.png'))


@pytest.mark.parametrize('image_format', ['', 'theora', 'rgb8; tiff compressed bgr8'])
def test_other_compressed_codecs_are_rejected_by_name(image_format):
    with pytest.raises(ImageDecodeError, match='unsupported compressed format'):
        decode_compressed_bgr(image_format, encoded(red_square_image(), '.png'))


def test_transport_topics_follow_image_transport_naming():
    assert transport_topic('/camera/image_raw', 'raw') == '/camera/image_raw'
    assert transport_topic('/raspicam_node/image', 'compressed') == \
        '/raspicam_node/image/compressed'
    transport, = IMAGE_TRANSPORT_PARAMS
    assert transport.default == 'raw'
    assert transport.choices == ('raw', 'compressed')


def test_decoded_image_keeps_the_header_and_takes_its_size_from_the_pixels():
    header = SimpleNamespace(frame_id='camera_optical_frame')
    image = DecodedImage(header, decode_compressed_bgr('png', encoded(red_square_image(), '.png')))
    assert image.header is header
    assert (image.width, image.height) == (320, 240)
