"""The robot's visual geometry, as Pinocchio reads it from the URDF, in plain arrays.

Pinocchio builds the visual :class:`pinocchio.GeometryModel` (primitives, and meshes of any
format its mesh loader reads: STL, OBJ, COLLADA, ...) from bounded copies of the meshes the URDF
names, each confined to the robot's description
(:func:`~scalf_opt.model.urdf_file.with_local_meshes`). Each geometry object
becomes a :class:`Visual`: a primitive's dimensions or a mesh's vertices and triangles (the
URDF's mesh scale applied), its colour, its parent joint and its placement in that joint's frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import pinocchio as pin

from scalf_opt.errors import ModelError, ScalfError
from scalf_opt.files import captured_native_output, scratch_folder
from scalf_opt.model.robot import Robot
from scalf_opt.model.urdf_file import read_urdf_text, with_local_meshes

Shape = Literal["box", "cylinder", "sphere", "ellipsoid", "mesh"]


@dataclass(frozen=True)
class Visual:
    """One visual element of the robot.

    Attributes:
        name: Pinocchio's geometry name (``<link>_<index>``).
        parent_joint: Index of the joint it moves with in ``robot.model``.
        placement: Homogeneous transform from the parent joint's frame to the geometry's frame,
            shape (4, 4) [m].
        shape: ``box``, ``cylinder`` (axis z), ``sphere``, ``ellipsoid`` or ``mesh``.
        size: Box edge lengths (x, y, z); cylinder (radius, length); sphere (radius,); ellipsoid
            radii (x, y, z) [m]; empty for a mesh.
        vertices: Mesh vertices in the geometry frame, shape (n, 3) [m] (empty otherwise).
        faces: Mesh triangles as vertex indices, shape (m, 3) (empty otherwise).
        rgba: Colour and opacity, each in [0, 1].
    """

    name: str
    parent_joint: int
    placement: np.ndarray
    shape: Shape
    size: tuple[float, ...]
    vertices: np.ndarray
    faces: np.ndarray
    rgba: tuple[float, float, float, float]


def description_packages() -> dict[str, Path]:
    """Robot description packages without a ``package.xml``, by name: example-robot-data's.

    Each ``robots/<name>_description`` folder of example-robot-data is the package its URDFs
    call ``package://<name>_description``.
    """
    try:
        from scalf_opt.robots.example_robot_data import example_robot_data_dir

        robots = example_robot_data_dir()
    except ScalfError:
        return {}  # not installed: only real packages and the URDF's own folder
    return {folder.name: folder for folder in sorted(robots.iterdir()) if folder.is_dir()}


def variant_parent_urdf(urdf: Path) -> Path | None:
    """The URDF a variant was derived from (its record beside it), else ``None``.

    A variant keeps its parent's ``package://`` mesh references; they resolve in the parent's
    description (:func:`~scalf_opt.model.urdf_file.resolve_mesh`).

    Raises:
        ConfigError: The variant's record cannot be read.
    """
    from scalf_opt.robots.loading import load_robot
    from scalf_opt.robots.variants import read_variant_record, variant_record_for

    record_path = variant_record_for(urdf)
    if not record_path.exists():
        return None
    record = read_variant_record(record_path)
    if record.parent_urdf is not None:
        return record.parent_urdf
    assert record.parent_robot is not None
    return load_robot(record.parent_robot).urdf_path


def visual_model(robot: Robot) -> pin.GeometryModel:
    """Pinocchio's visual geometry model of ``robot``, from the URDF text that passed the checks.

    Every mesh reference must stay inside the robot's description, and the meshes are read
    with a size bound into a private folder
    (:func:`~scalf_opt.model.urdf_file.with_local_meshes`); Pinocchio is given the checked text
    with every mesh reference replaced by its copy, and reads nothing else. What the mesh loader
    prints is caught.

    Raises:
        ModelError: A mesh leaves its folder, is too large, or cannot be found or read (the
            message names the URDF or the mesh).
    """
    text = read_urdf_text(robot.urdf_path)
    parent = variant_parent_urdf(robot.urdf_path)
    with scratch_folder("meshes") as folder:
        local = with_local_meshes(robot.urdf_path, text, description_packages(), folder, parent)
        try:
            with captured_native_output() as printed:
                return pin.buildGeomFromUrdfString(robot.model, local, pin.GeometryType.VISUAL)
        except (RuntimeError, ValueError, OSError) as exc:
            lines = [line for line in (str(exc), *printed) if line.strip()]
            first = lines[0].strip().splitlines()[0][:300] if lines else type(exc).__name__
            raise ModelError(
                f"{robot.urdf_path}: cannot load its visual geometry ({first})"
            ) from exc


def load_visuals(robot: Robot) -> tuple[list[Visual], list[str]]:
    """The robot's visuals, and the names of those whose geometry type cannot be drawn."""
    visuals, skipped = [], []
    for obj in visual_model(robot).geometryObjects:
        visual = _visual(obj)
        if visual is None:
            skipped.append(str(obj.name))
        else:
            visuals.append(visual)
    return visuals, skipped


def _visual(obj: pin.GeometryObject) -> Visual | None:
    geometry = obj.geometry
    kind = type(geometry).__name__
    empty = np.zeros((0, 3))
    size: tuple[float, ...] = ()
    vertices, faces = empty, np.zeros((0, 3), dtype=np.uint32)
    shape: Shape
    if kind == "Box":
        shape, size = "box", tuple(float(v) for v in 2.0 * np.asarray(geometry.halfSide))
    elif kind == "Cylinder":
        shape, size = "cylinder", (float(geometry.radius), 2.0 * float(geometry.halfLength))
    elif kind == "Sphere":
        shape, size = "sphere", (float(geometry.radius),)
    elif kind == "Ellipsoid":
        shape, size = "ellipsoid", tuple(float(v) for v in np.asarray(geometry.radii))
    elif hasattr(geometry, "num_tris") and hasattr(geometry, "tri_indices"):
        shape = "mesh"
        vertices = np.array(geometry.vertices(), dtype=float).reshape(-1, 3)
        triangles = (geometry.tri_indices(i) for i in range(geometry.num_tris))
        faces = np.array([[t[0], t[1], t[2]] for t in triangles], dtype=np.uint32).reshape(-1, 3)
    else:
        return None
    rgba = np.clip(np.asarray(obj.meshColor, dtype=float), 0.0, 1.0)
    return Visual(
        name=str(obj.name),
        parent_joint=int(obj.parentJoint),
        placement=np.array(obj.placement.homogeneous, dtype=float),
        shape=shape,
        size=size,
        vertices=vertices,
        faces=faces,
        rgba=(float(rgba[0]), float(rgba[1]), float(rgba[2]), float(rgba[3])),
    )
