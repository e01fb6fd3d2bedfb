"""Where a robot's log keeps its joints: the mapping of a bag topic or a wide CSV (TOML).

A robot's own log holds, per instant, every motor's angle, rate and torque, and often the feet's
force sensors, in the layout its driver chose. A mapping says where each quantity is:

* ``source``: ``bag`` (a ROS 2 bag, any message type whose definition the bag embeds) or ``csv``
  (a wide CSV: a row per instant, a column per joint and quantity);
* ``joints``: the URDF joint of each motor index ``{i}`` (``0, 1, ...``), in the log's order;
* ``position``, ``velocity`` (optional: else the angles are differentiated), ``effort``: a
  template per motor, with ``{i}`` the motor's index and ``{joint}`` its URDF name. In a bag a
  field path into the message (``motor_state[{i}].q``); in a CSV a column name (``q_{i}``);
* ``foot_force`` (optional) and ``feet``: the foot sensors' template and the leg (RF, LF, RH, LH)
  of each index ``{i}``;
* a bag's ``topic`` and ``message`` type (either may be left out when the bag has one topic of
  that type); ``time``: a stamp field (``header.stamp``) or ``""`` for the time the message was
  recorded; a CSV's ``time`` column and ``time_unit_s`` (``0.001`` for milliseconds);
* a ``sensor_msgs/JointState``-like message names its joints in each message: ``names = "name"``
  (a field of strings) and ``position = "position"`` (arrays in that order); ``joints`` then
  lists the URDF joint of each name in ``rename`` (``{ "bag name" = "URDF joint" }``), or none
  when the names are the URDF's.

Built-in mappings (:data:`BUILT_IN`): ``joint_state`` (``sensor_msgs/msg/JointState``),
``unitree_go`` (``unitree_go/msg/LowState`` of ``unitree_ros2``) and ``unitree_legged_msgs``
(``unitree_legged_msgs/msg/LowState``), the last two in Unitree's motor order FR, FL, RR, RL
(hip, thigh, calf each) with Unitree's joint names (Go1, A1).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from scalf_opt.errors import ConfigError, did_you_mean
from scalf_opt.files import read_toml
from scalf_opt.io.bag_bounds import MAX_JOINTS
from scalf_opt.types import LEG_NAMES

SOURCES = ("bag", "csv")
"""What a mapping reads: a ROS 2 bag's topic, or a wide CSV."""

QUANTITIES = ("position", "velocity", "effort", "foot_force")
"""The per-index templates of a mapping: angle [rad], rate [rad/s], torque [N m], foot force [N]."""

_PATH = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+\])?(\.[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+\])?)*$")
"""A field path once its placeholders are filled: ``motor_state[3].q``, ``header.stamp``."""

_FIELDS = (
    "source",
    "topic",
    "message",
    "time",
    "time_unit_s",
    "joints",
    "names",
    "rename",
    *QUANTITIES,
    "feet",
)

UNITREE_JOINTS: tuple[str, ...] = tuple(
    f"{leg}_{part}_joint" for leg in ("FR", "FL", "RR", "RL") for part in ("hip", "thigh", "calf")
)
"""Unitree's motor order (``motor_state[0..11]``) as the URDF joints of Go1 and A1."""

UNITREE_FEET: tuple[str, ...] = ("RF", "LF", "RH", "LH")
"""The legs of Unitree's ``foot_force[0..3]`` (FR, FL, RR, RL)."""


@dataclass(frozen=True)
class LogMapping:
    """Where a log keeps each joint's quantities (module docstring).

    Attributes:
        name: The mapping's name (a built-in's, or the file's path) for messages.
        source: ``bag`` or ``csv``.
        joints: The URDF joint of each index ``{i}``; empty with ``names`` and no ``rename``.
        position, velocity, effort: Templates (``velocity`` may be ``None``).
        foot_force: The foot sensors' template, or ``None``.
        feet: The leg of each foot-sensor index.
        topic: A bag's topic (``None``: the bag's one topic of ``message``).
        message: A bag's message type (``None``: any; then ``topic`` is required).
        time: A stamp field path (bag; ``""``: the recording time) or the time column (CSV).
        time_unit_s: Seconds per unit of a CSV's time column.
        names: A field of joint names in each message (``JointState``'s ``name``), or ``None``.
        rename: With ``names``: a message's joint name -> URDF joint.
    """

    name: str
    source: str
    joints: tuple[str, ...]
    position: str
    effort: str
    velocity: str | None = None
    foot_force: str | None = None
    feet: tuple[str, ...] = ()
    topic: str | None = None
    message: str | None = None
    time: str = ""
    time_unit_s: float = 1.0
    names: str | None = None
    rename: Mapping[str, str] = field(default_factory=dict)

    def path(self, quantity: str, index: int) -> str:
        """The filled template of ``quantity`` for index ``index`` (a field path or column)."""
        template = getattr(self, quantity)
        joint = self.joints[index] if quantity != "foot_force" and self.joints else ""
        return str(template).replace("{i}", str(index)).replace("{joint}", joint)

    def with_topic(self, topic: str | None) -> LogMapping:
        """The same mapping on another topic (``--topic``); ``None`` keeps its own."""
        return self if topic is None else replace(self, topic=topic)


def _unitree_low_state(package: str, motors: str, torque: str, feet: str) -> LogMapping:
    """A Unitree ``LowState`` message's mapping: the package's field names, Unitree's order."""
    return LogMapping(
        name=package,
        source="bag",
        message=f"{package}/msg/LowState",
        joints=UNITREE_JOINTS,
        position=f"{motors}[{{i}}].q",
        velocity=f"{motors}[{{i}}].dq",
        effort=f"{motors}[{{i}}].{torque}",
        foot_force=f"{feet}[{{i}}]",
        feet=UNITREE_FEET,
    )


BUILT_IN: dict[str, LogMapping] = {
    "joint_state": LogMapping(
        name="joint_state",
        source="bag",
        message="sensor_msgs/msg/JointState",
        time="header.stamp",
        joints=(),
        names="name",
        position="position",
        velocity="velocity",
        effort="effort",
    ),
    "unitree_go": _unitree_low_state("unitree_go", "motor_state", "tau_est", "foot_force"),
    "unitree_legged_msgs": _unitree_low_state(
        "unitree_legged_msgs", "motorState", "tauEst", "footForce"
    ),
}
"""The mappings known by name (``--mapping unitree_go``); a bag whose topic has one of their
message types is read through it without ``--mapping``."""

MAPPING_OF_MESSAGE = {m.message: m for m in BUILT_IN.values() if m.message}
"""Message type -> its built-in mapping."""


def _text(data: Mapping[str, Any], key: str, where: str, default: str | None = None) -> str | None:
    value = data.get(key, default)
    if value is None:
        return None
    if not isinstance(value, str):
        raise ConfigError(f"{where}: field {key} must be a string, got {value!r}"[:300], field=key)
    return value


def _names(data: Mapping[str, Any], key: str, where: str) -> tuple[str, ...]:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
        raise ConfigError(f"{where}: field {key} must be a list of names", field=key)
    if len(value) > MAX_JOINTS:
        raise ConfigError(f"{where}: field {key} lists {len(value)} names (most {MAX_JOINTS})")
    twice = sorted({v for v in value if value.count(v) > 1})
    if twice:
        raise ConfigError(f"{where}: field {key} names {twice[0]!r} twice", field=key)
    return tuple(value)


def _template(mapping: LogMapping, quantity: str, where: str) -> None:
    """A template must fill to a field path (bag) or a column name (CSV) for every index."""
    template = getattr(mapping, quantity)
    if template is None:
        return
    if not template.strip():
        raise ConfigError(f"{where}: field {quantity} is empty", field=quantity)
    count = len(mapping.feet) if quantity == "foot_force" else len(mapping.joints)
    per_index = "{i}" in template or "{joint}" in template
    if mapping.names is None and count > 1 and not per_index:
        raise ConfigError(
            f"{where}: field {quantity} = {template!r} names one place for {count} "
            "indices: put {i} (the index) or {joint} (the URDF joint) in it",
            field=quantity,
        )
    if mapping.source == "bag" and count:
        filled = mapping.path(quantity, 0)
        if not _PATH.match(filled):
            raise ConfigError(
                f"{where}: field {quantity} = {template!r} is not a field path "
                "(names, [index], dots: motor_state[{{i}}].q)",
                field=quantity,
            )


def mapping_from_dict(data: Mapping[str, Any], name: str) -> LogMapping:
    """Check a mapping's table (module docstring); ``name`` names it in messages.

    Raises:
        ConfigError: An unknown field (with the closest known one), a field of the wrong type, a
            missing ``position`` or ``effort``, no joints, feet that are no legs, a template that
            does not name its index.
    """
    where = f"mapping {name}"
    _check_fields(data, where)
    mapping = LogMapping(
        name=name,
        source=str(_text(data, "source", where, "bag")),
        joints=_names(data, "joints", where),
        position=str(_text(data, "position", where)),
        effort=str(_text(data, "effort", where)),
        velocity=_text(data, "velocity", where),
        foot_force=_text(data, "foot_force", where),
        feet=_feet(data, where),
        topic=_text(data, "topic", where),
        message=_text(data, "message", where),
        time=str(_text(data, "time", where, "")),
        time_unit_s=_time_unit_s(data, where),
        names=_text(data, "names", where),
        rename=_rename(data, where),
    )
    _check_together(mapping, where)
    for quantity in QUANTITIES:
        _template(mapping, quantity, where)
    return mapping


def _check_fields(data: Mapping[str, Any], where: str) -> None:
    """Every field known, the source one of :data:`SOURCES`, ``position`` and ``effort`` given."""
    for key in data:
        if key not in _FIELDS:
            raise ConfigError(
                f"{where}: unknown field {key!r}{did_you_mean(key, _FIELDS)} "
                f"(the fields: {', '.join(_FIELDS)})"[:400],
                field=key,
            )
    source = _text(data, "source", where, "bag")
    if source not in SOURCES:
        raise ConfigError(f"{where}: field source must be bag or csv, got {source!r}"[:200])
    for required in ("position", "effort"):
        if required not in data:
            raise ConfigError(f"{where}: field {required} is missing", field=required)


def _time_unit_s(data: Mapping[str, Any], where: str) -> float:
    unit = data.get("time_unit_s", 1.0)
    if isinstance(unit, bool) or not isinstance(unit, int | float) or not 1e-12 <= unit <= 1e6:
        raise ConfigError(
            f"{where}: field time_unit_s must be a number of seconds in [1e-12, 1e6], got {unit!r}"[
                :200
            ],
            field="time_unit_s",
        )
    return float(unit)


def _rename(data: Mapping[str, Any], where: str) -> dict[str, str]:
    rename = data.get("rename", {})
    if not isinstance(rename, dict) or not all(
        isinstance(k, str) and isinstance(v, str) for k, v in rename.items()
    ):
        raise ConfigError(f"{where}: field rename must map message names to URDF joints")
    return dict(rename)


def _feet(data: Mapping[str, Any], where: str) -> tuple[str, ...]:
    feet = _names(data, "feet", where)
    for leg in feet:
        if leg not in LEG_NAMES:
            raise ConfigError(
                f"{where}: field feet: {leg!r} is not a leg (the legs: {', '.join(LEG_NAMES)})",
                field="feet",
            )
    return feet


def _check_together(mapping: LogMapping, where: str) -> None:
    """The fields that only make sense together, or for one source."""
    if mapping.names is not None and mapping.source != "bag":
        raise ConfigError(f"{where}: field names is for a bag's messages, not a CSV")
    if mapping.names is None and not mapping.joints:
        raise ConfigError(f"{where}: field joints is missing (the URDF joint of each index)")
    if (mapping.foot_force is None) != (not mapping.feet):
        raise ConfigError(f"{where}: fields foot_force and feet go together")
    if mapping.source == "csv" and not mapping.time:
        raise ConfigError(f"{where}: field time is missing (the CSV's time column)")
    if mapping.source == "bag" and mapping.topic is None and mapping.message is None:
        raise ConfigError(f"{where}: give the bag's topic or message type (fields topic, message)")


def read_mapping(text: str) -> LogMapping:
    """A built-in mapping by name, or a mapping file (``.toml``).

    Raises:
        ConfigError: Neither a built-in name nor a readable, valid mapping file.
    """
    if text in BUILT_IN:
        return BUILT_IN[text]
    path = Path(text)
    if path.suffix != ".toml":
        raise ConfigError(
            f"--mapping {text}: neither a mapping file (.toml) nor a built-in mapping"
            f"{did_you_mean(text, BUILT_IN)} (built in: {', '.join(BUILT_IN)})"[:300]
        )
    return mapping_from_dict(read_toml(path, "mapping"), str(path))
