"""A cheapest-gait case: the row of ``gaits.csv`` and what rebuilds its optimum elsewhere.

A study case with a speed (``speed_m_s`` in a study file, every case of ``scalf-opt gait``) runs
:func:`~scalf_opt.optimize.gait_search.optimize_gait` instead of a fixed gait's swing
optimization. Its row holds the cheapest gait's every field, its energy per cycle and per metre,
average power, cost of transport and peaks, beside the robot's default trot at the same speed
(with optimized swings and with the reference swing), the limits that pin it and the status.
The row's ``details`` (plain data, cached with the row, not a column) hold the swings'
parameters and records: the command's process rebuilds the optimum's cycle from them and writes
it as ``optimize --out`` would, without running the search again.
"""

from __future__ import annotations

import math
from typing import Any

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.peaks import cycle_peaks
from scalf_opt.io.optimization_records import gait_search_record, leg_records, run_record
from scalf_opt.locomotion.gait import Gait
from scalf_opt.optimize.gait_search import GaitSearch, limit_name

GAIT_FIELD_COLUMNS: tuple[str, ...] = Gait.field_names()
"""The cheapest gait's fields, one column each (``sample_rate_hz``: the rate its swings
converged at)."""

GAIT_COLUMNS: tuple[str, ...] = (
    "speed_m_s",
    "status",
    "robot",
    "family",
    *GAIT_FIELD_COLUMNS,
    "energy_per_cycle_j",
    "energy_per_m_j",
    "average_power_w",
    "cost_of_transport",
    "default_cost_of_transport",
    "reference_cost_of_transport",
    "saving_vs_default_pct",
    "saving_vs_reference_pct",
    "peak_tau_nm",
    "peak_qd_rad_s",
    "peak_power_w",
    "peak_share_of_limit",
    "peak_nearest_limit",
    "pinned_by",
    "default_infeasible",
    "iterations",
    "evaluations",
    "error",
)
"""The columns of ``gaits.csv`` (energies of all four legs; the default trot retimed to the
speed by its step length)."""


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _peaks(row: dict[str, Any], search: GaitSearch, cycle: RobotCycle) -> None:
    assert search.best.run is not None
    pipeline = search.best.run.pipeline
    peaks = cycle_peaks(cycle, {leg: pipeline.physics(leg) for leg in cycle.legs})
    for quantity, column in (("tau", "peak_tau_nm"), ("qd", "peak_qd_rad_s")):
        row[column] = max(abs(p.value) for p in peaks if p.quantity == quantity)
    row["peak_power_w"] = max((abs(p.value) for p in peaks if p.quantity == "power"), default=None)
    limited = [p for p in peaks if p.limit]
    if limited:
        nearest = max(limited, key=lambda p: abs(p.value) / p.limit)  # type: ignore[operator]
        row["peak_share_of_limit"] = abs(nearest.value) / nearest.limit  # type: ignore[operator]
        row["peak_nearest_limit"] = f"{nearest.leg} {nearest.quantity}_{nearest.joint}"


def pinned_text(search: GaitSearch) -> str:
    """The limits that pin the answer, short, one per searched direction (``""``: none)."""
    return "; ".join(f"{where}: {limit_name(reason)}" for where, reason in search.pinned.items())


def gait_row(search: GaitSearch, robot: str) -> dict[str, Any]:
    """The ``gaits.csv`` row of a search (every column of :data:`GAIT_COLUMNS`)."""
    row: dict[str, Any] = dict.fromkeys(GAIT_COLUMNS)
    row.update(speed_m_s=search.speed_m_s, robot=robot, family=search.family.name, error="")
    row["iterations"], row["evaluations"] = search.iterations, search.evaluations
    row["default_infeasible"] = search.default.reason or ""
    default = search.default_cycle()
    row["default_cost_of_transport"] = default.cost_of_transport if default else None
    reference = search.reference
    row["reference_cost_of_transport"] = reference.cost_of_transport if reference else None
    if search.best.run is None:
        row["status"] = "not solved"
        row["error"] = f"no feasible gait found: {search.best.reason}"
        return row
    cycle = search.cycle()
    row.update(cycle.gait.to_dict())
    row["energy_per_cycle_j"] = cycle.energy_j
    row["energy_per_m_j"] = cycle.energy_j / cycle.gait.distance_per_cycle_m
    row["average_power_w"] = cycle.average_power_w
    row["cost_of_transport"] = cycle.cost_of_transport
    # per metre (the cost of transport at one speed): the gaits' cycles differ in length
    if default is not None:
        row["saving_vs_default_pct"] = 100.0 * (
            1 - cycle.cost_of_transport / default.cost_of_transport
        )
    if reference is not None:
        row["saving_vs_reference_pct"] = 100.0 * (
            1 - cycle.cost_of_transport / reference.cost_of_transport
        )
    _peaks(row, search, cycle)
    row["pinned_by"] = pinned_text(search)
    row["status"] = "ok" if search.success else "not solved"
    if not search.success:
        row["error"] = "the gait search did not converge"
    return row


def gait_details(search: GaitSearch) -> dict[str, Any]:
    """What rebuilds the cheapest gait's optimum in another process (plain data).

    ``gait`` (every field, at the converged rate), ``accounting``, ``family``, ``parameters``
    per optimized leg and their ``parameter_names``, the ``optimization`` and
    ``optimization_run`` records of ``summary.json``, and the search's own record
    ``cheapest_gait``.
    """
    run = search.best.run
    details: dict[str, Any] = {"cheapest_gait": gait_search_record(search)}
    if run is None or not run.success:
        return details
    details.update(
        gait=run.pipeline.gait.to_dict(),
        accounting=run.pipeline.accounting,
        family=run.family.name,
        parameters={leg: [float(v) for v in theta] for leg, theta in run.thetas.items()},
        parameter_names=run.family.parameter_names,
        optimization=leg_records(run),
        optimization_run=run_record(run),
    )
    return details
