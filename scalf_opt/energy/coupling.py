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
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
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
    """The pair's stance energy as a function of the swing parameters of ``legs``.

    Attributes:
        legs: The legs whose swings are optimized (one, or both legs of the pair together).
        varying: Their symmetric twins, swinging during the pair's stance, in the same order.
        motions: Each twin's motion at the stance samples, affine in its leg's parameters.
        terms: One per stance leg of the pair (``legs[0]`` and its diagonal partner).
        weights: Trapezoidal weights of the stance samples [s].
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

    def _map(self, pipeline: EnergyPipeline) -> None:
        n = self.weights.size
        if not self._mapped:
            for twin, motion in zip(self.varying, self.motions, strict=True):
                physics = pipeline.physics(twin)
                self._mapped[twin] = physics.wrench_function(motion.space).map(n)
            for term in self.terms:
                power = pipeline.physics(term.leg).power_function(pipeline.accounting)
                self._mapped[term.leg] = power.map(n)


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
    gait = pipeline.gait
    pair = (legs[0], DIAGONAL_PARTNER[legs[0]])
    if not set(legs) <= set(pair):
        raise ValueError(f"legs {legs} are not one diagonal pair")
    twins = tuple(SYMMETRIC_TWIN[leg] for leg in legs)
    t = pipeline.stance_times_s
    n = t.size
    cycle_times = stance_start_s(gait, legs[0]) + t  # the pair's stance: the same for both legs
    fixed = np.tile(static_wrench(pipeline.robot)[:, None], (1, n))
    for other in LEG_NAMES:
        if other in twins:
            continue
        own_family, theta = swings[other]
        motion = affine_leg_motion(pipeline, other, cycle_times, own_family, other in pair)
        fn = pipeline.physics(other).wrench_function(motion.space).map(n)
        fixed += np.array(fn(*motion.values(theta)))
    distribution = pipeline.stance_distribution(legs[0])
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
    motions = tuple(affine_leg_motion(pipeline, twin, cycle_times, family) for twin in twins)
    return StanceCoupling(legs, twins, motions, tuple(terms), trapezoid_weights(t))
