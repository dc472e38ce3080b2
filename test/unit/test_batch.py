"""Shards cover the trials once, shard records merge back into one evaluation, and two runs of
the same trials are compared trial by trial."""
import pytest

from can_seeker.evaluation.batch import compare_runs, merge_records, parse_shard, shard_indices
from can_seeker.evaluation.trials import TrialResult


def result(index, x=1.0, y=0.5, yaw=10.0, success=True):
    return TrialResult(index, 1.0, 0.0, success, 5.0 if success else None, 0.25, 0.1, False,
                       1.0, 6.0, 2.0, success, x, y, yaw)


def record(trials, **settings):
    base = {'trials': 5, 'seed': 3, 'shard': [1, 1]}
    base.update(settings)
    return {'settings': base, 'trials': [trial.as_dict() for trial in trials]}


def test_parse_shard():
    assert parse_shard('2/4') == (2, 4)
    for bad in ('0/2', '3/2', '2', 'a/b', '1/2/3'):
        with pytest.raises(ValueError):
            parse_shard(bad)


def test_shards_cover_every_trial_exactly_once():
    covered = sorted(index for shard in range(1, 4) for index in shard_indices(10, (shard, 3)))
    assert covered == list(range(10))
    assert shard_indices(10, (1, 1)) == list(range(10))
    assert shard_indices(2, (3, 3)) == []


def test_merge_orders_trials_and_ignores_the_shard_setting():
    settings, trials = merge_records([record([result(1), result(3)], shard=[2, 2]),
                                      record([result(0), result(2), result(4)], shard=[1, 2])])
    assert [trial.index for trial in trials] == [0, 1, 2, 3, 4]
    assert settings == {'trials': 5, 'seed': 3}


def test_merge_refuses_other_evaluations_and_repeated_trials():
    with pytest.raises(ValueError, match='seed'):
        merge_records([record([result(0)]), record([result(1)], seed=4)])
    with pytest.raises(ValueError, match='trial 0'):
        merge_records([record([result(0)]), record([result(0)], shard=[2, 2])])
    with pytest.raises(ValueError):
        merge_records([])


def test_identical_runs_are_repeatable():
    runs = [result(0), result(1, x=-1.0)]
    comparison = compare_runs(runs, list(runs))
    assert comparison['repeatable']
    assert comparison['max_position_diff_mm'] == 0.0
    assert comparison['compared'] == 2


def test_compare_reports_the_largest_pose_difference_and_its_trial():
    first = [result(0), result(1), result(2, yaw=179.99)]
    second = [result(0, x=1.0003), result(1, y=0.5012), result(2, yaw=-179.98)]
    comparison = compare_runs(first, second)
    assert comparison['max_position_diff_mm'] == pytest.approx(1.2)
    assert comparison['max_position_diff_trial'] == 1
    assert comparison['max_yaw_diff_deg'] == pytest.approx(0.03)
    assert comparison['max_yaw_diff_trial'] == 2
    assert not comparison['repeatable']


def test_compare_reports_differing_outcomes_and_missing_trials():
    comparison = compare_runs([result(0), result(1)], [result(0, success=False), result(2)])
    assert comparison['outcome_differs'] == [0]
    assert comparison['unmatched'] == [1, 2]
    assert not comparison['repeatable']
