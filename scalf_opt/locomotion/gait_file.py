"""Gait files: a TOML ``[gait]`` table of :class:`~scalf_opt.locomotion.gait.Gait` fields.

A key left out keeps the value of the gait it is read over (the robot's default). Beside the
table, ``robot = "NAME"`` may say which robot the gait was made for (``scalf-opt gait`` writes
it); a command that walks the gait on another robot says so (:func:`gait_file_robot`).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from scalf_opt.errors import ConfigError, GaitError
from scalf_opt.files import read_toml
from scalf_opt.locomotion.gait import Gait


def read_gait_fields(path: str | Path) -> dict[str, float | int]:
    """The fields a gait file sets (type-checked, not yet range-checked).

    Raises:
        ConfigError: The file cannot be read, is not TOML, or has an unknown or mistyped key.
    """
    path = Path(path)
    data = read_toml(path, "gait")
    table = data.get("gait", data)
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [gait] must be a table")
    stray = sorted(set(data) - {"gait", "robot"}) if "gait" in data else []
    if stray:
        raise ConfigError(
            f"{path}: unknown key or table {stray[0]!r} beside [gait] (a gait file holds one "
            "[gait] table, or its fields at the top level)"
        )
    known = Gait.field_names()
    values: dict[str, float | int] = {}
    for key, value in table.items():
        if key not in known:
            raise ConfigError(f"{path}: {Gait.unknown_field(key)}")
        if key == "cycles":
            if isinstance(value, bool) or not isinstance(value, int):
                raise ConfigError(f"{path}: gait field cycles must be an integer, got {value!r}")
        elif isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"{path}: gait field {key} must be a number, got {value!r}")
        values[key] = value
    return values


def gait_file_robot(path: str | Path) -> str | None:
    """The robot a gait file says it was made for (its ``robot`` key beside ``[gait]``).

    Raises:
        ConfigError: The file cannot be read, or ``robot`` is not a short text.
    """
    data = read_toml(Path(path), "gait")
    robot = data.get("robot") if "gait" in data else None
    if robot is not None and not (isinstance(robot, str) and 0 < len(robot) <= 200):
        raise ConfigError(f"{path}: robot must be a robot's name (a short text), got {robot!r}")
    return robot


def read_gait(path: str | Path, base: Gait | None = None) -> Gait:
    """The gait of a file, over ``base`` (default: the paper's) for the keys it leaves out.

    Raises:
        ConfigError: See :func:`read_gait_fields`.
        GaitError: A value is out of its allowed range (the message names the file and field).
    """
    values = read_gait_fields(path)
    try:
        return replace(base or Gait(), **values)  # type: ignore[arg-type]
    except GaitError as exc:
        raise GaitError(f"{path}: {exc}", field=exc.field) from exc
