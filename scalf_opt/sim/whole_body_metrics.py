"""What the 3-D referee measured, beside what the 3-D plan predicts (``simulation.json``).

Every figure is taken after the first gait cycle (the start-up), over the whole cycles that
follow (fewer when the robot fell or MuJoCo's integration diverged: ``fell_at_s``,
``diverged_at_s`` and ``divergence``, the check that failed in words,
:mod:`~scalf_opt.sim.divergence`; either makes the goal not met):

* ``joint_energy_per_cycle_j``: per leg, the simulated joint torques and rates charged through the
  3-D model's own power formula (:meth:`~scalf_opt.energy.whole_body.WholeBodyPhysics.
  power_function`: each joint's drive, the plan's accounting), ``tau_k qd_{k+1} dt`` per step,
  beside the plan's energy at ten times its node rate (Pinocchio's torques,
  :meth:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan.check`) and their relative difference;
  ``joint_energy_per_joint_j`` the same per joint;
* ``feedback_work_share``: per leg, the feedback's gross work over the applied torques' (both
  ``sum |tau qd| dt``): what the controller adds because the plan's torques do not carry the
  robot along it on their own;
* ``torque_saturation_fraction``: per joint, the share of steps it asked beyond its effort limit;
* ``trunk``: its height and roll/pitch ranges beside the plan's, the largest position and
  orientation errors against the plan, and its mean forward speed beside the plan's;
* ``foot_slip_m``: per leg, the largest horizontal distance a foot moves while it touches the
  ground in one contact;
* ``unplanned_contact_fraction``: per leg, the share of its planned swing its foot touches the
  ground (a foot that skims the ground between the plan's samples);
* ``stance_force_peak_n``: per leg, the largest vertical ground force, simulated and planned.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin

from scalf_opt.energy.whole_body import quaternion_rpy
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.sim.metrics import energy_goal
from scalf_opt.sim.whole_body_run import WholeBodyRecord, cycles_in_steps, steps_in_cycles
from scalf_opt.types import LEG_NAMES, Accounting


def _relative(simulated: float, model: float) -> float:
    return simulated / model - 1.0 if model else float("nan")


def measured_window(record: WholeBodyRecord, period_s: float) -> tuple[slice, int]:
    """The steps measured (every whole cycle after the first) and how many cycles they span.

    The period need not be a whole number of steps: the window holds the steps that start in
    ``[T, (1 + cycles) T)``, and a quantity per cycle is its mean rate over the window times
    ``T``. The steps are counted as the run counts them
    (:func:`~scalf_opt.sim.whole_body_run.steps_in_cycles`): a run of ``N`` cycles that did not
    stop early measures ``N - 1``.
    """
    dt = record.timestep_s
    whole = max(0, cycles_in_steps(record.t_s.size, period_s, dt) - 1)
    first = steps_in_cycles(1, period_s, dt)
    return slice(first, steps_in_cycles(1 + whole, period_s, dt)), whole


def _orientation_error(q: np.ndarray, q_plan: np.ndarray) -> float:
    worst = 0.0
    for k in range(q.shape[1]):
        rot = pin.Quaternion(q[3:7, k]).toRotationMatrix()
        rot_plan = pin.Quaternion(q_plan[3:7, k]).toRotationMatrix()
        worst = max(worst, float(np.linalg.norm(pin.log3(rot.T @ rot_plan))))
    return worst


def _slip(record: WholeBodyRecord, window: slice) -> list[float]:
    """Per foot, the largest horizontal travel [m] within one unbroken contact."""
    touching = np.linalg.norm(record.contact_force_n[:, :, window], axis=0) > 0
    feet = record.feet_m[:2, :, window]
    out = []
    for i in range(touching.shape[0]):
        worst, start = 0.0, None
        for k in range(touching.shape[1]):
            if not touching[i, k]:
                start = None
                continue
            if start is None:
                start = feet[:, i, k]
            worst = max(worst, float(np.linalg.norm(feet[:, i, k] - start)))
        out.append(worst)
    return out


def _span(values: np.ndarray) -> list[float] | None:
    """``[min, max]`` of ``values``, ``None`` when there are none (no cycle measured)."""
    return [float(values.min()), float(values.max())] if values.size else None


def _peak(values: np.ndarray) -> float | None:
    return float(values.max()) if values.size else None


def _mean(values: np.ndarray) -> float:
    return float(values.mean()) if values.size else 0.0


def _trunk(record: WholeBodyRecord, plan: WholeBodyPlan, window: slice) -> dict[str, Any]:
    """The trunk's ranges beside the plan's, its largest errors and its speed (window's)."""
    q, q_plan = record.q[:, window], record.q_plan[:, window]
    rpy, rpy_plan = quaternion_rpy(q[3:7, ::10]), quaternion_rpy(q_plan[3:7, ::10])
    t = record.t_s[window]
    return {
        "height_m": _span(q[2]),
        "plan_height_m": _span(q_plan[2]),
        "roll_rad": _span(rpy[0]),
        "plan_roll_rad": _span(rpy_plan[0]),
        "pitch_rad": _span(rpy[1]),
        "plan_pitch_rad": _span(rpy_plan[1]),
        "position_error_max_m": _peak(np.linalg.norm(q[:3] - q_plan[:3], axis=0)),
        "orientation_error_max_rad": _orientation_error(q[:, ::10], q_plan[:, ::10])
        if t.size
        else None,
        "forward_speed_m_s": float((q[0, -1] - q[0, 0]) / (t[-1] - t[0]))
        if t.size > 1
        else float("nan"),
        "plan_forward_speed_m_s": plan.speed_m_s,
    }


def _energies(
    record: WholeBodyRecord, plan: WholeBodyPlan, accounting: Accounting, window: slice
) -> tuple[np.ndarray, np.ndarray, dict[str, float]]:
    """Each joint's simulated and planned energy per cycle [J], each leg's feedback share."""
    physics = plan.physics
    n, steps = record.t_s.size, window.stop - window.start
    x, xd = np.zeros((physics.nx, n)), np.zeros((physics.nx, n))
    x[6:], xd[6:] = record.q[7:], record.qd_next  # the drives read their own joint only
    charged = np.array(physics.power_function(accounting).map(n)(x, xd, record.tau_nm))
    simulated = (
        charged[:, window].sum(axis=1) * plan.schedule.period_s / steps
        if steps
        else np.full(physics.n_joints, np.nan)
    )
    gross = np.abs(record.tau_nm[:, window] * record.qd_next[:, window]).sum(axis=1)
    fed_back = np.abs(record.feedback_nm[:, window] * record.qd_next[:, window]).sum(axis=1)
    legs = np.array(physics.joint_legs)
    feedback = {
        leg: float(fed_back[legs == i].sum() / max(gross[legs == i].sum(), 1e-300))
        for i, leg in enumerate(LEG_NAMES)
    }
    return simulated, plan.check(accounting).energy.joint_energy_j, feedback


def cycle_run_summary(
    record: WholeBodyRecord,
    plan: WholeBodyPlan,
    accounting: Accounting,
    robot_name: str,
) -> dict[str, Any]:
    """The measurements (module docstring) of one run of the 3-D referee.

    ``robot_name`` sets the per-leg energy goal (:func:`~scalf_opt.sim.metrics.energy_goal`).
    """
    physics = plan.physics
    window, whole = measured_window(record, plan.schedule.period_s)
    simulated, model, feedback = _energies(record, plan, accounting, window)
    legs = np.array(physics.joint_legs)
    energy = {}
    for i, leg in enumerate(LEG_NAMES):
        m, s = float(model[legs == i].sum()), float(simulated[legs == i].sum())
        energy[leg] = {"model": m, "simulated": s, "relative_difference": _relative(s, m)}
    total_model, total_sim = float(model.sum()), float(simulated.sum())
    planned_swing = ~record.plan_stance[:, window]
    touching = np.linalg.norm(record.contact_force_n[:, :, window], axis=0) > 0
    goal = energy_goal(robot_name)
    largest = max(abs(e["relative_difference"]) for e in energy.values())
    return {
        "fell_at_s": record.fell_at_s,
        "diverged_at_s": record.diverged_at_s,
        "divergence": record.divergence,
        "cycles_measured": whole,
        "joint_energy_per_cycle_j": energy,
        "joint_energy_per_joint_j": {
            name: {"model": float(model[j]), "simulated": float(simulated[j])}
            for j, name in enumerate(physics.joint_names)
        },
        "total_energy_per_cycle_j": {
            "model": total_model,
            "simulated": total_sim,
            "relative_difference": _relative(total_sim, total_model),
        },
        "feedback_work_share": feedback,
        "torque_saturation_fraction": {
            name: _mean(record.saturated[j, window]) for j, name in enumerate(physics.joint_names)
        },
        "trunk": _trunk(record, plan, window),
        "foot_slip_m": dict(zip(LEG_NAMES, _slip(record, window), strict=True)),
        "unplanned_contact_fraction": {
            leg: float((touching[i] & planned_swing[i]).sum() / max(1, planned_swing[i].sum()))
            for i, leg in enumerate(LEG_NAMES)
        },
        "stance_force_peak_n": {
            leg: {
                "simulated": _peak(record.contact_force_n[2, i, window]),
                "model": float(plan.forces_n[3 * i + 2].max()),
            }
            for i, leg in enumerate(LEG_NAMES)
        },
        "goals": {
            "joint_energy_relative_difference_at_most": goal,
            "did_not_fall": record.fell_at_s is None,
            "did_not_diverge": record.diverged_at_s is None,
            "joint_energy_met": bool(
                record.fell_at_s is None
                and record.diverged_at_s is None
                and whole
                and largest <= goal
            ),
        },
    }
