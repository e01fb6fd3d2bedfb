"""Swing optimization: pattern search against Ipopt, nesting, constraints, failures, goals."""

import itertools

import casadi as ca
import numpy as np
import pytest

from scalf_opt.api.gaits import read_gait
from scalf_opt.energy.limits import violations
from scalf_opt.energy.margins import NO_LIFT_PROFILE, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.fourier import FourierFamily, order_terms
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.kernels import HEAT_SMOOTHING_EPS_M_S, kernel_for
from scalf_opt.optimize.nlp import build_nlp
from scalf_opt.optimize.pattern_search import PatternSearchOptions
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import run_ipopt, run_pattern_search
from scalf_opt.robots.loading import load_robot

# The NLP smooths max(v, 0) by at most eps/2: heat rate error <= F_s eps / 2 per cylinder, so
# over a 0.25 s swing and two cylinders the smooth and exact energies differ by at most:
SMOOTHING_BOUND_J = 2 * 50.0 * HEAT_SMOOTHING_EPS_M_S / 2 * 0.25


@pytest.fixture(scope="module")
def model(scalf):
    # the one-leg swing NLP and its optimizers (the paper's trunk-only loads); the whole-body
    # objective is test_whole_body_objective.py's
    return EnergyPipeline(scalf, Gait(), loads="trunk")


@pytest.fixture(scope="module")
def reference(model):
    return model.robot_cycle(make_family("reference"), legs=("RF", "LH"))


@pytest.fixture(scope="module")
def paper_optima(model):
    out = {}
    for leg in ("RF", "LH"):
        problem = SwingProblem(model, leg, make_family("paper"))
        out[leg] = {
            "coarse": run_pattern_search(problem),
            "fine": run_pattern_search(problem, options=PatternSearchOptions(precision=1e-4)),
            "ipopt": run_ipopt(problem),
        }
    return out


@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_pattern_search_agrees_with_ipopt(paper_optima, leg):
    runs = paper_optima[leg]
    assert all(run.success for run in runs.values())
    nlp = runs["ipopt"].swing_energy_j
    assert abs(runs["fine"].swing_energy_j - nlp) <= 1e-3 * nlp  # the 0.1 %
    # the pattern search cannot beat the NLP optimum by more than the smoothing error
    assert runs["fine"].swing_energy_j >= nlp - SMOOTHING_BOUND_J
    assert runs["coarse"].swing_energy_j >= runs["fine"].swing_energy_j - SMOOTHING_BOUND_J
    np.testing.assert_allclose(runs["fine"].theta, runs["ipopt"].theta, atol=5e-3)


@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_paper_family_beats_the_reference(paper_optima, reference, leg):
    assert paper_optima[leg]["ipopt"].swing_energy_j < reference.legs[leg].swing_energy_j
    assert paper_optima[leg]["coarse"].swing_energy_j < reference.legs[leg].swing_energy_j


def test_pattern_search_records_its_history(paper_optima):
    run = paper_optima["RF"]["coarse"]
    energies = [row[-1] for row in run.pattern_details.history]
    assert len(run.pattern_details.history[0]) == 2 + 2  # iteration, C1, C2, energy
    assert all(b < a for a, b in itertools.pairwise(energies))
    assert run.pattern_details.history[-1][-1] == pytest.approx(run.swing_energy_j)
    # (0, 0) is infeasible: the feasibility phase ran, and infeasible points were counted
    assert run.pattern_details.feasibility_phase_iterations > 0
    assert run.pattern_details.infeasible.get("mid-swing clearance", 0) > 0


def test_richer_nested_families_never_do_worse(model):
    # under the same constraints: the paper family, too small to shape its lift, keeps no lift
    # profile (LimitMargins.for_family), so none here
    margins = LimitMargins(lift=NO_LIFT_PROFILE)
    for leg in ("RF", "LH"):
        previous = None
        chain = ("paper", "joint-3", "joint-4", "joint-5")
        for poor_name, rich_name in itertools.pairwise(chain):
            poor, rich = make_family(poor_name), make_family(rich_name)
            if previous is None:
                previous = run_ipopt(SwingProblem(model, leg, poor, margins=margins))
            warm = rich.embed(previous.theta, poor)
            richer = run_ipopt(SwingProblem(model, leg, rich, margins=margins), warm)
            assert richer.success
            assert richer.swing_energy_j <= previous.swing_energy_j + SMOOTHING_BOUND_J
            previous = richer


def test_foot_space_families_are_nested_too(model):
    poor = run_ipopt(SwingProblem(model, "RF", make_family("fourier-3")))
    rich_family = make_family("fourier-4")
    rich = run_ipopt(
        SwingProblem(model, "RF", rich_family),
        rich_family.embed(poor.theta, make_family("fourier-3")),
    )
    assert poor.success and rich.success
    assert rich.swing_energy_j <= poor.swing_energy_j + SMOOTHING_BOUND_J


@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_default_family_cuts_swing_energy_and_meets_every_constraint(model, reference, leg):
    problem = SwingProblem(model, leg, make_family(DEFAULT_FAMILY))
    optimum = run_ipopt(problem)
    assert optimum.success
    assert optimum.swing_energy_j <= 0.7 * reference.legs[leg].swing_energy_j
    # every constraint holds, checked on the samples of the pipeline's own phase evaluation
    # (the sample function the reports use, not the optimizer's compiled kernel)
    swing = model.swing(leg, problem.family, optimum.theta)
    assert violations(swing.values, problem.bounds) == []
    foot_z = swing.values["foot"][1]
    assert np.all(foot_z >= problem.ground_z_m - 1e-9)
    assert foot_z[problem.mid_index] >= problem.clearance_z_m - 1e-9
    assert swing.energy_j.sum() == pytest.approx(optimum.swing_energy_j, rel=1e-12)
    names = {b.name for b in problem.bounds}
    assert {"q_hip", "qd_knee", "tau_hip", "cyl_len_hip", "cyl_force_knee", "cyl_vel_hip"} <= names


def test_kernel_equals_the_pipeline_sample_function(model):
    # two code paths to the same numbers: the optimizer's kernel (compiled library) and the
    # reports' per-phase evaluation (the CasADi sample function mapped over the samples)
    family = make_family("joint-4")
    problem = SwingProblem(model, "LH", family)
    theta = np.random.default_rng(3).normal(size=problem.n_params)
    swing = model.swing("LH", family, theta)
    out = problem.outputs(theta)
    np.testing.assert_allclose(out["power"], swing.values["power"], rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(out["p_mech"], swing.values["p_mech"], rtol=1e-10, atol=1e-9)
    for i, bound in enumerate(problem.bounds):
        np.testing.assert_allclose(out["c"][i], bound.values(swing.values), rtol=1e-10, atol=1e-9)


def test_nlp_objective_equals_exact_energy_at_the_optimum(model, paper_optima):
    # slack pairs make sum(s+ + s-) equal |tau qd| at an optimum; only the heat is smoothed
    run = paper_optima["RF"]["ipopt"]
    assert abs(run.details.stats["smooth_objective_j"] - run.swing_energy_j) <= SMOOTHING_BOUND_J


@pytest.mark.parametrize("space", ["joint", "foot"])
def test_compiled_kernel_derivatives_against_finite_differences(model, space):
    # the NLP differentiates through the compiled kernel with the derivative functions its
    # library holds (jac, adj1, jac_adj1): check first and second derivatives numerically
    kernel = kernel_for(model.physics("RF"), space)
    smooth = kernel.smooth()
    y = ca.MX.sym("y", 6)
    out = smooth(y)
    weights = np.linspace(0.3, 1.7, out.size1())
    scalar = ca.dot(ca.DM(weights), out)
    grad = ca.Function("g", [y], [scalar, ca.gradient(scalar, y), ca.hessian(scalar, y)[0]])
    family = make_family("joint-3" if space == "joint" else "fourier-3")
    problem = SwingProblem(model, "RF", family)
    point = problem.samples(np.full(problem.n_params, 0.5))[:, 17]
    value, g, h = (np.array(v) for v in grad(point))
    value = value.item()
    assert np.all(np.isfinite(h)) and np.abs(h).max() > 0  # a reachable, non-trivial point
    step = 1e-6 * np.maximum(1.0, np.abs(point))
    # central differences: truncation ~step^2 |f'''|, round-off ~1e-16 |f| / step
    fd = [
        (float(grad(point + s * e)[0]) - float(grad(point - s * e)[0])) / (2 * s)
        for s, e in zip(step, np.eye(6), strict=True)
    ]
    np.testing.assert_allclose(g.ravel(), fd, rtol=1e-5, atol=1e-6 * abs(value))
    fd2 = np.array(
        [
            (np.array(grad(point + s * e)[1]) - np.array(grad(point - s * e)[1])).ravel() / (2 * s)
            for s, e in zip(step, np.eye(6), strict=True)
        ]
    )
    np.testing.assert_allclose(h, fd2, rtol=1e-4, atol=1e-5 * np.abs(h).max())


@pytest.mark.parametrize(
    ("robot", "family", "accounting"),
    [
        ("scalf", "joint-6", "paper"),
        ("scalf", "fourier-4", "positive"),
        ("scalf", "bspline-16", "regenerative"),
        ("hyq", "joint-6", "paper"),  # valve-controlled: no joint power charged, no slacks
    ],
)
def test_nlp_derivatives_from_the_kernels_equal_casadi_s_own(model, hyq, robot, family, accounting):
    # the lifted one-leg NLP takes its constraint Jacobian and Lagrangian Hessian from the
    # kernels' compiled derivatives, assembled by hand (nlp._sample_derivatives); CasADi's own
    # AD through the NLP's constraint and objective functions is the independent reference
    # (only the order of floating-point operations differs: 1e-9 of the largest entry)
    base = model if robot == "scalf" else EnergyPipeline(hyq, read_gait(robot=hyq), loads="trunk")
    pipeline = base.with_accounting(accounting)
    problem = SwingProblem(pipeline, "RF", make_family(family))
    solver = build_nlp(problem).solver
    x, p = ca.MX.sym("x", solver.size1_in("x0")), ca.MX.sym("p", solver.size1_in("p"))
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", solver.size1_in("lam_g0"))
    g, f = solver.get_function("nlp_g")(x, p), solver.get_function("nlp_f")(x, p)
    reference = ca.Function(
        "reference",
        [x, p, lam_f, lam_g],
        [ca.jacobian(g, x), ca.triu(ca.hessian(lam_f * f + ca.dot(lam_g, g), x)[0])],
    )
    # the variables (theta, Y, slacks): the samples Y of a reachable swing, the rest random;
    # the parameters (the affine path, the weights) random: the lifted rows are linear in them
    rng = np.random.default_rng(7)
    theta = np.full(problem.n_params, 0.3)
    samples = problem.samples(theta).ravel(order="F") * (1 + 1e-3 * rng.standard_normal())
    n_slacks = x.numel() - problem.n_params - samples.size
    x0 = np.concatenate([theta, samples, rng.uniform(0.0, 50.0, n_slacks)])
    p0 = rng.uniform(0.5, 1.5, p.numel())
    lam0 = rng.standard_normal(lam_g.numel()) * 10.0
    jac_ref, hess_ref = (ca.DM(m) for m in reference(x0, p0, 0.7, lam0))
    jac = ca.DM(solver.get_function("nlp_jac_g")(x0, p0)[1])
    hess = ca.DM(solver.get_function("nlp_hess_l")(x0, p0, 0.7, lam0))
    for ours, theirs in ((jac, jac_ref), (hess, hess_ref)):
        ours, theirs = np.array(ca.densify(ours)), np.array(ca.densify(theirs))
        assert np.abs(theirs).max() > 0
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-9 * np.abs(theirs).max())


@pytest.mark.parametrize(
    ("family", "loads"),
    [("joint-6", "trunk"), ("joint-12 coefficients", "trunk"), ("joint-6", "whole-body")],
)
def test_the_nlp_carries_a_dense_basis_on_its_nonzeros(scalf, family, loads):
    # each joint of a Fourier family moves with its own parameters: the NLP's parameter B M
    # holds only B M's nonzeros (half), and its lifted rows Y - Y_0 - (B M) x, the stance
    # term's too under whole-body loads, vanish at samples computed apart, in numpy, from the
    # dense basis (joint-12's coefficients: M conditions the basis); a value misplaced fails by far
    from scalf_opt.optimize import nlp

    pipeline = EnergyPipeline(scalf, Gait(), loads=loads)
    swing = coefficients_of(12) if family == "joint-12 coefficients" else make_family(family)
    problem = SwingProblem(pipeline, "RF", swing)
    built = build_nlp(problem)
    block = built.blocks[0]
    theta_map = nlp.parameter_map(problem, block)
    dense = nlp._basis_matrix(problem) @ theta_map
    assert block.basis is not None
    assert np.count_nonzero(dense) < 0.55 * dense.size
    # with a stance term B is given whole (nlp.BasisPattern says why)
    expected = dense != 0 if loads == "trunk" else np.ones_like(dense, dtype=bool)
    assert np.array_equal(block.basis.mask, expected)
    theta = np.random.default_rng(3).uniform(-5.0, 5.0, problem.n_params)  # deg
    x_theta = np.linalg.solve(theta_map, theta)  # as solve_nlp starts
    start = nlp._Start()
    nlp._swing_start(start, block, problem, theta, built.accounting, theta_map, x_theta)
    for shape, coupling in zip(built.coupled, problem.couplings, strict=True):
        nlp._stance_start(
            start, shape, coupling, problem, (theta,), built.accounting, [theta_map], [x_theta]
        )
    assert len(built.coupled) == (loads == "whole-body")
    x0, p0 = np.concatenate(start.x0), np.concatenate([*start.p, [1.0]])
    g = np.array(built.solver.get_function("nlp_g")(x0, p0)).ravel()
    n = problem.n_samples
    swing_rows = g[: 6 * n]
    rows = block.n_slack_rows(built.accounting) + block.index.size
    stance_rows = g[6 * n + rows :][: sum(s.n_lifted for s in built.coupled)]
    assert stance_rows.size == sum(6 * s.n_samples for s in built.coupled)
    # zero to the round-off of the products B theta and (B M) x: 1e-13 of their terms' sum
    terms = np.abs(problem.samples_base).max() + (np.abs(dense) @ np.abs(x_theta)).max()
    for lifted in (swing_rows, stance_rows):
        np.testing.assert_allclose(lifted, 0.0, rtol=0, atol=1e-13 * terms)


def test_an_unsolved_nlp_is_reported_not_presented(model):
    problem = SwingProblem(model, "RF", make_family("joint-4"))
    result = run_ipopt(problem, ipopt_options={"max_iter": 2})
    assert not result.success
    assert "Maximum_Iterations_Exceeded" in result.status
    assert result.details.stats["iter_count"] == 2


def test_build_nlp_has_the_constraints_and_is_built_once(model):
    problem = SwingProblem(model, "LH", make_family("paper"))
    built = build_nlp(problem)
    n, m = problem.n_samples, len(problem.bounds)
    # condensed (2 parameters): slack equalities 2n, bounds m n, ground n - 2, foot acceleration 2
    assert not built.lifted
    assert built.solver.size_out("g")[0] == 2 * n + m * n + (n - 2) + 2
    assert built.solver.size_in("x0")[0] == 2 + 4 * n
    # lifted: samples 6n and their equalities; the joint range and velocity bound Y itself
    rich = SwingProblem(model, "LH", make_family("joint-3"))
    lifted = build_nlp(rich)
    assert lifted.lifted and len(rich.input_rows) == 4  # q and qd of both joints
    # ... and, its lift shaped (more than two parameters), the landing speed's samples
    landing = int(rich.grid.landing().sum())
    assert landing > 0
    assert lifted.solver.size_out("g")[0] == 6 * n + 2 * n + (m - 4) * n + (n - 2) + landing + 2
    assert lifted.solver.size_in("x0")[0] == 6 + 6 * n + 4 * n
    # the same shape is never built twice, whatever family of that size or gait
    other = SwingProblem(model.with_gait(Gait(step_length_m=0.2)), "LH", make_family("paper"))
    assert build_nlp(other) is built


def test_feasible_points_have_zero_violation(paper_optima, model):
    problem = SwingProblem(model, "RF", make_family("paper"))
    optimum = paper_optima["RF"]["ipopt"]
    assert problem.evaluate(optimum.theta).violation == 0.0
    start = problem.evaluate(np.zeros(2))
    assert start.reason is not None and start.violation > 0  # (0, 0) is infeasible


def test_pattern_search_on_another_robot(hyq):
    gait = Gait(stance_height_m=hyq.nominal_stance_height_m)
    hyq_model = EnergyPipeline(hyq, gait, loads="trunk")
    reference = hyq_model.robot_cycle(make_family("reference"), legs=("RF", "LH"))
    for leg in ("RF", "LH"):
        optimum = run_pattern_search(SwingProblem(hyq_model, leg, make_family("paper")))
        assert optimum.success, optimum.status
        assert optimum.swing_energy_j < reference.legs[leg].swing_energy_j


@pytest.mark.parametrize(
    ("name", "loads"), [("solo12", "trunk"), ("solo12", "whole-body"), ("go1", "trunk")]
)
def test_ipopt_on_the_paper_family_finds_the_pattern_searchs_minimum_on_small_robots(name, loads):
    # Ipopt from zero, an infeasible start, once raised its barrier parameter to 500 on
    # Solo12, whose swing costs 0.16 J: the iterates went to the middle of the feasible region
    # and ended on a local optimum of 179 J (knee amplitude 198 deg); on Go1 it stopped on one
    # 18 % above, behind a step of the sampled Coulomb friction. The condensed NLP now divides
    # its objective by its value at the start and caps the barrier parameter: checked against
    # the fine pattern search, an independent, derivative-free search of the exact energy.
    robot = load_robot(name)
    pipeline = EnergyPipeline(robot, read_gait(robot=robot), loads=loads)
    for leg in ("RF", "LH"):
        problem = SwingProblem(pipeline, leg, make_family("paper"))
        nlp = run_ipopt(problem)
        search = run_pattern_search(problem, options=PatternSearchOptions(precision=1e-3))
        assert nlp.success and search.success
        # the sampled friction makes the energy step by up to 0.3 % where a sample's joint
        # rate changes sign: the two agree within that, not to the smoothing error
        assert nlp.objective_j <= search.objective_j * 1.005, (leg, nlp.theta, search.theta)


def test_pattern_search_reports_when_nothing_is_feasible(scalf):
    # 0.7 m of clearance under a hip 0.75 m high would fold the knee beyond its limit
    impossible = EnergyPipeline(scalf, Gait(clearance_m=0.7))
    result = run_pattern_search(SwingProblem(impossible, "RF", make_family("paper")))
    assert not result.success
    assert result.status == "no feasible point found"


def coefficients_of(order: int) -> FourierFamily:
    """``joint-N`` with its terms' coefficients as parameters instead of its modes."""
    terms = order_terms(order)
    return FourierFamily(f"joint-{order}", "joint", (terms, terms))


def test_a_badly_conditioned_basis_gets_a_map_that_orthogonalizes_it(model):
    # joint-12's terms' coefficients as parameters (the family before its modes) have a
    # joint-angle basis of condition number 3e9 (the Fourier terms cancel): the NLP's variables
    # x give theta = M x with B_q M orthogonal; joint-6's modes (orthonormal) keep theta
    from scalf_opt.optimize import nlp

    rich = SwingProblem(model.with_gait(Gait(sample_rate_hz=375)), "RF", coefficients_of(12))
    m = nlp.parameter_map(rich, build_nlp(rich).blocks[0])
    angles = rich.path.dense_basis()[0].reshape(-1, rich.n_params)
    assert np.linalg.cond(angles) > nlp.CONDITIONING_ABOVE
    assert np.allclose(np.triu(m), m)
    q = angles @ m
    gram = q.T @ q
    # orthogonal to the round-off of R^-1: the condition number (3e9) times 1e-16, 3e-7 at most
    assert np.allclose(gram, gram[0, 0] * np.eye(rich.n_params), rtol=0, atol=1e-6 * gram[0, 0])
    # the geometric mean of the columns' norms is kept: the family's units on average
    kept = np.exp(np.mean(np.log(np.linalg.norm(q, axis=0))))
    assert kept == pytest.approx(np.exp(np.mean(np.log(np.linalg.norm(angles, axis=0)))))
    default = SwingProblem(model, "RF", make_family(DEFAULT_FAMILY))
    assert np.array_equal(nlp.parameter_map(default, build_nlp(default).blocks[0]), np.eye(18))


def test_conditioning_lets_ipopt_converge_in_fewer_iterations(model, monkeypatch):
    # from zero, SCalf's RF joint-12: conditioned, about 70 iterations to 12.00 J; the plain NLP
    # took 130 to a local optimum of 12.81 J with CasADi's own derivatives and 191 to one of
    # 11.57 J with the kernels' assembled ones (the same values to round-off): in the plain
    # coordinates the path, and the optimum it ends on, follow the round-off
    from scalf_opt.optimize import nlp

    # the constraints it was measured under (with the lift profile the plain NLP did not
    # converge: 25 s, then a failed status)
    margins = LimitMargins(effort_share=0.0, lift=NO_LIFT_PROFILE)
    rich = SwingProblem(
        model.with_gait(Gait(sample_rate_hz=375)), "RF", coefficients_of(12), margins=margins
    )
    conditioned = run_ipopt(rich)
    monkeypatch.setattr(nlp, "parameter_map", lambda problem, block: np.eye(block.n_theta))
    plain = run_ipopt(rich)
    assert conditioned.success and plain.success
    assert conditioned.iterations < 0.7 * plain.iterations
