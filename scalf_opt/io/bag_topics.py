"""Any topic of a ROS 2 bag, read through the message definitions the bag embeds (extra ``ros``).

A robot's driver publishes its own messages (``unitree_go/msg/LowState``, ...), whose definitions
a recorder writes into the bag (MCAP schemas, the sqlite3 bag's ``message_definitions``);
``rosbags``' ``AnyReader`` builds its type store from them, so no ROS installation and no copy of
the driver's message package is needed. :func:`read_topics` reads several topics in one pass over
a bounded private copy of the bag (:func:`~scalf_opt.io.ros_bag.read_joint_states`' copy), each
message turned into a row of numbers by the caller's function.

Time: a stamp field (``header.stamp``: ``sec + 1e-9 nanosec``, or a number in ``time_unit_s``)
when the request names one and it is set, else the time the recorder received the message [s].
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.errors import LogError
from scalf_opt.io.bag_bounds import MAX_VALUES
from scalf_opt.io.ros_bag import _bag_error, check_topic_names, opened_bag

_STEP = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)(?:\[([0-9]+)\])?")


def field_getter(path: str) -> Callable[[Any], Any]:
    """A function that reads the field ``path`` (``motor_state[3].q``) of a message."""
    steps = [
        (m.group(1), None if m.group(2) is None else int(m.group(2))) for m in _STEP.finditer(path)
    ]

    def get(message: Any) -> Any:
        value = message
        for name, index in steps:
            value = getattr(value, name)
            if index is not None:
                value = value[index]
        return value

    return get


def stamp_s(value: Any, unit_s: float, origin_ns: int) -> float | None:
    """A stamp field as seconds after ``origin_ns``, or ``None`` when it is not set (zero).

    A ``builtin_interfaces/Time`` is taken in integer nanoseconds before the origin is subtracted
    (seconds since the epoch as a double resolve only a quarter of a microsecond); a number is
    taken in ``unit_s`` as it is (a driver's own clock: a tick count from its start).
    """
    if hasattr(value, "sec") and hasattr(value, "nanosec"):
        ns = int(value.sec) * 1_000_000_000 + int(value.nanosec)
        return (ns - origin_ns) * 1e-9 if ns > 0 else None
    seconds = float(value) * unit_s
    return seconds if seconds > 0 else None


@dataclass(frozen=True)
class TopicRequest:
    """A topic to read and how to turn each of its messages into numbers.

    Attributes:
        key: The request's name in the answer.
        topic: The topic (``None``: the bag's one topic of ``message``).
        message: The message type the topic must hold (``None``: any).
        row: A message -> its numbers, shape (k,); may raise :class:`LogError` naming the field.
        stamp: A stamp field path, or ``""`` for the recording time.
        time_unit_s: Seconds per unit of a numeric stamp field.
    """

    key: str
    topic: str | None
    message: str | None
    row: Callable[[Any], np.ndarray]
    stamp: str = ""
    time_unit_s: float = 1.0


@dataclass(frozen=True)
class TopicRows:
    """One topic's messages as numbers.

    Attributes:
        topic: The topic.
        message: Its message type.
        t_s: Each message's time, shape (n,) [s], from the bag's first recorded message (a
            stamp field in a number of ``time_unit_s``: as it is).
        values: The rows, shape (n, k).
    """

    topic: str
    message: str
    t_s: np.ndarray
    values: np.ndarray


def _choose(path: Path, request: TopicRequest, types: dict[str, set[str]]) -> str:
    """The topic of a request: its own (checked), or the bag's one topic of its type."""
    if request.topic is not None:
        if request.topic not in types:
            raise LogError(
                f"{path}: no topic {request.topic!r} in the bag (its topics: "
                f"{', '.join(sorted(types)) or 'none'})"[:400]
            )
        held = types[request.topic]
        if request.message is not None and held != {request.message}:
            raise LogError(
                f"{path}: topic {request.topic!r} holds {', '.join(sorted(held))}, not "
                f"{request.message}"[:300]
            )
        return request.topic
    matching = sorted(t for t, held in types.items() if request.message in held)
    if len(matching) != 1:
        have = ", ".join(f"{t} ({', '.join(sorted(h))})" for t, h in sorted(types.items()))
        raise LogError(
            f"{path}: the bag has {len(matching) or 'no'} {request.message} topics "
            f"({', '.join(matching) if matching else have or 'no topics'}); name one with --topic"[
                :400
            ]
        )
    return matching[0]


def read_topics(path: str | Path, requests: Sequence[TopicRequest]) -> dict[str, TopicRows]:
    """Read each requested topic of the bag ``path`` in one pass (module docstring).

    Raises:
        LogError: The bag cannot be read; a topic is missing, of another type, or ambiguous; a
            message cannot be turned into numbers (the message names the topic and its index); a
            value that is not finite; time that does not increase; a topic with no message; more
            numbers than :data:`MAX_VALUES`.
    """
    path = Path(path)
    with opened_bag(path) as reader:
        return _read(path, reader, requests)


class _Collector:
    """One request's messages as they come: their times and numbers, checked one by one."""

    def __init__(self, path: Path, request: TopicRequest, topic: str, origin_ns: int) -> None:
        self.path, self.request, self.topic, self.origin_ns = path, request, topic, origin_ns
        self.stamp_of = field_getter(request.stamp) if request.stamp else None
        self.times: list[float] = []
        self.rows: list[np.ndarray] = []

    def where(self) -> str:
        """The next message, for messages."""
        return f"{self.path}: topic {self.topic}, message {len(self.rows)}"

    def add(self, message: Any, recorded_ns: int) -> None:
        """Take one message (its stamp, else its recording time).

        Raises:
            LogError: A value or time that is not finite, time that goes back, or more numbers
                than :data:`MAX_VALUES`.
        """
        stamp = self.stamp_of
        stamped = (
            stamp_s(stamp(message), self.request.time_unit_s, self.origin_ns) if stamp else None
        )
        t = stamped if stamped is not None else (recorded_ns - self.origin_ns) * 1e-9
        values = np.asarray(self.request.row(message), dtype=float)
        if not np.all(np.isfinite(values)) or not np.isfinite(t):
            raise LogError(f"{self.where()}: a value is not a finite number")
        if self.times and t < self.times[-1]:
            raise LogError(
                f"{self.where()}: time {t!r} s goes back (the previous message has "
                f"{self.times[-1]!r} s)"
            )
        if (len(self.times) + 1) * values.size > MAX_VALUES:
            raise LogError(
                f"{self.path}: topic {self.topic} holds more than {MAX_VALUES:,} numbers: "
                "cut the bag to the part to analyse"
            )
        self.times.append(t)
        self.rows.append(values)

    def rows_of(self, message_types: set[str]) -> TopicRows:
        """What was collected.

        Raises:
            LogError: The topic had no message.
        """
        if not self.rows:
            raise LogError(f"{self.path}: topic {self.topic!r} has no messages")
        message = ", ".join(sorted(message_types))
        return TopicRows(self.topic, message, np.array(self.times), np.vstack(self.rows))


def _read(path: Path, reader: Any, requests: Sequence[TopicRequest]) -> dict[str, TopicRows]:
    """:func:`read_topics` of the opened bag ``reader``; messages name ``path``."""
    check_topic_names(path, reader)
    types: dict[str, set[str]] = {}
    for c in reader.connections:
        types.setdefault(c.topic, set()).add(c.msgtype)
    origin_ns = int(reader.start_time)
    by_topic = {}
    for r in requests:
        topic = _choose(path, r, types)
        by_topic[topic] = _Collector(path, r, topic, origin_ns)
    if len(by_topic) != len(requests):
        raise LogError(f"{path}: two requests name one topic")  # pragma: no cover
    connections = [c for c in reader.connections if c.topic in by_topic]
    where = f"{path}"
    try:
        for conn, ns, raw in reader.messages(connections=connections):
            collector = by_topic[conn.topic]
            where = collector.where()
            collector.add(reader.deserialize(raw, conn.msgtype), ns)
    except LogError:
        raise
    except (AttributeError, IndexError, TypeError, ValueError) as exc:
        raise LogError(f"{where}: {_short(exc)} (the mapping names a field it lacks?)") from exc
    except Exception as exc:
        raise _bag_error(path, exc) from exc
    return {c.request.key: c.rows_of(types[topic]) for topic, c in by_topic.items()}


def _short(exc: Exception) -> str:
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return text[:200]


def topic_types(path: str | Path) -> dict[str, set[str]]:
    """Each topic of the bag ``path`` and its message types (the bag's index only).

    Raises:
        LogError: The bag cannot be read.
    """
    with opened_bag(Path(path)) as reader:
        check_topic_names(Path(path), reader)
        types: dict[str, set[str]] = {}
        for c in reader.connections:
            types.setdefault(str(c.topic), set()).add(c.msgtype)
        return types
