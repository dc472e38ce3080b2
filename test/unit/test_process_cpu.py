"""The CPU time of a process tree counts the children and grandchildren, also those that ended
before the end, and not what ran before the start."""
import subprocess
import sys
import time

from can_seeker.evaluation.process_cpu import TreeCpu, process_table, tree

BURN = ('import time\nend = time.process_time() + %f\n'
        'while time.process_time() < end:\n    pass\n')


def burn(seconds):
    return [sys.executable, '-c', BURN % seconds]


def test_tree_cpu_counts_children_and_grandchildren_that_ended():
    meter = TreeCpu(interval_s=0.05, include_root_past=False)
    # A child that burns 0.4 s and a grandchild (started by a shell) that burns 0.4 s.
    subprocess.run(burn(0.4), check=True)
    subprocess.run(['sh', '-c', '"$0" -c "$1"; true', sys.executable, BURN % 0.4], check=True)
    total_s = meter.stop()
    assert 0.75 < total_s < 2.0


def test_tree_cpu_of_another_root_sees_its_live_descendants():
    parent = subprocess.Popen(['sh', '-c', '"$0" -c "$1"', sys.executable, BURN % 0.5])
    meter = TreeCpu(parent.pid, interval_s=0.05)
    # The shell starts its child when the scheduler lets it, late on a loaded machine.
    deadline = time.monotonic() + 10.0
    while len(tree(process_table(), parent.pid)) < 2 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert len(tree(process_table(), parent.pid)) == 2
    parent.wait()
    total_s = meter.stop()
    assert 0.2 < total_s < 1.5


def test_time_before_the_start_does_not_count_unless_asked():
    end = time.process_time() + 0.3
    while time.process_time() < end:
        pass
    assert TreeCpu(interval_s=0.05, include_root_past=False).stop() < 0.2
    assert TreeCpu(interval_s=0.05).stop() >= 0.3


def test_a_reading_on_the_way_counts_what_ran_so_far():
    """A sweep's per-setting cost is the difference of two readings of one meter."""
    meter = TreeCpu(interval_s=0.05, include_root_past=False)
    subprocess.run(burn(0.3), check=True)
    first_s = meter.read()
    subprocess.run(burn(0.3), check=True)
    total_s = meter.stop()
    assert 0.25 < first_s < 1.0
    assert 0.25 < total_s - first_s < 1.0
