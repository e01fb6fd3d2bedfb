"""Minimum-norm distribution of the trunk's load over the stance feet (Eq. 29-35, decision 11).

In the sagittal plane, with ``r_k = (x_k, z_k)`` the position of stance foot ``k`` relative to the
trunk's centre of mass (trunk frame) and ``F_k = (F_kx, F_kz)`` the ground reaction force on it,
force and moment balance of the trunk read ``A F = W``::

    A = [[1,      0,     1,      0,    ...],        W = [M a,
         [0,      1,     0,      1,    ...],             M g,
         [z_1,  -x_1,   z_2,   -x_2,   ...]]             0  ]

(the third row is the moment about +y: ``r_z F_x - r_x F_z``). With more unknowns than
equations the least-norm solution ``F = A^+ W = A^T (A A^T)^-1 W`` is taken.
"""

from __future__ import annotations

import numpy as np

GRAVITY_M_S2 = 9.81
"""Gravitational acceleration used by the paper [m/s^2] (decision 1)."""


def balance_matrix(feet_xz_m: np.ndarray) -> np.ndarray:
    """The 3 x 2k matrix ``A`` of sagittal force and moment balance.

    Args:
        feet_xz_m: Stance-foot positions relative to the trunk COM, shape (2, k) [m].
    """
    feet = np.asarray(feet_xz_m, dtype=float)
    k = feet.shape[1]
    a = np.zeros((3, 2 * k))
    a[0, 0::2] = 1.0
    a[1, 1::2] = 1.0
    a[2, 0::2] = feet[1]
    a[2, 1::2] = -feet[0]
    return a


def min_norm_foot_forces(
    feet_xz_m: np.ndarray,
    trunk_mass_kg: float,
    trunk_acceleration_m_s2: float = 0.0,
    gravity_m_s2: float = GRAVITY_M_S2,
) -> np.ndarray:
    """Ground reaction forces on the stance feet, shape (2, k) [N], rows (F_x, F_z).

    Args:
        feet_xz_m: Stance-foot positions relative to the trunk COM, shape (2, k) [m].
        trunk_mass_kg: Mass M carried by the feet [kg].
        trunk_acceleration_m_s2: Forward acceleration a of the trunk [m/s^2].
        gravity_m_s2: g [m/s^2].
    """
    a = balance_matrix(feet_xz_m)
    wrench = np.array([trunk_mass_kg * trunk_acceleration_m_s2, trunk_mass_kg * gravity_m_s2, 0.0])
    forces = np.linalg.pinv(a) @ wrench
    return forces.reshape(-1, 2).T
