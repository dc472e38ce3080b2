"""view.launch: the 'origin' window takes the camera through the image_transport asked for, so
a compressed camera (raspicam_node) shows where the compressed plugin is installed."""
import pathlib
import subprocess

import yaml

LAUNCH = pathlib.Path(__file__).resolve().parents[2] / 'launch' / 'view.launch'


def params(*args):
    result = subprocess.run(['roslaunch', '--dump-params', str(LAUNCH)] + list(args),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, check=False)
    assert result.returncode == 0, result.stdout
    return yaml.safe_load(result.stdout)


def test_the_camera_window_is_raw_by_default():
    assert params()['/view_origin/image_transport'] == 'raw'


def test_a_compressed_camera_reaches_the_camera_window_only():
    dumped = params('camera:=raspicam_node/image', 'image_transport:=compressed')
    assert dumped['/view_origin/image_transport'] == 'compressed'
    # the detector's images are raw topics of image_converter's own
    assert '/view_result/image_transport' not in dumped
    assert '/view_edges/image_transport' not in dumped
