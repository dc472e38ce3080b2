"""The closed loop does not hang on the CPU's SIMD kernels: two short lockstep trials (empty
world, can 0.5-0.6 m ahead) on systems whose every node runs without numpy's wide (AVX-512)
kernels end as the same trials on systems with them, within 1 mm and 0.1 deg, and every node
of the narrow system (the launch's processes: sim, image_converter, obstacle_scan,
can_stopper) was started with the variable that turns them off.
"""
import xmlrpc.client

import pytest
import rosgraph
import rosnode

from can_seeker.evaluation.batch import TrialLedger, compare_runs
from can_seeker.evaluation.cpu_features import DISABLE_VARIABLE, numpy_features_to_disable
from can_seeker.tools.engine import Engine, SystemSpec, run_missing

SETTINGS = {'trials': 2, 'seed': 40}
LAUNCH_ARGS = {'world': 'empty', 'can_min_distance': 0.5, 'can_max_distance': 0.6,
               'lockstep': 'true', 'real_time_factor': 0.0}
LAUNCHED_NODES = {'/sim', '/image_converter', '/obstacle_scan', '/can_stopper'}


def node_variables():
    """Each node of this worker's system (but its own): its ``NPY_DISABLE_CPU_FEATURES``, None
    where it has none (run on the worker)."""
    master = rosgraph.Master('/cpu_features_check')
    variables = {}
    for name in rosnode.get_node_names():
        if name == '/evaluate':
            continue
        _, _, pid = xmlrpc.client.ServerProxy(rosnode.get_api_uri(master, name)).getPid(
            '/cpu_features_check')
        with open('/proc/%d/environ' % pid, 'rb') as environ:
            entries = dict(entry.split(b'=', 1) for entry in environ.read().split(b'\0')
                           if b'=' in entry)
        value = entries.get(DISABLE_VARIABLE.encode())
        variables[name] = None if value is None else value.decode()
    return variables


def test_trials_without_wide_kernels_end_as_with_them():
    features = numpy_features_to_disable()
    if not features:
        pytest.skip('this CPU has no wide numpy kernels to disable')
    with_wide = TrialLedger(SETTINGS)
    without_wide = TrialLedger(SETTINGS)
    with Engine(jobs=1) as engine:
        assert run_missing(engine, SystemSpec.of(LAUNCH_ARGS, {}, 90.0), with_wide) == []
        narrow = SystemSpec.of(LAUNCH_ARGS, {}, 90.0, wide_kernels=False)
        assert run_missing(engine, narrow, without_wide) == []
        (variables,) = engine.client.run(node_variables).values()

    assert LAUNCHED_NODES <= set(variables)
    assert set(variables.values()) == {' '.join(features)}, variables
    comparison = compare_runs(with_wide.results(), without_wide.results())
    assert comparison['compared'] == 2
    assert comparison['repeatable'], comparison
