"""twist_mux: forwards the velocity command of the highest-priority fresh input to ``cmd_vel``.

Inputs come from ``~inputs`` (topic:priority:timeout_s, e.g. keyboard teleop over can_stopper);
the rules are :mod:`can_seeker.teleop.mux`. Publishes ``~active`` (std_msgs/String, latched:
the input in control, or empty), one zero Twist when every input has gone stale, zero on
shutdown, and /diagnostics (the input in control; each input's rate and age).
"""
import threading
import time

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import String

from can_seeker.health import OK, WARN, Health, InputMonitor
from can_seeker.ros.diagnostics import NodeDiagnostics
from can_seeker.params import read_params
from can_seeker.teleop.mux import PARAMS, TwistMux, parse_inputs

SHUTDOWN_ZERO_COUNT = 3
SHUTDOWN_ZERO_SPACING_S = 0.02


class TwistMuxNode:
    def __init__(self):
        params = read_params(PARAMS, rospy.get_param, rospy.logwarn)
        try:
            inputs = parse_inputs(params.inputs)
        except ValueError as error:
            default = next(spec.default for spec in PARAMS if spec.name == 'inputs')
            rospy.logerr('twist_mux: ~inputs %r: %s; using the default %r'
                         % (params.inputs, error, default))
            inputs = parse_inputs(default)
        self.mux = TwistMux(inputs)
        self.lock = threading.Lock()
        self.shutting_down = False
        self.cmd_pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)
        self.active_pub = rospy.Publisher('~active', String, queue_size=1, latch=True)
        self.active_topic = None
        self.publish_active(rospy.get_time())
        # A silent input is normal (nobody at the keys): its status stays OK.
        self.monitors = [InputMonitor(entry.topic, entry.timeout_s, OK,
                                      topic=rospy.resolve_name(entry.topic))
                         for entry in inputs]
        self.diagnostics = NodeDiagnostics()
        self.diagnostics.add('output', self.output_health)
        for index, entry in enumerate(inputs):
            self.diagnostics.add_input(self.monitors[index])
            rospy.Subscriber(entry.topic, Twist, self.on_command, callback_args=index,
                             queue_size=1)
            rospy.loginfo('twist_mux: input %s (resolved %s), priority %d, timeout %.2f s'
                          % (entry.topic, rospy.resolve_name(entry.topic), entry.priority,
                             entry.timeout_s))
        rospy.on_shutdown(self.on_shutdown)
        self.timer = rospy.Timer(rospy.Duration(1.0 / params.rate), self.on_timer)
        self.diagnostics.start()

    def output_health(self):
        """The input in control, or WARN when none is: cmd_vel is zero."""
        with self.lock:
            active = self.mux.active(rospy.get_time())
        if active is None:
            return Health(WARN, 'no fresh input: zero Twist sent', (('active', 'none'),))
        return Health(OK, 'forwarding %s (priority %d)' % (active.topic, active.priority),
                      (('active', active.topic),))

    def publish_active(self, now_s):
        """Publish the input in control when it changed (call with the lock held)."""
        active = self.mux.active(now_s)
        topic = active.topic if active else ''
        if topic != self.active_topic:
            self.active_topic = topic
            self.active_pub.publish(String(data=topic))

    def on_command(self, message, index):
        now_s = rospy.get_time()
        self.monitors[index].received(now_s)
        with self.lock:
            if not self.shutting_down and self.mux.offer(index, now_s):
                self.cmd_pub.publish(message)
            self.publish_active(now_s)

    def on_timer(self, _event):
        now_s = rospy.get_time()
        with self.lock:
            if not self.shutting_down and self.mux.zero_due(now_s):
                self.cmd_pub.publish(Twist())
                rospy.loginfo('twist_mux: every input is stale: zero Twist')
            self.publish_active(now_s)

    def on_shutdown(self):
        with self.lock:
            self.shutting_down = True
        self.timer.shutdown()
        for _ in range(SHUTDOWN_ZERO_COUNT):
            self.cmd_pub.publish(Twist())
            time.sleep(SHUTDOWN_ZERO_SPACING_S)


def main():
    rospy.init_node('twist_mux')
    TwistMuxNode()
    rospy.spin()
