"""The twist_mux rules: priority, per-input timeout, zero once when all inputs are stale."""
import pytest

from can_seeker.params import defaults
from can_seeker.teleop.mux import PARAMS, MuxInput, TwistMux, parse_inputs

TELEOP, AUTO = 0, 1


def mux():
    return TwistMux(parse_inputs(defaults(PARAMS).inputs))


def test_default_inputs_put_teleop_over_can_stopper():
    assert parse_inputs(defaults(PARAMS).inputs) == (
        MuxInput('cmd_vel_teleop', 100, 0.5), MuxInput('cmd_vel_auto', 10, 0.5))


@pytest.mark.parametrize('text', ['', 'a:1', 'a:x:0.5', 'a:1:0', 'a:1:-1', 'a:1:inf',
                                  ':1:0.5', 'a:1:0.5 a:2:0.5', 'a:1.5:0.5'])
def test_bad_inputs_are_refused(text):
    with pytest.raises(ValueError):
        parse_inputs(text)


def test_a_lone_input_is_forwarded():
    selector = mux()
    assert selector.offer(AUTO, 0.0)
    assert selector.offer(AUTO, 0.05)
    assert selector.active(0.05).topic == 'cmd_vel_auto'


def test_teleop_overrides_until_its_timeout():
    selector = mux()
    assert selector.offer(AUTO, 0.0)
    assert selector.offer(TELEOP, 0.1)
    assert not selector.offer(AUTO, 0.15)
    assert not selector.offer(AUTO, 0.6), 'teleop is fresh for 0.5 s'
    assert selector.active(0.6).topic == 'cmd_vel_teleop'
    assert selector.offer(AUTO, 0.61)
    assert selector.active(0.61).topic == 'cmd_vel_auto'


def test_a_lower_priority_never_blocks_a_higher_one():
    selector = mux()
    assert selector.offer(AUTO, 0.0)
    assert selector.offer(TELEOP, 0.01)


def test_equal_priorities_both_pass():
    selector = TwistMux(parse_inputs('a:5:0.5 b:5:0.5'))
    assert selector.offer(0, 0.0)
    assert selector.offer(1, 0.01)
    assert selector.active(0.01).topic == 'a'


def test_zero_is_due_once_when_everything_is_stale():
    selector = mux()
    assert not selector.zero_due(0.0), 'nothing was forwarded yet'
    selector.offer(TELEOP, 1.0)
    assert not selector.zero_due(1.4)
    assert selector.zero_due(1.6)
    assert not selector.zero_due(1.7)
    selector.offer(AUTO, 2.0)
    assert not selector.zero_due(2.3)
    assert selector.zero_due(2.6)


def test_no_zero_while_a_lower_input_is_fresh():
    selector = mux()
    selector.offer(AUTO, 0.0)
    selector.offer(TELEOP, 0.1)
    selector.offer(AUTO, 0.5)
    assert not selector.zero_due(0.7)
