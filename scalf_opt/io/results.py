"""Result export: ``samples.csv`` and ``summary.json`` of a robot cycle, and CSV tables.

Files are written with :func:`scalf_opt.files.write_atomic`: a reader never sees a half-written
file, and an interrupted run leaves the previous one intact.
"""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.peaks import cycle_peaks, cycle_violations, peaks_summary
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.files import number_text, write_atomic
from scalf_opt.locomotion.swing.registry import make_family
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
                row = [leg.leg, phase.phase, number_text(phase.t_s[j])]
                row += [number_text(cells[c][j]) if c in cells else "" for c in columns[3:]]
                writer.writerow(row)
    return buffer.getvalue()


def _cell(value: Any) -> Any:
    """A CSV cell: a float as :func:`~scalf_opt.files.number_text`, anything else as it is."""
    return number_text(value) if isinstance(value, float) else value


def cycle_summary(cycle: RobotCycle) -> dict[str, Any]:
    """Plain-data summary of a robot cycle (energies in J, power in W)."""
    legs: dict[str, Any] = {}
    for name, leg in cycle.legs.items():
        legs[name] = {
            "swing_family": leg.swing_family,
            "swing_parameters": [float(x) for x in leg.swing_theta],
            "swing_parameter_names": make_family(leg.swing_family).parameter_names,
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
        "loads": cycle.loads,
        "mean_stance_force_n": cycle.mean_stance_force_n,
        "peak_unbalanced_moment_nm": cycle.peak_unbalanced_moment_nm,
        "legs": legs,
        "total_energy_per_cycle_j": cycle.energy_j,
        "average_total_power_w": cycle.average_power_w,
        "cost_of_transport": cycle.cost_of_transport,
        "total_mass_kg": cycle.total_mass_kg,
        "symmetry_error": cycle.symmetry_error,
    }


def checked_summary(cycle: RobotCycle, pipeline: EnergyPipeline) -> dict[str, Any]:
    """:func:`cycle_summary` with the peaks per joint and every limit a sample exceeds."""
    physics = {leg: pipeline.physics(leg) for leg in cycle.legs}
    return {
        **cycle_summary(cycle),
        "peaks": peaks_summary(cycle_peaks(cycle, physics)),
        "limit_violations": [v.message() for v in cycle_violations(cycle, physics)],
    }


TIMINGS_FILE = "timings.json"
"""Where the run times of an output folder's result file go, so that the results repeat byte
for byte (a run's times never do)."""

_TIMING_KEYS = frozenset({"wall_time_s", "solver_time_s", "build_time_s"})
_TIMING_PREFIXES = ("t_proc_", "t_wall_")  # Ipopt's per-callback times in solver_stats


def is_timing_key(key: object) -> bool:
    """Whether a record's key holds a run time rather than a result."""
    return isinstance(key, str) and (key in _TIMING_KEYS or key.startswith(_TIMING_PREFIXES))


def split_timings(data: Any) -> tuple[Any, dict[str, Any]]:
    """``data`` without its run times, and the run times at the same paths.

    Dictionaries keep their other keys in order; a list's timings are keyed by the item's index.
    Sub-records left with no timing are left out of the timings.
    """
    if isinstance(data, dict):
        results: dict[Any, Any] = {}
        timings: dict[str, Any] = {}
        for key, value in data.items():
            if is_timing_key(key):
                timings[key] = value
                continue
            results[key], inner = split_timings(value)
            if inner:
                timings[str(key)] = inner
        return results, timings
    if isinstance(data, list | tuple):
        pairs = [split_timings(value) for value in data]
        return [r for r, _ in pairs], {str(i): t for i, (_, t) in enumerate(pairs) if t}
    return data, {}


def write_results_json(path: Path, data: Any) -> list[Path]:
    """Write ``data`` without its run times to ``path``, and the times to ``timings.json`` beside.

    Both atomically; ``timings.json`` only when there are times. Returns the paths written.
    """
    results, timings = split_timings(data)
    written = [write_atomic(path, to_json(results))]
    if timings:
        written.append(write_atomic(path.parent / TIMINGS_FILE, to_json({path.name: timings})))
    return written


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
        for row in rows:
            writer.writerow({k: _cell(v) for k, v in row.items()})
    return buffer.getvalue()
