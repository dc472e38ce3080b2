"""The trials of one evaluation as they finish, in any order and on any machine: which are
still missing (to resume), their record in trial order, written after every finished trial; and
how two runs of the same trials compare.

Trial i always uses seed + i, so any subset of the trials can run anywhere (another process, its
own master, another machine) and the collected result equals one run of them all.
"""
import json
import math
import os
import tempfile
from typing import Dict, List, Optional, Sequence, Tuple

from can_seeker.camera_mount import random_mount
from can_seeker.evaluation.trials import Criteria, TrialResult, json_ready, summarise

REPEAT_POSITION_TOLERANCE_M = 0.001
"""A repeated trial must end within this of the first run's position (m)..."""
REPEAT_YAW_TOLERANCE_DEG = 0.1
"""...and heading (deg), with the same outcome."""
RESUMABLE_CHANGES = ('trials',)
"""Settings a resumed evaluation may change: more (or fewer) trials of the same seeds."""


class TrialLedger:
    """The finished trials of one evaluation by index, the criteria they were judged by, and
    their JSON record (``settings``, ``summary``, ``trials`` in index order)."""

    def __init__(self, settings: dict, criteria: Optional[Criteria] = None,
                 results: Sequence[TrialResult] = ()):
        self.settings = dict(settings)
        self.criteria = criteria
        self.by_index: Dict[int, TrialResult] = {}
        for result in results:
            self.add(result)

    def add(self, result: TrialResult, criteria: Optional[Criteria] = None):
        """Record a finished trial; ValueError if that trial is already recorded or was judged
        by other criteria than the trials before it."""
        if result.index in self.by_index:
            raise ValueError('trial %d is already recorded' % result.index)
        if criteria is not None:
            if self.criteria is not None and criteria != self.criteria:
                raise ValueError('trial %d was judged by other criteria (%s, not %s)'
                                 % (result.index, criteria, self.criteria))
            self.criteria = criteria
        self.by_index[result.index] = result

    def results(self) -> List[TrialResult]:
        """The finished trials of this evaluation (index below ``settings['trials']``) in
        index order."""
        return [self.by_index[index] for index in sorted(self.by_index)
                if index < self.settings['trials']]

    def missing(self) -> List[int]:
        """The indices of the trials still to run, ascending."""
        return [index for index in range(self.settings['trials'])
                if index not in self.by_index]

    def summary(self) -> dict:
        return summarise(self.results(), self.criteria or Criteria())

    def record(self) -> dict:
        """The JSON record: settings, summary and every finished trial in index order (see
        :meth:`trial_record`)."""
        return json_ready({'settings': self.settings, 'summary': self.summary(),
                           'trials': [self.trial_record(result) for result in self.results()]})

    def trial_record(self, result: TrialResult) -> dict:
        """A trial's fields with the seed of its world and, where the camera mount is drawn
        per trial (``randomize_mount``), the mount drawn from it: ``camera_height_m``,
        ``camera_pitch_deg`` (deg below the horizon)."""
        record = result.as_dict()
        seed = self.settings['seed'] + result.index
        record['seed'] = seed
        if self.settings.get('randomize_mount'):
            mount = random_mount(seed)
            record['camera_height_m'], record['camera_pitch_deg'] = (mount.height_m,
                                                                     mount.pitch_deg)
        return record

    @classmethod
    def from_record(cls, record: dict, settings: dict) -> 'TrialLedger':
        """The finished trials of a JSON record, to resume the evaluation ``settings``
        describes; ValueError when the record is of another evaluation (settings other than
        :data:`RESUMABLE_CHANGES` differ)."""
        changed = sorted(key for key in set(record['settings']) | set(settings)
                         if key not in RESUMABLE_CHANGES
                         and record['settings'].get(key) != settings.get(key))
        if changed:
            raise ValueError('the record is of another evaluation (%s differ)'
                             % ', '.join(changed))
        return cls(settings, Criteria(**record['summary']['criteria']),
                   [TrialResult.from_dict(fields) for fields in record['trials']])


def write_json_atomically(path: str, record: dict):
    """Write ``record`` as JSON to ``path`` through a temporary file in the same folder, renamed
    over it: a reader (or a crash) sees the old or the new file whole, never a part."""
    folder = os.path.dirname(os.path.abspath(path))
    handle, temporary_path = tempfile.mkstemp(prefix='.%s.' % os.path.basename(path),
                                              suffix='.tmp', dir=folder)
    umask = os.umask(0)
    os.umask(umask)
    try:
        os.chmod(temporary_path, 0o666 & ~umask)  # as open() would create it, not 0600
        with os.fdopen(handle, 'w') as output:
            json.dump(json_ready(record), output, indent=2, allow_nan=False)
            output.flush()
            os.fsync(output.fileno())
        os.replace(temporary_path, path)
    except BaseException:
        os.unlink(temporary_path)
        raise


def outcome(result: TrialResult) -> Tuple[bool, bool, bool]:
    """What a trial's verdict rests on: (success, stopped, contact)."""
    return result.success, result.stopped, result.contact


def compare_runs(first: Sequence[TrialResult], second: Sequence[TrialResult]) -> dict:
    """The largest per-trial differences between two runs of the same trials.

    Position in mm and heading in deg of the final pose; the indices whose outcome differs or
    that only one run has; ``repeatable`` when there are none and the pose differences are
    within :data:`REPEAT_POSITION_TOLERANCE_M` and :data:`REPEAT_YAW_TOLERANCE_DEG`.
    ``timed_out`` names the trials in which either run had lockstep time-outs: there the
    simulator stepped on without an answer, so a difference says nothing of the code.
    """
    by_index = {result.index: result for result in second}
    position_mm, yaw_deg = [], []
    worst_position_index = worst_yaw_index = None
    differing, unmatched = [], sorted(set(by_index) ^ {result.index for result in first})
    timed_out = []
    for result in first:
        other = by_index.get(result.index)
        if other is None:
            continue
        if (result.lockstep_timeouts or 0) > 0 or (other.lockstep_timeouts or 0) > 0:
            timed_out.append(result.index)
        if outcome(result) != outcome(other):
            differing.append(result.index)
        position = 1000.0 * math.hypot(result.final_x_m - other.final_x_m,
                                       result.final_y_m - other.final_y_m)
        yaw = abs(math.remainder(result.final_yaw_deg - other.final_yaw_deg, 360.0))
        if not position_mm or position > max(position_mm):
            worst_position_index = result.index
        if not yaw_deg or yaw > max(yaw_deg):
            worst_yaw_index = result.index
        position_mm.append(position)
        yaw_deg.append(yaw)
    max_position = max(position_mm) if position_mm else None
    max_yaw = max(yaw_deg) if yaw_deg else None
    repeatable = (bool(position_mm) and not differing and not unmatched
                  and max_position <= 1000.0 * REPEAT_POSITION_TOLERANCE_M
                  and max_yaw <= REPEAT_YAW_TOLERANCE_DEG)
    return {'compared': len(position_mm), 'max_position_diff_mm': max_position,
            'max_position_diff_trial': worst_position_index, 'max_yaw_diff_deg': max_yaw,
            'max_yaw_diff_trial': worst_yaw_index, 'outcome_differs': differing,
            'unmatched': unmatched, 'timed_out': timed_out, 'repeatable': repeatable}
