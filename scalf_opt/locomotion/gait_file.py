"""Gait files: a TOML ``[gait]`` table of :class:`~scalf_opt.locomotion.gait.Gait` fields.

A key left out keeps the value of the gait it is read over (the robot's default). Beside the
table, ``robot = "NAME"`` may say which robot the gait was made for (``scalf-opt gait`` writes
it); a command that walks the gait on another robot says so (:func:`gait_file_robot`).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from scalf_opt.errors import GaitError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.tables import Table, number_value


def read_gait_fields(path: str | Path) -> dict[str, float | int]:
    """The fields a gait file sets (type-checked, not yet range-checked).

    Raises:
        ConfigError: The file cannot be read, is not TOML, or has an unknown or mistyped key.
    """
    file = Table.read(path, "gait")
    if "gait" in file and not isinstance(file.data["gait"], dict):
        raise file.error("[gait] must be a table")
    table = file.table("gait") if "gait" in file else file
    stray = sorted(set(file.data) - {"gait", "robot"}) if "gait" in file else []
    if stray:
        raise file.error(
            f"unknown key or table {stray[0]!r} beside [gait] (a gait file holds one "
            "[gait] table, or its fields at the top level)"
        )
    known = Gait.field_names()
    values: dict[str, float | int] = {}
    for key in table.data:
        if key not in known:
            raise file.error(Gait.unknown_field(key))
        label = f"gait field {key}"
        values[key] = (
            table.integer(key, label)
            if key == "cycles"
            else number_value(file.path, label, table.data[key], finite=False)
        )
    return values


def gait_file_robot(path: str | Path) -> str | None:
    """The robot a gait file says it was made for (its ``robot`` key beside ``[gait]``).

    Raises:
        ConfigError: The file cannot be read, or ``robot`` is not a short text.
    """
    file = Table.read(path, "gait")
    robot = file.data.get("robot") if "gait" in file else None
    if robot is not None and not (isinstance(robot, str) and 0 < len(robot) <= 200):
        raise file.error(f"robot must be a robot's name (a short text), got {robot!r}")
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
