"""bag_detect's choice of topics in a bag (the camera_info beside the image topic, as a camera
driver lays them out: raspicam_node has image/compressed and camera_info in one namespace), and
its report of frames the bag's TF gives no camera pose for."""
import pathlib

from can_seeker.tools.bag_detect import choose_camera_info_topic

INFO = 'sensor_msgs/CameraInfo'
IMAGE = 'sensor_msgs/Image'
COMPRESSED = 'sensor_msgs/CompressedImage'


def test_the_camera_info_beside_a_compressed_image_topic():
    bag = {'/raspicam_node/image/compressed': COMPRESSED, '/raspicam_node/camera_info': INFO,
           '/other/camera_info': INFO}
    assert choose_camera_info_topic(bag, '/raspicam_node/image/compressed', None) == \
        '/raspicam_node/camera_info'


def test_the_camera_info_beside_a_raw_image_topic():
    bag = {'/usb_cam/image_raw': IMAGE, '/usb_cam/camera_info': INFO, '/camera/camera_info': INFO}
    assert choose_camera_info_topic(bag, '/usb_cam/image_raw', None) == '/usb_cam/camera_info'


def test_else_the_bags_only_camera_info():
    bag = {'/front/image': IMAGE, '/front_info': INFO}
    assert choose_camera_info_topic(bag, '/front/image', None) == '/front_info'


def test_none_when_the_bag_has_no_camera_info_to_choose():
    assert choose_camera_info_topic({'/cam/image_raw': IMAGE}, '/cam/image_raw', None) is None
    two = {'/cam/image_raw': IMAGE, '/a/camera_info': INFO, '/b/camera_info': INFO}
    assert choose_camera_info_topic(two, '/cam/image_raw', None) is None


def test_a_requested_topic_is_taken_only_when_the_bag_holds_it():
    bag = {'/cam/image_raw': IMAGE, '/cam/camera_info': INFO}
    assert choose_camera_info_topic(bag, '/cam/image_raw', '/cam/camera_info') == '/cam/camera_info'
    assert choose_camera_info_topic(bag, '/cam/image_raw', '/camera/camera_info') is None


def test_frames_without_a_camera_pose_are_reported_with_the_missing_transform(tmp_path, capsys):
    """The bag's TF has base_link; a robot whose base is base_footprint is told what to set."""
    from can_seeker.tools.bag_detect import main as bag_detect
    bag = pathlib.Path(__file__).resolve().parents[1] / 'data' / 'sim_can_320x240.bag'
    bag_detect([str(bag), '--csv', str(tmp_path / 'run.csv'), '--param',
                'base_frame=base_footprint'])
    err = capsys.readouterr().err
    assert 'frames without a camera pose' in err
    assert 'no TF base_footprint <- camera_optical_frame' in err
    assert '--param base_frame=NAME' in err
    bag_detect([str(bag), '--csv', str(tmp_path / 'run.csv')])
    assert 'without a camera pose' not in capsys.readouterr().err
