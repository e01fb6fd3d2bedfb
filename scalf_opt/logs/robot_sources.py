"""A robot's own log read through a mapping: a ROS 2 bag topic or a wide CSV into joint series.

Both give :class:`JointSeries`: per instant every mapped joint's angle, rate (when logged) and
torque, and the foot sensors' forces (when mapped), in SI units, times as logged. Nothing here
knows the robot: :mod:`scalf_opt.logs.robot_log` checks the series against it.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.errors import LogError, did_you_mean
from scalf_opt.files import read_untrusted_text
from scalf_opt.io.bag_bounds import MAX_JOINTS
from scalf_opt.io.bag_topics import TopicRequest, field_getter, read_topics
from scalf_opt.io.ros_bag import checked_names
from scalf_opt.logs.log_file import MAX_LOG_BYTES, finite_number
from scalf_opt.logs.mapping import LogMapping

ODOMETRY = "nav_msgs/msg/Odometry"
"""The message type of a speed source in a bag."""


@dataclass(frozen=True)
class JointSeries:
    """Every mapped joint's samples (module docstring).

    Attributes:
        source: The file (and topic) for messages.
        joints: URDF joint names, in row order.
        t_s: Sample times, shape (n,) [s], as logged.
        q_rad: Angles, shape (m, n) [rad].
        qd_rad_s: Rates, shape (m, n) [rad/s], or ``None`` (not logged).
        tau_nm: Torques, shape (m, n) [N m].
        foot_force: Per leg with a sensor, its force, shape (n,) [N or the sensor's unit].
        rows: Each sample's message index (bag) or file row (CSV), shape (n,).
        odometry: ``(t_s (k,), xy_m (2, k))`` of the trunk from an odometry topic, or ``None``.
    """

    source: str
    joints: tuple[str, ...]
    t_s: np.ndarray
    q_rad: np.ndarray
    qd_rad_s: np.ndarray | None
    tau_nm: np.ndarray
    foot_force: dict[str, np.ndarray] | None
    rows: np.ndarray
    odometry: tuple[np.ndarray, np.ndarray] | None = None


def _counts(mapping: LogMapping, joints: int) -> list[tuple[str, int]]:
    """Each quantity and how many values of it a sample holds: the order of a row's numbers."""
    return [
        ("position", joints),
        ("velocity", joints if mapping.velocity else 0),
        ("effort", joints),
        ("foot_force", len(mapping.feet) if mapping.foot_force else 0),
    ]


def _split(mapping: LogMapping, values: np.ndarray, joints: int) -> dict[str, np.ndarray | None]:
    """Rows of ``[q..., qd..., tau..., force...]`` into the quantities, each (k, n)."""
    out: dict[str, np.ndarray | None] = {}
    at = 0
    for quantity, count in _counts(mapping, joints):
        out[quantity] = values[:, at : at + count].T if count else None
        at += count
    return out


def _series(
    mapping: LogMapping,
    source: str,
    joints: tuple[str, ...],
    t_s: np.ndarray,
    values: np.ndarray,
    odometry: tuple[np.ndarray, np.ndarray] | None = None,
) -> JointSeries:
    parts = _split(mapping, values, len(joints))
    force = parts["foot_force"]
    return JointSeries(
        source=source,
        joints=joints,
        t_s=t_s,
        q_rad=np.asarray(parts["position"]),
        qd_rad_s=parts["velocity"],
        tau_nm=np.asarray(parts["effort"]),
        foot_force=None if force is None else dict(zip(mapping.feet, force, strict=True)),
        rows=np.arange(t_s.size),
        odometry=odometry,
    )


class _NamedRow:
    """A message with its joint names in it (``JointState``) -> the mapped joints' numbers.

    The names of the first message fix the order; every later one must name the same joints.
    """

    def __init__(self, mapping: LogMapping) -> None:
        self.mapping = mapping
        self.names: tuple[str, ...] | None = None
        self.count = 0
        self.get_names = field_getter(str(mapping.names))
        self.getters = [
            (q, field_getter(str(getattr(mapping, q))))
            for q in ("position", "velocity", "effort")
            if getattr(mapping, q)
        ]

    def __call__(self, message: Any) -> np.ndarray:
        raw = self.get_names(message)
        if len(raw) > MAX_JOINTS:
            raise LogError(f"{len(raw):,} joints, more than the {MAX_JOINTS} a message may name")
        names = tuple(str(n) for n in raw)
        if self.names is None:
            self.names = checked_names(names, "this message")
        elif names != self.names:
            raise LogError(f"joint names {list(names)[:8]} differ from the first message's")
        self.count += 1
        values = []
        for quantity, get in self.getters:
            array = np.asarray(get(message), dtype=float).ravel()
            if array.size != len(names):
                raise LogError(f"{quantity} has {array.size} values for {len(names)} joints")
            values.append(array)
        return np.concatenate(values)

    def joints(self) -> tuple[str, ...]:
        """The URDF joint of each name (``rename``, else the name itself)."""
        assert self.names is not None
        return tuple(self.mapping.rename.get(n, n) for n in self.names)


def _indexed_row(mapping: LogMapping) -> Callable[[Any], np.ndarray]:
    """A message -> ``[q..., qd..., tau..., force...]`` by the mapping's field paths."""
    getters = [
        field_getter(mapping.path(quantity, i))
        for quantity, count in _counts(mapping, len(mapping.joints))
        for i in range(count)
    ]
    return lambda message: np.array([float(get(message)) for get in getters])


def bag_series(path: str | Path, mapping: LogMapping, odometry_topic: str | None) -> JointSeries:
    """Read a bag's joint topic (and its odometry topic) through ``mapping``.

    Raises:
        LogError: See :func:`~scalf_opt.io.bag_topics.read_topics`; a message whose field paths
            do not exist (named, with the topic and message index).
    """
    named = _NamedRow(mapping) if mapping.names else None
    requests = [
        TopicRequest(
            "joints",
            mapping.topic,
            mapping.message,
            named if named is not None else _indexed_row(mapping),
            mapping.time,
            mapping.time_unit_s,
        )
    ]
    if odometry_topic is not None:
        requests.append(
            TopicRequest(
                "odometry",
                odometry_topic,
                ODOMETRY,
                lambda m: np.array([m.pose.pose.position.x, m.pose.pose.position.y]),
                "header.stamp",
            )
        )
    try:
        topics = read_topics(path, requests)
    except LogError as exc:
        raise LogError(f"{exc} (mapping {mapping.name})"[:600]) from exc
    rows = topics["joints"]
    joints = named.joints() if named is not None else mapping.joints
    if named is not None and mapping.effort not in {q for q, _ in named.getters}:
        raise LogError(f"{path}: the messages have no effort (torques): the energy needs them")
    odometry = None
    if "odometry" in topics:
        odo = topics["odometry"]
        odometry = (odo.t_s, odo.values.T)
    return _series(mapping, f"{path} topic {rows.topic}", joints, rows.t_s, rows.values, odometry)


def csv_series(path: str | Path, mapping: LogMapping) -> JointSeries:
    """Read a wide CSV (a row per instant, a column per joint and quantity) through ``mapping``.

    Raises:
        LogError: The file cannot be read; a mapped column is missing from the header (named,
            with the closest header cell); a row with another number of cells than the header, or
            a cell that is not a finite number (row and column named); time that goes back.
    """
    source = str(path)
    text = read_untrusted_text(path, "log", MAX_LOG_BYTES, LogError)
    reader = csv.reader(io.StringIO(text))
    try:
        header = [cell.strip() for cell in next(reader)]
    except StopIteration:
        raise LogError(f"{source}: the file is empty") from None
    except csv.Error as exc:
        raise LogError(f"{source}: row 1: not CSV ({exc})") from None
    columns = [mapping.time] + [
        mapping.path(quantity, i)
        for quantity, count in _counts(mapping, len(mapping.joints))
        for i in range(count)
    ]
    index = _column_index(header, columns, source, mapping.name)
    data: list[list[float]] = []
    numbers: list[int] = []
    try:
        for number, cells in enumerate(reader, start=2):
            if any(cell.strip() for cell in cells):
                data.append(_row_numbers(cells, len(header), columns, index, source, number))
                numbers.append(number)
    except csv.Error as exc:
        raise LogError(f"{source}: row {reader.line_num}: not CSV ({exc})") from None
    if not data:
        raise LogError(f"{source}: row 2: the log has no samples")
    table = np.array(data)
    t_s = table[:, 0] * mapping.time_unit_s
    back = np.flatnonzero(np.diff(t_s) < 0)
    if back.size:
        raise LogError(
            f"{source}: row {numbers[back[0] + 1]}, column {mapping.time}: the time goes back"
        )
    series = _series(mapping, source, mapping.joints, t_s, table[:, 1:])
    return replace(series, rows=np.array(numbers))


def _column_index(header: list[str], columns: list[str], source: str, mapping: str) -> list[int]:
    """Where each mapped column is in the header.

    Raises:
        LogError: A column is missing (named, with the closest header cell).
    """
    at = {cell: k for k, cell in enumerate(header)}
    for column in columns:
        if column not in at:
            raise LogError(
                f"{source}: row 1, column {column}: missing from the header (mapping "
                f"{mapping}){did_you_mean(column, header)}"[:400]
            )
    return [at[c] for c in columns]


def _row_numbers(
    cells: list[str], width: int, columns: list[str], index: list[int], source: str, row: int
) -> list[float]:
    """The mapped cells of one CSV row as finite numbers.

    Raises:
        LogError: Another number of cells than the header's, or a cell that is no finite number.
    """
    if len(cells) != width:
        raise LogError(f"{source}: row {row}: {len(cells)} cells, the header has {width}")
    return [
        finite_number(source, row, column, cells[k].strip())
        for column, k in zip(columns, index, strict=True)
    ]
