r"""One periodic trot cycle of the whole robot in 3-D as one NLP, solved by Ipopt.

Variables, at each node ``k`` of the :class:`~scalf_opt.locomotion.contact_schedule.TrotSchedule`:
the coordinates ``X_k`` (trunk position and roll-pitch-yaw, every actuated joint), their rates and
second derivatives, the four feet's contact forces (world axes; zero in swing and at touch-down
and lift-off, linear in between: the C2 motion of the trunk asks for a continuous total force,
and a foot that lands or lifts off while others carry can bring no jump of force), each foot's
foothold ``(x, y)``, and the accounting's slacks.

Constraints:

* **the trajectory**: a periodic C2 cubic spline through the nodes
  (:func:`~scalf_opt.locomotion.periodic_spline.continuity_rows`); node ``N`` is node ``0`` moved
  forward by the stride ``v T`` (average speed ``v``); the trunk starts at ``x = y = 0``;
* **the dynamics**: the floating-base inverse dynamics leaves the trunk no wrench at any node
  (six rows, over the weight and the weight times the stance height);
* **the contacts**: a stance foot stands on its foothold on the flat ground ``z = 0`` with zero
  velocity (at every stance node, touch-down and lift-off included); its force lies in the
  friction cone ``\sqrt{f_x^2 + f_y^2} \le \mu f_z`` (rounded at its axis, :data:`CONE_SMOOTHING`);
* **the swing**: the foot at least the lift profile's height above the ground over the first and
  last share of the swing and in between (:class:`~scalf_opt.energy.margins.LiftProfile`), at least
  the clearance ``H`` at mid-swing, landing no faster than the profile's touch-down speed; each
  foot keeps to its side of the trunk (at least half its start's lateral offset from the trunk's
  midline: the legs cannot cross);
* **the limits**: every joint's range, velocity and effort limit and every drive bound, less the
  margins (:class:`~scalf_opt.energy.margins.LimitMargins`), at every read point of the schedule
  (:attr:`~scalf_opt.locomotion.contact_schedule.TrotSchedule.read_points`; by default the
  nodes, and the quarter points and midpoints of the intervals; there the spline's value and the
  forces interpolated linearly); the swing feet's floor too.

Objective: the drive energy of every joint over the cycle by composite Simpson's rule on the read
points (by default on the half intervals: their drawn power, the accounting's
slack form of the charged joint power plus the drives' losses, smoothed as in the sagittal NLP),
over the start's energy. Read at the nodes alone, a joint could rest at every node and move between
them for free; read at the nodes and midpoints only (Simpson's rule on whole intervals, this model's
first version), SCalf's optimum kept torque or rate near zero at those points and its energy at ten
times the rate was still 5 % higher on 26 nodes and 3.7 % on 50 (with the quarter points read too:
2.0 % and 0.8 %). The dynamics are not imposed inside the intervals: there the trunk's rows are
nearly the mean of the neighbouring nodes' (forces and trunk acceleration are both linear in
between), and such nearly dependent rows stall Ipopt (measured: the multipliers grew to 1e10 and the
energy fourfold); the ten-times check reports what is left between the nodes.

Derivatives: everything nonlinear but the cones is the node function at the read points, so the
constraint Jacobian and the Lagrangian's Hessian are assembled from that function's compiled
ones (:mod:`~scalf_opt.optimize.whole_body_kernel`); CasADi's own, expanded over the whole NLP,
took 24 s to build and 90 ms per Hessian on Go1's 10 nodes (2 s and 4 ms compiled).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import casadi as ca
import numpy as np

from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.margins import DEFAULT_MARGINS, LimitMargins
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.locomotion.contact_schedule import DEFAULT_FRICTION, TrotSchedule
from scalf_opt.locomotion.periodic_spline import continuity_rows, inner_points, interval_points
from scalf_opt.optimize.block_derivatives import block_diagonal, mapped_with_block_jacobian
from scalf_opt.optimize.nlp import MUMPS_WORK_SPACE
from scalf_opt.optimize.whole_body_kernel import PointKernel, point_kernel
from scalf_opt.optimize.whole_body_start import starting_plan
from scalf_opt.types import LEG_NAMES, Accounting

SIDE_SHARE = 0.5
"""A foot's smallest lateral offset from the trunk's midline, as a share of its start's."""

BASE_TILT_BOUND_RAD = 0.6
"""The trunk's roll, pitch and yaw stay within this [rad] (far from the pitch singularity)."""

REFERENCE_ENERGY_WEIGHT = 1e-3
"""The energy's weight (over the start's) beside the deviation from the reference when the
objective is ``"reference"``: it settles what the deviation leaves free (the slacks, the forces'
split) without trading the reference for energy."""

OBJECTIVE_SCALING = 1e3
"""Ipopt's factor on the objective (the energy over the start's).

Without it each variable's share of the objective's gradient is about 1e-4 (the energy is spread
over every read point's power), small beside the dynamics' curvature: Ipopt then
regularised the Hessian at every iteration and crept (SCalf on 12 nodes: 1,500 iterations, the
energy still falling by 1 % every 20). Scaled by 1e3 the same solve converged in 396 iterations
at 156 J instead of 257 J."""

CONE_SMOOTHING = 1e-4
"""The friction cone's rounding, as a share of the weight.

A stance force ``f`` (over the weight ``W``) keeps ``mu f_z >= sqrt(f_x^2 + f_y^2 + eps^2)``: a
concave row, so the cone is convex in the NLP's eyes, and smooth at its axis; the rounding
keeps it inside the exact cone (``f_z >= eps W / mu``). The first version's
``mu^2 f_z^2 - f_x^2 - f_y^2 >= 0`` (a row in N^2, 1e8 on SCalf) is the double cone, not convex:
its curvature made Ipopt regularise its Hessian at every iteration, and Go1's flying trot crept
(its first grid unfinished after 36 minutes; 50 s with this row and the compiled point kernel)."""

MUMPS_ORDERING = 0
"""MUMPS's fill-reducing ordering: approximate minimum degree. Go1 on 10 nodes: 10 s instead of
18 s with MUMPS's automatic choice (the KKT factorizations are most of the solve)."""

IPOPT_DEFAULTS: dict[str, Any] = {
    "obj_scaling_factor": OBJECTIVE_SCALING,
    "tol": 1e-6,
    "constr_viol_tol": 1e-8,
    "mu_strategy": "adaptive",
    "mumps_pivot_order": MUMPS_ORDERING,
    "acceptable_tol": 1e-4,
    "acceptable_constr_viol_tol": 1e-8,
    "acceptable_obj_change_tol": 1e-5,
    "acceptable_iter": 10,
    "max_iter": 3000,
    "print_level": 0,
    "sb": "yes",
    **MUMPS_WORK_SPACE,
}


@dataclass(frozen=True)
class CycleProblem:
    """A 3-D trot cycle to optimise.

    Attributes:
        physics: The robot's 3-D model.
        schedule: The contact schedule and node grid.
        speed_m_s: The average forward speed [m/s].
        stance_height_m: The pitching hips' height above the ground at the start [m].
        clearance_m: The swing foot's least height at mid-swing, H [m].
        friction: The friction coefficient of the contact cones.
        margins: How far inside its limits and above the ground the plan stays.
        accounting: How joint power is charged.
        period_range_s: The period's bounds ``(shortest, longest)`` [s] when the period is free
            (a decision variable, ``schedule.period_s`` its start); ``None`` fixes it. The
            duty factor and the node count stay the schedule's.
        objective: ``"energy"`` (the drive energy, the optimum) or ``"reference"``: the
            balanced motion nearest the kinematic reference trot (:func:`kinematic_start`),
            the mean squared deviation of the coordinates from it (trunk position over the
            stance height, angles in rad), the energy over the start's a tie-breaker weighted
            :data:`REFERENCE_ENERGY_WEIGHT` (what ``evaluate --model 3d`` reports).
    """

    physics: WholeBodyPhysics
    schedule: TrotSchedule
    speed_m_s: float
    stance_height_m: float
    clearance_m: float
    friction: float = DEFAULT_FRICTION
    margins: LimitMargins = field(default=DEFAULT_MARGINS)
    accounting: Accounting = "paper"
    period_range_s: tuple[float, float] | None = None
    objective: Literal["energy", "reference"] = "energy"

    def step_bounds_s(self) -> tuple[float, float]:
        """The node interval's bounds [s]: the period's over the node count."""
        n = self.schedule.intervals
        if self.period_range_s is None:
            return self.schedule.step_s, self.schedule.step_s
        shortest, longest = self.period_range_s
        return shortest / n, longest / n


@dataclass(frozen=True)
class CycleSolution:
    """What Ipopt made of a :class:`CycleProblem`.

    Attributes:
        plan: The last iterate as a plan (the optimum when ``success``).
        start: The plan it started from.
        success: Ipopt converged to its tolerances.
        status: Ipopt's return status.
        iterations: Ipopt's iterations.
        solve_s: Wall time of the solve [s].
    """

    plan: WholeBodyPlan
    start: WholeBodyPlan
    success: bool
    status: str
    iterations: int
    solve_s: float


@dataclass
class _Rows:
    """Constraint rows with their bounds, appended block by block."""

    g: list[ca.MX] = field(default_factory=list)
    lower: list[np.ndarray] = field(default_factory=list)
    upper: list[np.ndarray] = field(default_factory=list)
    names: list[str] = field(default_factory=list)

    def add(
        self, rows: ca.MX, lower: float | np.ndarray, upper: float | np.ndarray, name: str = ""
    ) -> None:
        rows = ca.vec(rows)
        n = rows.shape[0]
        self.names += [name] * n
        self.g.append(rows)
        self.lower.append(np.broadcast_to(np.asarray(lower, dtype=float).ravel(), (n,)).copy())
        self.upper.append(np.broadcast_to(np.asarray(upper, dtype=float).ravel(), (n,)).copy())


def lift_floor_m(problem: CycleProblem, phase: float) -> float:
    """The swing foot's least height [m] at swing phase ``phase`` in (0, 1)."""
    lift = problem.margins.lift
    height = lift.height_for(problem.clearance_m)
    edge = min(phase, 1 - phase) / lift.fraction
    return height * min(edge, 1.0) ** 2


@dataclass(frozen=True)
class CycleNlp:
    """The NLP of a :class:`CycleProblem`, built for Ipopt.

    Attributes:
        problem: What it optimises.
        variables: Every decision variable, scaled to order one (see :meth:`plan_of`).
        objective: The energy over the start's (Simpson's rule on the half intervals).
        constraints: Every constraint row.
        row_names: Each row's block name (``"RF cone"``, ``"base force"``, ...).
        lbw, ubw: The variables' bounds (scaled).
        lbg, ubg: The rows' bounds.
        w0: The start, scaled and clipped into the bounds.
        shapes: The shapes of the first six blocks of ``variables`` (coordinates, their rates
            and second derivatives as their change over one node interval ``h``, forces over
            the weight, footholds, and the period over the start's ``T / T0``); the slacks
            follow.
        scales: The first five blocks' factors from SI units to ``variables``' units at the
            start's interval ``h0`` (the rates' is ``h``, the solution's own).
        derivatives: ``nlpsol`` options giving the constraint Jacobian and the Lagrangian's
            Hessian assembled from the read point's compiled ones
            (:mod:`~scalf_opt.optimize.whole_body_kernel`); the NLP has no parameters.
    """

    problem: CycleProblem
    variables: ca.MX
    objective: ca.MX
    constraints: ca.MX
    row_names: tuple[str, ...]
    lbw: np.ndarray
    ubw: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    w0: np.ndarray
    shapes: tuple[tuple[int, int], ...]
    scales: tuple[float, ...]
    derivatives: dict[str, ca.Function]

    def plan_of(self, w: np.ndarray) -> WholeBodyPlan:
        """The plan a (scaled) variable vector ``w`` stands for (its slacks dropped)."""
        sizes = [r * c for r, c in self.shapes]
        parts = np.split(np.asarray(w, dtype=float).ravel(), np.cumsum(sizes))
        x, steps, bends, shares, holds, stretch = (
            p.reshape(shape, order="F") for p, shape in zip(parts[:6], self.shapes, strict=True)
        )
        problem = self.problem
        schedule = problem.schedule
        h = schedule.step_s * float(stretch[0, 0])
        return WholeBodyPlan(
            problem.physics,
            replace(schedule, period_s=h * schedule.intervals),
            problem.speed_m_s,
            x,
            steps / h,
            bends / h**2,
            shares / self.scales[3],
            holds,
        )


def build_cycle_nlp(problem: CycleProblem, start: WholeBodyPlan) -> CycleNlp:
    """The NLP of the module docstring, from ``start``."""
    physics, schedule = problem.physics, problem.schedule
    n, nx, nf = schedule.intervals, physics.nx, 3 * len(LEG_NAMES)
    h0 = schedule.step_s  # the start's node interval
    h_lo, h_hi = problem.step_bounds_s()
    acc = power_accounting(problem.accounting)
    charging = [j for j, d in enumerate(physics.drives) if d.charges_joint_power]

    weight = physics.weight_n
    # the variables are scaled to order one: rates and second derivatives as their change over
    # one interval (h Xd, h^2 Xdd), forces over the weight, the interval over the start's; so
    # the read points' inputs are linear in them, the period free or not
    x, steps, bends = (ca.MX.sym(name, nx, n) for name in ("X", "h_Xd", "h2_Xdd"))
    shares = ca.MX.sym("f_over_weight", nf, n)
    holds = ca.MX.sym("footholds", 2, len(LEG_NAMES))
    stretch = ca.MX.sym("period_over_start")
    h = h0 * stretch
    # the slacks of the read points: the nodes (first n columns), then each inner point's
    read = schedule.read_points
    points = len(read)
    slacks = [ca.MX.sym(f"s{m}", len(charging), points * n) for m in range(acc.slacks)]
    blocks = [x, steps, bends, shares, holds, stretch, *slacks]
    forces = shares * weight
    scales = (1.0, h0, h0**2, 1.0 / weight, 1.0)

    stride = problem.speed_m_s * n * h
    shift = ca.DM(physics.stride_shift(1.0)) * stride
    # the read points' inputs, nodes first, then each inner point's, and a symbol standing for
    # the kernel's outputs there (its call is substituted at the end: _with_point_derivatives);
    # the spline in scaled rates is the spline on a unit interval
    kernel = point_kernel(physics, problem.accounting)
    inner_states = {f: inner_points(x, steps, bends, 1.0, shift, f) for f, _ in read[1:]}
    interval = ca.repmat(h, 1, n)
    point_inputs = ca.horzcat(
        ca.vertcat(x, steps, bends, forces, interval),
        *(ca.vertcat(*inner_states[f], interval_points(forces, f), interval) for f in inner_states),
    )
    stand_in = ca.MX.sym("point_outputs", kernel.outputs, point_inputs.shape[1])
    out = kernel.named(stand_in[:, :n])
    inner = {
        f: (states, kernel.named(stand_in[:, (j + 1) * n : (j + 2) * n]))
        for j, (f, states) in enumerate(inner_states.items())
    }
    rows = _Rows()
    values, rates = continuity_rows(x, steps, bends, 1.0, shift)
    rows.add(values, 0.0, 0.0, "spline values")
    rows.add(rates, 0.0, 0.0, "spline rates")
    height = problem.stance_height_m
    rows.add(out["base_wrench"][:3, :] / weight, 0.0, 0.0, "base force")
    rows.add(out["base_wrench"][3:, :] / (weight * height), 0.0, 0.0, "base moment")
    _limit_rows(problem, rows, out)
    if h_lo < h_hi:  # the rates' bounds move with the interval: rows, not bounds
        _rate_rows(problem, rows, steps / h, "")
    for fraction, (states, outputs) in inner.items():
        _limit_rows(problem, rows, outputs, f" (at {fraction:g})")
        _inner_range_rows(problem, rows, (states[0], states[1] / h), fraction)
    _contact_rows(problem, rows, out, inner, x, shares, holds, stride, h / h0, start)
    bounds = _variable_bounds(problem, start)
    # composite Simpson's rule on the read points (the schedule's): each reading's weight times h
    power = ca.horzcat(
        out["p_joint"][charging, :], *(o["p_joint"][charging, :] for _, o in inner.values())
    )
    loss = ca.horzcat(out["loss"], *(o["loss"] for _, o in inner.values()))
    if acc.slacks:
        slack_rows = acc.slack_rows(power, slacks)
        assert slack_rows is not None  # an accounting with slacks has their rows
        rows.add(slack_rows, *acc.slack_row_bounds(), "slacks")
    cost = ca.sum1(acc.smooth_cost(power, slacks)) + ca.sum1(loss)
    scale = max(start.evaluate(problem.accounting).total_j, 1e-6)
    weights = np.repeat([w for _, w in read], n)
    # the mean drawn power times the start's period (the energy per cycle at a fixed period;
    # with the period free, the energy per distance at the given speed, as a cost of transport)
    objective = ca.mtimes(cost, ca.DM(weights)) * (h0 / scale)
    if problem.objective == "reference":
        objective = _reference_deviation(problem, x) + REFERENCE_ENERGY_WEIGHT * objective

    start_power = np.hstack(
        [start.node_outputs(problem.accounting)["p_joint"]]
        + [start.inner_outputs(problem.accounting, f)["p_joint"] for f, _ in read[1:]]
    )
    start_slacks = acc.initial_slacks(start_power[charging])
    start_blocks = (start.x, start.xd, start.xdd, start.forces_n, start.footholds_m)
    w0 = np.concatenate(
        [np.ravel(b * c, order="F") for b, c in zip(start_blocks, scales, strict=True)]
        + [np.ones(1)]
        + [np.ravel(b, order="F") for b in start_slacks]
    )
    # the rates' bounds at the longest interval (the rows hold them exactly when it is free)
    lbw, ubw = _scaled(bounds, blocks, (1.0, h_hi, h0**2, 1.0 / weight, 1.0, 1.0 / h0))
    variables = ca.veccat(*blocks)
    objective, constraints, derivatives = _with_point_derivatives(
        kernel, variables, objective, ca.vertcat(*rows.g), stand_in, point_inputs
    )
    return CycleNlp(
        problem,
        variables,
        objective,
        constraints,
        tuple(rows.names),
        lbw,
        ubw,
        np.concatenate(rows.lower),
        np.concatenate(rows.upper),
        np.clip(w0, lbw, ubw),
        tuple(b.shape for b in blocks[:6]),
        scales,
        derivatives,
    )


def _reference_deviation(problem: CycleProblem, x: ca.MX) -> ca.MX:
    """The mean squared deviation of the coordinates ``x`` (nx, N) from the kinematic reference.

    At the nodes: the trunk's position over the stance height, its angles and the joints' [rad].
    """
    reference = kinematic_start(problem)
    scale = np.ones((problem.physics.nx, 1))
    scale[:3] = problem.stance_height_m
    deviation = (x - ca.DM(reference.x)) / ca.repmat(ca.DM(scale), 1, x.shape[1])
    return ca.sumsqr(deviation) / x.shape[1]


def kinematic_start(problem: CycleProblem) -> WholeBodyPlan:
    """The problem's kinematic reference trot (:func:`starting_plan`), the default start."""
    return starting_plan(
        problem.physics,
        problem.schedule,
        problem.speed_m_s,
        problem.stance_height_m,
        problem.clearance_m,
    )


def solve_cycle(
    problem: CycleProblem, start: WholeBodyPlan | None = None, ipopt: dict[str, Any] | None = None
) -> CycleSolution:
    """Optimise one cycle (module docstring) from ``start`` (default :func:`kinematic_start`)."""
    start = kinematic_start(problem) if start is None else start
    nlp = build_cycle_nlp(problem, start)
    options = {**IPOPT_DEFAULTS, **(ipopt or {})}
    solver = ca.nlpsol(
        "whole_body_cycle",
        "ipopt",
        {"x": nlp.variables, "p": NO_PARAMETERS, "f": nlp.objective, "g": nlp.constraints},
        {"ipopt": options, "print_time": False, **nlp.derivatives},
    )
    began = time.perf_counter()
    result = solver(x0=nlp.w0, lbx=nlp.lbw, ubx=nlp.ubw, lbg=nlp.lbg, ubg=nlp.ubg)
    elapsed = time.perf_counter() - began
    stats = solver.stats()
    return CycleSolution(
        nlp.plan_of(np.array(result["x"])),
        start,
        bool(stats["success"]),
        str(stats["return_status"]),
        int(stats["iter_count"]),
        elapsed,
    )


NO_PARAMETERS = ca.MX.sym("p", 0, 1)
"""The cycle NLP's parameters: none (the derivative functions' second input)."""


def _with_point_derivatives(
    kernel: PointKernel,
    w: ca.MX,
    objective_z: ca.MX,
    g_z: ca.MX,
    stand_in: ca.MX,
    point_inputs: ca.MX,
) -> tuple[ca.MX, ca.MX, dict[str, ca.Function]]:
    """The objective and rows with the kernel's call for ``stand_in``, and their derivatives.

    ``objective_z`` and ``g_z`` are written on ``stand_in`` (the kernel's outputs at every read
    point, ``point_inputs``' columns), linear in it. The constraint Jacobian is CasADi's, through
    the kernel's mapped call whose Jacobian is the block diagonal of the points' compiled ones;
    the Lagrangian's Hessian is ``A' diag(H_p) A`` (``A`` the constant Jacobian of the points'
    inputs in ``w``, ``H_p`` each point's compiled Hessian of ``seed_p' out`` with
    ``seed = dL/d stand_in``) plus the Hessian of what is nonlinear in ``w`` alone (the cones).
    """
    points = point_inputs.shape[1]
    n_out = kernel.outputs
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g_z.numel())
    lagrangian = lam_f * objective_z + ca.dot(lam_g, g_z)
    seed = ca.jacobian(lagrangian, ca.vec(stand_in)).T
    if ca.depends_on(seed, ca.vertcat(ca.vec(stand_in), w)):
        raise AssertionError("the cycle NLP must be linear in its read points' outputs")
    inputs = ca.vec(point_inputs)
    jac_inputs = ca.jacobian(inputs, w)
    if ca.depends_on(jac_inputs, w):
        raise AssertionError("the read points' inputs must be linear in the variables")
    a = ca.Function("point_map", [w], [jac_inputs])(ca.DM.zeros(w.numel()))

    mapped = mapped_with_block_jacobian(kernel.function, points, f"{kernel.function.name()}_points")
    call = ca.reshape(mapped(inputs), n_out, points)
    objective, g = ca.substitute([objective_z, g_z], [stand_in], [call])
    h_blocks = kernel.hessian.map(points, "serial")(point_inputs, ca.reshape(seed, n_out, points))
    lifted = block_diagonal(h_blocks, kernel.hessian.sparsity_out(0), points)
    explicit = ca.hessian(lagrangian, w)[0]  # at fixed outputs: the cones
    hessian = ca.mtimes(a.T, ca.mtimes(lifted, a)) + explicit
    p = NO_PARAMETERS
    return (
        objective,
        g,
        {
            "jac_g": ca.Function(
                "whole_body_cycle_jac_g",
                [w, p],
                [g, ca.jacobian(g, w)],
                ["x", "p"],
                ["g", "jac_g_x"],
            ),
            "hess_lag": ca.Function(
                "whole_body_cycle_hess_lag",
                [w, p, lam_f, lam_g],
                [ca.triu(hessian)],
                ["x", "p", "lam_f", "lam_g"],
                ["triu_hess_gamma_x_x"],
            ),
        },
    )


def _scaled(
    bounds: tuple[np.ndarray, np.ndarray], blocks: list[ca.MX], scales: tuple[float, ...]
) -> tuple[np.ndarray, np.ndarray]:
    """The variables' bounds in the NLP's scaled units (the first blocks scaled, slacks not)."""
    factor = np.concatenate(
        [np.full(b.numel(), c) for b, c in zip(blocks, scales, strict=False)]
        + [np.ones(b.numel()) for b in blocks[len(scales) :]]
    )
    return bounds[0] * factor, bounds[1] * factor


def _contact_rows(
    problem: CycleProblem,
    rows: _Rows,
    out: dict[str, ca.MX],
    inner: dict[float, tuple[Any, dict[str, ca.MX]]],
    x: ca.MX,
    shares: ca.MX,
    holds: ca.MX,
    stride: ca.MX,
    stretch: ca.MX,
    start: WholeBodyPlan,
) -> None:
    """Stance feet on their footholds at rest, friction cones, swing heights, sides.

    ``stride`` [m] and ``stretch`` (the period over the start's) are expressions of the variables.
    """
    schedule = problem.schedule
    n = schedule.intervals
    feet_pos, feet_vel = out["feet_pos"], out["feet_vel"]
    lift = problem.margins.lift
    swing_s = schedule.period_s * (1 - schedule.duty_cycle)
    landing = lift.touchdown_speed_for(problem.clearance_m, swing_s)
    # the bound at the plan's own swing time (a period of its own when free)
    landing_now = lift.touchdown_speed_for(problem.clearance_m, swing_s * stretch)
    start_lateral = np.abs(start.footholds_m[1])
    for i, leg in enumerate(LEG_NAMES):
        stance = np.flatnonzero(schedule.stance[i])
        columns = [int(4 * k + i) for k in stance]
        back = schedule.previous_stance[i, stance].astype(float)
        target = ca.vertcat(
            ca.repmat(holds[0, i], 1, len(stance)) - stride * ca.DM(back).T,
            ca.repmat(holds[1, i], 1, len(stance)),
            ca.DM.zeros(1, len(stance)),
        )
        rows.add(feet_pos[:, columns] - target, 0.0, 0.0, f"{leg} stance position")
        # the cones where the foot may carry (its force is held at zero at touch-down and
        # lift-off, where a cone row would be identically zero: a degenerate row)
        loaded = shares[3 * i : 3 * i + 3, np.flatnonzero(schedule.loaded[i])]
        tangential = ca.sqrt(loaded[0, :] ** 2 + loaded[1, :] ** 2 + CONE_SMOOTHING**2)
        rows.add(problem.friction * loaded[2, :] - tangential, 0.0, np.inf, f"{leg} cone")
        inside = np.flatnonzero(schedule.stance[i] & np.roll(schedule.stance[i], -1))
        # the swing, at its nodes and inside its intervals (the read points)
        swing = np.flatnonzero(~schedule.stance[i])
        phase = schedule.swing_phase(leg)[swing]
        floor = np.array([lift_floor_m(problem, s) for s in phase])
        middle = int(np.argmin(np.abs(phase - 0.5)))
        floor[middle] = max(floor[middle], problem.clearance_m)
        columns = [int(4 * k + i) for k in swing]
        rows.add(feet_pos[2, columns], floor, np.inf, f"{leg} swing floor")
        airborne = np.setdiff1d(np.arange(n), inside)
        for fraction, (_, outputs) in inner.items():
            inner_phase = schedule.swing_progress(leg, airborne + fraction)
            rows.add(
                outputs["feet_pos"][2, [int(4 * k + i) for k in airborne]],
                np.array([lift_floor_m(problem, s) for s in inner_phase]),
                np.inf,
                f"{leg} swing floor (at {fraction:g})",
            )
        landing_nodes = [c for c, s in zip(columns, phase, strict=True) if s > 1 - lift.fraction]
        if landing_nodes and np.isfinite(landing):
            rows.add(feet_vel[2, landing_nodes] + landing_now, 0.0, np.inf, f"{leg} landing speed")
        side = np.sign(start.footholds_m[1, i])
        lateral = side * (feet_pos[1, [4 * k + i for k in range(n)]] - x[1, :])
        rows.add(lateral, SIDE_SHARE * start_lateral[i], np.inf, f"{leg} side")


def _variable_bounds(problem: CycleProblem, start: WholeBodyPlan) -> tuple[np.ndarray, np.ndarray]:
    """Box bounds of every variable in SI units (the node interval's in seconds).

    In the order of the NLP's blocks, each column-major.
    """
    physics, schedule = problem.physics, problem.schedule
    n, nx = schedule.intervals, physics.nx
    inf = np.inf
    x_lo, x_hi = np.full((nx, n), -inf), np.full((nx, n), inf)
    xd_lo, xd_hi = np.full((nx, n), -inf), np.full((nx, n), inf)
    x_lo[0, 0] = x_hi[0, 0] = 0.0  # the trunk starts at x = y = 0: the cycle's place
    x_lo[1, 0] = x_hi[1, 0] = 0.0
    base_z = float(start.x[2, 0])
    x_lo[2], x_hi[2] = 0.5 * base_z, 1.5 * base_z
    x_lo[3:6], x_hi[3:6] = -BASE_TILT_BOUND_RAD, BASE_TILT_BOUND_RAD
    for bound in problem.margins.apply(physics.joint_bounds()):
        if bound.output == "q":
            x_lo[6 + bound.joint], x_hi[6 + bound.joint] = bound.lower, bound.upper
        elif bound.output == "qd":
            xd_lo[6 + bound.joint], xd_hi[6 + bound.joint] = bound.lower, bound.upper
    free = np.full((nx, n), inf)
    f_lo, f_hi = np.zeros((3 * len(LEG_NAMES), n)), np.zeros((3 * len(LEG_NAMES), n))
    for i in range(len(LEG_NAMES)):
        f_lo[3 * i : 3 * i + 2, schedule.loaded[i]] = -inf
        f_hi[3 * i : 3 * i + 3, schedule.loaded[i]] = inf
    acc = power_accounting(problem.accounting)
    charging = sum(d.charges_joint_power for d in physics.drives)
    slack = np.zeros(acc.slacks * charging * len(schedule.read_points) * n)  # per read point
    h_lo, h_hi = problem.step_bounds_s()
    holds = np.full(2 * len(LEG_NAMES), inf)
    lower = [x_lo, xd_lo, -free, f_lo, -holds, np.array([h_lo]), slack]
    upper = [x_hi, xd_hi, free, f_hi, holds, np.array([h_hi]), slack + inf]
    return (
        np.concatenate([np.ravel(b, order="F") for b in lower]),
        np.concatenate([np.ravel(b, order="F") for b in upper]),
    )


def _rate_rows(problem: CycleProblem, rows: _Rows, rates: ca.MX, where: str) -> None:
    """Every joint's velocity limit (less margins) on ``rates`` (nx, k) [rad/s]."""
    for bound in problem.margins.apply(problem.physics.joint_bounds()):
        if bound.output == "qd":
            rows.add(rates[6 + bound.joint, :], bound.lower, bound.upper, f"qd{where}")


def _inner_range_rows(
    problem: CycleProblem, rows: _Rows, states: tuple[ca.MX, ca.MX], fraction: float
) -> None:
    """Every joint's range and velocity limit (less margins) inside the intervals.

    ``states``: the coordinates and their rates [SI] there.
    """
    for bound in problem.margins.apply(problem.physics.joint_bounds()):
        if bound.output in ("q", "qd"):
            values = states[0 if bound.output == "q" else 1]
            rows.add(
                values[6 + bound.joint, :],
                bound.lower,
                bound.upper,
                f"{bound.output} (at {fraction:g})",
            )


def _limit_rows(problem: CycleProblem, rows: _Rows, out: dict[str, ca.MX], where: str = "") -> None:
    """Effort limits and drive bounds (less margins) at every node (or inner point, ``where``)."""
    for bound in problem.margins.apply(problem.physics.joint_bounds()):
        if bound.output in ("q", "qd"):
            continue
        name = "tau" if bound.output == "tau" else f"{bound.output}_{bound.joint}"
        expr = out[name][bound.joint, :] if bound.output == "tau" else out[name]
        rows.add(expr, bound.lower, bound.upper, f"{name} {bound.source}{where}")
