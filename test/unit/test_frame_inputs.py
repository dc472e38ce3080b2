"""Lockstep inputs reach the controller in stamp order, whatever order they arrived in."""
from can_seeker.control.frame_inputs import FrameInputs


def live():
    return True


def dead():
    return False


def kinds(released):
    return [(kind, stamp) for kind, stamp, _ in released]


def test_detection_waits_for_odometry_and_scan_of_its_frame():
    inputs = FrameInputs(live, live)
    inputs.detection('d1', 1.0)
    assert inputs.ready() == []
    inputs.pose('p1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0)]
    inputs.scan('s1', 1.0)
    assert kinds(inputs.ready()) == [('scan', 1.0), ('detection', 1.0)]


def test_arrival_order_does_not_change_the_release_order():
    orders = []
    for arrival in (('scan', 'pose', 'detection'), ('detection', 'scan', 'pose'),
                    ('pose', 'detection', 'scan')):
        inputs = FrameInputs(live, live)
        inputs.pose('p0', 0.98)
        released = list(inputs.ready())
        for kind in arrival:
            getattr(inputs, kind)(kind, 1.0)
            released += inputs.ready()
        orders.append(kinds(released))
    assert orders[0] == orders[1] == orders[2] == [
        ('pose', 0.98), ('pose', 1.0), ('scan', 1.0), ('detection', 1.0)]


def test_a_scan_is_applied_only_once_odometry_reached_it():
    inputs = FrameInputs(live, live)
    inputs.pose('p0', 0.9)
    inputs.scan('s1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 0.9)]
    inputs.pose('p1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0), ('scan', 1.0)]


def test_inputs_without_a_source_are_not_waited_for():
    inputs = FrameInputs(live, dead)
    inputs.pose('p1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0), ('detection', 1.0)]
    inputs = FrameInputs(dead, dead)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('detection', 1.0)]


def test_a_late_scan_releases_the_frame_and_clear_drops_all():
    inputs = FrameInputs(live, live)
    inputs.pose('p1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0)]
    inputs.scan('s2', 1.1)
    assert kinds(inputs.ready()) == [('detection', 1.0)]
    inputs.detection('d3', 1.2)
    inputs.clear()
    inputs.pose('p3', 1.2)
    inputs.scan('s3', 1.2)
    assert kinds(inputs.ready()) == [('pose', 1.2), ('scan', 1.2)]


def test_a_frame_whose_scan_never_comes_is_answered_once_the_simulator_stepped_on():
    inputs = FrameInputs(live, live)
    inputs.pose('p1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0)]
    inputs.pose('p2', 1.02)
    assert kinds(inputs.ready()) == [('detection', 1.0), ('pose', 1.02)]


def test_inputs_from_before_a_reset_are_dropped_whenever_they_arrive():
    inputs = FrameInputs(live, live)
    inputs.pose('p0', 0.9)
    inputs.clear(1.0)
    for kind in ('pose', 'scan', 'detection'):
        getattr(inputs, kind)(kind + ' before', 1.0)
    assert inputs.ready() == []
    inputs.pose('p1', 1.01)
    inputs.scan('s1', 1.01)
    inputs.detection('d1', 1.01)
    assert [value for _, _, value in inputs.ready()] == ['p1', 's1', 'd1']
