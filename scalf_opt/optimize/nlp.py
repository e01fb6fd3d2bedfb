"""The swing optimization as a smooth NLP, built once with CasADi and solved by Ipopt.

Lifted formulation. Variables ``x = (theta, Y, slacks)``: the family's parameters, the kernel
inputs of every sample ``Y`` (6 x n: value, rate and acceleration of the two coordinates) and
the slacks of the energy's absolute values. The affine path is a linear equality,
``Y = Y_0 + B theta``, so that everything nonlinear is a function of one sample's six inputs:
the constraint Jacobian is block-sparse and the Lagrangian Hessian block-diagonal (6 x 6 per
sample), which Ipopt's sparse linear algebra factorizes several times faster than the condensed
problem, where every sample depends on every parameter (measured: ``joint-10`` at 500 Hz, 2.4 s
instead of 7.0 s; ``joint-6`` at 300 Hz, 0.16 s instead of 0.63 s). Families with at most
:data:`CONDENSED_MAX_PARAMS` parameters (the paper family) keep the condensed form, ``Y``
eliminated, which is faster for them.

Parameters ``p = (Y_0, B, trapezoidal weights)``, so that one built NLP serves every problem of
the same shape (leg, space, number of samples and parameters, accounting, constraint pattern):
other gaits, other families of the same size, the stance refinement. A family whose basis is
sparse (the B-splines of the free-trajectory bound: each sample depends on four control
points) keeps ``B`` as a sparse constant instead. The per-sample physics is the leg's compiled
kernel (:mod:`scalf_opt.optimize.kernels`) mapped over the samples; CasADi differentiates
through it (exact gradient, constraint Jacobian and Lagrangian Hessian).

The non-smooth energy is made smooth without changing its value at an optimum:

* ``paper`` accounting, ``|tau_i qd_i|`` at every sample: a slack pair ``s+ - s- = tau qd``,
  ``s+, s- >= 0``, cost ``s+ + s-`` (at an optimum one of the two is zero);
* ``positive``, ``max(tau qd, 0)``: a slack ``u >= 0``, ``u >= tau qd``, cost ``u``;
* ``regenerative``, ``tau qd``: charged as it is;
* the drives' losses take ``max(v, 0)`` as ``(v + sqrt(v^2 + eps^2)) / 2``
  (:data:`~scalf_opt.optimize.kernels.HEAT_SMOOTHING_EPS_M_S`).

A joint whose drive does not charge its mechanical power gets no slack. Constraints: every
constraint row of the kernel at the samples where it applies (:attr:`SwingProblem
.constraint_index`), given to Ipopt as exact bounds on ``g`` (``bound_relax_factor = 0``);
in joint space the bounds on the joint angles and rates are bounds on ``Y`` itself.
"""

from __future__ import annotations

import hashlib
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.interrupts import interruptible, stop_requested
from scalf_opt.optimize.kernels import (
    STANCE_INPUTS,
    SYMBOLIC_LOCK,
    casadi_name,
    stance_kernel,
    stance_limited_bounds,
)
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.types import Accounting, Space

IPOPT_DEFAULTS: dict[str, Any] = {
    # 1e-8 (Ipopt's default): at 1e-10 rich families stalled for a hundred iterations on
    # round-off after the energy had converged to 1e-9
    "tol": 1e-8,
    "acceptable_tol": 1e-6,
    "max_iter": 3000,
    "print_level": 0,
    "sb": "yes",
    "mu_strategy": "adaptive",
    # keep every bound exact: Ipopt relaxes bounds by 1e-8 by default, and the exact evaluator
    # judges feasibility at 1e-9
    "bound_relax_factor": 0.0,
    "constr_viol_tol": 1e-10,
    # approximate minimum degree ordering: MUMPS's automatic choice took 1.5x longer here
    "mumps_pivot_order": 0,
    # MUMPS's work space: the estimate plus 10 % (Ipopt's default adds 1000 %, allocated and
    # released at every factorization: the free-trajectory bound's finest levels spent a third
    # of their time doing so). Ipopt enlarges it if a factorization runs short.
    "mumps_mem_percent": 10,
}

CONDENSED_MAX_PARAMS = 2
"""Families with at most this many parameters get the condensed NLP (``Y`` eliminated): with
so few parameters the lifted variables cost more than they save (paper family, 200 Hz: 33 ms
condensed, 40 ms lifted; ``joint-6``, 300 Hz: 0.63 s condensed, 0.16 s lifted)."""

CONDENSED_OPTIONS: dict[str, Any] = {"mu_oracle": "probing"}
"""Ipopt options of the condensed NLP: Mehrotra's probing for the barrier parameter (paper
family: 20 iterations instead of 29; on the lifted NLP it took more, 79 instead of 52 for
``joint-6``)."""

SPARSE_BASIS_DENSITY = 0.25
"""A family's basis with fewer nonzeros than this fraction is built into the NLP as a sparse
constant (B-splines) instead of a dense parameter (Fourier families)."""


class StopCallback(ca.Callback):
    """Ipopt's iteration callback: ends the solve when a stop is requested.

    A solve in a worker thread cannot be interrupted by a signal (signals reach the main
    thread); this asks :func:`~scalf_opt.interrupts.stop_requested` once per iteration and
    Ipopt returns ``User_Requested_Stop``. It takes none of the iterate (empty inputs), and
    only NLPs built in a worker thread have it: on ``joint-6`` it cost 2 % of the solve.
    """

    def __init__(self, name: str) -> None:
        ca.Callback.__init__(self)
        self.construct(name, {})

    def get_n_in(self) -> int:  # noqa: D102
        return int(ca.nlpsol_n_out())

    def get_n_out(self) -> int:  # noqa: D102
        return 1

    def get_name_in(self, i: int) -> str:  # noqa: D102
        return str(ca.nlpsol_out(i))

    def get_name_out(self, i: int) -> str:  # noqa: D102
        return "stop"

    def get_sparsity_in(self, i: int) -> ca.Sparsity:  # noqa: D102
        return ca.Sparsity(0, 0)

    def eval(self, arg: Sequence[ca.DM]) -> list[int]:  # noqa: D102
        return [1 if stop_requested() else 0]


@dataclass
class BuiltNlp:
    """An NLP built for one shape of problem.

    Attributes:
        solver: The CasADi Ipopt solver.
        lifted: The samples ``Y`` are variables (else eliminated: the condensed NLP).
        n_theta: Number of family parameters.
        n_samples: Number of swing samples.
        charged: Joints whose mechanical power is charged (they carry the slacks).
        accounting: Power accounting.
        constant_basis: ``B`` is built in (sparse family) rather than a parameter.
        build_time_s: Time spent building it [s].
        index: The entries of the kernel's ``c`` it constrains (:func:`constraint_index`).
        coupled: The shape of the pair's stance term under whole-body loads, else ``None``.
        callback: Its iteration callback (kept alive with the solver).
    """

    solver: ca.Function
    lifted: bool
    n_theta: int
    n_samples: int
    charged: tuple[int, ...]
    accounting: Accounting
    constant_basis: bool
    build_time_s: float
    index: np.ndarray
    coupled: CoupledShape | None = None
    callback: StopCallback | None = None

    @property
    def n_slack_rows(self) -> int:
        """Slack constraints in ``g``: one per charged joint and sample when there are slacks."""
        if not power_accounting(self.accounting).slacks:
            return 0
        return len(self.charged) * self.n_samples

    @property
    def n_slacks(self) -> int:
        """Slack variables after ``theta`` and ``Y``."""
        return power_accounting(self.accounting).slacks * len(self.charged) * self.n_samples


@dataclass(frozen=True)
class CoupledShape:
    """The pair's stance term of a swing NLP under whole-body loads (its structure only).

    The stance legs' torques are affine in the twin's wrench (:mod:`scalf_opt.energy.coupling`):
    their charged power gets slacks like the swing's, their losses the smooth max.

    Attributes:
        varying: The swinging twin whose wrench loads the stance feet.
        space: Its samples' space.
        stance_legs: The pair's legs.
        n_samples: Stance samples.
        charged: Per stance leg, the joints whose mechanical power is charged.
        n_limited: Bounded quantities of the stance legs per sample that the swing moves
            (:func:`~scalf_opt.optimize.kernels.stance_limited_bounds`): constraint rows.
    """

    varying: str
    space: Space
    stance_legs: tuple[str, ...]
    n_samples: int
    charged: tuple[tuple[int, ...], ...]
    n_limited: int = 0

    def n_slacks(self, accounting: Accounting) -> int:
        """Slack variables of the stance term."""
        return power_accounting(accounting).slacks * self.n_charged

    def n_slack_rows(self, accounting: Accounting) -> int:
        """Slack constraints of the stance term."""
        return self.n_charged if power_accounting(accounting).slacks else 0

    @property
    def n_charged(self) -> int:
        """Charged joint samples of the stance legs."""
        return sum(len(c) for c in self.charged) * self.n_samples


def coupled_shape(problem: SwingProblem) -> CoupledShape | None:
    """The stance term's shape of ``problem`` (``None`` when its loads do not couple the legs)."""
    coupling = problem.coupling
    if coupling is None:
        return None
    pipeline = problem.pipeline
    charged = tuple(
        tuple(i for i, d in enumerate(pipeline.physics(t.leg).drives) if d.charges_joint_power)
        for t in coupling.terms
    )
    return CoupledShape(
        coupling.varying,
        coupling.motion.space,
        tuple(t.leg for t in coupling.terms),
        int(coupling.weights.size),
        charged,
        len(_stance_limits(problem)[0]),
    )


def _stance_limits(problem: SwingProblem) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of the stance legs' limited quantities at one sample."""
    coupling = problem.coupling
    assert coupling is not None
    bounds = [
        b for t in coupling.terms for b in stance_limited_bounds(problem.pipeline.physics(t.leg))
    ]
    return np.array([b.lower for b in bounds]), np.array([b.upper for b in bounds])


def _stance_parameters(problem: SwingProblem) -> list[np.ndarray]:
    """The stance term's parameter values, in :func:`_stance_cost`'s order."""
    coupling = problem.coupling
    assert coupling is not None
    n = coupling.weights.size
    motion = coupling.motion
    data = np.vstack(
        [np.vstack([t.q, t.qd, t.tau_fixed_nm, t.gain.reshape(n, 12).T]) for t in coupling.terms]
    )
    return [
        motion.base.reshape(6, n).ravel(order="F"),
        motion.dense_basis()
        .reshape(6, n, -1)
        .transpose(1, 0, 2)
        .reshape(6 * n, -1)
        .ravel(order="F"),
        coupling.weights,
        data.ravel(order="F"),
    ]


def _stance_cost(
    problem: SwingProblem, shape: CoupledShape, theta: ca.MX, accounting: Accounting
) -> tuple[ca.MX, list[ca.MX], list[ca.MX], list[ca.MX]]:
    """The pair's smooth stance energy: ``(cost, parameters, slack variables, slack rows)``."""
    pipeline = problem.pipeline
    n, n_theta = shape.n_samples, theta.numel()
    base = ca.MX.sym("twin_base", 6 * n)
    basis = ca.MX.sym("twin_basis", 6 * n * n_theta)
    weights = ca.MX.sym("stance_weights", n)
    rows_per_sample = STANCE_INPUTS * len(shape.stance_legs)
    data = ca.MX.sym("stance_data", rows_per_sample * n)
    parameters = [base, basis, weights, data]
    y = base + ca.mtimes(ca.reshape(basis, 6 * n, n_theta), theta) if n_theta else base
    kernel = stance_kernel(
        pipeline.physics(shape.varying),
        shape.space,
        tuple(pipeline.physics(s) for s in shape.stance_legs),
    )
    power, loss, limited = kernel.map(n, "serial")(ca.reshape(y, 6, n), ca.reshape(data, -1, n))
    cost: ca.MX = ca.mtimes(loss, weights)
    rule = power_accounting(accounting)
    slack_vars: list[ca.MX] = []
    rows: list[ca.MX] = []
    for k, (leg, charged) in enumerate(zip(shape.stance_legs, shape.charged, strict=True)):
        if not charged:
            continue
        p = ca.vertcat(*(power[2 * k + i, :] for i in charged))
        slacks = [ca.MX.sym(f"{leg}_slack{j}", len(charged), n) for j in range(rule.slacks)]
        slack_vars += [ca.vec(sl) for sl in slacks]
        slack_rows = rule.slack_rows(p, slacks)
        if slack_rows is not None:
            rows.append(ca.vec(ca.MX(slack_rows)))
        cost += ca.sum2(ca.sum1(rule.smooth_cost(p, slacks)) * weights.T)
    if shape.n_limited:  # after the slack rows: the stance legs' limits, sample by sample
        rows.append(ca.vec(limited))
    return cost, parameters, slack_vars, rows


def _basis_matrix(problem: SwingProblem) -> np.ndarray:
    """``B``, dense, shape (6n, n_theta): row ``6 k + i`` is kernel input ``i`` of sample ``k``."""
    basis = problem.path.dense_basis().reshape(6, problem.n_samples, problem.n_params)
    return basis.transpose(1, 0, 2).reshape(6 * problem.n_samples, -1)


def _sparse_basis(problem: SwingProblem) -> ca.DM | None:
    """``B`` as a sparse constant when the family's basis is sparse (else ``None``).

    A dense basis with fewer nonzeros than :data:`SPARSE_BASIS_DENSITY` counts as sparse.
    """
    from scipy.sparse import csc_array

    path = problem.path
    n = problem.n_samples
    if path.sparse:
        rows = path.basis_rows()
    else:
        if not path.basis.size or np.count_nonzero(path.basis) >= (
            SPARSE_BASIS_DENSITY * path.basis.size
        ):
            return None
        rows = path.basis.reshape(-1, problem.n_params)
    # the path's rows are (input i, sample k) in C order: sample-major is row 6 k + i
    order = np.arange(6 * n).reshape(6, n).T.ravel()
    matrix = csc_array(csc_array(rows)[order])
    matrix.eliminate_zeros()  # the pattern is the true one: each sample's four control points
    matrix.sort_indices()
    sparsity = ca.Sparsity(
        matrix.shape[0], matrix.shape[1], matrix.indptr.tolist(), matrix.indices.tolist()
    )
    return ca.DM(sparsity, matrix.data)


def constraint_index(
    problem: SwingProblem, lifted: bool, left_out: tuple[int, ...] = ()
) -> np.ndarray:
    """Flat (column-major) indices of the entries of the kernel's ``c`` the NLP constrains.

    Every entry that carries a bound; in the lifted NLP except the bounds on the samples' own
    coordinates (:attr:`SwingProblem.input_rows`), which bound ``Y`` directly; never the rows
    ``left_out`` (:mod:`scalf_opt.optimize.screening`).
    """
    mask = problem.constraint_mask.copy()
    if lifted:
        mask[list(problem.input_rows)] = False
    mask[list(left_out)] = False
    return np.flatnonzero(mask.ravel(order="F"))


def build_nlp(
    problem: SwingProblem,
    ipopt_options: dict[str, Any] | None = None,
    left_out: tuple[int, ...] = (),
) -> BuiltNlp:
    """The NLP of ``problem``'s shape: built on first use, then taken from the kernel's cache.

    ``left_out``: rows of the kernel's ``c`` the NLP does not carry (screened out).
    """
    with SYMBOLIC_LOCK:  # one CasADi build at a time (leg threads)
        lifted = problem.n_params > CONDENSED_MAX_PARAMS
        options = {
            **IPOPT_DEFAULTS,
            **({} if lifted else CONDENSED_OPTIONS),
            **(ipopt_options or {}),
        }
        kernel = problem.kernel
        charged = tuple(
            i for i, drive in enumerate(problem.physics.drives) if drive.charges_joint_power
        )
        accounting = problem.pipeline.accounting
        index = constraint_index(problem, lifted, left_out)
        constant = _sparse_basis(problem)
        shape = coupled_shape(problem)
        # in a worker thread a signal cannot stop the solve: its iteration callback does
        stoppable = threading.current_thread() is not threading.main_thread()
        key = (
            shape,
            lifted,
            problem.n_samples,
            problem.n_params,
            charged,
            accounting,
            hashlib.sha256(index.tobytes()).hexdigest(),
            None if constant is None else _digest(constant),
            tuple(sorted(options.items())),
            stoppable,
        )
        if key not in kernel.nlps:
            start = time.perf_counter()
            solver, callback = _build(
                problem, lifted, index, charged, accounting, constant, options, stoppable, shape
            )
            kernel.nlps[key] = BuiltNlp(
                solver,
                lifted,
                problem.n_params,
                problem.n_samples,
                charged,
                accounting,
                constant is not None,
                time.perf_counter() - start,
                index,
                shape,
                callback,
            )
        built = kernel.nlps[key]
    assert isinstance(built, BuiltNlp)
    return built


def _digest(matrix: ca.DM) -> str:
    """A hash of a sparse constant's pattern and values."""
    sparsity = matrix.sparsity()
    parts = (
        np.array(sparsity.shape, dtype=np.int64),
        np.array(sparsity.colind(), dtype=np.int64),
        np.array(sparsity.row(), dtype=np.int64),
        np.array(matrix.nonzeros(), dtype=float),
    )
    return hashlib.sha256(b"".join(p.tobytes() for p in parts)).hexdigest()


def _build(
    problem: SwingProblem,
    lifted: bool,
    index: np.ndarray,
    charged: tuple[int, ...],
    accounting: Accounting,
    constant_basis: ca.DM | None,
    options: dict[str, Any],
    stoppable: bool,
    shape: CoupledShape | None = None,
) -> tuple[ca.Function, StopCallback | None]:
    kernel = problem.kernel
    n, n_theta = problem.n_samples, problem.n_params
    theta = ca.MX.sym("theta", n_theta)
    base = ca.MX.sym("base", 6 * n)
    weights = ca.MX.sym("weights", n)
    parameters = [base]
    if constant_basis is not None:
        affine = base + ca.mtimes(constant_basis, theta)
    else:
        basis = ca.MX.sym("basis", 6 * n * n_theta)
        parameters.append(basis)
        affine = base + ca.mtimes(ca.reshape(basis, 6 * n, n_theta), theta) if n_theta else base
    parameters.append(weights)
    variables, constraints = [theta], []
    samples = affine
    if lifted:
        samples = ca.MX.sym("Y", 6 * n)
        variables.append(samples)
        constraints.append(samples - affine)
    out = kernel.smooth().map(n, "serial")(ca.reshape(samples, 6, n))
    p_mech, loss, c = out[0:2, :], out[2, :], out[3:, :]
    w = weights.T
    cost = ca.mtimes(loss, weights)
    k = len(charged)
    if k:
        power = ca.vertcat(*(p_mech[i, :] for i in charged))  # k x n
        rule = power_accounting(accounting)
        slacks = [ca.MX.sym(f"slack{j}", k, n) for j in range(rule.slacks)]
        variables += [ca.vec(s) for s in slacks]
        rows = rule.slack_rows(power, slacks)
        if rows is not None:
            constraints.append(ca.vec(ca.MX(rows)))
        cost += ca.sum2(ca.sum1(rule.smooth_cost(power, slacks)) * w)
    constraints.append(ca.vec(c)[index.tolist()])
    if shape is not None:
        stance_cost, stance_params, stance_slacks, stance_rows = _stance_cost(
            problem, shape, theta, accounting
        )
        cost += stance_cost
        parameters += stance_params
        variables += stance_slacks
        constraints += stance_rows
    x, p, g = ca.vertcat(*variables), ca.vertcat(*parameters), ca.vertcat(*constraints)
    name = casadi_name(kernel.physics.leg.name, kernel.space, accounting, f"n{n}", f"p{n_theta}")
    callback = StopCallback(f"{name}_stop") if stoppable else None
    solver = ca.nlpsol(
        name,
        "ipopt",
        {"x": x, "p": p, "f": cost, "g": g},
        # a trial step outside a foot-space leg's reach evaluates to NaN: Ipopt backtracks, which
        # is expected and needs no warning on the console
        {
            "ipopt": options,
            "print_time": False,
            "show_eval_warnings": False,
            **({"iteration_callback": callback} if callback is not None else {}),
        },
    )
    return solver, callback


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


def solve_nlp(built: BuiltNlp, problem: SwingProblem, theta0: np.ndarray) -> NlpSolution:
    """Solve ``problem`` with its built NLP from ``theta0`` (``Y`` and slacks consistent)."""
    theta0 = np.asarray(theta0, dtype=float)
    n = problem.n_samples
    outputs = problem.outputs(theta0)
    p_mech = np.nan_to_num(outputs["p_mech"][list(built.charged)])  # k x n
    rule = power_accounting(built.accounting)
    slacks = rule.initial_slacks(p_mech)
    y_lo, y_hi = problem.input_bounds
    m = 6 * n if built.lifted else 0  # lifted samples and their linear equalities
    stance_slacks: list[np.ndarray] = []
    n_stance_slacks = n_stance_rows = 0
    limit_lo = limit_hi = np.zeros(0)
    if built.coupled is not None:
        coupling = problem.coupling
        assert coupling is not None
        torques = coupling.torques_nm(problem.pipeline, theta0)
        for term, tau, charged in zip(coupling.terms, torques, built.coupled.charged, strict=True):
            if charged:
                p_stance = np.nan_to_num((tau * term.qd)[list(charged)])
                stance_slacks += [s.ravel(order="F") for s in rule.initial_slacks(p_stance)]
        n_stance_slacks = built.coupled.n_slacks(built.accounting)
        n_stance_rows = built.coupled.n_slack_rows(built.accounting)
        if built.coupled.n_limited:
            lo, hi = _stance_limits(problem)
            limit_lo, limit_hi = (
                np.tile(lo, built.coupled.n_samples),
                np.tile(hi, built.coupled.n_samples),
            )
    x0 = np.concatenate(
        [
            theta0,
            problem.samples(theta0).ravel(order="F")[:m],
            *(s.ravel(order="F") for s in slacks),
            *stance_slacks,
        ]
    )
    lbx = np.concatenate(
        [
            np.full(built.n_theta, -np.inf),
            y_lo.ravel(order="F")[:m],
            np.zeros(built.n_slacks + n_stance_slacks),
        ]
    )
    ubx = np.concatenate(
        [
            np.full(built.n_theta, np.inf),
            y_hi.ravel(order="F")[:m],
            np.full(built.n_slacks + n_stance_slacks, np.inf),
        ]
    )
    c_lo, c_hi = problem.constraint_bounds
    index = built.index
    slack_lo, slack_hi = rule.slack_row_bounds()
    lbg = np.concatenate(
        [
            np.zeros(m),
            np.full(built.n_slack_rows, slack_lo),
            c_lo.ravel(order="F")[index],
            np.full(n_stance_rows, slack_lo),
            limit_lo,
        ]
    )
    ubg = np.concatenate(
        [
            np.zeros(m),
            np.full(built.n_slack_rows, slack_hi),
            c_hi.ravel(order="F")[index],
            np.full(n_stance_rows, slack_hi),
            limit_hi,
        ]
    )
    params = [problem.samples_base.ravel(order="F")]
    if not built.constant_basis:
        params.append(_basis_matrix(problem).ravel(order="F"))
    params.append(problem.weights)
    if built.coupled is not None:
        params += _stance_parameters(problem)
    start = time.perf_counter()
    with interruptible():  # Ctrl-C stops the program, not just this solve
        sol = built.solver(x0=x0, p=np.concatenate(params), lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
    elapsed = time.perf_counter() - start
    stats = built.solver.stats()
    return NlpSolution(
        theta=np.array(sol["x"]).ravel()[: built.n_theta],
        success=bool(stats.get("success", False)),
        status=str(stats.get("return_status", "unknown")),
        iterations=int(stats.get("iter_count", -1)),
        objective_j=float(sol["f"]),
        wall_time_s=elapsed,
        stats={k: v for k, v in stats.items() if isinstance(v, int | float | str | bool)},
    )
