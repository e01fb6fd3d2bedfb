"""Swing families in foot space: basis derivatives, boundary conditions, nesting."""

import numpy as np
import pytest

from scalf_opt.errors import ConfigError
from scalf_opt.gait import GaitSpec
from scalf_opt.swing import foot_boundary, fourier_term, make_family

GAIT = GaitSpec()


@pytest.mark.parametrize("kind", ["cos", "sin"])
@pytest.mark.parametrize("order", [0, 1, 2, 3, 7])
def test_basis_derivatives_against_finite_differences(kind, order):
    s = np.linspace(0.05, 0.95, 19)
    h = 1e-5
    for d in (0, 1):
        fd = (fourier_term(kind, order, s + h, d) - fourier_term(kind, order, s - h, d)) / (2 * h)
        # central difference: truncation h^2 f'''/6 <= (7 pi)^4 h^2 ~ 2e-4 relative scale
        scale = max(1.0, (order * np.pi) ** (d + 1))
        np.testing.assert_allclose(fd, fourier_term(kind, order, s, d + 1), atol=1e-6 * scale)


def boundary_residuals(family, theta):
    path = family.path(GAIT, None)
    y = path.values(theta)
    b = foot_boundary(GAIT)
    mid = np.argmin(np.abs(path.tau_s - GAIT.swing_duration_s / 2))
    return np.concatenate(
        [
            y[0][:, 0] - b.start,
            y[0][:, -1] - b.end,
            y[1][:, 0] - b.start_rate,
            y[1][:, -1] - b.end_rate,
            y[0][:, mid] - b.mid,
        ]
    )


@pytest.mark.parametrize("name", ["reference", "fourier-3", "fourier-5", "fourier-12"])
def test_every_member_meets_the_boundary_conditions(name):
    family = make_family(name)
    rng = np.random.default_rng(7)
    for _ in range(50):
        theta = rng.normal(0.0, 20.0, family.n_params)
        assert np.max(np.abs(boundary_residuals(family, theta))) < 1e-12


def test_path_derivatives_are_consistent():
    family = make_family("fourier-4")
    gait = GaitSpec(sample_rate_hz=20000)
    theta = np.random.default_rng(3).normal(0, 5, family.n_params)
    path = family.path(gait, None)
    y = path.values(theta)
    dt = path.tau_s[1] - path.tau_s[0]
    for d in (0, 1):
        fd = np.gradient(y[d], dt, axis=1)[:, 2:-2]
        np.testing.assert_allclose(fd, y[d + 1][:, 2:-2], atol=1e-4 * np.max(np.abs(y[d + 1])))


def test_families_are_nested():
    poor, rich = make_family("fourier-3"), make_family("fourier-5")
    theta = np.random.default_rng(11).normal(0, 3, poor.n_params)
    np.testing.assert_allclose(
        rich.path(GAIT, None).values(rich.embed(theta, poor)),
        poor.path(GAIT, None).values(theta),
        atol=1e-14,
    )
    paper, joint3 = make_family("paper"), make_family("joint-4")
    assert set(paper.free_terms) <= set(joint3.free_terms)
    with pytest.raises(ConfigError, match="not nested"):
        poor.embed(np.zeros(paper.n_params), paper)


def test_reference_spline_is_c2_through_the_apex():
    path = make_family("reference").path(GAIT, None)
    y = path.values()
    mid = path.tau_s.size // 2
    assert y[0][1, mid] == pytest.approx(-GAIT.stance_height_m + GAIT.clearance_m, abs=1e-15)
    assert y[0][0, mid] == pytest.approx(0.0, abs=1e-15)
    # second derivative continuous across the middle knot
    assert abs(y[2][1, mid + 1] - y[2][1, mid - 1]) < 0.1 * np.max(np.abs(y[2][1]))


def test_family_names():
    assert make_family("paper").n_params == 2
    assert make_family("joint-3").n_params == 4
    assert make_family("fourier-6").n_params == 16
    assert make_family("paper").parameter_names == ["hip_sin3", "knee_sin3"]
    for bad in ("fourier-2", "fourier-13", "spline", "joint-x"):
        with pytest.raises(ConfigError, match="family"):
            make_family(bad)
