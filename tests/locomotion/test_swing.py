"""Swing families: basis derivatives, boundary conditions of random members, nesting."""

import numpy as np
import pytest

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.boundary import foot_boundary, joint_boundary
from scalf_opt.locomotion.swing.family import PARAMETER_SCALE
from scalf_opt.locomotion.swing.fourier import ELIMINATED_TERMS, FourierFamily, fourier_term
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.kinematics import LegKinematics

GAIT = Gait()


@pytest.fixture(scope="module")
def kinematics(scalf):
    return {leg: LegKinematics(scalf.leg(leg)) for leg in ("RF", "LH")}


@pytest.mark.parametrize("kind", ["cos", "sin"])
@pytest.mark.parametrize("order", [0, 1, 2, 3, 7])
def test_basis_derivatives_against_finite_differences(kind, order):
    s = np.linspace(0.05, 0.95, 19)
    h = 1e-5
    for d in (0, 1):
        fd = (fourier_term(kind, order, s + h, d) - fourier_term(kind, order, s - h, d)) / (2 * h)
        # central difference: truncation h^2 |f'''| / 6 <= h^2 (7 pi)^(d+3) / 6 ~ 1e-6 scale
        scale = max(1.0, (order * np.pi) ** (d + 1))
        np.testing.assert_allclose(fd, fourier_term(kind, order, s, d + 1), atol=1e-6 * scale)


def end_residuals(path, theta, boundary):
    y = path.values(theta)
    return np.concatenate(
        [
            y[0][:, 0] - boundary.start,
            y[0][:, -1] - boundary.end,
            y[1][:, 0] - boundary.start_rate,
            y[1][:, -1] - boundary.end_rate,
        ]
    )


@pytest.mark.parametrize(
    "name", ["reference", "paper", "fourier-2", "fourier-5", "fourier-12", "joint-3", "joint-8"]
)
@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_every_member_meets_the_boundary_conditions(kinematics, name, leg):
    family = make_family(name)
    kin = kinematics[leg]
    boundary = (
        joint_boundary(GAIT, kin) if family.space == "joint" else foot_boundary(GAIT, kin.leg.name)
    )
    path = family.path(GAIT, kin)
    rng = np.random.default_rng(7)
    for _ in range(50):
        theta = rng.normal(0.0, 20.0, family.n_params)
        residual = end_residuals(path, theta, boundary)
        assert np.max(np.abs(residual)) < 1e-12 * max(1.0, np.abs(boundary.start_rate).max())


def test_joint_boundary_is_the_stance_seen_through_ik(kinematics):
    kin = kinematics["RF"]
    b_joint, b_foot = joint_boundary(GAIT, kin), foot_boundary(GAIT, kin.leg.name)
    np.testing.assert_allclose(kin.forward(b_joint.start), b_foot.start, atol=1e-12)
    np.testing.assert_allclose(
        kin.jacobian(b_joint.end) @ b_joint.end_rate, b_foot.end_rate, atol=1e-12
    )


def test_path_derivatives_are_consistent(kinematics):
    gait = Gait(sample_rate_hz=20000)
    for name in ("fourier-4", "joint-4"):
        family = make_family(name)
        theta = np.random.default_rng(3).normal(0, 5, family.n_params)
        path = family.path(gait, kinematics["RF"])
        y = path.values(theta)
        dt = path.t_s[1] - path.t_s[0]
        for d in (0, 1):
            fd = np.gradient(y[d], dt, axis=1)[:, 2:-2]
            np.testing.assert_allclose(fd, y[d + 1][:, 2:-2], atol=1e-4 * np.max(np.abs(y[d + 1])))


def test_families_are_nested(kinematics):
    kin = kinematics["LH"]
    for poor_name, rich_name in (
        ("fourier-3", "fourier-5"),
        ("paper", "joint-3"),
        ("joint-2", "joint-6"),
    ):
        poor, rich = make_family(poor_name), make_family(rich_name)
        theta = np.random.default_rng(11).normal(0, 3, poor.n_params)
        np.testing.assert_allclose(
            rich.path(GAIT, kin).values(rich.embed(theta, poor)),
            poor.path(GAIT, kin).values(theta),
            atol=1e-13,
        )
    with pytest.raises(ConfigError, match="not nested"):
        make_family("fourier-3").embed(np.zeros(2), make_family("paper"))


@pytest.mark.parametrize(("name", "tolerance"), [("joint-3", 1e-10), ("fourier-12", 1e-6)])
def test_modes_are_orthonormal_over_the_swing_and_span_the_terms(kinematics, name, tolerance):
    """A mode has an rms of one unit over the swing and is orthogonal to the others (checked by
    Simpson's rule on 20,001 samples, not the Gauss-Legendre nodes that built them), and a
    member is the coefficients' family member at its Fourier coefficients.

    Simpson's rule errs by about 2e-10 on products of order 24; an order-12 mode is a sum of
    terms whose coefficients reach the terms' condition number (3e9) times the mode's size, so
    it carries their round-off, 3e9 x 1.1e-16 = 3e-7 at most (measured 3e-8)."""
    from scipy.integrate import simpson

    modes = make_family(name)
    terms = modes.free_terms
    coefficients = FourierFamily(name, modes.space, terms)
    fine = Gait(sample_rate_hz=20_000 / GAIT.swing_duration_s)
    path = modes.path(fine, kinematics["RF"])
    s = path.t_s / GAIT.swing_duration_s
    unit = PARAMETER_SCALE[modes.space]
    for c, block in enumerate((slice(0, len(terms[0])), slice(len(terms[0]), None))):
        columns = path.dense_basis()[0, c][:, block] / unit
        gram = simpson(columns[:, :, None] * columns[:, None, :], x=s, axis=0)
        np.testing.assert_allclose(gram, np.eye(gram.shape[0]), rtol=0, atol=tolerance)
    theta = np.random.default_rng(5).normal(0.0, 2.0, modes.n_params)
    as_terms = modes.fourier_coefficients(theta)
    np.testing.assert_allclose(modes.from_fourier_coefficients(as_terms), theta, atol=tolerance)
    exact = coefficients.path(GAIT, kinematics["RF"]).values(as_terms)
    np.testing.assert_allclose(
        modes.path(GAIT, kinematics["RF"]).values(theta),
        exact,
        rtol=0,
        atol=tolerance * np.abs(exact).max(),
    )


def test_a_mode_is_its_share_of_the_departure_from_the_base_path(kinematics):
    # Parseval: the parameters' root sum of squares is the departure's rms, in degrees, so no
    # parameter exceeds the departure's largest value
    family = make_family("joint-12")
    fine = Gait(sample_rate_hz=20_000 / GAIT.swing_duration_s)
    path = family.path(fine, kinematics["LH"])
    theta = np.random.default_rng(9).normal(0.0, 3.0, family.n_params)
    departure = (path.values(theta) - path.base)[0] / PARAMETER_SCALE["joint"]
    rms = np.sqrt(np.mean(departure**2, axis=1))
    half = family.n_params // 2
    np.testing.assert_allclose(
        rms, [np.linalg.norm(theta[:half]), np.linalg.norm(theta[half:])], rtol=1e-4
    )
    assert np.all(np.abs(theta[:half]) <= np.abs(departure[0]).max())
    assert family.parameter_names[:2] == ["hip_mode1", "hip_mode2"]
    assert family.parameter_names[half] == "knee_mode1"
    assert make_family("fourier-2").parameter_names == ["x_mode1", "z_mode1"]


def test_saved_coefficients_and_named_modes_read_back_as_the_same_member(kinematics):
    family = make_family("joint-4")
    theta = np.random.default_rng(2).normal(0.0, 4.0, family.n_params)
    coefficients = family.fourier_coefficients(theta)
    np.testing.assert_allclose(family.theta_from_record(coefficients, None), theta, atol=1e-12)
    np.testing.assert_allclose(
        family.theta_from_record(coefficients, family.coefficient_names), theta, atol=1e-12
    )
    assert np.array_equal(family.theta_from_record(theta, family.parameter_names), theta)
    with pytest.raises(ConfigError, match="neither"):
        family.theta_from_record(theta, ["a"] * family.n_params)
    paper = make_family("paper")  # its parameters are its coefficients
    assert np.array_equal(paper.theta_from_record([1.0, 2.0], None), [1.0, 2.0])


def test_reference_spline_is_c2_through_the_apex(kinematics):
    kin = kinematics["RF"]
    path = make_family("reference").path(GAIT, kin)
    y = path.values()
    mid = path.t_s.size // 2
    assert y[0][1, mid] == pytest.approx(-GAIT.stance_height_m + GAIT.clearance_m, abs=1e-15)
    assert y[0][0, mid] == pytest.approx(0.0, abs=1e-15)
    assert abs(y[2][1, mid + 1] - y[2][1, mid - 1]) < 0.1 * np.max(np.abs(y[2][1]))
    boundary = foot_boundary(GAIT, kin.leg.name)
    np.testing.assert_allclose(end_residuals(path, None, boundary), 0.0, atol=1e-14)


def test_family_names_and_sizes():
    assert make_family("paper").n_params == 2
    assert make_family("paper").parameter_names == ["hip_cos3", "knee_cos2"]
    assert make_family("joint-2").n_params == 2
    assert make_family("joint-3").n_params == 6
    assert make_family("fourier-6").n_params == 18
    for bad in ("fourier-1", "fourier-13", "spline", "joint-x"):
        with pytest.raises(ConfigError, match="family"):
            make_family(bad)
    with pytest.raises(ConfigError, match="eliminated"):
        FourierFamily("bad", "joint", ((ELIMINATED_TERMS[0],), ()))


def test_swing_grid_has_a_mid_sample():
    for rate in (200, 210, 333):
        tau = Gait(sample_rate_hz=rate).phase_times_s("swing")
        assert (tau.size - 1) % 2 == 0
        assert tau[(tau.size - 1) // 2] == pytest.approx(GAIT.swing_duration_s / 2)


def test_reference_spline_equals_scipy_clamped_cubic_spline():
    from scipy.interpolate import CubicSpline

    from scalf_opt.locomotion.swing.reference import clamped_spline

    rng = np.random.default_rng(5)
    for _ in range(20):
        y, slopes, h = rng.normal(size=3), rng.normal(size=2), rng.uniform(0.05, 0.5)
        t = np.linspace(0.0, 2 * h, 41)
        ours = clamped_spline(tuple(y), tuple(slopes), h, t)
        spline = CubicSpline([0, h, 2 * h], y, bc_type=((1, slopes[0]), (1, slopes[1])))
        for d in range(3):
            np.testing.assert_allclose(ours[d], spline(t, d), rtol=1e-12, atol=1e-12 / h**d)


@pytest.mark.parametrize("spans", [2, 5, 16])
@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_bspline_members_meet_the_boundary_conditions(kinematics, spans, leg):
    kin = kinematics[leg]
    family = make_family(f"bspline-{spans}")
    assert family.n_params == 2 * (spans - 1)
    path = family.path(GAIT, kin)
    rng = np.random.default_rng(spans)
    for _ in range(5):
        theta = rng.normal(scale=20.0, size=family.n_params)
        residual = end_residuals(path, theta, joint_boundary(GAIT, kin))
        np.testing.assert_allclose(residual, 0.0, atol=1e-12)


def test_bspline_design_matrix_derivatives_against_finite_differences():
    from scalf_opt.locomotion.swing.bspline import design_matrices

    s = (np.arange(40) + 0.37) / 40  # never a knot (a multiple of 1/8)
    h = 1e-6
    for d in (0, 1):
        fd = (design_matrices(8, s + h)[d] - design_matrices(8, s - h)[d]) / (2 * h)
        # central differences of cubic pieces; knots (multiples of 1/8) avoided by the grid
        np.testing.assert_allclose(fd, design_matrices(8, s)[d + 1], atol=1e-5 * 8 ** (d + 1))
    # a partition of unity, and at the ends only the end control point counts
    np.testing.assert_allclose(design_matrices(8, s)[0].sum(axis=1), 1.0, atol=1e-14)
    ends = design_matrices(8, np.array([0.0, 1.0]))[0]
    np.testing.assert_allclose(ends[0], np.eye(11)[0], atol=1e-14)
    np.testing.assert_allclose(ends[1], np.eye(11)[-1], atol=1e-14)


def test_sparse_bspline_design_matrices_match_scipys_splines():
    # the sparse derivative chain against SciPy's BSpline with identity coefficients, on and
    # between knots, at both ends
    from scipy.interpolate import BSpline

    from scalf_opt.locomotion.swing.bspline import knots, sparse_design_matrices

    for spans in (2, 3, 16):
        s = np.concatenate([np.linspace(0.0, 1.0, 8 * spans + 1), [0.123, 0.871]])
        spline = BSpline(knots(spans), np.eye(spans + 3), 3, extrapolate=True)
        for d, matrix in enumerate(sparse_design_matrices(spans, s)):
            expected = spline.derivative(d)(s) if d else spline(s)
            np.testing.assert_allclose(matrix.toarray(), expected, rtol=0, atol=1e-9 * spans**d)


def test_a_sparse_path_gives_the_dense_paths_samples(kinematics):
    from scalf_opt.locomotion.swing.family import AffinePath

    path = make_family("bspline-8").path(GAIT, kinematics["RF"])
    assert path.sparse
    dense = AffinePath(path.space, path.t_s, path.base, path.dense_basis())
    theta = np.random.default_rng(5).normal(scale=10.0, size=path.n_params)
    np.testing.assert_allclose(path.values(theta), dense.values(theta), rtol=1e-13, atol=1e-9)
    np.testing.assert_array_equal(path.basis_rows().toarray(), dense.basis_rows())


def test_bspline_families_are_nested(kinematics):
    # knot insertion: every member of bspline-K is a member of bspline-2K (exact fit)
    kin = kinematics["RF"]
    coarse, fine = make_family("bspline-8"), make_family("bspline-16")
    theta = np.random.default_rng(2).normal(scale=15.0, size=coarse.n_params)
    target = coarse.path(GAIT, kin).values(theta)
    fine_path = fine.path(GAIT, kin)
    design = fine_path.dense_basis().reshape(-1, fine.n_params)
    fit, *_ = np.linalg.lstsq(design, (target - fine_path.base).ravel(), rcond=None)
    np.testing.assert_allclose(fine_path.values(fit), target, atol=1e-9)


def test_stance_offset_moves_the_stance_and_the_swing_ends(kinematics):
    from dataclasses import replace

    gait = replace(GAIT, stance_x_offset_front_m=0.04, stance_x_offset_hind_m=-0.03)
    front, hind = foot_boundary(gait, "RF"), foot_boundary(gait, "LH")
    base = foot_boundary(GAIT, "RF")
    np.testing.assert_allclose(front.start - base.start, [0.04, 0.0], atol=1e-15)
    np.testing.assert_allclose(hind.end - base.end, [-0.03, 0.0], atol=1e-15)
    # the reference's apex is midway between lift-off and touch-down
    path = make_family("reference").path(gait, kinematics["RF"])
    mid = path.t_s.size // 2
    assert path.values()[0][0, mid] == pytest.approx(0.04, abs=1e-15)
