"""Result export: ``samples.csv`` and ``summary.json``, written atomically.

An output file is first written next to its destination under a temporary name and then renamed
over it (``os.replace``), so a reader never sees a half-written file and an interrupted run
leaves the previous file intact.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.cycle import RobotCycle
from scalf_opt.errors import ConfigError

CSV_COLUMNS: tuple[str, ...] = (
    "leg",
    "phase",
    "t_s",
    "q_hip_rad",
    "q_knee_rad",
    "qd_hip_rad_s",
    "qd_knee_rad_s",
    "qdd_hip_rad_s2",
    "qdd_knee_rad_s2",
    "foot_x_m",
    "foot_z_m",
    "grf_x_n",
    "grf_z_n",
    "tau_hip_nm",
    "tau_knee_nm",
    "cyl_len_hip_m",
    "cyl_len_knee_m",
    "cyl_vel_hip_m_s",
    "cyl_vel_knee_m_s",
    "cyl_force_hip_n",
    "cyl_force_knee_n",
    "friction_hip_n",
    "friction_knee_n",
    "power_hip_w",
    "power_knee_w",
)
"""Columns of ``samples.csv``: SI units, joint angles in the URDF convention."""

_PAIRED = (
    "q",
    "qd",
    "qdd",
    "foot",
    "grf",
    "tau",
    "cyl_len",
    "cyl_vel",
    "cyl_force",
    "friction",
    "power",
)


def temporary_sibling(path: Path) -> tuple[int, str]:
    """Open a temporary file beside ``path`` with the permissions a new file would get.

    ``mkstemp`` creates files readable by their owner only; outputs should be as readable as any
    file the user creates, so the mode follows the umask.

    Raises:
        ConfigError: The directory cannot be created or written.
    """
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise ConfigError(f"{path.parent}: cannot write output directory ({exc.strerror})") from exc
    umask = os.umask(0)
    os.umask(umask)
    os.fchmod(fd, 0o666 & ~umask)
    return fd, tmp


def write_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (temp file in the same directory, then rename)."""
    path = Path(path)
    fd, tmp = temporary_sibling(path)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def samples_csv_text(cycle: RobotCycle) -> str:
    """``samples.csv`` content: one row per sample per leg and phase (RF, LH, LF, RH)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    order = [leg for leg in ("RF", "LH", "LF", "RH") if leg in cycle.legs]
    for leg in order:
        for phase in (cycle.legs[leg].stance, cycle.legs[leg].swing):
            cols = [phase.values[k] for k in _PAIRED]
            for j in range(phase.t_s.size):
                row: list[str] = [leg, phase.phase, _fmt(phase.t_s[j])]
                for arr in cols:
                    row += [_fmt(arr[0, j]), _fmt(arr[1, j])]
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
            "stance_energy_per_joint_j": {
                "hip": float(leg.stance.energy_j[0]),
                "knee": float(leg.stance.energy_j[1]),
            },
            "swing_energy_per_joint_j": {
                "hip": float(leg.swing.energy_j[0]),
                "knee": float(leg.swing.energy_j[1]),
            },
            "friction_heat_j": float(leg.stance.heat_j.sum() + leg.swing.heat_j.sum()),
        }
    g = cycle.gait
    return {
        "gait": {
            "period_s": g.period_s,
            "duty_cycle": g.duty_cycle,
            "step_length_m": g.step_length_m,
            "clearance_m": g.clearance_m,
            "stance_height_m": g.stance_height_m,
            "sample_rate_hz": g.sample_rate_hz,
            "cycles": g.cycles,
            "speed_m_s": g.speed_m_s,
        },
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
    """CSV text of a list of flat records (columns: the first record's keys, in order)."""
    buffer = io.StringIO()
    if rows:
        columns = list(rows[0])
        for row in rows[1:]:
            columns += [k for k in row if k not in columns]
        writer = csv.DictWriter(buffer, fieldnames=columns, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    return buffer.getvalue()
