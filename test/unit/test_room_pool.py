"""map_rooms runs one room per seed in other processes and keeps the seed order."""
import argparse
import os

from can_seeker.tools.room_pool import map_rooms


def _seed_and_process(args, seed):
    return seed * args.scale, os.getpid()


def test_one_result_per_seed_in_seed_order():
    args = argparse.Namespace(seed=7, rooms=5, jobs=2, scale=10)
    results = map_rooms(_seed_and_process, args)
    assert [value for value, _ in results] == [70, 80, 90, 100, 110]


def test_rooms_run_outside_the_calling_process():
    args = argparse.Namespace(seed=0, rooms=3, jobs=0, scale=1)
    results = map_rooms(_seed_and_process, args)
    assert [value for value, _ in results] == [0, 1, 2]
    assert os.getpid() not in {pid for _, pid in results}
