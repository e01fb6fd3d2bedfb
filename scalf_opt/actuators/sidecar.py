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

Millimetres, degrees and bar are converted to SI as they are read. A joint the file does not
name has an ideal drive; a robot without a sidecar has ideal drives only. A joint named twice
is an error.
Each drive's tables are read by its kind in :data:`scalf_opt.actuators.registry.DRIVE_KINDS`
(a new drive: one module and one registry line); every table through
:class:`scalf_opt.tables.Table`, so each message names the file and the key path.
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from scalf_opt.actuators import registry
from scalf_opt.actuators.drive import Drive, IdealDrive
from scalf_opt.errors import ConfigError
from scalf_opt.model.robot import Robot
from scalf_opt.tables import Table

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


def _sources(file: Table) -> dict[str, str]:
    """The source of every parameter; ``{}`` without a ``[sources]`` table."""
    if "sources" not in file:
        return {}
    sources = file.table("sources")
    table = dict(sources.data)
    for key, text in table.items():
        if not isinstance(text, str) or not text.strip():
            raise file.error(f"{sources.key(key)} must be a non-empty text")
    parameters = _parameters({k: v for k, v in file.data.items() if k != "sources"})
    for key in table:
        if not any(_matches(key, p) for p in parameters):
            raise file.error(f"sources names {key!r}, which is no parameter of the file")
    out = {}
    for parameter in parameters:
        # the most specific key wins: the longest path, then the one without wildcards
        covering = [k for k in table if _matches(k, parameter)]
        if not covering:
            raise file.error(
                f"{parameter} has no entry in [sources] (give its source, or mark it "
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
    file = Table.read(path, "actuator")
    file.only(registry.file_tables())
    drives: dict[str, Drive] = {}
    for kind in registry.DRIVE_KINDS:
        for joint, drive in kind.read(file, drives).items():
            if joint in drives and not kind.replaces:
                raise file.error(f"joint {joint} has {_a(drives[joint].noun)} and {_a(drive.noun)}")
            drives[joint] = drive
    for kind in registry.DRIVE_KINDS:
        if kind.check is not None:
            kind.check(file, drives)
    if not drives:
        tables = " or ".join(f"[{k.tables[-1]}]" for k in registry.DRIVE_KINDS if not k.replaces)
        raise file.error(f"missing table {tables}: the file names no drive")
    return Sidecar(file.path, drives, _sources(file))


def _a(noun: str) -> str:
    return f"{'an' if noun[:1] in 'aeiou' else 'a'} {noun}"


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
    for joint, drive in drives.items():
        if not robot.model.existJointName(joint):
            raise ConfigError(
                f"{path}: {drive.file_table or 'drive'}.{joint} names no joint of {robot.urdf_path}"
            )
    return drives


def leg_drives(drives: dict[str, Drive], joint_names: tuple[str, str]) -> tuple[Drive, Drive]:
    """The drives of a leg's (hip pitch, knee) joints; a joint without one gets an ideal drive."""
    hip, knee = (drives.get(j) or IdealDrive(j) for j in joint_names)
    return hip, knee
