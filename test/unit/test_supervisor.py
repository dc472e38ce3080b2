"""The one transition table, and the supervisor that applies it."""
import pytest

from can_seeker.control.supervisor import TRANSITIONS, Event, State, Supervisor


class Recorder:
    def __init__(self):
        self.started = []

    def start(self, now_s):
        self.started.append(now_s)


def make():
    behaviours = {state: Recorder() for state in State}
    entered = []
    return Supervisor(behaviours, on_enter=(entered.append,)), behaviours, entered


def test_every_state_is_reachable_and_every_reset_goes_to_its_start_state():
    assert set(TRANSITIONS.values()) == set(State)
    for state in State:
        assert TRANSITIONS[(state, Event.RESET_DISARMED)] is State.IDLE
        assert TRANSITIONS[(state, Event.RESET_SEEK)] is State.SEARCH
        assert TRANSITIONS[(state, Event.RESET_WANDER)] is State.WANDER


def test_wander_and_idle_leave_only_by_a_reset():
    for state in (State.WANDER, State.IDLE):
        events = {event for (source, event) in TRANSITIONS if source is state}
        assert events == {Event.RESET_DISARMED, Event.RESET_SEEK, Event.RESET_WANDER}


def test_an_event_changes_the_state_by_the_table_and_starts_its_behaviour():
    supervisor, behaviours, entered = make()
    supervisor.handle(Event.RESET_SEEK, 1.0)
    supervisor.handle(Event.CAN_RANGED, 2.0)
    supervisor.handle(Event.CAN_OUT_OF_RANGE, 3.0)
    assert supervisor.state is State.LOST
    assert entered == [State.SEARCH, State.APPROACH, State.LOST]
    assert behaviours[State.LOST].started == [3.0]
    assert supervisor.behaviour is behaviours[State.LOST]


def test_no_event_changes_nothing_and_an_event_without_a_row_is_an_error():
    supervisor, _, entered = make()
    supervisor.handle(Event.RESET_SEEK, 0.0)
    supervisor.handle(None, 1.0)
    assert supervisor.state is State.SEARCH and entered == [State.SEARCH]
    with pytest.raises(KeyError):
        supervisor.handle(Event.SETTLED, 1.0)
    assert supervisor.state is State.SEARCH
