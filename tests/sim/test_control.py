"""The stance feedback's force distribution against the pseudo-inverse it replaces."""

import numpy as np
import pytest

from scalf_opt.sim.control import TrunkGains, stance_feedback_nm


def trunk_jacobian(feet_xz: np.ndarray) -> np.ndarray:
    """Rows (x, z) per foot over the trunk's (x, z, pitch) rates, feet fixed on the ground."""
    rows = []
    for x, z in feet_xz:
        rows += [[1.0, 0.0, z], [0.0, 1.0, -x]]
    return np.array(rows)


@pytest.mark.parametrize("feet", [2, 3, 4])
def test_feedback_forces_are_the_minimum_norm_ones(feet):
    rng = np.random.default_rng(feet)
    for _ in range(50):
        xz = np.column_stack([rng.uniform(-0.8, 0.8, feet), rng.uniform(-1.0, -0.6, feet)])
        jac_trunk = trunk_jacobian(xz)
        blocks = [rng.normal(size=(2, 2)) + 2 * np.eye(2) for _ in range(feet)]
        jac_joints = np.zeros((2 * feet, 2 * feet))
        for i, b in enumerate(blocks):
            jac_joints[2 * i : 2 * i + 2, 2 * i : 2 * i + 2] = b
        m = rng.normal(size=(3 + 2 * feet, 3 + 2 * feet))
        mass = m @ m.T + np.eye(3 + 2 * feet)
        error, rate = rng.normal(size=3) * 1e-3, rng.normal(size=3) * 1e-2
        gains = TrunkGains(2 * np.pi * 30.0, 0.7)
        tau = stance_feedback_nm(jac_trunk, jac_joints, mass, error, rate, gains)
        # the same torques through the SVD pseudo-inverse (the definition of minimum norm)
        to_joints = -np.linalg.solve(jac_joints, jac_trunk)
        t_map = np.vstack([np.eye(3), to_joints])
        w, z = gains.omega_rad_s, gains.damping_ratio
        force = t_map.T @ mass @ t_map @ (w**2 * error + 2 * z * w * rate)
        foot = -np.linalg.pinv(jac_trunk.T) @ force
        np.testing.assert_allclose(
            tau, jac_joints.T @ foot, rtol=1e-9, atol=1e-9 * np.abs(tau).max()
        )
        # and they supply the wrench asked: -J_x^T f = F
        np.testing.assert_allclose(-jac_trunk.T @ foot, force, rtol=1e-9)


def test_feet_in_one_point_fall_back_to_least_squares():
    jac_trunk = trunk_jacobian(np.array([[0.1, -0.8], [0.1, -0.8]]))  # rank 2: J^T J singular
    force = np.array([0.0, 1e-3, 0.0]) * 100.0  # inertia identity, error only, omega 10 rad/s
    tau = stance_feedback_nm(
        jac_trunk,
        np.eye(4),
        np.eye(7),
        np.array([0.0, 1e-3, 0.0]),
        np.zeros(3),
        TrunkGains(10.0, 0.7),
    )
    t_map = np.vstack([np.eye(3), -jac_trunk])
    force = t_map.T @ t_map @ force
    np.testing.assert_allclose(tau, -np.linalg.pinv(jac_trunk.T) @ force, rtol=1e-12)
