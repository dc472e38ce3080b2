"""bench_loop: where the closed loop's CPU goes, per simulated second, in lockstep.

Runs lockstep trials as ``evaluate`` does (the same demo.launch arguments, its own master, the
same trial runner: a new world per seed, the atomic start, STOPPED or the time limit) and reads
the CPU time (user + system, /proc/<pid>/stat, all threads) of every process of the loop over
the trials: rosmaster, roslaunch, rosout, sim, image_converter, obstacle_scan, can_stopper and
this process (the evaluator, with its ground-truth subscribers and service calls). The window
starts once the system is live (every node up, the controller commanding) and ends after the
last trial, so start-up is left out but the new worlds and resets between trials count.

"x real time per core" = sim seconds / CPU seconds of all the loop's processes together: how
many times faster than real time the loop would run on one core of its own (wall time depends
on the machine's other load; CPU time much less so). ``--py-spy DIR`` samples every Python
process of the loop with py-spy (if on PATH) over the same window and writes a flame graph per
process. ``--result FILE`` writes the figures as a result file for docs/results/.

``--realism ideal realistic`` measures each preset in turn, each on a system of its own (a
bench_loop process per preset: rospy has one node per process), and prints the presets' CPU per
sim second side by side. The other ``evaluate`` options (``--scan-topics``, ``--param``...)
pass through to every preset's run.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import rospy

from can_seeker.evaluation.result_files import command_line, result_record, write_result
from can_seeker.evaluation.trials import Criteria
from can_seeker.sim.realism import REALISM_PRESETS
from can_seeker.tools.closed_loop import LIVE_TIMEOUT_S, LaunchedSystem, TrialRunner
from can_seeker.tools.evaluate import launch_args, parse_args

CLOCK_TICKS_PER_S = os.sysconf('SC_CLK_TCK')
LOOP_PROCESSES = ('rosmaster', 'roslaunch', 'rosout', 'sim', 'image_converter', 'obstacle_scan',
                  'can_stopper')
"""The loop's processes in the order they are printed (then the evaluator, then others)."""
EVALUATOR = 'evaluator (this process)'
THREAD_LINE = re.compile(r'^thread \((\d+)\): ([^;]*);')


def cpu_seconds(pid):
    """User and system CPU time (s) of process ``pid`` (all its threads, also ended ones)."""
    with open('/proc/%d/stat' % pid) as stat:
        fields = stat.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS_PER_S


def thread_cpu_seconds(pid):
    """{thread id: user + system CPU s} of the live threads of process ``pid``."""
    times = {}
    for tid in os.listdir('/proc/%d/task' % pid):
        try:
            with open('/proc/%d/task/%s/stat' % (pid, tid)) as stat:
                fields = stat.read().rsplit(')', 1)[1].split()
        except OSError:
            continue
        times[int(tid)] = (int(fields[11]) + int(fields[12])) / CLOCK_TICKS_PER_S
    return times


def _parent(pid):
    with open('/proc/%d/stat' % pid) as stat:
        return int(stat.read().rsplit(')', 1)[1].split()[1])


def process_name(pid):
    """A short name of a loop process: its ROS node name (``__name:=``), else its program."""
    with open('/proc/%d/cmdline' % pid, 'rb') as cmdline:
        argv = [part.decode(errors='replace') for part in cmdline.read().split(b'\0') if part]
    for part in argv:
        if part.startswith('__name:='):
            return part.split(':=', 1)[1]
    programs = [os.path.basename(part) for part in argv[:2]]
    for known in ('rosmaster', 'roslaunch', 'rosout'):
        if known in programs:
            return known
    return programs[-1] if programs else str(pid)


def descendants(root_pid):
    """Process ids of ``root_pid`` and every process below it."""
    children = {}
    for entry in os.listdir('/proc'):
        if entry.isdigit():
            try:
                children.setdefault(_parent(int(entry)), []).append(int(entry))
            except (OSError, IndexError, ValueError):
                continue
    found, todo = [], [root_pid]
    while todo:
        pid = todo.pop()
        found.append(pid)
        todo.extend(children.get(pid, ()))
    return found


def loop_processes(launch_pid):
    """{name: pid} of the launch's processes and this one."""
    processes = {EVALUATOR: os.getpid()}
    for pid in descendants(launch_pid):
        try:
            name = process_name(pid)
        except OSError:
            continue
        if name in processes:
            name = '%s (%d)' % (name, pid)
        processes[name] = pid
    return processes


def sample(processes):
    """{name: CPU s} now (a process that has gone keeps no entry)."""
    times = {}
    for name, pid in processes.items():
        try:
            times[name] = cpu_seconds(pid)
        except OSError:
            continue
    return times


def cpu_used(before, after):
    """{process: CPU s between the samples} in the printed order: the loop's processes, the
    evaluator, then any others by name."""
    used = {name: after[name] - before[name] for name in after if name in before}
    order = ([name for name in LOOP_PROCESSES if name in used] + [EVALUATOR]
             + sorted(name for name in used if name not in LOOP_PROCESSES + (EVALUATOR,)))
    return {name: used[name] for name in order}


def breakdown_table(sim_s, before, after):
    """Markdown table: CPU s and CPU ms per sim s of each process, its share, the total, and
    sim s per CPU s."""
    used = cpu_used(before, after)
    total_s = sum(used.values())
    lines = ['| process | CPU s | CPU ms per sim s | share |', '|---|---|---|---|']
    for name in used:
        lines.append('| %s | %.2f | %.0f | %.1f %% |' % (name, used[name], 1000.0 * used[name]
                                                        / sim_s, 100.0 * used[name] / total_s))
    lines.append('| **total** | **%.2f** | **%.0f** | 100 %% |' % (total_s,
                                                                 1000.0 * total_s / sim_s))
    return '\n'.join(lines), total_s


class PySpy:
    """``py-spy record`` on each Python process of the loop until :meth:`stop`; also the CPU
    time of each thread over the same time, named as py-spy names them (Python thread names:
    a rospy subscriber's receiving thread is named after its topic)."""

    def __init__(self, processes, folder):
        self.recorders = []
        self.folder = folder
        self.processes = processes
        self.threads_before = self._thread_times()
        os.makedirs(folder, exist_ok=True)
        executable = shutil.which('py-spy')
        if executable is None:
            print('bench_loop: py-spy is not on PATH; no profiles', file=sys.stderr)
            return
        for name, pid in processes.items():
            if pid == os.getpid():
                continue
            path = os.path.join(folder, '%s.txt' % name.split()[0])
            self.recorders.append(subprocess.Popen(
                [executable, 'record', '--pid', str(pid), '--rate', '200', '--nonblocking',
                 '--threads', '--format', 'raw', '--output', path],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL))

    def _thread_times(self):
        times = {}
        for name, pid in self.processes.items():
            try:
                times.update({(name, tid): cpu_s for tid, cpu_s
                              in thread_cpu_seconds(pid).items()})
            except OSError:
                continue
        return times

    def thread_names(self):
        """{thread id: Python thread name} from the recorded stacks."""
        names = {}
        for entry in os.listdir(self.folder):
            if entry.endswith('.txt') and entry != 'threads.txt':
                with open(os.path.join(self.folder, entry)) as stacks:
                    for line in stacks:
                        match = THREAD_LINE.match(line)
                        if match:
                            names[int(match.group(1))] = match.group(2)
        return names

    def stop(self):
        """Stop the recorders; write DIR/threads.txt, each thread's CPU s over the window,
        most first."""
        threads_after = self._thread_times()
        for recorder in self.recorders:
            recorder.send_signal(signal.SIGINT)
        for recorder in self.recorders:
            try:
                recorder.wait(60.0)
            except subprocess.TimeoutExpired:
                recorder.kill()
                recorder.wait()
        names = self.thread_names()
        used = sorted(((cpu_s - self.threads_before.get(key, 0.0), key)
                       for key, cpu_s in threads_after.items()), reverse=True)
        with open(os.path.join(self.folder, 'threads.txt'), 'w') as output:
            for cpu_s, (process, tid) in used:
                output.write('%8.2f  %-26s %7d  %s\n' % (cpu_s, process, tid,
                                                        names.get(tid, '?')))


def run_presets(presets, args, evaluate_argv):
    """Measure each preset in a bench_loop process of its own (rospy has one node per process,
    each preset its own master) and print them side by side; the exit status."""
    folder = tempfile.mkdtemp(prefix='bench_loop_')
    measurements = []
    for preset in presets:
        path = (result_path(args.result, preset, presets) if args.result
                else os.path.join(folder, '%s.json' % preset))
        child_argv = ['--trials', str(args.trials), '--seed', str(args.seed), '--realism', preset,
                      '--result', path]
        if args.py_spy:
            child_argv += ['--py-spy', os.path.join(args.py_spy, preset)]
        if args.log:
            child_argv += ['--log', result_path(args.log, preset, presets)]
        status = subprocess.call([sys.executable, '-m', 'can_seeker.tools.bench_loop']
                                 + child_argv + evaluate_argv)
        if status != 0:
            print('bench_loop: the %s run failed (exit status %d)' % (preset, status),
                  file=sys.stderr)
            return status
        with open(path) as record:
            measurements.append((preset, json.load(record)['figures']))
    print(side_by_side_table(measurements))
    return 0


def side_by_side_table(measurements):
    """Markdown table from [(preset, result figures)]: CPU ms per sim s of each process under
    each preset, the totals and the x real time per core."""
    names = []
    for _, figures in measurements:
        names += [name for name in figures['cpu_ms_per_sim_s'] if name not in names]
    lines = ['| CPU ms per sim s | %s |' % ' | '.join(preset for preset, _ in measurements),
             '|---' * (len(measurements) + 1) + '|']
    for name in names:
        lines.append('| %s | %s |' % (name, ' | '.join(
            '%.0f' % figures['cpu_ms_per_sim_s'][name] if name in figures['cpu_ms_per_sim_s']
            else '' for _, figures in measurements)))
    lines.append('| **total** | %s |' % ' | '.join(
        '**%.0f**' % figures['cpu_ms_per_sim_s_total'] for _, figures in measurements))
    lines.append('| **x real time per core** | %s |' % ' | '.join(
        '**%.2f**' % figures['real_time_per_core'] for _, figures in measurements))
    lines.append('| successes | %s |' % ' | '.join(
        '%d/%d' % (figures['successes'], figures['trials']) for _, figures in measurements))
    return '\n'.join(lines)


def result_path(path, preset, presets):
    """Where the file of ``preset`` goes: ``path`` itself for a single preset, else ``path``
    with ``-PRESET`` before its extension."""
    if len(presets) == 1:
        return path
    stem, extension = os.path.splitext(path)
    return '%s-%s%s' % (stem, preset, extension)


def main(argv=None):
    """Run the trials under each realism preset and print the CPU breakdown per process."""
    parser = argparse.ArgumentParser(prog='bench_loop', description=__doc__.splitlines()[0])
    parser.add_argument('--trials', type=int, default=3, help='lockstep trials')
    parser.add_argument('--seed', type=int, default=1000, help='seed of the first trial')
    parser.add_argument('--realism', nargs='+', action='extend', choices=REALISM_PRESETS,
                        metavar='PRESET', help='realism presets to measure one after the other '
                        '(a list, or repeated: --realism ideal realistic), then printed side by '
                        'side (default: ideal)')
    parser.add_argument('--py-spy', metavar='DIR', help='write py-spy\'s collapsed stacks of '
                        'each Python process of the loop to DIR/<process>.txt (DIR/PRESET/ with '
                        'several presets)')
    parser.add_argument('--log', help='roslaunch output (default: a temporary file; LOG-PRESET '
                        'with several presets)')
    parser.add_argument('--result', metavar='FILE', help='write the figures with this command, '
                        'the commit and the machine as a result file (docs/results/NAME.json; '
                        'NAME-PRESET.json for each of several presets)')
    command_argv = rospy.myargv(argv if argv is not None else sys.argv)[1:]
    args, evaluate_argv = parser.parse_known_args(command_argv)
    presets = list(dict.fromkeys(args.realism or ['ideal']))
    options = parse_args(['--world', 'room'] + evaluate_argv + ['--trials', str(args.trials),
                                                                '--seed', str(args.seed),
                                                                '--realism', presets[0]])
    if not options.lockstep:
        parser.error('bench_loop measures the lockstep loop')
    if len(presets) > 1:
        sys.exit(run_presets(presets, args, evaluate_argv))
    log_path = args.log or tempfile.mkstemp(prefix='bench_loop_', suffix='.log')[1]
    with LaunchedSystem(launch_args(options), log_path, params=dict(options.param)) as launch:
        rospy.init_node('bench_loop', disable_signals=True)
        launch.wait_for_services()
        criteria = Criteria(stop_distance_m=rospy.get_param('can_stopper/stop_distance'),
                            time_limit_s=options.time_limit)
        runner = TrialRunner(criteria)
        runner.monitor.wait_until_live(LIVE_TIMEOUT_S)
        processes = loop_processes(launch.process.pid)
        profiler = PySpy(processes, args.py_spy) if args.py_spy else None
        load_before = os.getloadavg()
        before, wall_start_s = sample(processes), time.monotonic()
        results = []
        for index in range(options.trials):
            can_xy, visible = runner.new_world(options.seed + index)
            results.append(runner.run(index, can_xy, visible))
        after, wall_s = sample(processes), time.monotonic() - wall_start_s
        load_after = os.getloadavg()
        if profiler is not None:
            profiler.stop()
        rospy.signal_shutdown('benchmark done')
    sim_s = sum(result.sim_s for result in results)
    table, total_s = breakdown_table(sim_s, before, after)
    print('bench_loop: %d lockstep trials, %s world, seeds %d-%d, %dx%d camera, realism %s, '
          'scan topics %s, %d cores'
          % (len(results), options.world, options.seed, options.seed + options.trials - 1,
             options.width, options.height, options.realism, options.scan_topics or 'none',
             os.cpu_count()))
    for result in results:
        print('  trial %d (seed %d): %s, %.2f sim s, final pose (%.4f, %.4f) m, %.3f deg'
              % (result.index, options.seed + result.index,
                 'success' if result.success else 'FAILED', result.sim_s, result.final_x_m,
                 result.final_y_m, result.final_yaw_deg))
    print('sim time %.2f s, wall time %.1f s (%.2fx real time on this machine now), load '
          'average %.1f before, %.1f after\n' % (sim_s, wall_s, sim_s / wall_s,
                                                 load_before[0], load_after[0]))
    print(table)
    print('\n%.2fx real time per core: %.2f sim s per %.2f CPU s of the whole loop\n'
          % (sim_s / total_s, sim_s, total_s), flush=True)
    if profiler is not None:
        print('py-spy stacks in %s' % args.py_spy)
    if args.result:
        used = cpu_used(before, after)
        write_result(args.result, result_record('bench_loop', command_line('bench_loop',
                                                                           command_argv), {
            'realism': options.realism, 'scan_topics': options.scan_topics,
            'trials': len(results), 'successes': sum(result.success for result in results),
            'sim_s': sim_s, 'wall_s': wall_s, 'cpu_s_total': total_s,
            'cpu_ms_per_sim_s': {name: 1000.0 * cpu_s / sim_s for name, cpu_s in used.items()},
            'cpu_ms_per_sim_s_total': 1000.0 * total_s / sim_s,
            'real_time_per_core': sim_s / total_s, 'real_time_wall': sim_s / wall_s,
            'load_average_before': load_before[0], 'load_average_after': load_after[0]}))
        print('result written to %s' % args.result, flush=True)


if __name__ == '__main__':
    main()
