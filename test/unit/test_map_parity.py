"""The grid map and the planner, as optimised, against their straightforward computation.

Each reference below computes what the optimised code must give, the plain way: a scan's cells
from a separate sampling per layer and a whole-grid mask per set of cells; the wavefront by
Jacobi sweeps over the whole window until nothing changes. Both do the same integer and float
operations on each value, so the layers, distances and plans must be equal exactly.
"""
import math
import os

import numpy as np
import pytest

from can_seeker.control import planner
from can_seeker.control.elapsed import elapsed_s
from can_seeker.control.costmap.grid import RAY_STEPS_PER_CELL, isqrt, ray_samples, within
from can_seeker.control.costmap.obstacle_layer import (BLIND_EDGE_M, EVIDENCE_LIMIT,
                                                       HIT_EVIDENCE, MISS_EVIDENCE)
from can_seeker.control.costmap.world_map import WorldMap
from can_seeker.lattice import lattice

LAYERS = (('obstacles', 'evidence'), ('coverage', 'seen'), ('floor', 'observed'),
          ('obstacles', 'blind_s'), ('floor', 'blind_disc_s'), ('obstacles', 'hit_xy'),
          ('obstacles', 'contact'))


def samples(origin, offsets, squared, step_um):
    """(points N x M x 2, distances M): the straightforward sampling of the rays, each point
    rounded from its exact place as one array of (x, y)."""
    distances = np.arange(math.isqrt(int(squared.max())) // step_um + 1, dtype=np.int64) * step_um
    lengths = np.maximum(np.sqrt(squared.astype(float)), 1.0)
    points = distances.astype(float)[None, :, None] * offsets.astype(float)[:, None, :]
    points /= lengths[:, None, None]
    return np.rint(points) + origin[None, :, :], distances


def test_ray_samples_are_the_straightforward_ones():
    """:func:`ray_samples` x and y are the straightforward sampling's points exactly."""
    rng = np.random.default_rng(7)
    for _ in range(50):
        origin = lattice(rng.uniform(-3.0, 3.0, 2)).reshape(1, 2)
        ends = lattice(rng.uniform(-6.0, 6.0, (rng.integers(1, 400), 2)))
        offsets = ends - origin
        squared = (offsets * offsets).sum(axis=1)
        step_um = int(rng.choice((12500, 25000, 3333)))
        x_um, y_um, distances = ray_samples(origin, offsets, squared, step_um)
        points, expected = samples(origin, offsets, squared, step_um)
        assert np.array_equal(distances, expected)
        assert np.array_equal(x_um, points[..., 0]) and np.array_equal(y_um, points[..., 1])


def test_lattice_index_is_the_straightforward_one():
    """:meth:`GridGeometry.lattice_index` gives the clipped floor indices and whether both
    lie on the layer, inside, on the edges and outside it."""
    world = WorldMap(0.1, 4.0)
    grid = world.grid
    rng = np.random.default_rng(3)
    points = np.rint(rng.uniform(-4e6, 4e6, (2000, 2)))
    points[:8] = [[grid.origin_um, 0], [-grid.origin_um, 0], [grid.origin_um - 1, 0],
                  [-grid.origin_um - 1, 0], [0, grid.origin_um], [0, -grid.origin_um],
                  [0, grid.origin_um - 1], [0, -grid.origin_um - 1]]
    for resolution_um, cells in ((grid.resolution_um, grid.cells),
                                 (grid.fine_um, grid.fine_cells)):
        i, j, inside = grid.lattice_index(points, resolution_um, cells)
        ij = np.floor((points - grid.origin_um) / resolution_um).astype(np.int64)
        assert np.array_equal(inside, np.all((ij >= 0) & (ij < cells), axis=1))
        assert np.array_equal(np.stack((i, j), axis=1), np.clip(ij, 0, cells - 1))
        assert not inside.all() and inside.any()


def reference_add_scan(world, origin_xy, ends_xy, hits, clear_from_m=0.0, stamp_s=0.0,
                       source=''):
    """:meth:`WorldMap.update_from_scan`, each layer's samples taken and marked on their own,
    the layers' arrays updated in the order of one straightforward computation."""
    grid, obstacles, floor = world.grid, world.obstacles, world.floor
    ends_xy = np.asarray(ends_xy, float).reshape(-1, 2)
    previous_s = world.scan_s.get(source)
    elapsed = 0.0 if previous_s is None else elapsed_s(stamp_s, previous_s)
    world.scan_s[source] = stamp_s
    origin = lattice(origin_xy).reshape(1, 2)
    clear_um = int(lattice(clear_from_m))
    resolution_um, fine_um = grid.resolution_um, grid.fine_um
    disc_window = None
    if clear_um > 0 and elapsed > 0.0:
        ix, iy = grid.window(origin[0], clear_um, resolution_um, grid.cells)
        centres = grid.centres_um(*np.meshgrid(ix, iy, indexing='ij'), resolution_um)
        disc = within(centres, origin[0], clear_um)
        disc_window = np.ix_(ix, iy), disc
        floor.blind_disc_s[disc_window[0]] += np.where(disc, elapsed, 0.0)
    if len(ends_xy) == 0:
        if disc_window is not None:
            obstacles.blind_s[disc_window[0]] += np.where(disc_window[1], elapsed, 0.0)
        return

    def cells(xy_um, layer_um, count):
        ix, iy, inside = grid.lattice_index(xy_um.reshape(-1, 2), layer_um, count)
        marked = np.zeros((count, count), bool)
        marked[ix[inside], iy[inside]] = True
        return marked

    hits = np.asarray(hits, bool).reshape(-1)
    ends = lattice(ends_xy)
    offsets = ends - origin
    squared = (offsets * offsets).sum(axis=1)
    points, fractions = samples(origin, offsets, squared, resolution_um // RAY_STEPS_PER_CELL)
    reach = fractions[None, :] + np.where(hits, resolution_um, 0)[:, None]
    along = reach * reach <= squared[:, None]
    beyond_blind = fractions[None, :] >= clear_um
    free = cells(points[along & beyond_blind], resolution_um, grid.cells)
    within_blind = (fractions * fractions)[None, :] <= squared[:, None]
    within_blind &= ~beyond_blind
    blind = cells(points[within_blind], resolution_um, grid.cells)
    edge_um = clear_um + int(lattice(BLIND_EDGE_M))
    at_edge = hits & (squared <= edge_um * edge_um)
    kept = (cells(points[within_blind & at_edge[:, None]], resolution_um, grid.cells)
            & (obstacles.evidence > 0) if at_edge.any() else None)
    if disc_window is not None:
        blind[disc_window[0]] |= disc_window[1]
    nearest_first = np.argsort(squared[hits], kind='stable')
    hit_xy = ends_xy[hits][nearest_first]
    hx, hy, hit_inside = grid.lattice_index(ends[hits][nearest_first], resolution_um,
                                            grid.cells)
    hx, hy, hit_xy = hx[hit_inside], hy[hit_inside], hit_xy[hit_inside]
    _, first = np.unique(hx * grid.cells + hy, return_index=True)
    hit = np.zeros((grid.cells, grid.cells), bool)
    hit[hx, hy] = True
    obstacles.hit_xy[hx[first], hy[first]] = hit_xy[first]
    free &= ~hit
    blind &= ~hit
    fine_points, fine_fractions = samples(origin, offsets, squared,
                                           fine_um // RAY_STEPS_PER_CELL)
    fine_reach = fine_fractions[None, :] + np.where(hits, fine_um, 0)[:, None]
    fine_free = (fine_reach * fine_reach <= squared[:, None]) & (fine_fractions[None, :]
                                                                 >= clear_um)
    floor.observed |= cells(np.concatenate((fine_points[fine_free], ends[hits])), fine_um,
                            grid.fine_cells)
    obstacles.evidence[free] = np.maximum(obstacles.evidence[free] - MISS_EVIDENCE,
                                          -EVIDENCE_LIMIT)
    obstacles.evidence[hit] = np.minimum(obstacles.evidence[hit] + HIT_EVIDENCE, EVIDENCE_LIMIT)
    obstacles.blind_s[hit] = 0.0
    obstacles.blind_s[blind] += max(0.0, elapsed)
    if kept is not None:
        obstacles.blind_s[kept] = 0.0


def reference_wavefront(free, start):
    """:func:`planner.wavefront` by Jacobi sweeps over the whole array."""
    distance = np.full(free.shape, np.inf)
    distance[start] = 0.0
    passable = free.copy()
    passable[start] = True
    while True:
        best = distance
        for dx, dy, cost in planner.NEIGHBOURS:
            best = np.minimum(best, planner.shifted(distance, dx, dy, np.inf) + cost)
        best[~passable] = np.inf
        best[start] = 0.0
        if np.array_equal(best, distance):
            return distance
        distance = best


def random_scan(rng, origin, rays, max_range_m, fan_rad=None, blind_m=0.0):
    """Rays from ``origin`` (odom) over a fan (all round when None), some without a return,
    some ending inside the blind zone's edge."""
    start = rng.uniform(-math.pi, math.pi)
    spread = 2.0 * math.pi if fan_rad is None else fan_rad
    angles = start + np.sort(rng.uniform(0.0, spread, rays))
    ranges = rng.uniform(max(0.05, blind_m * 0.8), max_range_m, rays)
    edge = rng.random(rays) < 0.05
    ranges[edge] = blind_m + rng.uniform(0.0, BLIND_EDGE_M, edge.sum())
    hits = rng.random(rays) < 0.8
    ends = np.asarray(origin)[None, :] + ranges[:, None] * np.stack((np.cos(angles),
                                                                     np.sin(angles)), axis=-1)
    return ends, hits


def assert_same_layers(world, reference):
    for layer, name in LAYERS:
        np.testing.assert_array_equal(getattr(getattr(world, layer), name),
                                      getattr(getattr(reference, layer), name), name)
    assert world.scan_s == reference.scan_s


@pytest.mark.parametrize('seed', range(6))
def test_scans_mark_the_layers_as_the_per_layer_sampling_does(seed):
    """Random scans from a wandering sensor (camera fans, lidar rings, rays off the world),
    with blind zones, two sources and stamps a frame apart: every layer equal, every scan."""
    rng = np.random.default_rng(seed)
    resolution_m, size_m = ((0.1, 8.0), (0.05, 6.0), (0.08, 5.0))[seed % 3]
    world, reference = WorldMap(resolution_m, size_m), WorldMap(resolution_m, size_m)
    position = rng.uniform(-1.0, 1.0, 2)
    for scan in range(40):
        position = np.clip(position + rng.normal(0.0, 0.08, 2), -size_m / 2.0, size_m / 2.0)
        source = 'lidar' if scan % 3 == 2 else 'camera'
        blind_m = 0.12 if source == 'lidar' else 0.35
        ends, hits = random_scan(rng, position, int(rng.integers(0, 300)),
                                 rng.uniform(0.3, 5.0),
                                 None if source == 'lidar' else math.radians(60.0), blind_m)
        stamp_s = scan / 15.0
        world.update_from_scan(position, ends, hits, blind_m, stamp_s, source)
        reference_add_scan(reference, position, ends, hits, blind_m, stamp_s, source)
        assert_same_layers(world, reference)
    evidence = world.obstacles.evidence
    assert (evidence > 0).any() and (evidence < 0).any() and world.floor.observed.any()


def test_a_scan_reaching_past_the_grid_marks_only_cells_inside_it():
    world, reference = WorldMap(0.1, 2.0), WorldMap(0.1, 2.0)
    rng = np.random.default_rng(7)
    for stamp_s in (0.0, 0.1):
        ends, hits = random_scan(rng, (0.8, -0.7), 200, 3.0, None, 0.2)
        world.update_from_scan((0.8, -0.7), ends, hits, 0.2, stamp_s)
        reference_add_scan(reference, (0.8, -0.7), ends, hits, 0.2, stamp_s)
        assert_same_layers(world, reference)


@pytest.mark.parametrize('seed', range(8))
def test_wavefront_gives_the_distances_of_whole_window_sweeps(seed):
    rng = np.random.default_rng(100 + seed)
    shape = tuple(int(n) for n in rng.integers(1, 90, 2))
    free = rng.random(shape) > rng.uniform(0.0, 0.5)
    start = (int(rng.integers(0, shape[0])), int(rng.integers(0, shape[1])))
    np.testing.assert_array_equal(planner.wavefront(free, start),
                                  reference_wavefront(free, start))


def test_wavefront_through_rooms_and_a_maze_equals_the_sweeps():
    free = np.ones((82, 82), bool)
    free[20, 5:80] = False
    free[40, 0:70] = False
    free[60, 10:82] = False
    free[5:60, 70] = False
    free[30:35, 30:35] = False
    for start in ((0, 0), (81, 81), (41, 75), (30, 30)):
        np.testing.assert_array_equal(planner.wavefront(free, start),
                                      reference_wavefront(free, start))


def reference_inflate(blocked, radius_cells):
    """:func:`planner.inflate` one offset of the disc at a time."""
    grown = blocked.copy()
    reach = int(math.floor(radius_cells))
    for dx in range(-reach, reach + 1):
        for dy in range(-reach, reach + 1):
            if (dx or dy) and dx * dx + dy * dy <= radius_cells * radius_cells:
                grown |= planner.shifted(blocked, dx, dy, False)
    return grown


@pytest.mark.parametrize('radius_cells', (0.0, 0.5, 1.0, 1.2071, 2.0, 2.2360679774997896, 3.15,
                                          4.999999, 5.0, 7.3))
def test_inflate_grows_as_one_offset_at_a_time(radius_cells):
    rng = np.random.default_rng(int(radius_cells * 1000))
    for shape in ((8, 17), (40, 31), (82, 82)):
        blocked = rng.random(shape) < 0.05
        np.testing.assert_array_equal(planner.inflate(blocked, radius_cells),
                                      reference_inflate(blocked, radius_cells))


def test_integer_square_roots_are_exact_to_the_largest_squares():
    rng = np.random.default_rng(3)
    roots = np.concatenate((np.arange(0, 2000), rng.integers(0, 2 ** 31, 5000),
                            [2 ** 26 - 1, 2 ** 26, 2 ** 26 + 1, 94906265, 94906266, 2 ** 31 - 1]))
    squares = roots * roots
    values = np.concatenate((squares, squares + 1, np.maximum(squares - 1, 0),
                             rng.integers(0, 2 ** 62, 5000)))
    np.testing.assert_array_equal(isqrt(values), [math.isqrt(int(v)) for v in values])


def test_the_robot_body_and_the_camera_wedge_mark_as_whole_grid_masks_do():
    rng = np.random.default_rng(11)
    world = WorldMap(0.1, 6.0)
    for _ in range(5):
        ends, hits = random_scan(rng, (0.0, 0.0), 200, 2.5, None, 0.1)
        world.update_from_scan((0.0, 0.0), ends, hits, 0.1)
    for _ in range(60):
        centre, radius_m = rng.uniform(-3.3, 3.3, 2), rng.uniform(0.0, 0.4)
        expected = world.floor.observed.copy()
        fx, fy = np.meshgrid(np.arange(len(expected)), np.arange(len(expected)), indexing='ij')
        centres = world.grid.centres_um(fx, fy, world.grid.fine_um)
        expected |= within(centres, lattice(centre), int(lattice(radius_m)))
        world.update_from_footprint(centre, radius_m)
        np.testing.assert_array_equal(world.floor.observed, expected)
        seen = world.coverage.seen.copy()
        heading, half_fov = rng.uniform(-math.pi, math.pi), rng.uniform(0.1, 0.8)
        near_m, far_m = rng.uniform(0.0, 0.5), rng.uniform(0.3, 3.0)
        step_um = world.grid.resolution_um // RAY_STEPS_PER_CELL
        near_um, far_um = int(lattice(near_m)), int(lattice(far_m))
        if far_um > near_um:
            rays = -(-int(lattice(2.0 * half_fov * far_m)) // step_um) + 1
            bearings = heading + np.linspace(-half_fov, half_fov, rays)
            distances_um = np.arange(far_um // step_um + 1) * step_um
            points = (centre[None, None, :] + (distances_um / 1e6)[None, :, None]
                      * np.stack((np.cos(bearings), np.sin(bearings)), axis=-1)[:, None, :])
            ix, iy, inside = world.index_of(points.reshape(-1, 2))
            blocked = (world.occupied()[ix, iy] | ~inside).reshape(rays, len(distances_um))
            visible = ~np.maximum.accumulate(blocked, axis=1)
            visible &= distances_um[None, :] >= near_um
            seen[ix[visible.reshape(-1)], iy[visible.reshape(-1)]] = True
        world.update_from_camera(centre, heading, half_fov, near_m, far_m)
        np.testing.assert_array_equal(world.coverage.seen, seen)


def recorded_scans():
    """The first 40 camera scans of a realistic room trial (seed 1001), in odom, as the
    controller passed them to its world (stored as float32; see test/data/README.md)."""
    data = np.load(os.path.join(os.path.dirname(__file__), '..', 'data', 'camera_scans_room.npz'))
    starts = np.concatenate(([0], np.cumsum(data['ray_counts'])))
    for index, origin in enumerate(data['origins'].astype(float)):
        rays = slice(starts[index], starts[index + 1])
        yield (origin, data['ends'][rays].astype(float), data['hits'][rays],
               float(data['clear_from_m'][index]), float(data['stamps_s'][index]))


def test_recorded_scans_mark_the_layers_and_plan_as_the_straightforward_computation():
    world, reference = WorldMap(0.1, 20.0), WorldMap(0.1, 20.0)
    for origin, ends, hits, clear_from_m, stamp_s in recorded_scans():
        world.update_from_scan(origin, ends, hits, clear_from_m, stamp_s, 'camera_scan')
        reference_add_scan(reference, origin, ends, hits, clear_from_m, stamp_s, 'camera_scan')
        assert_same_layers(world, reference)
        blocked = reference_inflate(reference.occupied(), (0.165 + 0.15) / 0.1)
        np.testing.assert_array_equal(planner.inflate(world.occupied(), (0.165 + 0.15) / 0.1),
                                      blocked)
        start = world.cell_of(*origin)
        np.testing.assert_array_equal(planner.wavefront(~blocked, start),
                                      reference_wavefront(~blocked, start))
    assert (world.obstacles.evidence > 0).sum() > 50 and world.floor.observed.sum() > 1000
