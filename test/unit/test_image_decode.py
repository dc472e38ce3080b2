"""Image message fields -> BGR array, and a clear error for every kind of bad message."""
import numpy as np
import pytest

from can_seeker.image_decode import ImageDecodeError, NoColourError, decode_bgr

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


def test_padded_or_short_step_is_rejected(bgr):
    good = fields(bgr, 'bgr8')
    padded = np.zeros((HEIGHT, WIDTH * 3 + 2), np.uint8)
    padded[:, :WIDTH * 3] = bgr.reshape(HEIGHT, -1)
    with pytest.raises(ImageDecodeError, match='padded rows'):
        decode_bgr(**dict(good, step=WIDTH * 3 + 2, data=padded.tobytes()))
    with pytest.raises(ImageDecodeError, match='step'):
        decode_bgr(**dict(good, step=WIDTH * 3 - 3, data=good['data'][:HEIGHT * (WIDTH * 3 - 3)]))


@pytest.mark.parametrize('height, width', [(0, 0), (0, WIDTH), (HEIGHT, 0)])
def test_zero_sized_images_are_rejected(height, width):
    with pytest.raises(ImageDecodeError, match='empty image'):
        decode_bgr('bgr8', height, width, width * 3, b'')
