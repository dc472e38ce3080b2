"""What identifies a worker's ROS system: trials with equal launch arguments, parameters, time
limit, run and kernels share systems; any difference needs systems of its own; where logs go
does not matter. A local cluster counts the CPU time of its worker processes."""
import os
import time

from can_seeker.evaluation.cpu_features import narrow_kernel_environment, numpy_features_to_disable
from can_seeker.tools.engine import Engine, SystemSpec

LAUNCH_ARGS = {'world': 'room', 'lockstep': 'true', 'width': 320}


def test_equal_settings_in_any_order_are_one_system():
    first = SystemSpec.of(LAUNCH_ARGS, {'/sim/seed': 1, '/can_stopper/stop_distance': 0.25}, 90)
    second = SystemSpec.of(dict(reversed(list(LAUNCH_ARGS.items()))),
                           {'/can_stopper/stop_distance': '0.25', '/sim/seed': '1'}, 90.0,
                           log_dir='/tmp/logs')
    assert first.key() == second.key()


def test_another_setting_or_run_is_another_system():
    base = SystemSpec.of(LAUNCH_ARGS, {}, 90.0)
    others = [SystemSpec.of(dict(LAUNCH_ARGS, width=640), {}, 90.0),
              SystemSpec.of(LAUNCH_ARGS, {'/sim/realism/camera_read_noise': 4}, 90.0),
              SystemSpec.of(LAUNCH_ARGS, {}, 60.0),
              SystemSpec.of(LAUNCH_ARGS, {}, 90.0, run=1),
              SystemSpec.of(LAUNCH_ARGS, {}, 90.0, wide_kernels=False)]
    assert len({spec.key() for spec in others} | {base.key()}) == 6


def test_only_a_system_without_wide_kernels_adds_numpy_features_to_its_environment():
    assert SystemSpec.of(LAUNCH_ARGS, {}, 90.0).environment() == {}
    narrow = SystemSpec.of(LAUNCH_ARGS, {}, 90.0, wide_kernels=False).environment()
    assert narrow == narrow_kernel_environment(numpy_features_to_disable())


def _burn(seconds):
    end = time.process_time() + seconds
    while time.process_time() < end:
        pass
    return os.getpid()


def test_a_local_cluster_counts_the_cpu_of_its_worker_processes():
    with Engine(jobs=1) as engine:
        worker_pid = engine.client.submit(_burn, 1.0, pure=False).result()
        assert worker_pid != os.getpid()
        assert engine.cpu_s is None
    assert engine.cpu_s >= 1.0
    assert engine.real_time_per_core == 0.0
    engine.sim_s = 2.0 * engine.cpu_s
    assert engine.real_time_per_core == 2.0
