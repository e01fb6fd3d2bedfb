"""The planned trot for a controller: every leg's joints at a chosen rate, over N cycles.

From a saved optimum (``summary.json``: the gait, and per leg the swing family and its
parameters) the energy pipeline evaluates the stance and the swing at exactly the requested
rate (not resampled from ``samples.csv``): per leg and instant ``t_k = k / rate``

* ``contact``: 1 while the foot is planned on the ground (at touch-down the stance's sample, at
  lift-off the swing's: one value per instant);
* per joint (hip pitch, knee; URDF names in the JSON and the bag): angle [rad], velocity
  [rad/s], acceleration [rad/s^2] and the feed-forward torque ``tau = M qdd + C qd + G - J^T F``
  with the planned stance force [N m];
* the foot ``(x, z)`` in the hip frame (origin at the pitching hip, trunk axes) [m];
* for a joint driven by a hydraulic cylinder: its length [m], speed [m/s] and force [N].

The cycle is periodic, so ``cycles`` copies follow each other seamlessly: the sample after the
last is the first. ``t = 0`` is RF's (and LH's) touch-down. A sample falls on every touch-down
and lift-off, so that the stream is uniform and every sample an exact evaluation: a rate that
does not (``rate * T_stance``, ``rate * T_swing`` and ``rate`` times each leg's touch-down time
not whole numbers) is replaced by the nearest that does (:func:`fitted_rate`; the paper's 0.5 s
trot: any multiple of 4 Hz), and the export says so.

Formats, by the output's suffix: ``.csv`` (one row per instant and leg), ``.json`` (per leg,
arrays), ``.mcap`` (a ROS 2 bag: ``sensor_msgs/JointState`` on ``/plan/joint_states`` and, for
the cylinders, ``/plan/cylinder_states``; one ``trajectory_msgs/JointTrajectory`` on
``/plan/joint_trajectory``).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.errors import ConfigError
from scalf_opt.files import number_text, write_atomic
from scalf_opt.io.ros_bag import (
    JointStateSeries,
    TrajectoryMessage,
    cylinder_joint_name,
    write_bag,
)
from scalf_opt.io.saved import SavedSwings
from scalf_opt.locomotion.gait import (
    EVENT_SIDE_S,
    MAX_SAMPLES_PER_PHASE,
    MIN_SAMPLES_PER_PHASE,
    PHASE_EDGE_TOLERANCE_S,
    Gait,
)
from scalf_opt.locomotion.trot import TROT_PHASE_OFFSET
from scalf_opt.model.robot import Robot
from scalf_opt.types import JOINT_ROLES, LEG_NAMES

TOPICS = {
    "joints": "/plan/joint_states",
    "cylinders": "/plan/cylinder_states",
    "trajectory": "/plan/joint_trajectory",
}
"""Topics of the exported bag."""

MAX_CYCLES = 1000
"""Most cycles one export holds."""

MAX_INSTANTS = 150_000
"""Most instants one export holds (cycles times samples per cycle): 150 s at 1 kHz. A CSV of
SCalf's at this size is 190 MB and its bag 180 MB, inside what ``analyze-log`` reads (200 MiB and
512 MiB), and the export's own memory stays under a gigabyte."""

JOINT_FIELDS = (
    ("q", "angle_rad"),
    ("qd", "velocity_rad_s"),
    ("qdd", "acceleration_rad_s2"),
    ("tau", "torque_nm"),
)
"""Per joint: the pipeline's output and its column stem (``hip_angle_rad``)."""

CYLINDER_FIELDS = (("cyl_len", "length_m"), ("cyl_vel", "speed_m_s"), ("cyl_force", "force_n"))
"""Per cylinder: the drive's output and its column stem (``hip_length_m``: the cylinder-log
column of :mod:`scalf_opt.logs.log_file`)."""

_ALIGN = 1e-6
"""How close to a whole number of samples a phase must be (relative)."""


def _evaluate_cycle(robot: Robot, saved: SavedSwings, gait: Gait) -> RobotCycle:
    """The one call into the energy layer: every leg's stance and swing on ``gait``'s grid."""
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.energy.swings import planned_cycle

    pipeline = EnergyPipeline(robot, gait, saved.accounting, loads=saved.loads)
    return planned_cycle(pipeline, saved.require_all_legs())


def _whole(value: float) -> int | None:
    n = round(value)
    return n if abs(value - n) <= _ALIGN * max(1.0, abs(value)) else None


MAX_PATTERN = 10_000
"""Most samples per cycle the pattern of touch-downs and lift-offs may need."""


def fitted_rate(gait: Gait, rate_hz: float) -> tuple[float, int]:
    """The rate nearest ``rate_hz`` that samples every touch-down and lift-off [Hz], and N.

    A cycle of ``N`` samples puts one on every phase edge (each leg's touch-down at its trot
    offset, its lift-off ``duty`` later) when ``N`` times each edge's fraction of the period is
    a whole number: ``N`` is a multiple of the smallest such ``M`` (2 for a 50 % trot), the one
    nearest ``rate * T``. The rate is then ``N / T`` [Hz]: ``rate_hz`` itself when it fits (the
    paper's 0.5 s trot: any multiple of 4 Hz), else the nearest that does.

    Raises:
        ConfigError: The rate is not a finite number > 0, too coarse (fewer than
            :data:`~scalf_opt.locomotion.gait.MIN_SAMPLES_PER_PHASE` intervals in a phase) or too
            fine, or the duty cycle admits no such ``N`` below :data:`MAX_PATTERN`.
    """
    if isinstance(rate_hz, bool) or not isinstance(rate_hz, int | float):
        raise ConfigError(f"the rate must be a number [Hz], got {rate_hz!r}", field="rate")
    if not (math.isfinite(rate_hz) and rate_hz > 0):
        raise ConfigError(f"the rate must be a finite number > 0 Hz, got {rate_hz!r}", field="rate")
    fractions = [gait.duty_cycle] + [TROT_PHASE_OFFSET[leg] for leg in LEG_NAMES]
    pattern = next(
        (m for m in range(1, MAX_PATTERN + 1) if all(_whole(f * m) is not None for f in fractions)),
        None,
    )
    if pattern is None:
        raise ConfigError(
            f"gait field duty_cycle = {gait.duty_cycle!r}: no uniform rate puts a sample on every "
            f"touch-down and lift-off (give a duty cycle with fewer digits)",
            field="duty_cycle",
        )
    n = pattern * max(1, round(rate_hz * gait.period_s / pattern))
    shortest = min(gait.duty_cycle, 1.0 - gait.duty_cycle) * n
    if shortest < MIN_SAMPLES_PER_PHASE:
        least = MIN_SAMPLES_PER_PHASE / min(gait.stance_duration_s, gait.swing_duration_s)
        raise ConfigError(
            f"a rate of {rate_hz:g} Hz is too coarse for the gait's phases: give at least "
            f"{least:g} Hz",
            field="rate",
        )
    if 2 * max(gait.duty_cycle, 1.0 - gait.duty_cycle) * n > MAX_SAMPLES_PER_PHASE:
        finest = MAX_SAMPLES_PER_PHASE / 2 / gait.stance_duration_s
        raise ConfigError(
            f"a rate of {rate_hz:g} Hz is finer than the {finest:g} Hz the gait's phases allow",
            field="rate",
        )
    if math.isclose(n, rate_hz * gait.period_s, rel_tol=1e-12):
        return float(rate_hz), n  # it fits: not n / T, which may differ in the last bit
    return n / gait.period_s, n


@dataclass(frozen=True)
class PlanExport:
    """The planned trot sampled for a controller (module docstring).

    Attributes:
        robot: The robot.
        saved: The optimum it comes from.
        rate_hz: Sample rate [Hz].
        cycles: Gait cycles held.
        t_s: Sample times, shape (n,) [s] (``n = cycles * period * rate``).
        joints: Per leg, the (hip pitch, knee) URDF joint names.
        values: Per leg, arrays by field: ``contact`` (n,) bool, ``q``, ``qd``, ``qdd``, ``tau``,
            ``foot`` (2, n), and for cylinder legs ``cyl_len``, ``cyl_vel``, ``cyl_force`` (2, n).
        cycle: The planned cycle at this rate (the plan's energies).
        requested_rate_hz: The rate asked for, when :attr:`rate_hz` is the nearest that fits.
    """

    robot: Robot
    saved: SavedSwings
    rate_hz: float
    cycles: int
    t_s: np.ndarray
    joints: dict[str, tuple[str, str]]
    values: dict[str, dict[str, np.ndarray]]
    cycle: RobotCycle
    requested_rate_hz: float | None = None

    @property
    def has_cylinders(self) -> bool:
        """Whether every leg's joints are cylinder-driven (the cylinder fields are there)."""
        return all("cyl_len" in v for v in self.values.values())

    def csv_text(self) -> str:
        """One row per instant and leg (legs in :data:`LEG_NAMES` order), SI units."""
        columns = ["t_s", "leg", "contact"]
        for role in JOINT_ROLES:
            columns += [f"{role}_{stem}" for _, stem in JOINT_FIELDS]
        columns += ["foot_x_m", "foot_z_m"]
        if self.has_cylinders:
            for role in JOINT_ROLES:
                columns += [f"{role}_{stem}" for _, stem in CYLINDER_FIELDS]
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(columns)
        for k, t in enumerate(self.t_s):
            for leg in LEG_NAMES:
                v = self.values[leg]
                row = [number_text(t), leg, str(int(v["contact"][k]))]
                for j in range(2):
                    row += [number_text(v[name][j, k]) for name, _ in JOINT_FIELDS]
                row += [number_text(v["foot"][0, k]), number_text(v["foot"][1, k])]
                if self.has_cylinders:
                    for j in range(2):
                        row += [number_text(v[name][j, k]) for name, _ in CYLINDER_FIELDS]
                writer.writerow(row)
        return buffer.getvalue()

    def to_dict(self) -> dict[str, Any]:
        """Plain data: the JSON file."""
        legs: dict[str, Any] = {}
        for leg in LEG_NAMES:
            v = self.values[leg]
            record: dict[str, Any] = {
                "joints": list(self.joints[leg]),
                "contact": [int(c) for c in v["contact"]],
            }
            for name, stem in JOINT_FIELDS:
                record[stem] = v[name].tolist()
            record["foot_m"] = {"x": v["foot"][0].tolist(), "z": v["foot"][1].tolist()}
            if "cyl_len" in v:
                record["cylinders"] = {stem: v[name].tolist() for name, stem in CYLINDER_FIELDS}
            legs[leg] = record
        gait = self.saved.gait
        return {
            "source": str(self.saved.source),
            "robot": self.robot.name,
            "rate_hz": self.rate_hz,
            "requested_rate_hz": self.requested_rate_hz,
            "cycles": self.cycles,
            "period_s": gait.period_s,
            "duty_cycle": gait.duty_cycle,
            "swing_families": dict(self.saved.families),
            "planned_energy_per_cycle_j": self.cycle.energy_j,
            "planned_mechanical_energy_per_cycle_j": planned_mechanical_energy_j(self.cycle),
            "frames": {
                "foot_m": "foot (x, z) in the hip frame: origin at the pitching hip, trunk axes",
                "t_s": "0 at RF and LH touch-down",
            },
            "t_s": self.t_s.tolist(),
            "legs": legs,
        }

    def bag_series(self) -> tuple[list[JointStateSeries], list[TrajectoryMessage]]:
        """The bag's joint-state series and its one joint trajectory."""
        names = tuple(name for leg in LEG_NAMES for name in self.joints[leg])

        def stack(field: str) -> np.ndarray:
            return np.vstack([self.values[leg][field] for leg in LEG_NAMES])

        series = [
            JointStateSeries(
                TOPICS["joints"], names, self.t_s, stack("q"), stack("qd"), stack("tau")
            )
        ]
        if self.has_cylinders:
            series.append(
                JointStateSeries(
                    TOPICS["cylinders"],
                    tuple(cylinder_joint_name(n) for n in names),
                    self.t_s,
                    stack("cyl_len"),
                    stack("cyl_vel"),
                    stack("cyl_force"),
                )
            )
        trajectory = TrajectoryMessage(
            TOPICS["trajectory"],
            0.0,
            names,
            self.t_s,
            stack("q"),
            stack("qd"),
            stack("qdd"),
            stack("tau"),
        )
        return series, [trajectory]

    def bag_topic_lines(self) -> list[str]:
        """What each topic of the exported bag holds, a line each (for the command's output)."""
        lines = [
            f"{TOPICS['joints']}: sensor_msgs/JointState, a message per instant: angle, "
            "velocity, feed-forward torque"
        ]
        if self.has_cylinders:
            lines.append(
                f"{TOPICS['cylinders']}: sensor_msgs/JointState of the cylinders "
                "(<joint>_cylinder), a message per instant: length, speed, force"
            )
        lines.append(
            f"{TOPICS['trajectory']}: trajectory_msgs/JointTrajectory, one message: every "
            "instant's angle, velocity, acceleration and torque"
        )
        return lines

    def write(self, path: str | Path) -> Path:
        """Write the export, its format by the suffix (atomically).

        Raises:
            ConfigError: An unknown suffix.
        """
        path = Path(path)
        writer = EXPORT_WRITERS.get(path.suffix)
        if writer is None:
            raise ConfigError(
                f"{path}: unknown export format {path.suffix!r} (give {', '.join(EXPORT_FORMATS)})"
            )
        return writer(self, path)


def _csv(export: PlanExport, path: Path) -> Path:
    return write_atomic(path, export.csv_text())


def _json(export: PlanExport, path: Path) -> Path:
    from scalf_opt.io.results import to_json

    return write_atomic(path, to_json(export.to_dict()))


def _bag(export: PlanExport, path: Path) -> Path:
    series, trajectories = export.bag_series()
    return write_bag(path, series, trajectories)


EXPORT_WRITERS: dict[str, Callable[[PlanExport, Path], Path]] = {
    ".csv": _csv,
    ".json": _json,
    ".mcap": _bag,
}
"""The export formats, by suffix: a new format is one writer and one entry here."""

EXPORT_FORMATS = tuple(EXPORT_WRITERS)
"""Output suffixes :meth:`PlanExport.write` knows."""


def planned_mechanical_energy_j(cycle: RobotCycle) -> dict[str, float]:
    """Per leg, the plan's mechanical energy ``sum |tau qd|`` over one cycle [J]."""
    from scalf_opt.energy.physics import trapezoid_weights

    return {
        leg: float(
            sum(
                np.abs(phase.values["p_mech"]).sum(axis=0) @ trapezoid_weights(phase.t_phase_s)
                for phase in (leg_cycle.stance, leg_cycle.swing)
            )
        )
        for leg, leg_cycle in cycle.legs.items()
    }


def plan_rate_hz(gait: Gait, rate_hz: float = 1000.0) -> float:
    """The rate nearest ``rate_hz`` that samples every phase edge (:func:`fitted_rate`) [Hz]."""
    return fitted_rate(gait, rate_hz)[0]


def stream_columns(
    t_phase_s: np.ndarray, intervals: int, before: Sequence[float] = ()
) -> np.ndarray:
    """The samples of a phase grid that fall on the stream's uniform grid of ``intervals``.

    The phase grids are the stream's own, except that a stance with a duty cycle above 0.5 has
    two samples at each jump of its load (:meth:`~scalf_opt.locomotion.gait.Gait.phase_times_s`)
    where the stream has one. The stream takes the side with two feet on the ground, as a foot
    exactly at touch-down or lift-off carries nothing: the one after the other pair's lift-off,
    and the one before each instant of ``before`` (its touch-down).
    """
    uniform = np.linspace(0.0, float(t_phase_s[-1]), intervals + 1)
    columns = np.searchsorted(t_phase_s, uniform - PHASE_EDGE_TOLERANCE_S)
    for instant in before:
        columns[np.abs(uniform - instant) <= 2.0 * EVENT_SIDE_S] -= 1
    columns = np.minimum(columns, t_phase_s.size - 1)
    if not np.allclose(t_phase_s[columns], uniform, rtol=0.0, atol=2.0 * EVENT_SIDE_S):
        raise AssertionError("the phase grid is not the export's")  # pragma: no cover
    return columns


def export_plan(robot: Robot, saved: SavedSwings, rate_hz: float, cycles: int = 1) -> PlanExport:
    """Sample the saved optimum at ``rate_hz`` over ``cycles`` cycles (module docstring).

    Raises:
        ConfigError: A rate that misses a phase edge, cycles outside 1..1000, swings of another
            robot, a summary without every leg.
        GaitError, InfeasibleError: The plan leaves the robot's reach or joint limits.
    """
    if isinstance(cycles, bool) or not isinstance(cycles, int) or not 1 <= cycles <= MAX_CYCLES:
        raise ConfigError(
            f"cycles must be an integer in 1..{MAX_CYCLES}, got {cycles!r}", field="cycles"
        )
    saved.check_robot(robot)
    saved.require_all_legs()
    gait = saved.gait
    requested_hz = float(rate_hz)
    rate_hz, n_cycle = fitted_rate(gait, requested_hz)
    if cycles * n_cycle > MAX_INSTANTS:
        raise ConfigError(
            f"{cycles} cycles at {rate_hz:.6g} Hz are {cycles * n_cycle:,} instants, more than "
            f"the {MAX_INSTANTS:,} an export holds (what analyze-log reads back): fewer cycles "
            f"(at most {max(MAX_INSTANTS // n_cycle, 1)} at this rate) or a lower rate; the plan "
            "is periodic, one cycle repeats seamlessly",
            field="cycles",
        )
    per_phase = [round(n_cycle * gait.duty_cycle), n_cycle - round(n_cycle * gait.duty_cycle)]
    # the pipeline's phase grids have an even number of intervals: evaluate at twice the rate
    # when a phase has an odd number of samples, and keep every other one
    factor = 1 if all(n % 2 == 0 for n in per_phase) else 2
    cycle = _evaluate_cycle(robot, saved, replace(gait, sample_rate_hz=factor * rate_hz))
    values: dict[str, dict[str, np.ndarray]] = {}
    joints: dict[str, tuple[str, str]] = {}
    touch_down = cycle.gait.stance_load_jumps_s()[1:]  # the other pair's, inside a stance
    for leg, leg_cycle in cycle.legs.items():
        one: dict[str, np.ndarray] = {}
        stance, swing = leg_cycle.stance, leg_cycle.swing
        on_grid = (
            stream_columns(stance.t_phase_s, factor * per_phase[0], touch_down),
            stream_columns(swing.t_phase_s, factor * per_phase[1]),
        )
        fields = [name for name, _ in JOINT_FIELDS] + ["foot"]
        fields += [name for name, _ in CYLINDER_FIELDS if f"{name}_hip" in stance.values]
        for name in fields:
            if name.startswith("cyl_"):
                rows = [
                    np.vstack([p.values[f"{name}_{role}"] for role in JOINT_ROLES])
                    for p in (stance, swing)
                ]
            else:
                rows = [stance.values[name], swing.values[name]]
            one[name] = np.hstack(
                [r[:, c][:, ::factor][:, :-1] for r, c in zip(rows, on_grid, strict=True)]
            )
        one["contact"] = np.arange(n_cycle) < per_phase[0]
        shift = round(TROT_PHASE_OFFSET[leg] * n_cycle)
        values[leg] = {
            name: np.tile(np.roll(array, shift, axis=-1), (1,) * (array.ndim - 1) + (cycles,))
            for name, array in one.items()
        }
        joints[leg] = tuple(robot.leg(leg).joint_names)  # type: ignore[assignment]
    t_s = np.arange(cycles * n_cycle) * (gait.period_s / n_cycle)
    return PlanExport(robot, saved, rate_hz, cycles, t_s, joints, values, cycle, requested_hz)
