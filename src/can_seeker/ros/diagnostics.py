"""A node's /diagnostics (diagnostic_updater): one status per input and per concern, each
built by a pure function returning a :class:`can_seeker.health.Health`.

Published once a second of wall-clock time from a thread of its own, so a node still reports
while the simulator's clock stands still (paused, or stalled in lockstep); ages and rates are
on the node's clock (sim time under ``use_sim_time``).
"""
import threading
import time

import diagnostic_updater
import rospy
from rosgraph_msgs.msg import Clock

from can_seeker.health import WARN, ClockWatch, InputMonitor

PERIOD_S = 1.0
ERROR_PERIOD_S = 60.0
CLOCK_WARN_PERIOD_S = 30.0
"""A clock that does not start is logged at most this often (wall-clock s: rospy's throttled
logging counts on the clock that stands still)."""
IMAGE_TIMEOUT_S = 1.0
"""An image node reports the camera as missing once its newest image is this old (s)."""


class NodeDiagnostics:
    """diagnostic_updater tasks of one node; :meth:`start` begins publishing. With ``clock``
    (every node but the one that publishes /clock) a status 'clock' says whether, under
    use_sim_time, anything publishes /clock (:func:`can_seeker.health.clock_health`), and its
    WARN is logged too."""

    def __init__(self, clock: bool = True):
        self.updater = diagnostic_updater.Updater()
        self.updater.setHardwareID('none')
        self._thread = threading.Thread(target=self._publish, name='diagnostics', daemon=True)
        self._clock_sub = None
        if clock:
            sim_time = not rospy.rostime.is_wallclock()
            if sim_time:
                # rospy's own /clock connection, shared: it only counts the publishers
                self._clock_sub = rospy.Subscriber('/clock', Clock, queue_size=1)
            self._clock = ClockWatch(sim_time, time.monotonic(), CLOCK_WARN_PERIOD_S)
            self.add('clock', self._clock_health)

    def _clock_health(self):
        publishers = 0 if self._clock_sub is None else self._clock_sub.get_num_connections()
        health, log = self._clock.health(rospy.get_time(), publishers, time.monotonic())
        if log:
            rospy.logwarn('%s: %s' % (rospy.get_name().lstrip('/'), health.message))
        return health

    def add(self, name, health):
        """A status ``name`` from ``health()`` (a Health)."""
        def run(status):
            report = health()
            status.summary(report.level, report.message)
            for key, value in report.values:
                status.add(key, value)
            return status
        self.updater.add(name, run)

    def add_input(self, monitor: InputMonitor):
        """The status of an input: its rate and the age of its newest message."""
        self.add(monitor.name, lambda: monitor.health(rospy.get_time()))

    def start(self):
        self._thread.start()

    def _publish(self):
        while not rospy.is_shutdown():
            time.sleep(PERIOD_S)
            try:
                self.updater.force_update()
            except rospy.ROSException:  # shutting down: the publisher is gone
                return
            except Exception as error:  # a failing status must not end the others
                rospy.logerr_throttle(ERROR_PERIOD_S, 'diagnostics failed: %s: %s'
                                      % (type(error).__name__, error))


def image_diagnostics(node_outcomes, image_topic='', camera_info_topic=''):
    """A NodeDiagnostics with the image and camera_info inputs of an image node (on the
    resolved topics given) and its ``node_outcomes`` (an Outcomes, as status 'frames'); the
    two InputMonitors."""
    image = InputMonitor('image', IMAGE_TIMEOUT_S, topic=image_topic)
    camera_info = InputMonitor('camera_info', missing_level=WARN, topic=camera_info_topic)
    diagnostics = NodeDiagnostics()
    diagnostics.add('frames', node_outcomes.health)
    diagnostics.add_input(image)
    diagnostics.add_input(camera_info)
    return diagnostics, image, camera_info
