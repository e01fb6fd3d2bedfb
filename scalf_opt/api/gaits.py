"""Gaits for the API: the robot's default trot, a gait file's fields, and fields set by hand."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.gait_file import read_gait as read_gait_file
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.model.robot import Robot

VERBOSE_IPOPT: dict[str, Any] = {"print_level": 5}
"""Ipopt's own iteration log (``-v`` on the command line)."""


def as_robot(robot: str | Robot | None, default: str = "scalf") -> Robot:
    """A loaded robot as given, or a catalog robot's name (``"go1"``) loaded; ``None``: ``default``.

    Raises:
        ModelError: An unknown name (the message lists the catalog).
        ConfigError: Neither a name nor a robot.
    """
    from scalf_opt.robots.loading import load_robot

    if robot is None or isinstance(robot, str):
        return load_robot(default if robot is None else robot)
    if not isinstance(robot, Robot):
        raise ConfigError(
            f"robot must be a catalog robot's name or a loaded robot (load_robot), got "
            f"{type(robot).__name__}",
            field="robot",
        )
    return robot


def read_gait(
    path: str | Path | None = None,
    robot: str | Robot | None = None,
    base: Gait | None = None,
    **fields: float,
) -> Gait:
    """A gait: a base gait, under a gait file's fields, under ``fields``.

    Args:
        path: A gait file (TOML, ``[gait]`` table); ``None`` for none.
        robot: Whose default gait is the base (the paper's trot scaled to its legs, at its
            stance height, :func:`~scalf_opt.locomotion.scaling.default_gait_for`; a robot or a
            catalog name); ``None``: the paper's trot.
        base: The base gait instead of the robot's default (a saved optimum's gait).
        fields: Gait fields to set, e.g. ``period_s=0.4``.

    Raises:
        ConfigError: A bad file or an unknown field.
        GaitError: A value out of range (the message names the file or field).
    """
    unknown = sorted(set(fields) - set(Gait.field_names()))
    if unknown:
        raise ConfigError(Gait.unknown_field(unknown[0]))
    gait = base or (default_gait_for(as_robot(robot)) if robot is not None else Gait())
    if path is not None:
        gait = read_gait_file(path, gait)
    return replace(gait, **fields) if fields else gait  # type: ignore[arg-type]


def command_tuple(command: Any) -> tuple[str, ...] | None:
    """A command line as a tuple (``None`` from Python)."""
    return tuple(command) if command is not None else None
