"""Result export: ``samples.csv`` and ``summary.json`` of a robot cycle, and CSV tables.

Files are written with :func:`scalf_opt.files.write_atomic`: a reader never sees a half-written
file, and an interrupted run leaves the previous one intact.
"""

from __future__ import annotations

import csv
import io
import json
import math
from typing import Any

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.types import JOINT_ROLES

_PAIRED: tuple[tuple[str, str, tuple[str, str]], ...] = (
    ("q", "rad", JOINT_ROLES),
    ("qd", "rad_s", JOINT_ROLES),
    ("qdd", "rad_s2", JOINT_ROLES),
    ("foot", "m", ("x", "z")),
    ("grf", "n", ("x", "z")),
    ("tau", "nm", JOINT_ROLES),
)
"""Two-row sample values before the drive outputs: (name, unit, row names)."""

_LAST = ("power", "w", JOINT_ROLES)
"""The charged power, the last two columns."""


def _pair_columns(name: str, unit: str, rows: tuple[str, str]) -> list[str]:
    return [f"{name}_{row}_{unit}" for row in rows]


def csv_columns(cycle: RobotCycle) -> list[str]:
    """Columns of ``samples.csv`` for ``cycle``: the drive columns of every leg, in order."""
    drive_columns: dict[str, str] = {}
    for leg in cycle.legs.values():
        for phase in (leg.stance, leg.swing):
            drive_columns.update(phase.drive_columns)
    columns = ["leg", "phase", "t_s"]
    for spec in _PAIRED:
        columns += _pair_columns(*spec)
    return columns + list(drive_columns.values()) + _pair_columns(*_LAST)


def samples_csv_text(cycle: RobotCycle) -> str:
    """``samples.csv``: one row per sample per leg and phase, legs in LEG_NAMES order.

    A leg whose drives lack a column (an ideal drive has no cylinder) leaves it empty.
    """
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    columns = csv_columns(cycle)
    writer.writerow(columns)
    for leg in cycle.legs.values():
        for phase in (leg.stance, leg.swing):
            cells: dict[str, np.ndarray] = {}
            for name, unit, rows in (*_PAIRED, _LAST):
                for i, column in enumerate(_pair_columns(name, unit, rows)):
                    cells[column] = phase.values[name][i]
            for name, column in phase.drive_columns.items():
                cells[column] = phase.values[name]
            for j in range(phase.t_s.size):
                row = [leg.leg, phase.phase, _fmt(phase.t_s[j])]
                row += [_fmt(cells[c][j]) if c in cells else "" for c in columns[3:]]
                writer.writerow(row)
    return buffer.getvalue()


def _fmt(x: float) -> str:
    return "nan" if math.isnan(x) else repr(float(x))


def cycle_summary(cycle: RobotCycle) -> dict[str, Any]:
    """Plain-data summary of a robot cycle (energies in J, power in W)."""
    legs: dict[str, Any] = {}
    for name, leg in cycle.legs.items():
        legs[name] = {
            "swing_family": leg.swing_family,
            "swing_parameters": [float(x) for x in leg.swing_theta],
            "stance_energy_j": leg.stance_energy_j,
            "swing_energy_j": leg.swing_energy_j,
            "cycle_energy_j": leg.energy_j,
            "stance_energy_per_joint_j": dict(
                zip(JOINT_ROLES, map(float, leg.stance.energy_j), strict=True)
            ),
            "swing_energy_per_joint_j": dict(
                zip(JOINT_ROLES, map(float, leg.swing.energy_j), strict=True)
            ),
            "drive_loss_j": leg.loss_j,
        }
    g = cycle.gait
    return {
        "gait": {**g.to_dict(), "speed_m_s": g.speed_m_s},
        "accounting": cycle.accounting,
        "legs": legs,
        "total_energy_per_cycle_j": cycle.energy_j,
        "average_total_power_w": cycle.average_power_w,
        "cost_of_transport": cycle.cost_of_transport,
        "total_mass_kg": cycle.total_mass_kg,
        "symmetry_error": cycle.symmetry_error,
    }


def to_json(data: Any) -> str:
    """JSON text with numpy values converted and NaN written as null."""

    def convert(obj: Any) -> Any:
        if isinstance(obj, dict):
            return {str(k): convert(v) for k, v in obj.items()}
        if isinstance(obj, list | tuple):
            return [convert(v) for v in obj]
        if isinstance(obj, np.ndarray):
            return convert(obj.tolist())
        if isinstance(obj, np.generic):
            return convert(obj.item())
        if isinstance(obj, float) and not math.isfinite(obj):
            return None
        return obj

    return json.dumps(convert(data), indent=2, sort_keys=False) + "\n"


def rows_csv_text(rows: list[dict[str, Any]]) -> str:
    """CSV text of a list of flat records (columns: the first record's keys, then new ones)."""
    buffer = io.StringIO()
    if rows:
        columns = list(rows[0])
        for row in rows[1:]:
            columns += [k for k in row if k not in columns]
        writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    return buffer.getvalue()
