"""Load a robot by catalog name or from any quadruped URDF.

A URDF given by path is named by the legs file beside it (``<name>_legs.toml``) or by its
kinematic tree; its standing posture comes from an SRDF beside it (``<name>.srdf`` with a
``standing`` group state), else it stands like SCalf scaled to its leg length
(:func:`~scalf_opt.robots.similarity.similar_stance_height_m`). A path that is a catalog robot's
URDF loads that robot.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from scalf_opt.errors import ModelError
from scalf_opt.model.naming import LegNames, read_leg_map
from scalf_opt.model.robot import Robot
from scalf_opt.model.urdf_file import read_srdf_text
from scalf_opt.robots.catalog import CATALOG, RobotEntry, entry
from scalf_opt.robots.similarity import similar_stance_height_m


def _with_stance_height(robot: Robot, height_m: float | None) -> Robot:
    """``robot`` with its nominal stance height: given, else from its posture, else similar."""
    if height_m is None:
        height_m = robot.standing_height_m
    if height_m is None:
        height_m = similar_stance_height_m(robot.leg_length_m)
    return replace(robot, nominal_stance_height_m=height_m)


def _catalog_robot(known: RobotEntry, actuators: Path | None) -> Robot:
    srdf = (known.srdf(), known.STANDING_STATE) if known.srdf is not None else None
    if actuators is None and known.actuators is not None:
        actuators = known.actuators()
    robot = Robot.from_urdf(known.urdf(), known.naming, known.name, None, srdf, actuators)
    return _with_stance_height(robot, known.nominal_stance_height_m)


def _catalog_entry_of(path: Path) -> RobotEntry | None:
    resolved = path.resolve()
    for known in CATALOG.values():
        try:
            if known.urdf().resolve() == resolved:
                return known
        except ModelError:  # a robot whose files are not installed
            continue
    return None


def load_robot(
    name: str | None = None,
    urdf: str | Path | None = None,
    legs: str | Path | None = None,
    actuators: str | Path | None = None,
) -> Robot:
    """Load a robot by catalog ``name`` or from a ``urdf`` file (default: SCalf).

    Args:
        name: A catalog robot.
        urdf: A URDF file instead.
        legs: A legs file naming the legs of ``urdf`` (default: the one beside it, else the
            kinematic tree).
        actuators: An actuator file (default: the robot's own, or the one beside the URDF).

    Raises:
        ModelError: Unknown name; missing or invalid URDF; legs that cannot be found.
        ConfigError: An invalid legs file.
    """
    if name is not None and urdf is not None:
        raise ModelError("give a robot name or a URDF path, not both")
    actuator_path = Path(actuators) if actuators is not None else None
    if actuator_path is not None and not actuator_path.exists():
        raise ModelError(f"{actuator_path}: actuator file not found")
    if urdf is None:
        if legs is not None:
            raise ModelError("a legs file goes with a URDF path, not a catalog robot")
        return _catalog_robot(entry(name or "scalf"), actuator_path)
    path = Path(urdf)
    known = _catalog_entry_of(path) if path.is_file() and legs is None else None
    if known is not None:
        return _catalog_robot(known, actuator_path)
    names: LegNames | None = read_leg_map(Path(legs)) if legs is not None else None
    srdf_path = path.with_suffix(".srdf")
    standing = f'name="{RobotEntry.STANDING_STATE}"'
    has_posture = srdf_path.exists() and standing in read_srdf_text(srdf_path)
    srdf = (srdf_path, RobotEntry.STANDING_STATE) if has_posture else None
    robot = _with_stance_height(Robot.from_urdf(path, names, None, None, srdf, actuator_path), None)
    return _with_parent(robot)


def _with_parent(robot: Robot) -> Robot:
    """A variant (a ``<stem>_variant.toml`` record beside its URDF) with its parent robot."""
    from scalf_opt.robots.variants import read_variant_record, variant_record_for

    record_path = variant_record_for(robot.urdf_path)
    if not record_path.is_file():
        return robot
    record = read_variant_record(record_path)
    parent = load_robot(name=record.parent_robot, urdf=record.parent_urdf)
    return replace(robot, parent=parent)
