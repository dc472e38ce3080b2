"""The keyboard as a terminal in raw input mode: one key at a time, no echo, no line editing.

Input is raw (Ctrl-C arrives as the key ``\\x03``, not as SIGINT) but output processing stays
on, so lines printed by other processes sharing the terminal (roslaunch) keep their layout. The
previous settings are restored on exit, whatever happens.
"""
import os
import select
import termios

from can_seeker.teleop.keyboard import QUIT_KEY


class NotATerminalError(RuntimeError):
    """The input is not a terminal, so no keys can be read from it."""


class RawTerminal:
    """Context manager: ``fd`` in raw input mode while inside; ``read_key`` reads one key."""

    def __init__(self, fd: int):
        if not os.isatty(fd):
            raise NotATerminalError(
                'standard input is not a terminal: run the keyboard teleop in a terminal '
                '(rosrun can_seeker teleop_keyboard), or from roslaunch in a terminal of its own '
                '(launch-prefix="xterm -e")')
        self.fd = fd
        self._saved = None

    def __enter__(self):
        self._saved = termios.tcgetattr(self.fd)
        raw = termios.tcgetattr(self.fd)
        raw[0] &= ~(termios.BRKINT | termios.ICRNL | termios.INPCK | termios.ISTRIP
                    | termios.IXON)
        raw[3] &= ~(termios.ECHO | termios.ICANON | termios.IEXTEN | termios.ISIG)
        raw[6][termios.VMIN] = 1
        raw[6][termios.VTIME] = 0
        termios.tcsetattr(self.fd, termios.TCSAFLUSH, raw)
        return self

    def __exit__(self, *_exc):
        try:
            termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)
        except termios.error:
            pass  # the terminal is gone (hung up): there is nothing left to restore
        return False

    def read_key(self, timeout_s: float) -> str:
        """One key, or '' when none came within ``timeout_s`` (s). A closed terminal reads
        as Ctrl-C (quit): it must not leave the robot driving."""
        ready, _, _ = select.select([self.fd], [], [], timeout_s)
        if not ready:
            return ''
        try:
            data = os.read(self.fd, 1)
        except OSError:
            data = b''
        return data.decode('latin-1') if data else QUIT_KEY
