"""calibrate_colour: red-mask thresholds for your can under your light, as a params YAML.

Samples the can's colour from an image file, a bag (Image or CompressedImage topic) or a live
topic, inside ``--box x,y,w,h`` or around the can the detector finds at its defaults, and
prints (or writes with ``--output``) the thresholds of ``--colour-model`` as flat private
parameters (see vision/colour_calibration.py for the rule):

    rosrun dynamic_reconfigure dynparam load /image_converter can.yaml   # a running node
    rosparam load can.yaml /image_converter   # before rosrun can_seeker image_converter

(image_converter.launch sets every parameter from its args, which win over a rosparam load:
pass the values as args there.)
"""
import argparse
import sys

import cv2
import numpy as np

from can_seeker.vision.colour_calibration import (CalibrationError, can_pixels, params_yaml,
                                                  parse_box, thresholds, widened_box)
from can_seeker.vision.detector import COLOUR_MODELS, RedCanDetector
from can_seeker.vision.image_decode import MESSAGE_DECODERS, ImageDecodeError
from can_seeker.vision.report import CanModel, can_report

BOX_MARGIN = 0.15
"""The detected can's box is widened by this fraction each side: its dim edge pixels, which
the defaults may just miss, are sampled too."""


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument('--image', metavar='FILE', help='an image file (png, jpeg, ...)')
    source.add_argument('--bag', metavar='FILE', help='a bag with camera images')
    source.add_argument('--topic', help='a live sensor_msgs/Image or CompressedImage topic')
    parser.add_argument('--image-topic', help='image topic of --bag (default: '
                        '/camera/image_raw, else the bag\'s only image topic)')
    parser.add_argument('--box', help='x,y,width,height (px) of the can in every frame; '
                                      'default: around the can the detector finds')
    parser.add_argument('--colour-model', choices=COLOUR_MODELS, default='chromaticity',
                        help='the thresholds to write (default %(default)s)')
    parser.add_argument('--frames', type=int, default=20,
                        help='frames sampled from a bag (spread over it) or a topic '
                             '(default %(default)s)')
    parser.add_argument('--low', type=float, default=2.0, help='low percentile kept')
    parser.add_argument('--high', type=float, default=98.0, help='high percentile kept')
    parser.add_argument('--output', '-o', help='YAML file to write (default: print)')
    return parser.parse_args(argv)


def can_box(bgr, detector):
    """Box of the most can-like red blob, widened by BOX_MARGIN; None when there is none."""
    result = detector.detect(bgr)
    height, width = bgr.shape[:2]
    report = can_report(result.candidates, width, height, None, None, CanModel())
    if report.chosen is None:
        return None
    blob = result.candidates[report.chosen]
    return widened_box((blob.x, blob.y, blob.width, blob.height), BOX_MARGIN, width, height)


def bag_frames(path, image_topic, count):
    """Up to ``count`` decoded frames spread evenly over the bag's image topic."""
    import rosbag
    from can_seeker.tools.bag_detect import choose_image_topic
    with rosbag.Bag(path) as bag:
        topic_types = {topic: info.msg_type
                       for topic, info in bag.get_type_and_topic_info().topics.items()}
        topic, message_type = choose_image_topic(topic_types, image_topic)
        total = bag.get_message_count(topic)
        wanted = set(np.linspace(0, total - 1, min(count, total)).round().astype(int).tolist())
        decode = MESSAGE_DECODERS[message_type]
        for index, (_, msg, _) in enumerate(bag.read_messages(topics=[topic])):
            if index in wanted:
                yield decode_or_none(decode, msg, 'frame %d of %s' % (index, topic))


def topic_frames(topic, count):
    """``count`` decoded frames of a live topic (its type looked up on the master)."""
    import rospy
    import rostopic
    rospy.init_node('calibrate_colour', anonymous=True)
    message_class, real_topic, _ = rostopic.get_topic_class(topic, blocking=True)
    message_type = message_class._type
    if message_type not in MESSAGE_DECODERS:
        raise SystemExit('calibrate_colour: %s holds %s, expected %s' % (
            topic, message_type, ' or '.join(sorted(MESSAGE_DECODERS))))
    decode = MESSAGE_DECODERS[message_type]
    for index in range(count):
        msg = rospy.wait_for_message(real_topic, message_class, timeout=10.0)
        yield decode_or_none(decode, msg, 'frame %d of %s' % (index, topic))


def decode_or_none(decode, msg, where):
    try:
        return decode(msg)
    except ImageDecodeError as error:
        print('calibrate_colour: %s skipped: %s' % (where, error), file=sys.stderr)
        return None


def frames_of(args):
    if args.image:
        bgr = cv2.imread(args.image, cv2.IMREAD_COLOR)
        if bgr is None:
            raise SystemExit('calibrate_colour: cannot read the image %s' % args.image)
        return [bgr]
    if args.bag:
        return bag_frames(args.bag, args.image_topic, args.frames)
    return topic_frames(args.topic, args.frames)


def sample(frames, box):
    """(pixels, frames used, frames without a can) pooled over the frames."""
    detector = RedCanDetector()
    pooled, used, missed = [], 0, 0
    for bgr in frames:
        if bgr is None:
            continue
        frame_box = box if box is not None else can_box(bgr, detector)
        if frame_box is None:
            missed += 1
            continue
        pooled.append(can_pixels(bgr, frame_box))
        used += 1
    pixels = np.concatenate(pooled) if pooled else np.empty((0, 3), np.uint8)
    return pixels, used, missed


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        box = parse_box(args.box) if args.box else None
        pixels, used, missed = sample(frames_of(args), box)
        if used == 0:
            raise CalibrationError('no frame to sample: %s' % (
                'the detector found no red blob (give --box)' if box is None else 'none read'))
        values = thresholds(pixels, args.colour_model, args.low, args.high)
    except CalibrationError as error:
        raise SystemExit('calibrate_colour: %s' % error)
    source = args.image or args.bag or args.topic
    comments = ['calibrate_colour: %d can pixels of %d frame(s) of %s, %s, percentiles %g-%g' % (
        len(pixels), used, source, 'box %s' % args.box if box else 'around the detected can',
        args.low, args.high)]
    if missed:
        comments.append('%d frame(s) without a detected can were left out' % missed)
    text = params_yaml(values, comments)
    if args.output:
        with open(args.output, 'w') as output:
            output.write(text)
        print('calibrate_colour: wrote %s' % args.output, file=sys.stderr)
    else:
        sys.stdout.write(text)
    return values
