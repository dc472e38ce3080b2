"""Lockstep: hold the simulation at a camera frame until the nodes that consume it answered.

Like Gazebo's lockstep or CARLA's synchronous mode: after publishing a frame stamped ``t`` the
simulator steps no further until every awaited input (topics whose messages carry a std_msgs
Header, e.g. the detection, a scan, the stamped command) has a message stamped at or after ``t``,
or until a wall-clock timeout. Running as fast as possible, a trial then sees exactly the same
frames, detections and commands at the same sim times whatever the machine's load.

Answers arrive on other threads (subscriber callbacks); the simulation thread waits.
"""
import math
import struct
import threading
import time
from typing import Dict, Iterable, Optional, Sequence

HEADER_STAMP = struct.Struct('<III')
"""A serialized std_msgs/Header starts with seq, stamp.secs, stamp.nsecs (little-endian)."""


def header_stamp_s(serialized: bytes) -> float:
    """The header stamp (s) of a serialized message whose first field is a std_msgs/Header.

    ValueError when the buffer is too short to hold a header.
    """
    if len(serialized) < HEADER_STAMP.size:
        raise ValueError('a message of %d bytes cannot start with a Header' % len(serialized))
    _, secs, nsecs = HEADER_STAMP.unpack_from(serialized)
    return secs + nsecs * 1e-9


class LockstepGate:
    """The newest answer stamp per input, and the frame the simulation is held at.

    Stamps are compared with a tolerance of a microsecond: ROS times have nanosecond resolution
    and a frame's stamp comes back exactly, but floats of the same time may differ in the last
    bit.
    """

    TOLERANCE_S = 1e-6

    def __init__(self, timeout_s: float):
        self.timeout_s = timeout_s
        self.timeouts = 0
        self._condition = threading.Condition()
        self._newest_s: Dict[str, float] = {}
        self._frame_s: Optional[float] = None
        self._awaited: Sequence[str] = ()
        self._deadline_s = math.inf

    @property
    def holding(self) -> bool:
        """True while a frame waits for its answers."""
        with self._condition:
            return self._frame_s is not None

    def answered(self, name: str, stamp_s: float) -> None:
        """Input ``name`` produced a message stamped ``stamp_s`` (any thread)."""
        with self._condition:
            self._newest_s[name] = max(stamp_s, self._newest_s.get(name, -math.inf))
            self._condition.notify_all()

    def hold(self, frame_s: float, awaited: Iterable[str]) -> None:
        """The frame stamped ``frame_s`` went out: wait for ``awaited`` to answer it."""
        with self._condition:
            self._awaited = tuple(awaited)
            self._frame_s = frame_s if self._awaited else None
            self._deadline_s = time.monotonic() + self.timeout_s

    def missing(self) -> Sequence[str]:
        """The awaited inputs that have not answered the held frame yet."""
        with self._condition:
            return self._missing()

    def _missing(self) -> Sequence[str]:
        if self._frame_s is None:
            return ()
        return tuple(name for name in self._awaited
                     if self._newest_s.get(name, -math.inf) < self._frame_s - self.TOLERANCE_S)

    def wait(self, block_s: float) -> Optional[Sequence[str]]:
        """Wait up to ``block_s`` (wall clock) for the held frame's answers.

        Returns an empty tuple when the simulation may step (answered, or nothing held), None
        while it must still wait, and the inputs that never answered when the timeout expired
        (the frame is then released and counted in :attr:`timeouts`).
        """
        with self._condition:
            end_s = min(time.monotonic() + block_s, self._deadline_s)
            while self._missing():
                remaining_s = end_s - time.monotonic()
                if remaining_s <= 0.0:
                    break
                self._condition.wait(remaining_s)
            missing = self._missing()
            if not missing:
                self._frame_s = None
                return ()
            if time.monotonic() < self._deadline_s:
                return None
            self._frame_s = None
            self.timeouts += 1
            return missing
