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
        feet_xz_m: Stance-foot positions relative to the trunk COM, shape (..., 2, k) [m]
            (leading axes: a stack of stances, one matrix each).
    """
    feet = np.asarray(feet_xz_m, dtype=float)
    k = feet.shape[-1]
    a = np.zeros((*feet.shape[:-2], 3, 2 * k))
    a[..., 0, 0::2] = 1.0
    a[..., 1, 1::2] = 1.0
    a[..., 2, 0::2] = feet[..., 1, :]
    a[..., 2, 1::2] = -feet[..., 0, :]
    return a


def min_norm_foot_forces(
    feet_xz_m: np.ndarray,
    trunk_mass_kg: float,
    trunk_acceleration_m_s2: float | np.ndarray = 0.0,
    gravity_m_s2: float = GRAVITY_M_S2,
) -> np.ndarray:
    """Ground reaction forces on the stance feet, shape (..., 2, k) [N], rows (F_x, F_z).

    Args:
        feet_xz_m: Stance-foot positions relative to the trunk COM, shape (..., 2, k) [m]
            (leading axes: a stack of stances with the same number of feet).
        trunk_mass_kg: Mass M carried by the feet [kg].
        trunk_acceleration_m_s2: Forward acceleration a of the trunk [m/s^2], a number or
            one per stance of the stack (shape ``...``).
        gravity_m_s2: g [m/s^2].
    """
    a = balance_matrix(feet_xz_m)
    accel = np.broadcast_to(np.asarray(trunk_acceleration_m_s2, dtype=float), a.shape[:-2])
    wrench = np.zeros((*a.shape[:-2], 3))
    wrench[..., 0] = trunk_mass_kg * accel
    wrench[..., 1] = trunk_mass_kg * gravity_m_s2
    forces = (np.linalg.pinv(a) @ wrench[..., None])[..., 0]
    return np.swapaxes(forces.reshape(*forces.shape[:-1], -1, 2), -1, -2)


def cross_matrix(r: np.ndarray) -> np.ndarray:
    """``[r]_x`` (..., 3, 3): ``r x f = [r]_x f``, for ``r`` of shape (..., 3)."""
    r = np.asarray(r, dtype=float)
    out = np.zeros((*r.shape[:-1], 3, 3))
    out[..., 0, 1], out[..., 0, 2] = -r[..., 2], r[..., 1]
    out[..., 1, 0], out[..., 1, 2] = r[..., 2], -r[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -r[..., 1], r[..., 0]
    return out


def contact_maps(feet_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The minimum-norm maps from a required wrench to point-foot forces, in 3-D.

    With ``p_k`` the stance feet's positions in the trunk frame and ``c`` their centroid, the
    feet supply the wrench ``W_c = (sum F_k, sum (p_k - c) x F_k)`` about ``c``: ``W_c = A F``.
    The forces taken are ``F = A^+ W_c`` (Moore-Penrose pseudo-inverse): among the forces that
    supply the closest wrench, the smallest. So the distribution has no internal forces (no
    component in the null space of ``A``: two feet do not squeeze or pull each other).

    Two point feet cannot supply a moment about the line joining them (``A`` has rank 5); the
    centroid lies on that line, so the least-squares residual ``W_c - A F`` is exactly that
    moment (a pure moment, the same about any point): what this stance cannot balance.

    Both maps are linear in the wrench ``W`` (force, then moment about the trunk origin):

    Args:
        feet_m: Stance-foot positions in the trunk frame, shape (..., 3, k) [m], k >= 2
            (leading axes: a stack of stances with the same number of feet).

    Returns:
        ``(forces, unbalanced)``: ``forces`` (..., 3k, 6) maps ``W`` to the stacked foot
        forces ``(F_1, ..., F_k)``; ``unbalanced`` (..., 3, 6) maps it to the moment the feet
        cannot supply.
    """
    feet = np.asarray(feet_m, dtype=float)
    centroid = feet.mean(axis=-1)
    k = feet.shape[-1]
    stack = feet.shape[:-2]
    a = np.zeros((*stack, 6, 3 * k))
    for j in range(k):
        a[..., 0:3, 3 * j : 3 * j + 3] = np.eye(3)
        a[..., 3:6, 3 * j : 3 * j + 3] = cross_matrix(feet[..., :, j] - centroid)
    shift = np.broadcast_to(np.eye(6), (*stack, 6, 6)).copy()  # W about the origin -> about c
    shift[..., 3:6, 0:3] = -cross_matrix(centroid)
    forces = np.linalg.pinv(a, rcond=1e-10) @ shift
    return forces, shift[..., 3:6, :] - a[..., 3:6, :] @ forces


def sagittal_contact_maps(feet_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The minimum-norm maps of the sagittal distribution, in the shapes of :func:`contact_maps`.

    Only the wrench's forward and vertical forces and its pitch moment (about +y) are supplied:
    ``F = A^+ (W_x, W_z, M_y)`` with ``A`` the :func:`balance_matrix` of the feet's ``(x, z)``
    about the trunk origin, and no lateral foot force. This is how the feet share the load of a
    trunk that moves in its sagittal plane only, such as the simulation referee's planar trunk,
    whose joint takes the rest: two diagonal feet then supply the whole pitch moment, and the
    roll moment that their vertical forces' difference makes is left to the trunk.

    Args:
        feet_m: Stance-foot positions in the trunk frame, shape (..., 3, k) [m], k >= 2.

    Returns:
        ``(forces, unbalanced)`` as :func:`contact_maps`'s: ``unbalanced`` maps ``W`` to the
        moment about the trunk origin the forces leave, ``M - sum p_k x F_k`` (a pure moment
        when ``W_y`` is zero, as for legs that move in their sagittal planes).
    """
    feet = np.asarray(feet_m, dtype=float)
    k = feet.shape[-1]
    stack = feet.shape[:-2]
    pick = np.zeros((3, 6))
    pick[0, 0] = pick[1, 2] = pick[2, 4] = 1.0  # (W_x, W_z, M_y)
    sagittal = np.linalg.pinv(balance_matrix(feet[..., [0, 2], :]), rcond=1e-10) @ pick
    forces = np.zeros((*stack, 3 * k, 6))
    forces[..., 0::3, :] = sagittal[..., 0::2, :]
    forces[..., 2::3, :] = sagittal[..., 1::2, :]
    moment = np.zeros((*stack, 3, 6))
    moment[..., :, 3:6] = np.eye(3)
    for j in range(k):
        moment -= cross_matrix(feet[..., :, j]) @ forces[..., 3 * j : 3 * j + 3, :]
    return forces, moment


def min_norm_contact_forces(
    feet_m: np.ndarray, wrench: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Point-foot forces that supply ``wrench``, and the moment they cannot supply.

    Args:
        feet_m: Stance-foot positions in the trunk frame, shape (3, k) [m].
        wrench: Wrench the feet must supply, force [N] then moment about the trunk origin
            [N m], trunk axes, shape (6,).

    Returns:
        ``(forces, unbalanced)``: forces on the feet (3, k) [N]; the unbalanced moment (3,)
        [N m] (zero with three or more feet not in a line). See :func:`contact_maps`.
    """
    forces, unbalanced = contact_maps(feet_m)
    w = np.asarray(wrench, dtype=float)
    return (forces @ w).reshape(-1, 3).T, unbalanced @ w
