"""A 3-D cycle's files: ``summary.json`` and ``plan.csv``, one row per node, for a controller.

``plan.csv`` is wide, one row per node of the plan, so that a controller or anyone's Pinocchio
can re-check it. Columns: ``t_s``; the trunk's (root link's) ``base_pos_{x,y,z}_m``,
``base_quat_{x,y,z,w}``, ``base_lin_vel_{x,y,z}_m_s`` and ``base_ang_vel_{x,y,z}_rad_s`` (world
frame), ``base_lin_acc_{x,y,z}_m_s2`` and ``base_ang_acc_{x,y,z}_rad_s2`` (the time derivatives
of the world-frame velocities); per URDF joint ``<joint>_{q_rad,v_rad_s,a_rad_s2,tau_nm}``; per
foot frame ``<foot>_force_{x,y,z}_n`` (world axes, on the robot; zero in swing).
"""

from __future__ import annotations

import csv
import io
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.energy.whole_body import rpy_rotation
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.errors import ConfigError
from scalf_opt.files import write_atomic
from scalf_opt.types import Accounting

AXES = ("x", "y", "z")

REQUIRED_COLUMNS = (
    "t_s",
    "base_pos_z_m",
    "base_quat_x",
    "base_quat_y",
    "base_quat_z",
    "base_quat_w",
)
"""Columns a saved cycle must have to be read back (the figures draw from them)."""


def plan_columns(plan: WholeBodyPlan, accounting: Accounting) -> dict[str, np.ndarray]:
    """The CSV's columns (module docstring), each (N,) at the plan's nodes."""
    import casadi as ca

    physics = plan.physics
    q, v, a = plan.pinocchio_states
    tau = plan.node_outputs(accounting)["tau"]
    cols: dict[str, np.ndarray] = {"t_s": plan.schedule.times_s}
    n = plan.schedule.intervals
    ang_vel = np.zeros((3, n))
    ang_acc = np.zeros((3, n))
    rotation = ca.Function("R", [s := ca.SX.sym("rpy", 3)], [rpy_rotation(s)])
    for k in range(n):
        rot = np.array(rotation(plan.x[3:6, k]))
        ang_vel[:, k] = rot @ v[3:6, k]
        ang_acc[:, k] = rot @ a[3:6, k]  # d/dt (R w_b) = R dw_b/dt: R' w_b = R (w_b x w_b) = 0
    for i, axis in enumerate(AXES):
        cols[f"base_pos_{axis}_m"] = plan.x[i]
    for i, axis in enumerate((*AXES, "w")):
        cols[f"base_quat_{axis}"] = q[3 + i]
    for name, values in (
        ("base_lin_vel_{}_m_s", plan.xd[:3]),
        ("base_ang_vel_{}_rad_s", ang_vel),
        ("base_lin_acc_{}_m_s2", plan.xdd[:3]),
        ("base_ang_acc_{}_rad_s2", ang_acc),
    ):
        for i, axis in enumerate(AXES):
            cols[name.format(axis)] = values[i]
    for j, joint in enumerate(physics.joint_names):
        cols[f"{joint}_q_rad"] = plan.x[6 + j]
        cols[f"{joint}_v_rad_s"] = plan.xd[6 + j]
        cols[f"{joint}_a_rad_s2"] = plan.xdd[6 + j]
        cols[f"{joint}_tau_nm"] = tau[j]
    for i, foot in enumerate(physics.feet):
        for c, axis in enumerate(AXES):
            cols[f"{foot}_force_{axis}_n"] = plan.forces_n[3 * i + c]
    return cols


def plan_csv(plan: WholeBodyPlan, accounting: Accounting) -> str:
    """``plan.csv``'s text (full precision, ``repr`` of each float)."""
    cols = plan_columns(plan, accounting)
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(cols)
    for row in zip(*cols.values(), strict=True):
        writer.writerow([repr(float(value)) for value in row])
    return buffer.getvalue()


def write_cycle(
    out: Path, summary: dict[str, Any], plan: WholeBodyPlan, accounting: Accounting
) -> list[Path]:
    """Write ``summary.json`` and ``plan.csv`` in ``out`` (each atomically); their paths."""
    out.mkdir(parents=True, exist_ok=True)
    return [
        write_atomic(out / "plan.csv", plan_csv(plan, accounting)),
        write_atomic(out / "summary.json", json.dumps(summary, indent=2) + "\n"),
    ]


@dataclass(frozen=True)
class SavedCycle:
    """A 3-D cycle read back from ``optimize --model 3d --out DIR``.

    Attributes:
        directory: Where it was read from.
        summary: ``summary.json`` as written.
        columns: ``plan.csv``'s columns by name, each (N,) at the plan's nodes (SI units).
    """

    directory: Path
    summary: dict[str, Any]
    columns: dict[str, np.ndarray]

    @property
    def feet(self) -> tuple[str, ...]:
        """The foot frames with force columns, in the file's (the legs') order."""
        suffix = "_force_z_n"
        return tuple(name[: -len(suffix)] for name in self.columns if name.endswith(suffix))


def is_cycle_dir(directory: Path) -> bool:
    """Whether ``directory`` holds a 3-D cycle (a ``plan.csv`` beside its ``summary.json``)."""
    return (directory / "plan.csv").is_file() and (directory / "summary.json").is_file()


def read_cycle(directory: Path) -> SavedCycle:
    """Read a 3-D cycle's ``summary.json`` and ``plan.csv``.

    Raises:
        ConfigError: A file is missing or unreadable, is not a 3-D cycle's, or lacks a column
            (the message names the file and the column).
    """
    summary_path, plan_path = directory / "summary.json", directory / "plan.csv"
    try:
        summary = json.loads(summary_path.read_text())
    except (OSError, ValueError) as exc:
        raise ConfigError(f"{summary_path}: cannot be read ({exc})", field="from") from exc
    if not isinstance(summary, dict) or summary.get("model") != "3d":
        raise ConfigError(
            f"{summary_path}: not a 3-D cycle (write one with optimize --model 3d --out DIR)",
            field="from",
        )
    try:
        with plan_path.open(newline="") as handle:
            rows = list(csv.reader(handle))
    except OSError as exc:
        raise ConfigError(f"{plan_path}: cannot be read ({exc})", field="from") from exc
    if len(rows) < 2:
        raise ConfigError(f"{plan_path}: no rows", field="from")
    header, body = rows[0], rows[1:]
    try:
        values = np.array(body, dtype=float)
    except ValueError as exc:
        raise ConfigError(f"{plan_path}: {exc}", field="from") from exc
    if values.shape[1] != len(header):
        raise ConfigError(f"{plan_path}: rows and header differ in length", field="from")
    columns = {name: values[:, c] for c, name in enumerate(header)}
    for name in REQUIRED_COLUMNS:
        if name not in columns:
            raise ConfigError(f"{plan_path}: no column {name!r}", field="from")
    return SavedCycle(directory, summary, columns)
