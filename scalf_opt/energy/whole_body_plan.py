r"""A 3-D whole-body gait cycle as a plan: its nodes, what it costs, and its check between nodes.

A :class:`WholeBodyPlan` holds one periodic trot cycle of the 3-D model at the nodes of its
:class:`~scalf_opt.locomotion.contact_schedule.TrotSchedule`: the coordinates ``X`` with their rates
and second derivatives (a periodic C2 cubic spline, :mod:`~scalf_opt.locomotion.periodic_spline`)
and the four feet's contact forces (world axes, on the robot; linear between nodes, zero in swing).

:meth:`WholeBodyPlan.evaluate` gives the energy the optimizer saw: each joint's drawn power (exact
accounting and losses) at the schedule's read points (by default the nodes, quarter points and
midpoints), summed over the periodic grid by composite Simpson's rule.
:meth:`WholeBodyPlan.check` is the independent re-evaluation: the spline and the forces read at
``factor`` times the rate and pushed through Pinocchio's own ``rnea`` (with the forces as external
forces on the feet's parent joints, not the CasADi twin the optimizer used), giving the joint
torques, the energy, the wrench the trunk is left with (zero if the forces carry the robot between
the nodes too), how far a stance foot slides and how close a swing foot comes to the ground.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pinocchio as pin

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import TrotSchedule
from scalf_opt.locomotion.periodic_spline import evaluate as spline_at
from scalf_opt.locomotion.periodic_spline import inner_points, interval_points
from scalf_opt.types import Accounting


@dataclass(frozen=True)
class PlanEnergy:
    """What a plan costs, per joint and in total, at some rate.

    Attributes:
        rate_hz: The samples per second it was summed at.
        joint_energy_j: Each joint's drawn energy over one cycle [J] (physics' joint order).
        tau_nm: The joint torques at the samples (n_joints, n) [N m].
        times_s: The sample times (n,) [s].
    """

    rate_hz: float
    joint_energy_j: np.ndarray
    tau_nm: np.ndarray
    times_s: np.ndarray

    @property
    def total_j(self) -> float:
        """The whole robot's drawn energy per cycle [J]."""
        return float(self.joint_energy_j.sum())


@dataclass(frozen=True)
class PlanCheck:
    """The plan read between its nodes (:meth:`WholeBodyPlan.check`).

    Attributes:
        energy: The energy at the finer rate, from Pinocchio's torques.
        base_residual: The largest wrench left on the trunk, force [N] over the robot's weight
            (and moment [N m] over weight x stance height): 0 when the forces carry the robot.
        stance_slip_m: The largest distance a stance foot moves from its foothold [m].
        swing_floor_m: The lowest height of a swing foot's frame over the swing's inner samples
            (the first and last node excluded: there it is on the ground) [m].
        torque_gap_nm: The largest difference between Pinocchio's joint torques and the plan's at
            the nodes themselves [N m] (the twin against Pinocchio).
    """

    energy: PlanEnergy
    base_residual: float
    stance_slip_m: float
    swing_floor_m: float
    torque_gap_nm: float


@dataclass(frozen=True)
class PlanSamples:
    """The plan read at some instants through Pinocchio (:meth:`WholeBodyPlan.samples`).

    Attributes:
        t_s: The instants (n,) [s], in ``[0, T)``.
        x, xd: The coordinates ``X`` and their rates (nx, n).
        q, v, a: Pinocchio's free-flyer state ((nq, n), (nv, n), (nv, n)).
        forces_n: The feet's contact forces (12, n) [N], world axes, on the robot.
        tau_nm: The joint torques Pinocchio's ``rnea`` gives with those forces (n_joints, n).
        base_wrench: What ``rnea`` leaves on the trunk (6, n), zero when the forces carry it.
        feet_m: The feet's world positions (3, 4, n) [m].
    """

    t_s: np.ndarray
    x: np.ndarray
    xd: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    forces_n: np.ndarray
    tau_nm: np.ndarray
    base_wrench: np.ndarray
    feet_m: np.ndarray


@dataclass(frozen=True)
class WholeBodyPlan:
    """One periodic trot cycle of the whole robot in 3-D (immutable).

    Attributes:
        physics: The 3-D model it was planned on.
        schedule: Its contact schedule and node grid.
        speed_m_s: The trunk's average forward speed [m/s]; the stride is ``speed T``.
        x, xd, xdd: The coordinates, rates and second derivatives at the nodes (nx, N).
        forces_n: The feet's contact forces at the nodes (12, N) [N], world axes, on the robot,
            stacked per foot in :data:`~scalf_opt.types.LEG_NAMES` order.
        footholds_m: Each foot's foothold ``(x, y)`` of the stance that begins in the cycle
            (2, 4) [m], world.
    """

    physics: WholeBodyPhysics
    schedule: TrotSchedule
    speed_m_s: float
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    forces_n: np.ndarray
    footholds_m: np.ndarray

    @property
    def stride_m(self) -> float:
        """How far the trunk moves forward in one cycle [m]."""
        return self.speed_m_s * self.schedule.period_s

    def cost_of_transport(self, energy_j: float) -> float:
        """Dimensionless cost of transport of ``energy_j`` per cycle: ``E / (m g stride)``."""
        return energy_j / (self.physics.weight_n * self.stride_m)

    @cached_property
    def pinocchio_states(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Pinocchio's ``q``, ``v``, ``a`` at the nodes ((nq, N), (nv, N), (nv, N))."""
        fn = self.physics.pinocchio_state_function.map(self.schedule.intervals)
        q, v, a = fn(self.x, self.xd, self.xdd)
        return np.array(q), np.array(v), np.array(a)

    @property
    def shift(self) -> np.ndarray:
        """What one cycle adds to ``X`` (nx, 1): the stride on the trunk's x."""
        return self.physics.stride_shift(self.stride_m)

    def node_outputs(self, accounting: Accounting) -> dict[str, np.ndarray]:
        """Every output of :meth:`WholeBodyPhysics.node_function` at the nodes (exact losses)."""
        return self._outputs(accounting, (self.x, self.xd, self.xdd), self.forces_n)

    def inner_outputs(self, accounting: Accounting, fraction: float) -> dict[str, np.ndarray]:
        """Every output of :meth:`WholeBodyPhysics.node_function` inside the intervals.

        Column ``k`` is ``fraction`` of the way through ``[t_k, t_{k+1}]`` (the spline there, the
        forces interpolated linearly).
        """
        states = inner_points(self.x, self.xd, self.xdd, self.schedule.step_s, self.shift, fraction)
        return self._outputs(accounting, states, interval_points(self.forces_n, fraction))

    def _outputs(
        self, accounting: Accounting, states: tuple[np.ndarray, ...], forces: np.ndarray
    ) -> dict[str, np.ndarray]:
        fn = self.physics.node_function(accounting).map(forces.shape[1])
        values = fn(*states, forces)
        return {name: np.array(v) for name, v in zip(fn.name_out(), values, strict=True)}

    @property
    def _following_forces(self) -> np.ndarray:
        return np.roll(self.forces_n, -1, axis=1)

    def evaluate(self, accounting: Accounting) -> PlanEnergy:
        """The energy the optimizer sees, with the exact losses.

        Composite Simpson's rule on the schedule's read points
        (:attr:`~scalf_opt.locomotion.contact_schedule.TrotSchedule.read_points`: by default the
        nodes, quarter points and midpoints); the rate it reports is the nodes'.
        """
        step = self.schedule.step_s
        read = self.schedule.read_points
        nodes = self.node_outputs(accounting)
        energy = read[0][1] * step * nodes["charged"].sum(axis=1)
        for fraction, weight in read[1:]:
            inner = self.inner_outputs(accounting, fraction)
            energy = energy + weight * step * inner["charged"].sum(axis=1)
        return PlanEnergy(1.0 / step, energy, nodes["tau"], self.schedule.times_s)

    def forces_at(self, t_s: np.ndarray) -> np.ndarray:
        """The contact forces at times ``t_s`` in ``[0, T)`` (12, n) [N].

        Linear between nodes; zero in swing (a foot's force is zero at touch-down and lift-off).
        """
        step, n = self.schedule.step_s, self.schedule.intervals
        k = np.minimum((t_s / step).astype(int), n - 1)
        w = t_s / step - k
        return self.forces_n[:, k] * (1 - w) + self._following_forces[:, k] * w

    def states_at(self, t_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The coordinates, rates and second derivatives at times ``t_s`` in ``[0, T)`` (nx, n)."""
        return spline_at(self.x, self.xd, self.xdd, self.schedule.step_s, t_s)

    def samples(self, t_s: np.ndarray) -> PlanSamples:
        """The plan at times ``t_s`` in ``[0, T)`` through Pinocchio's own ``rnea``.

        The spline's state and the linear forces at ``t_s``, and what Pinocchio's free-flyer
        inverse dynamics makes of them, with the forces as external forces on the feet's parent
        joints (not the CasADi twin the optimizer used).
        """
        physics = self.physics
        model = physics.model
        data = model.createData()
        n = len(t_s)
        x, xd, xdd = self.states_at(t_s)
        forces = self.forces_at(t_s)
        fn = physics.pinocchio_state_function.map(n)
        qs, vs, as_ = (np.array(m) for m in fn(x, xd, xdd))
        fids = [model.getFrameId(f) for f in physics.feet]
        tau = np.zeros((physics.n_joints, n))
        base = np.zeros((6, n))
        feet = np.zeros((3, len(fids), n))
        for s in range(n):
            q = qs[:, s]
            pin.forwardKinematics(model, data, q)
            pin.updateFramePlacements(model, data)
            fext = [pin.Force.Zero() for _ in range(model.njoints)]
            for i, fid in enumerate(fids):
                frame = model.frames[fid]
                local = data.oMi[frame.parentJoint].rotation.T @ forces[3 * i : 3 * i + 3, s]
                moment = np.cross(frame.placement.translation, local)
                fext[frame.parentJoint] += pin.Force(local, moment)
                feet[:, i, s] = data.oMf[fid].translation
            out = pin.rnea(model, data, q, vs[:, s], as_[:, s], fext)
            base[:, s], tau[:, s] = out[:6], out[6:]
        return PlanSamples(np.asarray(t_s, float), x, xd, qs, vs, as_, forces, tau, base, feet)

    def check(self, accounting: Accounting, factor: int = 10) -> PlanCheck:
        """Re-read the plan at ``factor`` times its rate through Pinocchio (module docstring)."""
        schedule = self.schedule
        n = schedule.intervals * factor
        fine = self.samples(np.arange(n) * schedule.period_s / n)
        tau = fine.tau_nm
        charged = np.array(self.physics.power_function(accounting).map(n)(fine.x, fine.xd, tau))
        energy = PlanEnergy(
            n / schedule.period_s, charged.sum(axis=1) * schedule.period_s / n, tau, fine.t_s
        )
        return PlanCheck(
            energy=energy,
            base_residual=self._residual(fine.base_wrench),
            stance_slip_m=self._slip(fine.feet_m, factor),
            swing_floor_m=self._swing_floor(fine.feet_m, factor),
            torque_gap_nm=float(np.abs(tau[:, ::factor] - self.evaluate(accounting).tau_nm).max()),
        )

    def _residual(self, base: np.ndarray) -> float:
        weight = self.physics.weight_n
        height = float(np.mean(self.x[2]))
        force = np.abs(base[:3]).max() / weight
        return float(max(force, np.abs(base[3:]).max() / (weight * height)))

    def _stance_mask_fine(self, factor: int) -> np.ndarray:
        """Stance at the fine samples (4, n): strictly between two stance nodes, or on one."""
        return self.schedule.stance_at(np.arange(self.schedule.intervals * factor) / factor)

    def _slip(self, feet: np.ndarray, factor: int) -> float:
        stance = self._stance_mask_fine(factor)
        worst = 0.0
        for i in range(feet.shape[1]):
            on = stance[i]
            if not on.any():
                continue
            hold_x = self.footholds_m[0, i]
            t_index = np.flatnonzero(on)
            previous = np.repeat(self.schedule.previous_stance[i], factor)[t_index]
            expected = np.vstack(
                [
                    hold_x - self.stride_m * previous,
                    np.full(t_index.size, self.footholds_m[1, i]),
                    np.zeros(t_index.size),
                ]
            )
            worst = max(worst, float(np.linalg.norm(feet[:, i, t_index] - expected, axis=0).max()))
        return worst

    def _swing_floor(self, feet: np.ndarray, factor: int) -> float:
        swing = ~self._stance_mask_fine(factor)
        heights = np.where(swing, feet[2], np.inf)
        return float(heights.min())
