"""Images the nodes publish: the message written straight from a numpy array is byte for byte
the sensor_msgs/Image that cv_bridge-style code (data as bytes) would send."""
import io

import numpy as np
import pytest
import rospy
from sensor_msgs.msg import Image
from std_msgs.msg import Header

from can_seeker.ros.messages import image_msg


def wire_bytes(msg):
    buff = io.BytesIO()
    msg.serialize(buff)
    return buff.getvalue()


@pytest.mark.parametrize('shape, encoding', [((48, 64), 'mono8'), ((48, 64, 3), 'bgr8')])
def test_array_image_is_serialised_as_an_image_of_its_bytes(shape, encoding):
    array = np.random.default_rng(1).integers(0, 256, shape, np.uint8)
    header = Header(seq=7, stamp=rospy.Time(12, 345), frame_id='camera_optical_frame')
    msg = image_msg(header, array, encoding)
    expected = Image(header=header, height=shape[0], width=shape[1], encoding=encoding,
                     is_bigendian=0, step=shape[1] * (shape[2] if len(shape) > 2 else 1),
                     data=array.tobytes())
    assert wire_bytes(msg) == wire_bytes(expected)
    decoded = Image().deserialize(wire_bytes(msg))
    assert decoded.header.stamp == header.stamp and decoded.header.frame_id == header.frame_id
    assert np.array_equal(np.frombuffer(decoded.data, np.uint8).reshape(shape), array)


def test_a_strided_view_is_sent_as_its_pixels():
    array = np.arange(48 * 64 * 3, dtype=np.uint32).astype(np.uint8).reshape(48, 64, 3)
    view = array[10:20, 5:25]
    decoded = Image().deserialize(wire_bytes(image_msg(Header(), view, 'bgr8')))
    assert (decoded.height, decoded.width, decoded.step) == (10, 20, 60)
    assert np.array_equal(np.frombuffer(decoded.data, np.uint8).reshape(10, 20, 3), view)
