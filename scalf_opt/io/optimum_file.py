"""Reading back the swing trajectories and gait of a ``summary.json``.

``scalf-opt evaluate --out DIR`` and ``scalf-opt optimize --out DIR`` write ``DIR/summary.json``
with the gait and, per leg, ``swing_family`` and ``swing_parameters`` (family units: degrees or
centimetres); this module turns them back into what the pipeline evaluates.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES

MASS_TOLERANCE = 1e-9
"""Relative difference of total masses that still counts as the same robot."""


@dataclass(frozen=True)
class PlannedSwings:
    """The gait and every leg's swing, as a result file records them.

    Attributes:
        source: The file read.
        gait: The gait the swings were computed for.
        swings: Per leg (RF, LH, LF, RH), the family name and its parameters (family units).
    """

    source: Path
    gait: Gait
    swings: dict[str, tuple[str, np.ndarray]]


def _field(path: Path, data: Any, key: str, where: str) -> Any:
    if not isinstance(data, dict) or key not in data:
        raise ConfigError(f"{path}: missing field {where}{key}")
    return data[key]


def _check_robot(path: Path, data: Any, robot: Robot) -> None:
    record = data.get("provenance") if isinstance(data, dict) else None
    name = record.get("robot") if isinstance(record, dict) else None
    if isinstance(name, str) and name != robot.name:
        raise ConfigError(
            f"{path}: field provenance.robot is {name!r}, not {robot.name!r}: give the same "
            "--robot or --urdf"
        )
    mass = data.get("total_mass_kg") if isinstance(data, dict) else None
    if isinstance(mass, int | float) and not math.isclose(
        mass, robot.total_mass_kg, rel_tol=MASS_TOLERANCE
    ):
        raise ConfigError(
            f"{path}: field total_mass_kg is {mass:g} kg, but {robot.name} weighs "
            f"{robot.total_mass_kg:g} kg: the swings belong to another robot; give the same "
            "--robot or --urdf"
        )


def read_planned_swings(directory: str | Path, robot: Robot | None = None) -> PlannedSwings:
    """Read ``directory/summary.json``.

    Args:
        directory: Where ``summary.json`` is.
        robot: The robot the swings will be used on: the file's ``provenance.robot`` and
            ``total_mass_kg``, where it has them, must be this robot's, so that swings computed
            for one robot are not run on another.

    Raises:
        ConfigError: The file is missing or not JSON, or a field is missing or invalid (the
            message names the file and the field, e.g. ``legs.RF.swing_parameters``).
        GaitError: The recorded gait is invalid.
    """
    path = Path(directory) / "summary.json"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError as exc:
        raise ConfigError(
            f"{path}: not found (write it with scalf-opt optimize --out {directory})"
        ) from exc
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read ({exc.strerror})") from exc
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{path}: not valid JSON ({exc})") from exc
    if robot is not None:
        _check_robot(path, data, robot)
    gait_data = _field(path, data, "gait", "")
    if not isinstance(gait_data, dict):
        raise ConfigError(f"{path}: field gait must be an object")
    gait = Gait(**{k: gait_data[k] for k in Gait.field_names() if k in gait_data})
    legs = _field(path, data, "legs", "")
    swings = {}
    for leg in LEG_NAMES:
        entry = _field(path, legs, leg, "legs.")
        family_name = _field(path, entry, "swing_family", f"legs.{leg}.")
        values = _field(path, entry, "swing_parameters", f"legs.{leg}.")
        where = f"{path}: legs.{leg}.swing_parameters"
        if not isinstance(family_name, str):
            raise ConfigError(f"{path}: legs.{leg}.swing_family must be a family name")
        ok = isinstance(values, list) and all(
            isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
            for v in values
        )
        if not ok:
            raise ConfigError(f"{where} must be a list of finite numbers")
        family = make_family(family_name)
        if len(values) != family.n_params:
            raise ConfigError(
                f"{where} has {len(values)} values; family {family_name} has {family.n_params}"
            )
        swings[leg] = (family_name, np.array(values, dtype=float))
    return PlannedSwings(path, gait, swings)
