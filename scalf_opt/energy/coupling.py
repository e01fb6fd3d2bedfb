r"""A diagonal pair's stance energy as a function of one swinging leg: what a swing pays for.

Under whole-body loads (:mod:`scalf_opt.energy.loads`) the stance legs carry the swinging legs'
weight and inertia. In a trot the stance of the pair (L, its diagonal partner) coincides with the
swing of L's symmetric twin (LF for RF), which repeats L's swing half a cycle later: the swing
parameters ``theta`` of L change the pair's stance energy through the twin's wrench only.

Everything else is fixed during an optimization of L, so each stance leg's torques are affine in
the twin's wrench ``w(y_j)`` at each stance sample ``j``::

    tau_S(j) = tau_S0(j) + G_S(j) w(y_j),      G_S(j) = -J_S(q_j)^T K_S(j)  (2 x 6)

with ``K_S(j)`` the sagittal rows of the minimum-norm distribution for that sample's stance feet
and ``tau_S0`` the torques under every other part of the load. ``y_j`` is the twin's motion at
that sample, affine in ``theta`` (:func:`~scalf_opt.energy.loads.affine_leg_motion`). The exact
energy (:meth:`StanceCoupling.energy_j`) and the NLP's smooth form
(:mod:`scalf_opt.optimize.nlp`) both read these arrays and the same CasADi functions (the twin's
wrench, the stance legs' drive power), so the optimizers minimize what the evaluator reports.
"""

from __future__ import annotations

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
    """The pair's stance energy as a function of the swing parameters of ``leg``.

    Attributes:
        leg: The leg whose swing is optimized.
        varying: Its symmetric twin, swinging during the pair's stance.
        motion: The twin's motion at the stance samples, affine in the parameters.
        terms: One per stance leg of the pair (``leg`` and its diagonal partner).
        weights: Trapezoidal weights of the stance samples [s].
    """

    leg: str
    varying: str
    motion: AffinePath
    terms: tuple[StanceTerm, ...]
    weights: np.ndarray
    _mapped: dict[str, ca.Function] = field(default_factory=dict, repr=False, compare=False)

    def torques_nm(self, pipeline: EnergyPipeline, theta: np.ndarray | None) -> list[np.ndarray]:
        """Each stance term's joint torques (2, n) [N m] for the parameters ``theta``."""
        self._map(pipeline)
        wrench = np.array(self._mapped["wrench"](*self.motion.values(theta)))
        return [term.torques_nm(wrench) for term in self.terms]

    def energy_j(self, pipeline: EnergyPipeline, theta: np.ndarray | None) -> float:
        """The pair's exact stance energy [J] for the parameters ``theta``."""
        total = 0.0
        for term, tau in zip(self.terms, self.torques_nm(pipeline, theta), strict=True):
            power = np.array(self._mapped[term.leg](term.q, term.qd, tau)[0])
            total += float(np.sum(power @ self.weights))
        return total

    def _map(self, pipeline: EnergyPipeline) -> None:
        n = self.weights.size
        if not self._mapped:
            physics = pipeline.physics(self.varying)
            self._mapped["wrench"] = physics.wrench_function(self.motion.space).map(n)
            for term in self.terms:
                power = pipeline.physics(term.leg).power_function(pipeline.accounting)
                self._mapped[term.leg] = power.map(n)


def stance_coupling(
    pipeline: EnergyPipeline, leg: str, family: SwingFamily, swings: Swings
) -> StanceCoupling:
    """The pair's stance as a function of ``leg``'s swing parameters (module docstring).

    Args:
        pipeline: Robot, gait, accounting (its load model must couple the legs).
        leg: The optimized leg.
        family: Its swing family (the twin repeats it).
        swings: Every leg's swing; the twin's entry is ignored (it varies).
    """
    gait = pipeline.gait
    twin = SYMMETRIC_TWIN[leg]
    pair = (leg, DIAGONAL_PARTNER[leg])
    t = pipeline.stance_times_s
    n = t.size
    cycle_times = stance_start_s(gait, leg) + t
    fixed = np.tile(static_wrench(pipeline.robot)[:, None], (1, n))
    for other in LEG_NAMES:
        if other == twin:
            continue
        own_family, theta = swings[other]
        motion = affine_leg_motion(pipeline, other, cycle_times, own_family, other in pair)
        fn = pipeline.physics(other).wrench_function(motion.space).map(n)
        fixed += np.array(fn(*motion.values(theta)))
    distribution = pipeline.stance_distribution(leg)
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
    motion = affine_leg_motion(pipeline, twin, cycle_times, family)
    return StanceCoupling(leg, twin, motion, tuple(terms), trapezoid_weights(t))
