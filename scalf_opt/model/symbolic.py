"""CasADi twin of a Pinocchio model: symbolic kinematics and inverse dynamics.

Pinocchio's pip wheels have no ``pinocchio.casadi`` bindings, so the NLP's exact derivatives need
the chain as CasADi expressions. They are built here from the Pinocchio model's own data (joint
placements, joint types and axes, parents, inertias, frames, gravity) and nothing else, and the
tests compare them with ``pin.forwardKinematics``, ``pin.computeFrameJacobian``, ``pin.rnea`` and
``pin.crba`` on random states.

Conventions (Pinocchio's). A placement ``M = (R, p)`` maps child to parent coordinates. Spatial
motions ``(v, w)`` and forces ``(f, n)`` are expressed in a body frame with linear part first.
Recursive Newton-Euler, for joint ``i`` with parent ``lambda(i)`` and motion subspace ``S_i``::

    liMi  = jointPlacement_i * X_J(q_i)
    v_i   = liMi^-1 . v_lambda + S_i qd_i
    a_i   = liMi^-1 . a_lambda + S_i qdd_i + v_i x (S_i qd_i),        a_0 = -gravity
    f_i   = I_i a_i + v_i x* (I_i v_i)
    tau_i = S_i^T f_i,      f_lambda += liMi . f_i                        (backward pass)

with ``I (v, w) = (m (v - c x w), I_c w + c x m (v - c x w))`` for a body of mass ``m``, centre
of mass ``c`` and rotational inertia ``I_c`` about the COM. The mass matrix is the Jacobian of
RNEA with respect to the acceleration at zero velocity and gravity (RNEA is linear in ``qdd``).
"""

from __future__ import annotations

from functools import cached_property
from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from scalf_opt.errors import ModelError
from scalf_opt.model.spatial import (
    Placement,
    act_force,
    act_inv_motion,
    joint_kind,
    quaternion_rotation,
    skew,
)
from scalf_opt.types import Expr, casadi_name


class SymbolicChain:
    """CasADi twin of a Pinocchio model with revolute and prismatic joints, fixed or floating.

    A floating model's root is Pinocchio's free-flyer: ``q`` starts with the base's position and
    unit quaternion ``(x, y, z, w)`` (7), ``v`` and ``a`` with its linear and angular velocity in
    the base frame (6), and the first six entries of :meth:`rnea` are the wrench the base needs
    (force, then moment about the base origin, base axes), zero when the contact forces given to
    :meth:`contact_rnea` carry the robot.

    Every method accepts ``q`` (and ``v``, ``a``) as CasADi SX, MX or numeric (DM, numpy)
    column vectors of length ``nq`` and returns the same kind: internally each quantity is one
    SX :class:`casadi.Function` built once and called on the arguments.
    """

    def __init__(self, model: pin.Model) -> None:
        self._joints: list[tuple[str, np.ndarray, int, int]] = [("root", np.zeros(3), -1, -1)]
        for i in range(1, model.njoints):
            kind, axis = joint_kind(model.joints[i], model.names[i])
            if kind == "freeflyer" and model.parents[i] != 0:
                raise ModelError(f"joint {model.names[i]!r}: a free-flyer must be the root joint")
            joint = model.joints[i]
            self._joints.append((kind, axis, int(joint.idx_q), int(joint.idx_v)))
        self.model = model
        self.nq = int(model.nq)
        self.nv = int(model.nv)

    # --- building blocks on SX ---------------------------------------------------------------
    def _joint_motion(self, i: int, q: Expr) -> Placement:
        kind, axis, iq, _ = self._joints[i]
        if kind == "freeflyer":
            return quaternion_rotation(*(q[iq + k] for k in range(3, 7))), q[iq : iq + 3]
        if kind == "revolute":
            k = skew(ca.DM(axis))
            rot = ca.DM.eye(3) + ca.sin(q[iq]) * k + (1 - ca.cos(q[iq])) * ca.mtimes(k, k)
            return rot, ca.DM.zeros(3, 1)
        return ca.DM.eye(3), ca.DM(axis) * q[iq]

    def _local_placements(self, q: Expr) -> list[Placement]:
        out: list[Placement] = [(ca.DM.eye(3), ca.DM.zeros(3, 1))]
        for i in range(1, self.model.njoints):
            placement = self.model.jointPlacements[i]
            r0, p0 = ca.DM(placement.rotation), ca.DM(placement.translation)
            rj, pj = self._joint_motion(i, q)
            out.append((ca.mtimes(r0, rj), p0 + ca.mtimes(r0, pj)))
        return out

    def _world_placements(self, q: Expr) -> list[Placement]:
        local = self._local_placements(q)
        world: list[Placement] = [local[0]]
        for i in range(1, self.model.njoints):
            r_par, p_par = world[self.model.parents[i]]
            r, p = local[i]
            world.append((ca.mtimes(r_par, r), p_par + ca.mtimes(r_par, p)))
        return world

    def _subspace(self, i: int) -> list[tuple[ca.DM, ca.DM]]:
        """The joint's motion subspace: (linear, angular) in its frame, per degree of freedom."""
        kind, axis, _, _ = self._joints[i]
        zero = ca.DM.zeros(3, 1)
        if kind == "freeflyer":
            eye = np.eye(3)
            return [(ca.DM(eye[k]), zero) for k in range(3)] + [
                (zero, ca.DM(eye[k])) for k in range(3)
            ]
        return [(zero, ca.DM(axis)) if kind == "revolute" else (ca.DM(axis), zero)]

    def _joint_rate(self, i: int, x: Expr) -> tuple[Expr, Expr]:
        """``S_i x_i``: the joint's motion (linear, angular) for its entries of ``v`` or ``a``."""
        iv = self._joints[i][3]
        lin: Expr = ca.DM.zeros(3, 1)
        ang: Expr = ca.DM.zeros(3, 1)
        for k, (s_lin, s_ang) in enumerate(self._subspace(i)):
            lin, ang = lin + s_lin * x[iv + k], ang + s_ang * x[iv + k]
        return lin, ang

    def _frame_index(self, frame: str | int) -> int:
        if isinstance(frame, str):
            if not self.model.existFrame(frame):
                raise ModelError(f"model {self.model.name!r} has no frame {frame!r}")
            return int(self.model.getFrameId(frame))
        return int(frame)

    def _rnea_sx(self, q: Expr, v: Expr, a: Expr, gravity: bool) -> Expr:
        return self._rnea_parts(q, v, a, gravity)[0]

    def _rnea_parts(
        self,
        q: Expr,
        v: Expr,
        a: Expr,
        gravity: bool,
        external: dict[int, tuple[Expr, Expr]] | None = None,
    ) -> tuple[Expr, Expr]:
        """Joint forces (nv x 1) and the spatial force (6 x 1) the root supplies to the chain.

        The second output is the sum, over the root's children, of the force transmitted
        through their joints, expressed in the root frame about its origin (linear part first):
        what a floating root would have to add for the chain's motion and weight.
        ``external``: forces from outside on joint ``i``'s body, (linear, angular) in its frame
        about its origin, as Pinocchio's ``fext``.
        """
        model = self.model
        local = self._local_placements(q)
        g = np.array(model.gravity.linear) if gravity else np.zeros(3)
        vel: list[tuple[Expr, Expr]] = [(ca.DM.zeros(3, 1), ca.DM.zeros(3, 1))]
        acc: list[tuple[Expr, Expr]] = [(ca.DM(-g), ca.DM.zeros(3, 1))]
        forces: list[list[Expr]] = [[ca.DM.zeros(3, 1), ca.DM.zeros(3, 1)]]
        for i in range(1, model.njoints):
            rot, pos = local[i]
            parent = model.parents[i]
            vl, va = act_inv_motion(rot, pos, *vel[parent])
            vj_lin, vj_ang = self._joint_rate(i, v)
            vl, va = vl + vj_lin, va + vj_ang
            al, aa = act_inv_motion(rot, pos, *acc[parent])
            aj_lin, aj_ang = self._joint_rate(i, a)
            # a += S qdd + v x (S qd);  (v, w) x (u, z) = (w x u + v x z, w x z)
            al = al + aj_lin + ca.cross(va, vj_lin) + ca.cross(vl, vj_ang)
            aa = aa + aj_ang + ca.cross(va, vj_ang)
            vel.append((vl, va))
            acc.append((al, aa))
            inertia = model.inertias[i]
            m, c, ic = inertia.mass, ca.DM(inertia.lever), ca.DM(inertia.inertia)

            def momentum(
                lin: Expr, ang: Expr, m: float = m, c: Expr = c, ic: Expr = ic
            ) -> tuple[Expr, Expr]:
                h = m * (lin - ca.cross(c, ang))
                return h, ca.mtimes(ic, ang) + ca.cross(c, h)

            fl, fa = momentum(al, aa)
            hl, ha = momentum(vl, va)
            # v x* h = (w x h_lin, w x h_ang + v x h_lin)
            body = [fl + ca.cross(va, hl), fa + ca.cross(va, ha) + ca.cross(vl, hl)]
            if external and i in external:
                body = [body[0] - external[i][0], body[1] - external[i][1]]
            forces.append(body)
        tau: list[Expr] = [ca.SX(0)] * self.nv
        for i in range(model.njoints - 1, 0, -1):
            fl, fa = forces[i]
            iv = self._joints[i][3]
            for k, (s_lin, s_ang) in enumerate(self._subspace(i)):
                tau[iv + k] = ca.dot(s_lin, fl) + ca.dot(s_ang, fa)
            parent = model.parents[i]
            pl, pa = act_force(*local[i], fl, fa)
            forces[parent][0] = forces[parent][0] + pl
            forces[parent][1] = forces[parent][1] + pa
        return ca.vertcat(*tau), ca.vertcat(*forces[0])

    # --- compiled functions (SX, built once) ---------------------------------------------------
    @cached_property
    def _sym(self) -> tuple[Expr, Expr, Expr]:
        return ca.SX.sym("q", self.nq), ca.SX.sym("v", self.nv), ca.SX.sym("a", self.nv)

    @cached_property
    def _rnea_fn(self) -> ca.Function:
        q, v, a = self._sym
        return ca.Function(
            "rnea", [q, v, a], [self._rnea_sx(q, v, a, True)], ["q", "v", "a"], ["tau"]
        )

    @cached_property
    def _root_wrench_fn(self) -> ca.Function:
        q, v, a = self._sym
        return ca.Function(
            "root_wrench",
            [q, v, a],
            [self._rnea_parts(q, v, a, True)[1]],
            ["q", "v", "a"],
            ["wrench"],
        )

    @cached_property
    def _crba_fn(self) -> ca.Function:
        q, _, a = self._sym
        tau = self._rnea_sx(q, ca.DM.zeros(self.nv, 1), a, False)
        return ca.Function("crba", [q], [ca.jacobian(tau, a)], ["q"], ["M"])

    @cached_property
    def _placement_fns(self) -> dict[int, ca.Function]:
        return {}

    def _frame_fn(self, frame: str | int) -> ca.Function:
        index = self._frame_index(frame)
        if index not in self._placement_fns:
            q = self._sym[0]
            world = self._world_placements(q)
            f = self.model.frames[index]
            r_j, p_j = world[f.parentJoint]
            rot = ca.mtimes(r_j, ca.DM(f.placement.rotation))
            pos = p_j + ca.mtimes(r_j, ca.DM(f.placement.translation))
            # Jacobian in LOCAL_WORLD_ALIGNED: motion of the frame origin per unit joint rate
            support = set()
            j = int(f.parentJoint)
            while j > 0:
                support.add(j)
                j = int(self.model.parents[j])
            columns: list[Expr] = [ca.DM.zeros(6, 1)] * self.nv
            for i in support:
                r_i, p_i = world[i]
                for k, (s_lin, s_ang) in enumerate(self._subspace(i)):
                    w = ca.mtimes(r_i, s_ang)
                    lin = ca.mtimes(r_i, s_lin) + ca.cross(w, pos - p_i)
                    columns[self._joints[i][3] + k] = ca.vertcat(lin, w)
            jac = ca.horzcat(*columns)
            self._placement_fns[index] = ca.Function(
                casadi_name("frame", f.name), [q], [rot, pos, jac], ["q"], ["R", "p", "J"]
            )
        return self._placement_fns[index]

    # --- public API ----------------------------------------------------------------------------
    def frame_placement(self, q: Any, frame: str | int) -> tuple[Any, Any]:
        """World placement ``oMf`` (R 3x3, p 3x1) of a frame."""
        rot, pos, _ = self._frame_fn(frame)(q)
        return rot, pos

    def frame_position(self, q: Any, frame: str | int) -> Any:
        """World position of a frame's origin (3x1) [m]."""
        return self._frame_fn(frame)(q)[1]

    def frame_jacobian(
        self, q: Any, frame: str | int, reference: str = "LOCAL_WORLD_ALIGNED"
    ) -> Any:
        """Frame Jacobian (6 x nv), linear rows first, like ``pin.computeFrameJacobian``.

        Args:
            q: Configuration.
            frame: Frame name or index.
            reference: ``LOCAL_WORLD_ALIGNED`` (frame origin, world axes), ``WORLD`` (world
                origin and axes) or ``LOCAL`` (frame origin and axes).
        """
        rot, pos, jac = self._frame_fn(frame)(q)
        if reference == "LOCAL_WORLD_ALIGNED":
            return jac
        lin, ang = jac[:3, :], jac[3:, :]
        if reference == "WORLD":  # velocity of the world origin: v(0) = v(p) - w x p = v(p) + p x w
            return ca.vertcat(lin + ca.mtimes(skew(pos), ang), ang)
        if reference == "LOCAL":
            return ca.vertcat(ca.mtimes(rot.T, lin), ca.mtimes(rot.T, ang))
        raise ValueError(f"unknown reference frame {reference!r}")

    def rnea(self, q: Any, v: Any, a: Any) -> Any:
        """Joint forces ``M(q) a + C(q, v) v + G(q)`` (nv x 1), like ``pin.rnea``."""
        return self._rnea_fn(q, v, a)

    def root_wrench(self, q: Any, v: Any, a: Any) -> Any:
        """The spatial force the root supplies to the moving chain for motion ``(q, v, a)``.

        6 x 1: force [N], then moment [N m] about the root origin, root axes, gravity included.
        For a root that moves at constant velocity without rotating this is the chain's part
        of the wrench the rest of the robot must receive from outside (the first six rows of a
        floating-base RNEA): the rate of change of the chain's momentum minus its weight.
        """
        return self._root_wrench_fn(q, v, a)

    def contact_rnea(self, frames: tuple[str, ...]) -> ca.Function:
        """The joint forces ``RNEA(q, v, a) - sum_k J_k(q)^T f_k`` with point forces at ``frames``.

        On a floating model its first six entries are the base wrench. The function's inputs are
        ``q``, ``v``, ``a`` and ``f`` (3 per frame, stacked: each force on the robot in world axes
        [N]); its output ``tau`` (nv). What ``pin.rnea`` gives with the same forces as ``fext`` on
        the frames' parent joints.

        Raises:
            ModelError: A frame the model lacks.
        """
        q, v, a = self._sym
        forces = ca.SX.sym("f", 3 * len(frames))
        world = self._world_placements(q)
        external: dict[int, tuple[Expr, Expr]] = {}
        for k, frame in enumerate(frames):
            f = self.model.frames[self._frame_index(frame)]
            joint = int(f.parentJoint)
            local = ca.mtimes(world[joint][0].T, forces[3 * k : 3 * k + 3])
            moment = ca.cross(ca.DM(f.placement.translation), local)
            lin, ang = external.get(joint, (ca.DM.zeros(3, 1), ca.DM.zeros(3, 1)))
            external[joint] = (lin + local, ang + moment)
        tau = self._rnea_parts(q, v, a, True, external)[0]
        name = casadi_name("contact_rnea", *frames)
        return ca.Function(name, [q, v, a, forces], [tau], ["q", "v", "a", "f"], ["tau"])

    def crba(self, q: Any) -> Any:
        """Joint-space mass matrix M(q) (nv x nv), like ``pin.crba`` (full, symmetric)."""
        return self._crba_fn(q)

    def nonlinear_effects(self, q: Any, v: Any) -> Any:
        """``C(q, v) v + G(q)``, like ``pin.nonLinearEffects``."""
        return self._rnea_fn(q, v, ca.DM.zeros(self.nv, 1))

    def gravity(self, q: Any) -> Any:
        """Generalised gravity ``G(q)``, like ``pin.computeGeneralizedGravity``."""
        return self._rnea_fn(q, ca.DM.zeros(self.nv, 1), ca.DM.zeros(self.nv, 1))

    def functions(self, frame: str | int) -> dict[str, ca.Function]:
        """Named compiled functions ``fk`` (q)->(p), ``jacobian`` (q)->(J), ``rnea``, ``crba``."""
        q = self._sym[0]
        return {
            "fk": ca.Function("fk", [q], [self.frame_position(q, frame)], ["q"], ["p"]),
            "jacobian": ca.Function("jacobian", [q], [self.frame_jacobian(q, frame)], ["q"], ["J"]),
            "rnea": self._rnea_fn,
            "crba": self._crba_fn,
        }
