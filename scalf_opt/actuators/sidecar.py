"""The actuator sidecar: a TOML file beside a URDF that says which drive moves which joint.

``<urdf stem>_actuators.toml`` beside the URDF (SCalf: ``urdf/scalf_actuators.toml``; a catalog
robot may name its own file) chooses a drive per joint. Its tables, every one optional:

``[friction.extend]``, ``[friction.retract]``
    Stribeck friction shared by every cylinder (``viscous_n_s_per_m``, ``static_n``,
    ``coulomb_n``, ``stribeck_velocity_m_s``, all > 0); required when a cylinder is not fed by a
    supply (the paper's cylinder model charges its friction heat).
``[cylinders.<joint>]``
    A hydraulic cylinder's mounting (``a_mm``, ``b_mm``, ``stroke_mm`` > 0; ``phi_offset_deg``
    any number; ``angle_sign`` +1 or -1; optional limits ``max_force_n`` and ``max_speed_m_s``
    > 0, none when left out). Alone: SCalf's model, ``|tau qd|`` plus friction
    heat (:class:`~scalf_opt.actuators.cylinder.HydraulicCylinder`).
``[supplies.<name>]``
    A valve-controlled constant-pressure supply (``pressure_bar``, ``bore_mm``, ``rod_mm`` with
    rod < bore) and the ``joints`` it feeds; each needs a ``[cylinders.<joint>]`` table. Those
    cylinders draw pressure x flow
    (:class:`~scalf_opt.actuators.valve_cylinder.ValveControlledCylinder`).
``[electric.<name>]``
    An electric drive (``gear_ratio``, ``torque_constant_nm_per_a`` > 0;
    ``winding_resistance_ohm``, optional ``coulomb_friction_nm`` and
    ``viscous_friction_nm_s_per_rad`` >= 0; optional ``regenerative``, default false) and the
    ``joints`` it drives (:class:`~scalf_opt.actuators.electric.ElectricDrive`).
``[sources]``
    Where each number comes from: ``"<key path>" = "text"``, the path of a parameter
    (``"cylinders.RF_knee.a_mm"``) or of a table, which covers every parameter under it; ``*``
    stands for one path component (``"cylinders.*.a_mm"``). A text that starts with
    ``estimate`` marks an estimate. When the table is there, every parameter must be covered.

Millimetres, degrees and bar are converted to SI here. A joint the file does not name has an
ideal drive; a robot without a sidecar has ideal drives only. A joint named twice is an error.
"""

from __future__ import annotations

import fnmatch
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.actuators.drive import Drive, IdealDrive
from scalf_opt.actuators.electric import ElectricDrive
from scalf_opt.actuators.stribeck import StribeckBranch, StribeckFriction
from scalf_opt.actuators.valve_cylinder import ValveControlledCylinder
from scalf_opt.errors import ConfigError
from scalf_opt.files import read_toml
from scalf_opt.model.robot import Robot

_BRANCH_KEYS = ("viscous_n_s_per_m", "static_n", "coulomb_n", "stribeck_velocity_m_s")
_CYLINDER_KEYS = ("a_mm", "b_mm", "phi_offset_deg", "angle_sign", "stroke_mm")
_SUPPLY_KEYS = ("joints", "pressure_bar", "bore_mm", "rod_mm")
_ELECTRIC_REQUIRED = (
    "joints",
    "gear_ratio",
    "torque_constant_nm_per_a",
    "winding_resistance_ohm",
)
_ELECTRIC_OPTIONAL = ("coulomb_friction_nm", "viscous_friction_nm_s_per_rad", "regenerative")
_TOP_KEYS = ("friction", "cylinders", "supplies", "electric", "sources")
_CYLINDER_LIMIT_KEYS = ("max_force_n", "max_speed_m_s")
_FRICTION_KEYS = ("extend", "retract")
_BAR_TO_PA = 1e5

FRICTIONLESS = StribeckFriction(
    StribeckBranch(0.0, 0.0, 0.0, 1.0), StribeckBranch(0.0, 0.0, 0.0, 1.0)
)
"""No friction, for supply-fed cylinders of a file without a ``[friction]`` table."""

ESTIMATE_PREFIX = "estimate"
"""A source text that starts with this marks the number as an estimate."""


@dataclass(frozen=True)
class Sidecar:
    """An actuator file, read.

    Attributes:
        path: The file.
        drives: Drives keyed by URDF joint name, in file order.
        sources: Source text of each parameter, keyed by its path (empty without ``[sources]``).
    """

    path: Path
    drives: dict[str, Drive]
    sources: dict[str, str] = field(default_factory=dict)

    def estimates(self) -> list[str]:
        """Paths of the parameters marked as estimates."""
        return [k for k, v in self.sources.items() if v.lower().startswith(ESTIMATE_PREFIX)]


MAX_MAGNITUDE = 1e6
"""Largest magnitude of an actuator file's number, in the file's units (mm, deg, bar, N, N s/m,
m/s, N m/A, ohm): far beyond any robot's (SCalf's largest: 4000 N), below where the energy's
arithmetic overflows."""

MIN_POSITIVE = 1e-6
"""Smallest value of a number that must be positive (a torque constant or a stroke of 1e-300
would divide the energy into infinity)."""


def _number(path: Path, key: str, value: Any, positive: bool = True, zero: bool = False) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or (positive and (value < 0 if zero else value <= 0)):
        need = "a number >= 0" if zero else "a positive number" if positive else "a number"
        raise ConfigError(f"{path}: {key} must be {need}, got {value!r}")
    if abs(value) > MAX_MAGNITUDE or (positive and 0 < value < MIN_POSITIVE):
        low = "0" if zero else f"{MIN_POSITIVE:g}" if positive else f"{-MAX_MAGNITUDE:g}"
        raise ConfigError(
            f"{path}: {key} = {value!r} is out of range [{low}, {MAX_MAGNITUDE:g}] "
            "(in the file's units)"
        )
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


def _require(path: Path, table: dict[str, Any], keys: tuple[str, ...], prefix: str) -> None:
    for key in keys:
        if key not in table:
            raise ConfigError(f"{path}: missing key {prefix}.{key}")


def _joints(path: Path, table: dict[str, Any], prefix: str) -> list[str]:
    joints = table["joints"]
    if (
        not isinstance(joints, list)
        or not joints
        or not all(isinstance(j, str) and j for j in joints)
    ):
        raise ConfigError(f"{path}: {prefix}.joints must be a non-empty list of joint names")
    return joints


def _branch(path: Path, friction: dict[str, Any], key: str) -> StribeckBranch:
    name = f"friction.{key}"
    table = _table(path, friction, key, name)
    _no_extra(path, table, _BRANCH_KEYS, name)
    _require(path, table, _BRANCH_KEYS, name)
    return StribeckBranch(*(_number(path, f"{name}.{f}", table[f]) for f in _BRANCH_KEYS))


def _friction(path: Path, data: dict[str, Any]) -> StribeckFriction | None:
    if "friction" not in data:
        return None
    table = _table(path, data, "friction", "friction")
    _no_extra(path, table, _FRICTION_KEYS, "friction")
    return StribeckFriction(
        extend=_branch(path, table, "extend"), retract=_branch(path, table, "retract")
    )


def _cylinder(path: Path, joint: str, table: Any, friction: StribeckFriction) -> HydraulicCylinder:
    prefix = f"cylinders.{joint}"
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: {prefix} must be a table, got {table!r}")
    _no_extra(path, table, _CYLINDER_KEYS + _CYLINDER_LIMIT_KEYS, prefix)
    _require(path, table, _CYLINDER_KEYS, prefix)
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


def _groups(path: Path, data: dict[str, Any], key: str) -> dict[str, dict[str, Any]]:
    if key not in data:
        return {}
    groups = _table(path, data, key, key)
    for name, table in groups.items():
        if not isinstance(table, dict):
            raise ConfigError(f"{path}: {key}.{name} must be a table, got {table!r}")
    return groups


def _supplied(
    path: Path, data: dict[str, Any], cylinders: dict[str, HydraulicCylinder]
) -> dict[str, Drive]:
    """The cylinders fed by each ``[supplies.<name>]``, as valve-controlled cylinders."""
    out: dict[str, Drive] = {}
    for name, table in _groups(path, data, "supplies").items():
        prefix = f"supplies.{name}"
        _no_extra(path, table, _SUPPLY_KEYS, prefix)
        _require(path, table, _SUPPLY_KEYS, prefix)
        pressure = _number(path, f"{prefix}.pressure_bar", table["pressure_bar"]) * _BAR_TO_PA
        bore = _number(path, f"{prefix}.bore_mm", table["bore_mm"]) * 1e-3
        rod = _number(path, f"{prefix}.rod_mm", table["rod_mm"]) * 1e-3
        if rod >= bore:
            raise ConfigError(f"{path}: {prefix}.rod_mm must be below {prefix}.bore_mm")
        for joint in _joints(path, table, prefix):
            if joint not in cylinders:
                raise ConfigError(
                    f"{path}: {prefix}.joints names {joint}, which has no [cylinders.{joint}] table"
                )
            if joint in out:
                raise ConfigError(
                    f"{path}: {prefix}.joints names {joint}, already fed by another supply"
                )
            out[joint] = ValveControlledCylinder.from_diameters(
                cylinders[joint], pressure, bore, rod
            )
    return out


def _electric(path: Path, data: dict[str, Any]) -> dict[str, Drive]:
    out: dict[str, Drive] = {}
    for name, table in _groups(path, data, "electric").items():
        prefix = f"electric.{name}"
        _no_extra(path, table, _ELECTRIC_REQUIRED + _ELECTRIC_OPTIONAL, prefix)
        _require(path, table, _ELECTRIC_REQUIRED, prefix)
        regenerative = table.get("regenerative", False)
        if not isinstance(regenerative, bool):
            raise ConfigError(f"{path}: {prefix}.regenerative must be true or false")
        values = {
            "gear_ratio": _number(path, f"{prefix}.gear_ratio", table["gear_ratio"]),
            "torque_constant_nm_per_a": _number(
                path, f"{prefix}.torque_constant_nm_per_a", table["torque_constant_nm_per_a"]
            ),
            **{
                key: _number(path, f"{prefix}.{key}", table.get(key, 0.0), zero=True)
                for key in (
                    "winding_resistance_ohm",
                    "coulomb_friction_nm",
                    "viscous_friction_nm_s_per_rad",
                )
            },
        }
        for joint in _joints(path, table, prefix):
            if joint in out:
                raise ConfigError(
                    f"{path}: {prefix}.joints names {joint}, already driven by another motor"
                )
            out[joint] = ElectricDrive(joint_name=joint, regenerative=regenerative, **values)
    return out


def _parameters(data: dict[str, Any], prefix: str = "") -> list[str]:
    """Paths of every parameter (a leaf that is not a list of joints) under ``data``."""
    out = []
    for key, value in data.items():
        here = f"{prefix}.{key}" if prefix else key
        if isinstance(value, dict):
            out += _parameters(value, here)
        elif key != "joints":
            out.append(here)
    return out


def _matches(pattern: str, parameter: str) -> bool:
    """A source key covers a parameter: the same path, or a table above it; ``*`` = one part."""
    want, have = pattern.split("."), parameter.split(".")
    return len(want) <= len(have) and all(
        fnmatch.fnmatchcase(h, w) for w, h in zip(want, have, strict=False)
    )


def _sources(path: Path, data: dict[str, Any]) -> dict[str, str]:
    """The source of every parameter; ``{}`` without a ``[sources]`` table."""
    if "sources" not in data:
        return {}
    table = _table(path, data, "sources", "sources")
    for key, text in table.items():
        if not isinstance(text, str) or not text.strip():
            raise ConfigError(f"{path}: sources.{key} must be a non-empty text")
    parameters = _parameters({k: v for k, v in data.items() if k != "sources"})
    for key in table:
        if not any(_matches(key, p) for p in parameters):
            raise ConfigError(f"{path}: sources names {key!r}, which is no parameter of the file")
    out = {}
    for parameter in parameters:
        # the most specific key wins: the longest path, then the one without wildcards
        covering = [k for k in table if _matches(k, parameter)]
        if not covering:
            raise ConfigError(
                f"{path}: {parameter} has no entry in [sources] (give its source, or mark it "
                f'"{ESTIMATE_PREFIX}: ...")'
            )
        best = max(covering, key=lambda k: (k.count(".") + 1, -k.count("*")))
        out[parameter] = table[best]
    return out


def read_sidecar(path: str | Path) -> Sidecar:
    """Read an actuator sidecar: its drives, keyed by URDF joint name, and its sources.

    Which joints exist is checked against a robot by :func:`drives_for`, not here.

    Raises:
        ConfigError: Unreadable file, TOML syntax error, missing, unknown or invalid key, a joint
            given two drives, a parameter without a source; the one-line message names the file
            and the key path (``cylinders.RF_knee.a_mm``).
    """
    path = Path(path)
    data = read_toml(path, "actuator")
    _no_extra(path, data, _TOP_KEYS, "")
    friction = _friction(path, data)
    tables = _groups(path, data, "cylinders") if "cylinders" in data else {}
    if "cylinders" in data and not tables:
        raise ConfigError(f"{path}: [cylinders] is empty")
    geometry = {j: _cylinder(path, j, t, friction or FRICTIONLESS) for j, t in tables.items()}
    supplied = _supplied(path, data, geometry)
    plain = [j for j in geometry if j not in supplied]
    if plain and friction is None:
        raise ConfigError(
            f"{path}: missing table [friction] (cylinder {plain[0]} is not fed by a supply and "
            "charges its friction heat)"
        )
    drives: dict[str, Drive] = {j: supplied.get(j, cyl) for j, cyl in geometry.items()}
    for joint, drive in _electric(path, data).items():
        if joint in drives:
            raise ConfigError(f"{path}: joint {joint} has a cylinder and an electric drive")
        drives[joint] = drive
    if not drives:
        raise ConfigError(
            f"{path}: missing table [cylinders] or [electric.<name>]: the file names no drive"
        )
    return Sidecar(path, drives, _sources(path, data))


def load_sidecar(path: str | Path) -> dict[str, Drive]:
    """Read an actuator sidecar into drives keyed by URDF joint name, in file order.

    Raises:
        ConfigError: See :func:`read_sidecar`.
    """
    return read_sidecar(path).drives


def sidecar_path_for(urdf_path: str | Path) -> Path:
    """The actuator sidecar that belongs to a URDF: ``<name>_actuators.toml`` beside it."""
    urdf_path = Path(urdf_path)
    return urdf_path.with_name(f"{urdf_path.stem}_actuators.toml")


def robot_sidecar_path(robot: Robot) -> Path | None:
    """The robot's actuator file: the one it names, else the one beside its URDF, if any."""
    if robot.actuator_path is not None:
        return robot.actuator_path
    path = sidecar_path_for(robot.urdf_path)
    return path if path.exists() else None


def drives_for(robot: Robot) -> dict[str, Drive]:
    """The robot's drives from its actuator file; ``{}`` when there is none.

    Raises:
        ConfigError: The file is invalid or names a joint the robot does not have.
    """
    path = robot_sidecar_path(robot)
    if path is None:
        return {}
    drives = load_sidecar(path)
    for joint in drives:
        if not robot.model.existJointName(joint):
            table = "electric" if drives[joint].kind == "electric" else "cylinders"
            raise ConfigError(f"{path}: {table}.{joint} names no joint of {robot.urdf_path}")
    return drives


def leg_drives(drives: dict[str, Drive], joint_names: tuple[str, str]) -> tuple[Drive, Drive]:
    """The drives of a leg's (hip pitch, knee) joints; a joint without one gets an ideal drive."""
    hip, knee = (drives.get(j) or IdealDrive(j) for j in joint_names)
    return hip, knee
