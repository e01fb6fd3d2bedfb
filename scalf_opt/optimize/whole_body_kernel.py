"""The 3-D cycle NLP's function of one read point, compiled once with its derivatives.

Everything nonlinear in the 3-D cycle NLP (:mod:`~scalf_opt.optimize.whole_body_nlp`) but the
friction cones is the whole-body node function
(:meth:`~scalf_opt.energy.whole_body.WholeBodyPhysics.node_function`) at the read points, whose
inputs are linear in the variables (the nodes, and the spline and the forces inside the
intervals), and the NLP's objective and rows are linear in its outputs. So the NLP's derivatives
are assembled from the point's own: the constraint Jacobian from the point's Jacobian, the
Lagrangian's Hessian as ``A' diag(H_p) A`` (``A`` the constant map from the variables to the
points' inputs, ``H_p`` the point's Hessian of ``seed_p' out``, ``seed_p`` the multipliers and
weights that take its outputs) plus the cones' own.

A :class:`PointKernel` holds that function with its Jacobian and Hessian, compiled to native
code once per robot and accounting (:func:`~scalf_opt.energy.codegen.compile_library`, cached on
disk; CasADi's virtual machine without a compiler). Measured on Go1 (then 66 inputs, 114 outputs):
the Hessian at 50 points took 76 ms in the virtual machine and 7.9 ms compiled.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from scalf_opt.energy.codegen import compile_library, load_external
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.optimize.kernels import HEAT_SMOOTHING_EPS_M_S, SYMBOLIC_LOCK
from scalf_opt.types import Accounting, casadi_name


@dataclass(frozen=True)
class PointKernel:
    """The node function of one read point as ``z -> out``, with its derivatives.

    Attributes:
        function: ``z (inputs) -> out (outputs)``: ``z`` stacks the point's coordinates ``X``,
            its rates and second derivatives as their change over one node interval (``h Xd``,
            ``h^2 Xdd``), the four feet's forces [N] and the interval ``h`` [s] (the NLP's
            variables, so that ``z`` is linear in them even when the period is free); ``out``
            stacks every output of the node function, each column-major, in SI units.
        hessian: ``(z, seed) -> d2 (seed' out) / d z2`` (symmetric).
        layout: Each output's name, with its offset in ``out``, rows and columns.
        compiled: The functions run as native code.
    """

    function: ca.Function
    hessian: ca.Function
    layout: tuple[tuple[str, int, int, int], ...]
    compiled: bool

    @property
    def outputs(self) -> int:
        """The size of ``out``."""
        return int(self.function.size1_out(0))

    def named(self, out: ca.MX) -> dict[str, ca.MX]:
        """Outputs ``out`` (``outputs x k``: ``k`` points) by name, as the node function mapped.

        Each is ``rows x (columns k)``, point after point (the layout of
        ``node_function.map(k)``).
        """
        points = out.shape[1]
        return {
            name: ca.reshape(out[offset : offset + rows * cols, :], rows, cols * points)
            for name, offset, rows, cols in self.layout
        }


def point_kernel(physics: WholeBodyPhysics, accounting: Accounting) -> PointKernel:
    """The read point's function of ``physics`` under ``accounting`` (built and compiled once)."""

    def build() -> PointKernel:
        node = physics.node_function(accounting, HEAT_SMOOTHING_EPS_M_S)
        nx = physics.nx
        nf = node.size1_in(3)
        z = ca.SX.sym("z", 3 * nx + nf + 1)
        h = z[-1]
        values = node(z[:nx], z[nx : 2 * nx] / h, z[2 * nx : 3 * nx] / h**2, z[3 * nx : -1])
        layout, offset = [], 0
        for name, value in zip(node.name_out(), values, strict=True):
            layout.append((name, offset, value.shape[0], value.shape[1]))
            offset += value.numel()
        out = ca.vertcat(*(ca.vec(v) for v in values))
        name = casadi_name(physics.robot.name, accounting, "whole_body_point")
        function = ca.Function(name, [z], [out])
        seed = ca.SX.sym("seed", out.numel())
        hessian = ca.Function(f"{name}_hessian", [z, seed], [ca.hessian(ca.dot(seed, out), z)[0]])
        library = compile_library(name, [function, function.jacobian(), hessian])
        compiled_function = load_external(name, library)
        compiled_hessian = load_external(hessian.name(), library)
        if compiled_function is None or compiled_hessian is None:
            return PointKernel(function, hessian, tuple(layout), False)
        return PointKernel(compiled_function, compiled_hessian, tuple(layout), True)

    with SYMBOLIC_LOCK:
        return physics.built.get(("point kernel", accounting), build)
