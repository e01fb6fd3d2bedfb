"""A 3-D cycle's answer as plain data: ``summary.json`` and ``--json`` (SI units)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from scalf_opt.types import LEG_NAMES

if TYPE_CHECKING:
    from scalf_opt.optimize.whole_body_driver import CycleResult
    from scalf_opt.optimize.whole_body_nlp import CycleProblem


def leg_energies(problem: CycleProblem, joint_energy: Any) -> dict[str, float]:
    """Each leg's share of ``joint_energy`` (per joint, the physics' order) [J]."""
    legs = problem.physics.joint_legs
    return {
        leg: float(sum(e for e, owner in zip(joint_energy, legs, strict=True) if owner == i))
        for i, leg in enumerate(LEG_NAMES)
    }


def cycle_summary(problem: CycleProblem, result: CycleResult) -> dict[str, Any]:
    """The run as plain data (``--json`` and ``summary.json``; SI units).

    ``pinned_by`` names the limits the answer rides
    (:func:`~scalf_opt.optimize.whole_body_limits.pinned_limits`); ``grid_change`` is the
    answer's energy relative to the optimum on the last coarser grid (``grid_change_from_nodes``
    nodes), both at ten times their rate
    (:attr:`~scalf_opt.optimize.whole_body_driver.CycleResult.grid_change`).
    """
    from scalf_opt.optimize.whole_body_limits import pinned_limits

    plan, last = result.plan, result.last
    physics, schedule = problem.physics, plan.schedule
    energy = plan.evaluate(problem.accounting)
    grid = result.grid_change
    return {
        "model": "3d",
        "objective": problem.objective,
        "robot": physics.robot.name,
        "period_s": schedule.period_s,
        "period_range_s": None if problem.period_range_s is None else list(problem.period_range_s),
        "duty_cycle": schedule.duty_cycle,
        "speed_m_s": problem.speed_m_s,
        "stride_m": plan.stride_m,
        "clearance_m": problem.clearance_m,
        "friction": problem.friction,
        "accounting": problem.accounting,
        "nodes": schedule.intervals,
        "reads_per_interval": schedule.reads_per_interval,
        "converged": result.converged,
        "failure": result.failure(),
        "energy_per_cycle_j": energy.total_j,
        "energy_at_10x_j": last.check.energy.total_j,
        "rate_difference": last.rate_difference,
        "grid_change": None if grid is None else grid[0],
        "grid_change_from_nodes": None if grid is None else grid[1],
        "cost_of_transport": plan.cost_of_transport(energy.total_j),
        "leg_energy_per_cycle_j": leg_energies(problem, energy.joint_energy_j),
        "joint_energy_per_cycle_j": dict(
            zip(physics.joint_names, map(float, energy.joint_energy_j), strict=True)
        ),
        "drives": dict(zip(physics.joint_names, physics.drive_origins, strict=True)),
        "check_at_10x": {
            "trunk_wrench_share_of_weight": last.check.base_residual,
            "stance_slip_m": last.check.stance_slip_m,
            "swing_floor_m": last.check.swing_floor_m,
        },
        "pinned_by": list(pinned_limits(problem, plan)),
        "trunk": {
            "height_m": [float(plan.x[2].min()), float(plan.x[2].max())],
            "roll_rad": [float(plan.x[3].min()), float(plan.x[3].max())],
            "pitch_rad": [float(plan.x[4].min()), float(plan.x[4].max())],
        },
        "solves": [
            {
                "nodes": step.nodes,
                "reads_per_interval": step.reads_per_interval,
                "status": step.solution.status,
                "iterations": step.solution.iterations,
                "seconds": step.solution.solve_s,
                "energy_per_cycle_j": step.energy_j,
                "rate_difference": step.rate_difference,
            }
            for step in result.steps
        ],
    }
