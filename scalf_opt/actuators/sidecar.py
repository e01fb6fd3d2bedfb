"""The actuator sidecar: a TOML file beside a URDF that says which drive moves which joint.

``<urdf stem>_actuators.toml`` beside the URDF (SCalf: ``urdf/scalf_actuators.toml``) holds a
``[friction.extend]`` and a ``[friction.retract]`` table (keys ``viscous_n_s_per_m``,
``static_n``, ``coulomb_n``, ``stribeck_velocity_m_s``, all > 0) shared by every cylinder, and
one ``[cylinders.<joint>]`` table per joint driven by a hydraulic cylinder (``a_mm``, ``b_mm``,
``stroke_mm`` > 0; ``phi_offset_deg`` any number; ``angle_sign`` +1 or -1; optional limits
``max_force_n`` and ``max_speed_m_s`` > 0, none when left out). Millimetres and degrees are
converted to SI here. A joint the file does not name has an ideal drive; a robot
without a sidecar has ideal drives only.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.actuators.drive import Drive, IdealDrive
from scalf_opt.actuators.stribeck import StribeckBranch, StribeckFriction
from scalf_opt.errors import ConfigError
from scalf_opt.files import read_toml
from scalf_opt.model.robot import Robot

_BRANCH_KEYS = ("viscous_n_s_per_m", "static_n", "coulomb_n", "stribeck_velocity_m_s")
_CYLINDER_KEYS = ("a_mm", "b_mm", "phi_offset_deg", "angle_sign", "stroke_mm")
_CYLINDER_LIMIT_KEYS = ("max_force_n", "max_speed_m_s")
_TOP_KEYS = ("friction", "cylinders")
_FRICTION_KEYS = ("extend", "retract")


def _number(path: Path, key: str, value: Any, positive: bool = True) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or (positive and value <= 0):
        need = "a positive number" if positive else "a number"
        raise ConfigError(f"{path}: {key} must be {need}, got {value!r}")
    return float(value)


def _table(path: Path, parent: dict[str, Any], key: str, name: str) -> dict[str, Any]:
    """``parent[key]`` as a table; ``name`` is its full key path for messages."""
    if key not in parent:
        raise ConfigError(f"{path}: missing table [{name}]")
    value = parent[key]
    if not isinstance(value, dict):
        raise ConfigError(f"{path}: {name} must be a table, got {value!r}")
    return value


def _no_extra(path: Path, table: dict[str, Any], allowed: tuple[str, ...], prefix: str) -> None:
    extra = sorted(set(table) - set(allowed))
    if extra:
        key = f"{prefix}.{extra[0]}" if prefix else extra[0]
        raise ConfigError(f"{path}: unknown key {key} (allowed: {', '.join(allowed)})")


def _branch(path: Path, friction: dict[str, Any], key: str) -> StribeckBranch:
    name = f"friction.{key}"
    table = _table(path, friction, key, name)
    _no_extra(path, table, _BRANCH_KEYS, name)
    values = []
    for field in _BRANCH_KEYS:
        if field not in table:
            raise ConfigError(f"{path}: missing key {name}.{field}")
        values.append(_number(path, f"{name}.{field}", table[field]))
    return StribeckBranch(*values)


def _cylinder(path: Path, joint: str, table: Any, friction: StribeckFriction) -> HydraulicCylinder:
    prefix = f"cylinders.{joint}"
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: {prefix} must be a table, got {table!r}")
    _no_extra(path, table, _CYLINDER_KEYS + _CYLINDER_LIMIT_KEYS, prefix)
    for field in _CYLINDER_KEYS:
        if field not in table:
            raise ConfigError(f"{path}: missing key {prefix}.{field}")
    sign = table["angle_sign"]
    if isinstance(sign, bool) or not isinstance(sign, int) or sign not in (1, -1):
        raise ConfigError(f"{path}: {prefix}.angle_sign must be +1 or -1, got {sign!r}")
    offset_deg = _number(path, f"{prefix}.phi_offset_deg", table["phi_offset_deg"], positive=False)
    limits = {
        key: _number(path, f"{prefix}.{key}", table[key])
        for key in _CYLINDER_LIMIT_KEYS
        if key in table
    }
    return HydraulicCylinder(
        joint_name=joint,
        a_m=_number(path, f"{prefix}.a_mm", table["a_mm"]) * 1e-3,
        b_m=_number(path, f"{prefix}.b_mm", table["b_mm"]) * 1e-3,
        phi_offset_rad=math.radians(offset_deg),
        angle_sign=sign,
        stroke_m=_number(path, f"{prefix}.stroke_mm", table["stroke_mm"]) * 1e-3,
        friction=friction,
        **limits,
    )


def load_sidecar(path: str | Path) -> dict[str, Drive]:
    """Read an actuator sidecar into drives keyed by URDF joint name, in file order.

    Which joints exist is checked against a robot by :func:`drives_for`, not here.

    Raises:
        ConfigError: Unreadable file, TOML syntax error, missing, unknown or invalid key; the
            one-line message names the file and the key path (``cylinders.RF_knee.a_mm``).
    """
    path = Path(path)
    data = read_toml(path, "actuator")
    _no_extra(path, data, _TOP_KEYS, "")
    friction_table = _table(path, data, "friction", "friction")
    _no_extra(path, friction_table, _FRICTION_KEYS, "friction")
    friction = StribeckFriction(
        extend=_branch(path, friction_table, "extend"),
        retract=_branch(path, friction_table, "retract"),
    )
    cylinders = _table(path, data, "cylinders", "cylinders")
    out: dict[str, Drive] = {
        joint: _cylinder(path, joint, table, friction) for joint, table in cylinders.items()
    }
    if not out:
        raise ConfigError(f"{path}: [cylinders] is empty")
    return out


def sidecar_path_for(urdf_path: str | Path) -> Path:
    """The actuator sidecar that belongs to a URDF: ``<name>_actuators.toml`` beside it."""
    urdf_path = Path(urdf_path)
    return urdf_path.with_name(f"{urdf_path.stem}_actuators.toml")


def drives_for(robot: Robot) -> dict[str, Drive]:
    """The robot's drives from the sidecar beside its URDF; ``{}`` when there is none.

    Raises:
        ConfigError: The file is invalid or names a joint the robot does not have.
    """
    path = sidecar_path_for(robot.urdf_path)
    if not path.is_file():
        return {}
    drives = load_sidecar(path)
    for joint in drives:
        if not robot.model.existJointName(joint):
            raise ConfigError(f"{path}: cylinders.{joint} names no joint of {robot.urdf_path}")
    return drives


def leg_drives(drives: dict[str, Drive], joint_names: tuple[str, str]) -> tuple[Drive, Drive]:
    """The drives of a leg's (hip pitch, knee) joints; a joint without one gets an ideal drive."""
    hip, knee = (drives.get(j) or IdealDrive(j) for j in joint_names)
    return hip, knee
