"""The distributed engine of ``evaluate``: trials as Dask tasks on worker processes, each worker
process with a ROS system of its own.

A trial is one task. The worker process that runs it starts its system on its first trial
(``demo.launch`` under its own master on a free port, and this process's one rospy node on it)
and keeps it for the trials that follow; a worker plugin shuts it down when the worker closes.
rospy allows one node per process, so a worker process serves one system all its life: every
system (its launch arguments, parameters, time limit and run) runs on fresh worker processes,
the engine restarts them between systems (a sweep's settings, a repeat check's second run).

Results come back as they finish (``as_completed``). A worker process that is lost (killed,
crashed, or whose system failed: it leaves its process, which rospy cannot give a second node)
is restarted by its nanny and the scheduler runs its trials again, up to
:data:`WORKER_LOSSES_PER_TRIAL` lost workers per trial.

By default the engine runs a local cluster of ``jobs`` worker processes, one thread each;
``address`` connects to a running scheduler instead (``dask scheduler`` and ``dask worker
ADDRESS --nthreads 1`` on machines that have can_seeker, with nannies, the default).
"""
import json
import logging
import os
import socket
import sys
import tempfile
from dataclasses import dataclass
from typing import Callable, Dict, Optional, Sequence, Tuple

import dask
import rospy
from distributed import Client, LocalCluster, as_completed
from distributed.diagnostics.plugin import WorkerPlugin
from tqdm import tqdm

from can_seeker.evaluation.batch import TrialLedger, write_json_atomically
from can_seeker.evaluation.cpu_features import narrow_kernel_environment, numpy_features_to_disable
from can_seeker.evaluation.process_cpu import TreeCpu
from can_seeker.evaluation.trials import Criteria, TrialResult
from can_seeker.tools.closed_loop import LaunchedSystem, TrialRunner

WORKER_LOSSES_PER_TRIAL = 3
"""How many worker processes a trial may lose (killed with it, or its system failing) before
it counts as failed: the local cluster's ``allowed-failures`` (a running scheduler has its own,
3 unless configured otherwise)."""
SYSTEM_FAILED_EXIT_CODE = 3
"""Exit status of a worker process that left because its ROS system failed."""
RESTART_TIMEOUT_S = 120.0
"""Time for every worker process to close its system and come back, also the time a local
cluster waits for a lost worker to come back before it gives its nanny up (a worker process
needs 20 s and more to start on a busy machine: Dask's default of 15 s closed nannies that
were restarting)."""
PLUGIN_NAME = 'can_seeker_ros_system'
LOGGER = logging.getLogger('can_seeker.engine')


@dataclass(frozen=True)
class SystemSpec:
    """What a worker's ROS system is started with: demo.launch arguments, ``/node/param``
    overrides, the trials' sim time limit (s), and a run number that tells two otherwise equal
    runs apart (each run gets fresh systems). ``wide_kernels`` False: every node runs without
    numpy's wide SIMD kernels that the worker's CPU has (see
    :mod:`can_seeker.evaluation.cpu_features`). ``log_dir``: where each system's roslaunch
    output goes (None: the worker's temp folder)."""

    launch_args: Tuple[Tuple[str, str], ...]
    params: Tuple[Tuple[str, str], ...]
    time_limit_s: float
    run: int = 0
    log_dir: Optional[str] = None
    wide_kernels: bool = True

    @classmethod
    def of(cls, launch_args: Dict[str, object], params: Dict[str, object], time_limit_s: float,
           run: int = 0, log_dir: Optional[str] = None,
           wide_kernels: bool = True) -> 'SystemSpec':
        return cls(tuple(sorted((name, str(value)) for name, value in launch_args.items())),
                   tuple(sorted((name, str(value)) for name, value in params.items())),
                   float(time_limit_s), run, log_dir, wide_kernels)

    def key(self) -> str:
        """The system's identity (the log folder does not change the system)."""
        return json.dumps([self.launch_args, self.params, self.time_limit_s, self.run,
                           self.wide_kernels])

    def environment(self) -> Dict[str, str]:
        """The environment variables a worker adds for its system's nodes (computed on the
        worker: its CPU decides which wide kernels there are to turn off)."""
        if self.wide_kernels:
            return {}
        return narrow_kernel_environment(numpy_features_to_disable())


class WorkerSystem:
    """The ROS system of this worker process: the launch, the rospy node, the trial runner."""

    def __init__(self, spec: SystemSpec):
        self.key = spec.key()
        log_dir = spec.log_dir or tempfile.gettempdir()
        os.makedirs(log_dir, exist_ok=True)
        log_path = os.path.join(log_dir, 'can_seeker_evaluate_%s_%d.log'
                                % (socket.gethostname(), os.getpid()))
        self.launch = LaunchedSystem(dict(spec.launch_args), log_path, params=dict(spec.params),
                                     env=spec.environment())
        self.launch.__enter__()
        rospy.init_node('evaluate', disable_signals=True)
        self.launch.wait_for_services()
        self.criteria = Criteria(stop_distance_m=rospy.get_param('can_stopper/stop_distance'),
                                 time_limit_s=spec.time_limit_s,
                                 robot_radius_m=rospy.get_param('can_stopper/robot_radius'))
        self.runner = TrialRunner(self.criteria)

    def close(self):
        rospy.signal_shutdown('evaluation done')
        self.launch.__exit__(None, None, None)


_system: Optional[WorkerSystem] = None
"""This worker process's system, started by its first trial."""
_system_closed = False
"""Whether this process's system was shut down (rospy cannot start another node here)."""


def _worker_system(spec: SystemSpec) -> WorkerSystem:
    global _system
    if _system_closed:
        raise RuntimeError('this worker process has shut its ROS system down')
    if _system is None:
        _system = WorkerSystem(spec)
    elif _system.key != spec.key():
        raise RuntimeError('this worker process runs the ROS system of another evaluation; '
                           'one evaluation at a time per cluster')
    return _system


def close_worker_system():
    """Shut this process's system down (if it has one)."""
    global _system, _system_closed
    _system_closed = True
    if _system is not None:
        system, _system = _system, None
        system.close()


def run_trial(spec: SystemSpec, seed: int, index: int) -> Tuple[TrialResult, Criteria]:
    """Trial ``index`` in the world of ``seed`` + ``index`` on this worker's system (a task).

    If the system fails, it is shut down and the process leaves: its nanny starts a fresh one
    and the scheduler runs the trial again like any lost worker's.
    """
    try:
        system = _worker_system(spec)
        can_xy, visible = system.runner.new_world(seed + index)
        return system.runner.run(index, can_xy, visible), system.criteria
    except Exception:
        LOGGER.exception('trial %d (seed %d): the ROS system failed; this worker process '
                         'leaves and the trial runs again elsewhere', index, seed + index)
        close_worker_system()
        logging.shutdown()
        os._exit(SYSTEM_FAILED_EXIT_CODE)


class SystemShutdown(WorkerPlugin):
    """Shuts the worker's ROS system down when the worker closes."""

    def teardown(self, worker):
        close_worker_system()


def worker_system_key() -> Optional[str]:
    """The key of this worker process's system, None before its first trial (run on every
    worker)."""
    return None if _system is None else _system.key


class Engine:
    """A Dask client on a local cluster of ``jobs`` worker processes (one thread each), or on
    the scheduler at ``address``. A context manager: on exit the client (and a local cluster
    with its workers and their systems) is closed.

    ``sim_s`` sums the sim time of the trials it ran; on a local cluster ``cpu_s`` is, after
    the exit, the CPU time of this process (from its start) and of every process below it
    (scheduler, nannies, workers, their ROS systems), from start-up to shutdown."""

    def __init__(self, jobs: int = 1, address: Optional[str] = None):
        self.jobs = jobs
        self.address = address
        self.config = None
        self.cluster = None
        self.client = None
        self.sim_s = 0.0
        self.cpu_s = None
        self._tree_cpu = None

    @property
    def real_time_per_core(self) -> Optional[float]:
        """Sim seconds of the trials per CPU second of the whole batch (local cluster, after
        the exit); None otherwise."""
        return self.sim_s / self.cpu_s if self.cpu_s else None

    def cpu_so_far(self) -> Optional[float]:
        """CPU seconds of every process of the batch since the start, now (local cluster
        inside the context only; None otherwise)."""
        return None if self._tree_cpu is None else self._tree_cpu.read()

    def __enter__(self):
        if not self.address:
            self._tree_cpu = TreeCpu()
        if self.address:
            self.client = Client(self.address)
        else:
            self.config = dask.config.set({
                'distributed.scheduler.allowed-failures': WORKER_LOSSES_PER_TRIAL,
                'distributed.deploy.lost-worker-timeout': '%gs' % RESTART_TIMEOUT_S})
            self.cluster = LocalCluster(n_workers=self.jobs, threads_per_worker=1,
                                        processes=True, dashboard_address=None,
                                        silence_logs=logging.ERROR)
            self.client = Client(self.cluster)
        self.client.register_worker_plugin(SystemShutdown(), name=PLUGIN_NAME)
        return self

    def __exit__(self, *exc_info):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        if self.config is not None:
            self.config.__exit__(None, None, None)
        if self._tree_cpu is not None:
            self.cpu_s, self._tree_cpu = self._tree_cpu.stop(), None

    def worker_pids(self) -> Dict[str, int]:
        """Each worker's process id by its address."""
        return self.client.run(os.getpid)

    def _fresh_workers_for(self, spec: SystemSpec):
        """Restart the worker processes unless every one is fresh or already runs ``spec``."""
        keys = set(self.client.run(worker_system_key).values()) - {None}
        if keys - {spec.key()}:
            self.client.restart(timeout=RESTART_TIMEOUT_S)

    def run(self, spec: SystemSpec, seed: int, indices: Sequence[int],
            on_result: Callable[[TrialResult, Criteria], None], description: str = 'trials'):
        """Run the trials ``indices`` of the world seeds from ``seed`` on systems of ``spec``;
        ``on_result(result, criteria)`` for each as it finishes, under one progress bar. A trial
        that failed on every try is reported on stderr and left out. The indices that failed."""
        self._fresh_workers_for(spec)
        futures = {self.client.submit(run_trial, spec, seed, index, pure=False,
                                      priority=-index): index for index in indices}
        failed = []
        successes = finished = 0
        with tqdm(total=len(futures), desc=description, unit='trial', file=sys.stderr) as bar:
            for future in as_completed(futures):
                index = futures[future]
                if future.status == 'error':
                    failed.append(index)
                    tqdm.write('trial %d (seed %d) did not run: %s'
                               % (index, seed + index, future.exception()), file=sys.stderr)
                else:
                    result, criteria = future.result()
                    self.sim_s += result.sim_s
                    on_result(result, criteria)
                    successes += result.success
                finished += 1
                bar.update()
                bar.set_postfix(ok='%d/%d' % (successes, finished))
                future.release()
        return sorted(failed)


def failure_text(result: TrialResult, seed: int) -> str:
    """The line that reports a failed trial: where its can was and how it ended."""
    return ('trial %d (seed %d) failed: can at (%.2f, %.2f)%s, stopped=%s, gap %.3f m, '
            'bearing %.2f deg, contact=%s'
            % (result.index, seed + result.index, result.can_x_m, result.can_y_m,
               '' if result.can_visible_from_start is not False
               else ' (not visible from the start)', result.stopped, result.gap_m,
               result.bearing_deg, result.contact_text()))


def run_missing(engine: Engine, spec: SystemSpec, ledger: TrialLedger,
                json_path: Optional[str] = None, description: str = 'trials'):
    """Run the trials ``ledger`` is missing (seeds from ``ledger.settings['seed']``) on the
    engine, adding each to it as it finishes and, with ``json_path``, writing its record there
    after every trial (a crash or Ctrl-C loses no finished trial). The indices that did not
    run."""
    seed = ledger.settings['seed']

    def finished(result, criteria):
        ledger.add(result, criteria)
        if not result.success:
            tqdm.write(failure_text(result, seed), file=sys.stderr)
        if json_path:
            write_json_atomically(json_path, ledger.record())

    return engine.run(spec, seed, ledger.missing(), finished, description)
