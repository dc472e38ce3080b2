#!/usr/bin/env python3
"""Watches a running demo.launch (at ROS_MASTER_URI) until the controller reports STOPPED, then
writes what it saw as JSON: the detections (count, first one with a range), the controller
states, the true gap between robot and can, the command line of every node and the files the
can_seeker modules were loaded from.

Usage: demo_probe.py OUTPUT.json TIMEOUT_S
"""
import json
import math
import sys
import time
import xmlrpc.client

import rosgraph
import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from std_msgs.msg import String

import can_seeker
import can_seeker.msg
from can_seeker.control.controller import PARAMS as CONTROLLER_PARAMS
from can_seeker.control.tuning import CAN_RADIUS_M
from can_seeker.msg import CanDetection
from can_seeker.params import defaults

CONTROLLER = defaults(CONTROLLER_PARAMS)
SETTLE_S = 1.0
"""Wall time between STOPPED and the ground-truth reading, for the base to come to rest."""


class Watcher:
    """Keeps the detections, the distinct controller states and the latest ground truth."""

    def __init__(self):
        self.found = []
        self.states = []
        self.robot_xy = None
        self.can_xy = None
        rospy.Subscriber('/image_converter/detection', CanDetection, self.on_detection)
        rospy.Subscriber('/can_stopper/state', String, self.on_state)
        rospy.Subscriber('/sim/base_pose_ground_truth', Odometry, self.on_odom)
        rospy.Subscriber('/sim/can_pose', PoseStamped, self.on_can_pose)

    def on_detection(self, message):
        if message.found:
            self.found.append({'range_m': message.range, 'bearing_rad': message.bearing,
                               'centroid_px': [message.centroid_x, message.centroid_y]})

    def on_state(self, message):
        if not self.states or self.states[-1] != message.data:
            self.states.append(message.data)

    def on_odom(self, message):
        self.robot_xy = (message.pose.pose.position.x, message.pose.pose.position.y)

    def on_can_pose(self, message):
        self.can_xy = (message.pose.position.x, message.pose.position.y)

    def gap_m(self):
        """True gap between the robot front and the can's near surface."""
        centres_m = math.hypot(self.can_xy[0] - self.robot_xy[0], self.can_xy[1] - self.robot_xy[1])
        return centres_m - CONTROLLER.robot_radius - CAN_RADIUS_M


def node_command_lines(master):
    """{node name: its process's command line}, asked from each node through the master."""
    publishers, subscribers, _ = master.getSystemState()
    names = {node for _, nodes in publishers + subscribers for node in nodes}
    command_lines = {}
    for name in sorted(names):
        pid = xmlrpc.client.ServerProxy(master.lookupNode(name)).getPid('/demo_probe')[2]
        with open('/proc/%d/cmdline' % pid) as cmdline:
            command_lines[name] = cmdline.read().rstrip('\0').split('\0')
    return command_lines


def main():
    output_path, timeout_s = sys.argv[1], float(sys.argv[2])
    deadline = time.monotonic() + timeout_s
    master = rosgraph.Master('/demo_probe')
    while not master.is_online():
        if time.monotonic() > deadline:
            sys.exit('demo_probe: no master at %s' % rosgraph.get_master_uri())
        time.sleep(0.2)
    rospy.init_node('demo_probe', disable_signals=True)
    watcher = Watcher()
    while not (watcher.states and watcher.states[-1] == 'STOPPED' and watcher.found):
        if time.monotonic() > deadline:
            break
        time.sleep(0.1)
    time.sleep(SETTLE_S)
    stopped = bool(watcher.states) and watcher.states[-1] == 'STOPPED'
    report = {
        'states': watcher.states,
        'detections_found': len(watcher.found),
        'first_ranged': next((f for f in watcher.found if math.isfinite(f['range_m'])), None),
        'gap_m': watcher.gap_m() if stopped and watcher.robot_xy and watcher.can_xy else None,
        'stop_distance_m': rospy.get_param('/can_stopper/stop_distance'),
        'nodes': node_command_lines(master),
        'modules': {'can_seeker': can_seeker.__file__, 'can_seeker.msg': can_seeker.msg.__file__},
    }
    with open(output_path, 'w') as output:
        json.dump(report, output, indent=2)


if __name__ == '__main__':
    main()
