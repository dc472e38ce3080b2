"""evaluate --compare-with: the earlier record of the same trials is read and checked before any
trial runs; a record of other settings, or no record at all, is refused with the reason."""
import json
import subprocess

import pytest

from can_seeker.evaluation.batch import TrialLedger, compare_runs
from can_seeker.evaluation.trials import Criteria, TrialResult
from can_seeker.tools.evaluate import earlier_ledger, parse_args, settings


def result(index, x=1.0):
    return TrialResult(index, 1.0, 0.0, True, 5.0, 0.25, 0.1, False, 1.0, 6.0, 2.0, True, x,
                       0.5, 10.0)


def record_of(argv, results, path):
    ledger = TrialLedger(settings(parse_args(argv)), Criteria(), results)
    path.write_text(json.dumps(ledger.record()))
    return str(path)


def test_the_record_of_the_same_trials_is_compared_on_the_trials_run(tmp_path):
    path = record_of(['--trials', '4', '--seed', '70'], [result(i) for i in range(4)],
                     tmp_path / 'before.json')
    earlier = earlier_ledger(path, settings(parse_args(['--trials', '3', '--seed', '70'])))
    assert [trial.index for trial in earlier.results()] == [0, 1, 2]
    moved = compare_runs(earlier.results(), [result(0), result(1), result(2, x=1.01)])
    assert not moved['repeatable'] and moved['max_position_diff_trial'] == 2


def test_a_record_of_other_settings_is_refused_naming_them(tmp_path):
    path = record_of(['--trials', '2', '--seed', '70'], [result(0), result(1)],
                     tmp_path / 'before.json')
    for argv, differ in ((['--trials', '2', '--seed', '71'], 'seed'),
                         (['--trials', '2', '--seed', '70', '--realism', 'harsh'], 'realism'),
                         (['--trials', '2', '--seed', '70', '--param',
                           'can_stopper/stop_distance=0.3'], 'params')):
        with pytest.raises(ValueError, match=differ):
            earlier_ledger(path, settings(parse_args(argv)))


def test_what_is_no_record_is_refused(tmp_path):
    (tmp_path / 'broken.json').write_text('{"settings": ')
    (tmp_path / 'other.json').write_text('{"results": []}')
    for name, why in (('missing.json', 'cannot read'), ('broken.json', 'cannot read'),
                      ('other.json', 'not an evaluate --json record')):
        with pytest.raises(ValueError, match=why):
            earlier_ledger(str(tmp_path / name), settings(parse_args([])))


def test_the_earlier_record_is_never_the_one_written(tmp_path):
    with pytest.raises(SystemExit):
        parse_args(['--compare-with', str(tmp_path / 'a.json'), '--json',
                    str(tmp_path / '.' / 'a.json')])


def test_evaluate_refuses_a_record_of_other_trials_before_starting_anything(tmp_path):
    path = record_of(['--trials', '1', '--seed', '70'], [result(0)], tmp_path / 'before.json')
    run = subprocess.run(['rosrun', 'can_seeker', 'evaluate', '--trials', '1', '--seed', '71',
                          '--compare-with', path], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, universal_newlines=True, timeout=60)
    assert run.returncode == 2, run.stdout
    assert 'cannot compare with %s: the record is of another evaluation (seed differ)' % path \
        in run.stdout
    assert 'trials:' not in run.stdout  # no trial was started
