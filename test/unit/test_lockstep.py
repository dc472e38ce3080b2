"""The lockstep gate holds a frame until every awaited input answered it, or times out."""
import struct
import threading
import time

import pytest

from can_seeker.params import parse_topics
from can_seeker.sim.lockstep import LockstepGate, header_stamp_s


def test_parse_topics_keeps_order_and_drops_repeats():
    assert parse_topics(' /a, /b /a\t/c ') == ('/a', '/b', '/c')
    assert parse_topics('') == ()


def test_header_stamp_from_a_serialized_message():
    buffer = struct.pack('<III', 7, 12, 500000000) + b'\x00\x00\x00\x00rest'
    assert header_stamp_s(buffer) == pytest.approx(12.5)
    with pytest.raises(ValueError):
        header_stamp_s(b'\x01\x02')


def test_nothing_held_means_step_at_once():
    gate = LockstepGate(timeout_s=1.0)
    assert not gate.holding
    assert gate.wait(0.0) == ()


def test_frame_waits_until_every_input_answered_at_or_after_its_stamp():
    gate = LockstepGate(timeout_s=5.0)
    gate.hold(1.5, ['/detection', '/cmd'])
    assert gate.holding
    assert gate.wait(0.0) is None
    gate.answered('/detection', 1.5)
    gate.answered('/cmd', 1.4)
    assert gate.missing() == ('/cmd',)
    assert gate.wait(0.0) is None
    gate.answered('/cmd', 1.5)
    assert gate.wait(0.0) == ()
    assert not gate.holding
    assert gate.timeouts == 0


def test_answers_given_before_the_hold_count_when_stamped_late_enough():
    gate = LockstepGate(timeout_s=5.0)
    gate.answered('/scan', 3.0)
    gate.hold(2.0, ['/scan'])
    assert gate.wait(0.0) == ()


def test_no_awaited_inputs_holds_nothing():
    gate = LockstepGate(timeout_s=5.0)
    gate.hold(1.0, [])
    assert not gate.holding


def test_wait_returns_when_another_thread_answers():
    gate = LockstepGate(timeout_s=5.0)
    gate.hold(2.0, ['/detection'])
    answer = threading.Timer(0.05, gate.answered, args=('/detection', 2.0))
    answer.start()
    start = time.monotonic()
    try:
        assert gate.wait(2.0) == ()
    finally:
        answer.join()
    assert time.monotonic() - start < 1.0


def test_timeout_releases_the_frame_names_the_silent_inputs_and_counts():
    gate = LockstepGate(timeout_s=0.05)
    gate.hold(1.0, ['/detection', '/cmd'])
    gate.answered('/cmd', 1.0)
    deadline = time.monotonic() + 2.0
    outcome = None
    while outcome is None and time.monotonic() < deadline:
        outcome = gate.wait(0.01)
    assert outcome == ('/detection',)
    assert gate.timeouts == 1
    assert not gate.holding

