"""bench_floor: the camera obstacle scan against the truth on a scripted tour of random rooms.

Runs without ROS (see can_seeker.evaluation.floor_bench): per room, the share of obstacle
bases within ``--near`` that the scan misses, the frames with a miss of at least
``--min-missed-bins`` bins, and the share of phantom bins; then the total. The same seeds give
the same tours and frames, so two floor models (``--param NAME=VALUE``, any FloorSettings
field: obstacle_scan's floor parameters and the adaptive model's constants) are compared on exactly the same images.
"""
import argparse
import dataclasses
import sys
import time

from can_seeker.evaluation.floor_bench import run_room, summary_rows
from can_seeker.ros.paths import urdf_path
from can_seeker.sim.realism import REALISM_PRESETS
from can_seeker.params import Param
from can_seeker.tools.room_pool import map_rooms
from can_seeker.vision.floor import FLOOR_PARAMS, FloorSettings


def floor_override(text):
    """NAME=VALUE of a floor model setting (a parameter, or one of the adaptive model's
    constants by its settings name)."""
    name, _, value = text.partition('=')
    specs = {spec.name: spec for spec in FLOOR_PARAMS}
    specs.update({field.name: Param(field.name, field.default, '')
                  for field in dataclasses.fields(FloorSettings) if field.name not in specs})
    if name not in specs or not value:
        raise argparse.ArgumentTypeError('expected NAME=VALUE with NAME one of %s'
                                         % ', '.join(sorted(specs)))
    try:
        return name, specs[name].coerce(value)
    except ValueError as error:
        raise argparse.ArgumentTypeError('%s: %s' % (name, error))


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seed', type=int, default=2000, help='seed of the first room')
    parser.add_argument('--rooms', type=int, default=10, help='number of rooms (seeds)')
    parser.add_argument('--duration', type=float, default=40.0, help='sim seconds per room')
    parser.add_argument('--realism', default='harsh', choices=REALISM_PRESETS)
    parser.add_argument('--randomize-appearance', action='store_true')
    parser.add_argument('--randomize-mount', action='store_true')
    parser.add_argument('--near', type=float, default=1.0,
                        help='obstacle bases within this range (m) are judged for misses')
    parser.add_argument('--min-missed-bins', type=int, default=5,
                        help='missed bins that make a frame one with a miss')
    parser.add_argument('--frame-drops', action='store_true',
                        help='keep the realism preset\'s frame drops (a floor model then '
                        'steps over a dropped frame, as obstacle_scan does)')
    parser.add_argument('--param', action='append', default=[], type=floor_override,
                        help='floor model setting NAME=VALUE (repeatable)')
    parser.add_argument('--jobs', type=int, default=2, help='rooms run at once')
    return parser.parse_args(argv)


def _room(args, seed):
    settings = FloorSettings(**dict(args.param))
    return run_room(urdf_path(), seed, settings, args.duration, args.realism,
                    args.randomize_appearance, args.randomize_mount, args.near,
                    args.min_missed_bins, frame_drops=args.frame_drops)


def main(argv=None):
    args = parse_args(argv)
    start_s = time.monotonic()
    results = map_rooms(_room, args)
    print('bench_floor: %d rooms from seed %d, %s realism%s, %.0f s each, floor %s (%.0f s)'
          % (args.rooms, args.seed, args.realism,
             ' with frame drops' if args.frame_drops else '', args.duration,
             dict(args.param) or 'defaults', time.monotonic() - start_s))
    for row in summary_rows(results):
        print(row)
    return 0


if __name__ == '__main__':
    sys.exit(main())
