"""The swing optimization as a smooth NLP, built with CasADi and solved by Ipopt.

Built from :meth:`SwingProblem.graph` (the evaluator's own expressions), with two smooth
reformulations of the non-smooth energy:

* ``|tau_i qd_i|`` at every sample becomes a slack pair: ``s+ - s- = tau qd``, ``s+, s- >= 0``,
  and the objective charges ``s+ + s-``; at an optimum one of the two is zero, so the objective
  equals the exact mechanical energy (only for joints whose drive charges its mechanical power;
  a drive that meters its own input power, valve-controlled or electric, has no slacks);
* the drives' losses (SCalf: the friction heat) take ``max(v, 0)`` as
  ``(v + sqrt(v^2 + eps^2)) / 2`` with
  ``eps = HEAT_SMOOTHING_EPS_M_S``.

Constraints at every swing sample: joint limits, bounded drive outputs (SCalf: the cylinder
stroke), foot at or above the ground
(interior samples; lift-off and touch-down are on the ground by construction), the IK reach in
foot space, and the mid-swing clearance. Derivatives (gradient, constraint Jacobian, Lagrangian
Hessian) are exact, from CasADi's automatic differentiation.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from scalf_opt.energy.physics import mechanical_power, trapezoid_weights
from scalf_opt.optimize.problem import HEAT_SMOOTHING_EPS_M_S, SwingProblem, casadi_name
from scalf_opt.types import Expr

IPOPT_DEFAULTS: dict[str, Any] = {
    "tol": 1e-10,
    "acceptable_tol": 1e-8,
    "max_iter": 3000,
    "print_level": 0,
    "sb": "yes",
    "mu_strategy": "adaptive",
    # keep every bound exact: Ipopt relaxes bounds by 1e-8 by default, and the exact evaluator
    # judges feasibility at 1e-9
    "bound_relax_factor": 0.0,
    "constr_viol_tol": 1e-10,
}


@dataclass
class NlpBuild:
    """A built NLP: the CasADi solver and the bounds and layout it needs."""

    solver: ca.Function
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    n_theta: int
    n_samples: int
    p_mech: ca.Function  # theta -> signed mechanical power of the slack rows, for initial guesses


def build_nlp(problem: SwingProblem, ipopt_options: dict[str, Any] | None = None) -> NlpBuild:
    """Build the NLP of ``problem`` (no solving)."""
    n_theta = problem.n_params
    n = problem.path.t_s.size
    theta = ca.SX.sym("theta", n_theta)
    g = problem.graph(theta, HEAT_SMOOTHING_EPS_M_S)
    weights = np.tile(trapezoid_weights(problem.path.t_s), 2)
    w = ca.DM(weights)
    p_mech = ca.reshape(g["p_mech"].T, 2 * n, 1)  # column-major: all hip samples, then knee
    loss = ca.reshape(g["p_loss"].T, 2 * n, 1)
    # 1 where the joint's drive charges its mechanical power, 0 where it does not (a drive that
    # meters its own input power: its loss rate is all it draws)
    charged_rows = np.repeat([d.charges_joint_power for d in problem.physics.drives], n)
    charged = ca.DM(charged_rows.astype(float))
    accounting = problem.pipeline.accounting
    # the slack pair is the paper's |tau qd|, for the charged rows only (a slack without a cost
    # would leave Ipopt a free direction); the other accountings need no slacks
    paper = accounting == "paper"
    rows = np.flatnonzero(charged_rows).tolist() if paper else []
    s_pos = ca.SX.sym("s_pos", len(rows))
    s_neg = ca.SX.sym("s_neg", len(rows))
    p_slack = p_mech[rows] if rows else ca.SX(0, 1)
    if paper:
        objective = ca.dot(ca.DM(weights[rows]), s_pos + s_neg) + ca.dot(w, loss)
    else:
        objective = ca.dot(w, charged * mechanical_power(p_mech, accounting) + loss)

    constraints, lower, upper = [], [], []

    def add(expr: Expr, lo: np.ndarray | float, hi: np.ndarray | float) -> None:
        size = expr.numel()
        constraints.append(ca.reshape(expr, size, 1))
        lower.append(np.broadcast_to(np.asarray(lo, dtype=float), (size,)).ravel())
        upper.append(np.broadcast_to(np.asarray(hi, dtype=float), (size,)).ravel())

    if rows:
        add(s_pos - s_neg - p_slack, 0.0, 0.0)
    q_lo, q_hi = problem.joint_bounds
    add(
        g["q"],
        np.repeat(q_lo, n, axis=1).ravel(order="F"),
        np.repeat(q_hi, n, axis=1).ravel(order="F"),
    )
    for name, (lo, hi) in problem.output_bounds.items():
        add(g[name], lo, hi)
    add(g["foot"][1, 1:-1], problem.ground_z_m, np.inf)
    if "reach" in g:
        add(g["reach"], -1.0, 1.0)
    add(g["foot"][1, problem.mid_index], problem.clearance_z_m, np.inf)

    x = ca.vertcat(theta, s_pos, s_neg)
    options: dict[str, Any] = {
        "ipopt": {**IPOPT_DEFAULTS, **(ipopt_options or {})},
        "print_time": False,
    }
    solver = ca.nlpsol(
        casadi_name(problem.leg, problem.family.name, "nlp"),
        "ipopt",
        {"x": x, "f": objective, "g": ca.vertcat(*constraints)},
        options,
    )
    n_slack = 2 * len(rows)
    lbx = np.concatenate([np.full(n_theta, -np.inf), np.zeros(n_slack)])
    ubx = np.full(n_theta + n_slack, np.inf)
    return NlpBuild(
        solver=solver,
        lbx=lbx,
        ubx=ubx,
        lbg=np.concatenate(lower),
        ubg=np.concatenate(upper),
        n_theta=n_theta,
        n_samples=n,
        p_mech=ca.Function("p_mech", [theta], [p_slack]),
    )


@dataclass
class NlpSolution:
    """Ipopt's answer.

    Attributes:
        theta: Parameters at Ipopt's final iterate (family units).
        success: Ipopt reported a solved problem.
        status: Ipopt's return status.
        iterations: Ipopt iterations.
        objective_j: Smooth objective at the final iterate [J].
        wall_time_s: Time spent in the solver [s].
        stats: Ipopt's statistics as returned by CasADi.
    """

    theta: np.ndarray
    success: bool
    status: str
    iterations: int
    objective_j: float
    wall_time_s: float
    stats: dict[str, Any]


def solve_nlp(build: NlpBuild, theta0: np.ndarray) -> NlpSolution:
    """Solve a built NLP from ``theta0`` (slacks initialised consistently)."""
    theta0 = np.asarray(theta0, dtype=float)
    x0 = theta0
    if build.lbx.size > build.n_theta:
        pm = np.array(build.p_mech(theta0)).ravel()
        x0 = np.concatenate([theta0, np.maximum(pm, 0.0), np.maximum(-pm, 0.0)])
    start = time.perf_counter()
    sol = build.solver(x0=x0, lbx=build.lbx, ubx=build.ubx, lbg=build.lbg, ubg=build.ubg)
    elapsed = time.perf_counter() - start
    stats = build.solver.stats()
    return NlpSolution(
        theta=np.array(sol["x"]).ravel()[: build.n_theta],
        success=bool(stats.get("success", False)),
        status=str(stats.get("return_status", "unknown")),
        iterations=int(stats.get("iter_count", -1)),
        objective_j=float(sol["f"]),
        wall_time_s=elapsed,
        stats={k: v for k, v in stats.items() if isinstance(v, int | float | str | bool)},
    )
