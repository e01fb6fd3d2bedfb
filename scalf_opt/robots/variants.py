r"""URDF-driven leg variants: a robot with longer or shorter, heavier or lighter legs, as a URDF.

A variant is derived from a robot's URDF with yourdfpy. Every leg's thigh (the link the hip-pitch
joint moves) and shank (the link the knee moves) is *stretched along its axis*: the unit vector
``d`` from the link's joint to the next joint (thigh: the knee; shank: the foot), in the link's
frame. With the length scale ``s`` and the mass scale ``mu`` of that link, and
``S = 1 + (s - 1) d d^T`` the stretch:

* every point of the link moves to ``S p``: the child joints' origins (the knee, the foot, any
  fixed child), the COM ``c -> S c`` and the visual and collision origins; so the link length
  becomes ``s L`` and the joint placements and foot frames follow;
* the mass becomes ``mu m``;
* the inertia follows from the second moment of the mass distribution about the COM,
  ``Sigma = tr(I) / 2 * 1 - I``: ``Sigma' = mu S Sigma S^T`` and ``I' = tr(Sigma') * 1 - Sigma'``.
  A slender link's moments across its axis scale with ``mu s^2`` (the ``m L^2`` law), the moment
  about its axis with ``mu`` only; a stretched real body stays a real body (``Sigma'`` stays
  positive definite), so the variant always passes the physical-inertia check;
* boxes, cylinders and meshes aligned with ``d`` are stretched along it; other shapes keep their
  size (they are only drawn).

A leg's thigh is every link the hip-pitch joint moves rigidly (its child link and the links fixed
to it, up to the knee: ANYmal's knee drive housing is one), its shank every link the knee moves
rigidly (the foot included); a link placed at rotation ``R`` in its segment is stretched along
``R^T d`` in its own frame, which keeps the segment one rigid, stretched body. The trunk (the root
link and the links fixed to it) scales its masses and inertias with the trunk mass scale (its COM
and shape stay). Other links (hip housings) do not change. A link whose scales are both 1 is not
touched, so all scales 1 give back the original robot (its energies to round-off).

Files beside the variant: the robot's actuator file (``<variant>_actuators.toml``), whose
cylinder mounts *stay* (the same cylinders at the same mounting points near the joints, so each
joint keeps its length-to-angle map, stroke and force), its legs file and its SRDF (the standing
posture keeps its joint angles). A variant without an SRDF stands like SCalf scaled to its leg
length (:func:`~scalf_opt.robots.similarity.similar_stance_height_m`).
"""

from __future__ import annotations

import io
import math
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from scalf_opt.actuators.sidecar import robot_sidecar_path, sidecar_path_for
from scalf_opt.errors import ConfigError, ModelError
from scalf_opt.files import MAX_TOML_BYTES, read_toml, read_untrusted_text, write_atomic
from scalf_opt.interrupts import signals_held
from scalf_opt.model.inertia import inertia_problems
from scalf_opt.model.naming import legs_file_for
from scalf_opt.model.robot import Robot
from scalf_opt.model.urdf_file import read_srdf_text, read_urdf_text
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.types import LEG_NAMES

ALIGNED_TOLERANCE = 1e-9
"""How close to a shape's axis the stretch direction must be for the shape to be stretched."""


@dataclass(frozen=True)
class VariantScales:
    """Scale factors of a variant (1 keeps the original).

    Attributes:
        thigh_length_scale: Thigh length (hip-pitch axis to knee axis).
        shank_length_scale: Shank length (knee axis to foot).
        thigh_mass_scale: Thigh mass.
        shank_mass_scale: Shank mass.
        trunk_mass_scale: Trunk mass (and inertia).
    """

    thigh_length_scale: float = 1.0
    shank_length_scale: float = 1.0
    thigh_mass_scale: float = 1.0
    shank_mass_scale: float = 1.0
    trunk_mass_scale: float = 1.0

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            ok = isinstance(value, int | float) and not isinstance(value, bool)
            if not (ok and math.isfinite(value) and value > 0):
                raise ConfigError(
                    f"variant field {name} = {value!r} must be a finite number > 0", field=name
                )

    @classmethod
    def field_names(cls) -> tuple[str, ...]:
        """The scale names, in order."""
        return tuple(f.name for f in fields(cls))

    @classmethod
    def from_mapping(cls, values: dict[str, Any], source: str = "variant") -> VariantScales:
        """Scales from plain data, naming an unknown field.

        Raises:
            ConfigError: An unknown field or a value that is not a positive number.
        """
        unknown = sorted(set(values) - set(cls.field_names()))
        if unknown:
            raise ConfigError(
                f"{source}: unknown variant field {unknown[0]!r} "
                f"(known: {', '.join(cls.field_names())})"
            )
        return cls(**values)

    @property
    def is_identity(self) -> bool:
        """Every scale is 1: the variant is the original."""
        return all(v == 1.0 for v in asdict(self).values())


@dataclass(frozen=True)
class Variant:
    """A written variant.

    Attributes:
        urdf_path: The variant's URDF.
        source: The URDF it was derived from.
        scales: Its scales.
        written: Every file written (the URDF first).
    """

    urdf_path: Path
    source: Path
    scales: VariantScales
    written: tuple[Path, ...]


def stretch_matrix(direction: np.ndarray, scale: float) -> np.ndarray:
    """``S = 1 + (s - 1) d d^T``: stretch by ``s`` along the unit vector ``d``."""
    d = np.asarray(direction, dtype=float)
    return np.eye(3) + (scale - 1.0) * np.outer(d, d)


def stretched_inertia(inertia: np.ndarray, stretch: np.ndarray, mass_scale: float) -> np.ndarray:
    """Inertia about the COM of a body stretched by ``S`` with its mass times ``mu`` [kg m^2].

    ``Sigma = tr(I) / 2 - I`` is the second moment of the mass about the COM; it transforms as
    ``mu S Sigma S^T`` and gives back ``I' = tr(Sigma') - Sigma'``.
    """
    second = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    second = mass_scale * stretch @ second @ stretch.T
    return np.trace(second) * np.eye(3) - second


def _origin(element: Any) -> np.ndarray:
    return np.eye(4) if element.origin is None else np.array(element.origin, dtype=float)


def _stretch_shape(geometry: Any, direction: np.ndarray, scale: float) -> None:
    """Stretch a box, cylinder or mesh along ``direction`` (in its frame) when aligned with it."""
    axis = int(np.argmax(np.abs(direction)))
    if abs(abs(direction[axis]) - 1.0) > ALIGNED_TOLERANCE:
        return
    if geometry.box is not None:
        geometry.box.size = np.array(geometry.box.size, dtype=float)
        geometry.box.size[axis] *= scale
    elif geometry.cylinder is not None and axis == 2:
        geometry.cylinder.length *= scale
    elif geometry.mesh is not None:
        mesh_scale = np.ones(3) if geometry.mesh.scale is None else geometry.mesh.scale
        mesh_scale = np.broadcast_to(np.asarray(mesh_scale, dtype=float), (3,)).copy()
        mesh_scale[axis] *= scale
        geometry.mesh.scale = mesh_scale


def _scale_link(
    link: Any,
    children: list[Any],
    direction: np.ndarray,
    length_scale: float,
    mass_scale: float,
) -> None:
    """Stretch ``link`` (its inertial, shapes and child joints) and scale its mass."""
    if length_scale == 1.0 and mass_scale == 1.0:
        return
    stretch = stretch_matrix(direction, length_scale)
    if link.inertial is not None:
        origin = _origin(link.inertial)
        rotation = origin[:3, :3]
        origin[:3, 3] = stretch @ origin[:3, 3]
        link.inertial.origin = origin
        if link.inertial.mass is not None:
            link.inertial.mass = float(link.inertial.mass) * mass_scale
        if link.inertial.inertia is not None:
            in_link = rotation @ np.array(link.inertial.inertia, dtype=float) @ rotation.T
            scaled = stretched_inertia(in_link, stretch, mass_scale)
            link.inertial.inertia = rotation.T @ scaled @ rotation
    for shape in [*link.visuals, *link.collisions]:
        origin = _origin(shape)
        origin[:3, 3] = stretch @ origin[:3, 3]
        shape.origin = origin
        if shape.geometry is not None:
            _stretch_shape(shape.geometry, origin[:3, :3].T @ direction, length_scale)
    for joint in children:
        origin = _origin(joint)
        origin[:3, 3] = stretch @ origin[:3, 3]
        joint.origin = origin


def _segment(urdf: Any, start: str) -> dict[str, np.ndarray]:
    """The links rigidly fixed to ``start`` (through fixed joints), with their placement in it."""
    out = {start: np.eye(4)}
    todo = [start]
    while todo:
        parent = todo.pop()
        for joint in urdf.joints:
            if joint.parent == parent and joint.type == "fixed" and joint.child not in out:
                out[joint.child] = out[parent] @ _origin(joint)
                todo.append(joint.child)
    return out


def _direction(point: np.ndarray, what: str, source: Path) -> np.ndarray:
    norm = float(np.linalg.norm(point))
    if norm == 0.0:
        raise ModelError(f"{source}: {what} sits on the axis of the joint that moves it")
    return point / norm


def _scale_segment(
    urdf: Any,
    segment: dict[str, np.ndarray],
    direction: np.ndarray,
    length_scale: float,
    mass_scale: float,
) -> None:
    """Stretch every link of a rigid segment along ``direction`` (in the segment's first frame).

    A link placed at ``R`` in the segment is stretched along ``R^T d`` in its own frame; its
    joints (fixed ones inside the segment, and the next moving joint) move with it.
    """
    links = {link.name: link for link in urdf.links}
    for name, placement in segment.items():
        children = [j for j in urdf.joints if j.parent == name]
        local = placement[:3, :3].T @ direction
        _scale_link(links[name], children, local, length_scale, mass_scale)


def _frame_position(urdf: Any, segment: dict[str, np.ndarray], frame: str) -> np.ndarray | None:
    """Position of a link or joint named ``frame`` in the segment's first frame, if it is in it."""
    if frame in segment:
        return segment[frame][:3, 3]
    for joint in urdf.joints:
        if joint.name == frame and joint.parent in segment:
            return (segment[joint.parent] @ _origin(joint))[:3, 3]
    return None


def _root_link(robot_urdf: Any) -> Any:
    children = {j.child for j in robot_urdf.joints}
    roots = [link for link in robot_urdf.links if link.name not in children]
    return roots[0]


def variant_xml(robot: Robot, scales: VariantScales) -> str:
    """The URDF text of a variant of ``robot`` (nothing written).

    A leg's *thigh* is every link the hip-pitch joint moves rigidly (the links fixed to its child
    link), up to the knee; its *shank* every link the knee moves rigidly, the foot included.

    Raises:
        ModelError: A leg's knee does not hang from its thigh, its foot not from its shank, or
            a joint or foot sits on the axis that moves it (no length to stretch).
    """
    with signals_held():  # it imports trimesh, which may load native code: see signals_held
        import yourdfpy  # imported here: a second URDF parser, needed only for variants
    from lxml import etree

    source = robot.urdf_path
    checked = io.BytesIO(read_urdf_text(source).encode("utf-8"))  # not the file again: its text
    urdf = yourdfpy.URDF.load(
        checked,
        build_scene_graph=False,
        build_collision_scene_graph=False,
        load_meshes=False,
        load_collision_meshes=False,
        filename_handler=lambda filename: filename,  # no mesh is looked for: kept as written
    )
    joints = {joint.name: joint for joint in urdf.robot.joints}
    for leg in LEG_NAMES:
        names = robot.naming.names(leg)
        thigh = _segment(urdf.robot, joints[names.pitch].child)
        knee = joints[names.knee]
        if knee.parent not in thigh:
            raise ModelError(
                f"{source}: leg {leg}'s knee {knee.name} hangs from {knee.parent}, which the "
                f"hip-pitch joint {names.pitch} does not move rigidly"
            )
        knee_at = (thigh[knee.parent] @ _origin(knee))[:3, 3]
        shank = _segment(urdf.robot, knee.child)
        foot_at = _frame_position(urdf.robot, shank, names.foot)
        if foot_at is None:
            raise ModelError(
                f"{source}: leg {leg}'s foot {names.foot} is not fixed to the link the knee moves"
            )
        _scale_segment(
            urdf.robot,
            thigh,
            _direction(knee_at, f"leg {leg}'s knee", source),
            scales.thigh_length_scale,
            scales.thigh_mass_scale,
        )
        _scale_segment(
            urdf.robot,
            shank,
            _direction(foot_at, f"leg {leg}'s foot", source),
            scales.shank_length_scale,
            scales.shank_mass_scale,
        )
    if scales.trunk_mass_scale != 1.0:
        links = {link.name: link for link in urdf.robot.links}
        for name in _segment(urdf.robot, _root_link(urdf.robot).name):
            inertial = links[name].inertial
            if inertial is not None and inertial.mass is not None:
                inertial.mass = float(inertial.mass) * scales.trunk_mass_scale
                if inertial.inertia is not None:
                    inertial.inertia = np.array(inertial.inertia) * scales.trunk_mass_scale
    tree = urdf.write_xml()
    _keep_mesh_references(source, tree.getroot())
    note = ", ".join(f"{k} {v:g}" for k, v in asdict(scales).items())
    tree.getroot().insert(
        0, etree.Comment(f" variant of {source.name} by scalf-opt variant: {note} ")
    )
    return str(etree.tostring(tree, pretty_print=True, encoding="unicode"))


def _mesh_references(root: Any) -> dict[tuple[str, str, int], Any]:
    """Every ``<mesh>`` element of a URDF tree by (link, visual or collision, index)."""
    found = {}
    for link in root.iter("link"):
        for kind in ("visual", "collision"):
            for i, element in enumerate(link.findall(kind)):
                mesh = element.find("geometry/mesh")
                if mesh is not None:
                    found[(link.get("name"), kind, i)] = mesh
    return found


def _keep_mesh_references(source: Path, root: Any) -> None:
    """Write each mesh reference as the original URDF has it.

    A ``package://`` reference stays one, not the absolute path the URDF parser resolved it to,
    so the variant's meshes are found the way the original's are, wherever it is written.
    example-robot-data's own ``package://example-robot-data/robots/NAME/...`` becomes
    ``package://NAME/...``, the robot description's package, which is found from anywhere.
    """
    from defusedxml.ElementTree import fromstring

    original = fromstring(source.read_bytes(), forbid_dtd=True)
    before = _mesh_references(original)
    for key, mesh in _mesh_references(root).items():
        if key in before:
            filename = before[key].get("filename", "")
            mesh.set("filename", filename.replace(ERD_PACKAGE, "package://", 1))


ERD_PACKAGE = "package://example-robot-data/robots/"
"""How example-robot-data's URDFs name their own meshes."""


def _check_relative_meshes(robot: Robot, out: Path) -> None:
    """A mesh given relative to the original's folder is reachable only from that folder."""
    from defusedxml.ElementTree import fromstring

    if out.resolve().parent == robot.urdf_path.resolve().parent:
        return
    root = fromstring(robot.urdf_path.read_bytes(), forbid_dtd=True)
    for mesh in root.iter("mesh"):
        filename = mesh.get("filename", "")
        if "://" not in filename:
            raise ConfigError(
                f"{out}: {robot.urdf_path.name} names its mesh {filename!r} relative to its own "
                f"folder; write the variant into {robot.urdf_path.parent} so that it stays "
                "reachable"
            )


VARIANT_RECORD_SUFFIX = "_variant.toml"


def variant_record_for(urdf_path: Path) -> Path:
    """The record of a variant's parent and scales: ``<urdf stem>_variant.toml`` beside it."""
    return urdf_path.with_name(f"{urdf_path.stem}{VARIANT_RECORD_SUFFIX}")


def _record_text(robot: Robot, scales: VariantScales, out: Path) -> str:
    known = CATALOG.get(robot.name)
    if known is not None and robot.parent is None and known.urdf() == robot.urdf_path:
        parent = f'parent_robot = "{robot.name}"     # a catalog robot'
    else:
        parent = f'parent_urdf = "{robot.urdf_path.resolve().as_posix()}"'
    lines = [
        f"# {out.name} is a variant of {robot.name}, written by scalf-opt variant. It walks its",
        "# parent's default trot (a gait file or gait options still win), so that its energy",
        "# differs from the parent's only through the scales below.",
        "[variant]",
        parent,
        *(f"{name} = {value!r}" for name, value in asdict(scales).items()),
    ]
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class VariantRecord:
    """What a variant's record says.

    Attributes:
        parent_robot: The parent's catalog name, if it is a catalog robot.
        parent_urdf: The parent's URDF otherwise.
        scales: The scales that made the variant.
    """

    parent_robot: str | None
    parent_urdf: Path | None
    scales: VariantScales


def read_variant_record(path: Path) -> VariantRecord:
    """Read a variant record.

    Raises:
        ConfigError: Not a record: unknown keys, no parent or two, a parent file that is missing.
    """
    data = read_toml(path, "variant record")
    table = data.get("variant")
    if set(data) != {"variant"} or not isinstance(table, dict):
        raise ConfigError(f"{path}: a variant record has one [variant] table")
    parent_robot = table.pop("parent_robot", None)
    parent_urdf = table.pop("parent_urdf", None)
    if (parent_robot is None) == (parent_urdf is None):
        raise ConfigError(f"{path}: give parent_robot or parent_urdf (one of them)")
    if parent_robot is not None and parent_robot not in CATALOG:
        raise ConfigError(f"{path}: parent_robot {parent_robot!r} is not a known robot")
    urdf = None
    if parent_urdf is not None:
        urdf = (path.parent / str(parent_urdf)).resolve()
        if not urdf.is_file():
            raise ConfigError(f"{path}: parent_urdf {parent_urdf!r}: no such file")
    return VariantRecord(parent_robot, urdf, VariantScales.from_mapping(table, str(path)))


def _check_physical(xml: str, out: Path) -> None:
    model = pin.buildModelFromXML(xml)
    problems = inertia_problems(model)
    if problems:
        raise ModelError(f"{out}: the variant has an unphysical inertia ({problems[0]})")


def derive_variant(robot: Robot, scales: VariantScales, out: str | Path) -> Variant:
    """Write a variant of ``robot`` to ``out`` (a ``.urdf`` path) and its files beside it.

    The URDF is checked (Pinocchio reads it, every inertia is physical) before anything is
    written; every file is written atomically.

    Raises:
        ConfigError: ``out`` is not a ``.urdf`` path or is the robot's own URDF.
        ModelError: See :func:`variant_xml`.
    """
    out = Path(out)
    if out.suffix != ".urdf":
        raise ConfigError(f"{out}: the variant's file name must end in .urdf")
    if out.resolve() == robot.urdf_path.resolve():
        raise ConfigError(f"{out}: is the robot's own URDF; write the variant elsewhere")
    _check_relative_meshes(robot, out)
    xml = variant_xml(robot, scales)
    _check_physical(xml, out)
    header = (
        f"# Copied from {{src}} by scalf-opt variant ({out.name}). The cylinder mounts stay:\n"
        "# the same cylinders at the same mounting points, whatever the link lengths.\n"
    )
    extras = []
    actuators = robot_sidecar_path(robot)
    if actuators is not None:
        text = header.format(src=actuators.name) + read_untrusted_text(
            actuators, "actuator", MAX_TOML_BYTES
        )
        extras.append((sidecar_path_for(out), text))
    legs = legs_file_for(robot.urdf_path)
    if legs.exists():
        extras.append((legs_file_for(out), read_untrusted_text(legs, "legs", MAX_TOML_BYTES)))
    srdf = _srdf_of(robot)
    if srdf is not None:
        extras.append((out.with_suffix(".srdf"), read_srdf_text(srdf)))
    extras.append((variant_record_for(out), _record_text(robot, scales, out)))
    written = [write_atomic(out, xml)]
    written += [write_atomic(path, text) for path, text in extras]
    return Variant(out, robot.urdf_path, scales, tuple(written))


def _srdf_of(robot: Robot) -> Path | None:
    """The SRDF the robot's standing posture came from, if any (catalog or beside the URDF)."""
    if robot.reference_q is None:
        return None
    known = CATALOG.get(robot.name)
    if known is not None and known.srdf is not None and known.urdf() == robot.urdf_path:
        return known.srdf()
    beside = robot.urdf_path.with_suffix(".srdf")
    return beside if beside.is_file() else None
