"""The trials of an evaluation collected as they finish, in any order: what is left to run (and
to resume), the record in trial order written whole after every trial; and two runs of the same
trials compared trial by trial."""
import dataclasses
import json
import math
import os

import pytest

from can_seeker.camera_mount import random_mount
from can_seeker.evaluation.batch import TrialLedger, compare_runs, write_json_atomically
from can_seeker.evaluation.trials import Criteria, TrialResult

SETTINGS = {'trials': 5, 'seed': 3, 'world': 'empty', 'params': {}}


def result(index, x=1.0, y=0.5, yaw=10.0, success=True):
    return TrialResult(index, 1.0, 0.0, success, 5.0 if success else None, 0.25, 0.1, False,
                       1.0, 6.0, 2.0, success, x, y, yaw)


def test_trials_finishing_in_any_order_are_recorded_in_trial_order():
    ledger = TrialLedger(SETTINGS)
    for index in (3, 0, 4):
        ledger.add(result(index), Criteria())
    assert [trial.index for trial in ledger.results()] == [0, 3, 4]
    assert [trial['index'] for trial in ledger.record()['trials']] == [0, 3, 4]
    assert ledger.missing() == [1, 2]
    assert ledger.record()['summary']['trials'] == 3


def test_a_trial_is_recorded_once_and_by_one_set_of_criteria():
    ledger = TrialLedger(SETTINGS, Criteria(), [result(0)])
    with pytest.raises(ValueError, match='trial 0'):
        ledger.add(result(0))
    with pytest.raises(ValueError, match='other criteria'):
        ledger.add(result(1), Criteria(stop_distance_m=0.5))


def test_a_record_resumes_with_only_its_missing_trials(tmp_path):
    first = TrialLedger(SETTINGS)
    for index in (1, 4):
        first.add(result(index), Criteria(stop_distance_m=0.3))
    path = str(tmp_path / 'evaluate.json')
    write_json_atomically(path, first.record())
    with open(path) as stored:
        resumed = TrialLedger.from_record(json.load(stored), SETTINGS)
    assert resumed.missing() == [0, 2, 3]
    assert resumed.criteria == Criteria(stop_distance_m=0.3)
    assert json.dumps(resumed.record()) == json.dumps(first.record())


def test_each_trial_records_its_seed_and_the_camera_mount_drawn_from_it(tmp_path):
    """With the mount drawn per trial, a failing trial's mount is in its record (the
    simulator draws it from the trial's seed); a record with them resumes."""
    settings = dict(SETTINGS, randomize_mount=True)
    ledger = TrialLedger(settings, Criteria(), [result(0), result(2)])
    trials = ledger.record()['trials']
    assert [trial['seed'] for trial in trials] == [3, 5]
    assert (trials[1]['camera_height_m'], trials[1]['camera_pitch_deg']) == (
        random_mount(5).height_m, random_mount(5).pitch_deg)
    assert trials[0]['camera_height_m'] != trials[1]['camera_height_m']
    assert 'camera_height_m' not in TrialLedger(SETTINGS, Criteria(),
                                                [result(0)]).record()['trials'][0]
    resumed = TrialLedger.from_record(json.loads(json.dumps(ledger.record())), settings)
    assert resumed.missing() == [1, 3, 4]
    assert json.dumps(resumed.record()) == json.dumps(ledger.record())


def test_a_resume_may_change_the_number_of_trials_only():
    record = TrialLedger(SETTINGS, Criteria(), [result(0), result(3)]).record()
    more = TrialLedger.from_record(record, dict(SETTINGS, trials=7))
    assert more.missing() == [1, 2, 4, 5, 6]
    fewer = TrialLedger.from_record(record, dict(SETTINGS, trials=2))
    assert [trial.index for trial in fewer.results()] == [0] and fewer.missing() == [1]
    with pytest.raises(ValueError, match='seed, world'):
        TrialLedger.from_record(record, dict(SETTINGS, seed=4, world='room'))


def test_the_record_is_replaced_whole_and_leaves_no_temporary_file(tmp_path):
    path = tmp_path / 'evaluate.json'
    write_json_atomically(str(path), {'trials': [1]})
    write_json_atomically(str(path), {'trials': [1, 2]})
    assert json.loads(path.read_text()) == {'trials': [1, 2]}
    assert os.listdir(str(tmp_path)) == ['evaluate.json']
    umask = os.umask(0o022)
    try:
        write_json_atomically(str(path), {'trials': []})
    finally:
        os.umask(umask)
    assert path.stat().st_mode & 0o777 == 0o644


def test_a_failed_write_keeps_the_previous_record(tmp_path):
    path = tmp_path / 'evaluate.json'
    write_json_atomically(str(path), {'trials': [1]})
    with pytest.raises(TypeError):
        write_json_atomically(str(path), {'trials': [object()]})
    assert json.loads(path.read_text()) == {'trials': [1]}
    assert os.listdir(str(tmp_path)) == ['evaluate.json']


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


def test_compare_names_the_trials_with_lockstep_time_outs():
    first = [result(0), result(1)]
    second = [result(0), dataclasses.replace(result(1), lockstep_timeouts=2)]
    comparison = compare_runs(first, second)
    assert comparison['timed_out'] == [1]
    assert comparison['repeatable']


def strict_json(path):
    """The file parsed as strict JSON: a bare NaN or Infinity is an error (as for jq, browsers
    and other strict readers)."""
    def refuse(constant):
        raise ValueError('not JSON: %s' % constant)
    with open(path) as stored:
        return json.load(stored, parse_constant=refuse)


def test_unknown_values_are_null_in_the_record_and_nan_again_on_resume(tmp_path):
    ledger = TrialLedger(SETTINGS)
    ledger.add(result(0, success=False), Criteria())  # never touched: first_contact_* NaN
    ledger.add(result(1, x=float('nan')), Criteria())
    path = str(tmp_path / 'evaluate.json')
    write_json_atomically(path, ledger.record())
    record = strict_json(path)
    assert record['trials'][0]['first_contact_x_m'] is None
    assert record['trials'][1]['final_x_m'] is None
    resumed = TrialLedger.from_record(record, SETTINGS)
    assert math.isnan(resumed.results()[0].first_contact_yaw_deg)
    assert math.isnan(resumed.results()[1].final_x_m)
    assert resumed.results()[0].time_to_stop_s is None



def test_the_writer_turns_nan_into_null(tmp_path):
    path = str(tmp_path / 'x.json')
    write_json_atomically(path, {'pose': [1.0, float('nan'), float('inf')], 'gap_m': 0.25})
    assert strict_json(path) == {'pose': [1.0, None, None], 'gap_m': 0.25}
