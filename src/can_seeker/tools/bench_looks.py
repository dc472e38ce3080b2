"""bench_looks: how plainly the camera sees each wall and obstacle of random rooms.

Runs without ROS (see can_seeker.evaluation.look_contrast): per room, the wall and the
obstacle the camera renders closest to the floor beside them (the largest channel difference
of the medians along their outline, grey levels, from the side where it is least), then how
many rooms hold one within each ``--within`` level. The rooms are those of ``evaluate --world
room`` with the same seed and options; the camera is the ideal one (no noise, no white-balance
drift), so a real camera's noise comes on top.
"""
import argparse
import sys
import time

from can_seeker.evaluation.look_contrast import measure_room, summary_rows
from can_seeker.ros.paths import urdf_path
from can_seeker.tools.room_pool import map_rooms


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seed', type=int, default=3100, help='seed of the first room')
    parser.add_argument('--rooms', type=int, default=10, help='number of rooms (seeds)')
    parser.add_argument('--randomize-appearance', action='store_true',
                        help='colours drawn per room, as evaluate --randomize-appearance')
    parser.add_argument('--randomize-mount', action='store_true',
                        help='camera mount drawn per room, as evaluate --randomize-mount')
    parser.add_argument('--within', type=float, nargs='+', default=[3.0, 6.0, 10.0],
                        help='count the rooms with a wall or obstacle within these levels')
    parser.add_argument('--jobs', type=int, default=2, help='rooms measured at once')
    return parser.parse_args(argv)


def _room(args, seed):
    return measure_room(urdf_path(), seed, args.randomize_appearance, args.randomize_mount)


def main(argv=None):
    args = parse_args(argv)
    start_s = time.monotonic()
    results = map_rooms(_room, args)
    print('bench_looks: %d rooms from seed %d%s%s (%.0f s)'
          % (args.rooms, args.seed, ', random looks' if args.randomize_appearance else '',
             ', random mounts' if args.randomize_mount else '', time.monotonic() - start_s))
    for row in summary_rows(results, args.within):
        print(row)
    return 0


if __name__ == '__main__':
    sys.exit(main())
