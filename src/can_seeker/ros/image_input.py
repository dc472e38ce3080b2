"""The image input of the image nodes: ``image`` as sensor_msgs/Image, or its image_transport
``compressed`` topic as sensor_msgs/CompressedImage, with the decoder for what arrives."""
import rospy
from sensor_msgs.msg import CompressedImage, Image

from can_seeker.ros.messages import IMAGE_BUFF_SIZE
from can_seeker.vision.image_decode import MESSAGE_DECODERS, transport_topic

IMAGE_MESSAGES = {'raw': Image, 'compressed': CompressedImage}
"""The message type of each ~image_transport."""


def image_decoder(transport: str):
    """The decoder (message -> BGR pixels) of the messages a ``transport`` subscriber gets."""
    return MESSAGE_DECODERS[IMAGE_MESSAGES[transport]._type]


def image_topic(transport: str) -> str:
    """The resolved topic the images of ``transport`` arrive on: ``image``, or its
    ``transport`` subtopic."""
    return transport_topic(rospy.resolve_name('image'), transport)


def subscribe_images(node_name: str, transport: str, callback) -> None:
    """Subscribe ``image`` (or its ``transport`` topic) to ``callback``, always the newest
    frame (decode with :func:`image_decoder`)."""
    message_class = IMAGE_MESSAGES[transport]
    topic = image_topic(transport)
    if transport != 'raw':
        rospy.loginfo('%s: reading %s images from %s' % (node_name, transport, topic))
    rospy.Subscriber(topic, message_class, callback, queue_size=1, buff_size=IMAGE_BUFF_SIZE,
                     tcp_nodelay=True)
