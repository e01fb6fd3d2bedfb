r"""A diagonal pair's stance energy as a function of the swinging legs: what a swing pays for.

Under whole-body loads (:mod:`scalf_opt.energy.loads`) the stance legs carry the swinging legs'
weight and inertia. In a trot the stance of the pair (L, its diagonal partner) coincides with the
swing of L's symmetric twin (LF for RF), which repeats L's swing half a cycle later: the swing
parameters ``theta`` of L change the pair's stance energy through the twin's wrench only.

Everything else is fixed during an optimization of L, so each stance leg's torques are affine in
the twin's wrench ``w(y_j)`` at each stance sample ``j``::

    tau_S(j) = tau_S0(j) + G_S(j) w(y_j),      G_S(j) = -J_S(q_j)^T K_S(j)  (2 x 6)

with ``K_S(j)`` the sagittal rows of the minimum-norm distribution for that sample's stance feet
and ``tau_S0`` the torques under every other part of the load. ``y_j`` is the twin's motion at
that sample, affine in ``theta`` (:func:`~scalf_opt.energy.loads.affine_leg_motion`). When both
legs of the pair are optimized together, both twins (LF and RH for RF and LH) swing during the
pair's stance and their wrenches add: ``tau_S(j) = tau_S0(j) + G_S(j) (w_1(y_1j) + w_2(y_2j))``,
with ``tau_S0`` now free of both. The exact
energy (:meth:`StanceCoupling.energy_j`) and the NLP's smooth form
(:mod:`scalf_opt.optimize.nlp`) both read these arrays and the same CasADi functions (the twin's
wrench, the stance legs' drive power), so the optimizers minimize what the evaluator reports.

Half a cycle later the legs themselves swing during the other pair's stance (LF and RH for RF
and LH) and load it the same way, their own parameters now in ``w``. On a robot symmetric about
its sagittal midplane that stance mirrors the first and one window stands for both. Where the
sides differ (HyQ's trunk 21.5 mm to the left of its midplane, Go1's 1.9 mm) the two stances
differ in energy and in how close they come to a limit, and both count, each at half weight
(:func:`stance_couplings`): the objective of the pair is then half the robot's cycle energy
(on a symmetric robot, the pair's), and every loaded stance leg's limits bind the swings.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

from scalf_opt.energy.loads import Swings, affine_leg_motion, static_wrench
from scalf_opt.energy.physics import trapezoid_weights
from scalf_opt.locomotion.swing.family import AffinePath, SwingFamily
from scalf_opt.locomotion.trot import (
    DIAGONAL_PARTNER,
    SYMMETRIC_TWIN,
    stance_start_s,
)
from scalf_opt.types import LEG_NAMES

if TYPE_CHECKING:
    from scalf_opt.energy.pipeline import EnergyPipeline


@dataclass(frozen=True)
class StanceTerm:
    """One stance leg's torques, affine in the varying leg's wrench.

    Attributes:
        leg: The stance leg.
        q: Joint angles (2, n) [rad].
        qd: Joint rates (2, n) [rad/s].
        tau_fixed_nm: Torques under every other part of the load (2, n) [N m].
        gain: ``G(j)``, shape (n, 2, 6): torque per unit of the varying leg's wrench [m, 1].
    """

    leg: str
    q: np.ndarray
    qd: np.ndarray
    tau_fixed_nm: np.ndarray
    gain: np.ndarray

    def torques_nm(self, wrench: np.ndarray) -> np.ndarray:
        """Torques (2, n) [N m] for the varying leg's wrench (6, n)."""
        return self.tau_fixed_nm + np.einsum("nij,jn->in", self.gain, wrench)


@dataclass(frozen=True)
class StanceCoupling:
    """A pair's stance energy as a function of the swing parameters of ``legs``.

    Attributes:
        legs: The legs whose swings are optimized (one, or both legs of the pair together).
        varying: The legs swinging with those parameters during this stance, in the same order:
            the legs' symmetric twins during the stance of the legs' own pair, or the legs
            themselves during the other pair's (:func:`stance_couplings`).
        motions: Each varying leg's motion at the stance samples, affine in the parameters.
        terms: One per stance leg of the pair.
        weights: Trapezoidal weights of the stance samples [s], times the window's share of the
            objective (1, or 1/2 when two windows count).
    """

    legs: tuple[str, ...]
    varying: tuple[str, ...]
    motions: tuple[AffinePath, ...]
    terms: tuple[StanceTerm, ...]
    weights: np.ndarray
    _mapped: dict[str, ca.Function] = field(default_factory=dict, repr=False, compare=False)

    def torques_nm(
        self, pipeline: EnergyPipeline, thetas: Sequence[np.ndarray | None]
    ) -> list[np.ndarray]:
        """Each stance term's joint torques (2, n) [N m] for the parameters of :attr:`legs`."""
        self._map(pipeline)
        wrench = sum(
            np.array(self._mapped[twin](*motion.values(theta)))
            for twin, motion, theta in zip(self.varying, self.motions, thetas, strict=True)
        )
        return [term.torques_nm(np.asarray(wrench)) for term in self.terms]

    def energy_j(self, pipeline: EnergyPipeline, thetas: Sequence[np.ndarray | None]) -> float:
        """The pair's exact stance energy [J] for the parameters of :attr:`legs`."""
        total = 0.0
        for term, tau in zip(self.terms, self.torques_nm(pipeline, thetas), strict=True):
            power = np.array(self._mapped[term.leg](term.q, term.qd, tau)[0])
            total += float(np.sum(power @ self.weights))
        return total

    def halved(self) -> StanceCoupling:
        """This window at half the weight (one of two windows of the objective)."""
        return replace(self, weights=self.weights / 2.0, _mapped={})

    def mirrors(self, other: StanceCoupling, pipeline: EnergyPipeline) -> bool:
        """Whether ``other``, the other pair's stance, is this one's mirror image.

        The stance legs' paths, the weights and their torques at zero and at unit parameters
        agree within :data:`MIRROR_RTOL` (the gains themselves differ: the lateral parts of the
        wrench change sign between mirror-image legs, and so do their columns).
        """
        pairs = [(self.weights, other.weights)]
        pairs += [(a.q, b.q) for a, b in zip(self.terms, other.terms, strict=True)]
        pairs += [(a.qd, b.qd) for a, b in zip(self.terms, other.terms, strict=True)]
        for value in (0.0, 1.0):
            thetas = [np.full(m.n_params, value) for m in self.motions]
            pairs += list(
                zip(
                    self.torques_nm(pipeline, thetas),
                    other.torques_nm(pipeline, thetas),
                    strict=True,
                )
            )
        return all(
            a.shape == b.shape
            and bool(np.all(np.abs(a - b) <= MIRROR_RTOL * max(float(np.max(np.abs(a))), 1e-300)))
            for a, b in pairs
        )

    def _map(self, pipeline: EnergyPipeline) -> None:
        n = self.weights.size
        if not self._mapped:
            for twin, motion in zip(self.varying, self.motions, strict=True):
                physics = pipeline.physics(twin)
                self._mapped[twin] = physics.wrench_function(motion.space).map(n)
            for term in self.terms:
                power = pipeline.physics(term.leg).power_function(pipeline.accounting)
                self._mapped[term.leg] = power.map(n)


def stances_energy_j(
    couplings: Sequence[StanceCoupling],
    pipeline: EnergyPipeline,
    thetas: Sequence[np.ndarray],
) -> float:
    """The energy of every stance window of ``couplings`` [J] (weighted by its share).

    ``thetas``: the parameters of the windows' ``legs``, in that order (0 with no window).
    """
    arrays = tuple(np.asarray(theta, dtype=float) for theta in thetas)
    return sum((c.energy_j(pipeline, arrays) for c in couplings), 0.0)


MIRROR_RTOL = 1e-12
"""Two stance windows whose arrays agree within this share of their largest entry mirror each
other: the robot is symmetric about its sagittal midplane, and one window stands for both."""


def stance_couplings(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    swings: Swings,
    twins_repeat: bool = True,
) -> tuple[StanceCoupling, ...]:
    """Every stance the swings of ``legs`` load, as a function of their parameters.

    A swing of ``legs`` loads two stances over a cycle: its symmetric twin, repeating it half a
    cycle later, loads the stance of the legs' own pair (the window of :func:`stance_coupling`),
    and the legs themselves load the other pair's stance, which coincides with their own swing.
    On a robot symmetric about its sagittal midplane the second window mirrors the first, and
    one window stands for both (its energy the pair's stance energy, its limits the other pair's
    too). Where the two differ (a trunk whose centre of mass is off the midplane: HyQ's, 21.5 mm
    to the left), both windows count, each with half the weight: the stance part of the
    objective is then half the stance energy of all four legs, which on the symmetric robot is
    the pair's, and the limits of every loaded stance leg bind the swing.

    When the twins swing with parameters of their own (every leg optimized on its own), a
    twin's swing does not repeat the legs', and only the stance the legs' own swings load
    depends on their parameters: that window alone, at full weight.

    Args:
        pipeline: Robot, gait, accounting (its load model must couple the legs).
        legs: The optimized legs: one leg, or both legs of one diagonal pair.
        family: Their swing family.
        swings: Every leg's swing; the entries of the legs and of twins that repeat them are
            ignored (they vary).
        twins_repeat: The twins repeat the legs' swings half a cycle later (the paper's
            symmetry); ``False``: they keep their own entries of ``swings``.
    """
    other = _window(pipeline, SYMMETRIC_TWIN[legs[0]], legs, legs, family, swings)
    if not twins_repeat:
        return (other,)
    own = stance_coupling(pipeline, legs, family, swings)
    if own.mirrors(other, pipeline):
        return (own,)
    return (own.halved(), other.halved())


def stance_coupling(
    pipeline: EnergyPipeline, legs: tuple[str, ...], family: SwingFamily, swings: Swings
) -> StanceCoupling:
    """The pair's stance as a function of the swing parameters of ``legs`` (module docstring).

    Args:
        pipeline: Robot, gait, accounting (its load model must couple the legs).
        legs: The optimized legs: one leg, or both legs of one diagonal pair.
        family: Their swing family (the twins repeat it).
        swings: Every leg's swing; the twins' entries are ignored (they vary).
    """
    pair = (legs[0], DIAGONAL_PARTNER[legs[0]])
    if not set(legs) <= set(pair):
        raise ValueError(f"legs {legs} are not one diagonal pair")
    twins = tuple(SYMMETRIC_TWIN[leg] for leg in legs)
    return _window(pipeline, legs[0], twins, legs, family, swings)


def _window(
    pipeline: EnergyPipeline,
    stance_leg: str,
    varying: tuple[str, ...],
    legs: tuple[str, ...],
    family: SwingFamily,
    swings: Swings,
) -> StanceCoupling:
    """The stance of ``stance_leg``'s pair with the swings of ``varying`` as the variables.

    ``varying``: the swinging legs whose motion repeats the parameters of ``legs`` (in the same
    order): the legs' twins, or the legs themselves.
    """
    gait = pipeline.gait
    pair = (stance_leg, DIAGONAL_PARTNER[stance_leg])
    t = pipeline.stance_times_s
    n = t.size
    cycle_times = stance_start_s(gait, stance_leg) + t  # the pair's stance: the same for both
    fixed = np.tile(static_wrench(pipeline.robot)[:, None], (1, n))
    for other in LEG_NAMES:
        if other in varying:
            continue
        own_family, theta = swings[other]
        motion = affine_leg_motion(pipeline, other, cycle_times, own_family, other in pair)
        fn = pipeline.physics(other).wrench_function(motion.space).map(n)
        fixed += np.array(fn(*motion.values(theta)))
    distribution = pipeline.stance_distribution(stance_leg)
    shares = {s: distribution.force[s][:, [0, 2]] for s in pair}  # sagittal rows (n, 2, 6)
    terms = []
    for s in pair:
        physics = pipeline.physics(s)
        path = pipeline.stance_paths[s]
        out = physics.sample_function("foot", pipeline.accounting).map(n)(
            path[0], path[1], path[2], np.zeros((2, n))
        )
        values = dict(zip(physics.output_names, out, strict=True))
        q, qd = np.array(values["q"]), np.array(values["qd"])
        rnea = np.array(values["tau"])
        jac = np.array(pipeline.kinematics(s).functions["jacobian"].map(n)(q))  # 2 x 2n
        jac = jac.reshape(2, n, 2).transpose(1, 0, 2)  # (n, 2 rows xz, 2 joints)
        gain = -np.einsum("nrj,nrk->njk", jac, shares[s])  # -J^T K: (n, 2 joints, 6)
        tau_fixed = rnea + np.einsum("njk,kn->jn", gain, fixed)
        terms.append(StanceTerm(s, q, qd, tau_fixed, gain))
    motions = tuple(affine_leg_motion(pipeline, v, cycle_times, family) for v in varying)
    return StanceCoupling(legs, varying, motions, tuple(terms), trapezoid_weights(t))
