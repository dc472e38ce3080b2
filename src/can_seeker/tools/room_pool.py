"""Benchmarks that measure room after room run their rooms in a pool of processes."""
from concurrent.futures import ProcessPoolExecutor


def map_rooms(room, args):
    """``room(args, seed)`` for the ``args.rooms`` seeds from ``args.seed``, ``args.jobs``
    rooms at once; the results in seed order. ``room`` runs in another process, so it is a
    module-level function and ``args`` can be pickled."""
    seeds = range(args.seed, args.seed + args.rooms)
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        return list(pool.map(room, [args] * len(seeds), seeds))
