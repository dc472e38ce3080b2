"""The raw terminal on a real pseudo-terminal: one key at a time, settings restored."""
import os
import termios

import pytest

from can_seeker.teleop.keyboard import QUIT_KEY
from can_seeker.teleop.terminal import NotATerminalError, RawTerminal


@pytest.fixture
def pty_pair():
    master, slave = os.openpty()
    yield master, slave
    for fd in (master, slave):
        try:
            os.close(fd)
        except OSError:
            pass


def test_keys_arrive_one_by_one_without_enter(pty_pair):
    master, slave = pty_pair
    with RawTerminal(slave) as terminal:
        os.write(master, b'ik\x03')
        assert [terminal.read_key(1.0) for _ in range(3)] == ['i', 'k', QUIT_KEY]
        assert terminal.read_key(0.05) == ''


def test_raw_input_mode_inside_and_settings_restored_after(pty_pair):
    _, slave = pty_pair
    before = termios.tcgetattr(slave)
    assert before[3] & termios.ICANON and before[3] & termios.ECHO
    with RawTerminal(slave):
        inside = termios.tcgetattr(slave)
        assert not inside[3] & (termios.ICANON | termios.ECHO | termios.ISIG)
        assert inside[1] & termios.OPOST, 'output keeps its newline processing'
    assert termios.tcgetattr(slave) == before


def test_settings_restored_after_an_exception(pty_pair):
    _, slave = pty_pair
    before = termios.tcgetattr(slave)
    with pytest.raises(KeyError):
        with RawTerminal(slave):
            raise KeyError('boom')
    assert termios.tcgetattr(slave) == before


def test_a_closed_terminal_reads_as_quit(pty_pair):
    master, slave = pty_pair
    with RawTerminal(slave) as terminal:
        os.close(master)
        assert terminal.read_key(1.0) == QUIT_KEY


def test_a_pipe_is_refused_with_a_clear_error():
    read_end, write_end = os.pipe()
    try:
        with pytest.raises(NotATerminalError, match='not a terminal'):
            RawTerminal(read_end)
    finally:
        os.close(read_end)
        os.close(write_end)
