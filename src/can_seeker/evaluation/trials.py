"""Closed-loop trials judged against ground truth, and their summary.

The truth is the simulator's: base_link pose from ``/sim/base_pose_ground_truth`` (never the
robot's own ``/odom``, which drifts with ``~realism``), the can's centre from
``/sim/can_pose``, contact with anything but the floor from ``/sim/contact`` (which objects from
``/sim/contacts``). A trial succeeds when the controller reached STOPPED within the time limit,
the true gap is within ``gap_tolerance_m`` of the stop distance, the can is within
``bearing_tolerance_deg`` of straight ahead and the robot never touched anything (can, wall or
obstacle). Robot and can sizes come from the world description (``sim/scene.py``).
"""
import collections
import math
import statistics
from dataclasses import asdict, dataclass, fields
from typing import Iterable, List, Optional, Sequence, Tuple

import numpy as np

from can_seeker.control.controller import PARAMS as CONTROL_PARAMS
from can_seeker.params import defaults
from can_seeker.sim.scene import CAN_RADIUS_M, ROBOT_RADIUS_M

CONTROL = defaults(CONTROL_PARAMS)


@dataclass(frozen=True)
class Criteria:
    """What counts as a successful stop."""

    stop_distance_m: float = CONTROL.stop_distance
    gap_tolerance_m: float = 0.02
    bearing_tolerance_deg: float = 3.0
    time_limit_s: float = 90.0
    robot_radius_m: float = ROBOT_RADIUS_M
    can_radius_m: float = CAN_RADIUS_M


def true_gap_and_bearing(base_xy: Sequence[float], base_yaw_rad: float,
                         can_xy: Sequence[float], criteria: Criteria) -> Tuple[float, float]:
    """(gap m, bearing rad): robot front to can surface, and the can centre's direction from the
    robot heading (left positive, wrapped to [-pi, pi])."""
    dx, dy = can_xy[0] - base_xy[0], can_xy[1] - base_xy[1]
    gap_m = math.hypot(dx, dy) - criteria.can_radius_m - criteria.robot_radius_m
    bearing = math.atan2(dy, dx) - base_yaw_rad
    return gap_m, math.atan2(math.sin(bearing), math.cos(bearing))


def path_length(points: Iterable[Sequence[float]]) -> float:
    """Length of the polyline through ``points`` (m)."""
    length = 0.0
    previous = None
    for point in points:
        if previous is not None:
            length += math.hypot(point[0] - previous[0], point[1] - previous[1])
        previous = point
    return length


def until(stamped_poses: Sequence[Sequence[float]], end_s: float
          ) -> Tuple[Optional[Tuple[float, ...]], List[Tuple[float, float]]]:
    """(the last (x, y, yaw) stamped at or before ``end_s``, or None; the (x, y) path up to
    it) of ``stamped_poses`` ((stamp s, x, y, yaw) in stamp order): a trial judged at the sim
    time it ends, whatever came in after that."""
    poses = [pose for pose in stamped_poses if pose[0] <= end_s]
    final = tuple(float(value) for value in poses[-1][1:4]) if poses else None
    return final, [(float(pose[1]), float(pose[2])) for pose in poses]


def pose_at(stamped_poses: Sequence[Sequence[float]], stamp_s: float) -> Optional[Tuple[float, ...]]:
    """The (x, y, yaw) of the last of ``stamped_poses`` ((stamp s, x, y, yaw) in stamp order)
    stamped at or before ``stamp_s`` (the first one when all are later; None when empty)."""
    if not stamped_poses:
        return None
    stamps = np.array([pose[0] for pose in stamped_poses], float)
    index = max(0, int(np.searchsorted(stamps, stamp_s, side='right')) - 1)
    return tuple(float(value) for value in stamped_poses[index][1:4])


@dataclass(frozen=True)
class Contact:
    """The first touch of a trial: when (sim s after the start), where base_link was (odom, m
    and rad) and what it touched."""

    time_s: Optional[float]
    x_m: float
    y_m: float
    yaw_rad: float
    objects: Sequence[str]


@dataclass(frozen=True)
class TrialResult:
    """One trial: where the can was, whether and when the robot stopped, the true final state.

    ``time_to_stop_s`` is sim time from the start to STOPPED (None if it never stopped);
    ``sim_s`` / ``wall_s`` the sim and wall-clock time the trial took; ``final_*`` the true
    base_link pose at the end (odom, m and deg); ``contact_objects`` what the robot touched
    ('can', wall and obstacle names); ``can_visible_from_start`` whether the start camera saw the
    can unoccluded (None: not known); ``first_contact_*`` when the robot first touched something
    (sim s after the start; None: never), the true base_link pose then and what it touched;
    ``lockstep_timeouts`` the frames the simulator stepped on without their answers during the
    trial (None: not in lockstep, or not known).
    """

    index: int
    can_x_m: float
    can_y_m: float
    stopped: bool
    time_to_stop_s: Optional[float]
    gap_m: float
    bearing_deg: float
    contact: bool
    path_length_m: float
    sim_s: float
    wall_s: float
    success: bool
    final_x_m: float = math.nan
    final_y_m: float = math.nan
    final_yaw_deg: float = math.nan
    contact_objects: Sequence[str] = ()
    can_visible_from_start: Optional[bool] = None
    first_contact_s: Optional[float] = None
    first_contact_x_m: float = math.nan
    first_contact_y_m: float = math.nan
    first_contact_yaw_deg: float = math.nan
    first_contact_objects: Sequence[str] = ()
    lockstep_timeouts: Optional[int] = None

    def contact_text(self) -> str:
        """What was touched, and when and where first (for failure lines)."""
        if not self.contact:
            return 'no'
        text = ', '.join(self.contact_objects) or 'yes'
        if self.first_contact_s is not None:
            text += (' (first %s at %.2f s sim, base_link at (%.3f, %.3f) yaw %.1f deg)'
                     % (', '.join(self.first_contact_objects) or 'contact',
                        self.first_contact_s, self.first_contact_x_m, self.first_contact_y_m,
                        self.first_contact_yaw_deg))
        return text

    def as_dict(self):
        """JSON-ready fields: a value that is not known (NaN) is None (JSON null)."""
        return json_ready(asdict(self))

    @classmethod
    def from_dict(cls, fields: dict) -> 'TrialResult':
        """The result :meth:`as_dict` gave (null in a float field is NaN again), from a trial's
        record: what else it tells of the trial's world (its seed, camera mount) is left out."""
        return cls(**{name: math.nan if value is None and name in _FLOAT_FIELDS else value
                      for name, value in fields.items() if name in _FIELDS})


_FIELDS = frozenset(field.name for field in fields(TrialResult))
_FLOAT_FIELDS = frozenset(field.name for field in fields(TrialResult) if field.type is float)


def json_ready(value):
    """``value`` (dicts, lists, tuples, numbers, ...) with every NaN or infinite float replaced
    by None: JSON has no NaN, and ``json.dump`` would write a bare ``NaN`` that strict readers
    (``python3 -m json.tool``, browsers, jq) reject."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {key: json_ready(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(item) for item in value]
    return value


def judge(index: int, can_xy: Sequence[float], time_to_stop_s: Optional[float],
          base_xy: Sequence[float], base_yaw_rad: float, final_can_xy: Sequence[float],
          contact: bool, path_m: float, sim_s: float, wall_s: float,
          criteria: Criteria, contact_objects: Sequence[str] = (),
          can_visible_from_start: Optional[bool] = None,
          first_contact: Optional[Contact] = None,
          lockstep_timeouts: Optional[int] = None) -> TrialResult:
    """The result of a trial from its true final state (``final_can_xy``: the can may have
    been pushed, so it is measured where it is, not where it was placed)."""
    touch = first_contact or Contact(None, math.nan, math.nan, math.nan, ())
    gap_m, bearing_rad = true_gap_and_bearing(base_xy, base_yaw_rad, final_can_xy, criteria)
    stopped = time_to_stop_s is not None and time_to_stop_s <= criteria.time_limit_s
    success = (stopped and not contact
               and abs(gap_m - criteria.stop_distance_m) <= criteria.gap_tolerance_m
               and abs(math.degrees(bearing_rad)) <= criteria.bearing_tolerance_deg)
    return TrialResult(index, float(can_xy[0]), float(can_xy[1]), stopped, time_to_stop_s,
                       gap_m, math.degrees(bearing_rad), contact, path_m, sim_s, wall_s, success,
                       float(base_xy[0]), float(base_xy[1]), math.degrees(base_yaw_rad),
                       sorted(contact_objects), can_visible_from_start, touch.time_s,
                       touch.x_m, touch.y_m, math.degrees(touch.yaw_rad), sorted(touch.objects),
                       lockstep_timeouts)


def _stats(values: List[float], kind: str) -> Optional[float]:
    if not values:
        return None
    if kind == 'mean':
        return statistics.fmean(values)
    if kind == 'median':
        return statistics.median(values)
    return max(values)


def summarise(results: Sequence[TrialResult], criteria: Criteria) -> dict:
    """Success rate and error statistics; gap and bearing errors over the trials that stopped."""
    stopped = [result for result in results if result.stopped]
    gap_errors = [abs(result.gap_m - criteria.stop_distance_m) for result in stopped]
    bearing_errors = [abs(result.bearing_deg) for result in stopped]
    times = [result.time_to_stop_s for result in stopped]
    hidden = [result for result in results if result.can_visible_from_start is False]
    touched = collections.Counter(name for result in results
                                  for name in set(result.contact_objects))
    timeouts = [result.lockstep_timeouts for result in results
                if result.lockstep_timeouts is not None]
    sim_total = sum(result.sim_s for result in results)
    wall_total = sum(result.wall_s for result in results)
    return {
        'trials': len(results),
        'successes': sum(result.success for result in results),
        'success_rate': (sum(result.success for result in results) / len(results)
                         if results else None),
        'stopped': len(stopped),
        'gap_error_mean_m': _stats(gap_errors, 'mean'),
        'gap_error_max_m': _stats(gap_errors, 'max'),
        'bearing_error_mean_deg': _stats(bearing_errors, 'mean'),
        'bearing_error_max_deg': _stats(bearing_errors, 'max'),
        'time_to_stop_median_s': _stats(times, 'median'),
        'time_to_stop_max_s': _stats(times, 'max'),
        'contacts': sum(result.contact for result in results),
        'contact_objects': dict(sorted(touched.items())),
        'path_length_median_m': _stats([result.path_length_m for result in results], 'median'),
        'can_hidden_at_start': len(hidden),
        'successes_can_hidden_at_start': sum(result.success for result in hidden),
        'real_time_factor': sim_total / wall_total if wall_total > 0.0 else None,
        'lockstep_timeouts': sum(timeouts) if timeouts else None,
        'trials_with_lockstep_timeouts': sum(count > 0 for count in timeouts),
        'criteria': asdict(criteria),
    }


def _format(value, scale=1.0, digits=3, unit=''):
    return 'n/a' if value is None else '%.*f%s' % (digits, value * scale, unit)


def _touched(summary: dict) -> str:
    objects = summary.get('contact_objects') or {}
    if not objects:
        return ''
    return ' (%s)' % ', '.join('%s in %d' % item for item in objects.items())


def _timeouts(summary: dict) -> str:
    if summary.get('lockstep_timeouts') is None:
        return 'n/a'
    return '%d (in %d trials)' % (summary['lockstep_timeouts'],
                                  summary['trials_with_lockstep_timeouts'])


def _per_core(summary: dict) -> str:
    if summary.get('real_time_factor_per_core') is None:
        return 'n/a'
    return '%.2fx (%.1f sim s per %.1f CPU s of every process, start-up included)' % (
        summary['real_time_factor_per_core'], summary['batch_sim_s'], summary['batch_cpu_s'])


def summary_table(summary: dict) -> str:
    """The summary as a two-column Markdown table."""
    rows = [
        ('success rate', '%d/%d (%s)' % (summary['successes'], summary['trials'],
                                         _format(summary['success_rate'], 100.0, 1, '%'))),
        ('stopped', '%d/%d' % (summary['stopped'], summary['trials'])),
        ('gap error mean / max', '%s / %s' % (_format(summary['gap_error_mean_m'], 1000.0, 1),
                                              _format(summary['gap_error_max_m'], 1000.0, 1,
                                                      ' mm'))),
        ('bearing error mean / max', '%s / %s' % (_format(summary['bearing_error_mean_deg'],
                                                          digits=2),
                                                  _format(summary['bearing_error_max_deg'],
                                                          digits=2, unit=' deg'))),
        ('time to stop median / max', '%s / %s' % (_format(summary['time_to_stop_median_s'],
                                                           digits=1),
                                                   _format(summary['time_to_stop_max_s'],
                                                           digits=1, unit=' s sim'))),
        ('trials with contact (any object)', '%d%s' % (summary['contacts'], _touched(summary))),
        ('path length median', _format(summary['path_length_median_m'], digits=2, unit=' m')),
        ('can not visible from the start', '%d (%d of them succeeded)'
         % (summary['can_hidden_at_start'], summary['successes_can_hidden_at_start'])),
        ('real-time factor', _format(summary['real_time_factor'], digits=2, unit='x')),
        ('real-time factor per core (whole batch)', _per_core(summary)),
        ('lockstep time-outs during trials', _timeouts(summary)),
    ]
    lines = ['| metric | value |', '|---|---|']
    lines += ['| %s | %s |' % row for row in rows]
    return '\n'.join(lines)
