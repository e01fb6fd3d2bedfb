"""The optimizers' results as the records of ``summary.json``.

The writer; the reader of the swings they hold is :mod:`scalf_opt.io.saved`, beside it.

One function per result type, so that a record's schema lives in one place beside its reader,
and the optimizers' result types stay plain frozen data: :func:`optimum_record` (one solver's
answer for one leg), :func:`leg_record` (a leg's optimization: its best answer, its starts, the
comparisons), :func:`run_record` (the ``optimization_run`` record), :func:`bound_record` (the
free-trajectory bound), :func:`stance_record` (the free stance) and :func:`gait_search_record`
(the cheapest trot at a speed).
"""

from __future__ import annotations

import math
from dataclasses import fields
from typing import Any

from scalf_opt.optimize.bound import BoundLevel, FreeBound
from scalf_opt.optimize.driver import LegResult, StartResult, SwingOptimization
from scalf_opt.optimize.free_stance import STANCE_VARIABLES, FreeStance
from scalf_opt.optimize.gait_search import SEARCH_VARIABLES, GaitBox, GaitSearch
from scalf_opt.optimize.sampling import CHECK_FACTOR
from scalf_opt.optimize.solve import History, IpoptDetails, PatternSearchDetails, SwingOptimum


def _history_records(optimum: SwingOptimum, rows: History, value: str) -> list[dict[str, Any]]:
    """History rows ``(iteration, *theta, value)`` as records with named parameters."""
    return [
        {
            "iteration": int(row[0]),
            "parameters": dict(zip(optimum.parameter_names, map(float, row[1:-1]), strict=True)),
            value: float(row[-1]),
        }
        for row in rows
    ]


def optimum_record(optimum: SwingOptimum) -> dict[str, Any]:
    """One solver's answer for one leg: parameters by name, energies, status, its details."""
    details = optimum.details
    pattern = details if isinstance(details, PatternSearchDetails) else None
    stats = details.stats if isinstance(details, IpoptDetails) else details.solver_stats()
    return {
        "leg": optimum.leg,
        "family": optimum.family,
        "method": optimum.method,
        "parameters": dict(zip(optimum.parameter_names, map(float, optimum.theta), strict=True)),
        "unit": optimum.unit,
        "swing_energy_j": optimum.swing_energy_j,
        "objective_j": optimum.objective_j,
        "success": optimum.success,
        "status": optimum.status,
        "iterations": optimum.iterations,
        "evaluations": optimum.evaluations,
        "wall_time_s": optimum.wall_time_s,
        "infeasible_evaluations": dict(pattern.infeasible) if pattern else {},
        "solver_stats": dict(stats),
        "history": _history_records(optimum, pattern.history if pattern else (), "swing_energy_j"),
        "feasibility_history": _history_records(
            optimum, pattern.feasibility_history if pattern else (), "violation"
        ),
    }


def start_record(start: StartResult) -> dict[str, Any]:
    """One start of one leg."""
    return {
        "start": start.label,
        "swing_energy_j": start.optimum.swing_energy_j,
        "check_energy_j": start.check_energy_j,
        "success": start.optimum.success,
        "converged": start.converged,
        "status": start.optimum.status,
        "iterations": start.optimum.iterations,
        "wall_time_s": start.optimum.wall_time_s,
    }


def leg_record(result: LegResult) -> dict[str, Any]:
    """A leg's optimization: the best optimum's record, with the comparisons and the starts."""
    return {
        **optimum_record(result.best),
        "success": result.success,
        "reference_swing_energy_j": result.reference_swing_energy_j,
        "change_against_reference_pct": result.change_percent,
        "worse_than_reference": result.worse_than_reference,
        "check_energy_j": result.check_energy_j,
        "check_rate_factor": CHECK_FACTOR,
        "sampling_error": result.sampling_error,
        "check_swing_energy_j": result.check_swing_energy_j,
        "bound_check_energy_j": result.bound_check_energy_j,
        "gap_to_bound_pct": result.gap_to_bound_percent,
        "starts": [start_record(s) for s in result.starts],
        "spread_j": result.spread_j,
    }


def leg_records(run: SwingOptimization) -> dict[str, dict[str, Any]]:
    """Every leg's record of ``run``, by leg (``summary.json``'s ``optimization``)."""
    return {leg: leg_record(r) for leg, r in run.legs.items()}


def run_record(run: SwingOptimization) -> dict[str, Any]:
    """The ``optimization_run`` record of ``summary.json``: the rate, the rates tried, settings."""
    return {
        "family": run.family.name,
        "method": run.settings.method,
        "starts": run.settings.starts,
        "sample_rate_hz": run.rate_hz,
        "rates_tried_hz": list(run.rates_hz),
        "sampling_tolerance": run.settings.sampling_tolerance,
        "converged_sampling": run.converged_sampling,
        "success": run.success,
        "any_worse_than_reference": any(r.worse_than_reference for r in run.legs.values()),
        "wall_time_s": run.wall_time_s,
        "loads": run.pipeline.loads,
        "alternation_rounds": run.rounds,
        "alternation_settled": run.alternation_settled,
        "legs_solved_together": run.solved_together,
    }


def level_record(level: BoundLevel) -> dict[str, Any]:
    """One refinement level of the free-trajectory bound."""
    return {f.name: getattr(level, f.name) for f in fields(level)}


def bound_record(bound: FreeBound) -> dict[str, Any]:
    """The free-trajectory bound of one leg, its levels and its control points."""
    return {
        "leg": bound.leg,
        "family": bound.family.name,
        "swing_energy_j": bound.swing_energy_j,
        "check_energy_j": bound.check_energy_j,
        "sample_rate_hz": bound.sample_rate_hz,
        "converged": bound.converged,
        "remaining_estimate_j": bound.remaining_j,
        "success": bound.success,
        "status": bound.status_text(),
        "levels": [level_record(level) for level in bound.levels],
        "parameters_deg": [float(x) for x in bound.result.best.theta],
    }


def bound_records(bounds: dict[str, FreeBound]) -> dict[str, dict[str, Any]]:
    """Every leg's bound record, by leg (``summary.json``'s ``free_bound``)."""
    return {leg: bound_record(b) for leg, b in bounds.items()}


def stance_record(stance: FreeStance) -> dict[str, Any]:
    """The free stance: the stance found, the energies, the saving's split, the search."""
    g = stance.best.gait
    return {
        "stance": {name: getattr(g, name) for name in STANCE_VARIABLES},
        "nominal_stance": {name: getattr(stance.nominal.gait, name) for name in STANCE_VARIABLES},
        "total_energy_per_cycle_j": stance.cycle().energy_j,
        "nominal_stance_total_energy_per_cycle_j": stance.nominal_cycle().energy_j,
        "reference_total_energy_per_cycle_j": stance.reference.energy_j,
        "saving_j": stance.split_j(),
        "evaluations": stance.evaluations,
        "iterations": stance.iterations,
        "converged": stance.converged,
        "success": stance.success,
        "history_cm_j": [list(map(float, row)) for row in stance.history],
        "wall_time_s": stance.wall_time_s,
    }


def box_record(box: GaitBox) -> dict[str, float]:
    """The gait search's box."""
    return {
        "period_min_s": box.period_min_s,
        "period_max_s": box.period_max_s,
        "duty_min": box.duty_min,
        "duty_max": box.duty_max,
    }


def gait_search_record(search: GaitSearch) -> dict[str, Any]:
    """The cheapest trot at one speed: the answer, the default trot, the grid, the search."""

    def record(e: Any) -> dict[str, Any]:
        cot = search.cost_of_transport(e)
        return {
            **{name: getattr(e.gait, name) for name in (*SEARCH_VARIABLES, "step_length_m")},
            "pair_energy_per_cycle_j": e.total_j if math.isfinite(e.total_j) else None,
            "cost_of_transport": cot if math.isfinite(cot) else None,
            "infeasible": e.reason,
        }

    return {
        "speed_m_s": search.speed_m_s,
        "family": search.family.name,
        "method": search.settings.method,
        "box": box_record(search.box),
        "best": record(search.best),
        "default_at_speed": record(search.default),
        "reference_cost_of_transport": (
            search.reference.cost_of_transport if search.reference is not None else None
        ),
        "grid": [record(e) for e in search.grid],
        "pinned": search.pinned,
        "iterations": search.iterations,
        "evaluations": search.evaluations,
        "converged": search.converged,
        "success": search.success,
        "history": [list(map(float, row)) for row in search.history],
        "wall_time_s": search.wall_time_s,
    }
