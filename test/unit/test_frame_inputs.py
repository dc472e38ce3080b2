"""Lockstep inputs reach the controller in stamp order, whatever order they arrived in."""
import itertools

from can_seeker.control.frame_inputs import FrameInputs

CAMERA = '/camera_scan'
LIDAR = '/scan'
FRAME_S = 1.0 / 15.0
LIDAR_PERIOD_S = 0.1


def live(*_source):
    return True


def dead(*_source):
    return False


def kinds(released):
    return [(kind, stamp) for kind, stamp, _ in released]


def heard(inputs, stamp_s=0.0):
    """``inputs`` after its sources were heard from and a reset at ``stamp_s``, as before a
    trial (a source not heard from yet has no schedule, and is not waited for)."""
    for source, period_s in ((CAMERA, 0.0), (LIDAR, LIDAR_PERIOD_S)):
        inputs.scan(source, 'warm-up', stamp_s - 0.05, period_s)
    inputs.clear(stamp_s)
    return inputs


def camera_inputs(pose_live=live, scan_live=live):
    return heard(FrameInputs(pose_live, scan_live, (CAMERA,)))


def test_detection_waits_for_odometry_and_scan_of_its_frame():
    inputs = camera_inputs()
    inputs.detection('d1', 1.0)
    assert inputs.ready() == []
    inputs.pose('p1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0)]
    inputs.scan(CAMERA, 's1', 1.0)
    assert kinds(inputs.ready()) == [('scan', 1.0), ('detection', 1.0)]


def test_arrival_order_does_not_change_the_release_order():
    orders = []
    for arrival in (('scan', 'pose', 'detection'), ('detection', 'scan', 'pose'),
                    ('pose', 'detection', 'scan')):
        inputs = camera_inputs()
        inputs.pose('p0', 0.98)
        released = list(inputs.ready())
        for kind in arrival:
            if kind == 'scan':
                inputs.scan(CAMERA, kind, 1.0)
            else:
                getattr(inputs, kind)(kind, 1.0)
            released += inputs.ready()
        orders.append(kinds(released))
    assert orders[0] == orders[1] == orders[2] == [
        ('pose', 0.98), ('pose', 1.0), ('scan', 1.0), ('detection', 1.0)]


def test_a_scan_is_applied_only_once_odometry_reached_it():
    inputs = camera_inputs()
    inputs.pose('p0', 0.9)
    inputs.scan(CAMERA, 's1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 0.9)]
    inputs.pose('p1', 1.0)
    assert [(kind, stamp, value) for kind, stamp, value in inputs.ready()] == [
        ('pose', 1.0, 'p1'), ('scan', 1.0, (CAMERA, 's1'))]


def test_inputs_without_a_source_are_not_waited_for():
    inputs = camera_inputs(scan_live=dead)
    inputs.pose('p1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0), ('detection', 1.0)]
    inputs = camera_inputs(pose_live=dead, scan_live=dead)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('detection', 1.0)]


def test_a_late_scan_releases_the_frame_and_clear_drops_all():
    inputs = camera_inputs()
    inputs.pose('p1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0)]
    inputs.scan(CAMERA, 's2', 1.1)
    assert kinds(inputs.ready()) == [('detection', 1.0)]
    inputs.detection('d3', 1.2)
    inputs.clear()
    inputs.pose('p3', 1.2)
    inputs.scan(CAMERA, 's3', 1.2)
    assert kinds(inputs.ready()) == [('pose', 1.2), ('scan', 1.2)]


def test_a_frame_whose_scan_never_comes_is_answered_once_a_later_frame_arrived():
    inputs = camera_inputs()
    inputs.pose('p1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0)]
    inputs.pose('p2', 1.0 + FRAME_S)
    inputs.detection('d2', 1.0 + FRAME_S)
    assert kinds(inputs.ready()) == [('detection', 1.0), ('pose', 1.0 + FRAME_S)]


def test_odometry_past_a_late_published_frame_does_not_release_it_without_its_scan():
    """With camera latency the frame is published, with its odometry, after its capture stamp:
    that odometry is no sign that the simulator stepped on."""
    inputs = camera_inputs()
    inputs.detection('d1', 1.0)
    inputs.pose('p published', 1.05)
    assert kinds(inputs.ready()) == []
    inputs.scan(CAMERA, 's1', 1.0)
    assert kinds(inputs.ready()) == [('scan', 1.0), ('detection', 1.0), ('pose', 1.05)]


def test_inputs_from_before_a_reset_are_dropped_whenever_they_arrive():
    inputs = camera_inputs()
    inputs.pose('p0', 0.9)
    inputs.ready()
    inputs.clear(1.0)
    inputs.pose('pose before', 1.0)
    inputs.scan(CAMERA, 'scan before', 1.0)
    inputs.detection('detection before', 1.0)
    assert inputs.ready() == []
    inputs.pose('p1', 1.01)
    inputs.scan(CAMERA, 's1', 1.01)
    inputs.detection('d1', 1.01)
    assert [value for _, _, value in inputs.ready()] == ['p1', (CAMERA, 's1'), 'd1']


PHYSICS_HZ = 240
FRAME_STEPS = 16
LIDAR_STEPS = 24


def lidar_run(sources, arrival_orders):
    """Lockstep frames at 15 Hz with a 10 Hz lidar (and the camera scan) from a reset at 0, on
    the simulator's 240 Hz steps: each frame is published only after the previous one was
    answered, and the scans due by a frame before it; the inputs of one frame arrive in the
    order ``arrival_orders`` gives. Returns what was released, asserting that every frame
    was answered before the next one."""
    inputs = heard(FrameInputs(live, live, sources))
    released, lidar_step = [], LIDAR_STEPS
    for frame, order in zip(range(1, 13), arrival_orders):
        frame_step = frame * FRAME_STEPS
        messages = []
        while lidar_step <= frame_step:
            if LIDAR in sources:
                messages.append(('lidar', lidar_step / PHYSICS_HZ))
            lidar_step += LIDAR_STEPS
        frame_s = frame_step / PHYSICS_HZ
        messages += [('pose', frame_s), ('detection', frame_s)]
        if CAMERA in sources:
            messages.append(('camera', frame_s))
        for kind, stamp_s in order(messages):
            if kind == 'lidar':
                inputs.scan(LIDAR, 'lidar', stamp_s, LIDAR_STEPS / PHYSICS_HZ)
            elif kind == 'camera':
                inputs.scan(CAMERA, 'camera', stamp_s)
            else:
                getattr(inputs, kind)(kind, stamp_s)
            released += inputs.ready()
        answered = [stamp for kind, stamp in kinds(released) if kind == 'detection']
        assert answered and answered[-1] == frame_s, (
            'frame %d (t=%.4f) is still waiting: lockstep would stall' % (frame, frame_s))
    return released


def test_a_lidar_slower_than_the_frames_never_stalls_lockstep():
    released = lidar_run((LIDAR,), itertools.repeat(list))
    detections = [stamp for kind, stamp in kinds(released) if kind == 'detection']
    assert len(detections) == 12


def test_each_frame_is_answered_after_every_scan_due_by_it_whatever_the_arrival_order():
    runs = [lidar_run((CAMERA, LIDAR), itertools.repeat(order)) for order in (
        list, lambda messages: list(reversed(messages)),
        lambda messages: sorted(messages, key=lambda message: message[0]))]
    assert [kinds(run) for run in runs[1:]] == [kinds(runs[0])] * 2
    order = kinds(runs[0])
    for index, (kind, stamp_s) in enumerate(order):
        if kind == 'detection':
            applied = {scan_s for scan_kind, scan_s in order[:index] if scan_kind == 'scan'}
            due = {step / PHYSICS_HZ for step in range(LIDAR_STEPS, 200, LIDAR_STEPS)
                   if step / PHYSICS_HZ <= stamp_s}
            assert due <= applied


def test_a_source_not_heard_from_yet_is_not_waited_for():
    inputs = FrameInputs(live, live, (CAMERA,))
    inputs.pose('p1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0), ('detection', 1.0)]
    inputs.scan(CAMERA, 's1', 1.0)
    inputs.pose('p2', 1.1)
    inputs.detection('d2', 1.1)
    assert kinds(inputs.ready()) == [('scan', 1.0), ('pose', 1.1)]


def test_scans_of_two_sources_with_one_stamp_are_released_in_source_order():
    releases = []
    for first, second in ((CAMERA, LIDAR), (LIDAR, CAMERA)):
        inputs = FrameInputs(live, live, (CAMERA, LIDAR))
        inputs.scan(first, first, 1.0)
        inputs.scan(second, second, 1.0)
        inputs.pose('p', 1.0)
        releases.append([value for _, _, value in inputs.ready()])
    assert releases[0] == releases[1] == ['p', (CAMERA, CAMERA), (LIDAR, LIDAR)]


def test_a_late_frame_is_answered_from_the_odometry_of_its_delivery_whatever_the_arrival():
    """Camera latency: the frame stamped 1.0 goes out at 1.12 with the odometry of 1.12. The
    answer must come after that odometry, not after whichever odometry happened to arrive
    before the detection did. (Odometry comes in stamp order; a scan is placed at the pose of
    its stamp, so whether later odometry was applied before it does not matter.)"""
    befores = set()
    arrivals = (('pose', 1.1), ('pose', 1.12), ('delivery', None), ('scan', 1.0),
                ('detection', 1.0))
    for arrival in itertools.permutations(arrivals):
        if arrival.index(('pose', 1.1)) > arrival.index(('pose', 1.12)):
            continue
        inputs = camera_inputs()
        inputs.pose('p0', 0.98)
        released = list(inputs.ready())
        inputs.delivery(0.9, 0.95)   # an earlier frame's: deliveries are being sent
        for kind, stamp_s in arrival:
            if kind == 'delivery':
                inputs.delivery(1.0, 1.12)
            elif kind == 'scan':
                inputs.scan(CAMERA, 's1', stamp_s)
            else:
                getattr(inputs, kind)(kind, stamp_s)
            released += inputs.ready()
        assert kinds(released)[-1] == ('detection', 1.0)
        befores.add(frozenset(kinds(released)[:-1]))
    assert befores == {frozenset((('pose', 0.98), ('scan', 1.0), ('pose', 1.1),
                                  ('pose', 1.12)))}


def test_a_late_frame_waits_for_lidar_scans_due_by_its_delivery():
    inputs = heard(FrameInputs(live, live, (CAMERA, LIDAR)))
    inputs.delivery(0.5, 0.5)
    inputs.pose('p', 1.12)
    inputs.scan(CAMERA, 'camera', 1.0)
    inputs.delivery(1.0, 1.12)
    inputs.detection('d', 1.0)
    inputs.scan(LIDAR, 'lidar', 0.0)
    assert ('detection', 1.0) not in kinds(inputs.ready())
    inputs.scan(LIDAR, 'lidar', 1.1)
    assert kinds(inputs.ready())[-3:] == [('scan', 1.1), ('pose', 1.12), ('detection', 1.0)]


def test_without_deliveries_a_frame_is_answered_as_before():
    inputs = camera_inputs()
    inputs.pose('p1', 1.0)
    inputs.scan(CAMERA, 's1', 1.0)
    inputs.detection('d1', 1.0)
    assert kinds(inputs.ready()) == [('pose', 1.0), ('scan', 1.0), ('detection', 1.0)]
