"""evaluate: N closed-loop trials of the real nodes (sim, image_converter, can_stopper) under
their own master, judged on the simulator's ground truth.

The nodes start once (``demo.launch`` on a free port); between trials the sim and the controller
are reset through their services. Each trial stands the can at a random bearing and distance
(trial i uses seed + i, so ``--seed S+i --trials 1`` repeats it). Prints a progress bar, then a
summary table; ``--json FILE`` writes every trial and the summary. Exits 1 when a trial failed.
"""
import argparse
import json
import os
import sys
import tempfile

import rospy
from tqdm import tqdm

from can_seeker.tools.closed_loop import LaunchedSystem, TrialRunner
from can_seeker.params import defaults
from can_seeker.sim.simulation import PARAMS as SIM_PARAMS, random_can_position
from can_seeker.evaluation.trials import Criteria, summarise, summary_table

SIM = defaults(SIM_PARAMS)


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
    parser.add_argument('--time-limit', type=float, default=Criteria.time_limit_s,
                        help='sim time allowed to reach STOPPED (s)')
    parser.add_argument('--real-time-factor', type=float, default=0.0,
                        help='sim speed; 0 runs as fast as possible')
    parser.add_argument('--no-lockstep', dest='lockstep', action='store_false',
                        help='let the simulator run without waiting for each frame\'s '
                        'detection and command (results then depend on the machine\'s load)')
    parser.add_argument('--json', metavar='FILE', help='write the results as JSON')
    parser.add_argument('--log', metavar='FILE',
                        help='roslaunch output (default: a file in the temp directory)')
    return parser.parse_args(argv)


def launch_args(args):
    """demo.launch arguments for the camera and can options."""
    return {'width': args.width, 'height': args.height, 'camera_height': args.camera_height,
            'camera_pitch_deg': args.camera_pitch, 'can_rgba': args.can_rgba,
            'real_time_factor': args.real_time_factor, 'can_placement': 'fixed',
            'lockstep': str(args.lockstep).lower()}


def settings(args):
    """The options that define the evaluation, for the JSON record."""
    return {name: getattr(args, name) for name in (
        'trials', 'seed', 'min_distance', 'max_distance', 'width', 'height', 'camera_height',
        'camera_pitch', 'can_rgba', 'time_limit', 'real_time_factor', 'lockstep')}


def run_trial(runner, args, index):
    """Trial ``index`` with the can placed from seed + index; failures are reported at once."""
    can_xy = random_can_position(args.seed + index, args.min_distance, args.max_distance)
    result = runner.run(index, can_xy)
    if not result.success:
        tqdm.write('trial %d (seed %d) failed: can at (%.2f, %.2f), stopped=%s, gap %.3f m, '
                   'bearing %.2f deg, contact=%s'
                   % (index, args.seed + index, result.can_x_m, result.can_y_m, result.stopped,
                      result.gap_m, result.bearing_deg, result.contact), file=sys.stderr)
    return result


def run(args):
    """Start the nodes, run the trials (Ctrl-C ends early); the results and the criteria."""
    log_path = args.log or os.path.join(tempfile.gettempdir(),
                                        'can_seeker_evaluate_%d.log' % os.getpid())
    results = []
    with LaunchedSystem(launch_args(args), log_path) as system:
        rospy.init_node('evaluate', disable_signals=True)
        system.wait_for_services()
        criteria = Criteria(stop_distance_m=rospy.get_param('/can_stopper/stop_distance'),
                            time_limit_s=args.time_limit)
        runner = TrialRunner(criteria)
        bar = tqdm(range(args.trials), desc='trials', unit='trial', file=sys.stderr)
        try:
            for index in bar:
                results.append(run_trial(runner, args, index))
                bar.set_postfix(ok='%d/%d' % (sum(r.success for r in results), len(results)))
        except KeyboardInterrupt:
            tqdm.write('evaluate: interrupted; summarising the %d finished trials' % len(results),
                       file=sys.stderr)
        rospy.signal_shutdown('evaluation done')
    return results, criteria


def main():
    args = parse_args(rospy.myargv()[1:])
    try:
        results, criteria = run(args)
    except KeyboardInterrupt:
        print('evaluate: interrupted while starting the nodes', file=sys.stderr)
        sys.exit(130)
    summary = summarise(results, criteria)
    print('\nevaluate: %d trials, can %.1f-%.1f m, %dx%d, camera %.2f m / %.1f deg, can %s'
          % (len(results), args.min_distance, args.max_distance, args.width, args.height,
             args.camera_height, args.camera_pitch, args.can_rgba))
    print(summary_table(summary))
    if args.json:
        with open(args.json, 'w') as output:
            json.dump({'settings': settings(args), 'summary': summary,
                       'trials': [result.as_dict() for result in results]}, output, indent=2)
        print('results written to %s' % args.json)
    sys.exit(0 if results and summary['successes'] == summary['trials'] else 1)
