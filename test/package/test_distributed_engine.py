"""The distributed engine on a real local Dask cluster, each worker process with its full ROS
system (master, simulator, vision, controller): four short lockstep trials (empty world, can
0.5-0.6 m ahead) on two worker processes, one of them killed while it runs a trial, end with
all four in the JSON record, each with the outcome and final pose (within 1 mm and 0.1 deg) of
the same trial run in one worker process; the killed worker's ROS system is gone with it and
its nanny has started a fresh worker.
"""
import json
import os
import signal
import threading
import time

import rosgraph

from can_seeker.evaluation.batch import TrialLedger, compare_runs
from can_seeker.evaluation.trials import TrialResult
from can_seeker.tools.engine import Engine, SystemSpec, run_missing

SETTINGS = {'trials': 4, 'seed': 40}
SPEC = SystemSpec.of({'world': 'empty', 'can_min_distance': 0.5, 'can_max_distance': 0.6,
                      'lockstep': 'true', 'real_time_factor': 0.0}, {}, 90.0)
KILL_TIMEOUT_S = 600.0


def master_uri():
    """This process's ROS master (run on a worker: its own system's)."""
    return os.environ['ROS_MASTER_URI']


class WorkerKiller(threading.Thread):
    """Once the first trial is in the record, kills (SIGKILL) a worker process that is running
    a trial; remembers its process id and its system's master."""

    def __init__(self, engine, json_path):
        super().__init__(daemon=True)
        self.engine = engine
        self.json_path = json_path
        self.killed_pid = None
        self.killed_master_uri = None

    def run(self):
        deadline = time.monotonic() + KILL_TIMEOUT_S
        while time.monotonic() < deadline:
            busy = [address for address, keys in self.engine.client.processing().items()
                    if keys]
            if os.path.exists(self.json_path) and busy:
                pids = self.engine.worker_pids()
                self.killed_master_uri = self.engine.client.run(
                    master_uri, workers=busy[:1])[busy[0]]
                self.killed_pid = pids[busy[0]]
                os.kill(self.killed_pid, signal.SIGKILL)
                return
            time.sleep(0.2)


def test_trials_on_two_workers_one_killed_match_one_worker_and_lose_nothing(tmp_path):
    one_worker = TrialLedger(SETTINGS)
    with Engine(jobs=1) as engine:
        assert run_missing(engine, SPEC, one_worker) == []

    json_path = str(tmp_path / 'evaluate.json')
    with Engine(jobs=2) as engine:
        killer = WorkerKiller(engine, json_path)
        killer.start()
        not_run = run_missing(engine, SPEC, TrialLedger(SETTINGS), json_path)
        killer.join()
        workers_after = engine.worker_pids()

    assert not_run == []
    assert killer.killed_pid is not None, 'no worker was running a trial after the first'
    assert len(workers_after) == 2 and killer.killed_pid not in workers_after.values()
    assert not rosgraph.Master('/test', master_uri=killer.killed_master_uri).is_online()
    with open(json_path) as stored:
        record = json.load(stored)
    assert [trial['index'] for trial in record['trials']] == [0, 1, 2, 3]
    two_workers = [TrialResult.from_dict(fields) for fields in record['trials']]
    comparison = compare_runs(one_worker.results(), two_workers)
    assert comparison['repeatable'], comparison
