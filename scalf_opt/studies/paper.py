"""Reproduce the paper's Tables 5 and 6: reference, pattern search and Ipopt, side by side.

For the RF and LH legs (LF and RH repeat them half a cycle later, the paper's symmetry), each
run through :func:`~scalf_opt.optimize.driver.optimize_swings`, the code path and defaults of
``scalf-opt optimize`` (so that ``paper`` and ``optimize`` give the same number for the same
question):

* the cubic-spline reference;
* the pattern search on the paper family with the paper's settings (start (0, 0), step
  (0.5, 0.5), precision 0.1), and again at precision 1e-4 (validation);
* Ipopt on the paper family (the NLP optimum the pattern search is validated against);
* Ipopt on the default rich family;
* the free-trajectory bound of each leg and every run's gap to it, and the default family with
  the stance optimized too (beyond the paper; both left out in quick mode).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from scalf_opt.energy.cycle import RobotCycle, change_percent
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.interrupts import results_in_order
from scalf_opt.io.optimization_records import bound_records, leg_records, stance_record
from scalf_opt.io.provenance import provenance
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.bound import FreeBound, bound_jobs, leg_bound
from scalf_opt.optimize.driver import Settings, SwingOptimization, optimize_swings
from scalf_opt.optimize.free_stance import FreeStance, optimize_stance
from scalf_opt.optimize.pattern_search import PatternSearchOptions
from scalf_opt.optimize.sampling import SAMPLING_TOLERANCE
from scalf_opt.optimize.solve import SwingOptimum
from scalf_opt.optimize.solvers import PatternSearchSolver
from scalf_opt.types import FIRST_PAIR
from scalf_opt.workers import WorkerProcesses, worker_progress

FINE_PRECISION = 1e-4
"""Pattern-search precision of the validation run."""

PAIR = FIRST_PAIR

RUNS: dict[str, tuple[str, str, Settings]] = {
    "pattern": (
        "paper",
        "pattern search, paper family (precision 0.1)",
        Settings(PatternSearchSolver.name),
    ),
    "pattern_fine": (
        "paper",
        f"pattern search, paper family (precision {FINE_PRECISION:g})",
        Settings(PatternSearchSolver.name, pattern=PatternSearchOptions(precision=FINE_PRECISION)),
    ),
    "ipopt": ("paper", "Ipopt, paper family", Settings()),
    "ipopt_rich": (DEFAULT_FAMILY, f"Ipopt, {DEFAULT_FAMILY} family", Settings()),
}
"""Run key -> (family, label, settings); the settings are ``scalf-opt optimize``'s (the paper
family keeps no lift profile: :meth:`~scalf_opt.energy.margins.LimitMargins.for_family`)."""


@dataclass(frozen=True)
class WholeBody:
    """The reference and the default optimum under whole-body loads (the report's one line).

    The paper's tables use the trunk-only loads (decision 11); this is what the other commands
    compute by default (:mod:`scalf_opt.energy.loads`), with the default family re-optimized
    so that a swing pays for the loads it puts on the stance legs.

    Attributes:
        trunk_reference: The reference under trunk-only loads, at the run's rate.
        run: The default family's optimization under whole-body loads.
    """

    trunk_reference: RobotCycle
    run: SwingOptimization

    @property
    def reference(self) -> RobotCycle:
        """The reference under whole-body loads, at the run's rate."""
        return self.run.reference_cycle()

    def as_dict(self) -> dict[str, Any]:
        """Plain data for ``paper.json``."""
        optimum = self.run.cycle() if self.run.success else None
        reference = self.reference
        return {
            "loads": self.run.pipeline.loads,
            "family": self.run.family.name,
            "sample_rate_hz": self.run.rate_hz,
            "success": self.run.success,
            "reference_total_energy_j": reference.energy_j,
            "trunk_reference_total_energy_j": self.trunk_reference.energy_j,
            "optimum_total_energy_j": optimum.energy_j if optimum is not None else None,
            "optimum_change_pct": (
                change_percent(optimum.energy_j, reference.energy_j)
                if optimum is not None
                else None
            ),
            "reference_mean_stance_force_n": reference.mean_stance_force_n,
            "trunk_mean_stance_force_n": self.trunk_reference.mean_stance_force_n,
            "reference_peak_unbalanced_moment_nm": reference.peak_unbalanced_moment_nm,
            "optima": leg_records(self.run),
        }


@dataclass
class Reproduction:
    """Everything the paper report shows.

    Attributes:
        pipeline: Robot, gait and accounting of the reproduction.
        reference: Robot cycle with the reference swing on every leg, at the gait's rate.
        runs: Run key -> the optimization (RF and LH).
        optima: Run key -> leg -> best optimizer answer.
        cycles: Run key -> robot cycle with that run's swing (LF, RH by symmetry), at its rate.
        references: Run key -> the reference cycle at that run's rate.
        bounds: Leg -> the free-trajectory bound (empty when left out).
        free_stance: The default family with the stance optimized too (``None`` when left out).
        whole_body: The reference and the default optimum under whole-body loads (``None``
            when the reproduction itself uses them).
        wall_time_s: Time of the whole reproduction [s].
    """

    pipeline: EnergyPipeline
    reference: RobotCycle
    runs: dict[str, SwingOptimization] = field(default_factory=dict)
    optima: dict[str, dict[str, SwingOptimum]] = field(default_factory=dict)
    cycles: dict[str, RobotCycle] = field(default_factory=dict)
    references: dict[str, RobotCycle] = field(default_factory=dict)
    bounds: dict[str, FreeBound] = field(default_factory=dict)
    free_stance: FreeStance | None = None
    whole_body: WholeBody | None = None
    wall_time_s: float = 0.0

    @property
    def gait(self) -> Gait:
        """The gait."""
        return self.pipeline.gait

    @property
    def all_solved(self) -> bool:
        """Everything converged.

        Every optimizer (to a feasible point, its energy converged in the sampling), every
        bound's refinement (its remainder below the tolerance), the stance search.
        """
        return (
            (self.whole_body is None or self.whole_body.run.success)
            and all(run.success for run in self.runs.values())
            and all(b.success for b in self.bounds.values())
            and (self.free_stance is None or self.free_stance.success)
        )

    def failures(self) -> list[str]:
        """What did not converge, one phrase each."""
        out = [
            f"{RUNS[key][1]}: {run.failure()}" for key, run in self.runs.items() if not run.success
        ]
        out += [
            f"the free-trajectory bound of {leg}: {b.status_text()}"
            for leg, b in self.bounds.items()
            if not b.success
        ]
        if self.free_stance is not None and not self.free_stance.success:
            out.append(f"the free stance ({self.free_stance.best.reason or 'not converged'})")
        if self.whole_body is not None and not self.whole_body.run.success:
            out.append(
                f"the default optimum under whole-body loads: {self.whole_body.run.failure()}"
            )
        return out


def reproduce(
    pipeline: EnergyPipeline,
    beyond: bool = True,
    ipopt_options: dict[str, Any] | None = None,
    progress: Callable[[str], None] | None = None,
) -> Reproduction:
    """Run every optimizer of the paper's comparison on the RF and LH legs.

    Args:
        pipeline: Robot, gait, accounting.
        beyond: Also compute the free-trajectory bound (and every run's gap to it) and the
            default family with a free stance.
        ipopt_options: Extra Ipopt options (e.g. ``{"print_level": 5}`` for its log).
        progress: Called with a label before each step.
    """
    start = time.perf_counter()

    def step(label: str) -> None:
        if progress is not None:
            progress(label)

    out = Reproduction(pipeline, pipeline.robot_cycle(make_family("reference")))
    # the rest is independent solves, each Ipopt's and so one factorization at a time per
    # process (scalf_opt.workers): they run side by side in worker processes, those that need
    # no optimum of the tables from the start. The whole-body line, the shortest, runs behind
    # the others in priority; the free stance beside the bounds: behind them it was the last to
    # finish, alone on one core (measured: docs/speed-log.md, "Measurements behind choices")
    settings = Settings(ipopt=ipopt_options)
    early: list[tuple[str, Any]] = []
    if not pipeline.load_model.couples_legs:
        early.append(
            (WHOLE_BODY_JOB, (pipeline.with_loads(DEFAULT_LOADS), DEFAULT_FAMILY, settings))
        )
    if beyond:
        early.append((FREE_STANCE_JOB, (pipeline, DEFAULT_FAMILY, settings)))
    with WorkerProcesses(len(early) + (len(PAIR) if beyond else 0), progress) as processes:
        started = [
            processes.submit(independent_solve, job, background=job[0] == WHOLE_BODY_JOB)
            for job in early
        ]
        _table_runs(out, pipeline, ipopt_options, step)
        bounded = beyond and all(out.runs[k].success for k in ("ipopt", "ipopt_rich"))
        jobs = list(zip(early, started, strict=True))
        if not bounded:  # nothing beyond the tables to compare with: the free stance is dropped
            jobs = [(job, future) for job, future in jobs if job[0] != FREE_STANCE_JOB]
        else:
            for leg_job in bound_jobs(pipeline, PAIR, _bound_seeds(out)):
                job = (BOUND_JOB, leg_job)
                jobs.append((job, processes.submit(independent_solve, job)))
        if jobs:
            step(", ".join(dict.fromkeys(kind for (kind, _), _ in jobs)))
        solved = results_in_order([future for _, future in jobs])
    for ((kind, args), _), result in zip(jobs, solved, strict=True):
        if kind == WHOLE_BODY_JOB:
            trunk_reference = result.pipeline.with_loads(pipeline.loads).robot_cycle(
                make_family("reference")
            )
            out.whole_body = WholeBody(trunk_reference, result)
        elif kind == BOUND_JOB:
            out.bounds[args[1]] = result  # a bound job names its leg second
        else:
            out.free_stance = result
    checks = {leg: bound.check_energy_j for leg, bound in out.bounds.items()}
    out.runs = {key: run.with_bound_checks(checks) for key, run in out.runs.items()}
    out.wall_time_s = time.perf_counter() - start
    return out


def _table_runs(
    out: Reproduction,
    pipeline: EnergyPipeline,
    ipopt_options: dict[str, Any] | None,
    step: Callable[[str], None],
) -> None:
    """The tables' runs (:data:`RUNS`), each on the RF and LH legs, into ``out``."""
    for key, (family_name, label, settings) in RUNS.items():
        step(label)
        run = optimize_swings(
            pipeline, PAIR, make_family(family_name), replace(settings, ipopt=ipopt_options)
        )
        out.runs[key] = run
        out.optima[key] = {leg: r.best for leg, r in run.legs.items()}
        if run.success:
            out.cycles[key] = run.cycle()
            out.references[key] = run.reference_cycle()


def _bound_seeds(out: Reproduction) -> dict[str, list[tuple[SwingFamily, np.ndarray]]]:
    """The bound's starts per leg: the two Ipopt optima of the tables."""
    return {
        leg: [
            (out.runs[k].family, out.runs[k].legs[leg].best.theta) for k in ("ipopt", "ipopt_rich")
        ]
        for leg in PAIR
    }


WHOLE_BODY_JOB, BOUND_JOB, FREE_STANCE_JOB = "the whole-body line", "the bounds", "the free stance"
"""The kinds of :func:`independent_solve`'s jobs, which also name them in the progress line."""


def independent_solve(job: tuple[str, Any]) -> Any:
    """One of ``paper``'s solves beyond Tables 5 and 6, in a worker process of :func:`reproduce`.

    A family's swings under whole-body loads (a :class:`SwingOptimization`; ``job`` is
    ``(WHOLE_BODY_JOB, (pipeline, family name, settings))``), one leg's bound
    (:class:`FreeBound`; ``(BOUND_JOB, bound job)``) or the free stance with a family's swings
    (:class:`FreeStance`; ``(FREE_STANCE_JOB, (pipeline, family name, settings))``).
    """
    kind, args = job
    if kind == BOUND_JOB:
        return leg_bound(args)
    pipeline, family, settings = args
    if kind == WHOLE_BODY_JOB:
        worker_progress(f"{family} under whole-body loads")
        return optimize_swings(pipeline, PAIR, make_family(family), settings)
    worker_progress(FREE_STANCE_JOB)
    return optimize_stance(pipeline, make_family(family), settings)


def free_stance_label(result: FreeStance) -> str:
    """The Table 6 label of the free-stance row."""
    g = result.best.gait
    return (
        f"Ipopt, {DEFAULT_FAMILY} family, free stance (z0 = {g.stance_height_m:.3f} m, "
        f"x-offset front {1000 * g.stance_x_offset_front_m:+.1f} mm, hind "
        f"{1000 * g.stance_x_offset_hind_m:+.1f} mm)"
    )


def gap_percent(optimum: SwingOptimum, best: SwingOptimum) -> float:
    """How much higher ``optimum``'s exact swing energy is than ``best``'s [%]."""
    return 100.0 * (optimum.swing_energy_j - best.swing_energy_j) / best.swing_energy_j


AGREEMENT_PERCENT = 100.0 * SAMPLING_TOLERANCE
"""How far the fine pattern search may end below Ipopt's paper-family optimum [%] before the
two disagree: the sampling tolerance, as the two may be sampled at different rates."""


def ipopt_above_pattern_search(rep: Reproduction) -> dict[str, float]:
    """The legs where Ipopt's paper-family optimum is not the family's minimum, and by how much.

    Per leg, how far the pattern search at precision 1e-4 ends below Ipopt's optimum [%], for
    the legs where that is more than :data:`AGREEMENT_PERCENT`: there Ipopt stopped on a higher
    local optimum.
    """
    missing = unvalidated(rep)
    below = {
        leg: -gap_percent(rep.optima["pattern_fine"][leg], rep.optima["ipopt"][leg])
        for leg in PAIR
        if leg not in missing
    }
    return {leg: amount for leg, amount in below.items() if amount > AGREEMENT_PERCENT}


def unvalidated(rep: Reproduction) -> list[str]:
    """The legs the validation cannot compare: Ipopt or the fine pattern search did not solve."""
    return [
        leg
        for leg in PAIR
        if not (rep.optima["ipopt"][leg].success and rep.optima["pattern_fine"][leg].success)
    ]


def table6_rows(rep: Reproduction) -> list[dict[str, float | str]]:
    """Rows of Table 6: per trajectory, energies per leg and their changes against the reference."""
    rows: list[dict[str, float | str]] = []
    entries = [("reference", rep.reference), *rep.cycles.items()]
    if rep.free_stance is not None and rep.free_stance.success:
        entries.append(("free_stance", rep.free_stance.cycle()))
    for key, cycle in entries:
        if key == "reference":
            label, ref = "reference (cubic spline)", rep.reference
        elif key == "free_stance":
            assert rep.free_stance is not None
            label, ref = free_stance_label(rep.free_stance), rep.free_stance.reference
        else:
            label, ref = RUNS[key][1], rep.references[key]
        row: dict[str, float | str] = {
            "trajectory": label,
            "sample_rate_hz": cycle.gait.sample_rate_hz,
        }
        for leg in PAIR:
            row[f"{leg}_swing_j"] = cycle.legs[leg].swing_energy_j
            row[f"{leg}_cycle_j"] = cycle.legs[leg].energy_j
            row[f"{leg}_swing_change_pct"] = change_percent(
                cycle.legs[leg].swing_energy_j, ref.legs[leg].swing_energy_j
            )
            row[f"{leg}_cycle_change_pct"] = change_percent(
                cycle.legs[leg].energy_j, ref.legs[leg].energy_j
            )
        row["total_energy_j"] = cycle.energy_j
        row["reference_total_energy_j"] = ref.energy_j
        row["total_change_pct"] = change_percent(cycle.energy_j, ref.energy_j)
        row["average_power_w"] = cycle.average_power_w
        row["cost_of_transport"] = cycle.cost_of_transport
        rows.append(row)
    return rows


def table5_rows(rep: Reproduction) -> list[dict[str, float | str]]:
    """Rows of Table 5: the optimum's parameters, iterations and swing energy per run and leg."""
    rows: list[dict[str, float | str]] = []
    for key, (family, label, _) in RUNS.items():
        for leg in PAIR:
            o = rep.optima[key][leg]
            row: dict[str, float | str] = {"run": label, "family": family, "leg": leg}
            if family == "paper":
                row["C1"], row["C2"] = float(o.theta[0]), float(o.theta[1])
            row.update(
                {
                    "iterations": o.iterations,
                    "evaluations": o.evaluations,
                    "swing_energy_j": o.swing_energy_j,
                    "status": o.status,
                    "sample_rate_hz": rep.runs[key].rate_hz,
                    "wall_time_s": o.wall_time_s,
                }
            )
            rows.append(row)
    return rows


def summary(
    rep: Reproduction, robot: Robot, command: Sequence[str] | None = None
) -> dict[str, object]:
    """Plain data of the whole reproduction (``paper.json``), with its provenance."""
    not_agreeing = {*ipopt_above_pattern_search(rep), *unvalidated(rep)}
    return {
        "provenance": provenance(robot, command),
        "gait": rep.gait.to_dict(),
        "reference_average_power_w": rep.reference.average_power_w,
        "table5": table5_rows(rep),
        "table6": table6_rows(rep),
        "optima": {k: leg_records(run) for k, run in rep.runs.items()},
        "sample_rate_hz": {k: run.rate_hz for k, run in rep.runs.items()},
        "free_bound": bound_records(rep.bounds),
        "free_stance": stance_record(rep.free_stance) if rep.free_stance is not None else None,
        "loads": rep.pipeline.loads,
        "whole_body": rep.whole_body.as_dict() if rep.whole_body is not None else None,
        "gap_to_bound_pct": {
            k: {leg: r.gap_to_bound_percent for leg, r in run.legs.items()}
            for k, run in rep.runs.items()
        },
        "validation": {
            leg: {
                "gap_at_paper_precision_pct": gap_percent(
                    rep.optima["pattern"][leg], rep.optima["ipopt"][leg]
                ),
                "gap_at_fine_precision_pct": gap_percent(
                    rep.optima["pattern_fine"][leg], rep.optima["ipopt"][leg]
                ),
                "agrees": leg not in not_agreeing,
                "parameter_distance": float(
                    np.linalg.norm(
                        rep.optima["pattern"][leg].theta - rep.optima["ipopt"][leg].theta
                    )
                ),
            }
            for leg in PAIR
        },
        "wall_time_s": rep.wall_time_s,
        "all_solved": rep.all_solved,
        "status": "converged" if rep.all_solved else "not converged: " + "; ".join(rep.failures()),
    }
