"""The 3-D scene of robots walking their foot paths, as meshcat commands (no server needed).

meshcat's viewer (three.js) is driven by msgpack-encoded commands: ``set_object``,
``set_transform``, ``set_property`` and ``set_animation``. This module builds those commands with
meshcat's own classes and packs them; :mod:`scalf_opt.viz.html` embeds them in one page with the
viewer's bundled JavaScript, so the page needs neither a server nor a network.

Scene: a ground plane at z = 0; per trajectory, one robot (Pinocchio's visuals from the URDF)
walking ``n_cycles`` gait cycles along +x, robots side by side along +y in the order given (the
first nearest to the camera); the foot path of every leg as a tube, in the trajectory's colour
or coloured by the leg's power; one animation clip per visual element, keyed at
``frame_rate_hz``, that loops forever. :func:`build_scene` walks sagittal cycles
(:class:`~scalf_opt.viz.walk.Walk`); :func:`compose_scene` draws any
:class:`~scalf_opt.viz.walk.Walker` (a 3-D whole-body plan's:
:func:`~scalf_opt.viz.whole_body_walk.build_plan_scene`).
"""

from __future__ import annotations

import uuid
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin
import umsgpack
from meshcat.animation import AnimationClip, AnimationTrack
from meshcat.commands import SetAnimation, SetObject, SetProperty, SetTransform
from meshcat.path import Path as MeshcatPath

from scalf_opt.errors import ConfigError
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES
from scalf_opt.viz.colors import hex_rgb, trajectory_color
from scalf_opt.viz.trajectories import Trajectory
from scalf_opt.viz.visuals import Visual, load_visuals
from scalf_opt.viz.walk import Walk, Walker

ColorBy = Literal["trajectory", "power"]

POWER_COLORMAP = "viridis"
"""Colour map of the power colouring (perceptually uniform, legible in grey)."""

_TUBE_SIDES = 10

SAGITTAL_POWER_NOTE = "hip + knee, losses included"
"""What a sagittal leg's power sums, in the legend's words."""


@dataclass(frozen=True)
class SceneOptions:
    """How the scene is built.

    Attributes:
        n_cycles: Gait cycles each robot walks (and the animation plays).
        frame_rate_hz: Key frames per second of walk time [Hz].
        color_by: ``trajectory`` (one colour each) or ``power`` (the leg's power along the path).
        playback_speed: Animation time per walk time (1: real time; 0.25: four times slower).
    """

    n_cycles: int = 3
    frame_rate_hz: float = 100.0
    color_by: ColorBy = "trajectory"
    playback_speed: float = 1.0

    def __post_init__(self) -> None:
        if isinstance(self.n_cycles, bool) or not isinstance(self.n_cycles, int):
            raise ConfigError(f"cycles must be an integer, got {self.n_cycles!r}", field="cycles")
        if not 1 <= self.n_cycles <= 50:
            raise ConfigError(f"cycles must be in 1..50, got {self.n_cycles}", field="cycles")
        if not 1.0 <= self.frame_rate_hz <= 1000.0:
            raise ConfigError(f"frame rate must be in [1, 1000] Hz, got {self.frame_rate_hz}")
        if self.color_by not in ("trajectory", "power"):
            raise ConfigError(
                f"color by must be trajectory or power, got {self.color_by!r}", field="color_by"
            )
        if not 0.01 <= self.playback_speed <= 100.0:
            raise ConfigError(
                f"playback speed must be in [0.01, 100], got {self.playback_speed}",
                field="playback_speed",
            )


@dataclass(frozen=True)
class LegendEntry:
    """One trajectory in the page's legend.

    Attributes:
        label: Its name.
        color: Its colour (``#rrggbb``).
        energy_j: Energy of all legs per cycle [J].
        average_power_w: Average total power [W].
        leg_energy_j: Energy per leg [J]: its swing's (a sagittal cycle), or the whole cycle's
            (a 3-D plan), as ``leg_energy_kind`` says.
        lateral_offset_m: Where its robot walks along y [m].
        energy_model: What the energies were evaluated with: the stance loads and the power
            accounting (``whole-body loads, paper accounting``).
        leg_energy_kind: What ``leg_energy_j`` is, in the legend's words (``swing``, ``per leg``).
    """

    label: str
    color: str
    energy_j: float
    average_power_w: float
    leg_energy_j: dict[str, float]
    lateral_offset_m: float
    energy_model: str
    leg_energy_kind: str = "swing"


@dataclass
class Scene:
    """Packed meshcat commands and what the legend says about them.

    Attributes:
        commands: msgpack-encoded commands, in the order the viewer must apply them.
        legend: One entry per trajectory.
        title: One line that names the robot and the gait.
        color_by: How the paths are coloured.
        power_range_w: The power colour scale's ends [W] (``color_by == "power"``).
        skipped_visuals: URDF visuals whose geometry type could not be drawn.
        n_cycles: Cycles walked.
        playback_speed: Animation time per walk time.
        power_note: What the power colouring sums (``hip + knee, losses included``).
    """

    commands: list[bytes] = field(default_factory=list)
    legend: list[LegendEntry] = field(default_factory=list)
    title: str = ""
    color_by: ColorBy = "trajectory"
    power_range_w: tuple[float, float] = (0.0, 0.0)
    skipped_visuals: list[str] = field(default_factory=list)
    n_cycles: int = 3
    playback_speed: float = 1.0
    power_note: str = SAGITTAL_POWER_NOTE


class _Commands:
    """Collects meshcat commands; every scene element gets a deterministic UUID."""

    def __init__(self) -> None:
        self.packed: list[bytes] = []
        self._count = 0

    def _uuid(self) -> str:
        self._count += 1
        return str(uuid.UUID(int=self._count))

    def mesh(self, geometry: mg.Geometry, material: mg.Material) -> mg.Mesh:
        obj = mg.Mesh(geometry, material)
        for element in (obj, geometry, material):
            element.uuid = self._uuid()
        return obj

    def send(self, command: Any) -> None:
        self.packed.append(umsgpack.packb(command.lower()))


def path_of(*parts: str) -> MeshcatPath:
    """A meshcat scene path under ``/meshcat`` (where meshcat-python puts user objects)."""
    return MeshcatPath(("meshcat", *parts))


def viewer_path(*parts: str) -> MeshcatPath:
    """A path of the viewer's own nodes (``Axes``, ``Grid``, ``Cameras``, ``Background``)."""
    return MeshcatPath(parts)


def build_scene(
    robot: Robot,
    trajectories: Sequence[Trajectory],
    options: SceneOptions | None = None,
    loaded: tuple[list[Visual], list[str]] | None = None,
) -> Scene:
    """The scene of ``trajectories`` walked by ``robot``.

    ``loaded``: the robot's :func:`~scalf_opt.viz.visuals.load_visuals`, when loaded already
    (``view`` loads them before it optimizes, so that a bad mesh is refused first).

    Raises:
        ModelError: The robot's visual geometry cannot be loaded.
        ConfigError: No trajectory, or bad options.
    """
    opts = options or SceneOptions()
    if not trajectories:
        raise ConfigError("nothing to show: give at least one trajectory")
    walkers = [t.robot or robot for t in trajectories]
    visuals, skipped = robot_looks(robot, walkers, loaded)
    gait = trajectories[0].cycle.gait
    spacing = max(lateral_spacing_m(walker) for walker in walkers)
    walks = [
        Walk(walker, t.cycle, opts.n_cycles, lateral_offset_m=i * spacing)
        for i, (walker, t) in enumerate(zip(walkers, trajectories, strict=True))
    ]
    legend = [
        LegendEntry(
            label=trajectory.label,
            color=trajectory_color(index),
            energy_j=trajectory.cycle.energy_j,
            average_power_w=trajectory.cycle.average_power_w,
            leg_energy_j={leg: c.swing_energy_j for leg, c in trajectory.cycle.legs.items()},
            lateral_offset_m=walk.lateral_offset_m,
            energy_model=trajectory.energy_model,
        )
        for index, (trajectory, walk) in enumerate(zip(trajectories, walks, strict=True))
    ]
    title = (
        f"{' beside '.join(dict.fromkeys(w.name for w in walkers))}: trot T = "
        f"{gait.period_s:.4g} s, duty {gait.duty_cycle:.4g}, "
        f"S = {gait.step_length_m:.4g} m, H = {gait.clearance_m:.4g} m, "
        f"z0 = {gait.stance_height_m:.4g} m, {gait.speed_m_s:.3g} m/s"
    )
    return compose_scene(walks, visuals, legend, title, opts, skipped)


def compose_scene(
    walks: Sequence[Walker],
    visuals: Sequence[Sequence[Visual]],
    legend: list[LegendEntry],
    title: str,
    opts: SceneOptions,
    skipped: list[str] | None = None,
    power_note: str = SAGITTAL_POWER_NOTE,
) -> Scene:
    """The scene of ``walks`` side by side, whatever walks them (sagittal or 3-D).

    Args:
        walks: One walker per legend entry, at its own lateral offset (the first nearest the
            camera), each walking ``opts.n_cycles`` cycles.
        visuals: Each walker's robot's visuals.
        legend: One entry per walker; entry ``i`` has :func:`trajectory_color` ``(i)``.
        title: The scene's one-line title.
        opts: The scene options.
        skipped: URDF visuals that could not be drawn.
        power_note: What the power colouring sums, for the legend.
    """
    spacing = max(lateral_spacing_m(walk.robot) for walk in walks)
    paths = [w.foot_paths() for w in walks]
    # the scale spans the swings' power: a stance foot rests in one place, only swings draw arcs
    power_max = max(float(p.power_w[p.swing].max()) for legs in paths for p in legs.values())
    power_range = (0.0, power_max if power_max > 0 else 1.0)
    out = _Commands()
    # the viewer's grid and axes sit at its origin, where the camera looks, not on the ground
    out.send(SetProperty("visible", False, viewer_path("Axes")))
    out.send(SetProperty("visible", False, viewer_path("Grid")))
    out.send(SetProperty("top_color", [0.97, 0.97, 0.98], viewer_path("Background")))
    out.send(SetProperty("bottom_color", [0.74, 0.78, 0.85], viewer_path("Background")))
    _send_ground(out, walks, spacing)
    for index, (walk, feet) in enumerate(zip(walks, paths, strict=True)):
        color = trajectory_color(index)
        prefix = ("trajectories", f"{index}")
        _send_robot(out, prefix, visuals[index])
        _send_lane(out, prefix, walk, color, spacing)
        radius = tube_radius_m(walk.stance_height_m)
        for leg, foot in feet.items():
            if opts.color_by == "power":
                colors = power_colors(foot.power_w, power_range)
            else:
                colors = np.tile(hex_rgb(color), (foot.t_s.size, 1))
            vertices, faces, vertex_colors = tube(foot.position_m, radius, colors)
            geometry = mg.TriangularMeshGeometry(vertices, faces, color=vertex_colors)
            material = mg.MeshLambertMaterial(vertexColors=True)
            out.send(SetObject(out.mesh(geometry, material), path=path_of(*prefix, "feet", leg)))
    _send_animation(out, walks, visuals, opts)
    _send_camera(out, walks, spacing)
    return Scene(
        commands=out.packed,
        legend=legend,
        title=title,
        color_by=opts.color_by,
        power_range_w=power_range,
        skipped_visuals=list(skipped or []),
        n_cycles=opts.n_cycles,
        playback_speed=opts.playback_speed,
        power_note=power_note,
    )


def robot_looks(
    robot: Robot, walkers: Sequence[Robot], loaded: tuple[list[Visual], list[str]] | None
) -> tuple[list[list[Visual]], list[str]]:
    """Each walker's visuals (each robot's loaded once), and the names of those not drawn."""
    looks: dict[int, tuple[list[Visual], list[str]]] = {
        id(robot): load_visuals(robot) if loaded is None else loaded
    }
    for walker in walkers:
        if id(walker) not in looks:
            looks[id(walker)] = load_visuals(walker)
    skipped = list(dict.fromkeys(name for _, names in looks.values() for name in names))
    return [looks[id(walker)][0] for walker in walkers], skipped


def lateral_spacing_m(robot: Robot) -> float:
    """Distance between robots walking side by side [m]: their width plus a gap."""
    widths = [abs(robot.leg(leg).hip_origin_m[1]) for leg in ("RF", "LH", "LF", "RH")]
    return 2.0 * max(widths) + 1.0 * (robot.nominal_stance_height_m or 0.5)


def tube_radius_m(stance_height_m: float) -> float:
    """Radius of the foot-path tubes [m]: visible next to the robot, thin beside its feet."""
    return 0.012 * stance_height_m


def power_colors(power_w: np.ndarray, power_range_w: tuple[float, float]) -> np.ndarray:
    """RGB in [0, 1] of each power value on the :data:`POWER_COLORMAP` scale, shape (n, 3)."""
    from matplotlib import colormaps

    lo, hi = power_range_w
    scaled = np.clip((np.asarray(power_w, dtype=float) - lo) / (hi - lo), 0.0, 1.0)
    return np.asarray(colormaps[POWER_COLORMAP](scaled))[:, :3]


def tube(
    points: np.ndarray, radius: float, colors: np.ndarray, sides: int = _TUBE_SIDES
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A closed-ring tube mesh around a polyline, with a colour per point.

    A ring is put at the first point of every arc length ``radius`` along the polyline and at its
    end: closer rings would not show (a swing sampled at a bound's 6.7 kHz made Solo12's view
    19 MB instead of 5 MB), and repeated points (a foot resting in stance) make none.

    Args:
        points: Polyline, shape (n, 3) [m].
        radius: Tube radius [m].
        colors: RGB in [0, 1] per point, shape (n, 3).
        sides: Vertices per ring.

    Returns:
        Vertices (n * sides, 3) [m], triangles (2 * sides * (n - 1), 3), vertex colours
        (n * sides, 3).
    """
    points = np.asarray(points, dtype=float)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    stretch = np.floor(arc / radius)
    keep = np.ones(len(points), dtype=bool)
    keep[1:] = stretch[1:] > stretch[:-1]
    last_kept = np.flatnonzero(keep)[-1]
    keep[-1] = keep[-1] or arc[-1] - arc[last_kept] > 1e-9
    points, colors = points[keep], np.asarray(colors, dtype=float)[keep]
    n = len(points)
    tangent = np.gradient(points, axis=0) if n > 1 else np.array([[1.0, 0.0, 0.0]])
    tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-12)
    reference = np.where(np.abs(tangent[:, 1:2]) < 0.9, [[0.0, 1.0, 0.0]], [[0.0, 0.0, 1.0]])
    normal = np.cross(tangent, reference)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    binormal = np.cross(tangent, normal)
    angles = 2.0 * np.pi * np.arange(sides) / sides
    ring = np.cos(angles)[None, :, None] * normal[:, None, :]
    ring = ring + np.sin(angles)[None, :, None] * binormal[:, None, :]
    vertices = (points[:, None, :] + radius * ring).reshape(-1, 3)
    faces = []
    for i in range(n - 1):
        for k in range(sides):
            a, b = i * sides + k, i * sides + (k + 1) % sides
            c, d = a + sides, b + sides
            faces += [(a, b, d), (a, d, c)]
    return (
        vertices,
        np.array(faces, dtype=np.uint32).reshape(-1, 3),
        np.repeat(colors, sides, axis=0),
    )


def _send_ground(out: _Commands, walks: Sequence[Walker], spacing: float) -> None:
    """A light ground slab whose top is 1 mm below z = 0 (the grid lines stay visible).

    ``spacing``: the lateral distance between the walks [m].
    """
    margin = 3.0 * max(w.trunk_height_m for w in walks)
    x_lo = min(w.x_range_m[0] for w in walks) - margin
    x_hi = max(w.x_range_m[1] for w in walks) + margin
    y_lo = -spacing
    y_hi = max(w.lateral_offset_m for w in walks) - y_lo
    thickness = 0.01
    box = mg.Box([x_hi - x_lo, y_hi - y_lo, thickness])
    material = mg.MeshLambertMaterial(color=0xE9E6DF)
    out.send(SetObject(out.mesh(box, material), path=path_of("ground")))
    center = [(x_lo + x_hi) / 2.0, (y_lo + y_hi) / 2.0, -0.001 - thickness / 2.0]
    out.send(SetTransform(_translation(center), path_of("ground")))


def _send_lane(
    out: _Commands, prefix: tuple[str, ...], walk: Walker, color: str, spacing: float
) -> None:
    """A strip of the trajectory's colour on the ground along the robot's walk (its label)."""
    start, end = walk.x_range_m
    length = end - start
    width, thickness = 0.12 * spacing, 0.001
    rgb = hex_rgb(color)
    material = mg.MeshLambertMaterial(
        color=(round(rgb[0] * 255) << 16) | (round(rgb[1] * 255) << 8) | round(rgb[2] * 255),
        opacity=0.6,
    )
    lane = path_of(*prefix, "lane")
    out.send(SetObject(out.mesh(mg.Box([length, width, thickness]), material), path=lane))
    middle = [(start + end) / 2.0, walk.lateral_offset_m, -0.0009]
    out.send(SetTransform(_translation(middle), lane))


def _send_robot(out: _Commands, prefix: tuple[str, ...], visuals: Sequence[Visual]) -> None:
    """Every visual of one robot; its node is animated, its ``shape`` child fixes the axes."""
    for visual in visuals:
        color = round(visual.rgba[0] * 255) << 16
        color |= round(visual.rgba[1] * 255) << 8
        color |= round(visual.rgba[2] * 255)
        material = mg.MeshPhongMaterial(color=color, opacity=visual.rgba[3])
        intrinsic = np.eye(4)
        if visual.shape == "box":
            geometry: mg.Geometry = mg.Box(list(visual.size))
        elif visual.shape == "cylinder":
            geometry = mg.Cylinder(visual.size[1], visual.size[0])
            intrinsic = _rotation_x(np.pi / 2.0)  # three.js cylinders lie along y, URDF's along z
        elif visual.shape == "sphere":
            geometry = mg.Sphere(visual.size[0])
        elif visual.shape == "ellipsoid":
            geometry = mg.Ellipsoid(list(visual.size))
        else:
            geometry = mg.TriangularMeshGeometry(visual.vertices, visual.faces)
        shape_path = path_of(*prefix, "robot", visual.name, "shape")
        out.send(SetObject(out.mesh(geometry, material), path=shape_path))
        if visual.shape == "cylinder":
            out.send(SetTransform(intrinsic, shape_path))


def _visual_poses(walk: Walker, visuals: Sequence[Visual], times: np.ndarray) -> np.ndarray:
    """World pose of every visual at every time, shape (n_times, n_visuals, 4, 4).

    ``trunk_pose(t) * oMi(q(t)) * placement``: the trunk's whole world pose (rotation included)
    times the visual's pose in the trunk frame by Pinocchio's forward kinematics.
    """
    model = walk.robot.model
    data = model.createData()
    q = walk.configurations(times)
    trunk = walk.trunk_pose(times)
    poses = np.empty((times.size, len(visuals), 4, 4))
    placements = [pin.SE3(v.placement) for v in visuals]
    for f in range(times.size):
        pin.forwardKinematics(model, data, q[f])
        world = pin.SE3(trunk[f])
        for k, (visual, placement) in enumerate(zip(visuals, placements, strict=True)):
            poses[f, k] = (world * data.oMi[visual.parent_joint] * placement).homogeneous
    return poses


def animation_times(walk: Walker, frame_rate_hz: float) -> np.ndarray:
    """The key frames' walk times [s]: evenly over the walk, its ends included."""
    n_frames = max(2, round(walk.duration_s * frame_rate_hz) + 1)
    return np.linspace(0.0, walk.duration_s, n_frames)


def _send_animation(
    out: _Commands,
    walks: Sequence[Walker],
    visuals: Sequence[Sequence[Visual]],
    opts: SceneOptions,
) -> None:
    """Place every visual at its first pose and animate it over its walk, looping.

    Each robot's clips loop over its own walk (walks of different periods loop apart).
    """
    clips: dict[MeshcatPath, AnimationClip] = {}
    for index, (walk, looks) in enumerate(zip(walks, visuals, strict=True)):
        times = animation_times(walk, opts.frame_rate_hz)
        frames = list(range(times.size))
        # three.js plays key ``k`` at k / fps seconds: fps sets the playback speed
        fps = (times.size - 1) / walk.duration_s * opts.playback_speed
        poses = _visual_poses(walk, looks, times)
        for k, visual in enumerate(looks):
            node = path_of("trajectories", f"{index}", "robot", visual.name)
            out.send(SetTransform(poses[0, k], node))
            positions = [[float(v) for v in poses[f, k, :3, 3]] for f in frames]
            quaternions = [_js_quaternion(poses[f, k, :3, :3]) for f in frames]
            clips[node] = AnimationClip(
                tracks={
                    "position": AnimationTrack("position", "vector3", frames, positions),
                    "quaternion": AnimationTrack("quaternion", "quaternion", frames, quaternions),
                },
                fps=fps,
            )

    class _Animation:  # meshcat's Animation.lower() with our clips
        def lower(self) -> list[dict[str, Any]]:
            return [{"path": p.lower(), "clip": c.lower()} for p, c in clips.items()]

    out.send(SetAnimation(_Animation(), play=True, repetitions=float("inf")))


def _send_camera(out: _Commands, walks: Sequence[Walker], spacing: float) -> None:
    """Look at the middle of the foot paths from ahead on the right, above: every robot in sight.

    The scene is shifted so that its middle is at the origin, where the camera looks.
    ``spacing``: the lateral distance between the walks [m].
    """
    height = max(w.trunk_height_m for w in walks)
    x_start = min(w.x_range_m[0] for w in walks)
    x_end = max(w.x_range_m[1] for w in walks)
    hip_x = max(abs(w.robot.leg(leg).hip_origin_m[0]) for w in walks for leg in LEG_NAMES)
    y_max = max(w.lateral_offset_m for w in walks)
    center = np.array([(x_start + x_end) / 2.0, y_max / 2.0, 0.45 * height])
    # what must fit: every foot path along x, every robot along y, a standing robot along z
    span = max(x_end - x_start + 2.0 * hip_x, y_max + spacing, 2.5 * height)
    direction = np.array([0.6, -1.0, 0.55])
    offset = 0.9 * span * direction / np.linalg.norm(direction)
    # the viewer's orbit controls turn about the origin: move the scene so that its middle is there
    out.send(SetTransform(_translation(-center), path_of()))
    # the camera node is rotated so that three.js's y-up is the world's z-up: (x, z, -y)
    position = [float(offset[0]), float(offset[2]), float(-offset[1])]
    out.send(
        SetProperty("position", position, viewer_path("Cameras", "default", "rotated", "<object>"))
    )


def _translation(p: Sequence[float] | np.ndarray) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = p
    return matrix


def _rotation_x(angle: float) -> np.ndarray:
    matrix = np.eye(4)
    c, s = np.cos(angle), np.sin(angle)
    matrix[1:3, 1:3] = [[c, -s], [s, c]]
    return matrix


def _js_quaternion(rotation: np.ndarray) -> list[float]:
    """A rotation matrix as three.js's quaternion ``(x, y, z, w)``."""
    coeffs = pin.Quaternion(np.asarray(rotation)).coeffs()  # Eigen's order: x, y, z, w
    return [float(v) for v in coeffs]
