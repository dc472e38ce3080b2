"""Benchmark of the simulator world without ROS: how many times faster than real time it runs.

The robot drives a slow circle past the can so every frame has the floor, the can and motion in
it. Wall time covers physics, rendering and the RGBA -> bgr8 conversion, i.e. everything the
node does per step except publishing.
"""
import statistics
import time

from can_seeker.params import defaults
from can_seeker.sim.simulation import PARAMS, Simulation, camera_spec, checked_config
from can_seeker.sim.world import World

CASES = ((320, 240, 15.0, 3.0, 'empty', 'plain'), (320, 240, 15.0, 3.0, 'empty', 'textured'),
         (320, 240, 15.0, 3.0, 'room', 'textured'), (640, 480, 30.0, 1.0, 'empty', 'plain'),
         (640, 480, 30.0, 1.0, 'room', 'textured'))
"""(width px, height px, camera rate Hz, target real-time factor, world, can texture)."""


def run_case(urdf_path, renderer, width, height, camera_rate_hz, duration_s, world='empty',
             can_texture='plain'):
    """Run one camera configuration in ``world`` ('empty' or 'room', seed 0, lidar at its
    default rate) for ``duration_s`` of sim time; returns its measurements."""
    config = checked_config(defaults(PARAMS, dict(
        width=width, height=height, camera_rate=camera_rate_hz, renderer=renderer,
        can_placement='fixed', can_x=1.0, can_y=0.2, world=world, can_texture=can_texture)),
        print)
    with World(urdf_path, camera_spec(config), config.physics_rate, renderer,
               can_rgba=config.can_color, scene=config.scene,
               can_texture=config.can_texture) as world:
        simulation = Simulation.from_config(world, config)
        frame_walls_s, plain_walls_s = [], []
        start_s = time.perf_counter()
        for _ in range(int(round(duration_s * config.physics_rate))):
            simulation.command(0.15, 0.3)
            step_start_s = time.perf_counter()
            result = simulation.step()
            step_wall_s = time.perf_counter() - step_start_s
            (frame_walls_s if result.image is not None else plain_walls_s).append(step_wall_s)
        wall_s = time.perf_counter() - start_s
        return {
            'renderer': world.renderer_name,
            'real_time_factor': simulation.time_s / wall_s,
            'frames': len(frame_walls_s),
            'frame_ms': 1e3 * (statistics.median(frame_walls_s) - statistics.median(plain_walls_s)),
            'step_us': 1e6 * statistics.median(plain_walls_s),
            'wall_s': wall_s,
        }

