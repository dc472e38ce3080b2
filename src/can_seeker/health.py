"""How a node is doing, for its /diagnostics: each input's rate and the age of its newest
message, and summaries at the levels of diagnostic_msgs/DiagnosticStatus.

Pure: the nodes feed :class:`InputMonitor` from their callbacks and publish every
:class:`Health` with diagnostic_updater (``can_seeker.ros.diagnostics``).
"""
import collections
import math
import threading
from dataclasses import dataclass
from typing import Deque, Optional, Sequence, Tuple

OK, WARN, ERROR = 0, 1, 2
"""diagnostic_msgs/DiagnosticStatus levels."""
RATE_WINDOW_S = 2.0
"""Rates are counted over this much of the node's clock (s)."""


@dataclass(frozen=True)
class Health:
    """A status: ``level`` (OK, WARN, ERROR), a one-line ``message`` and (key, value) pairs."""

    level: int
    message: str
    values: Tuple[Tuple[str, str], ...] = ()


CLOCK_GRACE_S = 10.0
"""Wall-clock seconds a node under use_sim_time waits for a /clock publisher before it warns."""
NO_CLOCK_HINT = ('start the simulator or rosbag play --clock, or, if /use_sim_time was left true '
                 'by an earlier sim or playback launch on this master, rosparam set '
                 '/use_sim_time false and start the nodes again')
"""What to do about a node under use_sim_time without a clock."""


def clock_health(sim_time: bool, clock_s: float, clock_publishers: int,
                 unpublished_s: float) -> Health:
    """The node's clock: the wall clock, or under use_sim_time the time /clock gave; a WARN
    (with :data:`NO_CLOCK_HINT`) once nothing has published /clock for ``unpublished_s`` >=
    :data:`CLOCK_GRACE_S` wall-clock seconds (since the start, or since its publisher left):
    the clock stands still, so no timer fires and every input keeps its age."""
    if not sim_time:
        return Health(OK, 'wall clock')
    values = (('use_sim_time', 'true'), ('time (s)', '%.3f' % clock_s),
              ('/clock publishers', str(clock_publishers)))
    if clock_publishers > 0:
        return Health(OK, 'sim time from /clock', values)
    if unpublished_s < CLOCK_GRACE_S:
        return Health(OK, 'waiting for /clock', values)
    if clock_s > 0.0:
        return Health(WARN, 'nothing has published /clock for %.0f s: the clock stands at %.3f s '
                      '(a bag that ended, a simulator that stopped); %s'
                      % (unpublished_s, clock_s, NO_CLOCK_HINT), values)
    return Health(WARN, 'use_sim_time is true and nothing has published /clock for %.0f s: the '
                  'clock stands at 0; %s' % (unpublished_s, NO_CLOCK_HINT), values)


class ClockWatch:
    """The clock status over time (:func:`clock_health`): remembers when a /clock publisher
    was last seen (wall clock; the start before any) and says when a WARN is due in the log
    (at most every ``log_period_s``: rospy's throttled logging counts on the clock that stands
    still). Used from one thread."""

    def __init__(self, sim_time: bool, start_wall_s: float, log_period_s: float = 30.0):
        self.sim_time = sim_time
        self.log_period_s = log_period_s
        self._published_wall_s = start_wall_s
        self._logged_wall_s = -math.inf

    def health(self, clock_s: float, clock_publishers: int,
               now_wall_s: float) -> Tuple[Health, bool]:
        """(the clock's Health now, whether to log it)."""
        if clock_publishers:
            self._published_wall_s = now_wall_s
        health = clock_health(self.sim_time, clock_s, clock_publishers,
                              now_wall_s - self._published_wall_s)
        log = health.level >= WARN and now_wall_s - self._logged_wall_s >= self.log_period_s
        if log:
            self._logged_wall_s = now_wall_s
        return health, log


def worst(healths: Sequence[Health]) -> int:
    """The highest level among ``healths`` (OK for none)."""
    return max((health.level for health in healths), default=OK)


class InputMonitor:
    """One input topic: how often it arrived over the last ``window_s`` and how old its newest
    message is (by its header stamp when it has one, else by its arrival), on the node's clock.

    Older than ``timeout_s`` (None: no limit), or never received, is ``missing_level``: ERROR
    for an input the node cannot work without, WARN for one it works on without, OK for one
    that may well be silent (a teleop that nobody types into). ``topic``, the resolved name it
    arrives on, is reported with it, so a missing input says where the node listens.
    Thread-safe: callbacks record, the diagnostics thread reads.
    """

    def __init__(self, name: str, timeout_s: Optional[float] = None,
                 missing_level: int = ERROR, window_s: float = RATE_WINDOW_S, topic: str = ''):
        self.name = name
        self.topic = topic
        self.timeout_s = timeout_s
        self.missing_level = missing_level
        self.window_s = window_s
        self.count = 0
        self._arrivals: Deque[float] = collections.deque()
        self._newest_s: Optional[float] = None
        self._last_arrival_s = -math.inf
        self._refused = ''
        self._lock = threading.Lock()

    def received(self, now_s: float, stamp_s: Optional[float] = None,
                 refused: str = '') -> None:
        """A message arrived at ``now_s``, stamped ``stamp_s`` (None or 0: no stamp);
        ``refused`` says why it could not be used (the input is then reported at its missing
        level until one that is used arrives)."""
        with self._lock:
            self.count += 1
            self._arrivals.append(now_s)
            self._last_arrival_s = now_s
            self._refused = refused
            self._newest_s = stamp_s if stamp_s else now_s
            self._forget_before(now_s - self.window_s)

    def _forget_before(self, start_s: float) -> None:
        while self._arrivals and self._arrivals[0] < start_s:
            self._arrivals.popleft()

    def rate_hz(self, now_s: float) -> float:
        """Messages per second over the last ``window_s`` (0 with fewer than two)."""
        with self._lock:
            self._forget_before(now_s - self.window_s)
            if len(self._arrivals) < 2 or self._arrivals[-1] <= self._arrivals[0]:
                return 0.0
            return (len(self._arrivals) - 1) / (self._arrivals[-1] - self._arrivals[0])

    def age_s(self, now_s: float) -> Optional[float]:
        """How old the newest message is (s), None before the first."""
        with self._lock:
            return None if self._newest_s is None else now_s - self._newest_s

    def arrival_age_s(self, now_s: float) -> float:
        """How long ago the newest message arrived, whatever its stamp (inf before the first)."""
        with self._lock:
            return now_s - self._last_arrival_s

    def health(self, now_s: float) -> Health:
        """OK with the rate and age, or ``missing_level`` when never received or too old."""
        age_s, rate_hz = self.age_s(now_s), self.rate_hz(now_s)
        values = (('messages', str(self.count)), ('rate (Hz)', '%.2f' % rate_hz),
                  ('age of the newest (s)', 'none' if age_s is None else '%.3f' % age_s),
                  ('timeout (s)', 'none' if self.timeout_s is None else '%.3f' % self.timeout_s))
        if self.topic:
            values = (('topic', self.topic),) + values
        if age_s is None:
            return Health(self.missing_level, 'no message yet', values)
        with self._lock:
            refused = self._refused
        if refused:
            return Health(self.missing_level, 'arriving, the newest refused: %s' % refused,
                          values)
        if (self.timeout_s is not None and age_s > self.timeout_s
                and self.arrival_age_s(now_s) <= self.timeout_s):
            # Messages keep coming, stamped too long ago: the stamps, not the sender, are late.
            return Health(self.missing_level, 'arriving at %.1f Hz but stamped %.2f s ago '
                          '(timeout %.2f s): a late sender, or its clock behind this one '
                          '(synchronise the clocks, e.g. with chrony)'
                          % (rate_hz, age_s, self.timeout_s), values)
        if self.timeout_s is not None and age_s > self.timeout_s:
            return Health(self.missing_level, 'no message for %.2f s (timeout %.2f s)'
                          % (age_s, self.timeout_s), values)
        return Health(OK, '%.1f Hz, newest %.3f s old' % (rate_hz, age_s), values)


class Outcomes:
    """What a node made of its last ``window`` frames (e.g. 'can found', 'no scan: no
    camera_info yet'), each at a level: the status is the worst of them, with their counts."""

    def __init__(self, window: int = 30):
        self._recent: Deque[Tuple[str, int]] = collections.deque(maxlen=window)
        self.count = 0
        self._lock = threading.Lock()

    def add(self, outcome: str, level: int = OK) -> None:
        """One frame's outcome."""
        with self._lock:
            self.count += 1
            self._recent.append((outcome, level))

    def health(self) -> Health:
        with self._lock:
            recent = list(self._recent)
        if not recent:
            return Health(WARN, 'no frame yet', (('frames', '0'),))
        counts = collections.Counter(outcome for outcome, _ in recent)
        summary = ', '.join('%d %s' % (count, outcome) for outcome, count in counts.most_common())
        return Health(max(level for _, level in recent),
                      'last %d frames: %s' % (len(recent), summary),
                      (('frames', str(self.count)),) + tuple(
                          (outcome, str(count)) for outcome, count in counts.most_common()))
