"""The free-trajectory bound: the lowest swing energy any smooth swing reaches.

A swing family's optimum is only as good as the family. The bound says how good a swing can
be at all under the same end conditions, constraints and energy: the joint angles are dense
clamped cubic B-splines (:class:`~scalf_opt.locomotion.swing.bspline.BSplineFamily`, twice
continuously differentiable), optimized by Ipopt at :data:`SPANS` = 16, 32, 64, ... spans, each
level started from the previous level's optimum (the families are nested, so a finer level
starts exactly where the coarser one ended and can only go lower).

The transcription follows the splines: each level is sampled at :data:`SAMPLES_PER_SPAN`
samples per span with a sample on every knot, where the joint accelerations (piecewise linear)
have their kinks and the cylinder forces their extremes. A level's optimum rides the cylinders'
force limits; sampled off the knots it crossed them between samples and the rate had to be
doubled again and again (the finest level took minutes at 6,400 Hz); on the knots it does not,
and the sampling check (:mod:`scalf_opt.optimize.sampling`, ten times the rate) passes at the
first rate.

A level after the first leaves out of its NLP the rows far from their bounds at its start
(:mod:`scalf_opt.optimize.screening`; an answer that crosses one is solved again with every row).
Measured on SCalf, same run: RF's bound in 8 s instead of 21 s (its 128-span level in 3.7 s
instead of 6.3 s, and a different round-off path through the levels, which converged there), LH's
in 17 s instead of 22 s.

The levels' energies fall as the optimum sharpens its accelerations where the joints turn, up
to the force limits. The refinement stops when the energy still to be gained, estimated from
the last two savings ``d_(k-1)``, ``d_k``, is below :data:`BOUND_TOLERANCE` of the energy. The
estimate is a geometric series ``d_k r / (1 - r)`` with ``r`` the larger of the observed ratio
``d_k / d_(k-1)`` and :data:`SLOWEST_RATIO`: the savings are assumed to shrink no faster than
by half per level (first order in the span width, what a bang-bang acceleration approximated by
splines gives), since a lucky small saving alone would otherwise promise convergence that the
next level refutes. The bound reported is the finest level's energy, a swing that is actually
reached; the estimate of what is left is reported beside it, and a test checks it against one
level finer. The estimate needs each level's minimum, and a level's optimum is the local one its
start leads to: when the estimate is close above the tolerance (:data:`REVISIT_WITHIN`), the
coarser level is solved again from the finer optimum's closest member, and the lower of its two
optima counts (the level is marked ``revisited``), before refining further.

The first level starts from the member closest to each given path (the reference swing, and
the optima of the families being compared), and keeps the best: a bound started from a
family's optimum cannot end above it by more than the sampling error.

The gap of a family's optimum to the bound compares the two swings' energies at ten times
their optimization rates (the converged energies), so that neither grid's error enters it.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from scalf_opt.energy.loads import PAPER_LOADS
from scalf_opt.energy.margins import DEFAULT_MARGINS, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.interrupts import raise_if_stopped
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.bspline import BSplineFamily
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.optimize.driver import LegResult, Settings, optimize_swings
from scalf_opt.optimize.problem import SwingGoal
from scalf_opt.optimize.sampling import Transcription
from scalf_opt.optimize.starts import closest_member, reference_path
from scalf_opt.workers import map_in_processes, worker_progress

SPANS: tuple[int, ...] = (16, 32, 64, 128, 256)
"""The refinement levels: spans per joint angle."""

SAMPLES_PER_SPAN = 8
"""Sample intervals per span, so that every knot is a sample. Measured on SCalf's RF leg: the
optima of 16 to 128 spans at 8 per span agree with their energies at ten times the rate within
0.3 % and cross no limit between samples; at 4 per span the energy was 0.9 % off."""

LEVEL_OPTIONS: dict[str, Any] = {"max_soc": 0}
"""Ipopt's options on every level, cold or warm: no second-order corrections of a step.

On an optimum that rides a limit (ANYmal C's RF hip at its 80 N m effort limit) Ipopt's filter
took steps corrected to second order that raised the energy by half, again and again, while the
constraint violation sat at round-off (1e-11, where any decrease of it admits a step): the
32-span level of ANYmal C's RF, started from the 16-span optimum the paper's seeds lead to,
ran out of iterations under every strategy (1000, 1000 and 3000; 67 s) and the bound stopped at
16 spans, not converged. Without the corrections that level converged in 40 iterations
(0.3 s). Measured on the six robots' bounds of both legs with the paper's seeds (the bound of
``scalf-opt paper``): SCalf's and HyQ's levels the same to the last digit (no step there needed
a correction), the four electric robots' bounds each converged, in 0.8 to 1.8 s instead of 2.3
to 67 s (their first levels, solved cold from three starts, 0.4 to 0.7 s instead of 0.6 to
18 s), their energies within 0.2 % of the old ones where those converged, above or below. Only
on the bound: on the families' NLPs the same option moved SCalf's ``joint-12`` optimum of RF
1.7 % higher."""

WARM_START_OPTIONS: dict[str, Any] = {
    **LEVEL_OPTIONS,
    "mu_strategy": "monotone",
    "mu_init": 1e-5,
    "warm_start_init_point": "yes",
    "warm_start_bound_push": 1e-9,
    "warm_start_slack_bound_push": 1e-9,
    "warm_start_mult_bound_push": 1e-9,
    "acceptable_iter": 3,
    "acceptable_obj_change_tol": 1e-9,
    # MUMPS without its scaling and its weighted-matching permutation: see below
    "mumps_scaling": 0,
    "mumps_permuting_scaling": 0,
}
"""Ipopt's options on a level after the first, which starts at the previous level's optimum (an
exact member of the finer family): a small, monotone barrier parameter and the start kept close
to its active bounds, instead of Ipopt's default of pushing it back into the interior. Measured
on SCalf's RF leg, 128 spans from the 64-span optimum: 92 iterations and 4.3 s of CPU instead of
139 and 8.1 s, and a lower optimum (11.293 J instead of 11.300 J).

The finest levels end "solved to an acceptable level": the constraint violation stalls at
round-off (1e-9 on accelerations of 1e4 rad/s^2) above the 1e-10 asked, and Ipopt waited 15
such iterations (its default) with the energy unchanged to 1e-9 J. Three, with the energy's
change below 1e-9 relative: 256 spans from the 128-span optimum in 72 iterations instead of 84,
the same optimum to the printed 1e-6 J. Warm starting the multipliers too (the coarser level's,
interpolated in time and halved with the weights) saved 7 more and was left out.

MUMPS factorizes these warm levels' KKT systems unscaled and without the weighted-matching
permutation it computes for every factorization (Ipopt's ``mumps_scaling`` 77 and
``mumps_permuting_scaling`` 7 by default): a warm level starts at a solution and its systems are
well scaled already. Measured (the six robots' bounds of both legs, one process, the same hour):
SCalf's RF in 4.9 s instead of 5.5 s and LH in 4.3 s instead of 4.8 s, every level's energy the
same to the printed digit; the other robots' bounds the same levels and energies within 0.01 %
(ANYmal C's RF and Solo12's RF took other round-off paths to the same bound), 16.7 s for all
twelve instead of 18.1 s; on ten bounds at other gaits the same, except SCalf's RF at T 0.45 s and
S 0.3 m, 0.23 % higher (another local optimum at 128 spans; both at 256 spans, converged).
Without the scaling alone (the permutation kept) it saved nothing; an
earlier round of the bound without a revisit had taken 145 iterations instead of 73 at 256
spans without the scaling: the levels' paths depend on round-off."""

REVISIT_OPTIONS: dict[str, Any] = {**WARM_START_OPTIONS, "mu_init": 1e-4}
"""Ipopt's options on a revisit (:data:`REVISIT_WITHIN`): those of a warm level with a larger first
barrier parameter. A revisit starts from the finer optimum's closest member, near a minimum of
its own level, while a forward level starts from a coarser optimum that it must leave. Measured
on SCalf's 64-span level started from the 128-span optimum: RF in 83 iterations instead of 122
(1.1 s instead of 1.6 s), LH in 83 instead of 96, the same optima; over the six robots' bounds
every level the same energy. On the forward levels the same barrier parameter took another
round-off path: SCalf's bounds then needed 256 spans (14 s and 12 s)."""

SLOWEST_RATIO = 0.5
"""The least ratio of successive savings the remainder estimate assumes (first order)."""

BOUND_TOLERANCE = 0.01
"""The bound has converged when the energy still to be gained by refining is estimated below
this fraction of it (1 %)."""

REVISIT_WITHIN = 2.0
"""A level whose estimate is above the tolerance but within this multiple of it solves the
coarser level again, from the closest member of its own optimum, before refining further.

The estimate is as good as the levels' energies, and a level's optimum is only the local one
its start leads to: on SCalf, the 64-span level's optimum from the 32-span one was 11.4158 J
for RF with the paper's seeds and 11.3925 J without, and 11.1521 J and 11.1306 J for LH, the
other way round. The higher one left the estimate at 1.1 % and cost a 256-span level (7 s);
started from the 128-span optimum, the 64-span level found the lower one on both paths (2 s),
and both bounds converged at 128 spans (0.9 %). A level's optima differ by a few tenths of a
per cent, so an estimate above twice the tolerance is not revisited."""


@dataclass(frozen=True)
class BoundLevel:
    """One refinement level of the bound for one leg."""

    spans: int
    swing_energy_j: float
    check_energy_j: float
    sample_rate_hz: float
    status: str
    success: bool
    wall_time_s: float
    revisited: bool = False
    """Solved again from the finer level's optimum (its energy the lower of the two)."""


@dataclass(frozen=True)
class FreeBound:
    """The free-trajectory bound of one leg.

    Attributes:
        leg: Leg name.
        family: The finest B-spline family used.
        result: That level's optimization of this leg.
        levels: Every level, coarse to fine.
        converged: The energy still to be gained is estimated below the tolerance.
        remaining_j: That estimate [J] (``inf`` before three levels).
    """

    leg: str
    family: SwingFamily
    result: LegResult
    levels: list[BoundLevel] = field(default_factory=list)
    converged: bool = False
    remaining_j: float = float("inf")

    @property
    def spans(self) -> int:
        """Spans of the level the bound comes from."""
        assert isinstance(self.family, BSplineFamily)
        return self.family.spans

    @property
    def sample_rate_hz(self) -> float:
        """The rate of the level the bound comes from [Hz]."""
        return next(lv.sample_rate_hz for lv in self.levels if lv.spans == self.spans)

    @property
    def swing_energy_j(self) -> float:
        """The bound at its optimization's rate [J]."""
        return self.result.best.swing_energy_j

    @property
    def check_energy_j(self) -> float:
        """The bound at ten times its rate [J]: the converged energy gaps are measured with."""
        return self.result.check_energy_j

    @property
    def success(self) -> bool:
        """A level solved and the refinement converged."""
        return self.converged and self.result.success

    @property
    def remaining_percent(self) -> float:
        """The estimated energy still to gain, as a share of the bound [%] (inf if unknown)."""
        return 100.0 * self.remaining_j / self.check_energy_j

    def status_text(self) -> str:
        """``bspline-128, converged: ~0.8 % left`` or why it is not converged."""
        left = (
            f"~{self.remaining_percent:.1f} % left"
            if math.isfinite(self.remaining_percent)
            else "what is left unknown"
        )
        failed = [lv for lv in self.levels if not lv.success]
        if not self.result.success:
            return f"no level solved ({self.levels[0].status})"
        if self.converged:
            return f"{self.family.name}, converged: {left}"
        if failed:
            return (
                f"{self.family.name}, not converged: {left}; the {failed[0].spans}-span level "
                f"failed ({failed[0].status})"
            )
        return f"{self.family.name}, not converged by {self.spans} spans: {left}"

    def gap_percent(self, check_energy_j: float) -> float:
        """How far above the bound a swing with this converged energy is [%]."""
        return 100.0 * (check_energy_j / self.check_energy_j - 1.0)


def bound_for(
    pipeline: EnergyPipeline,
    leg: str,
    seeds: list[tuple[SwingFamily, np.ndarray]] | None = None,
    tolerance: float = BOUND_TOLERANCE,
    spans: tuple[int, ...] = SPANS,
    progress: Callable[[str], None] | None = None,
    margins: LimitMargins = DEFAULT_MARGINS,
) -> FreeBound:
    """The free-trajectory bound of ``leg``, its first level started from each seed swing.

    Args:
        pipeline: Robot, gait, accounting.
        leg: The leg.
        seeds: Swings ``(family, theta)`` to start from besides the reference (e.g. the
            optima of the families being compared).
        tolerance: Energy still to gain, relative, that counts as converged.
        spans: The refinement levels.
        progress: Called with a label as each level starts.
        margins: How far inside the joint range and the cylinder stroke the swing stays.
    """
    # the bound is on the swing energy alone, which the stance loads do not change (no foot
    # force in swing): the swing problem without a stance term is exactly that
    pipeline = pipeline.with_loads(PAPER_LOADS)
    pipeline.stance(leg)  # an impossible stance is the gait's error: once, at the gait's rate
    levels: list[BoundLevel] = []
    previous: tuple[SwingFamily, np.ndarray] | None = None
    result: tuple[SwingFamily, LegResult] | None = None
    converged = False
    for count in spans:
        family = BSplineFamily(count)
        start = time.perf_counter()
        raise_if_stopped()
        if progress is not None:
            progress(f"{leg}: free-trajectory bound, {count} spans")
        level = Transcription(level_rate_hz(pipeline.gait, count)).on(pipeline)
        if previous is None:
            candidates = _seed_starts(level, leg, family, seeds or [])
        else:
            candidates = [_projection(level, leg, family, *previous)]
        best: LegResult | None = None
        rate = 0.0
        for theta0 in candidates:
            leg_result, run_rate = _solve_level(
                level, leg, family, theta0, previous is not None, margins
            )
            if best is None or (
                leg_result.success
                and (not best.success or leg_result.best.swing_energy_j < best.best.swing_energy_j)
            ):
                best, rate = leg_result, run_rate
        assert best is not None
        levels.append(_level_record(count, best, rate, time.perf_counter() - start))
        if not best.success:  # the finest solved level stays the bound; not converged
            break
        result, previous = (family, best), (family, best.best.theta)
        remaining = remaining_estimate([lv.check_energy_j for lv in levels])
        limit = tolerance * best.check_energy_j
        if limit < remaining <= REVISIT_WITHIN * limit:
            levels[-2] = _revisit(pipeline, leg, levels[-2], family, best.best.theta, margins)
            remaining = remaining_estimate([lv.check_energy_j for lv in levels])
        if remaining <= limit:
            converged = True
            break
    solved = [lv.check_energy_j for lv in levels if lv.success]
    if result is None:  # even the coarsest level failed: report it
        assert best is not None
        return FreeBound(leg, BSplineFamily(spans[0]), best, levels, False)
    return FreeBound(leg, result[0], result[1], levels, converged, remaining_estimate(solved))


def _level_record(
    spans: int, found: LegResult, rate_hz: float, wall_time_s: float, revisited: bool = False
) -> BoundLevel:
    """The record of a level solved to ``found`` at ``rate_hz``."""
    return BoundLevel(
        spans,
        found.best.swing_energy_j,
        found.check_energy_j,
        rate_hz,
        found.best.status,
        found.success,
        wall_time_s,
        revisited,
    )


def _solve_level(
    level: EnergyPipeline,
    leg: str,
    family: BSplineFamily,
    theta0: np.ndarray,
    warm: bool,
    margins: LimitMargins,
    warm_options: dict[str, Any] = WARM_START_OPTIONS,
) -> tuple[LegResult, float]:
    """One level's optimum from ``theta0``, and the rate it converged at [Hz].

    ``warm``: ``theta0`` is another level's optimum, carried over: Ipopt starts with
    ``warm_options`` (:data:`WARM_START_OPTIONS`, or :data:`REVISIT_OPTIONS` on a revisit) and
    the rows far from their bounds left out; a warm start that fails (Go1's RF at 64 spans ran
    out of iterations before the constraint screening) is tried again with Ipopt's own start and
    every retry strategy of the solver, with every row. Every solve has :data:`LEVEL_OPTIONS`.
    """
    for ipopt in [warm_options, LEVEL_OPTIONS] if warm else [LEVEL_OPTIONS]:
        screen = ipopt is warm_options
        settings = Settings(ipopt=ipopt, margins=margins, screen=screen)
        run = optimize_swings(level, (leg,), family, settings, {leg: theta0}, stance_checked=True)
        if run.legs[leg].success:
            break
    return run.legs[leg], run.rate_hz


def _revisit(
    pipeline: EnergyPipeline,
    leg: str,
    coarse: BoundLevel,
    fine_family: BSplineFamily,
    fine_theta: np.ndarray,
    margins: LimitMargins,
) -> BoundLevel:
    """``coarse`` solved again from the finer level's optimum; the lower of the two optima.

    The level's minimum the remainder estimate needs is better known from the finer optimum's
    closest member than from the coarser start it was reached from (:data:`REVISIT_WITHIN`).
    """
    start = time.perf_counter()
    family = BSplineFamily(coarse.spans)
    level = Transcription(coarse.sample_rate_hz).on(pipeline)
    theta0 = _projection(level, leg, family, fine_family, fine_theta)
    found, rate = _solve_level(level, leg, family, theta0, True, margins, REVISIT_OPTIONS)
    spent = coarse.wall_time_s + time.perf_counter() - start
    if not found.success or found.check_energy_j >= coarse.check_energy_j:
        return replace(coarse, wall_time_s=spent, revisited=True)
    return _level_record(coarse.spans, found, rate, spent, revisited=True)


def bounds_for(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    seeds: Mapping[str, list[tuple[SwingFamily, np.ndarray]]] | None = None,
    progress: Callable[[str], None] | None = None,
    processes: int | None = None,
    spans: tuple[int, ...] = SPANS,
    margins: LimitMargins = DEFAULT_MARGINS,
) -> dict[str, FreeBound]:
    """The bound of each leg (:func:`bound_for`), the legs in parallel worker processes.

    The legs' solves are independent and their time is Ipopt's linear solver, which runs one
    factorization at a time per process (:mod:`scalf_opt.workers`): on two threads SCalf's two
    legs took 34 s, in two processes 20 s. The answers are bitwise those of one leg after the
    other; Ctrl-C or SIGTERM ends the workers.

    Args:
        pipeline: Robot, gait, accounting.
        legs: The legs.
        seeds: Per leg, the swings to start the first level from besides the reference.
        progress: Called with a label as each level of each leg starts.
        processes: Worker processes; default one per core, at most one per leg (1: in this
            process).
        spans: The refinement levels.
        margins: How far inside the joint range and the cylinder stroke the swings stay.
    """
    workers = (os.cpu_count() or 1) if processes is None else processes
    jobs = bound_jobs(pipeline, legs, seeds, spans, margins)
    found = map_in_processes(leg_bound, jobs, workers, progress)
    return dict(zip(legs, found, strict=True))


BoundJob = tuple[
    EnergyPipeline, str, list[tuple[SwingFamily, np.ndarray]] | None, tuple[int, ...], LimitMargins
]
"""One leg's bound as work for a worker process (:func:`leg_bound`): it pickles."""


def bound_jobs(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    seeds: Mapping[str, list[tuple[SwingFamily, np.ndarray]]] | None = None,
    spans: tuple[int, ...] = SPANS,
    margins: LimitMargins = DEFAULT_MARGINS,
) -> list[BoundJob]:
    """Each leg's bound as work for :func:`leg_bound` (arguments as :func:`bounds_for`'s)."""
    return [(pipeline, leg, (seeds or {}).get(leg), spans, margins) for leg in legs]


def leg_bound(job: BoundJob) -> FreeBound:
    """One leg's bound, in a worker process (its levels' labels to the worker's progress)."""
    pipeline, leg, seeds, spans, margins = job
    return bound_for(pipeline, leg, seeds, spans=spans, progress=worker_progress, margins=margins)


def level_rate_hz(gait: Gait, spans: int) -> float:
    """The rate that puts :data:`SAMPLES_PER_SPAN` sample intervals in every span [Hz].

    At least the gait's own rate, in whole multiples of the knot-aligned rate (the gait rounds
    a phase's intervals to ``round(T_sw rate)``, a multiple of ``spans`` here).
    """
    aligned = spans * SAMPLES_PER_SPAN / gait.swing_duration_s
    return aligned * max(1, math.ceil(gait.sample_rate_hz / aligned))


def remaining_estimate(energies: list[float]) -> float:
    """Energy still to be gained by refining, from the last three levels' energies [J].

    With savings ``d_(k-1)`` and ``d_k`` between them, ratio ``r = max(d_k / d_(k-1),``
    :data:`SLOWEST_RATIO` ``)``, the rest of a geometric series is ``d_k r / (1 - r)``. ``inf``
    when the savings do not shrink (or the energy rose), ``nan``-free; ``inf`` with fewer than
    three levels.
    """
    if len(energies) < 3:
        return float("inf")
    d_prev = energies[-3] - energies[-2]
    d_last = energies[-2] - energies[-1]
    if d_last <= 0.0:  # no further saving: converged as far as refinement can tell
        return 0.0
    if d_prev <= 0.0 or d_last >= d_prev:
        return float("inf")
    ratio = max(d_last / d_prev, SLOWEST_RATIO)
    return d_last * ratio / (1.0 - ratio)


def _seed_starts(
    pipeline: EnergyPipeline,
    leg: str,
    family: SwingFamily,
    seeds: list[tuple[SwingFamily, np.ndarray]],
) -> list[np.ndarray]:
    problem = SwingGoal(family).on(pipeline, leg)
    out = [closest_member(problem, reference_path(problem))]
    out += [_projection(pipeline, leg, family, f, theta) for f, theta in seeds]
    return out


def _projection(
    pipeline: EnergyPipeline,
    leg: str,
    family: SwingFamily,
    source: SwingFamily,
    theta: np.ndarray,
) -> np.ndarray:
    """The member of ``family`` closest to ``source``'s member ``theta`` (joint space)."""
    problem = SwingGoal(family).on(pipeline, leg)
    path = pipeline.swing_path(leg, source).values(theta)
    if source.space == "foot":
        kin = pipeline.kinematics(leg)
        path = np.array(kin.joint_motion(path[0], path[1], path[2]))
    return closest_member(problem, path)


def bound_cycle_inputs(
    pipeline: EnergyPipeline, bounds: dict[str, FreeBound]
) -> tuple[EnergyPipeline, SwingFamily, dict[str, np.ndarray]]:
    """One pipeline, family and parameters per leg that reproduce every leg's bound swing.

    The legs may have converged at different levels and rates: the finest family holds every
    coarser one exactly (nested), so each leg's swing is carried over to it, and the cycle is
    sampled at the finest rate.
    """
    spans = max(b.spans for b in bounds.values())
    rate = max(b.sample_rate_hz for b in bounds.values())
    at_rate = Transcription(rate).on(pipeline)
    family = BSplineFamily(spans)
    thetas = {
        leg: _projection(at_rate, leg, family, b.family, b.result.best.theta)
        for leg, b in bounds.items()
    }
    return at_rate, family, thetas
