"""Per-kind log throttling: kinds do not hide each other, texts within a kind do not count."""
from can_seeker.throttle import KindThrottle


def test_first_message_of_each_kind_is_logged():
    throttle = KindThrottle(5.0)
    assert throttle.allow('data length', 0.0) == (True, 0)
    assert throttle.allow('encoding', 0.1) == (True, 0)


def test_repeats_within_the_period_are_held_back_and_counted():
    throttle = KindThrottle(5.0)
    assert throttle.allow('data length', 0.0)[0]
    assert [throttle.allow('data length', 0.5 * i)[0] for i in range(1, 10)] == [False] * 9
    assert throttle.allow('data length', 5.0) == (True, 9)
    assert throttle.allow('data length', 6.0) == (False, 0)
    assert throttle.allow('data length', 10.0) == (True, 1)
