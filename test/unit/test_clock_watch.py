from can_seeker.evaluation.clock_watch import ClockWatch


def test_a_clock_that_moves_is_never_stalled_however_slowly():
    watch = ClockWatch(30.0, 10.0, 0.0)
    for step in range(1, 20):
        assert not watch.stalled(10.0 + 0.001 * step, 25.0 * step)


def test_a_clock_that_stands_still_is_stalled_after_the_wall_time():
    watch = ClockWatch(30.0, 10.0, 0.0)
    assert not watch.stalled(10.0, 29.0)
    assert watch.stalled(10.0, 31.0)
    assert not watch.stalled(10.05, 32.0)             # it moved again: a fresh start
    assert not watch.stalled(10.05, 61.0)
    assert watch.stalled(10.05, 62.5)
