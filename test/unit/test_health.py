"""Input rates and ages, and the levels a node's diagnostics report them at."""
import pytest

from can_seeker.health import (CLOCK_GRACE_S, ERROR, ClockWatch, NO_CLOCK_HINT, OK, WARN, Health, InputMonitor,
                               Outcomes, clock_health, worst)
from can_seeker.sim.status import RunStatus


def test_rate_counts_the_recent_arrivals_only():
    monitor = InputMonitor('image', window_s=2.0)
    for index in range(45):                      # 15 Hz for 3 s
        monitor.received(index / 15.0, index / 15.0)
    assert monitor.rate_hz(44 / 15.0) == pytest.approx(15.0)
    assert monitor.rate_hz(10.0) == 0.0           # nothing within the last 2 s
    assert monitor.count == 45


def test_age_is_by_stamp_when_stamped_and_by_arrival_otherwise():
    monitor = InputMonitor('detection')
    assert monitor.age_s(5.0) is None
    monitor.received(5.0, 4.6)
    assert monitor.age_s(5.5) == pytest.approx(0.9)
    monitor.received(6.0)
    assert monitor.age_s(6.5) == pytest.approx(0.5)


def test_an_input_names_the_topic_it_listens_on_even_before_any_message():
    image = InputMonitor('image', 1.0, topic='/raspicam_node/image/compressed')
    assert image.health(1.0).message == 'no message yet'
    assert ('topic', '/raspicam_node/image/compressed') in image.health(1.0).values
    image.received(1.0, 1.0)
    assert ('topic', '/raspicam_node/image/compressed') in image.health(1.2).values
    assert 'topic' not in dict(InputMonitor('image').health(1.0).values)


def test_messages_that_keep_coming_with_old_stamps_point_at_the_senders_clock():
    """A camera on a Pi whose clock is 2 s behind: 15 Hz of images, each stamped 2 s ago."""
    image = InputMonitor('image', timeout_s=0.5, missing_level=ERROR)
    for index in range(30):
        image.received(10.0 + index / 15.0, 8.0 + index / 15.0)
    health = image.health(12.0)
    assert health.level == ERROR
    assert health.message.startswith('arriving at 15.0 Hz but stamped 2.07 s ago (timeout 0.50 s)')
    assert 'clock' in health.message
    assert image.health(12.5).message == 'no message for 2.57 s (timeout 0.50 s)'  # none since


def test_missing_or_stale_input_is_reported_at_its_level():
    odometry = InputMonitor('odometry', timeout_s=0.5, missing_level=ERROR)
    assert odometry.health(1.0).level == ERROR
    assert odometry.health(1.0).message == 'no message yet'
    odometry.received(1.0, 1.0)
    odometry.received(1.02, 1.02)
    fresh = odometry.health(1.1)
    assert fresh.level == OK and fresh.message.startswith('50.0 Hz, newest 0.080 s old')
    stale = odometry.health(2.22)
    assert stale.level == ERROR
    assert stale.message == 'no message for 1.20 s (timeout 0.50 s)'
    assert ('timeout (s)', '0.500') in stale.values
    teleop = InputMonitor('keys', timeout_s=0.5, missing_level=OK)
    assert teleop.health(3.0).level == OK


def test_worst_level():
    assert worst([]) == OK
    assert worst([Health(OK, 'a'), Health(ERROR, 'b'), Health(WARN, 'c')]) == ERROR


def test_the_simulation_reports_its_pace_and_new_lockstep_timeouts():
    status = RunStatus()
    first = status.report(10.0, 100.0, False, 150, 0, ())
    assert first.level == OK and first.message.startswith('t=10.000 s')
    running = status.report(13.0, 101.0, False, 195, 0, ())
    assert running.level == OK and running.message == 't=13.000 s, 3.00x real time'
    stalled = status.report(13.1, 103.0, False, 196, 1, ('/cmd_vel_stamped',))
    assert stalled.level == WARN
    assert stalled.message.startswith('lockstep: 1 frames timed out')
    assert ('waiting for', '/cmd_vel_stamped') in stalled.values
    assert status.report(13.1, 104.0, True, 196, 1, ()).message == 'paused at t=13.100 s'
    free = RunStatus().report(1.0, 1.0, False, 15, None)
    assert 'lockstep time-outs' not in dict(free.values)


def test_outcomes_report_the_worst_of_the_recent_frames():
    outcomes = Outcomes(window=3)
    assert outcomes.health().level == WARN
    outcomes.add('skipped: data length', ERROR)
    for _ in range(2):
        outcomes.add('can found')
    assert outcomes.health().level == ERROR
    outcomes.add('no can')
    health = outcomes.health()
    assert health.level == OK
    assert health.message == 'last 3 frames: 2 can found, 1 no can'
    assert ('frames', '4') in health.values


def test_clock_health_warns_without_a_clock_publisher():
    assert clock_health(False, 0.0, 0, 100.0) == Health(OK, 'wall clock')
    assert clock_health(True, 0.0, 0, CLOCK_GRACE_S - 0.1).level == OK
    assert clock_health(True, 0.0, 1, CLOCK_GRACE_S + 100.0).level == OK   # a paused sim at 0
    never = clock_health(True, 0.0, 0, CLOCK_GRACE_S + 1.0)
    assert never.level == WARN
    assert NO_CLOCK_HINT in never.message and 'use_sim_time' in never.message
    assert clock_health(True, 3.25, 0, CLOCK_GRACE_S - 0.1).level == OK   # shutting down
    gone = clock_health(True, 3.25, 0, CLOCK_GRACE_S + 1.0)
    assert gone.level == WARN and '3.250' in gone.message
    started = clock_health(True, 3.25, 1, CLOCK_GRACE_S + 100.0)
    assert started.level == OK and ('time (s)', '3.250') in started.values


def test_a_refused_message_is_reported_until_one_is_used():
    monitor = InputMonitor('camera_info', 1.0, WARN, topic='/camera/camera_info')
    monitor.received(10.0, 10.0)
    assert monitor.health(10.1).level == OK
    monitor.received(10.2, 10.2, refused='K is all zero')
    refused = monitor.health(10.3)
    assert refused.level == WARN and 'K is all zero' in refused.message
    assert ('topic', '/camera/camera_info') in refused.values
    monitor.received(10.4, 10.4)
    assert monitor.health(10.5).level == OK


def test_clock_watch_warns_once_a_publisher_is_gone_for_the_grace_and_logs_at_its_period():
    watch = ClockWatch(True, start_wall_s=100.0, log_period_s=30.0)
    assert watch.health(0.0, 0, 100.0 + CLOCK_GRACE_S - 1.0) == (
        clock_health(True, 0.0, 0, CLOCK_GRACE_S - 1.0), False)
    health, log = watch.health(0.0, 0, 100.0 + CLOCK_GRACE_S + 1.0)
    assert health.level == WARN and log
    assert watch.health(0.0, 0, 100.0 + CLOCK_GRACE_S + 2.0)[1] is False   # logged already
    assert watch.health(0.0, 0, 100.0 + CLOCK_GRACE_S + 32.0)[1] is True
    assert watch.health(5.0, 1, 200.0)[0].level == OK
    assert watch.health(7.0, 0, 200.0 + CLOCK_GRACE_S - 1.0)[0].level == OK   # shutting down
    gone, _ = watch.health(7.0, 0, 200.0 + CLOCK_GRACE_S + 1.0)
    assert gone.level == WARN and '7.000' in gone.message
