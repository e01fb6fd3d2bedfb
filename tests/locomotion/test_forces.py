"""Minimum-norm foot-force distribution: balance, symmetry, hand-computed cases."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scalf_opt.locomotion.forces import balance_matrix, min_norm_foot_forces

G = 9.81
M = 200.0


def residual(feet, forces, mass, accel):
    wrench = np.array([mass * accel, mass * G, 0.0])
    return balance_matrix(feet) @ forces.T.ravel() - wrench


def test_symmetric_feet_carry_half_the_weight_each():
    # feet symmetric about the COM: each carries M g / 2 = 981 N (paper's Fig. 13: about 980 N)
    feet = np.array([[0.68, -0.68], [-0.945, -0.945]])
    f = min_norm_foot_forces(feet, M)
    np.testing.assert_allclose(f[1], [M * G / 2, M * G / 2], rtol=0, atol=1e-9)
    np.testing.assert_allclose(f[0], [0.0, 0.0], atol=1e-9)


def test_hand_computed_asymmetric_case():
    # Feet at x1 = 1, x2 = -0.5, both at z = -1, a = 0.
    # Unknowns (F1x, F1z, F2x, F2z); A = [[1,0,1,0],[0,1,0,1],[-1,-1,-1,0.5]], W = (0, Mg, 0).
    # Min-norm: F = A^T (A A^T)^-1 W. A A^T = [[2,0,-2],[0,2,-0.5],[-2,-0.5,3.25]].
    a = np.array([[1, 0, 1, 0], [0, 1, 0, 1], [-1, -1, -1, 0.5]], dtype=float)
    w = np.array([0.0, M * G, 0.0])
    expected = a.T @ np.linalg.solve(a @ a.T, w)
    f = min_norm_foot_forces(np.array([[1.0, -0.5], [-1.0, -1.0]]), M)
    np.testing.assert_allclose(f.T.ravel(), expected, rtol=1e-12, atol=1e-9)
    # and it is the least-norm member of the solution set: orthogonal to the null space of A
    null = np.linalg.svd(a)[2][-1]
    assert abs(null @ f.T.ravel()) < 1e-9


@settings(max_examples=200, deadline=None)
@given(
    x1=st.floats(0.3, 1.2),
    x2=st.floats(-1.2, -0.3),
    z1=st.floats(-1.2, -0.5),
    z2=st.floats(-1.2, -0.5),
    accel=st.floats(-3.0, 3.0),
)
def test_balance_residual_below_1e9_newton(x1, x2, z1, z2, accel):
    feet = np.array([[x1, x2], [z1, z2]])
    f = min_norm_foot_forces(feet, M, accel)
    assert np.max(np.abs(residual(feet, f, M, accel))) < 1e-9


def test_four_feet_balance():
    feet = np.array([[0.8, 0.6, -0.6, -0.7], [-0.95, -0.95, -0.95, -0.95]])
    f = min_norm_foot_forces(feet, M, 0.5)
    assert np.max(np.abs(residual(feet, f, M, 0.5))) < 1e-9


@pytest.mark.parametrize("accel", [-2.0, 2.0])
def test_trunk_acceleration_is_carried_by_horizontal_forces(accel):
    feet = np.array([[0.68, -0.68], [-0.945, -0.945]])
    f = min_norm_foot_forces(feet, M, accel)
    assert f[0].sum() == pytest.approx(M * accel, rel=1e-12)


def test_a_stack_of_stances_gives_each_stance_s_forces():
    rng = np.random.default_rng(0)
    feet = np.stack([rng.uniform(-1.0, 1.0, (2, 3)) - [[0.0], [1.0]] for _ in range(5)])
    accel = rng.uniform(-2.0, 2.0, 5)
    stacked = min_norm_foot_forces(feet, M, accel)
    assert stacked.shape == (5, 2, 3)
    for j in range(5):
        np.testing.assert_array_equal(stacked[j], min_norm_foot_forces(feet[j], M, accel[j]))
        assert np.max(np.abs(residual(feet[j], stacked[j], M, accel[j]))) < 1e-9


def test_a_stack_of_3d_stances_gives_each_stance_s_maps():
    from scalf_opt.locomotion.forces import contact_maps

    rng = np.random.default_rng(1)
    feet = rng.uniform(-0.5, 0.5, (4, 3, 2)) - np.array([[0.0], [0.0], [0.9]])
    forces, unbalanced = contact_maps(feet)
    assert forces.shape == (4, 6, 6) and unbalanced.shape == (4, 3, 6)
    for j in range(4):
        f, u = contact_maps(feet[j])
        np.testing.assert_array_equal(forces[j], f)
        np.testing.assert_array_equal(unbalanced[j], u)
