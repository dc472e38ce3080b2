"""The pybullet world: floor, walls, obstacles, differential-drive robot, soda can, physics
stepping, the camera and the lidar.

Real rigid-body physics: the robot is driven through its wheel motors and pushes the can by
contact; walls and obstacles are static. What stands where comes from a :class:`Scene`. The camera renders with EGL (CPU llvmpipe works headless) or, when the EGL plugin is
missing or renders nothing, with pybullet's TinyRenderer. The world frame is the odom frame and
the robot starts at its origin facing +x. Use one World from one thread: pybullet is not
thread-safe.

A frame's CPU is mostly the EGL plugin's: it clears and draws a 4096 x 4096 shadow map before
every image (its resolution is not settable in DIRECT mode, and any other would change the
images), about a third of it Mesa's clear of that map alone.
"""
import importlib.util
import math
import os
import shutil
import tempfile
from dataclasses import dataclass, replace
from typing import Dict, FrozenSet, Optional, Sequence, Tuple

import cv2
import numpy as np
import pybullet
import pybullet_data
from pybullet_utils.bullet_client import BulletClient

from can_seeker.camera_geometry import intrinsics_from_vertical_fov, quaternion_matrix, \
    yaw_from_quaternion
from can_seeker.camera_mount import CameraMount
from can_seeker.robot_model import robot_urdf
from can_seeker.robot_profile import RobotProfile
from can_seeker.sim import can_texture
from can_seeker.sim.drive import wheel_speeds
from can_seeker.sim.lidar import LidarSpec
from can_seeker.sim.scene import (CAN_HEIGHT_M, CAN_MASS_KG, CAN_RADIUS_M, EMPTY_FLOOR_HALF_SIDE_M,
                                  ROBOT_RADIUS_M, WHEEL_RADIUS_M, WHEEL_SEPARATION_M, Scene, Solid,
                                  empty_bounds)

WHEEL_MAX_TORQUE_NM = 2.0
CAN_LATERAL_FRICTION = 0.5
CAN_AWAY_M = (0.0, 0.0, 1000.0)
"""Where the can waits, touching nothing, while its old contacts are dropped (m, world)."""
FLOOR_DEPTH_M = 10.0
"""Thickness of a coloured floor slab, as deep as pybullet's plane (m)."""
CAN_RGBA = (0.8, 0.05, 0.05, 1.0)
"""Default can colour (red, green, blue, alpha in 0-1)."""

SEGMENTATION_BODY_MASK = (1 << 24) - 1
"""A segmentation pixel holds the body index in its low 24 bits (the link index above them
when link masks are asked for; they are not)."""
CLIP_NEAR_M = 0.02
CLIP_FAR_M = 30.0
INVISIBLE_VISUAL_RADIUS_M = 1e-4
"""A solid of alpha 0 is drawn as a sphere this small at its centre (m): no renderer shows
it and it casts no shadow. Its own shape at alpha 0 would still cast one under the EGL
renderer, and a body without a visual shape is drawn as its collision shape."""
CONTACT_TOLERANCE_M = 0.001
"""Contact points farther apart than this (m) are a near miss, not a touch."""

RENDERERS = ('auto', 'egl', 'tiny')
CAN_TEXTURES = ('textured', 'plain')
"""textured: red body, white lettering band, silver lid and base; plain: one colour."""


CHECKER_TEXTURE_PX = 256
"""Side of a floor checker texture (px): two squares each way, like pybullet's."""


def checker_image(rgba: Sequence[float], checker_rgba: Sequence[float]) -> np.ndarray:
    """BGR texture of a 2 x 2 checker: ``rgba`` in the squares at the texture's origin and
    opposite corner, ``checker_rgba`` in the other two (colours in 0-1)."""
    half = CHECKER_TEXTURE_PX // 2
    first, second = (np.array([round(255.0 * channel) for channel in colour[2::-1]], np.uint8)
                     for colour in (rgba, checker_rgba))
    image = np.empty((CHECKER_TEXTURE_PX, CHECKER_TEXTURE_PX, 3), np.uint8)
    image[:half, :half] = image[half:, half:] = first
    image[:half, half:] = image[half:, :half] = second
    return image


def checker_floor_obj(mtl_name: str) -> str:
    """pybullet's plane100.obj with material ``floor`` from ``mtl_name``: a 200 m square at
    z = 0 whose texture repeats every 2 m (a 2 x 2 checker texture gives 1 m squares, with a
    corner at the origin)."""
    side = EMPTY_FLOOR_HALF_SIDE_M
    return ('mtllib %s\no floor\n'
            'v %g %g 0\nv %g %g 0\nv %g %g 0\nv %g %g 0\n'
            'vt %g 0\nvt %g %g\nvt 0 %g\nvt 0 0\nvn 0 0 1\n'
            'usemtl floor\ns off\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n'
            % (mtl_name, side, -side, side, side, -side, side, -side, -side,
               side, side, side, side))


@dataclass(frozen=True)
class CameraSpec:
    """Image size (px), vertical field of view (deg) and mount of the robot's camera."""

    width: int
    height: int
    fov_deg: float
    mount: CameraMount

    @property
    def intrinsics(self):
        """The pinhole intrinsics of the projection used to render."""
        return intrinsics_from_vertical_fov(self.width, self.height, self.fov_deg)


@dataclass(frozen=True)
class RobotState:
    """base_link's pose in the world (odom) frame and its twist in base_link.

    Units: m, quaternion (x, y, z, w), m/s, rad/s.
    """

    position: Tuple[float, float, float]
    orientation_xyzw: Tuple[float, float, float, float]
    linear_velocity: Tuple[float, float, float]
    angular_velocity: Tuple[float, float, float]

    @property
    def yaw_rad(self) -> float:
        """Heading about z (rad)."""
        return yaw_from_quaternion(*self.orientation_xyzw)


RGBA_CONVERSIONS = {'bgr8': cv2.COLOR_RGBA2BGR, 'rgb8': cv2.COLOR_RGBA2RGB}
"""OpenCV's conversion from pybullet's RGBA to each image encoding: a few microseconds a frame
where numpy's copy of a reversed channel view takes a third of a millisecond."""


def rgba_to_image(rgba: np.ndarray, encoding: str) -> np.ndarray:
    """An HxWx3 uint8 image in ``encoding`` ('bgr8' or 'rgb8') from pybullet's HxWx4 RGBA."""
    if encoding not in RGBA_CONVERSIONS:
        raise ValueError('unsupported encoding %r (bgr8 or rgb8)' % (encoding,))
    return cv2.cvtColor(rgba, RGBA_CONVERSIONS[encoding])


class World:
    """Floor, walls and obstacles of a :class:`Scene`, robot (``urdf_path`` with the camera's
    mount applied, see :mod:`can_seeker.robot_model`) and can; stepped at ``physics_rate_hz``.

    ``renderer`` is 'auto' (EGL, TinyRenderer fallback), 'egl' (RuntimeError if unusable) or
    'tiny'. ``gui`` opens the pybullet GUI (needs a display); it renders with its own OpenGL.
    Without a scene the world is the empty floor with the can 1 m ahead. ``can_texture`` is one
    of CAN_TEXTURES. ``profile`` gives the robot its body, wheels and casters
    (:func:`can_seeker.robot_model.apply_body`; None: the URDF's own, today's robot).
    """

    def __init__(self, urdf_path: str, camera: CameraSpec, physics_rate_hz: float = 240.0,
                 renderer: str = 'auto', gui: bool = False,
                 can_rgba: Sequence[float] = CAN_RGBA, scene: Optional[Scene] = None,
                 can_texture: str = 'plain', profile: Optional[RobotProfile] = None):
        if renderer not in RENDERERS:
            raise ValueError('renderer must be one of %s, got %r'
                             % (', '.join(RENDERERS), renderer))
        if can_texture not in CAN_TEXTURES:
            raise ValueError('can_texture must be one of %s, got %r'
                             % (', '.join(CAN_TEXTURES), can_texture))
        self._textured_can = can_texture == 'textured'
        self._texture_dir = tempfile.mkdtemp(prefix='can_seeker_textures_')
        self._floor_meshes = {}
        self.camera = camera
        self.profile = profile
        self.body_radius_m = ROBOT_RADIUS_M if profile is None else profile.body_radius_m
        self.wheel_separation_m = (WHEEL_SEPARATION_M if profile is None
                                   else profile.wheel_separation_m)
        self.wheel_radius_m = WHEEL_RADIUS_M if profile is None else profile.wheel_radius_m
        self.dt_s = 1.0 / physics_rate_hz
        self._client = BulletClient(connection_mode=pybullet.GUI if gui else pybullet.DIRECT)
        self._egl_plugin = -1
        if gui:
            self.renderer_name = 'opengl-gui'
        elif renderer in ('auto', 'egl'):
            self._egl_plugin = self._load_egl_plugin()
            self.renderer_name = 'egl' if self._egl_plugin >= 0 else 'tiny'
        else:
            self.renderer_name = 'tiny'
        client = self._client
        client.setAdditionalSearchPath(pybullet_data.getDataPath())
        client.setGravity(0.0, 0.0, -9.81)
        client.setTimeStep(self.dt_s)
        # Contact pairs solved in a sorted order: otherwise the order (and so the result) of a
        # trial after a rebuilt scene depends on what the world did before it.
        client.setPhysicsEngineParameter(deterministicOverlappingPairs=1)
        self._floor = None
        self._solids = {}
        self._robot = client.loadURDF(self._mounted_urdf(urdf_path), useFixedBase=False)
        self._wheel_joints = self._joint_indices(('left_wheel_joint', 'right_wheel_joint'))
        dynamics = client.getDynamicsInfo(self._robot, -1)
        self._base_in_inertial = client.invertTransform(dynamics[3], dynamics[4])
        self._inertial_in_base = (dynamics[3], dynamics[4])
        self._can = self._create_can(can_rgba)
        self._can_home = (1.0, 0.0)
        self.scene = None
        self.set_scene(scene if scene is not None else Scene(empty_bounds(), can_xy=(1.0, 0.0)))
        self.reset_robot()
        if self.renderer_name == 'egl' and not self._renders_scene():
            client.unloadPlugin(self._egl_plugin)
            self._egl_plugin = -1
            self.renderer_name = 'tiny'
        if renderer == 'egl' and self.renderer_name != 'egl':
            self.close()
            raise RuntimeError('the EGL renderer is not available')

    def set_scene(self, scene: Scene):
        """Rebuild the floor, walls and obstacles of ``scene`` and stand the can at its place
        (kept where it is when the scene has none); the robot is not moved."""
        client = self._client
        for body in list(self._solids) + ([self._floor] if self._floor is not None else []):
            client.removeBody(body)
        self._floor = self._create_floor(scene.floor_rgba, scene.floor_checker_rgba)
        self._solids = {self._create_solid(solid, scene.colour_of(solid)): solid.name
                        for solid in scene.solids}
        self.scene = scene
        self.place_can(*(scene.can_xy if scene.can_xy is not None else self._can_home))

    def _mounted_urdf(self, urdf_path: str) -> str:
        """The robot file ``urdf_path`` with this world's camera mount applied (the model
        robot_description holds for the same mount), written beside the textures."""
        with open(urdf_path) as template:
            urdf = robot_urdf(template.read(), self.camera.mount, profile=self.profile)
        path = os.path.join(self._texture_dir, 'robot.urdf')
        with open(path, 'w') as mounted:
            mounted.write(urdf)
        return path

    def _create_floor(self, rgba: Optional[Sequence[float]],
                      checker_rgba: Optional[Sequence[float]] = None) -> int:
        """pybullet's checker plane, or a slab of its size in one colour or in a checker of
        ``rgba`` and ``checker_rgba``."""
        client = self._client
        if rgba is None:
            return client.loadURDF('plane.urdf')
        half_extents = (EMPTY_FLOOR_HALF_SIDE_M, EMPTY_FLOOR_HALF_SIDE_M, FLOOR_DEPTH_M / 2.0)
        if checker_rgba is None:
            visual = client.createVisualShape(pybullet.GEOM_BOX, halfExtents=half_extents,
                                              rgbaColor=list(rgba))
        else:
            visual = client.createVisualShape(pybullet.GEOM_MESH,
                                              fileName=self._checker_mesh(rgba, checker_rgba),
                                              visualFramePosition=(0.0, 0.0, FLOOR_DEPTH_M / 2.0))
        floor = client.createMultiBody(
            baseMass=0.0,
            baseCollisionShapeIndex=client.createCollisionShape(pybullet.GEOM_BOX,
                                                                halfExtents=half_extents),
            baseVisualShapeIndex=visual, basePosition=(0.0, 0.0, -FLOOR_DEPTH_M / 2.0))
        client.changeDynamics(floor, -1, lateralFriction=1.0)
        return floor

    def _checker_mesh(self, rgba: Sequence[float], checker_rgba: Sequence[float]) -> str:
        """An OBJ floor like pybullet's plane whose material's texture is a checker of the two
        colours, written once per pair. The texture comes with the mesh: one set later with
        changeVisualShape shows another texture under the EGL renderer (its texture ids are
        not pybullet's)."""
        key = (tuple(rgba[:3]), tuple(checker_rgba[:3]))
        if key not in self._floor_meshes:
            name = 'floor_%d' % len(self._floor_meshes)
            cv2.imwrite(os.path.join(self._texture_dir, name + '.png'),
                        checker_image(rgba, checker_rgba))
            with open(os.path.join(self._texture_dir, name + '.mtl'), 'w') as mtl:
                mtl.write('newmtl floor\nKd 1 1 1\nmap_Kd %s.png\n' % name)
            path = os.path.join(self._texture_dir, name + '.obj')
            with open(path, 'w') as mesh:
                mesh.write(checker_floor_obj(name + '.mtl'))
            self._floor_meshes[key] = path
        return self._floor_meshes[key]

    def _create_solid(self, solid: Solid, rgba: Sequence[float]) -> int:
        """A static box or cylinder standing on the floor; one of alpha 0 is invisible (see
        INVISIBLE_VISUAL_RADIUS_M)."""
        client = self._client
        colour = list(rgba)
        if solid.shape == 'cylinder':
            radius = solid.size_x_m / 2.0
            collision = client.createCollisionShape(pybullet.GEOM_CYLINDER, radius=radius,
                                                    height=solid.height_m)
            visual_shape = dict(shapeType=pybullet.GEOM_CYLINDER, radius=radius,
                                length=solid.height_m)
        else:
            half_extents = (solid.size_x_m / 2.0, solid.size_y_m / 2.0, solid.height_m / 2.0)
            collision = client.createCollisionShape(pybullet.GEOM_BOX, halfExtents=half_extents)
            visual_shape = dict(shapeType=pybullet.GEOM_BOX, halfExtents=half_extents)
        if rgba[3] == 0.0:
            visual = client.createVisualShape(pybullet.GEOM_SPHERE,
                                              radius=INVISIBLE_VISUAL_RADIUS_M, rgbaColor=colour)
        else:
            visual = client.createVisualShape(rgbaColor=colour, **visual_shape)
        return client.createMultiBody(
            baseMass=0.0, baseCollisionShapeIndex=collision, baseVisualShapeIndex=visual,
            basePosition=(solid.x_m, solid.y_m, solid.height_m / 2.0),
            baseOrientation=client.getQuaternionFromEuler((0.0, 0.0, solid.yaw_rad)))

    def _load_egl_plugin(self) -> int:
        """Load pybullet's EGL renderer (before any body exists); -1 when it is unavailable."""
        spec = importlib.util.find_spec('eglRenderer')
        if spec is None or spec.origin is None:
            return -1
        return self._client.loadPlugin(spec.origin, '_eglRendererPlugin')

    def _renders_scene(self) -> bool:
        """False when the renderer returns a blank frame (EGL without a usable device)."""
        rgba = self.render_rgba()
        return bool(np.ptp(rgba[:, :, :3]) > 0)

    def _joint_indices(self, names: Sequence[str]) -> Tuple[int, ...]:
        by_name = {}
        for index in range(self._client.getNumJoints(self._robot)):
            by_name[self._client.getJointInfo(self._robot, index)[1].decode()] = index
        missing = [name for name in names if name not in by_name]
        if missing:
            raise ValueError('the robot URDF has no joint %s' % ', '.join(missing))
        return tuple(by_name[name] for name in names)

    def _create_can(self, rgba: Sequence[float]) -> int:
        client = self._client
        collision = client.createCollisionShape(pybullet.GEOM_CYLINDER, radius=CAN_RADIUS_M,
                                                height=CAN_HEIGHT_M)
        if not self._textured_can:
            visual = client.createVisualShape(pybullet.GEOM_CYLINDER, radius=CAN_RADIUS_M,
                                              length=CAN_HEIGHT_M, rgbaColor=list(rgba))
        else:
            mesh_path = os.path.join(self._texture_dir, 'can.obj')
            with open(mesh_path, 'w') as mesh:
                mesh.write(can_texture.mesh_obj(CAN_RADIUS_M, CAN_HEIGHT_M))
            visual = client.createVisualShape(pybullet.GEOM_MESH, fileName=mesh_path,
                                              rgbaColor=[1.0, 1.0, 1.0, 1.0])
        can = client.createMultiBody(baseMass=CAN_MASS_KG, baseCollisionShapeIndex=collision,
                                     baseVisualShapeIndex=visual,
                                     basePosition=(0.0, 0.0, CAN_HEIGHT_M / 2.0))
        client.changeDynamics(can, -1, lateralFriction=CAN_LATERAL_FRICTION)
        if self._textured_can:
            self._paint_label(can, rgba)
        return can

    def _paint_label(self, can: int, rgba: Sequence[float]):
        """Give the textured can a label whose body has the colour ``rgba``."""
        body_rgb = [int(round(255 * channel)) for channel in rgba[:3]]
        label_path = os.path.join(self._texture_dir, 'label_%02x%02x%02x.png' % tuple(body_rgb))
        cv2.imwrite(label_path, cv2.cvtColor(can_texture.label_image(body_rgb),
                                             cv2.COLOR_RGB2BGR))
        self._client.changeVisualShape(can, -1,
                                       textureUniqueId=self._client.loadTexture(label_path))

    def set_can_color(self, rgba: Sequence[float]):
        """Repaint the can (red, green, blue, alpha in 0-1): the body of a textured can."""
        if self._textured_can:
            self._paint_label(self._can, rgba)
        else:
            self._client.changeVisualShape(self._can, -1, rgbaColor=list(rgba))

    def reset_robot(self, x_m: float = 0.0, y_m: float = 0.0, yaw_rad: float = 0.0):
        """Put the robot at (x, y) in the world frame facing ``yaw_rad`` (the origin facing +x
        by default), at rest, wheels stopped."""
        client = self._client
        position, orientation = client.multiplyTransforms(
            (x_m, y_m, 0.0), client.getQuaternionFromEuler((0.0, 0.0, yaw_rad)),
            *self._inertial_in_base)
        client.resetBasePositionAndOrientation(self._robot, position, orientation)
        client.resetBaseVelocity(self._robot, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        for joint in self._wheel_joints:
            client.resetJointState(self._robot, joint, 0.0, 0.0)
        self._hold_angles_rad = None
        self.set_twist(0.0, 0.0)

    def place_can(self, x_m: float, y_m: float):
        """Stand the can upright and at rest with its axis at (x, y) in the world frame (m).

        The physics engine carries a resting body's contact points from step to step; the can
        first leaves everything it touches for one collision pass, so it settles the same
        whatever it did or how long it stood before (else a trial's can settled a fraction of a
        micrometre differently with the time its start took, and some trials took another
        course)."""
        self._can_home = (float(x_m), float(y_m))
        client = self._client
        client.resetBasePositionAndOrientation(self._can, CAN_AWAY_M, (0.0, 0.0, 0.0, 1.0))
        client.performCollisionDetection()
        client.resetBasePositionAndOrientation(self._can, (x_m, y_m, CAN_HEIGHT_M / 2.0),
                                               (0.0, 0.0, 0.0, 1.0))
        client.resetBaseVelocity(self._can, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))

    @property
    def can_home(self) -> Tuple[float, float]:
        """Where the can was last placed (m, world frame)."""
        return self._can_home

    def set_twist(self, linear_mps: float, angular_radps: float):
        """Drive the wheel motors at the speeds of the given base twist (m/s, rad/s).

        A zero twist holds the wheels at their angles: a zero-velocity motor creeps (~0.1 mm/s)
        under the solver's residual error, a position hold does not.
        """
        client = self._client
        if linear_mps == 0.0 and angular_radps == 0.0:
            if self._hold_angles_rad is None:
                self._hold_angles_rad = [client.getJointState(self._robot, joint)[0]
                                         for joint in self._wheel_joints]
                client.setJointMotorControlArray(
                    self._robot, self._wheel_joints, pybullet.POSITION_CONTROL,
                    targetPositions=self._hold_angles_rad, forces=[WHEEL_MAX_TORQUE_NM] * 2)
            return
        self._hold_angles_rad = None
        left, right = wheel_speeds(linear_mps, angular_radps, self.wheel_separation_m,
                                   self.wheel_radius_m)
        client.setJointMotorControlArray(
            self._robot, self._wheel_joints, pybullet.VELOCITY_CONTROL,
            targetVelocities=[left, right], forces=[WHEEL_MAX_TORQUE_NM] * 2)

    def step(self):
        """Advance the physics by one time step (``dt_s``)."""
        self._client.stepSimulation()

    def _com_and_base_poses(self):
        """((position, orientation) of the robot's centre of mass, the same of base_link),
        world frame (m, quaternion xyzw)."""
        client = self._client
        com = client.getBasePositionAndOrientation(self._robot)
        return com, client.multiplyTransforms(*com, *self._base_in_inertial)

    def robot_pose(self) -> Tuple[float, float, float]:
        """base_link's (x m, y m, yaw rad) in the world frame, as :meth:`robot_state` has it,
        without the twist: read at every physics step, where the twist's arithmetic would cost
        as much as the step."""
        _, (position, orientation) = self._com_and_base_poses()
        return position[0], position[1], yaw_from_quaternion(*orientation)

    def robot_state(self) -> RobotState:
        """The true pose and twist of base_link (perfect odometry)."""
        client = self._client
        (com_position, _), (position, orientation) = self._com_and_base_poses()
        com_velocity, angular_world = client.getBaseVelocity(self._robot)
        lever_m = np.subtract(position, com_position)
        linear_world = np.add(com_velocity, np.cross(angular_world, lever_m))
        world_from_base = quaternion_matrix(*orientation)
        return RobotState(tuple(position), tuple(orientation),
                          tuple(world_from_base.T @ linear_world),
                          tuple(world_from_base.T @ np.asarray(angular_world)))

    def can_pose(self) -> Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]:
        """Position of the can's centre (m) and its orientation (quaternion xyzw), world frame."""
        position, orientation = self._client.getBasePositionAndOrientation(self._can)
        return tuple(position), tuple(orientation)

    def touched_objects(self) -> FrozenSet[str]:
        """Names of everything but the floor the robot touched in the last step ('can', wall
        and obstacle names)."""
        return self.touches()[0]

    def touches(self) -> Tuple[FrozenSet[str], bool]:
        """(:meth:`touched_objects`, whether any of those touches is on the front half of the
        robot: ahead of base_link along its heading, where a bumper is)."""
        names, points = set(), []
        for point in self._client.getContactPoints(bodyA=self._robot):
            if point[8] > CONTACT_TOLERANCE_M or point[2] == self._floor:
                continue
            names.add('can' if point[2] == self._can else self._solids.get(point[2], 'unknown'))
            points.append(point[5])
        if not points:
            return frozenset(), False
        robot_x_m, robot_y_m, yaw_rad = self.robot_pose()
        heading = (math.cos(yaw_rad), math.sin(yaw_rad))
        front = any((x - robot_x_m) * heading[0] + (y - robot_y_m) * heading[1] > 0.0
                    for x, y, _ in points)
        return frozenset(names), front

    def robot_touches_can(self) -> bool:
        """Whether any part of the robot touched the can in the last step."""
        return 'can' in self.touched_objects()

    def scan(self, lidar: LidarSpec) -> np.ndarray:
        """Ranges (m) of a lidar on the robot (see :class:`LidarSpec`), from ray casts against
        every body; the robot's own body lies below the beams."""
        starts, ends = lidar.rays(*self.robot_pose())
        hits = self._client.rayTestBatch(starts.tolist(), ends.tolist())
        return lidar.ranges([hit[2] if hit[0] >= 0 else 1.0 for hit in hits])

    def set_mount(self, mount: CameraMount) -> None:
        """Move the camera to ``mount`` (the images follow; the robot's body keeps its look)."""
        self.camera = replace(self.camera, mount=mount)

    def camera_pose(self) -> Tuple[np.ndarray, np.ndarray]:
        """camera_link position (m) and rotation matrix (columns x forward, y left, z up), world."""
        state = self.robot_state()
        mount = self.camera.mount
        position, orientation = self._client.multiplyTransforms(
            state.position, state.orientation_xyzw, mount.translation_m, mount.rotation_xyzw)
        return np.asarray(position), quaternion_matrix(*orientation)

    def render_rgba(self, light_direction: Optional[Sequence[float]] = None) -> np.ndarray:
        """The camera image as an HxWx4 uint8 RGBA array, lit from ``light_direction`` (a
        vector toward the light, world frame) or by the renderer's fixed light."""
        return self._camera_image(pybullet.ER_NO_SEGMENTATION_MASK, light_direction)[0]

    def render_segmented(self, encoding: str = 'bgr8') -> Tuple[np.ndarray, Dict[str, np.ndarray]]:
        """(image as :meth:`render`, {name: boolean HxW mask of its pixels}) for 'floor', 'can',
        'robot' and every wall and obstacle of the scene in view."""
        rgba, segmentation = self._camera_image(0, None)
        names = {**self._solids, self._can: 'can', self._robot: 'robot'}
        if self._floor is not None:
            names[self._floor] = 'floor'
        body = np.asarray(segmentation).reshape(rgba.shape[:2]) & SEGMENTATION_BODY_MASK
        masks = {names[int(index)]: body == index for index in np.unique(body)
                 if int(index) in names}
        return rgba_to_image(rgba, encoding), masks

    def _camera_image(self, flags: int, light_direction: Optional[Sequence[float]],
                      margin_px: int = 0):
        """(HxWx4 uint8 RGBA, segmentation) of the camera, rendered with pybullet ``flags``,
        ``margin_px`` larger on every side at the same focal length."""
        client = self._client
        eye, rotation = self.camera_pose()
        view = client.computeViewMatrix(eye.tolist(), (eye + rotation[:, 0]).tolist(),
                                        rotation[:, 2].tolist())
        camera = self.camera
        width, height = camera.width + 2 * margin_px, camera.height + 2 * margin_px
        fov_deg = math.degrees(2.0 * math.atan(
            height / camera.height * math.tan(math.radians(camera.fov_deg) / 2.0)))
        projection = client.computeProjectionMatrixFOV(fov_deg, width / height,
                                                       CLIP_NEAR_M, CLIP_FAR_M)
        renderer = (pybullet.ER_TINY_RENDERER if self.renderer_name == 'tiny'
                    else pybullet.ER_BULLET_HARDWARE_OPENGL)
        lighting = {} if light_direction is None else {'lightDirection': list(light_direction)}
        _, _, rgba, _, segmentation = client.getCameraImage(
            width, height, view, projection, renderer=renderer, flags=flags, **lighting)
        return np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4), segmentation

    def render(self, encoding: str = 'bgr8',
               light_direction: Optional[Sequence[float]] = None,
               margin_px: int = 0) -> np.ndarray:
        """The camera image as an HxWx3 uint8 array in ``encoding`` ('bgr8' or 'rgb8'), lit as
        in :meth:`render_rgba`; ``margin_px`` larger on every side at the same focal length
        (the view a lens that bends rays sees beyond the pinhole one)."""
        rgba = self._camera_image(pybullet.ER_NO_SEGMENTATION_MASK, light_direction,
                                  margin_px)[0]
        return rgba_to_image(rgba, encoding)

    def close(self):
        """Disconnect from pybullet (the world is unusable afterwards)."""
        if self._texture_dir is not None:
            shutil.rmtree(self._texture_dir, ignore_errors=True)
            self._texture_dir = None
        if self._client is not None:
            if self._egl_plugin >= 0:
                self._client.unloadPlugin(self._egl_plugin)
            self._client.disconnect()
            self._client = None

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()
