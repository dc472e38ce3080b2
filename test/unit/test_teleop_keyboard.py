"""Keyboard teleop: teleop_twist_keyboard's key layout, speed keys, limits, stop and timeout."""
import pytest

from can_seeker.params import defaults
from can_seeker.teleop.keyboard import (MOVE_BINDINGS, PARAMS, QUIT_KEY, KeyboardTeleop,
                                        TeleopCommand)


def teleop(key_timeout_s=0.0):
    values = defaults(PARAMS)
    return KeyboardTeleop(values.speed, values.turn, values.speed_limit, values.turn_limit,
                          key_timeout_s)


def command_after(*keys):
    keyboard = teleop()
    for index, key in enumerate(keys):
        keyboard.on_key(key, float(index))
    return keyboard.command()


def test_defaults_are_upstreams_speeds():
    values = defaults(PARAMS)
    assert (values.speed, values.turn) == (0.5, 1.0)
    assert (values.key_timeout, values.repeat_rate) == (0.0, 0.0)


@pytest.mark.parametrize('key,expected', [
    ('i', TeleopCommand(0.5, 0.0, 0.0, 0.0)),
    (',', TeleopCommand(-0.5, 0.0, 0.0, 0.0)),
    ('j', TeleopCommand(0.0, 0.0, 0.0, 1.0)),
    ('l', TeleopCommand(0.0, 0.0, 0.0, -1.0)),
    ('u', TeleopCommand(0.5, 0.0, 0.0, 1.0)),
    ('o', TeleopCommand(0.5, 0.0, 0.0, -1.0)),
    ('m', TeleopCommand(-0.5, 0.0, 0.0, -1.0)),
    ('.', TeleopCommand(-0.5, 0.0, 0.0, 1.0)),
    ('J', TeleopCommand(0.0, 0.5, 0.0, 0.0)),
    ('L', TeleopCommand(0.0, -0.5, 0.0, 0.0)),
    ('U', TeleopCommand(0.5, 0.5, 0.0, 0.0)),
    ('>', TeleopCommand(-0.5, -0.5, 0.0, 0.0)),
    ('t', TeleopCommand(0.0, 0.0, 0.5, 0.0)),
    ('b', TeleopCommand(0.0, 0.0, -0.5, 0.0)),
])
def test_move_keys_give_upstreams_twists(key, expected):
    assert command_after(key) == expected


def test_the_layout_has_every_upstream_move_key():
    assert set(MOVE_BINDINGS) == set('uiojlm,.UIOJLM<>tb')


@pytest.mark.parametrize('stop_key', ['k', ' ', 'K', 'a', '\x1b'])
def test_any_other_key_stops(stop_key):
    assert command_after('u', stop_key) == TeleopCommand()


def test_speed_keys_scale_and_keep_the_direction():
    command = command_after('u', 'q')
    assert command.linear_x == pytest.approx(0.55)
    assert command.angular_z == pytest.approx(1.1)
    command = command_after('u', 'z', 'x', 'c')
    assert command.linear_x == pytest.approx(0.5 * 0.9 * 0.9)
    assert command.angular_z == pytest.approx(1.0 * 0.9 * 0.9)
    command = command_after('u', 'w', 'e', 'e')
    assert command.linear_x == pytest.approx(0.55)
    assert command.angular_z == pytest.approx(1.21)


def test_speeds_never_exceed_their_limits():
    command = command_after('u', *('q' * 40))
    assert command.linear_x == pytest.approx(defaults(PARAMS).speed_limit)
    assert command.angular_z == pytest.approx(defaults(PARAMS).turn_limit)
    assert KeyboardTeleop(5.0, 9.0, 1.0, 2.0, 0.0).speed == 1.0


def test_ctrl_c_stops_and_quits():
    keyboard = teleop()
    keyboard.on_key('i', 0.0)
    assert not keyboard.quit
    assert keyboard.on_key(QUIT_KEY, 1.0)
    assert keyboard.quit
    assert keyboard.command() == TeleopCommand()


def test_without_a_key_timeout_the_last_key_holds():
    keyboard = teleop()
    keyboard.on_key('i', 0.0)
    assert not keyboard.on_idle(1000.0)
    assert keyboard.command().linear_x == 0.5


def test_the_key_timeout_stops_once():
    keyboard = teleop(key_timeout_s=0.5)
    keyboard.on_key('i', 10.0)
    assert not keyboard.on_idle(10.4)
    keyboard.on_key('i', 10.4)
    assert not keyboard.on_idle(10.8)
    assert keyboard.on_idle(10.9)
    assert keyboard.command() == TeleopCommand()
    assert not keyboard.on_idle(11.5), 'an idle robot is not stopped again'
