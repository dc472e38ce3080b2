"""CPU time of a process tree: a process and everything it started, also the processes that
ended (or left the tree) before the end, read from /proc.

A thread samples the tree every ``interval_s``: each process's own user + system time (all its
threads) as last seen, per process (its id and start time, so a reused id is another process).
The total at :meth:`TreeCpu.stop` is the sum of the last samples, or, when larger, the root's
own time plus that of the children it reaped (which holds every descendant reaped along an
unbroken chain, however short-lived). Either is a lower bound: a process that ended between two
samples and was not reaped along the chain loses at most one interval of its time.
"""
import os
import threading
from typing import Dict, Tuple

CLOCK_TICKS_PER_S = os.sysconf('SC_CLK_TCK')


def _stat_fields(pid: int):
    with open('/proc/%d/stat' % pid) as stat:
        return stat.read().rsplit(')', 1)[1].split()


def process_table() -> Dict[int, Tuple[int, int, float]]:
    """{pid: (parent pid, start time in clock ticks, own user + system CPU s)} of every
    process now."""
    table = {}
    for entry in os.listdir('/proc'):
        if not entry.isdigit():
            continue
        try:
            fields = _stat_fields(int(entry))
        except (OSError, IndexError):
            continue
        table[int(entry)] = (int(fields[1]), int(fields[19]),
                             (int(fields[11]) + int(fields[12])) / CLOCK_TICKS_PER_S)
    return table


def tree(table: Dict[int, Tuple[int, int, float]], root_pid: int):
    """The pids of ``root_pid`` and its descendants in ``table``."""
    children = {}
    for pid, (parent, _, _) in table.items():
        children.setdefault(parent, []).append(pid)
    found, todo = [], [root_pid]
    while todo:
        pid = todo.pop()
        if pid in table:
            found.append(pid)
            todo.extend(children.get(pid, ()))
    return found


class TreeCpu:
    """CPU seconds of the tree below ``root_pid`` (default: this process) from now until
    :meth:`stop`; with ``include_root_past`` the root's own time before the start counts too
    (a command's whole cost, its start-up included)."""

    def __init__(self, root_pid: int = None, interval_s: float = 0.5,
                 include_root_past: bool = True):
        self.root_pid = os.getpid() if root_pid is None else root_pid
        self.interval_s = interval_s
        self._last: Dict[Tuple[int, int], float] = {}
        self._stop = threading.Event()
        table = process_table()
        self._at_start = {(pid, table[pid][1]): table[pid][2]
                          for pid in tree(table, self.root_pid)}
        if include_root_past:
            self._at_start[(self.root_pid, table[self.root_pid][1])] = 0.0
        self._children_at_start = self._reaped_children_s()
        self._thread = threading.Thread(target=self._run, name='tree_cpu', daemon=True)
        self._thread.start()

    def _reaped_children_s(self) -> float:
        if self.root_pid != os.getpid():
            return 0.0
        times = os.times()
        return times.children_user + times.children_system

    def _sample(self):
        table = process_table()
        for pid in tree(table, self.root_pid):
            self._last[(pid, table[pid][1])] = table[pid][2]

    def _run(self):
        while not self._stop.wait(self.interval_s):
            self._sample()

    def stop(self) -> float:
        """Stop sampling; the CPU seconds of the tree since the start."""
        self._stop.set()
        self._thread.join()
        return self.read()

    def read(self) -> float:
        """The CPU seconds of the tree since the start, sampled now (sampling goes on)."""
        self._sample()
        sampled_s = sum(cpu_s - self._at_start.get(key, 0.0) for key, cpu_s in self._last.items())
        root_keys = [key for key in self._last if key[0] == self.root_pid]
        if not root_keys:
            return sampled_s
        reaped_s = (self._last[root_keys[0]] - self._at_start.get(root_keys[0], 0.0)
                    + self._reaped_children_s() - self._children_at_start)
        return max(sampled_s, reaped_s)
