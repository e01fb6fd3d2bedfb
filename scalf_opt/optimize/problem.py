"""The swing-optimization problem of one leg, shared by the pattern search and the NLP.

Decision variables: the swing family's free parameters ``theta`` (degrees or centimetres, see
:mod:`scalf_opt.locomotion.swing`). Objective: the leg's swing energy [J], the trapezoidal
integral of the exact charged power over the swing samples; under a load model that couples
the legs (whole-body loads) plus the stance energy of the leg's diagonal pair, which the swing
changes through the loads its symmetric twin puts on the stance feet
(:mod:`scalf_opt.energy.coupling`): with the other optimized legs' parameters fixed, this is
the pair's energy over a cycle (half the robot's) up to a constant. On a robot whose sides
differ (a trunk off its midplane) the other pair's stance, which the leg's own swing loads,
counts too, each stance at half weight: half the robot's energy, up to a constant. Under trunk
loads the stance energy does not depend on the swing and the objective is the swing energy
alone.
Constraints at every swing sample (decision 14 and the actuators' limits): every bound
of the leg (:func:`~scalf_opt.energy.limits.leg_bounds`: the joint range, the URDF's velocity
and effort limits, the drives' bounds such as SCalf's cylinder stroke, force and speed), the
foot on or above its lift profile at every interior sample and at least H above the ground at
mid-swing, coming down no faster than the touch-down speed over the landing, the foot leaving
and meeting the ground from above (vertical acceleration >= 0 at lift-off and touch-down, where
the foot is on the ground at rest vertically: without it the foot could dip below the ground
between the first samples), and in foot space the target inside the reach. The joint range,
the cylinder stroke and the effort and force limits (the swing's own, and the loaded stance
legs') keep the problem's margins, and the lift profile is the margins' too
(:class:`~scalf_opt.energy.limits.LimitMargins`, :mod:`scalf_opt.optimize.constraints`).

The samples are the pipeline's gait's swing grid: the caller chooses the rate
(:mod:`scalf_opt.optimize.sampling`). The per-sample physics is the leg's kernel
(:mod:`scalf_opt.optimize.kernels`), the same functions for the exact energy and the NLP.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from scalf_opt.energy.coupling import StanceCoupling, stance_couplings, stances_energy_j
from scalf_opt.energy.limits import Bound
from scalf_opt.energy.margins import DEFAULT_MARGINS, LimitMargins
from scalf_opt.energy.physics import LegPhysics, trapezoid_weights
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.swing.family import AffinePath, SwingFamily
from scalf_opt.locomotion.trot import SYMMETRIC_TWIN
from scalf_opt.optimize.constraints import (
    FEASIBILITY_TOLERANCE,
    ConstraintFamily,
    GroundClearance,
    LandingSpeed,
    LeavesFromAbove,
    LimitRows,
    Reach,
    SwingGrid,
)
from scalf_opt.optimize.kernels import (
    FOOT_Z,
    FOOT_Z_ACCEL,
    FOOT_Z_VEL,
    REACH,
    Kernel,
    kernel_for,
    stance_limit_function,
    stance_limited_bounds,
)

STANCE_LIMIT_RTOL = 1e-6
"""A loaded stance leg's torque or force may cross its limit by this share of the limit before
a member counts as infeasible (Ipopt holds those rows to its 1e-4 absolute tolerance: 5e-8 of
SCalf's 14 kN cylinder force)."""


@dataclass(frozen=True)
class Evaluation:
    """Exact evaluation of one parameter vector.

    Attributes:
        energy_j: The objective [J] (exact, non-smooth): the swing energy of both joints, plus
            the pair's stance energy under whole-body loads; inf if infeasible.
        reason: ``None`` if feasible, else which constraint fails first.
        violation: Sum of every constraint's excess over its bound beyond the tolerance (SI
            units of each constraint, bounds relative to their size); zero exactly when the
            point is feasible.
    """

    energy_j: float
    reason: str | None
    violation: float = 0.0


@dataclass
class SwingProblem:
    """One leg's swing optimization over one family.

    Attributes:
        pipeline: The robot's energy pipeline (robot, gait and its sample rate, accounting).
        leg: Leg name.
        family: Swing family.
        others: Parameters of the other legs optimized with this one (family units): fixed
            here, they set the loads under whole-body loads (``None``: no other leg, the
            rule of :meth:`~scalf_opt.energy.pipeline.EnergyPipeline.swings`).
        margins: How far inside the joint range and the stroke the swing stays.
        stance_term: Whether the objective holds the pair's stance energy under whole-body
            loads (``False``: the leg's own swing alone, the part of a :class:`PairProblem`
            that owns the stance term).
    """

    pipeline: EnergyPipeline
    leg: str
    family: SwingFamily
    others: Mapping[str, np.ndarray] | None = None
    margins: LimitMargins = DEFAULT_MARGINS
    stance_term: bool = True

    def __post_init__(self) -> None:
        self.margins = self.margins.for_family(self.family.n_params)  # a small family: no lift

    @cached_property
    def couplings(self) -> tuple[StanceCoupling, ...]:
        """The stances this leg's swing loads, as functions of it (none under trunk loads).

        One window, the pair's stance, on a robot symmetric about its midplane; else both
        pairs' stances at half weight each (:func:`~scalf_opt.energy.coupling.stance_couplings`);
        when the leg's twin is among :attr:`others` (every leg optimized on its own), the
        stance the leg's own swing loads alone.
        """
        if not (self.stance_term and self.pipeline.load_model.couples_legs):
            return ()
        thetas = {**(self.others or {}), self.leg: np.zeros(self.n_params)}
        swings = self.pipeline.swings(self.family, thetas)
        twins_repeat = SYMMETRIC_TWIN[self.leg] not in thetas
        return stance_couplings(self.pipeline, (self.leg,), self.family, swings, twins_repeat)

    def stance_energy_j(self, theta: np.ndarray) -> float:
        """The part of the objective in the stances the swing loads [J] (0 under trunk loads)."""
        return stances_energy_j(self.couplings, self.pipeline, (theta,))

    def swing_energy_j(self, theta: np.ndarray) -> float:
        """Exact swing energy of a member [J], feasible or not (the leg's own swing only)."""
        return self._energy_j(self.outputs(theta))

    @cached_property
    def path(self) -> AffinePath:
        """The family's affine swing path for this leg."""
        return self.pipeline.swing_path(self.leg, self.family)

    @property
    def physics(self) -> LegPhysics:
        """The leg's physics."""
        return self.pipeline.physics(self.leg)

    @cached_property
    def kernel(self) -> Kernel:
        """The leg's per-sample functions in the family's space."""
        return kernel_for(self.physics, self.family.space)

    @cached_property
    def bounds(self) -> tuple[Bound, ...]:
        """The leg's bounds on per-sample quantities, the range and stroke less the margins."""
        return self.margins.apply(self.kernel.bounds)

    @property
    def n_params(self) -> int:
        """Number of free parameters."""
        return self.family.n_params

    @property
    def n_samples(self) -> int:
        """Number of swing samples."""
        return int(self.path.t_s.size)

    @cached_property
    def weights(self) -> np.ndarray:
        """Trapezoidal weights of the swing samples [s]."""
        return trapezoid_weights(self.path.t_s)

    @cached_property
    def samples_base(self) -> np.ndarray:
        """The path at theta = 0 as kernel inputs, shape (6, n): y, y', y'' (two rows each)."""
        return self.path.base.reshape(6, -1)

    def samples(self, theta: np.ndarray) -> np.ndarray:
        """Kernel inputs (6, n) of a family member."""
        if self.n_params == 0:
            return self.samples_base
        if self.path.sparse:
            return self.path.values(theta).reshape(6, -1)
        basis = self.path.basis.reshape(6, self.n_samples, self.n_params)
        return self.samples_base + basis @ np.asarray(theta, dtype=float)

    @property
    def mid_index(self) -> int:
        """Index of the mid-swing sample (the swing grid has an even number of intervals)."""
        return self.grid.mid_index

    @property
    def clearance_z_m(self) -> float:
        """Lowest foot height allowed at mid-swing, in the leg frame [m]: ground + H."""
        return self.grid.clearance_z_m

    @property
    def ground_z_m(self) -> float:
        """Ground height in the leg frame [m]."""
        return -self.pipeline.gait.stance_height_m

    @cached_property
    def grid(self) -> SwingGrid:
        """What the constraint families need of the swing's samples."""
        return SwingGrid.on(
            self.path.t_s, self.ground_z_m, self.pipeline.gait.clearance_m, self.margins.lift
        )

    @cached_property
    def constraints(self) -> tuple[ConstraintFamily, ...]:
        """The constraint family of each kernel row, in row order (:mod:`.constraints`)."""
        families: list[ConstraintFamily] = [LimitRows(b.name, b) for b in self.bounds]
        families += [
            GroundClearance(FOOT_Z),
            LandingSpeed(FOOT_Z_VEL),
            LeavesFromAbove(FOOT_Z_ACCEL),
        ]
        if REACH in self.kernel.rows:
            families.append(Reach(REACH))
        assert tuple(f.row for f in families) == self.kernel.rows
        return tuple(families)

    @cached_property
    def constraint_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds of the kernel's constraint rows at every sample, (m, n) each.

        ``-inf``/``inf`` where a row does not apply: the foot height at the two end samples
        (on the ground by construction), its acceleration at the interior samples.
        """
        pairs = [family.bounds(self.grid) for family in self.constraints]
        return np.array([lo for lo, _ in pairs]), np.array([hi for _, hi in pairs])

    @cached_property
    def input_rows(self) -> dict[int, int]:
        """Constraint rows that are kernel inputs themselves: row of ``c`` -> row of ``Y``.

        In joint space the joint angles and rates are the samples' own coordinates, so their
        bounds (joint range, URDF velocity limit) bound the NLP's lifted variables directly,
        which Ipopt handles more cheaply than constraints.
        """
        if self.family.space != "joint":
            return {}
        inputs = {"q": 0, "qd": 2}
        return {
            i: inputs[b.output] + int(b.row or 0)
            for i, b in enumerate(self.bounds)
            if b.output in inputs
        }

    @cached_property
    def constraint_mask(self) -> np.ndarray:
        """Which entries of the kernel's ``c`` (m, n) carry a bound.

        The pattern depends only on the kernel and the number of samples.
        """
        lower, upper = self.constraint_bounds
        return np.isfinite(lower) | np.isfinite(upper)

    @cached_property
    def constraint_index(self) -> np.ndarray:
        """Flat (column-major) indices of the entries of ``c`` that carry a bound."""
        return np.flatnonzero(self.constraint_mask.ravel(order="F"))

    @cached_property
    def input_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounds on the kernel inputs ``Y`` (6, n) from :attr:`input_rows` (else infinite)."""
        lower = np.full((6, self.n_samples), -np.inf)
        upper = np.full((6, self.n_samples), np.inf)
        c_lo, c_hi = self.constraint_bounds
        for row, y_row in self.input_rows.items():
            lower[y_row], upper[y_row] = c_lo[row], c_hi[row]
        return lower, upper

    @cached_property
    def constraint_tolerance(self) -> np.ndarray:
        """Round-off allowed per constraint row, (m, 1): bounds relative to their size."""
        return np.array([[family.tolerance()] for family in self.constraints])

    def outputs(self, theta: np.ndarray) -> dict[str, np.ndarray]:
        """Exact per-sample outputs of a member: ``power``, ``p_mech`` (2, n), ``c`` (m, n)."""
        out = self.kernel.evaluate_exact(self.pipeline.accounting, self.samples(theta))
        return {"power": out[0:2], "p_mech": out[2:4], "c": out[4:]}

    def _energy_j(self, outputs: dict[str, np.ndarray]) -> float:
        """The swing energy [J] of :meth:`outputs`: the trapezoidal integral of the power."""
        return float(np.sum(outputs["power"] @ self.weights))

    def energy_j(self, theta: np.ndarray) -> float:
        """Exact objective of a member [J], feasible or not."""
        return self._energy_j(self.outputs(theta)) + self.stance_energy_j(theta)

    def _stance_shares(self, theta: np.ndarray) -> list[tuple[str, np.ndarray]]:
        """Per limit of each loaded stance leg: its reason and its excess at every sample.

        The excesses as shares of the bound's size (0 inside; ``inf`` where not finite). Empty
        under trunk loads.
        """
        shares = []
        thetas = (np.asarray(theta, dtype=float),)
        loaded = [
            (term, tau)
            for coupling in self.couplings
            for term, tau in zip(
                coupling.terms, coupling.torques_nm(self.pipeline, thetas), strict=True
            )
        ]
        for term, tau in loaded:
            physics = self.pipeline.physics(term.leg)
            bounds = self.margins.apply(stance_limited_bounds(physics))
            if not bounds:
                continue
            fn = stance_limit_function(physics).map(tau.shape[1])
            values = np.array(fn(term.q, term.qd, tau)).reshape(len(bounds), -1)
            for b, row in zip(bounds, values, strict=True):
                if not np.all(np.isfinite(row)):
                    shares.append(
                        (f"stance of {term.leg}: non-finite {b.name}", np.array([np.inf]))
                    )
                    continue
                reason = f"stance of {term.leg}: {b.name} beyond its {b.source}"
                shares.append((reason, np.asarray(b.excess(row), dtype=float) / b.size))
        return shares

    def stance_excess(self, theta: np.ndarray) -> tuple[float, str | None]:
        """How far the loaded stance legs cross a torque or force limit, and which one.

        Under whole-body loads this leg's swing (through its twin) changes the torques of the
        pair's stance legs; their effort limits and torque-dependent drive limits (a cylinder's
        force) bind the swing as its own limits do. Returns the largest excess as a share of
        the bound's size (0 when inside, and always under trunk loads) and its reason.
        """
        worst, reason = 0.0, None
        for why, shares in self._stance_shares(theta):
            share = float(np.max(shares))
            if share > worst:
                worst, reason = share, why
                if math.isinf(share):
                    break
        return worst, reason

    def violation(self, theta: np.ndarray) -> float:
        """The total constraint violation of a member: 0 exactly when it is feasible.

        The sum of the rows' excesses beyond their round-off (each relative to its row's scale,
        as :meth:`evaluate` weighs them) and of the loaded stance legs' excesses beyond
        :data:`STANCE_LIMIT_RTOL` (shares of their bounds), over every sample; a motion that is
        not finite counts as :meth:`evaluate` counts it. What the pattern search's feasibility
        phase minimizes: every crossed limit counts at once, so a step that meets one limit
        while another stays crossed is progress (HyQ's reference swing under whole-body loads
        misses the clearance by 0.1 mm and crosses a stance cylinder's force limit by a fifth:
        judged by the first crossing alone, meeting the clearance looked like a step back).
        """
        rows, _, finite = self._row_violation(self.outputs(theta)["c"])
        if not finite:
            return rows
        stance = sum(
            float(np.sum(np.where(shares > STANCE_LIMIT_RTOL, shares, 0.0)))
            for _, shares in self._stance_shares(theta)
        )
        return rows + stance

    def energy_and_bound_excess(self, theta: np.ndarray) -> tuple[float, float]:
        """A member's exact objective [J] and how far it crosses its limits.

        The second value is the largest excess of any box bound of the leg (joint range,
        velocity, effort, drive limits) over the samples, as a share of the bound's size (the
        larger of its finite ends' magnitudes): 0 when every sample is inside, ``inf`` when the
        motion is not finite. The ground counts too: the foot's depth below the ground at an
        interior sample as a share of the clearance H (the lift profile and the clearance are the
        optimizer's own margins, met at its samples; between them the foot must not touch).
        """
        out = self.outputs(theta)
        energy = self._energy_j(out) + self.stance_energy_j(theta)
        k = len(self.bounds)
        c = out["c"][:k]
        foot_z = out["c"][self.kernel.row(FOOT_Z), 1:-1]
        if not (np.all(np.isfinite(c)) and np.all(np.isfinite(foot_z))):
            return energy, math.inf
        lower, upper = (b[:k] for b in self.constraint_bounds)
        excess = np.maximum(np.maximum(lower - c, c - upper), 0.0)
        share = excess / np.array([[b.size] for b in self.bounds])
        depth = max(float(np.max(self.ground_z_m - foot_z, initial=0.0)), 0.0)
        return energy, max(
            float(share.max(initial=0.0)),
            depth / self.pipeline.gait.clearance_m,
            self.stance_excess(theta)[0],
        )

    def evaluate(self, theta: np.ndarray) -> Evaluation:
        """Exact swing energy and feasibility of ``theta`` (family units)."""
        out = self.outputs(theta)
        violation, reason, _ = self._row_violation(out["c"])
        if reason is not None:
            return Evaluation(float("inf"), reason, violation)
        stance_share, stance_reason = self.stance_excess(theta)
        if stance_share > STANCE_LIMIT_RTOL:  # the NLP's rows hold these to Ipopt's tolerance
            return Evaluation(float("inf"), stance_reason, stance_share)
        return Evaluation(self._energy_j(out) + self.stance_energy_j(theta), None, 0.0)

    def _row_violation(self, c: np.ndarray) -> tuple[float, str | None, bool]:
        """The rows' violation at the samples' outputs ``c``, its reason, and whether finite.

        Each row's excess beyond its round-off, relative to the row's scale (1 m, 1 rad, or the
        bound's size: 14 kN of force), so that every constraint weighs alike; summed over rows
        and samples. The reason is the largest excess's (``None`` when inside).
        """
        if not np.all(np.isfinite(c)):
            if REACH in self.kernel.rows:
                over = np.abs(c[self.kernel.row(REACH)]) - 1.0
                amount = float(np.sum(over[over > 0])) or 1.0  # NaN angles: always > 0
                return amount, "foot target out of reach", False
            return 1.0, "non-finite motion", False
        lower, upper = self.constraint_bounds
        excess: np.ndarray = np.maximum(np.maximum(lower - c, c - upper), 0.0)
        tol = self.constraint_tolerance
        beyond: np.ndarray = np.where(excess > tol, excess, 0.0) * (FEASIBILITY_TOLERANCE / tol)
        violation = float(np.sum(beyond))
        if violation == 0.0:
            return 0.0, None, True
        row, sample = np.unravel_index(int(np.argmax(beyond)), beyond.shape)
        return violation, self._reason(int(row), int(sample)), True

    def _reason(self, row: int, sample: int) -> str:
        return self.constraints[row].reason(sample, self.grid)


@dataclass(frozen=True)
class SwingGoal:
    """What a swing optimization asks for, before it is put on a robot's sampled gait.

    The family the swing is sought in and how far inside the joint range and the stroke it
    stays; :meth:`on` puts it on a pipeline (its robot, gait and sampling) for one leg, the one
    place a :class:`SwingProblem` is built.
    """

    family: SwingFamily
    margins: LimitMargins = DEFAULT_MARGINS

    def on(
        self,
        pipeline: EnergyPipeline,
        leg: str,
        others: Mapping[str, np.ndarray] | None = None,
        stance_term: bool = True,
    ) -> SwingProblem:
        """``leg``'s problem on ``pipeline`` (see :class:`SwingProblem` for the arguments)."""
        return SwingProblem(pipeline, leg, self.family, others, self.margins, stance_term)


@dataclass
class PairProblem:
    """Both legs of a diagonal pair optimized together, under loads that couple them.

    Under whole-body loads the pair's stance energy depends on both legs' swings (their twins
    load the same stance feet, :mod:`scalf_opt.energy.coupling`). Its objective is the pair's
    energy over a cycle up to a constant: both legs' swing energies plus the pair's stance
    energy; its constraints are each leg's and the loaded stance legs' limits. One NLP over
    both legs' parameters (:mod:`scalf_opt.optimize.nlp`) reaches the pair's optimum in one
    solve, where optimizing the legs in turn needs rounds until they settle.

    Attributes:
        pipeline: The robot's energy pipeline (its load model couples the legs).
        legs: The pair's legs (a leg and its diagonal partner).
        family: Their swing family.
        margins: How far inside the joint range and the stroke the swings stay.
    """

    pipeline: EnergyPipeline
    legs: tuple[str, ...]
    family: SwingFamily
    margins: LimitMargins = DEFAULT_MARGINS

    def __post_init__(self) -> None:
        self.margins = self.margins.for_family(self.family.n_params)  # a small family: no lift

    @cached_property
    def problems(self) -> tuple[SwingProblem, ...]:
        """Each leg's own swing problem, without the stance term (which the pair owns)."""
        goal = SwingGoal(self.family, self.margins)
        return tuple(goal.on(self.pipeline, leg, stance_term=False) for leg in self.legs)

    @cached_property
    def couplings(self) -> tuple[StanceCoupling, ...]:
        """The stances both legs' swings load, as functions of them (as a leg's problem's)."""
        zeros = {leg: np.zeros(self.family.n_params) for leg in self.legs}
        swings = self.pipeline.swings(self.family, zeros)
        return stance_couplings(self.pipeline, self.legs, self.family, swings)

    def stance_energy_j(self, thetas: Sequence[np.ndarray]) -> float:
        """The stance part of the objective [J] for each leg's parameters, in :attr:`legs` order."""
        return stances_energy_j(self.couplings, self.pipeline, thetas)

    def leg_problem(self, leg: str, thetas: Mapping[str, np.ndarray]) -> SwingProblem:
        """``leg``'s problem, the other leg's parameters fixed at ``thetas``, its stance term in.

        What a leg's answer is evaluated on, exactly as when the leg is solved alone.
        """
        others = {o: np.asarray(thetas[o], dtype=float) for o in self.legs if o != leg}
        return SwingGoal(self.family, self.margins).on(self.pipeline, leg, others)
