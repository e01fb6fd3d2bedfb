"""Plain-text reports of an optimization: optima, starts, sampling, bound, peaks and limits."""

from __future__ import annotations

import math

import numpy as np

from scalf_opt.energy.cycle import RobotCycle, change_percent
from scalf_opt.energy.limits import printed_unit
from scalf_opt.energy.peaks import CycleViolation, Peak, cycle_violations
from scalf_opt.optimize.bound import FreeBound
from scalf_opt.optimize.constraints import FEASIBILITY_TOLERANCE, SwingGrid
from scalf_opt.optimize.driver import ALTERNATION_RTOL, LegResult, SwingOptimization
from scalf_opt.optimize.free_stance import FreeStance
from scalf_opt.optimize.sampling import CHECK_FACTOR, relative_difference
from scalf_opt.types import JOINT_ROLES


def _g(x: float) -> str:
    """Four significant digits, no exponent for the sizes reports show."""
    if x == 0 or not math.isfinite(x):
        return f"{x:g}"
    digits = max(0, 3 - math.floor(math.log10(abs(x))))
    return f"{x:.{digits}f}"


def peaks_table(peaks: list[Peak], reference: list[Peak] | None = None) -> str:
    """Peaks per leg and joint, then the limits; ``*`` marks a peak beyond its limit.

    A quantity whose two sides have different limits (HyQ's cylinder force: push and pull) is
    shown signed, its peak the sample closest to its side's limit, and that limit signed too.

    Args:
        peaks: The cycle's peaks.
        reference: The reference cycle's peaks, shown in brackets beside each (optimize).
    """
    columns: list[tuple[str, str]] = []
    for p in peaks:
        if (p.quantity, p.unit) not in columns:
            columns.append((p.quantity, p.unit))
    signed = {p.quantity for p in peaks if p.quantity == "power" or p.one_sided}
    heads = [
        f"{q} [{printed_unit(u)}]" if q in signed else f"|{q}| [{printed_unit(u)}]"
        for q, u in columns
    ]
    width = 22 if reference else 16
    note = "; the reference trajectory's in brackets" if reference else ""
    lines = [
        f"peaks over the cycle (* = beyond its limit{note}):",
        "leg   joint " + "".join(f"{h:>{width}s}" for h in heads),
    ]

    rows, ref_rows = _by_row(peaks), _by_row(reference or [])
    limits: dict[tuple[str, str], list[str]] = {}
    for (leg, joint), by_quantity in rows.items():
        pairs = [
            _peak_cells(by_quantity.get(q), ref_rows.get((leg, joint), {}).get(q), q in signed)
            for q, _ in columns
        ]
        cells = [cell for cell, _ in pairs]
        lines.append(f"{leg:5s} {joint:5s} " + "".join(f"{c:>{width}s}" for c in cells))
        limits[(leg, joint)] = [limit for _, limit in pairs]
    return "\n".join(lines + _limit_rows(limits, width))


def _by_row(items: list[Peak]) -> dict[tuple[str, str], dict[str, Peak]]:
    """The peaks by (leg, joint), then by quantity."""
    rows: dict[tuple[str, str], dict[str, Peak]] = {}
    for p in items:
        rows.setdefault((p.leg, p.joint), {})[p.quantity] = p
    return rows


def _peak_cells(p: Peak | None, ref: Peak | None, signed: bool) -> tuple[str, str]:
    """A peak's cell (the reference's in brackets, ``*`` beyond its limit) and its limit's."""
    if p is None:
        return "-", "-"
    value = _g(p.value) if signed else _g(abs(p.value))
    if ref is not None:
        shown = _g(ref.value) if signed else _g(abs(ref.value))
        value += f" ({shown}{'*' if ref.exceeds else ''})"
    if p.limit is None:
        limit = "none "
    else:  # a one-sided limit carries the sign of its side
        limit = _g(p.limit if p.value >= 0 or not p.one_sided else -p.limit) + " "
    return f"{value}{'*' if p.exceeds else ' '}", limit


def _limit_rows(limits: dict[tuple[str, str], list[str]], width: int) -> list[str]:
    """The limits: one row per joint when every leg has the same, else one per leg and joint."""
    by_joint = {joint: cells for (_, joint), cells in limits.items()}
    if all(cells == by_joint[joint] for (_, joint), cells in limits.items()):
        return [
            f"limit {joint:5s} " + "".join(f"{c:>{width}s}" for c in cells)
            for joint, cells in by_joint.items()
        ]
    return [
        f"limit {leg} {joint:5s}" + "".join(f"{c:>{width}s}" for c in cells)
        for (leg, joint), cells in limits.items()
    ]


def violation_lines(violations: list[CycleViolation]) -> list[str]:
    """One warning line per exceeded limit."""
    return [f"warning: {v.message()}" for v in violations]


def _leg_lines(result: LegResult, method: str, family: str) -> list[str]:
    o = result.best
    verdict = "solved" if result.success else "NOT SOLVED"
    lines = [
        f"{result.leg}: {family} by {method}: {verdict} ({o.status}), {o.iterations} iterations"
        + (f", {o.evaluations} evaluations" if o.evaluations else "")
        + f", {o.wall_time_s:.2f} s"
    ]
    if not math.isfinite(o.swing_energy_j):  # why is in the status; Ipopt's log: --verbose
        return lines
    if math.isfinite(result.reference_swing_energy_j):
        against = (
            f"vs reference {result.reference_swing_energy_j:.4f} J ({result.change_percent:+.2f} %)"
        )
    else:
        against = "(the reference swing leaves the joint range at this gait)"
    if o.objective_j == o.swing_energy_j:
        lines.append(
            f"  swing energy {o.swing_energy_j:.4f} J {against}; at {CHECK_FACTOR}x the rate "
            f"{result.check_energy_j:.4f} J ({100 * result.sampling_error:.3f} % apart)"
        )
    else:  # whole-body loads: the swing pays for the stance it loads
        swing_check = result.check_swing_energy_j
        swing_apart = (
            f"; at {CHECK_FACTOR}x the rate {swing_check:.4f} J "
            f"({100 * relative_difference(o.swing_energy_j, swing_check):.3f} % apart)"
            if swing_check is not None and math.isfinite(swing_check)
            else ""
        )
        objective_apart = relative_difference(o.objective_j, result.check_energy_j)
        lines += [
            f"  swing energy {o.swing_energy_j:.4f} J {against}{swing_apart}",
            f"  objective (its swing and the stance it loads) {o.objective_j:.4f} J; at "
            f"{CHECK_FACTOR}x the rate {result.check_energy_j:.4f} J "
            f"({100 * objective_apart:.3f} % apart)",
        ]
    gap = result.gap_to_bound_percent
    if gap is not None and result.bound_check_energy_j is not None:
        lines.append(
            f"  free-trajectory bound {result.bound_check_energy_j:.4f} J (at {CHECK_FACTOR}x "
            f"its rate): this optimum is {gap:+.2f} % above it"
        )
    if len(result.starts) > 1:
        parts = []
        for s in result.starts:
            state = f"{s.optimum.swing_energy_j:.4f} J" if s.converged else "failed"
            parts.append(f"{s.label}: {state}" + ("" if s.converged else f" ({s.optimum.status})"))
        lines.append(
            f"  {len(result.starts)} starts, best {o.swing_energy_j:.4f} J, spread "
            f"{result.spread_j:.4f} J: " + "; ".join(parts)
        )
    params = ", ".join(f"{n}={v:.4f}" for n, v in zip(o.parameter_names, o.theta, strict=True))
    lines.append(f"  parameters [{o.unit}]: {params}")
    return lines


def optimization_report(run: SwingOptimization) -> str:
    """Text of ``scalf-opt optimize``: each leg's optimum against the reference and the bound."""
    rates = ", ".join(f"{r:g}" for r in run.rates_hz)
    stance = run.pipeline.load_model.couples_legs  # the objective holds the stance it loads
    lines = [
        f"sampled at {run.rate_hz:g} Hz (tried {rates} Hz: each optimum's "
        + ("swing energy, objective and stance part" if stance else "swing energy")
        + f" must agree with {'theirs' if stance else 'its energy'} at {CHECK_FACTOR}x the "
        f"rate within {100 * run.settings.sampling_tolerance:g} %)"
        + ("" if run.converged_sampling else "; NOT CONVERGED")
    ]
    if run.coupled and run.solved_together:
        lines.append(
            "whole-body loads couple the legs (each swing loads the other's stance feet): "
            "both solved as one problem, from where one round of the legs in turn ended; the "
            f"whole optimization took {run.wall_time_s:.2f} s"
        )
    elif run.coupled:
        unsolved = [leg for leg, result in run.legs.items() if not result.best.success]
        if unsolved:  # the alternation stops at a leg it could not solve
            turns = f"stopped in round {run.rounds}, where {', '.join(unsolved)} was not solved"
        elif run.alternation_settled:
            turns = (
                f"{run.rounds_text} until a round changed the pair's energy by less than "
                f"{ALTERNATION_RTOL:g} relative"
            )
        else:
            turns = f"{run.rounds_text} and stopped there, its energy still changing: NOT CONVERGED"
        lines.append(
            f"whole-body loads couple the legs (each swing loads the other's stance feet): "
            f"solved in turn, {turns}; a leg's iterations and time below are its last solve's, "
            f"the whole optimization took {run.wall_time_s:.2f} s"
        )
    for result in run.legs.values():
        lines += _leg_lines(result, run.settings.method, run.family.name)
    return "\n".join(lines)


def optimization_warnings(run: SwingOptimization) -> list[str]:
    """Warning lines: optima worse than the reference, failed starts, unconverged sampling.

    Under loads that couple the legs a swing is optimized with the stance it loads, and its own
    energy may rise where the pair's falls (or where the reference crosses a stance limit that
    the optimum keeps): the line then says what the whole cycle costs against the reference's.
    """
    out = []
    cycles = ""
    worse = {leg for leg, r in run.legs.items() if r.success and r.worse_than_reference}
    if worse:
        optimized, reference = run.cycle(), run.reference_cycle()
        if run.coupled:
            cycles = (
                f"; under {run.pipeline.loads} loads a swing is optimized with the stance it "
                f"loads: the cycle costs {optimized.energy_j:.3f} J against the reference's "
                f"{reference.energy_j:.3f} J "
                f"({change_percent(optimized.energy_j, reference.energy_j):+.2f} %)"
            )
        cycles += _reference_beyond(run, optimized, reference)
    for result in run.legs.values():
        if result.leg in worse:
            out.append(
                f"warning: {result.leg}: the {run.family.name} optimum "
                f"({result.best.swing_energy_j:.4f} J) is WORSE than the reference swing "
                f"({result.reference_swing_energy_j:.4f} J, {result.change_percent:+.2f} %)"
                + cycles
            )
        failed = [s for s in result.starts if not s.converged]
        if failed and result.success:
            out.append(
                f"warning: {result.leg}: {len(failed)} of {len(result.starts)} starts failed: "
                + "; ".join(f"{s.label} ({s.optimum.status})" for s in failed)
            )
    return out


def _reference_beyond(run: SwingOptimization, optimized: RobotCycle, reference: RobotCycle) -> str:
    """``; the reference crosses ...``: the reference cycle's worst crossed limit, else ``""``.

    An optimum kept inside every limit may cost more than a reference that is not.
    """
    physics = {leg: run.pipeline.physics(leg) for leg in reference.legs}
    crossed = {(v.leg, v.violation.bound.name) for v in cycle_violations(optimized, physics)}
    beyond = [
        v
        for v in cycle_violations(reference, physics)
        if (v.leg, v.violation.bound.name) not in crossed
    ]
    low = _reference_below_lift(run, reference)
    if not beyond:
        return low
    worst = max(beyond, key=lambda v: v.violation.share)
    b = worst.violation.bound
    over = 100.0 * worst.violation.share
    others = f" and {len(beyond) - 1} more" if len(beyond) > 1 else ""
    return (
        f"; the reference crosses limits the optimum keeps: {worst.leg} "
        f"{JOINT_ROLES[b.joint]} {b.quantity} by {over:.2g} % in {worst.phase}{others}" + low
    )


def _reference_below_lift(run: SwingOptimization, reference: RobotCycle) -> str:
    """``; the reference swing lifts its feet slower than the lift profile ...`` or ``""``.

    The optimum keeps the lift profile of its margins (:class:`~scalf_opt.energy.margins.
    LiftProfile`); the reference swing was not made to, and where it lifts slower it may cost
    less than any swing that does.
    """
    gait = run.pipeline.gait
    lift = run.settings.margins.for_family(run.family.n_params).lift
    if lift.height_for(gait.clearance_m) == 0.0:
        return ""
    for leg, cycle in reference.legs.items():
        swing = cycle.swing
        t = swing.t_phase_s
        grid = SwingGrid.on(t, -gait.stance_height_m, gait.clearance_m, lift)
        z = swing.values["foot"][1]
        if np.any(z[1:-1] < grid.lift_z_m()[1:-1] - FEASIBILITY_TOLERANCE):
            return (
                f"; the reference swing lifts its feet slower than the lift profile the optimum "
                f"keeps ({leg}: {1e3 * grid.lift_height_m:.3g} mm up by "
                f"{100 * grid.lift_fraction:g} % of the swing; optimize --lift-height, "
                "--lift-fraction)"
            )
    return ""


def bound_report(bounds: dict[str, FreeBound]) -> str:
    """Text of the free-trajectory bound per leg, its status and its refinement."""
    lines = []
    for leg, b in bounds.items():
        verdict = b.status_text() if b.success else f"NOT CONVERGED: {b.status_text()}"
        steps = "; ".join(
            f"{lv.spans} spans: {lv.swing_energy_j:.4f} J at {lv.sample_rate_hz:g} Hz"
            + ("" if lv.success else f" ({lv.status})")
            for lv in b.levels
        )
        lines += [
            f"{leg}: free-trajectory bound {b.swing_energy_j:.4f} J ({verdict}; "
            f"{b.check_energy_j:.4f} J at {CHECK_FACTOR}x the rate)",
            f"  refinement: {steps}",
        ]
    return "\n".join(lines)


def free_stance_report(result: FreeStance) -> str:
    """The stance found, and where the saving comes from."""
    g, n = result.best.gait, result.nominal.gait
    split = result.split_j()
    ref = result.reference.energy_j
    best = result.cycle().energy_j

    def pct(x: float) -> str:
        return f"{100 * x / ref:.1f} %"

    return "\n".join(
        [
            f"free stance: z0 = {g.stance_height_m:.4f} m (was {n.stance_height_m:.4f}), stance "
            f"x-offset front {1000 * g.stance_x_offset_front_m:+.1f} mm, hind "
            f"{1000 * g.stance_x_offset_hind_m:+.1f} mm ({result.iterations} pattern-search "
            f"iterations, {result.evaluations} stances tried, {result.wall_time_s:.1f} s)",
            f"  energy per cycle: reference {ref:.3f} J -> optimized swing "
            f"{result.nominal_cycle().energy_j:.3f} J -> free stance {best:.3f} J",
            f"  saving {split['total']:.3f} J/cycle ({pct(split['total'])} of the reference): "
            f"{split['stance']:.3f} J ({pct(split['stance'])}) from the stance, "
            f"{split['swing']:.3f} J ({pct(split['swing'])}) from the swing",
            f"  (the swing optimization alone saves {split['swing_only']:.3f} J; freeing the "
            f"stance adds {split['from_freeing_the_stance']:.3f} J)",
        ]
    )
