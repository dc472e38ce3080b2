"""playback.launch feeds a bag's camera to image_converter as it was recorded: raw Images, or
CompressedImages (raspicam_node's image/compressed) with image_transport:=compressed. What
roslaunch would set (--dump-params and its loader), no master needed."""
import pathlib
import subprocess

import roslaunch.config
import yaml

LAUNCH = pathlib.Path(__file__).resolve().parents[2] / 'launch' / 'playback.launch'


def launched(*args):
    """(parameters, image_converter's remaps) of playback.launch with ``args``."""
    result = subprocess.run(['roslaunch', '--dump-params', str(LAUNCH), 'bag:=/tmp/run.bag']
                            + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, check=False)
    assert result.returncode == 0, result.stdout
    config = roslaunch.config.load_config_default(
        [(str(LAUNCH), ['bag:=/tmp/run.bag'] + list(args))], None)
    node = next(node for node in config.nodes if node.name == 'image_converter')
    return yaml.safe_load(result.stdout), dict(node.remap_args)


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
