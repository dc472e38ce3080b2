"""teleop_keyboard: drive the robot from the keyboard, teleop_twist_keyboard-compatible.

Reads keys from the terminal on standard input (raw input mode, restored on exit) and publishes
geometry_msgs/Twist on ``cmd_vel`` (remappable), when a key is read and, with ``~repeat_rate``,
repeatedly. Keys, speeds and timeouts: :mod:`can_seeker.teleop.keyboard`. Publishes a zero
Twist when it quits (Ctrl-C, closed terminal or ROS shutdown).
"""
import sys
import threading
import time

import rospy
from geometry_msgs.msg import Twist

from can_seeker.params import read_params
from can_seeker.teleop.keyboard import HELP, PARAMS, KeyboardTeleop, TeleopCommand
from can_seeker.teleop.terminal import NotATerminalError, RawTerminal

KEY_POLL_S = 0.05
"""Longest wait for a key (s): how soon ROS shutdown, the key timeout and repeats are noticed."""
SHUTDOWN_ZERO_COUNT = 3
SHUTDOWN_ZERO_SPACING_S = 0.02


def twist(command: TeleopCommand) -> Twist:
    message = Twist()
    message.linear.x = command.linear_x
    message.linear.y = command.linear_y
    message.linear.z = command.linear_z
    message.angular.z = command.angular_z
    return message


def say(text):
    """Print to the terminal (output processing is on: plain newlines work)."""
    sys.stdout.write(text + '\n')
    sys.stdout.flush()


class TeleopNode:
    """The key loop and the zero commands at the end, never a key's command after them."""

    def __init__(self, params):
        self.teleop = KeyboardTeleop(params.speed, params.turn, params.speed_limit,
                                     params.turn_limit, params.key_timeout)
        self.repeat_period_s = 1.0 / params.repeat_rate if params.repeat_rate > 0.0 else None
        self.publisher = rospy.Publisher('cmd_vel', Twist, queue_size=1)
        self.lock = threading.Lock()
        self.stopped = False
        rospy.on_shutdown(self.stop)

    def drive(self, terminal):
        """Until Ctrl-C, a closed terminal or ROS shutdown."""
        teleop = self.teleop
        say(HELP)
        say(teleop.speeds_text())
        last_publish_s = None
        while not rospy.is_shutdown() and not teleop.quit:
            key = terminal.read_key(KEY_POLL_S)
            now_s = time.monotonic()
            speeds = (teleop.speed, teleop.turn)
            changed = teleop.on_key(key, now_s) if key else teleop.on_idle(now_s)
            if (teleop.speed, teleop.turn) != speeds:
                say(teleop.speeds_text())
            repeat_due = (self.repeat_period_s is not None and last_publish_s is not None
                          and now_s - last_publish_s >= self.repeat_period_s)
            if changed or repeat_due:
                with self.lock:
                    if not self.stopped:
                        self.publisher.publish(twist(teleop.command()))
                last_publish_s = now_s

    def stop(self):
        """Publish zero a few times (before rospy closes the publisher on shutdown)."""
        with self.lock:
            if self.stopped:
                return
            self.stopped = True
            for _ in range(SHUTDOWN_ZERO_COUNT):
                self.publisher.publish(Twist())
                time.sleep(SHUTDOWN_ZERO_SPACING_S)


def main():
    try:
        terminal = RawTerminal(sys.stdin.fileno())
    except NotATerminalError as error:
        sys.stderr.write('teleop_keyboard: %s\n' % error)
        sys.exit(1)
    rospy.init_node('teleop_keyboard')
    node = TeleopNode(read_params(PARAMS, rospy.get_param, rospy.logwarn))
    try:
        with terminal:
            node.drive(terminal)
    finally:
        node.stop()
        say('teleop_keyboard: stopped (zero Twist sent)')
