"""What a result file says about where it came from: tool, robot, URDF and its hash, command."""

from __future__ import annotations

import hashlib
import shlex
from collections.abc import Sequence
from typing import Any

from scalf_opt.errors import ModelError
from scalf_opt.files import read_untrusted
from scalf_opt.model.robot import Robot
from scalf_opt.model.urdf_file import MAX_URDF_BYTES
from scalf_opt.version import __version__


def sha256_of(path: Any) -> str:
    """SHA-256 of a URDF's bytes (hex), read as untrusted input (a bounded regular file).

    Raises:
        ModelError: The file is not a regular file or is too large.
    """
    return hashlib.sha256(read_untrusted(path, "URDF", MAX_URDF_BYTES, ModelError)).hexdigest()


def run_provenance(command: Sequence[str] | None = None, **about: str) -> dict[str, Any]:
    """The ``provenance`` record of a result that is not one robot's (a study).

    Args:
        command: The command line that produced it (``None`` from the Python API).
        about: What it is about, e.g. ``study="speed.toml"``.
    """
    return {
        "tool": "scalf-opt",
        "version": __version__,
        **about,
        "command": shlex.join(command) if command is not None else None,
    }


def provenance(robot: Robot, command: Sequence[str] | None = None) -> dict[str, Any]:
    """The ``provenance`` record of a result file.

    The gait itself is in the result; ``default_gait`` says where the gait the command started
    from came from (the command line says which gait file or options changed it), and
    ``variant_of`` names a variant's parent.

    Args:
        robot: The robot the results are for.
        command: The command line that produced them (``None`` from the Python API).
    """
    from scalf_opt.locomotion.scaling import default_gait_origin

    record: dict[str, Any] = {
        "tool": "scalf-opt",
        "version": __version__,
        "robot": robot.name,
        "urdf": str(robot.urdf_path),
        "urdf_sha256": sha256_of(robot.urdf_path),
        "command": shlex.join(command) if command is not None else None,
        "default_gait": default_gait_origin(robot),
    }
    if robot.parent is not None:
        record["variant_of"] = {"robot": robot.parent.name, "urdf": str(robot.parent.urdf_path)}
    return record
