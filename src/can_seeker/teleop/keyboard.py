"""Keyboard teleoperation with teleop_twist_keyboard's keys, speeds and timing rules.

The key layout (upstream's)::

       u    i    o          shift (holonomic):   U    I    O
       j    k    l                               J    K    L
       m    ,    .                               M    <    >

``i``/``,`` drive forward/back, ``j``/``l`` turn left/right in place, ``u o m .`` combine them
(``m`` and ``.`` mirror upstream: backing up, ``.`` turns left and ``m`` right); the shifted keys
strafe (``linear.y``, ignored by a differential-drive base); ``t``/``b`` move up/down
(``linear.z``). ``q``/``z`` scale both speeds by 1.1/0.9, ``w``/``x`` only the linear speed,
``e``/``c`` only the turn rate; a speed key keeps the current direction. Any other key stops,
Ctrl-C quits. With a key timeout, no key for that long stops the robot too.
"""
from dataclasses import dataclass
from typing import Dict, Tuple

from can_seeker.params import Param

PARAMS = (
    Param('speed', 0.5, 'linear speed of a drive key at start (m/s); q/z and w/x scale it',
          0.0, 10.0),
    Param('turn', 1.0, 'turn rate of a turn key at start (rad/s); q/z and e/c scale it',
          0.0, 20.0),
    Param('speed_limit', 1.0, 'q and w never raise the linear speed above this (m/s)', 0.0, 10.0),
    Param('turn_limit', 3.0, 'q and e never raise the turn rate above this (rad/s)', 0.0, 20.0),
    Param('key_timeout', 0.0, 'stop when no key came for this long (s, wall clock); 0 = never, '
          'the robot keeps the last key until another key', 0.0, 60.0),
    Param('repeat_rate', 0.0, 'republish the current command at this rate (Hz, wall clock); '
          '0 = publish only when a key is read', 0.0, 100.0),
)

QUIT_KEY = '\x03'
"""Ctrl-C: read as a key in raw mode."""

MOVE_BINDINGS: Dict[str, Tuple[int, int, int, int]] = {
    'i': (1, 0, 0, 0), 'o': (1, 0, 0, -1), 'j': (0, 0, 0, 1), 'l': (0, 0, 0, -1),
    'u': (1, 0, 0, 1), ',': (-1, 0, 0, 0), '.': (-1, 0, 0, 1), 'm': (-1, 0, 0, -1),
    'O': (1, -1, 0, 0), 'I': (1, 0, 0, 0), 'J': (0, 1, 0, 0), 'L': (0, -1, 0, 0),
    'U': (1, 1, 0, 0), '<': (-1, 0, 0, 0), '>': (-1, -1, 0, 0), 'M': (-1, 1, 0, 0),
    't': (0, 0, 1, 0), 'b': (0, 0, -1, 0),
}
"""Key -> (x, y, z, yaw) direction, each -1, 0 or 1."""

SPEED_BINDINGS: Dict[str, Tuple[float, float]] = {
    'q': (1.1, 1.1), 'z': (0.9, 0.9), 'w': (1.1, 1.0), 'x': (0.9, 1.0), 'e': (1.0, 1.1),
    'c': (1.0, 0.9),
}
"""Key -> (linear speed factor, turn rate factor)."""

HELP = """Keyboard teleop: keys publish a Twist
   u    i    o      forward-left   forward   forward-right
   j    k    l      turn left      stop      turn right
   m    ,    .      back-right     back      back-left
 shift (U I O J K L M < >): strafe sideways instead of turning (holonomic bases only)
 t / b: up / down (+z / -z)
 q / z: all speeds +10 % / -10 %
 w / x: linear speed +10 % / -10 %
 e / c: turn rate +10 % / -10 %
 any other key: stop          Ctrl-C: quit (publishes a zero Twist)"""


@dataclass(frozen=True)
class TeleopCommand:
    """The velocity to publish (m/s along x, y, z of the base; rad/s about z)."""

    linear_x: float = 0.0
    linear_y: float = 0.0
    linear_z: float = 0.0
    angular_z: float = 0.0


class KeyboardTeleop:
    """Turns keys (and their absence) into commands, like teleop_twist_keyboard's main loop."""

    def __init__(self, speed: float, turn: float, speed_limit: float, turn_limit: float,
                 key_timeout_s: float):
        self.speed = min(speed, speed_limit)
        self.turn = min(turn, turn_limit)
        self.speed_limit = speed_limit
        self.turn_limit = turn_limit
        self.key_timeout_s = key_timeout_s
        self.direction = (0, 0, 0, 0)
        self.quit = False
        self._last_key_s = None

    def command(self) -> TeleopCommand:
        x, y, z, yaw = self.direction
        return TeleopCommand(x * self.speed, y * self.speed, z * self.speed, yaw * self.turn)

    def speeds_text(self) -> str:
        return 'currently:\tspeed %.3f m/s\tturn %.3f rad/s' % (self.speed, self.turn)

    def on_key(self, key: str, now_s: float) -> bool:
        """Apply one key read at ``now_s`` (s); True when the command is to be published."""
        self._last_key_s = now_s
        if key in MOVE_BINDINGS:
            self.direction = MOVE_BINDINGS[key]
        elif key in SPEED_BINDINGS:
            speed_factor, turn_factor = SPEED_BINDINGS[key]
            self.speed = min(self.speed_limit, self.speed * speed_factor)
            self.turn = min(self.turn_limit, self.turn * turn_factor)
        else:
            self.direction = (0, 0, 0, 0)
            self.quit = key == QUIT_KEY
        return True

    def on_idle(self, now_s: float) -> bool:
        """No key up to ``now_s`` (s): True when the key timeout has just stopped the robot."""
        if self.key_timeout_s <= 0.0 or self.direction == (0, 0, 0, 0):
            return False
        if self._last_key_s is not None and now_s - self._last_key_s < self.key_timeout_s:
            return False
        self.direction = (0, 0, 0, 0)
        return True
