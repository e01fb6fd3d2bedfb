"""``analyze_robot_log``: every joint of a robot's own log, and the model at the log's gait."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.api.gaits import as_robot, command_tuple
from scalf_opt.errors import ConfigError, LogError
from scalf_opt.io.provenance import provenance
from scalf_opt.model.robot import Robot


@dataclass(frozen=True)
class RobotLogResult:
    """A whole-robot log's energies, and the model beside them.

    Attributes:
        robot: The robot.
        mapping: The name of the mapping the log was read through.
        analysis: Every joint's energies (:class:`scalf_opt.logs.robot_energy.RobotLogAnalysis`).
        comparison: The model at the log's gait
            (:class:`scalf_opt.logs.log_plan.LogPlanComparison`), or ``None``.
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    mapping: str
    analysis: Any
    comparison: Any = None
    command: tuple[str, ...] | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain data: what ``analyze-log --json`` prints."""
        data = {
            "provenance": provenance(self.robot, self.command),
            "log_kind": "robot",
            "mapping": self.mapping,
            **self.analysis.as_dict(),
        }
        if self.comparison is not None:
            data["model_comparison"] = self.comparison.as_dict()
        return data

    def write_figure(self, path: str | Path) -> Path:
        """Every joint's measured and planned power over a cycle (PNG, atomically).

        Raises:
            ConfigError: The result has no comparison (``compare=True``).
        """
        from scalf_opt.viz.figures import save_atomic
        from scalf_opt.viz.joint_log_figure import joint_comparison_figure

        if self.comparison is None:
            raise ConfigError("a figure of the log against the model needs --compare")
        g = self.comparison.gait
        measured = self.analysis.average_power_w
        title = (
            f"{self.analysis.source} ({self.robot.name}) against the sagittal model at T\u00a0"
            f"{g.period_s:.3g}\u00a0s, duty\u00a0{g.duty_cycle:.3g}, "
            f"{self.analysis.speed_m_s:.3g}\u00a0m/s (dashed: lift-off, log and model): "
            f"{measured:.1f} W measured (every joint), "
            f"{sum(c.planned_j / g.period_s for c in self.comparison.joints):.1f} W planned"
        )
        return save_atomic(joint_comparison_figure(self.comparison, title), Path(path))


def _mapping_for(path: Path, mapping: Any, topic: str | None) -> Any:
    """The mapping asked for, or the one the bag's message type has."""
    from scalf_opt.io.bag_topics import topic_types
    from scalf_opt.io.ros_bag import is_bag
    from scalf_opt.logs.mapping import LogMapping, read_mapping

    if isinstance(mapping, LogMapping):
        return mapping.with_topic(topic)
    if mapping is not None:
        return read_mapping(str(mapping)).with_topic(topic)
    if not is_bag(path):
        raise ConfigError(
            f"{path}: a wide CSV is read through a mapping: give --mapping FILE.toml "
            "(examples/mappings/unitree_sdk_csv.toml is Unitree's SDK log)"
        )
    return _mapping_of_types(path, topic_types(path), topic)


def _mapping_of_types(path: Path, types: dict[str, set[str]], topic: str | None) -> Any:
    """The built-in mapping of the bag's topic (``topic``, else its one topic of a known type).

    Raises:
        LogError: No such topic, or not exactly one topic of a type with a built-in mapping.
    """
    from scalf_opt.logs.mapping import MAPPING_OF_MESSAGE

    known = {t: held & set(MAPPING_OF_MESSAGE) for t, held in types.items()}
    if topic is not None:
        if topic not in types:
            raise LogError(
                f"{path}: no topic {topic!r} in the bag (its topics: {', '.join(sorted(types))})"[
                    :400
                ]
            )
        candidates = [topic] if known[topic] else []
    else:
        candidates = [t for t, k in known.items() if k]
    if len(candidates) != 1:
        listed = ", ".join(f"{t} ({', '.join(sorted(h))})" for t, h in sorted(types.items()))
        raise LogError(
            f"{path}: {'no' if not candidates else len(candidates)} topic(s) of a message type "
            f"with a built-in mapping ({', '.join(MAPPING_OF_MESSAGE)}) in the bag ({listed}): "
            "name one with --topic, or give --mapping FILE.toml"[:500]
        )
    (message,) = known[candidates[0]]
    return MAPPING_OF_MESSAGE[message].with_topic(candidates[0])


def robot_log_mapping(
    path: str | Path,
    topic: str | None = None,
    mapping: Any = None,
    odometry_topic: str | None = None,
    speed_m_s: float | None = None,
    compare: bool = False,
) -> Any:
    """The mapping ``analyze-log`` reads ``path`` through as a robot's own log, or ``None``.

    A robot's own log (every joint) with a mapping, an odometry topic, a speed or a comparison
    with the model; and a bag whose topic (``topic``, else its one topic of a known message type)
    is of a message type with a built-in mapping other than ``JointState`` (a Unitree
    ``LowState``). ``None``: the sagittal reader's log (a cylinder log, an export's CSV, a
    JointState bag, or a bag that cannot be listed, which that reader reports). The bag is
    listed once: the mapping found is the one to read it with.

    Raises:
        ConfigError, LogError: A robot's own log whose mapping cannot be found
            (:func:`analyze_robot_log`'s ``mapping``).
    """
    from scalf_opt.io.bag_topics import topic_types
    from scalf_opt.io.ros_bag import JOINT_STATE, is_bag
    from scalf_opt.logs.mapping import MAPPING_OF_MESSAGE

    path = Path(path)
    if mapping is not None or odometry_topic is not None or speed_m_s is not None or compare:
        return _mapping_for(path, mapping, topic)
    if not is_bag(path):
        return None
    try:
        types = topic_types(path)
    except LogError:
        return None
    robot_types = set(MAPPING_OF_MESSAGE) - {JOINT_STATE}
    if topic is not None:
        robot = bool(types.get(topic, set()) & robot_types)
    else:
        has_joint_state = any(JOINT_STATE in held for held in types.values())
        robot = not has_joint_state and any(held & robot_types for held in types.values())
    return _mapping_of_types(path, types, topic) if robot else None


def analyze_robot_log(
    path: str | Path,
    robot: str | Robot | None = None,
    *,
    mapping: Any = None,
    topic: str | None = None,
    odometry_topic: str | None = None,
    speed_m_s: float | None = None,
    compare: bool = False,
    loads: str | None = None,
    command: Sequence[str] | None = None,
) -> RobotLogResult:
    """Every joint's mechanical energy per leg and cycle in a robot's own log.

    Args:
        path: A ROS 2 bag (``.mcap``, ``.db3``, a bag folder) or a wide CSV.
        robot: The robot (default: SCalf); its URDF names the joints and gives the kinematics.
        mapping: A :class:`~scalf_opt.logs.mapping.LogMapping`, a built-in mapping's name or a
            mapping file; ``None``: the built-in mapping of the bag topic's message type.
        topic: The bag's joint topic (over the mapping's).
        odometry_topic: A ``nav_msgs/msg/Odometry`` topic: the speed.
        speed_m_s: The forward speed [m/s] (over the odometry's).
        compare: Evaluate the model at the log's gait and compare joint by joint.
        loads: The model's stance load model (``None``: the default).
        command: The command line, recorded in the provenance.

    Raises:
        LogError: A bad log (the message names the file and the row, or the topic and the
            message), a log of another robot (joint names), a leg that never touches down twice.
        ConfigError: A bad mapping, a speed that is not > 0, ``compare`` without a speed.
    """
    from scalf_opt.logs.contacts import foot_heights_m, log_contacts, weight_note
    from scalf_opt.logs.robot_energy import analyze_robot_log as analyze
    from scalf_opt.logs.robot_energy import joint_powers
    from scalf_opt.logs.robot_log import robot_log
    from scalf_opt.logs.robot_sources import bag_series, csv_series

    if speed_m_s is not None and not (np.isfinite(speed_m_s) and 0 < speed_m_s < 100):
        raise ConfigError(f"the speed must be in (0, 100) m/s, got {speed_m_s}", field="speed_m_s")
    robot = as_robot(robot)
    path = Path(path)
    chosen = _mapping_for(path, mapping, topic)
    if chosen.source == "csv":
        if odometry_topic is not None:
            raise ConfigError(f"{path}: --odometry is a topic of a bag, not of a CSV")
        series = csv_series(path, chosen)
    else:
        series = bag_series(path, chosen, odometry_topic)
    place = "row" if chosen.source == "csv" else "message"
    log = robot_log(series, robot, chosen.names is not None, place, chosen.time or "t_s")
    contacts = log_contacts(log, robot)
    weight = weight_note(log, robot, contacts.stance)
    if weight is not None:
        log = replace(log, notes=(*log.notes, weight))
    power, velocity_source = joint_powers(log)
    analysis = analyze(log, contacts, robot.total_mass_kg, power, velocity_source, speed_m_s)
    comparison = None
    if compare:
        from scalf_opt.logs.log_plan import compare_with_plan

        comparison = compare_with_plan(
            analysis, robot, log.t_s, power, foot_heights_m(log, robot), contacts.stance, loads
        )
    return RobotLogResult(robot, chosen.name, analysis, comparison, command_tuple(command))
