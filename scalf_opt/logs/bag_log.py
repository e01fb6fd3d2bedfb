"""A robot's log in other forms than the cylinder CSV, read into the same :class:`CylinderLog`.

Two sources, both giving per leg the (hip pitch, knee) cylinder lengths and forces, and where the
log has them the cylinder speeds (:class:`MeasuredLegLog`), so that the analysis needs no
differentiation:

* a ROS 2 bag (MCAP, sqlite3 ``.db3`` or a bag directory; extra ``ros``): one topic of
  ``sensor_msgs/JointState`` messages, either the **joints** (``position`` the angle [rad],
  ``velocity`` [rad/s], ``effort`` the torque [N m]; converted by each joint's cylinder,
  ``l = l(q)``, ``v = (dl/dq) qd``, ``F = tau / (dl/dq)``), or the **cylinders** (``position``
  the length [m], ``velocity`` the speed [m/s], ``effort`` the force [N]). Names map to the
  robot's joints: by default the URDF's joint names (cylinders: ``<joint>_cylinder``); a driver
  with its own names gives ``names`` (bag name -> URDF joint name). Other joints in the messages
  (a robot arm, the abduction joints) are ignored; a leg is read when both its joints are there,
  and a leg with only one of them is refused. Times are the messages' header stamps (else their
  receive times) less the first one: ``t = 0`` is the topic's first message. The bag has no
  contact; ``rows`` are the messages' indices (for messages about a sample);
* the CSV of ``scalf-opt export`` (its ``t_s, leg, contact`` and cylinder columns: lengths,
  speeds, forces), checked by the cylinder log's own parser.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import LogError
from scalf_opt.files import read_untrusted_text
from scalf_opt.io.ros_bag import JointStateSeries, cylinder_joint_name, read_joint_states
from scalf_opt.logs.analysis import leg_cylinders
from scalf_opt.logs.joint_log import JointLegLog, JointLog
from scalf_opt.logs.log_file import (
    ALL_COLUMNS,
    MAX_LOG_BYTES,
    CylinderLog,
    LegLog,
    check_times,
    finite_number,
    parse_log,
)
from scalf_opt.types import JOINT_ROLES, LEG_NAMES

Signals = Literal["joints", "cylinders"]

SPEED_COLUMNS: tuple[str, str] = tuple(f"{j}_speed_m_s" for j in JOINT_ROLES)  # type: ignore[assignment]
"""The cylinder speeds in ``scalf-opt export``'s CSV [m/s]."""

EXPORT_MARKER = "hip_angle_rad"
"""A column only ``scalf-opt export``'s CSV has."""


@dataclass(frozen=True)
class MeasuredLegLog(LegLog):
    """A leg's samples with, when the log has them, the cylinders' speeds.

    Attributes:
        speed_m_s: (hip, knee) cylinder speeds, shape (2, n) [m/s], or ``None``.
    """

    speed_m_s: np.ndarray | None = None


def _names_of(
    pipeline: EnergyPipeline, signals: Signals, names: Mapping[str, str] | None
) -> dict[str, str]:
    """Bag name -> URDF joint name for the legs' joints."""
    joints = [j for leg in LEG_NAMES for j in pipeline.robot.leg(leg).joint_names]
    if names:
        unknown = sorted(set(names.values()) - set(joints))
        if unknown:
            raise LogError(
                f"joint map: {', '.join(unknown)} is not a leg joint of {pipeline.robot.name} "
                f"(its joints: {', '.join(joints)})"
            )
        return dict(names)
    if signals == "cylinders":
        return {cylinder_joint_name(j): j for j in joints}
    return {j: j for j in joints}


def _choose_signals(
    series: JointStateSeries, pipeline: EnergyPipeline, names: Mapping[str, str] | None
) -> Signals:
    """``joints`` when the topic names the joints, ``cylinders`` when it names the cylinders."""
    if names:
        return "joints"
    joint_names = set(_names_of(pipeline, "joints", None))
    return "joints" if joint_names & set(series.names) else "cylinders"


def bag_log(
    path: str | Path,
    pipeline: EnergyPipeline,
    topic: str | None = None,
    signals: Signals | None = None,
    names: Mapping[str, str] | None = None,
) -> CylinderLog | JointLog:
    """Read one joint-state topic of a ROS 2 bag as a cylinder log (module docstring).

    The joints of a robot without cylinders make a :class:`~scalf_opt.logs.joint_log.JointLog`.

    Args:
        path: The bag.
        pipeline: The robot (its joints and cylinders).
        topic: The topic of ``sensor_msgs/JointState`` messages (``None``: the bag's only one).
        signals: ``joints`` or ``cylinders``; ``None`` decides by the names in the messages.
        names: Bag joint name -> URDF joint name (default: the URDF's own names).

    Raises:
        LogError: The bag cannot be read, no such topic, a leg with one joint missing, no
            leg's joints at all, a joint topic without efforts, a cylinder topic without forces.
    """
    if names:
        _names_of(pipeline, "joints", names)  # a mapping to no joint: before reading the bag
    series = read_joint_states(path, topic)
    chosen = signals or _choose_signals(series, pipeline, names)
    mapping = _names_of(pipeline, chosen, names)
    urdf_to_bag = {urdf: bag for bag, urdf in mapping.items() if bag in series.names}
    source = f"{path} topic {series.topic}"
    what = "effort (torques)" if chosen == "joints" else "effort (forces)"
    if series.effort is None:
        raise LogError(f"{source}: the messages have no {what}: the energy needs them")
    legs: dict[str, LegLog] = {}
    joint_legs: dict[str, JointLegLog] = {}
    without_cylinders = chosen == "joints" and not _has_cylinders(pipeline)
    t = series.t_s - series.t_s[0]
    check_times(source, "", t, np.arange(t.size), place="message")
    for leg in LEG_NAMES:
        index = _leg_rows(pipeline, leg, series, mapping, urdf_to_bag, source)
        if index is None:
            continue
        position = series.position[index]
        effort = series.effort[index]
        velocity = None if series.velocity is None else series.velocity[index]
        if without_cylinders:
            joint_legs[leg] = JointLegLog(t, position, velocity, effort, None, np.arange(t.size))
            continue
        if chosen == "cylinders":
            length, force, speed = position, effort, velocity
        else:
            length, force, speed = _through_cylinders(pipeline, leg, position, velocity, effort)
        legs[leg] = MeasuredLegLog(
            t, length, force, None, np.arange(t.size), None if speed is None else speed
        )
    if joint_legs:
        return JointLog(source, joint_legs)
    if not legs:
        raise _no_leg(pipeline, series, mapping, chosen, signals is None and not names, source)
    if chosen == "joints":  # said, or the report calls joint states a cylinder log unasked
        source += " (joint states, converted to the cylinders' lengths, speeds and forces)"
    return CylinderLog(source, legs)


def _leg_rows(
    pipeline: EnergyPipeline,
    leg: str,
    series: JointStateSeries,
    mapping: Mapping[str, str],
    urdf_to_bag: Mapping[str, str],
    source: str,
) -> list[int] | None:
    """The rows of ``leg``'s joints in the messages (hip pitch, knee), ``None`` when absent.

    Raises:
        LogError: The messages hold one of the leg's joints and not the other.
    """
    joints = pipeline.robot.leg(leg).joint_names
    present = [j in urdf_to_bag for j in joints]
    if not any(present):
        return None
    if not all(present):
        missing = next(j for j, p in zip(joints, present, strict=True) if not p)
        wanted = next(b for b, u in mapping.items() if u == missing)
        raise LogError(
            f"{source}: joint {wanted!r} ({leg} {JOINT_ROLES[present.index(False)]}) is "
            f"missing from the messages, which hold {', '.join(series.names)}"
        )
    return [series.names.index(urdf_to_bag[j]) for j in joints]


def _no_leg(
    pipeline: EnergyPipeline,
    series: JointStateSeries,
    mapping: Mapping[str, str],
    chosen: Signals,
    guessed: bool,
    source: str,
) -> LogError:
    """The error of messages that name no leg's joints (``guessed``: neither way was given)."""
    expected = ", ".join(list(mapping)[:4]) + ", ..."
    held = ", ".join(series.names[:8]) + (", ..." if len(series.names) > 8 else "")
    what = f"{pipeline.robot.name}'s {chosen}"
    if guessed:
        what = f"{pipeline.robot.name}'s leg joints nor their cylinders (<joint>_cylinder)"
        expected = ", ".join(list(_names_of(pipeline, "joints", None))[:4]) + ", ..."
    return LogError(
        f"{source}: the messages name none of {what} (expected {expected}; they hold "
        f"{held}): give the robot (--robot, --urdf) or map the names with "
        "--joint NAME=URDF_JOINT"
    )


def _has_cylinders(pipeline: EnergyPipeline) -> bool:
    """Whether every leg's hip pitch and knee are driven by hydraulic cylinders."""
    try:
        for leg in LEG_NAMES:
            leg_cylinders(pipeline, leg)
    except LogError:
        return False
    return True


def _through_cylinders(
    pipeline: EnergyPipeline,
    leg: str,
    q_rad: np.ndarray,
    qd_rad_s: np.ndarray | None,
    tau_nm: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Lengths [m], forces [N] and speeds [m/s] of the leg's cylinders for joint states."""
    cylinders = leg_cylinders(pipeline, leg)
    length = np.vstack([np.array(c.length_m(q_rad[j])).ravel() for j, c in enumerate(cylinders)])
    arm = np.vstack([np.array(c.moment_arm_m(q_rad[j])).ravel() for j, c in enumerate(cylinders)])
    speed = None if qd_rad_s is None else arm * qd_rad_s
    return length, tau_nm / arm, speed


def header_cells(text: str) -> list[str]:
    """The first row of CSV text, read without quoting (a log's cells are never quoted)."""
    header = next(csv.reader(io.StringIO(text[:4096]), quoting=csv.QUOTE_NONE), [])
    return [cell.strip() for cell in header]


def export_csv_log(text: str, source: str) -> CylinderLog | JointLog:
    """``scalf-opt export``'s CSV as a log: cylinders with their speeds, else joints.

    With cylinder columns, a cylinder log; without (a robot without cylinders), a joint log.

    Raises:
        LogError: The cylinder log parser's row-and-column errors (the joints': the same kind).
    """
    rows = list(csv.reader(io.StringIO(text), quoting=csv.QUOTE_NONE))
    header = [cell.strip() for cell in rows[0]]
    if not all(c in header for c in (*ALL_COLUMNS, *SPEED_COLUMNS)):
        return _export_joint_log(rows, header, source)
    keep = [header.index(c) for c in ALL_COLUMNS]
    speeds = [header.index(c) for c in SPEED_COLUMNS]
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(ALL_COLUMNS)
    speed_of_row: dict[int, tuple[float, float]] = {}
    for number, cells in enumerate(rows[1:], start=2):
        if len(cells) != len(header):
            writer.writerow(cells)  # the parser names the row
            continue
        writer.writerow([cells[k] for k in keep])
        try:
            speed_of_row[number] = (float(cells[speeds[0]]), float(cells[speeds[1]]))
        except ValueError as exc:
            raise LogError(f"{source}: row {number}: a cylinder speed is not a number") from exc
    log = parse_log(buffer.getvalue(), source)
    legs: dict[str, LegLog] = {}
    for leg, data in log.legs.items():
        speed = np.array([speed_of_row[int(r)] for r in data.rows]).T
        if not np.all(np.isfinite(speed)):
            raise LogError(f"{source}: a cylinder speed of leg {leg} is not a finite number")
        legs[leg] = MeasuredLegLog(
            data.t_s, data.length_m, data.force_n, data.contact, data.rows, speed
        )
    return CylinderLog(log.source, legs)


JOINT_COLUMNS = tuple(
    f"{role}_{stem}"
    for stem in ("angle_rad", "velocity_rad_s", "torque_nm")
    for role in JOINT_ROLES
)
"""The export's joint columns a joint log reads: angles, rates, torques (hip, knee)."""


def _export_joint_log(rows: list[list[str]], header: list[str], source: str) -> JointLog:
    for column in ("t_s", "leg", "contact", *JOINT_COLUMNS):
        if column not in header:
            raise LogError(f"{source}: row 1, column {column}: missing from the header")
    at = {c: header.index(c) for c in header}
    samples: dict[str, list[list[float]]] = {leg: [] for leg in LEG_NAMES}
    numbers: dict[str, list[int]] = {leg: [] for leg in LEG_NAMES}
    for number, cells in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in cells):
            continue
        if len(cells) != len(header):
            raise LogError(
                f"{source}: row {number}: {len(cells)} cells, the header has {len(header)}"
            )
        leg = cells[at["leg"]].strip()
        if leg not in samples:
            raise LogError(f"{source}: row {number}, column leg: {leg!r} is not a leg")
        values = [
            finite_number(source, number, column, cells[at[column]])
            for column in ("t_s", "contact", *JOINT_COLUMNS)
        ]
        if samples[leg] and values[0] <= samples[leg][-1][0]:
            raise LogError(f"{source}: row {number}, column t_s: the time does not increase")
        samples[leg].append(values)
        numbers[leg].append(number)
    legs = {}
    for leg in LEG_NAMES:
        if samples[leg]:
            d = np.array(samples[leg]).T
            check_times(source, leg, d[0], np.array(numbers[leg]))
            legs[leg] = JointLegLog(
                d[0], d[2:4], d[4:6], d[6:8], d[1] > 0.5, np.array(numbers[leg])
            )
    if not legs:
        raise LogError(f"{source}: row 2: the log has no samples")
    return JointLog(source, legs)


def read_any_log(
    path: str | Path,
    pipeline: EnergyPipeline,
    topic: str | None = None,
    signals: Signals | None = None,
    names: Mapping[str, str] | None = None,
) -> CylinderLog | JointLog:
    """A bag (by its suffix or folder), ``export``'s CSV, or the cylinder-log CSV.

    Raises:
        LogError: A bag without ``topic`` whose JointState topic is not the only one, a topic
            given for a CSV, and every reader's errors.
    """
    from scalf_opt.io.ros_bag import is_bag
    from scalf_opt.logs.log_file import parse_log

    path = Path(path)
    if is_bag(path):
        return bag_log(path, pipeline, topic, signals, names)
    if topic is not None or names:
        raise LogError(f"{path}: --topic and --joint are for a ROS 2 bag (.mcap, .db3)")
    text = read_untrusted_text(path, "log", MAX_LOG_BYTES, LogError)
    header = header_cells(text)
    if EXPORT_MARKER in header:
        return export_csv_log(text, str(path))
    if "leg" not in header:
        raise LogError(
            f"{path}: row 1: neither a cylinder log (t_s, leg, ...) nor the CSV of export: a "
            "robot's own CSV (a column per joint) is read through a mapping: --mapping "
            "FILE.toml (examples/mappings/unitree_sdk_csv.toml is Unitree's SDK log)"
        )
    return parse_log(text, str(path))
