"""The swing optimization as a smooth NLP, built once with CasADi and solved by Ipopt.

Lifted formulation. Variables ``x = (theta, Y, slacks)``: the family's parameters (for the rich
Fourier families, whose basis is badly conditioned, ``theta = M x_theta`` of well-conditioned
variables: :func:`parameter_map`), the kernel inputs of every sample ``Y`` (6 x n: value, rate
and acceleration of the two coordinates) and the slacks of the energy's absolute values. The
affine path is a linear equality, ``Y = Y_0 + B theta``, so that everything nonlinear is a
function of one sample's six inputs: the constraint Jacobian is block-sparse and the Lagrangian
Hessian block-diagonal (6 x 6 per sample), which Ipopt's sparse linear algebra factorizes
several times faster than the condensed problem, where every sample depends on every parameter
(measured: docs/speed-log.md, "Measurements behind choices"). Families with at most
:data:`~scalf_opt.optimize.sampling.CONDENSED_MAX_PARAMS` parameters (the paper family) keep the
condensed form, ``Y`` eliminated, which is faster for them (the transcription's
:func:`~scalf_opt.optimize.sampling.scheme`).

Parameters ``p = (Y_0, B, trapezoidal weights)`` (``B`` by its nonzeros: :class:`BasisPattern`),
so that one built NLP serves every problem of the same shape (leg, space, number of samples and
parameters, accounting, constraint pattern, the basis's pattern):
other gaits, other families of the same size, the stance refinement. A family whose basis is
sparse (the B-splines of the free-trajectory bound: each sample depends on four control
points) keeps ``B`` as a sparse constant instead. The per-sample physics is the leg's compiled
kernel (:mod:`scalf_opt.optimize.kernels`) mapped over the samples; CasADi differentiates
through it (exact gradient, constraint Jacobian and Lagrangian Hessian).

One NLP holds one leg, or both legs of a diagonal pair (:class:`~scalf_opt.optimize.problem
.PairProblem`): one block of variables, rows and parameters per leg (:class:`LegBlock`), in the
legs' order, then under whole-body loads a stance term per stance window the swings load
(:class:`CoupledShape`): the pair's stance, whose torques take the wrenches of every optimized
leg's twin, and on a robot whose sides differ the other pair's too, whose torques take the
optimized legs' own wrenches (:func:`~scalf_opt.energy.coupling.stance_couplings`).

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
import math
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import casadi as ca
import numpy as np

from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.coupling import StanceCoupling
from scalf_opt.interrupts import interruptible, stop_requested
from scalf_opt.optimize.block_derivatives import block_diagonal, mapped_with_block_jacobian
from scalf_opt.optimize.kernels import (
    STANCE_INPUTS,
    SYMBOLIC_LOCK,
    Kernel,
    casadi_name,
    stance_kernel,
    stance_limited_bounds,
)
from scalf_opt.optimize.problem import PairProblem, SwingProblem
from scalf_opt.optimize.sampling import scheme
from scalf_opt.types import Accounting, Space

MUMPS_WORK_SPACE: dict[str, Any] = {"mumps_mem_percent": 10}
"""MUMPS's work space: the estimate plus 10 % (Ipopt's default adds 1000 %, allocated and
released at every factorization: the free-trajectory bound's finest levels spent a third of
their time doing so). Ipopt enlarges it if a factorization runs short."""

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
    **MUMPS_WORK_SPACE,
}

CONDENSED_OPTIONS: dict[str, Any] = {"mu_oracle": "probing", "mu_max": 10.0}
"""Ipopt options of the condensed NLP: Mehrotra's probing for the barrier parameter (paper
family: 20 iterations instead of 29; on the lifted NLP it took more, 79 instead of 52 for
``joint-6``), capped at ten times the objective, which the condensed NLP divides by its value at
the start (:attr:`BuiltNlp.normalized`). Uncapped, the barrier parameter follows the
complementarity of rows whose distances to their bounds are in newtons and radians per second:
from zero on Solo12's paper family it rose to 500 (600 under whole-body loads) where the swing
costs 0.16 J, the iterates went to the middle of the feasible region and Ipopt ended on a local
optimum of 179 J (a knee amplitude of 198 degrees) against the pattern search's 0.158 J. Measured
from zero on the six robots' default trots, paper family, both legs, trunk and whole-body loads:
with the cap at 10 every leg Ipopt solves from zero ends within 0.1 % of the lowest optimum
any start or setting found (SCalf's and HyQ's optima unchanged); at 1 and 0.1, Go1's and A1's
ended 4.6 % and 1 % higher under trunk loads. ``joint-2``, condensed too, moved between
neighbouring optima on the electric robots (up to 1.4 % either way; SCalf's and HyQ's
unchanged): their sampled Coulomb friction steps the energy where a sample's joint rate changes
sign, and a local search stops at such steps."""

COUPLED_OPTIONS: dict[str, Any] = {"mumps_pivot_order": 5}
"""Ipopt options of an NLP with the pair's stance term (whole-body loads): MUMPS orders the KKT
system by METIS's nested dissection instead of the approximate minimum degree. Every stance row
depends on all of a leg's parameters (quasi-dense rows), on which the minimum degree ordering
left large fronts (measured: docs/speed-log.md, "Measurements behind choices")."""

PAIR_OPTIONS: dict[str, Any] = {"nlp_scaling_method": "none"}
"""Ipopt options of a pair's NLP (both legs in one problem): without Ipopt's gradient-based
scaling of the rows: as many or fewer iterations on the six robots' default pairs, the same
optima or lower, not fewer everywhere (measured: docs/speed-log.md, "Measurements behind
choices")."""

CONDITIONING_ABOVE = 1e6
"""A dense basis whose values have a condition number above this is conditioned
(:func:`parameter_map`). The Fourier families' modes are orthonormal (condition number 1) and
never are; their terms' coefficients were, from ``joint-8`` (1.2e6) on, ``joint-12`` at 3e9: the
Fourier terms left after the end conditions cancel more with every order, and Ipopt's steps, its
regularization and its barrier are not invariant to that. Conditioned, those rich families solved
faster to the same or lower optima; below the threshold conditioning only picked other local
optima (measured: docs/speed-log.md, "Measurements behind choices"). A family registered with
such a basis is conditioned the same way."""

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


@dataclass(frozen=True)
class BasisPattern:
    """Where a dense family's basis ``B`` (``6 n x n_theta``, sample-major rows) is not zero.

    Given to CasADi as the structure of the parameter ``B``, the zeros leave the NLP: a Fourier
    family's joint (or foot coordinate) moves with its own parameters only, so half of ``B`` is
    zero, and so is half of the Jacobian's and of Ipopt's KKT entries that couple the samples to
    the parameters: fewer or as many iterations, the same optima, except where Ipopt's path follows
    the round-off to a neighbouring optimum, where sampled Coulomb friction makes them (measured:
    docs/speed-log.md, "Measurements behind choices"). The pattern is every exact zero of ``B``: a
    zero that only some gaits have gives those gaits their own NLP (the pattern is part of the
    NLP's shape).

    An NLP with a stance term (whole-body loads) keeps ``B`` whole (:meth:`full`): there the
    pattern changed the order MUMPS eliminates in (METIS's, on the quasi-dense stance rows) and
    with it the round-off path, to neighbouring optima (the six robots' default ``optimize``:
    SCalf the same, the others' cycles from -0.03 % to +0.35 %) in about the same time (22.9 s
    for the six instead of 24.5 s, HyQ faster and ANYmal C slower): no gain to move them for.

    Attributes:
        n_rows: Rows of ``B``.
        n_cols: Columns of ``B`` (parameters).
        bits: Where ``B`` is not zero, column-major, packed (:func:`numpy.packbits`).
    """

    n_rows: int
    n_cols: int
    bits: bytes

    @classmethod
    def of(cls, basis: np.ndarray) -> BasisPattern:
        """The pattern of ``basis``."""
        rows, cols = basis.shape
        return cls(rows, cols, np.packbits(basis.ravel(order="F") != 0.0).tobytes())

    @classmethod
    def full(cls, basis: np.ndarray) -> BasisPattern:
        """Every entry of ``basis``, zero or not."""
        return cls.of(np.ones_like(basis))

    @property
    def mask(self) -> np.ndarray:
        """Where ``B`` is not zero, ``(n_rows, n_cols)`` booleans."""
        size = self.n_rows * self.n_cols
        flat = np.unpackbits(np.frombuffer(self.bits, dtype=np.uint8), count=size)
        return flat.astype(bool).reshape(self.n_rows, self.n_cols, order="F")

    def parameter(self, name: str) -> tuple[ca.MX, ca.MX]:
        """``B`` as an NLP parameter: ``(the symbol of its nonzeros, the matrix)``."""
        rows, cols = np.nonzero(self.mask)
        sparsity = ca.Sparsity.triplet(self.n_rows, self.n_cols, rows.tolist(), cols.tolist())
        symbol = ca.MX.sym(name, sparsity.nnz())
        return symbol, ca.MX(sparsity, symbol)

    def values(self, basis: np.ndarray) -> np.ndarray:
        """The values of :meth:`parameter`'s symbol for ``basis`` (which has this pattern)."""
        return basis.T[self.mask.T]  # column-major, like CasADi's nonzeros


@dataclass(frozen=True)
class LegBlock:
    """One leg's part of a built NLP.

    Its variables ``(theta, Y, slacks)``, its rows (the lifted equalities, the slack rows, the
    kernel's constrained entries) and its parameters ``(Y_0, B, weights)``, in this order.

    Attributes:
        lifted: The samples ``Y`` are variables (else eliminated: the condensed NLP).
        n_theta: Number of family parameters.
        n_samples: Number of swing samples.
        charged: Joints whose mechanical power is charged (they carry the slacks).
        constant_basis: ``B`` is built in (sparse family) rather than a parameter.
        index: The entries of the kernel's ``c`` it constrains (:func:`constraint_index`).
        basis: Where ``B M`` is not zero when it is a parameter (:class:`BasisPattern`).
    """

    lifted: bool
    n_theta: int
    n_samples: int
    charged: tuple[int, ...]
    constant_basis: bool
    index: np.ndarray
    basis: BasisPattern | None = None

    def n_slack_rows(self, accounting: Accounting) -> int:
        """Slack constraints: one per charged joint and sample when there are slacks."""
        if not power_accounting(accounting).slacks:
            return 0
        return len(self.charged) * self.n_samples

    def n_slacks(self, accounting: Accounting) -> int:
        """Slack variables after ``theta`` and ``Y``."""
        return power_accounting(accounting).slacks * len(self.charged) * self.n_samples

    def n_variables(self, accounting: Accounting) -> int:
        """Variables of the block."""
        return self.n_theta + (6 * self.n_samples if self.lifted else 0) + self.n_slacks(accounting)


@dataclass
class BuiltNlp:
    """An NLP built for one shape of problem: one leg, or a pair of legs solved together.

    Attributes:
        solver: The CasADi Ipopt solver.
        blocks: Each leg's part, in the order of the problem's legs.
        accounting: Power accounting.
        build_time_s: Time spent building it [s].
        coupled: The shapes of the stance terms under whole-body loads (one per stance window
            the swings load: :func:`coupled_shapes`), else empty.
        callback: Its iteration callback (kept alive with the solver).
        problem: The CasADi problem the solver wraps (:func:`transcribe`).
    """

    solver: ca.Function
    blocks: tuple[LegBlock, ...]
    accounting: Accounting
    build_time_s: float
    coupled: tuple[CoupledShape, ...] = ()
    callback: StopCallback | None = None
    problem: CasadiNlp | None = None

    @property
    def lifted(self) -> bool:
        """The samples are variables (every leg of one NLP has the same family)."""
        return self.blocks[0].lifted

    @property
    def normalized(self) -> bool:
        """Ipopt solves the objective divided by its value at the start: the condensed NLP.

        Ipopt's barrier parameter and tolerances are absolute, and the swing energies of the
        catalog's robots span three orders of magnitude (Solo12's 0.16 J, HyQ's 100 J): divided
        by its value at the start, the objective is 1 there on every robot, and the barrier's cap
        in :data:`CONDENSED_OPTIONS` means the same on each. The lifted NLP keeps its objective
        in joules: normalized, its ``joint-6`` optima from zero moved on four of six robots, up
        or down, and ANYmal C's RF ran out of iterations.
        """
        return not self.lifted


@dataclass(frozen=True)
class CoupledShape:
    """The pair's stance term of a swing NLP under whole-body loads (its structure only).

    The stance legs' torques are affine in the twins' wrench (:mod:`scalf_opt.energy.coupling`):
    their charged power gets slacks like the swing's, their losses the smooth max. When the
    swings are lifted, so are the twins' samples at the stance samples (variables ``Y_twin``
    and the linear equalities ``Y_twin = Y_0 + B theta``): every stance row then depends on
    one sample's twelve inputs instead of every parameter of both legs, and an Ipopt iteration
    on SCalf's pair costs 18 ms instead of 28 (the same optimum to 1e-13 J).

    Attributes:
        varying: The swinging legs whose wrenches load the stance feet, one per optimized leg:
            its twin in the pair's own stance, the leg itself in the other pair's.
        space: Its samples' space.
        stance_legs: The pair's legs.
        n_samples: Stance samples.
        charged: Per stance leg, the joints whose mechanical power is charged.
        n_limited: Bounded quantities of the stance legs per sample that the swing moves
            (:func:`~scalf_opt.optimize.kernels.stance_limited_bounds`): constraint rows.
        lifted: The twins' stance samples are variables (first among the stance term's
            variables, their equalities first among its rows).
    """

    varying: tuple[str, ...]
    space: Space
    stance_legs: tuple[str, ...]
    n_samples: int
    charged: tuple[tuple[int, ...], ...]
    n_limited: int = 0
    lifted: bool = False

    @property
    def n_lifted(self) -> int:
        """The twins' lifted samples: variables, and as many linear equalities."""
        return 6 * self.n_samples * len(self.varying) if self.lifted else 0

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


def coupled_shapes(problem: SwingProblem | PairProblem) -> tuple[CoupledShape, ...]:
    """The shape of each stance term of ``problem``, one per stance window its swings load.

    Empty when its loads do not couple the legs; one (the pair's stance) on a robot symmetric
    about its midplane; two otherwise (:func:`~scalf_opt.energy.coupling.stance_couplings`).
    """
    pipeline = problem.pipeline
    shapes = []
    for coupling in problem.couplings:
        charged = tuple(
            tuple(i for i, d in enumerate(pipeline.physics(t.leg).drives) if d.charges_joint_power)
            for t in coupling.terms
        )
        shapes.append(
            CoupledShape(
                coupling.varying,
                coupling.motions[0].space,
                tuple(t.leg for t in coupling.terms),
                int(coupling.weights.size),
                charged,
                len(_stance_limits(problem, coupling)[0]),
                scheme(problem.family.n_params) == "lifted",
            )
        )
    return tuple(shapes)


def _stance_limits(
    problem: SwingProblem | PairProblem, coupling: StanceCoupling
) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of a stance window's limited quantities at one sample."""
    bounds = [
        b
        for t in coupling.terms
        for b in problem.margins.apply(stance_limited_bounds(problem.pipeline.physics(t.leg)))
    ]
    return np.array([b.lower for b in bounds]), np.array([b.upper for b in bounds])


def _stance_parameters(
    coupling: StanceCoupling, theta_maps: Sequence[np.ndarray]
) -> list[np.ndarray]:
    """A stance term's parameter values, in :func:`_stance_cost`'s order.

    ``theta_maps``: each varying leg's optimized leg's :func:`parameter_map` ``M`` (its
    parameters are ``M x`` of the NLP's variables ``x``, so the varying leg's basis enters as
    ``B M``).
    """
    n = coupling.weights.size
    data = np.vstack(
        [np.vstack([t.q, t.qd, t.tau_fixed_nm, t.gain.reshape(n, 12).T]) for t in coupling.terms]
    )
    motions = [
        part
        for motion, theta_map in zip(coupling.motions, theta_maps, strict=True)
        for part in (
            motion.base.reshape(6, n).ravel(order="F"),
            (
                motion.dense_basis().reshape(6, n, -1).transpose(1, 0, 2).reshape(6 * n, -1)
                @ theta_map
            ).ravel(order="F"),
        )
    ]
    return [*motions, coupling.weights, data.ravel(order="F")]


def parameter_map(problem: SwingProblem, block: LegBlock) -> np.ndarray:
    """``M``: the family's parameters are ``theta = M x`` of the NLP's variables ``x``.

    For a family whose basis is a parameter of the NLP (dense: the Fourier families) and whose
    joint-angle basis ``B_q`` has a condition number above :data:`CONDITIONING_ABOVE`,
    ``M = R^-1`` with ``R`` the triangular factor of ``B_q = Q R`` (``Q`` with orthonormal
    columns), scaled so that the geometric mean of the columns' norms of ``B_q M`` is that of
    ``B_q``'s: in the NLP's variables no two directions cancel, and their size stays that of the
    family's units on average. The identity otherwise, and for a sparse (B-spline) basis, whose
    control points are the joint angles themselves.

    The NLP is given the basis ``B M`` and its answer mapped back as ``M x``: the same matrix
    both ways, so that ``B (M x)`` is the NLP's path ``(B M) x`` to the round-off of a product
    (a triangular solve each way differed by ten times as much on ``joint-12``).
    """
    if block.constant_basis or block.n_theta == 0:
        return np.eye(block.n_theta)
    angles = problem.path.dense_basis()[0].reshape(-1, block.n_theta)  # (2 n, n_theta)
    if np.linalg.cond(angles) <= CONDITIONING_ABOVE:
        return np.eye(block.n_theta)
    r = np.linalg.qr(angles, mode="r")
    return np.linalg.inv(r) * np.exp(np.mean(np.log(np.linalg.norm(angles, axis=0))))


def _stance_cost(
    problem: SwingProblem | PairProblem,
    shape: CoupledShape,
    thetas: Sequence[ca.MX],
    accounting: Accounting,
) -> tuple[ca.MX, list[ca.MX], list[ca.MX], list[ca.MX]]:
    """A stance window's smooth energy: ``(cost, parameters, slack variables, slack rows)``.

    ``thetas``: the parameters each varying leg repeats, in the order of ``shape.varying``.
    """
    pipeline = problem.pipeline
    n = shape.n_samples
    parameters: list[ca.MX] = []
    samples = []
    slack_vars: list[ca.MX] = []
    rows: list[ca.MX] = []
    window = "".join(shape.stance_legs)
    for swinging, theta in zip(shape.varying, thetas, strict=True):
        n_theta = theta.numel()
        base = ca.MX.sym(f"{window}_{swinging}_base", 6 * n)
        basis = ca.MX.sym(f"{window}_{swinging}_basis", 6 * n * n_theta)
        parameters += [base, basis]
        y = base + ca.mtimes(ca.reshape(basis, 6 * n, n_theta), theta) if n_theta else base
        if shape.lifted:
            lifted = ca.MX.sym(f"{window}_{swinging}_Y", 6 * n)
            slack_vars.append(lifted)
            rows.append(lifted - y)
            y = lifted
        samples.append(ca.reshape(y, 6, n))
    weights = ca.MX.sym(f"{window}_stance_weights", n)
    rows_per_sample = STANCE_INPUTS * len(shape.stance_legs)
    data = ca.MX.sym(f"{window}_stance_data", rows_per_sample * n)
    parameters += [weights, data]
    kernel = stance_kernel(
        tuple(pipeline.physics(v) for v in shape.varying),
        shape.space,
        tuple(pipeline.physics(s) for s in shape.stance_legs),
    )
    power, loss, limited = kernel.map(n, "serial")(ca.vertcat(*samples), ca.reshape(data, -1, n))
    cost: ca.MX = ca.mtimes(loss, weights)
    rule = power_accounting(accounting)
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


def _legs(problem: SwingProblem | PairProblem) -> tuple[SwingProblem, ...]:
    """The legs' own problems of an NLP: the one leg, or each leg of the pair."""
    return problem.problems if isinstance(problem, PairProblem) else (problem,)


def _block(
    problem: SwingProblem, left_out: tuple[int, ...], coupled: bool
) -> tuple[LegBlock, ca.DM | None]:
    """The shape of ``problem``'s part of an NLP, and its sparse basis (``None``: dense).

    ``coupled``: the NLP has a stance term (then a dense basis is given whole:
    :class:`BasisPattern`).
    """
    lifted = scheme(problem.n_params) == "lifted"
    charged = tuple(
        i for i, drive in enumerate(problem.physics.drives) if drive.charges_joint_power
    )
    constant = _sparse_basis(problem)
    block = LegBlock(
        lifted,
        problem.n_params,
        problem.n_samples,
        charged,
        constant is not None,
        constraint_index(problem, lifted, left_out),
    )
    if constant is None:
        basis = _basis_matrix(problem) @ parameter_map(problem, block)
        block = replace(block, basis=(BasisPattern.full if coupled else BasisPattern.of)(basis))
    return block, constant


def build_nlp(
    problem: SwingProblem | PairProblem,
    ipopt_options: dict[str, Any] | None = None,
    left_out: tuple[int, ...] = (),
) -> BuiltNlp:
    """The NLP of ``problem``'s shape: built on first use, then taken from the kernel's cache.

    ``left_out``: rows of the kernel's ``c`` the NLP does not carry (screened out; one leg only).
    """
    legs = _legs(problem)
    if left_out and len(legs) > 1:
        raise ValueError("rows can be left out of one leg's NLP only")
    with SYMBOLIC_LOCK:  # one CasADi build at a time (leg threads)
        coupled = bool(problem.couplings)
        blocks, constants = zip(*(_block(leg, left_out, coupled) for leg in legs), strict=True)
        shapes = coupled_shapes(problem)
        options = {
            **IPOPT_DEFAULTS,
            **({} if blocks[0].lifted else CONDENSED_OPTIONS),
            **(COUPLED_OPTIONS if shapes else {}),
            **(PAIR_OPTIONS if len(legs) > 1 else {}),
            **(ipopt_options or {}),
        }
        kernel = legs[0].kernel
        accounting = problem.pipeline.accounting
        # in a worker thread a signal cannot stop the solve: its iteration callback does
        stoppable = threading.current_thread() is not threading.main_thread()
        key = (
            shapes,
            tuple(leg.leg for leg in legs[1:]),
            tuple(
                (
                    b.lifted,
                    b.n_samples,
                    b.n_theta,
                    b.charged,
                    hashlib.sha256(b.index.tobytes()).hexdigest(),
                    None if c is None else _digest(c),
                    b.basis,
                )
                for b, c in zip(blocks, constants, strict=True)
            ),
            accounting,
            tuple(sorted(options.items())),
            stoppable,
        )

        def build() -> BuiltNlp:
            start = time.perf_counter()
            nlp = transcribe(problem, legs, blocks, constants, accounting, shapes)
            solver, callback = ipopt_solver(nlp, options, stoppable)
            return BuiltNlp(
                solver, blocks, accounting, time.perf_counter() - start, shapes, callback, nlp
            )

        return kernel.nlps.get(key, build)


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


def _at_samples(fn: ca.Function, samples: ca.MX, n: int) -> ca.MX:
    """A per-sample function at each of the ``n`` samples of ``samples`` (``6 n``, sample-major)."""
    return fn.map(n, "serial")(ca.reshape(samples, 6, n))


@dataclass(frozen=True)
class _KernelUse:
    """Where one leg's NLP expressions use its compiled kernel.

    The expressions are built on ``outputs``, a symbol standing for the kernel's outputs at
    every sample (they are linear in it), and the kernel's mapped call is substituted for it
    afterwards (:func:`_substitute_kernels`): so the NLP's derivatives can also be assembled
    from the kernel's own compiled derivatives (:func:`_sample_derivatives`).

    Attributes:
        kernel: The leg's kernel (its :meth:`~scalf_opt.optimize.kernels.Kernel.smooth`
            function and that function's Hessian).
        samples: The kernel's inputs, ``6 n`` (sample-major): the variables ``Y`` when lifted.
        outputs: The stand-in symbol, ``rows x n``.
    """

    kernel: Kernel
    samples: ca.MX
    outputs: ca.MX

    @property
    def n(self) -> int:
        """Samples."""
        return int(self.outputs.size2())

    def call(self, fn: ca.Function | None = None) -> ca.MX:
        """The kernel at every sample, or ``fn`` (all samples at once, with other derivatives)."""
        if fn is not None:
            return ca.reshape(fn(self.samples), self.outputs.shape)
        return _at_samples(self.kernel.smooth(), self.samples, self.n)


def _swing_part(
    problem: SwingProblem, block: LegBlock, constant_basis: ca.DM | None, accounting: Accounting
) -> tuple[ca.MX, list[ca.MX], list[ca.MX], list[ca.MX], ca.MX, _KernelUse]:
    """One leg's smooth swing energy: ``(theta, variables, parameters, rows, cost, kernel use)``.

    The rows and the cost are in terms of the kernel use's stand-in outputs.
    """
    kernel = problem.kernel
    n, n_theta = block.n_samples, block.n_theta
    theta = ca.MX.sym(f"{problem.leg}_theta", n_theta)
    base = ca.MX.sym(f"{problem.leg}_base", 6 * n)
    weights = ca.MX.sym(f"{problem.leg}_weights", n)
    parameters = [base]
    if constant_basis is not None:
        affine = base + ca.mtimes(constant_basis, theta)
    else:
        assert block.basis is not None
        basis, matrix = block.basis.parameter(f"{problem.leg}_basis")
        parameters.append(basis)
        affine = base + ca.mtimes(matrix, theta) if n_theta else base
    parameters.append(weights)
    variables, constraints = [theta], []
    samples = affine
    if block.lifted:
        samples = ca.MX.sym(f"{problem.leg}_Y", 6 * n)
        variables.append(samples)
        constraints.append(samples - affine)
    out = ca.MX.sym(f"{problem.leg}_kernel_outputs", kernel.smooth().size1_out(0), n)
    p_mech, loss, c = out[0:2, :], out[2, :], out[3:, :]
    cost = ca.mtimes(loss, weights)
    k = len(block.charged)
    if k:
        power = ca.vertcat(*(p_mech[i, :] for i in block.charged))  # k x n
        rule = power_accounting(accounting)
        slacks = [ca.MX.sym(f"{problem.leg}_slack{j}", k, n) for j in range(rule.slacks)]
        variables += [ca.vec(s) for s in slacks]
        rows = rule.slack_rows(power, slacks)
        if rows is not None:
            constraints.append(ca.vec(ca.MX(rows)))
        cost += ca.sum2(ca.sum1(rule.smooth_cost(power, slacks)) * weights.T)
    constraints.append(ca.vec(c)[block.index.tolist()])
    return theta, variables, parameters, constraints, cost, _KernelUse(kernel, samples, out)


@dataclass(frozen=True)
class CasadiNlp:
    """A swing problem transcribed: CasADi's ``{x, p, f, g}`` and how to differentiate it.

    Attributes:
        name: A name for the compiled functions (legs, space, accounting, samples, parameters).
        x: The variables (parameters, lifted samples, slacks).
        p: The parameters (samples at zero, basis, weights, stance terms, objective scale).
        f: The objective.
        g: The constraint rows.
        derivatives: ``nlpsol`` options giving hand-built derivative functions (empty: CasADi's
            own).
    """

    name: str
    x: ca.MX
    p: ca.MX
    f: ca.MX
    g: ca.MX
    derivatives: dict[str, Any]


def ipopt_solver(
    nlp: CasadiNlp, options: dict[str, Any], stoppable: bool
) -> tuple[ca.Function, StopCallback | None]:
    """CasADi's Ipopt on ``nlp`` with Ipopt's ``options``.

    ``stoppable``: with an iteration callback that stops it on a signal (a solve in a worker
    thread, where the signal cannot interrupt the native solver).
    """
    callback = StopCallback(f"{nlp.name}_stop") if stoppable else None
    solver = ca.nlpsol(
        nlp.name,
        "ipopt",
        {"x": nlp.x, "p": nlp.p, "f": nlp.f, "g": nlp.g},
        # a trial step outside a foot-space leg's reach evaluates to NaN: Ipopt backtracks, which
        # is expected and needs no warning on the console
        {
            "ipopt": options,
            "print_time": False,
            "show_eval_warnings": False,
            **nlp.derivatives,
            **({"iteration_callback": callback} if callback is not None else {}),
        },
    )
    return solver, callback


def transcribe(
    problem: SwingProblem | PairProblem,
    legs: tuple[SwingProblem, ...],
    blocks: tuple[LegBlock, ...],
    constants: tuple[ca.DM | None, ...],
    accounting: Accounting,
    shapes: tuple[CoupledShape, ...] = (),
) -> CasadiNlp:
    """The CasADi problem of ``problem``'s legs in their blocks (and the pair's stance terms)."""
    thetas: list[ca.MX] = []
    variables: list[ca.MX] = []
    parameters: list[ca.MX] = []
    constraints: list[ca.MX] = []
    costs: list[ca.MX] = []
    uses: list[_KernelUse] = []
    for leg, block, constant in zip(legs, blocks, constants, strict=True):
        theta, leg_vars, leg_params, leg_rows, leg_cost, use = _swing_part(
            leg, block, constant, accounting
        )
        uses.append(use)
        thetas.append(theta)
        variables += leg_vars
        parameters += leg_params
        constraints += leg_rows
        costs.append(leg_cost)
    cost = sum(costs[1:], costs[0])
    for shape in shapes:
        stance_cost, stance_params, stance_slacks, stance_rows = _stance_cost(
            problem, shape, thetas, accounting
        )
        cost += stance_cost
        parameters += stance_params
        variables += stance_slacks
        constraints += stance_rows
    # the objective's scale [1/J], the last parameter: 1 for the lifted NLP, one over the
    # objective at the start for the condensed one (:attr:`BuiltNlp.normalized`)
    scale = ca.MX.sym("objective_scale")
    parameters.append(scale)
    cost = scale * cost
    x, p, g_z = ca.vertcat(*variables), ca.vertcat(*parameters), ca.vertcat(*constraints)
    cost_z = cost
    cost, g = _substitute_kernels([cost_z, g_z], uses)
    first = blocks[0]
    name = casadi_name(
        *(leg.leg for leg in legs),
        legs[0].kernel.space,
        accounting,
        f"n{first.n_samples}",
        f"p{first.n_theta}",
    )
    derivatives = (
        _sample_derivatives(name, x, p, cost_z, g_z, uses[0], first)
        if len(legs) == 1 and not shapes and first.lifted
        else {}
    )
    return CasadiNlp(name, x, p, cost, g, derivatives)


def _substitute_kernels(expressions: list[ca.MX], uses: Sequence[_KernelUse]) -> list[ca.MX]:
    """``expressions`` with each kernel use's stand-in replaced by the kernel's mapped call."""
    return list(ca.substitute(expressions, [u.outputs for u in uses], [u.call() for u in uses]))


def _sample_derivatives(
    name: str, x: ca.MX, p: ca.MX, cost_z: ca.MX, g_z: ca.MX, use: _KernelUse, block: LegBlock
) -> dict[str, ca.Function]:
    """The lifted one-leg NLP's derivatives from the kernel's compiled ones (``nlpsol`` options).

    Everything nonlinear in the NLP is the kernel at one sample's six inputs, and the cost and
    the rows are linear in its outputs ``Z``. So the constraint Jacobian is ``dg/dx`` at fixed
    ``Z`` plus ``dg/dZ`` times the block-diagonal of the samples' compiled Jacobians, and the
    Lagrangian's Hessian is the block-diagonal of the samples' compiled Hessians of ``s_k' f``,
    with the seed ``s = dL/dZ`` (the multipliers and weights of the rows and costs that take each
    output). CasADi's own derivatives propagate seeds through the mapped kernel, colour by
    colour: at 1,025 samples the Jacobian took 6.6 ms and the Hessian 4.4 ms, assembled 3.7 ms
    and 2.7 ms. The two are cross-checked in ``tests/optimize/test_optimize.py``. ``{}``
    (CasADi's own) if the cost or the rows are not linear as assumed. The condensed NLP and the
    NLPs with more than one leg or a stance term keep CasADi's: their rows depend on many
    samples' kernels at once.
    """
    kernel, n, z = use.kernel.smooth(), use.n, use.outputs
    rows = kernel.size1_out(0)
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g_z.numel())
    lagrangian = lam_f * cost_z + ca.dot(lam_g, g_z)
    seed = ca.jacobian(lagrangian, ca.vec(z)).T
    if ca.depends_on(seed, ca.vec(z)) or ca.depends_on(ca.gradient(lagrangian, x), x):
        return {}

    kernels = mapped_with_block_jacobian(kernel, n, f"{name}_kernels")
    g = ca.substitute(g_z, z, use.call(kernels))
    hessian = use.kernel.smooth_hessian()  # (y, seed) -> d2 (seed' out) / d y2
    h_blocks = hessian.map(n, "serial")(ca.reshape(use.samples, 6, n), ca.reshape(seed, rows, n))
    lifted = block_diagonal(h_blocks, hessian.sparsity_out(0), n)
    after = x.numel() - block.n_theta - 6 * n
    full = ca.diagcat(ca.MX(block.n_theta, block.n_theta), lifted, ca.MX(after, after))
    return {
        "jac_g": ca.Function(
            f"{name}_jac_g", [x, p], [g, ca.jacobian(g, x)], ["x", "p"], ["g", "jac_g_x"]
        ),
        "hess_lag": ca.Function(
            f"{name}_hess_lag",
            [x, p, lam_f, lam_g],
            [ca.triu(full)],
            ["x", "p", "lam_f", "lam_g"],
            ["triu_hess_gamma_x_x"],
        ),
    }


@dataclass(frozen=True)
class NlpSolution:
    """Ipopt's answer.

    Attributes:
        thetas: Parameters of each leg at Ipopt's final iterate (family units).
        success: Ipopt reported a solved problem.
        status: Ipopt's return status.
        iterations: Ipopt iterations.
        objective_j: Smooth objective at the final iterate [J].
        wall_time_s: Time spent in the solver [s].
        stats: Ipopt's statistics as returned by CasADi.
    """

    thetas: tuple[np.ndarray, ...]
    success: bool
    status: str
    iterations: int
    objective_j: float
    wall_time_s: float
    stats: dict[str, Any]

    @property
    def theta(self) -> np.ndarray:
        """The parameters of a one-leg NLP."""
        (theta,) = self.thetas
        return theta


@dataclass
class _Start:
    """Start, bounds and parameter values of an NLP, in its variables' and rows' order."""

    x0: list[np.ndarray] = field(default_factory=list)
    lbx: list[np.ndarray] = field(default_factory=list)
    ubx: list[np.ndarray] = field(default_factory=list)
    lbg: list[np.ndarray] = field(default_factory=list)
    ubg: list[np.ndarray] = field(default_factory=list)
    p: list[np.ndarray] = field(default_factory=list)

    def variables(self, x0: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> None:
        self.x0.append(x0)
        self.lbx.append(lower)
        self.ubx.append(upper)

    def rows(self, lower: np.ndarray, upper: np.ndarray) -> None:
        self.lbg.append(lower)
        self.ubg.append(upper)


def _swing_start(
    start: _Start,
    block: LegBlock,
    problem: SwingProblem,
    theta0: np.ndarray,
    accounting: Accounting,
    theta_map: np.ndarray,
    x0: np.ndarray,
) -> None:
    """Append one leg's start (``Y`` and slacks consistent with ``theta0``), bounds and values.

    ``theta_map``: the leg's :func:`parameter_map` ``M``; ``x0``: its variables at the start,
    ``M^-1 theta0``.
    """
    n = block.n_samples
    outputs = problem.outputs(theta0)
    p_mech = np.nan_to_num(outputs["p_mech"][list(block.charged)])  # k x n
    rule = power_accounting(accounting)
    slacks = rule.initial_slacks(p_mech)
    y_lo, y_hi = problem.input_bounds
    n_lifted = 6 * n if block.lifted else 0  # lifted samples and their linear equalities
    n_slacks = block.n_slacks(accounting)
    start.variables(x0, np.full(block.n_theta, -np.inf), np.full(block.n_theta, np.inf))
    start.variables(
        problem.samples(theta0).ravel(order="F")[:n_lifted],
        y_lo.ravel(order="F")[:n_lifted],
        y_hi.ravel(order="F")[:n_lifted],
    )
    start.variables(
        np.concatenate([np.zeros(0), *(s.ravel(order="F") for s in slacks)]),
        np.zeros(n_slacks),
        np.full(n_slacks, np.inf),
    )
    slack_lo, slack_hi = rule.slack_row_bounds()
    c_lo, c_hi = problem.constraint_bounds
    n_rows = block.n_slack_rows(accounting)
    start.rows(np.zeros(n_lifted), np.zeros(n_lifted))
    start.rows(np.full(n_rows, slack_lo), np.full(n_rows, slack_hi))
    start.rows(c_lo.ravel(order="F")[block.index], c_hi.ravel(order="F")[block.index])
    start.p.append(problem.samples_base.ravel(order="F"))
    if not block.constant_basis:
        assert block.basis is not None
        start.p.append(block.basis.values(_basis_matrix(problem) @ theta_map))
    start.p.append(problem.weights)


def _stance_start(
    start: _Start,
    shape: CoupledShape,
    coupling: StanceCoupling,
    problem: SwingProblem | PairProblem,
    thetas0: Sequence[np.ndarray],
    accounting: Accounting,
    theta_maps: Sequence[np.ndarray],
    xs0: Sequence[np.ndarray],
) -> None:
    """Append a stance term's start (its slacks at ``thetas0``), bounds and values.

    ``theta_maps``: each leg's :func:`parameter_map`, in the order of ``thetas0``; ``xs0``:
    each leg's variables at the start.
    """
    rule = power_accounting(accounting)
    parameters = _stance_parameters(coupling, theta_maps)
    if shape.lifted:  # the swinging legs' samples at the start, in _stance_cost's layout
        n = 6 * shape.n_samples
        for k, x0 in enumerate(xs0):
            base, basis = parameters[2 * k], parameters[2 * k + 1]
            y0 = base + basis.reshape(n, -1, order="F") @ x0
            start.variables(y0, np.full(n, -np.inf), np.full(n, np.inf))
        start.rows(np.zeros(shape.n_lifted), np.zeros(shape.n_lifted))
    torques = coupling.torques_nm(problem.pipeline, thetas0)
    slacks = []
    for term, tau, charged in zip(coupling.terms, torques, shape.charged, strict=True):
        if charged:
            p_stance = np.nan_to_num((tau * term.qd)[list(charged)])
            slacks += [s.ravel(order="F") for s in rule.initial_slacks(p_stance)]
    n_slacks = shape.n_slacks(accounting)
    start.variables(
        np.concatenate([np.zeros(0), *slacks]), np.zeros(n_slacks), np.full(n_slacks, np.inf)
    )
    slack_lo, slack_hi = rule.slack_row_bounds()
    n_rows = shape.n_slack_rows(accounting)
    start.rows(np.full(n_rows, slack_lo), np.full(n_rows, slack_hi))
    if shape.n_limited:
        lo, hi = _stance_limits(problem, coupling)
        start.rows(np.tile(lo, shape.n_samples), np.tile(hi, shape.n_samples))
    start.p += parameters


def solve_nlp(
    built: BuiltNlp,
    problem: SwingProblem | PairProblem,
    theta0: np.ndarray | Sequence[np.ndarray],
) -> NlpSolution:
    """Solve ``problem`` with its built NLP from ``theta0`` (``Y`` and slacks consistent).

    ``theta0``: the leg's parameters, or for a :class:`PairProblem` each leg's in its order.
    """
    legs = _legs(problem)
    thetas0 = (
        (np.asarray(theta0, dtype=float),)
        if isinstance(problem, SwingProblem)
        else tuple(np.asarray(t, dtype=float) for t in theta0)
    )
    start = _Start()
    maps = [parameter_map(leg, block) for block, leg in zip(built.blocks, legs, strict=True)]
    xs0 = [np.linalg.solve(m, theta) for m, theta in zip(maps, thetas0, strict=True)]
    for block, leg, theta, theta_map, x0 in zip(
        built.blocks, legs, thetas0, maps, xs0, strict=True
    ):
        _swing_start(start, block, leg, theta, built.accounting, theta_map, x0)
    for shape, coupling in zip(built.coupled, problem.couplings, strict=True):
        _stance_start(start, shape, coupling, problem, thetas0, built.accounting, maps, xs0)
    x0 = np.concatenate(start.x0)
    scale = 1.0
    if built.normalized:
        unscaled = np.concatenate([*start.p, [1.0]])
        at_start = abs(float(built.solver.get_function("nlp_f")(x0, unscaled)))
        scale = 1.0 / at_start if math.isfinite(at_start) and at_start > 0.0 else 1.0
    begin = time.perf_counter()
    with interruptible():  # Ctrl-C stops the program, not just this solve
        sol = built.solver(
            x0=x0,
            p=np.concatenate([*start.p, [scale]]),
            lbx=np.concatenate(start.lbx),
            ubx=np.concatenate(start.ubx),
            lbg=np.concatenate(start.lbg),
            ubg=np.concatenate(start.ubg),
        )
    elapsed = time.perf_counter() - begin
    stats = built.solver.stats()
    x = np.array(sol["x"]).ravel()
    offsets = np.cumsum([0, *(b.n_variables(built.accounting) for b in built.blocks)])
    return NlpSolution(
        thetas=tuple(
            theta_map @ x[offset : offset + b.n_theta]
            for offset, b, theta_map in zip(offsets, built.blocks, maps, strict=False)
        ),
        success=bool(stats.get("success", False)),
        status=str(stats.get("return_status", "unknown")),
        iterations=int(stats.get("iter_count", -1)),
        objective_j=float(sol["f"]) / scale,
        wall_time_s=elapsed,
        stats={k: v for k, v in stats.items() if isinstance(v, int | float | str | bool)},
    )
