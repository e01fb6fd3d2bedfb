"""When each foot of a logged robot is on the ground: its force sensor, its torques, its motion.

* ``foot force``: the leg's sensor reading against thresholds low in the span between its low
  and high levels (5th and 95th percentiles; :data:`ON_SHARE`, :data:`OFF_SHARE`). A sensor
  whose span is under :data:`MIN_FORCE_SPAN` of its level reads nothing (Go1's often read zero):
  the next method decides.
* ``joint torque``: the same test on the vertical force the leg's joint torques imply
  (:func:`torque_forces_n`), for a log without foot sensors (the torques a motor driver
  estimates from its current are enough: the stance carries the robot's weight, the swing none);
* ``motion``, where the torques do not tell stance from swing: the foot's height in its leg
  plane (the trunk frame with the abduction undone) by the URDF's kinematics (Pinocchio) at
  every logged configuration. A swing is where the foot rises over half its lift (robust to
  noise and to the trunk's bobbing), widened on both sides while the foot is more than
  :data:`LIFT_TOLERANCE` of its lift above its stance level (the median height of the samples in
  the lowest quarter of the span), so that lift-off and touch-down are where the foot leaves and
  meets that level, not where it crosses half the lift. A foot that leaves the ground slowly is
  found late by its height: the torques come first for that reason.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from scalf_opt.errors import LogError
from scalf_opt.locomotion.forces import GRAVITY_M_S2
from scalf_opt.logs.robot_log import RobotLog, leg_joints, neutral_configuration
from scalf_opt.model.robot import Robot

MIN_FORCE_SPAN = 0.05
"""A foot sensor whose 5-95 % span is under this share of its largest reading reads nothing."""

ON_SHARE, OFF_SHARE = 0.35, 0.2
"""A foot force above this share of its span (over its low level) touches down; below that one it
lifts off: low in the span, as a stance's force rises fast but may start at a fraction of its
peak (a front foot of a trunk whose weight sits behind), and apart, so that noise makes no
extra touch-down."""

LIFT_TOLERANCE = 0.03
"""A foot this share of its lift above its stance level is off the ground."""

MIN_LIFT_M = 1e-3
"""A foot that never rises this far in the trunk frame never swings [m]."""


@dataclass(frozen=True)
class Contacts:
    """Per leg, the samples where the foot is on the ground, and how that was found.

    Attributes:
        stance: Per leg, shape (n,) bool.
        method: Per leg, ``foot force`` or ``motion``.
    """

    stance: dict[str, np.ndarray]
    method: dict[str, str]


def _schmitt(signal: np.ndarray, low: float, high: float) -> np.ndarray:
    """On above ``high``, off below ``low``, else as before (starts by the midpoint)."""
    decided = (signal > high) | (signal < low)
    # each sample takes the state of the last decided sample at or before it
    last = np.maximum.accumulate(np.where(decided, np.arange(signal.size), -1))
    start = bool(signal[0] > 0.5 * (low + high))
    return np.where(last >= 0, signal[np.maximum(last, 0)] > high, start)


def force_stance(force: np.ndarray) -> np.ndarray | None:
    """Stance from a foot sensor's reading, or ``None`` when the sensor reads nothing."""
    lo, hi = (float(v) for v in np.percentile(force, [5.0, 95.0]))
    span = hi - lo
    if not span > MIN_FORCE_SPAN * max(abs(lo), abs(hi), 1e-12):
        return None
    return _schmitt(force, lo + OFF_SHARE * span, lo + ON_SHARE * span)


def configurations(log: RobotLog, robot: Robot, samples: np.ndarray) -> np.ndarray:
    """The robot's configuration at the given samples, shape (nq, k).

    The logged joints at their angles, the others at the reference posture.
    """
    model = robot.model
    q = np.tile(neutral_configuration(robot)[:, None], (1, samples.size))
    for joint, values in log.q_rad.items():
        q[model.idx_qs[model.getJointId(joint)]] = values[samples]
    return q


def _roll_joint_ids(robot: Robot, leg: str) -> list[int]:
    """The joints of a leg's chain before its hip pitch (the abduction), trunk first."""
    model = robot.model
    chain = leg_joints(robot, leg)
    pitch = chain.index(robot.leg(leg).joint_names[0])
    return [model.getJointId(j) for j in chain[:pitch]]


def foot_heights_m(log: RobotLog, robot: Robot) -> dict[str, np.ndarray]:
    """Per leg, the foot's height in its leg plane at each sample [m] (URDF kinematics).

    The foot's position in the trunk frame with the rotation of the joints before the hip pitch
    (the abduction) undone: the height the sagittal leg sees, flat over a stance on level ground
    whatever the abduction does.
    """
    model = robot.model
    data = model.createData()
    q0 = neutral_configuration(robot)
    q = configurations(log, robot, np.arange(log.t_s.size))
    frames = {leg: model.getFrameId(robot.leg(leg).foot_frame) for leg in log.legs}
    rolls = {leg: _roll_joint_ids(robot, leg) for leg in log.legs}
    zero = q0.copy()
    for ids in rolls.values():
        for j in ids:
            zero[model.idx_qs[j] : model.idx_qs[j] + model.nqs[j]] = pin.neutral(model)[
                model.idx_qs[j] : model.idx_qs[j] + model.nqs[j]
            ]
    pin.forwardKinematics(model, data, zero)
    rest = {leg: data.oMi[ids[-1]].rotation.copy() for leg, ids in rolls.items() if ids}
    heights = {leg: np.empty(log.t_s.size) for leg in log.legs}
    for k in range(log.t_s.size):
        pin.forwardKinematics(model, data, q[:, k])
        for leg, frame in frames.items():
            foot = pin.updateFramePlacement(model, data, frame).translation
            if leg in rest:
                placement = data.oMi[rolls[leg][-1]]
                foot = rest[leg] @ placement.actInv(foot)
            heights[leg][k] = foot[2]
    return heights


def torque_forces_n(
    log: RobotLog, robot: Robot, samples: np.ndarray | None = None
) -> dict[str, np.ndarray]:
    """Per leg, the ground's vertical force on the foot that the joint torques imply [N].

    ``tau - g(q) = -J^T f`` of the leg's joints (quasi-static: the legs' inertia left out),
    solved for ``f`` by least squares; ``g`` the gravity torque of the fixed-trunk model and ``J``
    the foot's translation Jacobian in the trunk's axes. The vertical component: the weight a
    stance foot carries. ``samples``: the sample indices to evaluate (default: every one).
    """
    model = robot.model
    data = model.createData()
    index = np.arange(log.t_s.size) if samples is None else samples
    q = configurations(log, robot, index)
    zero = np.zeros(model.nv)
    frames = {leg: model.getFrameId(robot.leg(leg).foot_frame) for leg in log.legs}
    columns = {
        leg: [model.idx_vs[model.getJointId(j)] for j in joints] for leg, joints in log.legs.items()
    }
    torques = {
        leg: np.vstack([log.tau_nm[j][index] for j in joints]) for leg, joints in log.legs.items()
    }
    gravity = np.empty((index.size, model.nv))
    jacobians = {leg: np.empty((index.size, len(columns[leg]), 3)) for leg in log.legs}
    frame_axes = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for k in range(index.size):
        gravity[k] = pin.rnea(model, data, q[:, k], zero, zero)
        pin.computeJointJacobians(model, data, q[:, k])
        pin.updateFramePlacements(model, data)
        for leg, frame in frames.items():
            jacobian = pin.getFrameJacobian(model, data, frame, frame_axes)
            jacobians[leg][k] = jacobian[:3, columns[leg]].T
    forces = {}
    for leg, jt in jacobians.items():
        load = torques[leg].T - gravity[:, columns[leg]]  # (n, joints)
        # least squares of J^T f = -load at every sample at once (pinv of each J^T)
        force = -np.einsum("nij,nj->ni", np.linalg.pinv(jt), load)
        forces[leg] = force[:, 2]
    return forces


MOST_WEIGHT_SAMPLES = 20_000
"""The weight check evaluates at most this many samples, evenly spread (a mean needs no more)."""

WEIGHT_TOLERANCE = 0.25
"""The torques may carry this share more or less than the robot's weight before a warning (the
legs' inertia is left out of the estimate, and a motor's torque estimate is rough)."""


def carried_mass_kg(log: RobotLog, robot: Robot, stance: dict[str, np.ndarray]) -> float | None:
    """The mass the legs' joint torques hold up on average over whole cycles [kg].

    The sum over legs of :func:`torque_forces_n`, averaged over the whole cycles of the first leg
    (from its first touch-down to its last; over a period the trunk's momentum repeats, so the
    feet carry the weight on average, a flying trot's too), over ``g``. ``None`` without two
    touch-downs.
    """
    on = next(iter(stance.values()))
    downs = np.flatnonzero(on[1:] & ~on[:-1]) + 1
    if downs.size < 2:
        return None
    step = max(1, int(downs[-1] - downs[0]) // MOST_WEIGHT_SAMPLES)
    index = np.arange(downs[0], downs[-1] + 1, step)
    total = sum(torque_forces_n(log, robot, index).values())
    t = log.t_s[index]
    return float(np.trapezoid(total, t) / (t[-1] - t[0]) / GRAVITY_M_S2)


def weight_note(log: RobotLog, robot: Robot, stance: dict[str, np.ndarray]) -> str | None:
    """A line comparing the weight the torques carry with the robot's (a warning when far)."""
    carried = carried_mass_kg(log, robot, stance)
    if carried is None:
        return None
    mass = robot.total_mass_kg
    line = (
        f"the joint torques hold up {carried:.3g} kg on average over the cycles; {robot.name} "
        f"weighs {mass:.3g} kg"
    )
    if abs(carried / mass - 1.0) > WEIGHT_TOLERANCE:
        return (
            f"warning: {line}: a log of another robot, torques in other units, or another "
            "sign convention?"
        )
    return line


def motion_stance(height_m: np.ndarray, source: str, leg: str) -> np.ndarray:
    """Stance from a foot's height in the trunk frame (module docstring).

    Raises:
        LogError: The foot never lifts (:data:`MIN_LIFT_M`).
    """
    lo, hi = (float(v) for v in np.percentile(height_m, [5.0, 95.0]))
    lift = hi - lo
    if not lift > MIN_LIFT_M:
        raise LogError(
            f"{source}: leg {leg}'s foot never rises {MIN_LIFT_M * 1e3:g} mm in the trunk frame: "
            "no swing to find (give the foot forces in the mapping)"
        )
    level = float(np.median(height_m[height_m < lo + 0.25 * lift]))
    core = height_m > lo + 0.5 * lift
    off = height_m > level + LIFT_TOLERANCE * lift
    # a swing is a run of samples off the ground that holds a clearly lifted one
    run = np.cumsum(np.concatenate([[off[0]], off[1:] & ~off[:-1]])) * off
    lifted = np.bincount(run, weights=core.astype(float)) > 0
    lifted[0] = False  # label 0: on the ground
    return ~lifted[run]


def log_contacts(log: RobotLog, robot: Robot) -> Contacts:
    """Each leg's stance samples: its foot sensor when it reads, else its motion."""
    stance: dict[str, np.ndarray] = {}
    method: dict[str, str] = {}
    loads: dict[str, np.ndarray] | None = None
    heights: dict[str, np.ndarray] | None = None
    for leg in log.legs:
        sensed = None
        if log.foot_force is not None and leg in log.foot_force:
            sensed = force_stance(log.foot_force[leg])
        if sensed is not None:
            stance[leg], method[leg] = sensed, "foot force"
            continue
        if loads is None:
            loads = torque_forces_n(log, robot)
        sensed = force_stance(loads[leg])
        if sensed is not None and _plausible(sensed):
            stance[leg], method[leg] = sensed, "joint torque"
            continue
        if heights is None:
            heights = foot_heights_m(log, robot)
        stance[leg], method[leg] = motion_stance(heights[leg], log.source, leg), "motion"
    return Contacts(stance, method)


def _plausible(stance: np.ndarray) -> bool:
    """A stance estimate with touch-downs and a stance share a gait can have (0.1 to 0.95)."""
    downs = int(np.count_nonzero(stance[1:] & ~stance[:-1]))
    return downs >= 2 and 0.1 <= float(stance.mean()) <= 0.95
