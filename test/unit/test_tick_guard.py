"""A control tick always ends in a command: zero, logged, when anything in it failed."""
import math

from can_seeker.control.tick_guard import TickGuard
from can_seeker.control.twist_limits import require_finite


class Robot:
    def __init__(self):
        self.zeros = 0
        self.logged = []

    def send_zero(self):
        self.zeros += 1


def broken_tick():
    raise RuntimeError('broken')


def test_a_failing_tick_sends_zero_and_logs_the_traceback():
    robot = Robot()
    guard = TickGuard(robot.logged.append, period_s=5.0)
    guard.run(broken_tick, robot.send_zero, 0.0)
    assert robot.zeros == 1
    assert len(robot.logged) == 1
    assert 'RuntimeError: broken' in robot.logged[0] and 'Traceback' in robot.logged[0]
    assert 'broken_tick' in robot.logged[0]


def test_repeated_failures_send_zero_every_tick_and_log_throttled():
    robot = Robot()
    guard = TickGuard(robot.logged.append, period_s=5.0)
    for tick in range(120):
        guard.run(broken_tick, robot.send_zero, tick * 0.05)
    assert robot.zeros == 120
    assert len(robot.logged) == 2
    assert 'Traceback' not in robot.logged[1] and '99' in robot.logged[1]


def test_a_tick_that_works_sends_no_extra_zero():
    robot = Robot()
    guard = TickGuard(robot.logged.append)
    guard.run(lambda: None, robot.send_zero, 0.0)
    assert robot.zeros == 0 and robot.logged == []


def test_a_failing_zero_is_logged_not_raised():
    robot = Robot()
    guard = TickGuard(robot.logged.append)

    def broken_publisher():
        raise OSError('publisher closed')
    guard.run(broken_tick, broken_publisher, 0.0)
    assert any('publisher closed' in message for message in robot.logged)


def test_a_non_finite_command_is_a_failure():
    robot = Robot()
    guard = TickGuard(robot.logged.append)
    sent = []
    guard.run(lambda: sent.append(require_finite((math.nan, 0.0))), robot.send_zero, 0.0)
    assert sent == [] and robot.zeros == 1 and 'finite' in robot.logged[0]
