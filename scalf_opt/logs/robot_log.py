"""A robot's whole joint log checked against its URDF: every leg's joints, clean samples.

:func:`robot_log` takes the joint series of a bag or wide CSV
(:mod:`~scalf_opt.logs.robot_sources`) and the robot, and

* refuses a log that names a joint the robot does not have (a mapping's ``joints``), or lacks a
  leg's hip pitch or knee; counts every other joint between the trunk and a foot (the abduction)
  that it holds, and warns of those it lacks (a plan's export holds only the sagittal joints);
  joints of a message that are no leg's (an arm, a head) are set aside;
* drops repeated stale samples (a row equal to the one before in every value: a driver that
  re-publishes its last state) and counts them; refuses time that does not increase after that;
* warns of gaps in the stamps (a step over :data:`GAP_FACTOR` times the median) and of angles
  beyond a joint's URDF range (by more than :data:`RANGE_TOLERANCE_RAD`: the log of another robot,
  or another zero).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from scalf_opt.errors import LogError
from scalf_opt.logs.log_file import check_times
from scalf_opt.logs.robot_sources import JointSeries
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES

GAP_FACTOR = 5.0
"""A step between samples this many times the median is a gap in the log."""

RANGE_TOLERANCE_RAD = 0.05
"""An angle this far beyond its URDF limit is out of range (encoders and calibration may read a
little past a mechanical stop; 3 degrees more is another robot or another zero)."""


def leg_joints(robot: Robot, leg: str) -> tuple[str, ...]:
    """Every joint between the trunk and leg ``leg``'s foot, trunk first (URDF names)."""
    model = robot.model
    foot = robot.leg(leg).foot_frame
    joint = model.frames[model.getFrameId(foot)].parentJoint
    chain = []
    while joint > 0:
        chain.append(model.names[joint])
        joint = model.parents[joint]
    return tuple(reversed(chain))


@dataclass(frozen=True)
class RobotLog:
    """A whole-robot joint log, checked (module docstring).

    Attributes:
        source: The file and topic.
        legs: Per leg, its joints (URDF names, trunk first).
        t_s: Sample times from the first, shape (n,) [s].
        q_rad, tau_nm: Per joint (URDF name), its angle [rad] and torque [N m], shape (n,).
        qd_rad_s: Per joint its rate [rad/s], or ``None`` when the log has no rates.
        foot_force: Per leg with a foot sensor, its reading, shape (n,), or ``None``.
        odometry: The trunk's ``(t_s, xy_m)`` from an odometry topic (times from the first
            sample), or ``None``.
        notes: What the checks found and did (dropped samples, gaps, ranges), one line each.
        leg_model_joints: Per leg, the joints the sagittal model has (hip pitch, knee).
    """

    source: str
    legs: dict[str, tuple[str, ...]]
    t_s: np.ndarray
    q_rad: dict[str, np.ndarray]
    qd_rad_s: dict[str, np.ndarray] | None
    tau_nm: dict[str, np.ndarray]
    foot_force: dict[str, np.ndarray] | None
    odometry: tuple[np.ndarray, np.ndarray] | None
    notes: tuple[str, ...]
    leg_model_joints: dict[str, tuple[str, ...]]

    @property
    def sample_rate_hz(self) -> float:
        """The median sample rate [Hz]."""
        return float(1.0 / np.median(np.diff(self.t_s)))


def _known_joints(robot: Robot, series: JointSeries, named: bool) -> list[int]:
    """Rows of the series that are the robot's joints; unknown ones refused unless ``named``."""
    model = robot.model
    known = {model.names[j] for j in range(1, model.njoints)}
    rows = []
    for row, joint in enumerate(series.joints):
        if joint in known:
            rows.append(row)
        elif not named:
            raise LogError(
                f"{series.source}: joint {joint!r} of the mapping is not a joint of "
                f"{robot.name} (is the log of another robot? --robot; its joints: "
                f"{', '.join(sorted(known)[:6])}, ...)"[:400]
            )
    return rows


def _stale(series: JointSeries, rows: list[int]) -> np.ndarray:
    """Samples equal to the one before in every value (a re-published state)."""
    parts = [series.q_rad[rows], series.tau_nm[rows]]
    if series.qd_rad_s is not None:
        parts.append(series.qd_rad_s[rows])
    if series.foot_force is not None:
        parts.append(np.vstack(list(series.foot_force.values())))
    values = np.vstack(parts)
    same = np.all(values[:, 1:] == values[:, :-1], axis=0)
    return np.concatenate([[False], same])


def robot_log(
    series: JointSeries,
    robot: Robot,
    named: bool = False,
    place: str = "message",
    time_column: str = "t_s",
) -> RobotLog:
    """Check ``series`` against ``robot`` (module docstring).

    Args:
        series: The joint series.
        robot: The robot.
        named: The joints are names the messages carry (``JointState``): names that are no
            joint of the robot are set aside, not refused.
        place: What the series' ``rows`` count, for messages: ``message`` (a bag) or ``row``.
        time_column: A CSV's time column, for messages.

    Raises:
        LogError: A joint of the mapping the robot does not have; a hip pitch or knee missing;
            fewer than three samples; once stale samples are dropped, times that do not increase
            by 10 us or more, or that span more than 116 days
            (:func:`~scalf_opt.logs.log_file.check_times`).
    """
    source = series.source
    rows = _known_joints(robot, series, named)
    present = {series.joints[r]: r for r in rows}
    legs, notes = _leg_chains(robot, series, present)
    used = [present[j] for joints in legs.values() for j in joints]
    set_aside = len(series.joints) - len(used)
    if set_aside:
        notes.append(f"{set_aside} joint(s) of the log are no leg's and are set aside")
    stale = _stale(series, used)
    keep = ~stale
    if stale.any():
        notes.append(
            f"{int(stale.sum())} repeated stale sample(s) dropped (equal to the one before in "
            "every value)"
        )
    t = series.t_s[keep]
    if t.size < 3:
        raise LogError(f"{source}: {t.size} samples: too few to analyse")
    check_times(source, "", t - t[0], series.rows[keep], place, time_column)
    notes += _gap_notes(t)
    notes += _range_notes(robot, {j: series.q_rad[present[j], keep] for j in present})
    t0 = float(t[0])
    odometry = None
    if series.odometry is not None:
        odometry = (series.odometry[0] - t0, series.odometry[1])

    def by_joint(array: np.ndarray) -> dict[str, np.ndarray]:
        return {j: array[present[j], keep] for joints in legs.values() for j in joints}

    return RobotLog(
        source=source,
        legs=legs,
        t_s=t - t0,
        q_rad=by_joint(series.q_rad),
        qd_rad_s=None if series.qd_rad_s is None else by_joint(series.qd_rad_s),
        tau_nm=by_joint(series.tau_nm),
        foot_force=None
        if series.foot_force is None
        else {leg: f[keep] for leg, f in series.foot_force.items()},
        odometry=odometry,
        notes=tuple(notes),
        leg_model_joints={leg: tuple(robot.leg(leg).joint_names) for leg in LEG_NAMES},
    )


def _leg_chains(
    robot: Robot, series: JointSeries, present: dict[str, int]
) -> tuple[dict[str, tuple[str, ...]], list[str]]:
    """Per leg, its joints the log holds (trunk first), and a warning for those it lacks.

    Raises:
        LogError: A leg's hip pitch or knee is not in the log.
    """
    legs = {}
    absent = []
    for leg in LEG_NAMES:
        chain = leg_joints(robot, leg)
        missing = [j for j in robot.leg(leg).joint_names if j not in present]
        if missing:
            held = ", ".join(series.joints[:6]) + (", ..." if len(series.joints) > 6 else "")
            raise LogError(
                f"{series.source}: leg {leg}'s joint {missing[0]!r} is not in the log (it holds "
                f"{held}; give the robot with --robot, or map the joints with --mapping)"[:400]
            )
        legs[leg] = tuple(j for j in chain if j in present)
        absent += [j for j in chain if j not in present]
    notes = []
    if absent:
        notes.append(
            f"warning: {len(absent)} leg joint(s) of {robot.name} are not in the log and their "
            f"work is not counted: {', '.join(absent[:8])}{', ...' if len(absent) > 8 else ''}"
        )
    return legs, notes


def _gap_notes(t_s: np.ndarray) -> list[str]:
    """A note on the gaps in the stamps (steps over :data:`GAP_FACTOR` times the median)."""
    steps = np.diff(t_s)
    median = float(np.median(steps))
    gaps = steps > GAP_FACTOR * median
    if not gaps.any():
        return []
    return [
        f"{int(gaps.sum())} gap(s) in the time stamps (steps over {GAP_FACTOR:g} times the "
        f"median {median * 1e3:.3g} ms; the longest {steps.max() * 1e3:.4g} ms at "
        f"t = {t_s[int(np.argmax(steps))] - t_s[0]:.4g} s): power is interpolated across them"
    ]


def _range_notes(robot: Robot, q_rad: dict[str, np.ndarray]) -> list[str]:
    """A warning per joint whose angles go beyond its URDF range by more than the tolerance."""
    model = robot.model
    notes = []
    for joint, q in q_rad.items():
        jid = model.getJointId(joint)
        lo = float(model.lowerPositionLimit[model.idx_qs[jid]])
        hi = float(model.upperPositionLimit[model.idx_qs[jid]])
        beyond = max(lo - float(q.min()), float(q.max()) - hi)
        if np.isfinite(lo) and np.isfinite(hi) and hi > lo and beyond > RANGE_TOLERANCE_RAD:
            notes.append(
                f"warning: {joint} reaches {np.degrees(beyond):.1f} deg beyond its URDF range "
                f"[{np.degrees(lo):.1f}, {np.degrees(hi):.1f}] deg (a log of another robot?)"
            )
    return notes


def neutral_configuration(robot: Robot) -> np.ndarray:
    """The robot's reference configuration (or Pinocchio's neutral one), shape (nq,)."""
    if robot.reference_q is not None:
        return np.array(robot.reference_q, dtype=float)
    return pin.neutral(robot.model)
