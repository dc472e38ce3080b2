"""playback.launch feeds a bag's camera to image_converter as it was recorded: raw Images, or
CompressedImages (raspicam_node's image/compressed) with image_transport:=compressed. What
roslaunch would set (--dump-params and its loader), no master needed."""
import roslaunch.config

from launch_query import LAUNCH_DIR, dumped_params


def launched(*args):
    """(parameters, image_converter's remaps) of playback.launch with ``args``."""
    args = ('bag:=/tmp/run.bag',) + args
    config = roslaunch.config.load_config_default(
        [(str(LAUNCH_DIR / 'playback.launch'), list(args))], None)
    node = next(node for node in config.nodes if node.name == 'image_converter')
    return dumped_params('playback.launch', *args), dict(node.remap_args)


def test_a_bag_of_raw_images_is_read_raw():
    params, remaps = launched()
    assert params['/image_converter/image_transport'] == 'raw'
    assert remaps['image'] == 'camera/image_raw'


def test_a_bag_of_compressed_images_is_read_compressed():
    params, remaps = launched('image:=/raspicam_node/image', 'image_transport:=compressed',
                              'camera_info:=/raspicam_node/camera_info')
    assert params['/image_converter/image_transport'] == 'compressed'
    assert remaps['image'] == '/raspicam_node/image'
    assert remaps['camera_info'] == '/raspicam_node/camera_info'
