"""Calls from other threads run on the owner thread, in order, with results and errors."""
import threading

import pytest

from can_seeker.sim.call_queue import CallQueue


def _owner_loop(calls, stop):
    while not stop.is_set():
        calls.run_pending()
        stop.wait(0.001)


def test_call_runs_on_the_owner_thread_and_returns_its_result():
    calls, stop = CallQueue(), threading.Event()
    owner = threading.Thread(target=_owner_loop, args=(calls, stop))
    owner.start()
    try:
        assert calls.call(threading.get_ident, timeout_s=5.0) == owner.ident
    finally:
        stop.set()
        owner.join()


def test_call_reraises_the_error_in_the_caller():
    calls, stop = CallQueue(), threading.Event()
    owner = threading.Thread(target=_owner_loop, args=(calls, stop))
    owner.start()
    try:
        with pytest.raises(ZeroDivisionError):
            calls.call(lambda: 1 / 0, timeout_s=5.0)
    finally:
        stop.set()
        owner.join()


def test_call_times_out_when_the_owner_does_not_run():
    with pytest.raises(TimeoutError):
        CallQueue().call(lambda: None, timeout_s=0.05)


def test_posted_calls_run_in_order_without_waiting():
    calls, order = CallQueue(), []
    for index in range(3):
        calls.post(lambda index=index: order.append(index))
    assert order == []
    calls.run_pending()
    assert order == [0, 1, 2]
    calls.run_pending()
    assert order == [0, 1, 2]
