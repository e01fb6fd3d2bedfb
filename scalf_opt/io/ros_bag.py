"""ROS 2 bags of joint states: write an MCAP file, read an MCAP or sqlite3 bag (extra ``ros``).

The one place that speaks ROS 2: :func:`write_bag` writes ``sensor_msgs/msg/JointState`` series
(one message per instant, every joint of the series in it) and ``trajectory_msgs/msg/
JointTrajectory`` messages into a single ``.mcap`` file, CDR-serialized with the message
definitions embedded (what ``ros2 bag record`` writes since ROS 2 Iron), so ``ros2 bag info``,
Foxglove and any MCAP reader open it. :func:`read_joint_states` reads one topic of
``JointState`` messages from an MCAP file, a sqlite3 ``.db3`` file or a bag directory.

Time stamps: a message's ``header.stamp`` [s] when set, else its receive time in the bag. A
joint state of a cylinder is written as a prismatic joint: ``position`` its length [m],
``velocity`` its speed [m/s], ``effort`` its force [N].

Uses ``rosbags`` (pure Python, no ROS installation); imported only when a bag is read or written.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.errors import ConfigError, LogError
from scalf_opt.files import SCRATCH_PREFIX, copy_untrusted, scratch_folder, write_with
from scalf_opt.io.bag_bounds import (
    MAX_BAG_BYTES,
    MAX_JOINTS,
    MAX_VALUES,
    bounded_decompression,
    check_sqlite_files,
    inflate_compressed_files,
)

BAG_SUFFIXES = (".mcap", ".db3")
"""Suffixes of the bag files read (a directory holding ``metadata.yaml`` is a bag too)."""

JOINT_STATE = "sensor_msgs/msg/JointState"
JOINT_TRAJECTORY = "trajectory_msgs/msg/JointTrajectory"
FRAME_ID = "base_link"
"""``header.frame_id`` of the messages written."""


def _rosbags() -> Any:
    try:
        import rosbags.rosbag2
        import rosbags.typesys
    except ImportError as exc:  # pragma: no cover - the extra is part of "all"
        raise ConfigError("ROS 2 bags need the 'ros' extra: pip install 'scalf-opt[ros]'") from exc
    return rosbags


def is_bag(path: str | Path) -> bool:
    """Whether ``path`` names a ROS 2 bag (``.mcap``, ``.db3`` or a bag directory)."""
    path = Path(path)
    return path.suffix in BAG_SUFFIXES or (path.is_dir() and (path / "metadata.yaml").exists())


@dataclass(frozen=True)
class JointStateSeries:
    """A topic of ``JointState`` messages: one per instant, the same joints in each.

    Attributes:
        topic: Topic name, e.g. ``/joint_states``.
        names: Joint names, in message order.
        t_s: Message times, shape (n,) [s].
        position: Shape (joints, n) [rad or m].
        velocity: Shape (joints, n) [rad/s or m/s], or ``None`` (not in the messages).
        effort: Shape (joints, n) [N m or N], or ``None``.
    """

    topic: str
    names: tuple[str, ...]
    t_s: np.ndarray
    position: np.ndarray
    velocity: np.ndarray | None = None
    effort: np.ndarray | None = None


@dataclass(frozen=True)
class TrajectoryMessage:
    """One ``JointTrajectory`` message: points of the joints at times from its start.

    Attributes:
        topic: Topic name.
        t_s: Its stamp [s].
        names: Joint names.
        time_from_start_s: Each point's time from the start, shape (n,) [s].
        position, velocity, acceleration, effort: Shape (joints, n), SI units.
    """

    topic: str
    t_s: float
    names: tuple[str, ...]
    time_from_start_s: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray


def _split_ns(t_s: float) -> tuple[int, int]:
    ns = round(t_s * 1e9)
    return ns // 1_000_000_000, ns % 1_000_000_000


def write_bag(
    path: str | Path,
    series: list[JointStateSeries],
    trajectories: list[TrajectoryMessage] = (),  # type: ignore[assignment]
) -> Path:
    """Write the series and trajectories into one MCAP file ``path``, atomically.

    Raises:
        ConfigError: ``path`` does not end in ``.mcap``, or its folder cannot be written.
    """
    path = Path(path)
    if path.suffix != ".mcap":
        raise ConfigError(f"{path}: a ROS 2 bag is written as an .mcap file")
    rb = _rosbags()
    store = rb.typesys.get_typestore(rb.typesys.Stores.ROS2_HUMBLE)
    types = store.types
    header, stamp = types["std_msgs/msg/Header"], types["builtin_interfaces/msg/Time"]
    duration = types["builtin_interfaces/msg/Duration"]
    state, trajectory = types[JOINT_STATE], types[JOINT_TRAJECTORY]
    point = types["trajectory_msgs/msg/JointTrajectoryPoint"]
    # written in a private scratch folder, then into place as any output (write_with)
    scratch = Path(tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}bag-{os.getpid()}-"))
    try:
        bag = scratch / "bag"
        messages: list[tuple[int, Any, bytes]] = []
        writer = rb.rosbag2.Writer(bag, version=9, storage_plugin=rb.rosbag2.StoragePlugin.MCAP)
        with writer:
            for s in series:
                conn = writer.add_connection(s.topic, JOINT_STATE, typestore=store)
                empty = np.zeros(0)
                for k, t in enumerate(s.t_s):
                    msg = state(
                        header(stamp(*_split_ns(float(t))), FRAME_ID),
                        list(s.names),
                        np.ascontiguousarray(s.position[:, k], dtype=np.float64),
                        empty if s.velocity is None else np.ascontiguousarray(s.velocity[:, k]),
                        empty if s.effort is None else np.ascontiguousarray(s.effort[:, k]),
                    )
                    ns = round(float(t) * 1e9)
                    messages.append((ns, conn, store.serialize_cdr(msg, JOINT_STATE)))
            for traj in trajectories:
                conn = writer.add_connection(traj.topic, JOINT_TRAJECTORY, typestore=store)
                points = [
                    point(
                        np.ascontiguousarray(traj.position[:, k], dtype=np.float64),
                        np.ascontiguousarray(traj.velocity[:, k], dtype=np.float64),
                        np.ascontiguousarray(traj.acceleration[:, k], dtype=np.float64),
                        np.ascontiguousarray(traj.effort[:, k], dtype=np.float64),
                        duration(*_split_ns(float(ts))),
                    )
                    for k, ts in enumerate(traj.time_from_start_s)
                ]
                msg = trajectory(
                    header(stamp(*_split_ns(traj.t_s)), FRAME_ID), list(traj.names), points
                )
                messages.append(
                    (round(traj.t_s * 1e9), conn, store.serialize_cdr(msg, JOINT_TRAJECTORY))
                )
            # in time order, as a recorder writes them (readers expect it)
            for ns, conn, data in sorted(messages, key=lambda m: (m[0], m[1].id)):
                writer.write(conn, ns, data)
        with open(bag / "bag.mcap", "rb") as written:
            write_with(path, lambda handle: shutil.copyfileobj(written, handle))
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return path


_SCRATCH_FOLDER = re.compile(rf"[^\s'\"]*{re.escape(SCRATCH_PREFIX)}bag-\d+-[^\s'\"/]*/")
"""The private copy's folder at the start of a path a reader's error quotes."""


def _bag_error(path: Path, exc: Exception) -> LogError:
    """The reader's error as one line about the bag the user named.

    A path in the private copy (which is gone once the command ends) is shown as ``path``.
    """
    text = str(exc).strip()
    reason = text.splitlines()[0].rstrip(".") if text else type(exc).__name__
    where = "" if str(path.parent) == "." else f"{path.parent}/"
    reason = _SCRATCH_FOLDER.sub(lambda _: where, reason)
    return LogError(f"{path}: not a readable ROS 2 bag ({reason}; truncated or not a bag?)")


def read_joint_states(path: str | Path, topic: str | None = None) -> JointStateSeries:
    """Read every ``JointState`` message of ``topic`` in the bag ``path``.

    ``topic`` ``None``: the bag's one ``JointState`` topic.

    Raises:
        LogError: The bag cannot be read (truncated, not a bag), has no such topic (the message
            lists the joint-state topics it has), no topic given and not exactly one
            ``JointState`` topic (the message lists them), the topic is of another type, a message's
            names or arrays disagree with the first's, a value is not finite, or the time stamps
            do not increase (the message names the topic and the message's index).
    """
    path = Path(path)
    with opened_bag(path) as reader:
        return _read_joint_states(path, reader, topic)


@contextmanager
def opened_bag(path: Path) -> Iterator[Any]:
    """``rosbags``' ``AnyReader``, opened on a bounded private copy of the bag ``path``.

    The reader is given the copy, nothing else (:func:`_bounded_copy`); its errors name ``path``.

    Raises:
        LogError: The bag does not exist, is too large, or cannot be opened (truncated, not a
            bag).
    """
    if not path.exists():
        raise LogError(f"{path}: the bag does not exist")
    _rosbags()
    from rosbags.highlevel import AnyReader

    with scratch_folder("bag") as folder, bounded_decompression(path):
        local = _bounded_copy(path, folder)
        if local.is_dir() and (local / "metadata.yaml").exists():
            copied = sum(f.stat().st_size for f in local.iterdir())
            inflate_compressed_files(local, path, MAX_BAG_BYTES - copied)
        check_sqlite_files(local, path)
        try:
            reader = AnyReader([local])
            reader.open()
        except LogError:
            raise
        except Exception as exc:  # rosbags raises many kinds on a broken file
            raise _bag_error(path, exc) from exc
        try:
            yield reader
        finally:
            reader.close()


def _bounded_copy(path: Path, folder: Path) -> Path:
    """A copy of the bag ``path`` (a file, or a folder of files) in ``folder``, bounded.

    Raises:
        LogError: The bag, or a file of its folder, is not a regular file or is larger than
            :data:`MAX_BAG_BYTES`; its folder holds a link or a folder.
    """
    if not path.is_dir():
        copy = folder / path.name
        copy_untrusted(path, copy, "bag", MAX_BAG_BYTES, LogError)
        return copy
    copy = folder / (path.name or "bag")
    copy.mkdir()
    entries = sorted(path.iterdir())
    for entry in entries:
        if entry.is_symlink() or entry.is_dir():
            raise LogError(f"{entry}: a bag folder holds its files only, not links or folders")
    total = sum(entry.stat().st_size for entry in entries)
    if total > MAX_BAG_BYTES:
        raise LogError(
            f"{path}: its files hold {total:,} bytes together, more than the {MAX_BAG_BYTES:,} "
            "a bag may hold"
        )
    left = MAX_BAG_BYTES  # and bounded while copying: a file may grow meanwhile
    for entry in entries:
        left -= copy_untrusted(entry, copy / entry.name, "bag", left, LogError)
    return copy


def checked_names(names: tuple[str, ...], where: str) -> tuple[str, ...]:
    """A message's joint names, each once (in linear time: a message may be hostile).

    Raises:
        LogError: A joint named twice (the message names it).
    """
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise LogError(f"{where}: joint {name!r} is named twice in one message")
        seen.add(name)
    return names


def check_topic_names(path: Path, reader: Any) -> None:
    """Refuse a bag whose index names a topic by nothing (a NULL or empty name, or not text).

    Raises:
        LogError: Such a connection, with its message type.
    """
    for c in reader.connections:
        if not isinstance(c.topic, str) or not c.topic:
            raise LogError(f"{path}: a topic of {c.msgtype!s:.100} messages has no name")


def _read_joint_states(path: Path, reader: Any, topic: str | None) -> JointStateSeries:
    """:func:`read_joint_states` of the opened bag ``reader``; messages name ``path``."""
    topic, connections = _joint_state_topic(path, reader, topic)
    names: tuple[str, ...] | None = None
    times: list[float] = []
    columns: dict[str, list[np.ndarray]] = {"position": [], "velocity": [], "effort": []}
    try:
        for index, (conn, ns, raw) in enumerate(reader.messages(connections=connections)):
            msg: Any = reader.deserialize(raw, conn.msgtype)
            stamp = msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec
            t = stamp if stamp > 0 else ns * 1e-9
            where = f"{path}: topic {topic}, message {index}"
            names = _message_names(msg, names, where)
            if (index + 1) * 3 * len(names) > MAX_VALUES:
                raise LogError(
                    f"{path}: topic {topic} holds more than {MAX_VALUES:,} numbers: cut the bag "
                    "to the part to analyse"
                )
            if times and not t > times[-1]:
                raise LogError(
                    f"{where}: time stamp {t!r} s does not increase (the previous message "
                    f"has {times[-1]!r} s)"
                )
            times.append(t)
            for field, values in columns.items():
                values.append(_message_values(msg, field, len(names), where))
    except LogError:
        raise
    except Exception as exc:
        raise _bag_error(path, exc) from exc
    if names is None:
        raise LogError(f"{path}: topic {topic!r} has no messages")
    where = f"{path}: topic {topic}"
    series = {
        field: _stacked(values, len(names), field, where) for field, values in columns.items()
    }
    position = series["position"]
    if position is None:
        raise LogError(f"{path}: topic {topic}: the messages have no position")
    t_s = np.array(times)
    if t_s.size and not math.isfinite(float(t_s[-1])):
        raise LogError(f"{path}: topic {topic}: a time stamp is not finite")
    return JointStateSeries(topic, names, t_s, position, series["velocity"], series["effort"])


def _joint_state_topic(path: Path, reader: Any, topic: str | None) -> tuple[str, list[Any]]:
    """The JointState topic to read and its connections.

    ``topic`` ``None``: the bag's only JointState topic.
    """
    check_topic_names(path, reader)
    states = sorted({c.topic for c in reader.connections if c.msgtype == JOINT_STATE})
    have = ", ".join(states) if states else "none"
    if topic is None:
        if len(states) != 1:
            raise LogError(
                f"{path}: the bag has {len(states) or 'no'} JointState topics ({have}); "
                "name one with --topic"
            )
        topic = states[0]
    connections = [c for c in reader.connections if c.topic == topic]
    if not connections:
        raise LogError(
            f"{path}: no topic {topic!r} in the bag (its JointState topics: {have}); "
            "name one with --topic"
        )
    kinds = {c.msgtype for c in connections}
    if kinds != {JOINT_STATE}:
        raise LogError(
            f"{path}: topic {topic!r} holds {', '.join(sorted(kinds))}, not {JOINT_STATE}"
        )
    return topic, connections


def _message_names(msg: Any, first: tuple[str, ...] | None, where: str) -> tuple[str, ...]:
    """A message's joint names: bounded, each once, the same as the first message's."""
    if len(msg.name) > MAX_JOINTS:
        raise LogError(
            f"{where}: {len(msg.name):,} joints, more than the {MAX_JOINTS} a message may name"
        )
    here = tuple(msg.name)
    if first is None:
        return checked_names(here, where)
    if here != first:
        raise LogError(f"{where}: joint names {list(here)} differ from the first's")
    return first


def _message_values(msg: Any, field: str, joints: int, where: str) -> np.ndarray:
    """A message's ``field`` (position, velocity, effort): none, or one finite value a joint."""
    array = np.asarray(getattr(msg, field), dtype=float)
    if array.size not in (0, joints):
        raise LogError(f"{where}: {field} has {array.size} values for {joints} joints")
    if not np.all(np.isfinite(array)):
        raise LogError(f"{where}: {field} holds a value that is not finite")
    return array


def _stacked(values: list[np.ndarray], joints: int, field: str, where: str) -> np.ndarray | None:
    """A field over the messages, shape (joints, messages); ``None`` when no message has it.

    Raises:
        LogError: Some messages have it and some do not.
    """
    sizes = {v.size for v in values}
    if sizes == {0}:
        return None
    if sizes == {joints}:
        return np.array(values).T
    raise LogError(f"{where}: {field} is missing from some messages")


CYLINDER_SUFFIX = "_cylinder"


def cylinder_joint_name(joint: str) -> str:
    """The joint-state name of the cylinder driving URDF joint ``joint`` (``<joint>_cylinder``)."""
    return f"{joint}{CYLINDER_SUFFIX}"
