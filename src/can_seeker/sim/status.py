"""The simulator's own status for /diagnostics: sim time, its pace against the wall clock,
paused or not, and in lockstep the frames that timed out waiting for their answers."""
import math
from typing import Optional, Sequence

from can_seeker.health import OK, WARN, Health


class RunStatus:
    """Reports, one after the other, how the simulation ran since the previous report."""

    def __init__(self):
        self._previous: Optional[tuple] = None

    def report(self, sim_s: float, wall_s: float, paused: bool, frames: int,
               lockstep_timeouts: Optional[int], waiting_for: Sequence[str] = ()) -> Health:
        """The status at sim time ``sim_s`` and wall time ``wall_s`` (s): WARN when frames
        timed out in lockstep since the previous report; ``lockstep_timeouts`` is None without
        lockstep, ``waiting_for`` the answers the held frame still waits for."""
        previous, self._previous = self._previous, (sim_s, wall_s, lockstep_timeouts or 0)
        pace = math.nan
        new_timeouts = 0
        if previous is not None:
            if wall_s > previous[1]:
                pace = (sim_s - previous[0]) / (wall_s - previous[1])
            new_timeouts = (lockstep_timeouts or 0) - previous[2]
        values = [('sim time (s)', '%.3f' % sim_s), ('real-time factor', '%.2f' % pace),
                  ('paused', str(paused).lower()), ('frames', str(frames))]
        if lockstep_timeouts is not None:
            values += [('lockstep time-outs', str(lockstep_timeouts)),
                       ('waiting for', ' '.join(waiting_for) or 'nothing')]
        if new_timeouts > 0:
            return Health(WARN, 'lockstep: %d frames timed out waiting for their answers since '
                          'the last report (%d in all)' % (new_timeouts, lockstep_timeouts),
                          tuple(values))
        if paused:
            return Health(OK, 'paused at t=%.3f s' % sim_s, tuple(values))
        return Health(OK, 't=%.3f s, %.2fx real time' % (sim_s, pace), tuple(values))
