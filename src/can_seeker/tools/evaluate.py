"""evaluate: N closed-loop trials of the real nodes (sim, image_converter, obstacle_scan,
can_stopper) under their own master, judged on the simulator's ground truth.

The nodes start once per worker process (``demo.launch`` on a free port); trial i rebuilds the
world of seed S+i and starts atomically through the simulator's and the controller's reset
services. Options choose the world (``--world``, ``--randomize-appearance``,
``--randomize-mount``, ``--robot``), the senses (``--realism``, ``--scan-topics``), any node
parameter (``--param``), a sweep over settings (``--sweep``), where the trials run (``--jobs``,
``--cluster``: every trial a Dask task, each worker with a ROS system of its own), second runs
that compare final poses (``--repeat-check``, ``--cpu-features-check``), a comparison with an
earlier record of the same trials (``--compare-with``: before and after a change), and the records
(``--json`` after every trial, ``--resume``, ``--result`` for docs/results/). Prints a summary
table; exits 1 when a trial failed. All options: docs/tools.md.
"""
import argparse
import json
import os
import sys

import rospy

from can_seeker.tools.engine import Engine, SystemSpec, run_missing
from can_seeker.camera_mount import RANDOM_HEIGHT_RANGE_M, RANDOM_PITCH_RANGE_DEG
from can_seeker.params import defaults
from can_seeker.control.controller import PARAMS as CONTROL_PARAMS
from can_seeker.sim.realism import REALISM_PRESETS
from can_seeker.sim.simulation import PARAMS as SIM_PARAMS
from can_seeker.sim.world import CAN_TEXTURES
from can_seeker.evaluation.batch import (REPEAT_POSITION_TOLERANCE_M, REPEAT_YAW_TOLERANCE_DEG,
                                         TrialLedger, compare_runs, write_json_atomically)
from can_seeker.evaluation.cpu_features import (DISABLE_VARIABLE, NOTHING_TO_DISABLE, describe,
                                                numpy_features_to_disable)
from can_seeker.evaluation.result_files import command_line, result_record, write_result
from can_seeker.evaluation.sweep import (override_arg, parse_sweep, plot_sweep,
                                         setting_label, sweep_grid, sweep_table)
from can_seeker.evaluation.trials import Criteria, json_ready, summary_table
from can_seeker.output_paths import default_output_dir
from can_seeker.robot_profile import ProfileError, load_profile

SIM = defaults(SIM_PARAMS)
CONTROL = defaults(CONTROL_PARAMS)
WORLD_OPTIONS = ('world', 'obstacles', 'room_size', 'floor_rgba', 'wall_rgba', 'obstacle_rgba',
                 'can_texture', 'realism')
CONTROL_OPTIONS = ('scan_topics',)
REFERENCE_SPEED_MPS = 0.4
"""Top speed the default time limit is meant for (can_stopper's default ~max_linear)."""
LOCKSTEP_CLOCK_RATE_HZ = 50.0
"""/clock in lockstep (Hz, sim time): at every physics step (240 Hz) it cost more CPU than the
detector, every node receiving and handling each tick; the nodes' timers need no finer clock."""


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog='evaluate', description=__doc__.split('\n\n')[0],
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument('--trials', type=int, default=50, help='number of trials')
    parser.add_argument('--seed', type=int, default=0, help='seed of the first can placement')
    parser.add_argument('--min-distance', type=float, default=SIM.can_min_distance,
                        help='nearest can centre from the robot start (m)')
    parser.add_argument('--max-distance', type=float, default=SIM.can_max_distance,
                        help='farthest can centre from the robot start (m)')
    parser.add_argument('--width', type=int, default=SIM.width, help='image width (px)')
    parser.add_argument('--height', type=int, default=SIM.height, help='image height (px)')
    parser.add_argument('--camera-height', type=float, default=SIM.camera_height,
                        help='camera height above the floor (m)')
    parser.add_argument('--camera-pitch', type=float, default=SIM.camera_pitch_deg,
                        help='camera pitch below the horizon (deg)')
    parser.add_argument('--can-rgba', default=SIM.can_rgba,
                        help='can colour: red green blue alpha in 0-1')
    parser.add_argument('--can-texture', default=SIM.can_texture, choices=CAN_TEXTURES,
                        help='textured soda can or plain red')
    parser.add_argument('--world', default=SIM.world,
                        help='empty, room or a YAML world file (a path or a name in worlds/)')
    parser.add_argument('--obstacles', type=int, default=SIM.obstacles,
                        help='random obstacles in the room')
    parser.add_argument('--room-size', type=_room_size,
                        default='%gx%g' % (SIM.room_length, SIM.room_width), metavar='LxW',
                        help='room length (x) by width (y) in metres, e.g. 6x4')
    parser.add_argument('--floor-rgba', default=SIM.floor_rgba,
                        help='floor colour "R G B A" in 0-1 (empty: the checker floor)')
    parser.add_argument('--wall-rgba', default=SIM.wall_rgba, help='wall colour "R G B A"')
    parser.add_argument('--obstacle-rgba', default=SIM.obstacle_rgba,
                        help='obstacle colour "R G B A"')
    parser.add_argument('--scan-topics', '--scan-topic', dest='scan_topics',
                        default=CONTROL.scan_topics,
                        help='obstacle scans can_stopper drives by, separated by spaces: '
                        '/camera_scan (the camera), /scan (the simulated lidar), both (an '
                        'obstacle either sees is one), or "" for none')
    parser.add_argument('--randomize-appearance', action='store_true',
                        help='draw the floor (plain or checkered, light or dark), wall and '
                        'obstacle colours of each trial from its seed, instead of the '
                        '--floor-rgba, --wall-rgba and --obstacle-rgba colours')
    parser.add_argument('--randomize-mount', action='store_true',
                        help='draw the camera mount of each trial from its seed: height '
                        '0.15-0.35 m, pitch 15-35 deg, instead of --camera-height and '
                        '--camera-pitch')
    parser.add_argument('--realism', default=SIM.realism.preset, choices=REALISM_PRESETS,
                        help='sensor and actuator realism preset of the simulator '
                        '(sim/realism/preset)')
    parser.add_argument('--param', action='append', default=[], type=override_arg,
                        metavar='NODE/PARAM=VALUE',
                        help='set a parameter of sim, image_converter, obstacle_scan or '
                        'can_stopper, e.g. sim/realism/camera_latency_s=0.1 (repeatable)')
    parser.add_argument('--sweep', action='append', default=[], type=_sweep,
                        metavar='NODE/PARAM=V1,V2,...',
                        help='evaluate the same seeds at every value (repeatable: every '
                        'combination); writes a table and a plot to --sweep-output')
    parser.add_argument('--sweep-output', default=default_output_dir('sweep'), metavar='DIR',
                        help='folder for sweep.md, sweep.json and sweep.png')
    parser.add_argument('--robot', default='', help='robot profile: a name in the package\'s '
                        'config/robots/ or a YAML path; empty: the built-in robot')
    parser.add_argument('--time-limit', type=float, default=None,
                        help='sim time allowed to reach STOPPED (s); default %g, scaled for a slow --robot' % Criteria.time_limit_s)
    parser.add_argument('--real-time-factor', type=float, default=0.0,
                        help='sim speed; 0 runs as fast as possible')
    parser.add_argument('--clock-rate', type=float, metavar='HZ',
                        help='rate of the simulator\'s /clock (sim time); default: %g in '
                        'lockstep (every frame, scan and state message also ticks it, and the '
                        'lockstep results are the same as at every physics step), every physics '
                        'step (0) without' % LOCKSTEP_CLOCK_RATE_HZ)
    parser.add_argument('--no-lockstep', dest='lockstep', action='store_false',
                        help='let the simulator run without waiting for each frame\'s '
                        'detection and command (results then depend on the machine\'s load)')
    parser.add_argument('--jobs', type=int, default=1,
                        help='worker processes of the local Dask cluster, each running trials '
                        'on a ROS system of its own')
    parser.add_argument('--cluster', metavar='ADDRESS',
                        help='run the trials on the workers of this Dask scheduler (e.g. '
                        'tcp://host:8786) instead of a local cluster')
    parser.add_argument('--repeat-check', action='store_true',
                        help='run the trials twice and report the largest per-trial difference; '
                        'exit 1 unless outcomes match and final poses agree within %g mm and '
                        '%g deg' % (1000.0 * REPEAT_POSITION_TOLERANCE_M,
                                    REPEAT_YAW_TOLERANCE_DEG))
    parser.add_argument('--cpu-features-check', action='store_true',
                        help='run the trials again with every node started without the wide '
                        'SIMD (AVX-512) kernels of numpy that the workers\' CPUs have (%s) and '
                        'report the largest per-trial difference; exit 1 unless outcomes match '
                        'and final poses agree within %g mm and %g deg'
                        % (DISABLE_VARIABLE, 1000.0 * REPEAT_POSITION_TOLERANCE_M,
                           REPEAT_YAW_TOLERANCE_DEG))
    parser.add_argument('--compare-with', metavar='FILE',
                        help='an earlier --json record of the same trials (another commit, '
                        'another machine): report the largest per-trial difference from it; '
                        'exit 1 unless outcomes match and final poses agree within %g mm and '
                        '%g deg (a record of other settings is refused before any trial runs)'
                        % (1000.0 * REPEAT_POSITION_TOLERANCE_M, REPEAT_YAW_TOLERANCE_DEG))
    parser.add_argument('--json', metavar='FILE',
                        help='write the results as JSON, again after every finished trial')
    parser.add_argument('--result', metavar='FILE',
                        help='write the summary with this command, the commit and the machine '
                        'as a result file (docs/results/NAME.json) once every trial has run')
    parser.add_argument('--resume', action='store_true',
                        help='run only the trials missing from --json FILE (same settings; '
                        '--trials may grow)')
    parser.add_argument('--log-dir', metavar='DIR',
                        help='folder for the roslaunch output of each worker\'s system; '
                        'None: the worker\'s temp folder')
    args = parser.parse_args(argv)
    if args.robot:
        try:
            profile = load_profile(args.robot, [robots_dir()])
        except ProfileError as error:
            parser.error(str(error))
        if os.path.isfile(args.robot):
            args.robot = os.path.abspath(args.robot)
        if args.time_limit is None:
            args.time_limit = scaled_time_limit(profile.max_linear_mps)
    if args.time_limit is None:
        args.time_limit = Criteria.time_limit_s
    if args.clock_rate is None:
        args.clock_rate = LOCKSTEP_CLOCK_RATE_HZ if args.lockstep else 0.0
    if args.cluster and args.jobs != 1:
        parser.error('--jobs sizes the local cluster; --cluster uses the workers it has')
    if args.jobs < 1:
        parser.error('--jobs must be at least 1')
    if args.resume and not args.json:
        parser.error('--resume needs --json FILE')
    if args.result and args.sweep:
        parser.error('--result records one evaluation, not a --sweep')
    if args.compare_with and args.sweep:
        parser.error('--compare-with compares one evaluation, not a --sweep')
    if (args.compare_with and args.json
            and os.path.realpath(args.compare_with) == os.path.realpath(args.json)):
        parser.error('--compare-with needs the earlier record kept: --json must name another '
                     'file')
    if args.resume and (args.sweep or args.repeat_check or args.cpu_features_check):
        parser.error('--resume continues one evaluation, not a --sweep, --repeat-check or '
                     '--cpu-features-check')
    return args


def robots_dir():
    from can_seeker.ros.paths import robots_dir as package_robots_dir
    return package_robots_dir()


def scaled_time_limit(max_linear_mps: float) -> float:
    """The trial time limit (s) for a robot of this top speed: the default limit, scaled up by
    REFERENCE_SPEED_MPS over the speed for a slower robot (it has the same floor to cover)."""
    return Criteria.time_limit_s * max(1.0, REFERENCE_SPEED_MPS / max_linear_mps)


def _room_size(text):
    try:
        length_m, width_m = (float(part) for part in text.lower().split('x'))
    except ValueError:
        raise argparse.ArgumentTypeError('a room size is LxW in metres, e.g. 6x4, got %r'
                                         % (text,))
    return '%gx%g' % (length_m, width_m)


def _sweep(text):
    try:
        return parse_sweep(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error))


def launch_args(args):
    """demo.launch arguments for the camera and can options."""
    room_length, room_width = args.room_size.split('x')
    world = args.world
    if world not in ('empty', 'room') and os.path.exists(world):
        world = os.path.abspath(world)
    return {'width': args.width, 'height': args.height, 'camera_height': args.camera_height,
            'camera_pitch_deg': args.camera_pitch, 'can_rgba': args.can_rgba,
            'real_time_factor': args.real_time_factor, 'clock_rate': args.clock_rate,
            'can_placement': 'random',
            'can_min_distance': args.min_distance, 'can_max_distance': args.max_distance,
            'world': world, 'obstacles': args.obstacles, 'room_length': room_length,
            'room_width': room_width, 'floor_rgba': args.floor_rgba,
            'wall_rgba': args.wall_rgba, 'obstacle_rgba': args.obstacle_rgba,
            'can_texture': args.can_texture, 'realism': args.realism,
            'scan_topics': args.scan_topics, 'lockstep': str(args.lockstep).lower(),
            'randomize_appearance': str(args.randomize_appearance).lower(),
            'randomize_mount': str(args.randomize_mount).lower(), 'robot': args.robot}


def settings(args):
    """The options that define the evaluation, for the JSON record."""
    record = {name: getattr(args, name) for name in (
        'trials', 'seed', 'min_distance', 'max_distance', 'width', 'height', 'camera_height',
        'camera_pitch', 'can_rgba', 'time_limit', 'real_time_factor', 'lockstep',
        'randomize_appearance', 'randomize_mount') + WORLD_OPTIONS + CONTROL_OPTIONS}
    if args.robot:
        record['robot'] = args.robot
    record['params'] = dict(args.param)
    return record


def system_spec(args, run=0, wide_kernels=True):
    """The ROS system the trials of ``args`` run on (``run`` tells a repeat check's runs
    apart: each gets fresh systems; ``wide_kernels`` False: its nodes run without numpy's
    wide SIMD kernels)."""
    log_dir = os.path.abspath(args.log_dir) if args.log_dir else None
    return SystemSpec.of(launch_args(args), dict(args.param), args.time_limit, run, log_dir,
                         wide_kernels)


def earlier_ledger(path, evaluation_settings):
    """The trials of the earlier ``--json`` record at ``path``, to resume or to compare with
    the evaluation ``evaluation_settings`` describes; ValueError when it cannot be read or is
    of another evaluation."""
    try:
        with open(path) as stream:
            record = json.load(stream)
    except (OSError, ValueError) as error:
        raise ValueError('cannot read %s: %s' % (path, error))
    try:
        return TrialLedger.from_record(record, evaluation_settings)
    except (KeyError, TypeError) as error:
        raise ValueError('%s is not an evaluate --json record (%s)' % (path, error))


def new_ledger(args):
    """The ledger of this evaluation: empty, or with ``--resume`` the trials the ``--json``
    record holds."""
    if not (args.resume and os.path.exists(args.json)):
        return TrialLedger(settings(args))
    ledger = earlier_ledger(args.json, settings(args))
    print('evaluate: resuming %s: %d trials done, %d to run'
          % (args.json, len(ledger.results()), len(ledger.missing())), file=sys.stderr)
    return ledger


def evaluate(args, engine, ledger, run=0, json_path=None, wide_kernels=True,
             description='trials'):
    """Run the trials ``ledger`` is missing on the engine, writing its record to ``json_path``
    after each; the indices that did not run."""
    return run_missing(engine, system_spec(args, run, wide_kernels), ledger, json_path,
                       description)


def report_repeat(first, second, check='repeat check'):
    """Print how far a second run of the trials landed from the first; the comparison (see
    ``compare_runs``)."""
    comparison = compare_runs(first, second)
    print('\n%s: %d trials compared; largest final-pose difference %s mm (trial %s), '
          '%s deg (trial %s); outcomes differ in %s; unmatched %s; lockstep time-outs in %s '
          '-> %s'
          % (check, comparison['compared'], _number(comparison['max_position_diff_mm']),
             comparison['max_position_diff_trial'], _number(comparison['max_yaw_diff_deg']),
             comparison['max_yaw_diff_trial'], comparison['outcome_differs'] or 'none',
             comparison['unmatched'] or 'none', comparison['timed_out'] or 'none',
             'repeatable' if comparison['repeatable'] else 'NOT repeatable'))
    return comparison


def cpu_features_check(args, engine, ledger):
    """Run the trials again on systems without the wide kernels each worker's CPU has and
    compare them with ``ledger``'s: the comparison with ``disabled`` (what each worker turned
    off) and the indices that did not run. When no worker has wide kernels there is no second
    run and the comparison is None."""
    disabled = {address: describe(features) for address, features
                in sorted(engine.client.run(numpy_features_to_disable).items())}
    shown = sorted(set(disabled.values()))
    if shown == [NOTHING_TO_DISABLE]:
        print('\ncpu-features check: %s on any worker; nothing to compare' % NOTHING_TO_DISABLE)
        return None, []
    print('\ncpu-features check: the second run\'s nodes run with %s'
          % (shown[0] if len(shown) == 1 else '; '.join(
              '%s on %s' % (text, address) for address, text in disabled.items())),
          file=sys.stderr)
    narrow = TrialLedger(settings(args))
    not_run = evaluate(args, engine, narrow, wide_kernels=False,
                       description='trials, no wide kernels')
    comparison = report_repeat(ledger.results(), narrow.results(), 'cpu-features check')
    return dict(comparison, disabled=disabled), not_run


def _world_text(record_settings):
    world = record_settings.get('world', 'empty')
    if world == 'room':
        return 'room %s m with %d obstacles' % (record_settings['room_size'],
                                                record_settings['obstacles'])
    return world


def _number(value):
    return 'n/a' if value is None else '%.4f' % value


def run_sweep(args, engine):
    """Evaluate every setting of the sweep grid on the same seeds (each on fresh systems);
    write the table, the JSON record and the plot; exit 0 once every setting ran."""
    os.makedirs(args.sweep_output, exist_ok=True)
    rows, records = [], []
    base_params = list(args.param)
    for setting in sweep_grid(args.sweep):
        args.param = base_params + sorted(setting.items())
        print('evaluate: sweep setting %s' % setting_label(setting), file=sys.stderr)
        ledger = TrialLedger(settings(args))
        cpu_before_s, sim_before_s = engine.cpu_so_far(), engine.sim_s
        evaluate(args, engine, ledger)
        record = ledger.record()
        record['summary'].update(setting_cost(cpu_before_s, engine.cpu_so_far(),
                                              engine.sim_s - sim_before_s))
        rows.append((setting, record['summary']))
        records.append(dict(record, setting=setting))
    args.param = base_params
    table = sweep_table(rows)
    title = ('%d trials per setting from seed %d, %s world, realism %s'
             % (args.trials, args.seed, args.world, args.realism))
    with open(os.path.join(args.sweep_output, 'sweep.md'), 'w') as output:
        output.write('%s\n\n%s\n' % (title, table))
    with open(os.path.join(args.sweep_output, 'sweep.json'), 'w') as output:
        json.dump(json_ready({'title': title, 'settings': records}), output, indent=2,
                  allow_nan=False)
    plot_sweep(rows, os.path.join(args.sweep_output, 'sweep.png'), title)
    print('\nevaluate sweep: %s\n%s\nwritten to %s (sweep.md, sweep.json, sweep.png)'
          % (title, table, args.sweep_output))


def setting_cost(cpu_before_s, cpu_after_s, sim_s):
    """A sweep setting's figures of what it cost: the CPU time of every process of the batch
    while it ran (its systems' start-up included) and its real-time factor per core; None
    where the batch's CPU is not measured (a running scheduler's workers)."""
    if cpu_before_s is None or cpu_after_s is None:
        return {'setting_cpu_s': None, 'setting_real_time_per_core': None}
    cpu_s = cpu_after_s - cpu_before_s
    return {'setting_cpu_s': cpu_s,
            'setting_real_time_per_core': sim_s / cpu_s if cpu_s > 0 else None}


def batch_cpu(engine):
    """The summary's figures of the batch's whole cost: the sim time of the trials this run
    ran, the CPU time of every process of the batch (local cluster only: None on a running
    scheduler's workers) and their ratio, the real-time factor per core."""
    if engine is None:
        return {}
    return {'batch_sim_s': engine.sim_s, 'batch_cpu_s': engine.cpu_s,
            'real_time_factor_per_core': engine.real_time_per_core}


def main():
    argv = rospy.myargv()[1:]
    args = parse_args(argv)
    if args.sweep:
        with Engine(args.jobs, args.cluster) as engine:
            run_sweep(args, engine)
        if engine.real_time_per_core is not None:
            print('%.2fx real time per core: %.1f sim s of trials per %.1f CPU s of every '
                  'process of the sweep' % (engine.real_time_per_core, engine.sim_s,
                                            engine.cpu_s))
        sys.exit(0)
    try:
        ledger = new_ledger(args)
    except ValueError as error:
        print('evaluate: cannot resume %s: %s' % (args.json, error), file=sys.stderr)
        sys.exit(2)
    earlier = None
    if args.compare_with:
        try:
            earlier = earlier_ledger(args.compare_with, settings(args))
        except ValueError as error:
            print('evaluate: cannot compare with %s: %s' % (args.compare_with, error),
                  file=sys.stderr)
            sys.exit(2)
    repeat, cpu_check, compared, not_run, interrupted, engine = None, None, None, [], False, None
    try:
        if ledger.missing():
            engine = Engine(args.jobs, args.cluster)
            with engine:
                not_run = evaluate(args, engine, ledger, json_path=args.json)
                if args.repeat_check:
                    second = TrialLedger(settings(args))
                    not_run += evaluate(args, engine, second, run=1,
                                        description='trials, run 2')
                    repeat = report_repeat(ledger.results(), second.results())
                if args.cpu_features_check:
                    cpu_check, cpu_not_run = cpu_features_check(args, engine, ledger)
                    not_run += cpu_not_run
    except KeyboardInterrupt:
        interrupted = True
        print('evaluate: interrupted; summarising the %d finished trials'
              % len(ledger.results()), file=sys.stderr)
    results, record_settings = ledger.results(), ledger.settings
    if earlier is not None and not interrupted:
        compared = dict(report_repeat(earlier.results(), results,
                                      'comparison with %s' % args.compare_with),
                        record=args.compare_with)
    summary = dict(ledger.summary(), **batch_cpu(engine))
    if record_settings.get('robot'):
        camera = 'robot %s (its camera), time limit %.0f s' % (record_settings['robot'],
                                                             record_settings['time_limit'])
    elif record_settings.get('randomize_mount'):
        camera = 'camera mount drawn per trial (%.2f-%.2f m / %.0f-%.0f deg)' % (
            *RANDOM_HEIGHT_RANGE_M, *RANDOM_PITCH_RANGE_DEG)
    else:
        camera = 'camera %.2f m / %.1f deg' % (record_settings['camera_height'],
                                               record_settings['camera_pitch'])
    print('\nevaluate: %d trials, %s world%s, can %.1f-%.1f m, %dx%d, %s, '
          'can %s %s, scan %s, realism %s' % (len(results), _world_text(record_settings),
                      ' with colours drawn per trial'
                      if record_settings.get('randomize_appearance') else '',
                      record_settings['min_distance'], record_settings['max_distance'],
                      record_settings['width'], record_settings['height'], camera,
                      record_settings.get('can_texture', 'plain'),
                      record_settings['can_rgba'], record_settings.get('scan_topics') or 'none',
                      record_settings.get('realism', 'ideal')))
    print(summary_table(summary))
    if args.json:
        record = ledger.record()
        record['summary'].update(batch_cpu(engine))
        if repeat is not None:
            record['repeat_check'] = repeat
        if cpu_check is not None:
            record['cpu_features_check'] = cpu_check
        if compared is not None:
            record['compared_with'] = compared
        write_json_atomically(args.json, record)
        print('results written to %s' % args.json)
    if args.result:
        if interrupted or not_run:
            print('evaluate: not every trial ran; no result written to %s' % args.result,
                  file=sys.stderr)
        else:
            figures = dict(summary)
            for name, comparison in (('repeat_check', repeat), ('cpu_features_check', cpu_check),
                                     ('compared_with', compared)):
                if comparison is not None:
                    figures[name] = comparison
            write_result(args.result, result_record('evaluate', command_line('evaluate', argv),
                                                    json_ready(figures)))
            print('result written to %s' % args.result)
    if interrupted:
        sys.exit(130)
    ok = bool(results) and not not_run and summary['successes'] == summary['trials']
    checks = [check['repeatable'] for check in (repeat, cpu_check, compared)
              if check is not None]
    sys.exit(0 if ok and all(checks) else 1)
