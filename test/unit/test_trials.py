"""Judging closed-loop trials against ground truth and summarising them."""
import math

import pytest

from can_seeker.camera_geometry import yaw_from_quaternion
from can_seeker.evaluation.trials import Contact, Criteria, TrialResult, judge, path_length, \
    pose_at, summarise, summary_table, true_gap_and_bearing, until

CRITERIA = Criteria()
TARGET_CENTRE_M = 0.25 + 0.165 + 0.033


def test_true_gap_and_bearing_straight_ahead():
    gap, bearing = true_gap_and_bearing((1.0, 2.0), 0.0, (1.0 + TARGET_CENTRE_M, 2.0), CRITERIA)
    assert gap == pytest.approx(0.25)
    assert bearing == pytest.approx(0.0)


def test_true_bearing_is_relative_to_heading_and_wrapped():
    _, bearing = true_gap_and_bearing((0.0, 0.0), math.radians(170.0), (-1.0, -0.1), CRITERIA)
    assert bearing == pytest.approx(math.atan2(-0.1, -1.0) - math.radians(170.0) + 2 * math.pi)
    assert -math.pi <= bearing <= math.pi
    _, left = true_gap_and_bearing((0.0, 0.0), 0.0, (1.0, 0.2), CRITERIA)
    assert left > 0.0


@pytest.mark.parametrize('yaw_deg', [0.0, 45.0, 179.0, -120.0])
def test_yaw_from_quaternion_about_z(yaw_deg):
    half = math.radians(yaw_deg) / 2.0
    assert yaw_from_quaternion(0.0, 0.0, math.sin(half), math.cos(half)) == \
        pytest.approx(math.radians(yaw_deg))


def test_path_length():
    assert path_length([]) == 0.0
    assert path_length([(0, 0), (3, 4), (3, 5)]) == pytest.approx(6.0)


def trial(gap_error=0.0, bearing_deg=0.0, time_to_stop=10.0, contact=False, index=0):
    yaw = math.radians(30.0)
    bearing = yaw + math.radians(bearing_deg)
    distance = TARGET_CENTRE_M + gap_error
    can = (distance * math.cos(bearing), distance * math.sin(bearing))
    return judge(index, can, time_to_stop, (0.0, 0.0), yaw, can, contact, 1.0, 12.0, 6.0,
                 CRITERIA)


def test_success_needs_stop_gap_bearing_and_no_contact():
    assert trial().success
    assert trial(gap_error=0.019, bearing_deg=-2.9).success
    assert not trial(gap_error=0.021).success
    assert not trial(gap_error=-0.021).success
    assert not trial(bearing_deg=3.1).success
    assert not trial(contact=True).success
    assert not trial(time_to_stop=None).success
    assert not trial(time_to_stop=90.5).success


def test_judge_reports_true_values():
    result = trial(gap_error=0.012, bearing_deg=-1.5)
    assert result.gap_m == pytest.approx(0.262)
    assert result.bearing_deg == pytest.approx(-1.5)
    assert result.as_dict()['gap_m'] == result.gap_m


def test_summary_statistics():
    results = [trial(0.004, 1.0, 8.0, index=0), trial(-0.010, -2.0, 12.0, index=1),
               trial(0.030, 0.0, 20.0, index=2), trial(0.0, 0.0, None, index=3)]
    summary = summarise(results, CRITERIA)
    assert summary['trials'] == 4
    assert summary['successes'] == 2
    assert summary['success_rate'] == 0.5
    assert summary['stopped'] == 3
    assert summary['gap_error_mean_m'] == pytest.approx((0.004 + 0.010 + 0.030) / 3)
    assert summary['gap_error_max_m'] == pytest.approx(0.030)
    assert summary['bearing_error_max_deg'] == pytest.approx(2.0)
    assert summary['time_to_stop_median_s'] == 12.0
    assert summary['time_to_stop_max_s'] == 20.0
    assert summary['real_time_factor'] == pytest.approx(2.0)
    table = summary_table(summary)
    assert '| success rate | 2/4 (50.0%) |' in table
    assert '14.7 / 30.0 mm' in table


def test_summary_of_nothing():
    summary = summarise([], CRITERIA)
    assert summary['success_rate'] is None
    assert 'n/a' in summary_table(summary)


def test_contacts_by_object_and_hidden_cans_are_summarised():
    touching = judge(0, (1.0, 0.0), 10.0, (0.0, 0.0), 0.0, (1.0, 0.0), True, 1.0, 12.0, 6.0,
                     CRITERIA, ('wall_front', 'obstacle_2'), False)
    assert not touching.success and touching.contact_objects == ['obstacle_2', 'wall_front']
    hidden_ok = judge(1, (TARGET_CENTRE_M, 0.0), 10.0, (0.0, 0.0), 0.0, (TARGET_CENTRE_M, 0.0),
                      False, 2.0, 12.0, 6.0, CRITERIA, (), False)
    seen = judge(2, (TARGET_CENTRE_M, 0.0), 10.0, (0.0, 0.0), 0.0, (TARGET_CENTRE_M, 0.0),
                 False, 3.0, 12.0, 6.0, CRITERIA, (), True)
    summary = summarise([touching, hidden_ok, seen], CRITERIA)
    assert summary['contact_objects'] == {'obstacle_2': 1, 'wall_front': 1}
    assert (summary['can_hidden_at_start'], summary['successes_can_hidden_at_start']) == (2, 1)
    assert summary['path_length_median_m'] == 2.0
    table = summary_table(summary)
    assert '| trials with contact (any object) | 1 (obstacle_2 in 1, wall_front in 1) |' in table
    assert '| can not visible from the start | 2 (1 of them succeeded) |' in table


def test_a_trial_is_judged_on_the_poses_up_to_its_end():
    poses = [(10.0 + 0.1 * i, 0.01 * i, 0.0, 0.1) for i in range(10)]
    final, path = until(poses, 10.55)
    assert final == (0.05, 0.0, 0.1)
    assert path == [(0.01 * i, 0.0) for i in range(6)]
    assert until(poses, 9.0) == (None, [])


def test_pose_at_takes_the_last_pose_at_or_before_the_stamp():
    poses = [(10.0, 0.0, 0.0, 0.0), (10.02, 0.01, 0.0, 0.1), (10.04, 0.02, 0.0, 0.2)]
    assert pose_at(poses, 10.03) == (0.01, 0.0, 0.1)
    assert pose_at(poses, 10.04) == (0.02, 0.0, 0.2)
    assert pose_at(poses, 9.0) == (0.0, 0.0, 0.0)
    assert pose_at([], 10.0) is None


def test_the_first_contact_is_reported_with_time_and_pose():
    first = Contact(12.5, -0.351, -2.057, math.radians(-63.3), ['obstacle_5'])
    touching = judge(0, (1.0, 0.0), 10.0, (0.0, 0.0), 0.0, (1.0, 0.0), True, 1.0, 30.0, 6.0,
                     CRITERIA, ('obstacle_5', 'wall_left'), False, first)
    assert touching.first_contact_s == 12.5
    assert (touching.first_contact_x_m, touching.first_contact_y_m) == (-0.351, -2.057)
    assert touching.first_contact_yaw_deg == pytest.approx(-63.3)
    assert touching.as_dict()['first_contact_objects'] == ['obstacle_5']
    assert touching.contact_text() == ('obstacle_5, wall_left (first obstacle_5 at 12.50 s '
                                       'sim, base_link at (-0.351, -2.057) yaw -63.3 deg)')
    assert trial().contact_text() == 'no' and trial().first_contact_s is None


def test_lockstep_time_outs_are_summed_over_the_trials_that_know_them():
    def with_timeouts(index, count):
        return judge(index, (TARGET_CENTRE_M, 0.0), 10.0, (0.0, 0.0), 0.0,
                     (TARGET_CENTRE_M, 0.0), False, 1.0, 12.0, 6.0, CRITERIA,
                     lockstep_timeouts=count)
    summary = summarise([with_timeouts(0, 0), with_timeouts(1, 3), with_timeouts(2, 1)],
                        CRITERIA)
    assert (summary['lockstep_timeouts'], summary['trials_with_lockstep_timeouts']) == (4, 2)
    assert '| lockstep time-outs during trials | 4 (in 2 trials) |' in summary_table(summary)
    free_running = summarise([trial()], CRITERIA)
    assert free_running['lockstep_timeouts'] is None
    assert '| lockstep time-outs during trials | n/a |' in summary_table(free_running)
    assert TrialResult.from_dict(with_timeouts(0, 3).as_dict()).lockstep_timeouts == 3
    old = with_timeouts(0, 3).as_dict()
    del old['lockstep_timeouts']
    assert TrialResult.from_dict(old).lockstep_timeouts is None
