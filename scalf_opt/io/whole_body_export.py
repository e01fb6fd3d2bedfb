"""A 3-D cycle's files: ``summary.json`` and ``plan.csv``, one row per node, for a controller.

``plan.csv`` is wide, one row per node of the plan, so that a controller or anyone's Pinocchio
can re-check it. Columns: ``t_s``; the trunk's (root link's) ``base_pos_{x,y,z}_m``,
``base_quat_{x,y,z,w}``, ``base_lin_vel_{x,y,z}_m_s`` and ``base_ang_vel_{x,y,z}_rad_s`` (world
frame), ``base_lin_acc_{x,y,z}_m_s2`` and ``base_ang_acc_{x,y,z}_rad_s2`` (the time derivatives
of the world-frame velocities); per URDF joint ``<joint>_{q_rad,v_rad_s,a_rad_s2,tau_nm}``; per
foot frame ``<foot>_force_{x,y,z}_n`` (world axes, on the robot; zero in swing).

:func:`read_plan` rebuilds the :class:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan` the files
were written from (for a referee that follows it, e.g. a simulator).
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.energy.whole_body import (
    WholeBodyPhysics,
    body_angular_velocity,
    quaternion_rpy,
    rpy_rotation,
)
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.errors import ConfigError
from scalf_opt.files import read_untrusted_text, write_atomic
from scalf_opt.locomotion.contact_schedule import TrotSchedule
from scalf_opt.locomotion.periodic_spline import READS_PER_INTERVAL
from scalf_opt.types import LEG_NAMES, Accounting

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
    physics = plan.physics
    q, v, a = plan.pinocchio_states
    tau = plan.node_outputs(accounting)["tau"]
    cols: dict[str, np.ndarray] = {"t_s": plan.schedule.times_s}
    n = plan.schedule.intervals
    ang_vel = np.zeros((3, n))
    ang_acc = np.zeros((3, n))
    rotation = _rotation_function()
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
    def headline(self) -> str:
        """Where it was read from and what its ``summary.json`` reports, in one line.

        The robot, period, speed, energy per cycle and cost of transport (as ``optimize --model
        3d`` prints them; ``nan`` where a field is missing).
        """
        summary = self.summary

        def number(key: str) -> float:
            return summary_number(summary.get(key))

        return (
            f"{self.directory}: {summary.get('robot')}, T = {number('period_s'):.4g} s, "
            f"{number('speed_m_s'):.3g} m/s, {number('energy_per_cycle_j'):.3f} J per cycle, "
            f"cost of transport {number('cost_of_transport'):.4f}"
        )

    @property
    def feet(self) -> tuple[str, ...]:
        """The foot frames with force columns, in the file's (the legs') order."""
        suffix = "_force_z_n"
        return tuple(name[: -len(suffix)] for name in self.columns if name.endswith(suffix))


def summary_number(value: object) -> float:
    """A ``summary.json`` field as a finite float, else NaN (missing, ``true``, not a number)."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        return math.nan
    return float(value)


def is_cycle_dir(directory: Path) -> bool:
    """Whether ``directory`` holds a 3-D cycle (a ``plan.csv`` beside its ``summary.json``)."""
    return (directory / "plan.csv").is_file() and (directory / "summary.json").is_file()


def is_3d_cycle(directory: Path) -> bool:
    """Whether ``directory`` holds a 3-D cycle: a ``plan.csv``, or a ``summary.json`` saying so.

    The second case is a 3-D folder that lost its plan: its readers then say what is missing.
    """
    if is_cycle_dir(directory):
        return True
    from scalf_opt.io.saved import read_json

    try:  # bounded, and a regular file only (a link to /dev/zero would never end)
        summary = read_json(directory / "summary.json", "summary")
    except ConfigError:
        return False  # the sagittal reader says what is wrong with it
    return isinstance(summary, dict) and summary.get("model") == "3d"


def _bad_cell(header: list[str], body: list[list[str]]) -> str | None:
    """Where the first cell that is not a number is (``row 3, column 't_s': 'oops'``)."""
    for r, row in enumerate(body, start=2):
        for name, cell in zip(header, row, strict=False):
            try:
                float(cell)
            except ValueError:
                return f"row {r}, column {name!r}: {cell!r} is not a number"
    return None


MAX_PLAN_BYTES = 64 * 1024 * 1024
"""The largest ``plan.csv`` read back [bytes] (a 100-node Go1 plan is about 0.2 MB)."""


def read_cycle(directory: Path) -> SavedCycle:
    """Read a 3-D cycle's ``summary.json`` and ``plan.csv``.

    Raises:
        ConfigError: A file is missing or unreadable, is not a 3-D cycle's, or lacks a column
            (the message names the file and the column).
    """
    from scalf_opt.io.saved import read_json

    summary_path, plan_path = directory / "summary.json", directory / "plan.csv"
    try:  # bounded regular files only: a link to /dev/zero is refused, not read forever
        summary = read_json(summary_path, "summary")
        plan_text = read_untrusted_text(plan_path, "plan", MAX_PLAN_BYTES)
    except ConfigError as exc:
        raise ConfigError(str(exc), field="from") from exc
    if not isinstance(summary, dict) or summary.get("model") != "3d":
        raise ConfigError(
            f"{summary_path}: not a 3-D cycle (write one with optimize --model 3d --out DIR)",
            field="from",
        )
    rows = list(csv.reader(io.StringIO(plan_text, newline="")))
    if len(rows) < 2:
        raise ConfigError(f"{plan_path}: no rows", field="from")
    header, body = rows[0], rows[1:]
    try:
        values = np.array(body, dtype=float)
    except ValueError as exc:
        raise ConfigError(f"{plan_path}: {_bad_cell(header, body) or exc}", field="from") from exc
    if values.shape[1] != len(header):
        raise ConfigError(f"{plan_path}: rows and header differ in length", field="from")
    columns = {name: values[:, c] for c, name in enumerate(header)}
    for name in REQUIRED_COLUMNS:
        if name not in columns:
            raise ConfigError(f"{plan_path}: no column {name!r}", field="from")
    return SavedCycle(directory, summary, columns)


MAX_PITCH_RAD = math.radians(80.0)
"""The largest trunk pitch :func:`read_plan` accepts [rad] (roll-pitch-yaw: singular at 90 deg)."""

TIME_TOLERANCE_S = 1e-9
"""How far ``t_s`` may lie from the node times ``k T / N`` [s]."""

QUATERNION_NORM_TOLERANCE = 1e-6
"""How far a saved trunk quaternion's norm may lie from one (the writer's is one to 1e-15)."""

SUMMARY_NUMBERS = ("period_s", "duty_cycle", "nodes", "speed_m_s")
"""The ``summary.json`` fields :func:`read_plan` rebuilds the schedule and speed from (and
``reads_per_interval`` when present)."""

MAX_READS_PER_INTERVAL = 64
"""The densest reading a saved cycle may ask for (the driver's is 8)."""

_BASE_RATES = (("lin_vel", "m_s"), ("ang_vel", "rad_s"), ("lin_acc", "m_s2"), ("ang_acc", "rad_s2"))
"""The trunk's world-frame rate columns ``base_<kind>_{x,y,z}_<unit>``."""


def read_plan(directory: Path, physics: WholeBodyPhysics) -> WholeBodyPlan:
    """The plan ``optimize --model 3d --out DIR`` wrote to ``directory``.

    :func:`saved_plan` of :func:`read_cycle` (its docstring says how, and what is refused).
    """
    return saved_plan(read_cycle(directory), physics)


def saved_plan(saved: SavedCycle, physics: WholeBodyPhysics) -> WholeBodyPlan:
    """The plan of a cycle read by :func:`read_cycle`.

    The schedule is ``TrotSchedule(period_s, duty_cycle, nodes, reads_per_interval)`` (the last
    4 when absent) and the speed ``speed_m_s`` of ``summary.json``. From ``plan.csv`` (SI
    units), in the optimizer's coordinates ``X`` (:mod:`scalf_opt.energy.whole_body`): the
    trunk's position, velocity and acceleration are the world-frame columns; its roll, pitch,
    yaw [rad] are the quaternion's (``R = R_z(yaw) R_y(pitch) R_x(roll)``, the sign of the
    quaternion immaterial; roll and yaw in ``(-pi, pi]``: the optimizer keeps all three within
    0.6 rad); their rates solve ``R^T omega_world = E(rpy) rpy_dot`` and their second derivatives
    ``R^T domega_world/dt = E rpy_ddot + dE/dt rpy_dot`` (``E`` from
    :func:`~scalf_opt.energy.whole_body.body_angular_velocity`, the one place it is written);
    the joints follow ``physics.joint_names``, the forces (world axes, on the robot, [N])
    ``physics.feet``. The files do not hold the footholds: each foot's is where the plan puts it
    at its touch-down node (world ``x, y`` [m]), as the optimizer's stance rows make it (to
    Ipopt's constraint tolerance, 1e-8 m, on an optimized plan).

    Raises:
        ConfigError: (``field="from"``, one line naming the file and the field) what
            :func:`read_cycle` raises; ``summary.json`` is another robot's or lacks one of
            :data:`SUMMARY_NUMBERS` (or it is not a number); ``plan.csv`` has not ``nodes`` rows,
            its ``t_s`` are not the nodes' times, it lacks a column of this robot's joints or
            feet (or the trunk's), a quaternion is not of unit norm or the trunk pitches more than
            :data:`MAX_PITCH_RAD`.
    """
    directory = saved.directory
    summary_path, plan_path = directory / "summary.json", directory / "plan.csv"
    summary = saved.summary
    robot = summary.get("robot")
    if robot != physics.robot.name:
        raise ConfigError(
            f"{summary_path}: the cycle of robot {robot!r}, not of {physics.robot.name!r}",
            field="from",
        )
    period, duty, nodes, speed = (
        _summary_number(summary, key, summary_path) for key in SUMMARY_NUMBERS
    )
    if not (period > 0 and nodes >= 1 and nodes == int(nodes)):
        raise ConfigError(
            f"{summary_path}: period_s {period!r} must be > 0 and nodes {nodes!r} a whole number "
            ">= 1",
            field="from",
        )
    reads = _summary_reads(summary, summary_path)
    schedule = TrotSchedule(period, duty, int(nodes), reads)
    n = schedule.intervals
    if abs(duty * n - round(duty * n)) > 1e-9:
        raise ConfigError(
            f"{summary_path}: duty_cycle {duty!r} times nodes {n} is not a whole number of "
            "intervals (a saved cycle's phase edges fall on nodes)",
            field="from",
        )
    columns = _plan_columns_of(saved, physics, plan_path, n)
    times = columns["t_s"]
    expected = schedule.times_s
    worst = int(np.argmax(np.nan_to_num(np.abs(times - expected), nan=np.inf)))
    if not abs(times[worst] - expected[worst]) <= TIME_TOLERANCE_S:  # NaN too
        raise ConfigError(
            f"{plan_path}: t_s in row {worst + 1} is {times[worst]!r} s, not node {worst}'s "
            f"{expected[worst]!r} s (period_s {period!r} over nodes {n})",
            field="from",
        )

    def stack(pattern: str, names: tuple[str, ...]) -> np.ndarray:
        return np.vstack([columns[pattern.format(name)] for name in names])

    x, xd, xdd = (np.zeros((physics.nx, n)) for _ in range(3))
    x[:3] = stack("base_pos_{}_m", AXES)
    xd[:3] = stack("base_lin_vel_{}_m_s", AXES)
    xdd[:3] = stack("base_lin_acc_{}_m_s2", AXES)
    x[3:6], xd[3:6], xdd[3:6] = _rpy_states(
        stack("base_quat_{}", (*AXES, "w")),
        stack("base_ang_vel_{}_rad_s", AXES),
        stack("base_ang_acc_{}_rad_s2", AXES),
        plan_path,
    )
    x[6:] = stack("{}_q_rad", physics.joint_names)
    xd[6:] = stack("{}_v_rad_s", physics.joint_names)
    xdd[6:] = stack("{}_a_rad_s2", physics.joint_names)
    forces = np.vstack([stack(f"{foot}_force_{{}}_n", AXES) for foot in physics.feet])
    footholds = np.zeros((2, len(LEG_NAMES)))
    feet = physics.feet_function
    for i, leg in enumerate(LEG_NAMES):
        node = schedule.touchdown_node(leg)
        footholds[:, i] = np.array(feet(x[:, node]))[:2, i]
    return WholeBodyPlan(physics, schedule, speed, x, xd, xdd, forces, footholds)


def _summary_reads(summary: dict[str, Any], path: Path) -> int:
    """``summary``'s ``reads_per_interval`` (the default when absent: cycles saved before it was).

    Raises:
        ConfigError: It is not an even whole number from 2 to :data:`MAX_READS_PER_INTERVAL`.
    """
    if "reads_per_interval" not in summary:
        return READS_PER_INTERVAL
    reads = _summary_number(summary, "reads_per_interval", path)
    if not (reads == int(reads) and int(reads) % 2 == 0 and 2 <= reads <= MAX_READS_PER_INTERVAL):
        raise ConfigError(
            f"{path}: reads_per_interval {reads!r} must be an even whole number from 2 to "
            f"{MAX_READS_PER_INTERVAL}",
            field="from",
        )
    return int(reads)


def _summary_number(summary: dict[str, Any], key: str, path: Path) -> float:
    """``summary[key]``, a finite number (JSON's ``true``/``false`` are not).

    Raises:
        ConfigError: It is missing or not a finite number (names the file and the key).
    """
    if key not in summary:
        raise ConfigError(f"{path}: no field {key!r}", field="from")
    value = summary[key]
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ConfigError(f"{path}: {key} is {value!r}, not a number", field="from")
    return float(value)


def _plan_columns_of(
    saved: SavedCycle, physics: WholeBodyPhysics, path: Path, nodes: int
) -> dict[str, np.ndarray]:
    """``plan.csv``'s columns, checked for ``nodes`` rows and every column :func:`read_plan` reads.

    Raises:
        ConfigError: Another row count, or a missing column (names the file and the column).
    """
    columns = saved.columns
    rows = columns["t_s"].size
    if rows != nodes:
        raise ConfigError(f"{path}: {rows} rows, but summary.json's nodes is {nodes}", field="from")
    needed = [
        *(f"base_pos_{a}_m" for a in AXES),
        *(f"base_quat_{a}" for a in (*AXES, "w")),
        *(f"base_{kind}_{a}_{unit}" for kind, unit in _BASE_RATES for a in AXES),
        *(f"{j}_{s}" for j in physics.joint_names for s in ("q_rad", "v_rad_s", "a_rad_s2")),
        *(f"{foot}_force_{a}_n" for foot in physics.feet for a in AXES),
    ]
    for name in needed:
        if name not in columns:
            raise ConfigError(
                f"{path}: no column {name!r} (robot {physics.robot.name!r})", field="from"
            )
    return columns


def _rpy_states(
    quat_xyzw: np.ndarray, ang_vel: np.ndarray, ang_acc: np.ndarray, path: Path
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Roll-pitch-yaw, their rates and second derivatives (3, N) of the trunk's saved motion.

    Args:
        quat_xyzw: The trunk's orientation as quaternions ``(x, y, z, w)`` (4, N).
        ang_vel: Its angular velocity, world frame (3, N) [rad/s].
        ang_acc: That velocity's time derivative, world frame (3, N) [rad/s^2].
        path: The file they come from (for the errors).

    Raises:
        ConfigError: A quaternion is not of unit norm, or the trunk pitches beyond
            :data:`MAX_PITCH_RAD`.
    """
    norm = np.linalg.norm(quat_xyzw, axis=0)
    bad = np.flatnonzero(~(np.abs(norm - 1.0) <= QUATERNION_NORM_TOLERANCE))  # NaN too
    if bad.size:
        raise ConfigError(
            f"{path}: base_quat_{{x,y,z,w}} in row {bad[0] + 1} has norm {norm[bad[0]]:.9g}, not 1",
            field="from",
        )
    rpy = quaternion_rpy(quat_xyzw)
    steep = np.flatnonzero(np.abs(rpy[1]) > MAX_PITCH_RAD)
    if steep.size:
        k = steep[0]
        raise ConfigError(
            f"{path}: base_quat_{{x,y,z,w}} in row {k + 1} pitches the trunk "
            f"{math.degrees(rpy[1, k]):.1f} deg, beyond +-{math.degrees(MAX_PITCH_RAD):g} deg "
            "(roll-pitch-yaw are singular at 90 deg)",
            field="from",
        )
    terms = _rpy_rate_terms()
    rotation = _rotation_function()
    rpy_dot, rpy_ddot = np.zeros_like(rpy), np.zeros_like(rpy)
    zero = np.zeros(3)
    for k in range(rpy.shape[1]):
        rot = np.array(rotation(rpy[:, k]))
        e_matrix = np.array(terms(rpy[:, k], zero)[0])
        rpy_dot[:, k] = np.linalg.solve(e_matrix, rot.T @ ang_vel[:, k])
        bias = np.array(terms(rpy[:, k], rpy_dot[:, k])[1]).ravel()
        rpy_ddot[:, k] = np.linalg.solve(e_matrix, rot.T @ ang_acc[:, k] - bias)
    return rpy, rpy_dot, rpy_ddot


@cache
def _rpy_rate_terms() -> Any:
    """``(rpy, rpy_dot) -> (E, dE/dt rpy_dot)`` of :func:`body_angular_velocity` (CasADi).

    ``omega_b = E(rpy) rpy_dot`` (``E`` 3x3, independent of ``rpy_dot``), so
    ``domega_b/dt = E rpy_ddot + (d omega_b / d rpy) rpy_dot``: the second output.
    """
    import casadi as ca

    rpy, rpy_dot = ca.SX.sym("rpy", 3), ca.SX.sym("rpy_dot", 3)
    omega = body_angular_velocity(rpy, rpy_dot)
    return ca.Function(
        "rpy_rate_terms",
        [rpy, rpy_dot],
        [ca.jacobian(omega, rpy_dot), ca.jtimes(omega, rpy, rpy_dot)],
        ["rpy", "rpy_dot"],
        ["E", "E_dot_rpy_dot"],
    )


@cache
def _rotation_function() -> Any:
    """``rpy -> R``: :func:`rpy_rotation` as a CasADi function (world from trunk axes)."""
    import casadi as ca

    rpy = ca.SX.sym("rpy", 3)
    return ca.Function("R", [rpy], [rpy_rotation(rpy)])
