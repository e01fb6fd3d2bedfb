"""The 3-D cycle NLP's assembled derivatives against CasADi's own, and its compiled kernel."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize import whole_body_kernel
from scalf_opt.optimize.whole_body_nlp import (
    NO_PARAMETERS,
    CycleProblem,
    build_cycle_nlp,
    kinematic_start,
)
from scalf_opt.robots.loading import load_robot


def _problem(physics: WholeBodyPhysics) -> CycleProblem:
    gait = default_gait_for(physics.robot)
    return CycleProblem(
        physics,
        trot_schedule(gait.period_s, 0.5, 20.0),
        gait.speed_m_s,
        gait.stance_height_m,
        gait.clearance_m,
        accounting="paper",
        # the period free: every term of the fixed period's NLP, and the interval's own
        period_range_s=(0.7 * gait.period_s, 1.5 * gait.period_s),
    )


@pytest.fixture(scope="module")
def nlps():
    """Go1's cycle NLP with its compiled kernel, and the same NLP on CasADi's virtual machine."""
    robot = load_robot("go1")
    compiled = build_cycle_nlp(
        problem := _problem(WholeBodyPhysics.of(robot)), kinematic_start(problem)
    )
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(whole_body_kernel, "compile_library", lambda *_: None)
        plain_problem = _problem(WholeBodyPhysics.of(robot))
        plain = build_cycle_nlp(plain_problem, kinematic_start(plain_problem))
    return compiled, plain


def test_the_point_kernel_is_compiled_where_a_compiler_is(nlps):
    compiled, plain = nlps
    physics = compiled.problem.physics
    assert whole_body_kernel.point_kernel(physics, "paper").compiled
    assert not whole_body_kernel.point_kernel(plain.problem.physics, "paper").compiled


def test_assembled_jacobian_and_hessian_are_casadi_s_own(nlps):
    """At a perturbed start and random multipliers, the hand-assembled derivatives (compiled
    kernel) equal CasADi's automatic differentiation of the whole NLP (virtual machine) to
    round-off: the assembly's ``A' diag(H_p) A`` plus the cones' Hessian misses no term."""
    compiled, plain = nlps
    rng = np.random.default_rng(7)
    w = compiled.w0 + 1e-3 * rng.standard_normal(compiled.w0.size)
    lam_g = rng.standard_normal(compiled.constraints.numel())
    lam_f = ca.MX.sym("lam_f")
    lam = ca.MX.sym("lam_g", plain.constraints.numel())
    lagrangian = lam_f * plain.objective + ca.dot(lam, plain.constraints)
    w_sym = plain.variables
    reference = ca.Function(
        "reference",
        [w_sym, lam_f, lam],
        [
            plain.objective,
            plain.constraints,
            ca.jacobian(plain.constraints, w_sym),
            ca.triu(ca.hessian(lagrangian, w_sym)[0]),
        ],
    )(w, 1.3, lam_g)
    f, g = ca.Function("fg", [compiled.variables], [compiled.objective, compiled.constraints])(w)
    jac = compiled.derivatives["jac_g"](w, ca.DM.zeros(NO_PARAMETERS.shape))[1]
    hess = compiled.derivatives["hess_lag"](w, ca.DM.zeros(NO_PARAMETERS.shape), 1.3, lam_g)
    for mine, theirs in zip((f, g, jac, hess), reference, strict=True):
        mine, theirs = np.array(ca.densify(mine)), np.array(ca.densify(theirs))
        assert np.abs(mine - theirs).max() <= 1e-12 * max(np.abs(theirs).max(), 1.0)
    assert np.abs(np.array(ca.densify(reference[3]))).max() > 1.0  # a Hessian worth comparing
