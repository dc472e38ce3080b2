"""view.launch: the 'origin' window takes the camera through the image_transport asked for, so
a compressed camera (raspicam_node) shows where the compressed plugin is installed."""
from launch_query import dumped_params


def params(*args):
    return dumped_params('view.launch', *args)


def test_the_camera_window_is_raw_by_default():
    assert params()['/view_origin/image_transport'] == 'raw'


def test_a_compressed_camera_reaches_the_camera_window_only():
    dumped = params('camera:=raspicam_node/image', 'image_transport:=compressed')
    assert dumped['/view_origin/image_transport'] == 'compressed'
    # the detector's images are raw topics of image_converter's own
    assert '/view_result/image_transport' not in dumped
    assert '/view_edges/image_transport' not in dumped
