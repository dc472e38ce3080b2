"""Splitting an evaluation into shards, merging their results, and comparing two runs.

Trial i always uses seed + i, so any subset of the trials can run anywhere (another process, its
own master, another machine) and the merged result equals one run of them all.
"""
import math
from typing import Dict, List, Sequence, Tuple

from can_seeker.evaluation.trials import TrialResult

SHARD_INDEPENDENT = ('shard', 'jobs', 'repeat_check')
"""Settings that may differ between the records of one evaluation."""
REPEAT_POSITION_TOLERANCE_M = 0.001
"""A repeated trial must end within this of the first run's position (m)..."""
REPEAT_YAW_TOLERANCE_DEG = 0.1
"""...and heading (deg), with the same outcome."""


def parse_shard(text: str) -> Tuple[int, int]:
    """``'i/N'`` (1 <= i <= N) as (i, N); ValueError otherwise."""
    try:
        index_text, count_text = text.split('/')
        index, count = int(index_text), int(count_text)
    except ValueError:
        raise ValueError('a shard is i/N, e.g. 2/4, got %r' % (text,))
    if not 1 <= index <= count:
        raise ValueError('shard %r: i must be in 1..N' % (text,))
    return index, count


def shard_indices(trials: int, shard: Tuple[int, int]) -> List[int]:
    """The trial indices of shard (i, N): every N-th trial from trial i - 1."""
    index, count = shard
    return list(range(index - 1, trials, count))


def merge_records(records: Sequence[dict]) -> Tuple[dict, List[TrialResult]]:
    """(settings, trials sorted by index) of evaluate JSON records of one evaluation.

    ValueError when their settings differ (other than the shard) or a trial appears twice.
    """
    if not records:
        raise ValueError('nothing to merge')
    settings = {key: value for key, value in records[0]['settings'].items()
                if key not in SHARD_INDEPENDENT}
    trials: Dict[int, TrialResult] = {}
    for record in records:
        other = {key: value for key, value in record['settings'].items()
                 if key not in SHARD_INDEPENDENT}
        if other != settings:
            changed = sorted(key for key in set(other) | set(settings)
                             if other.get(key) != settings.get(key))
            raise ValueError('the records come from different evaluations (%s differ)'
                             % ', '.join(changed))
        for fields in record['trials']:
            result = TrialResult(**fields)
            if result.index in trials:
                raise ValueError('trial %d appears in more than one record' % result.index)
            trials[result.index] = result
    return settings, [trials[index] for index in sorted(trials)]


def outcome(result: TrialResult) -> Tuple[bool, bool, bool]:
    """What a trial's verdict rests on: (success, stopped, contact)."""
    return result.success, result.stopped, result.contact


def compare_runs(first: Sequence[TrialResult], second: Sequence[TrialResult]) -> dict:
    """The largest per-trial differences between two runs of the same trials.

    Position in mm and heading in deg of the final pose; the indices whose outcome differs or
    that only one run has; ``repeatable`` when there are none and the pose differences are
    within :data:`REPEAT_POSITION_TOLERANCE_M` and :data:`REPEAT_YAW_TOLERANCE_DEG`.
    """
    by_index = {result.index: result for result in second}
    position_mm, yaw_deg = [], []
    worst_position_index = worst_yaw_index = None
    differing, unmatched = [], sorted(set(by_index) ^ {result.index for result in first})
    for result in first:
        other = by_index.get(result.index)
        if other is None:
            continue
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
            'unmatched': unmatched, 'repeatable': repeatable}
