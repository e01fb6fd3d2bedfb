"""Beyond the paper: optimize the stance together with the swing.

With the trunk at constant height the stance foot path is fixed by two choices the paper made by
hand: the stance height ``z0`` (pitching hip above the ground) and where the foot stands
relative to the hip at mid-stance (the stance x-offset). The stance is 59 % of SCalf's energy.
Here ``z0`` (one for the trunk) and the x-offsets (one per leg pair: front, hind) are decision
variables too:

    minimize over (z0, d_front, d_hind):  sum over RF, LH of
        E_stance(z0, d) + min over theta E_swing(theta; z0, d)

The inner minimization is the swing optimization of :func:`~scalf_opt.optimize.driver
.optimize_swings` at that stance (same family, method and options; warm-started from the last
optimum); the outer one is the paper's pattern search (:mod:`scalf_opt.optimize.pattern_search`)
over the three stance numbers in centimetres, from the gait's stance, initial step
:data:`STANCE_STEP_CM`, precision :data:`STANCE_PRECISION_CM`. The minimum over the pair is the
minimum over the robot, because LF and RH repeat RF and LH; where the robot's sides differ (a
trunk off its midplane loads one side's feet more) the sum is half the robot's energy, all four
legs (:func:`pair_energy_j`). A stance is feasible when its path stays inside the reach and the
joint range and every sample of every leg respects the leg's limits (URDF velocity and effort,
the cylinders' stroke, force and speed); the swing keeps its constraints (ground, clearance H at
mid-swing, limits) at the new height.

Under whole-body loads the stance energy depends on the swings (the stance feet carry the
swinging legs): a stance's total is the cycle energy with its optimized swings
(:func:`pair_energy_j`), and its stance limits are checked with those swings too.

The report splits the saving against the paper's stance with the reference swing into the part
of the stance energy and the part of the swing energy.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.limits import leg_bounds, violations
from scalf_opt.energy.margins import LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ScalfError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.locomotion.trot import SYMMETRIC_TWIN
from scalf_opt.optimize.driver import (
    Settings,
    SwingOptimization,
    legs_coupled,
    optimize_swings,
)
from scalf_opt.optimize.pattern_search import PatternSearchOptions, pattern_search
from scalf_opt.optimize.sampling import Transcription
from scalf_opt.types import FIRST_PAIR

STANCE_STEP_CM = 2.0
"""Initial step of the stance search in each variable [cm]."""

STANCE_PRECISION_CM = 0.1
"""The stance search stops when every step is below this [cm] (1 mm)."""

STANCE_VARIABLES = ("stance_height_m", "stance_x_offset_front_m", "stance_x_offset_hind_m")
"""The gait fields the stance search changes, in the order of its variables."""


def stance_gait(gait: Gait, x_cm: np.ndarray) -> Gait:
    """``gait`` with the stance numbers ``(z0, d_front, d_hind)`` given in centimetres."""
    z0, front, hind = (float(v) * 0.01 for v in x_cm)
    return replace(
        gait, stance_height_m=z0, stance_x_offset_front_m=front, stance_x_offset_hind_m=hind
    )


def stance_vector_cm(gait: Gait) -> np.ndarray:
    """The stance numbers of ``gait`` in centimetres."""
    return np.array([100.0 * getattr(gait, name) for name in STANCE_VARIABLES])


@dataclass(frozen=True)
class StanceEvaluation:
    """One stance tried by the search.

    Attributes:
        gait: The gait with that stance.
        total_j: Energy of RF and LH over a cycle, stance and optimized swing, at the
            optimization's rate [J]: half the robot's where its sides differ
            (:func:`pair_energy_j`; inf if infeasible).
        reason: Why it is infeasible, else ``None``.
        run: The swing optimization at that stance (``None`` if the stance itself failed).
    """

    gait: Gait
    total_j: float
    reason: str | None
    run: SwingOptimization | None = None


@dataclass(frozen=True)
class FreeStance:
    """The stance and swing optimized together.

    Attributes:
        nominal: The gait's own stance with the optimized swing (the plain ``optimize``).
        best: The best stance found, with its optimized swing.
        reference: Robot cycle: the gait's stance, the reference swing.
        evaluations: Stances tried.
        iterations: Pattern-search iterations.
        converged: The search's steps fell below the precision.
        history: Accepted points: (iteration, z0, d_front, d_hind [cm], total [J]).
        wall_time_s: Time spent [s].
    """

    nominal: StanceEvaluation
    best: StanceEvaluation
    reference: RobotCycle
    evaluations: int = 0
    iterations: int = 0
    converged: bool = False
    history: list[tuple[float, ...]] = field(default_factory=list)
    wall_time_s: float = 0.0

    @property
    def success(self) -> bool:
        """The search converged to a feasible stance whose swings are solved."""
        return self.converged and self.best.run is not None and self.best.run.success

    def cycle(self) -> RobotCycle:
        """The robot's cycle with the best stance and its optimized swings (evaluated once)."""
        assert self.best.run is not None
        return self.best.run.cycle()

    def nominal_cycle(self) -> RobotCycle:
        """The robot's cycle with the gait's stance and the optimized swings (evaluated once)."""
        assert self.nominal.run is not None
        return self.nominal.run.cycle()

    def split_j(self) -> dict[str, float]:
        """The saving against the reference, split into its stance and swing parts [J/cycle].

        Keys: ``total``, ``stance``, ``swing`` (against the reference: the gait's stance and
        the reference swing), and ``swing_only`` and ``from_freeing_the_stance`` (the plain
        swing optimization's saving, and what freeing the stance adds to it).
        """
        ref, best, nominal = self.reference, self.cycle(), self.nominal_cycle()

        def phase_sum(cycle: RobotCycle, phase: str) -> float:
            return sum(getattr(leg, f"{phase}_energy_j") for leg in cycle.legs.values())

        return {
            "total": ref.energy_j - best.energy_j,
            "stance": phase_sum(ref, "stance") - phase_sum(best, "stance"),
            "swing": phase_sum(ref, "swing") - phase_sum(best, "swing"),
            "swing_only": ref.energy_j - nominal.energy_j,
            "from_freeing_the_stance": nominal.energy_j - best.energy_j,
        }


def _stance_feasible(
    pipeline: EnergyPipeline, legs: tuple[str, ...], margins: LimitMargins
) -> tuple[float, str | None]:
    """Stance energy of ``legs`` and their twins [J], or ``(inf, reason)`` at a broken limit.

    The joint range and the stroke count less their margins. The twins (LF and RH for RF and
    LH) stand on the same stance path, but where the robot's sides differ they carry other loads.
    """
    total = 0.0
    for leg in with_twins(legs):
        try:
            phase = pipeline.stance(leg)
        except ScalfError as exc:
            return math.inf, str(exc)
        beyond = violations(phase.values, margins.apply(leg_bounds(pipeline.physics(leg))))
        if beyond:
            b = beyond[0].bound
            return math.inf, f"stance of {leg}: {b.name} beyond its {b.source}"
        total += float(phase.energy_j.sum())
    return total, None


def pair_energy_j(
    pipeline: EnergyPipeline, family: SwingFamily, run: SwingOptimization, legs: tuple[str, ...]
) -> tuple[float, str | None]:
    """Half the energy of ``legs`` and their twins over a cycle with the run's swings [J].

    The cycle as every report evaluates it (the stance loads of ``pipeline``'s model, with these
    swings), of ``legs`` and the symmetric twins that repeat their swings half a cycle later,
    halved: the pair's energy (RF and LH) on a robot symmetric about its midplane, and half the
    robot's where its sides differ (HyQ's trunk 21.5 mm to the left loads its left feet more),
    as the swing's objective counts it (:func:`~scalf_opt.energy.coupling.stance_couplings`).
    ``(inf, reason)`` when a stance sample of any of them breaks a limit of its leg.
    """
    loaded = with_twins(legs)
    try:
        cycle = pipeline.robot_cycle(family, run.thetas, loaded)
    except ScalfError as exc:
        return math.inf, str(exc)
    for leg in loaded:
        beyond = violations(cycle.legs[leg].stance.values, leg_bounds(pipeline.physics(leg)))
        if beyond:
            b = beyond[0].bound
            return math.inf, f"stance of {leg}: {b.name} beyond its {b.source}"
    return cycle.energy_j / 2.0, None


def with_twins(legs: tuple[str, ...]) -> tuple[str, ...]:
    """``legs`` and, after them, each one's symmetric twin (LF for RF) not already among them."""
    twins = tuple(SYMMETRIC_TWIN[leg] for leg in legs)
    return legs + tuple(t for t in twins if t not in legs)


class GaitTrials:
    """Gaits a search tries: each one's stance checked, its swings optimized, each once.

    The swings of every new gait start from the last solved gait's optima (warm start): a
    search moves in small steps, and Ipopt from a neighbour's optimum takes a few iterations.
    Such a trial is solved by the solver's warm strategy alone (``optimize_swings``'
    ``trial``): a gait whose swings it does not solve is infeasible for the search, which moves
    on, rather than retried with every cold strategy (near a limit, minutes per gait).
    A gait is known by its fields; asking for it again returns the first answer. With
    ``keep_uncoupled`` (the free stance's trials), where the legs' problems are independent
    (trunk-only loads), a leg's swing problem is known by the fields it depends on, every one but
    the other pair's stance x-offset: a gait that moves only the hind feet keeps the front leg's
    optimum of the gait it was found at and solves the hind leg alone (:meth:`swings`; SCalf's
    free stance under trunk loads: 10 s instead of 12.5 s). The gait search does not keep them:
    a kept optimum is another warm start for the trials after it, and the local search another
    path (on Go1's six speeds under trunk loads, three cheaper trots and one 5.6 % dearer). With
    ``stance_at_swing_rate`` a gait's stance energy is taken at the rate its swings converged
    at (one cycle's samples: gaits of different timing refine differently); without it, at the
    trials' rate (the free stance's search, whose stances share one rate).
    """

    def __init__(
        self,
        pipeline: EnergyPipeline,
        family: SwingFamily,
        settings: Settings,
        legs: tuple[str, ...] = FIRST_PAIR,
        warm: SwingOptimization | None = None,
        stance_at_swing_rate: bool = False,
        keep_uncoupled: bool = False,
    ) -> None:
        self.pipeline = pipeline
        self.family = family
        self.settings = settings
        self.legs = legs
        self.warm: dict[str, np.ndarray] = dict(warm.thetas) if warm is not None else {}
        self.seen: dict[tuple[float, ...], StanceEvaluation] = {}
        self.stance_at_swing_rate = stance_at_swing_rate
        self.keep_uncoupled = keep_uncoupled
        self.leg_runs: dict[tuple[object, ...], SwingOptimization] = {}

    @staticmethod
    def key(gait: Gait) -> tuple[float, ...]:
        """What tells two gaits apart (every field, to 1e-12)."""
        return tuple(round(float(v), 12) for v in gait.to_dict().values())

    @staticmethod
    def leg_key(gait: Gait, leg: str) -> tuple[object, ...]:
        """What tells two of ``leg``'s uncoupled swing problems apart.

        Every field of the gait (to 1e-12) but the other pair's stance x-offset.
        """
        own = round(gait.stance_x_offset_m(leg), 12)
        rest = replace(gait, stance_x_offset_front_m=0.0, stance_x_offset_hind_m=0.0)
        return (leg, own, *GaitTrials.key(rest))

    def swings(self, trial: EnergyPipeline) -> SwingOptimization:
        """The legs' swings optimized at ``trial``'s gait, warm from the last solved gait.

        With ``keep_uncoupled``, uncoupled legs whose problem an earlier gait posed already keep
        that optimum; the others are solved. Should they converge at another rate than the kept
        ones (the sampling refinement), every leg is solved at this gait, so that one rate holds.
        """
        legs, warm = self.legs, self.warm or None
        if not self.keep_uncoupled or legs_coupled(trial, legs):
            return optimize_swings(trial, legs, self.family, self.settings, warm, trial=True)
        keys = {leg: self.leg_key(trial.gait, leg) for leg in legs}
        kept = {leg: self.leg_runs[keys[leg]] for leg in legs if keys[leg] in self.leg_runs}
        todo = tuple(leg for leg in legs if leg not in kept)
        if not todo:
            first = next(iter(kept.values()))
            at_rate = Transcription(first.rate_hz).on(trial)
            run = replace(first, pipeline=at_rate, legs={}, wall_time_s=0.0)
        else:
            run = optimize_swings(trial, todo, self.family, self.settings, warm, trial=True)
            if any(k.rates_hz != run.rates_hz for k in kept.values()):
                kept, todo = {}, legs
                run = optimize_swings(trial, legs, self.family, self.settings, warm, trial=True)
            for leg in todo:
                self.leg_runs[keys[leg]] = run
        return replace(
            run,
            legs={leg: kept[leg].legs[leg] if leg in kept else run.legs[leg] for leg in legs},
            converged_sampling=all(r.converged_sampling for r in (run, *kept.values())),
        )

    def from_every_start(self, evaluation: StanceEvaluation) -> StanceEvaluation:
        """The search's answer with its swings optimized again from every start asked for.

        A trial solves its swings once, warm (no extra start of ``settings.starts``); the gait
        a search settles on is optimized again with them, its trial's optimum the first start
        (cold strategies, every row), so that the answer records every start and keeps the
        best. Without extra starts, for an infeasible gait, or should that optimization fail
        or break a stance limit, ``evaluation`` itself.
        """
        if self.settings.starts == 1 or evaluation.run is None or evaluation.reason is not None:
            return evaluation
        pipeline = self.pipeline.with_gait(evaluation.gait)
        settings = replace(self.settings, screen=False)
        try:
            run = optimize_swings(pipeline, self.legs, self.family, settings, evaluation.run.thetas)
        except ScalfError:
            return evaluation
        if not run.success:
            return evaluation
        total, why = self.total_j(pipeline, run)
        if why is not None:
            return evaluation
        return StanceEvaluation(evaluation.gait, total, None, run)

    def total_j(self, trial: EnergyPipeline, run: SwingOptimization) -> tuple[float, str | None]:
        """The legs' cycle energy at ``trial``'s gait with the run's swings [J], or why not.

        At the rate the swings converged at with ``stance_at_swing_rate``, else at the trials'
        (:func:`pair_energy_j`).
        """
        evaluated = run.pipeline if self.stance_at_swing_rate else trial
        return pair_energy_j(evaluated, self.family, run, self.legs)

    def remember(self, evaluation: StanceEvaluation) -> None:
        """Record an evaluation made elsewhere (the nominal gait's)."""
        self.seen[self.key(evaluation.gait)] = evaluation

    def evaluate(self, gait: Gait) -> StanceEvaluation:
        """The gait's stance plus optimized swing energy of the legs, or why it is infeasible."""
        key = self.key(gait)
        if key in self.seen:
            return self.seen[key]
        trial = self.pipeline.with_gait(gait)
        _, why = _stance_feasible(trial, self.legs, self.settings.margins)
        if why is not None:
            self.seen[key] = StanceEvaluation(gait, math.inf, why)
            return self.seen[key]
        try:
            run = self.swings(trial)
        except ScalfError as exc:  # a swing the gait makes impossible (its path leaves the reach)
            self.seen[key] = StanceEvaluation(gait, math.inf, str(exc))
            return self.seen[key]
        if not run.success:
            why = f"swing not solved: {run.failure()}"
            self.seen[key] = StanceEvaluation(gait, math.inf, why, run)
            return self.seen[key]
        self.warm.update(run.thetas)
        total, why = self.total_j(trial, run)
        self.seen[key] = StanceEvaluation(gait, total, why, run)
        return self.seen[key]


def optimize_stance(
    pipeline: EnergyPipeline,
    family: SwingFamily,
    settings: Settings | None = None,
    legs: tuple[str, ...] = FIRST_PAIR,
) -> FreeStance:
    """Optimize the stance height and x-offsets together with the swings of ``legs``.

    Raises:
        ScalfError: The gait's own stance is impossible, or its swings cannot be optimized.
    """
    settings = settings or Settings()
    start = time.perf_counter()
    nominal_run = optimize_swings(pipeline, legs, family, settings)
    # the whole search at the rate the nominal optimization converged at, so that every stance
    # is compared on the same grid (a stance that needs a finer one is refined by the driver)
    at_rate = Transcription(nominal_run.rate_hz).on(pipeline)
    _, reason = _stance_feasible(at_rate, legs, settings.margins)
    if reason is not None:
        raise ScalfError(reason)
    nominal_total, reason = pair_energy_j(at_rate, family, nominal_run, legs)
    if reason is not None:
        raise ScalfError(reason)
    nominal = StanceEvaluation(at_rate.gait, nominal_total, None, nominal_run)
    # a trial starts at a neighbouring stance's optimum: its NLP leaves out the rows far from
    # their bounds there (screening: the same stance, faster; docs/speed-log.md has the
    # measurement)
    trials = GaitTrials(
        at_rate, family, replace(settings, screen=True), legs, nominal_run, keep_uncoupled=True
    )

    def evaluate(x_cm: np.ndarray) -> StanceEvaluation:
        try:
            gait = stance_gait(at_rate.gait, x_cm)
        except ScalfError as exc:
            return StanceEvaluation(at_rate.gait, math.inf, str(exc))
        return trials.evaluate(gait)

    x0 = stance_vector_cm(at_rate.gait)
    trials.remember(nominal)
    result = pattern_search(
        lambda x: (evaluate(x).total_j, evaluate(x).reason),
        x0,
        PatternSearchOptions(initial_step=STANCE_STEP_CM, precision=STANCE_PRECISION_CM),
    )
    best = trials.from_every_start(evaluate(result.x))
    # every cycle the report compares, at the rate of the best stance's swings
    final = best.run.rate_hz if best.run is not None else nominal_run.rate_hz
    at_final = Transcription(final).on(pipeline)
    if final != nominal_run.rate_hz:
        thetas = {leg: r.best.theta for leg, r in nominal_run.legs.items()}
        nominal_run = replace(nominal_run, pipeline=at_final)
        nominal = StanceEvaluation(
            at_final.gait,
            at_final.robot_cycle(family, thetas, legs).energy_j,
            None,
            nominal_run,
        )
    return FreeStance(
        nominal=nominal,
        best=best,
        reference=at_final.robot_cycle(make_family("reference")),
        evaluations=result.evaluations,
        iterations=result.iterations,
        converged=result.converged,
        history=list(result.history),
        wall_time_s=time.perf_counter() - start,
    )
