"""The stance phase: the foot path of Table 3 and the ground forces the stance feet carry.

Stance path (in the leg frame, origin at the pitching hip): the foot stays on the ground while
the trunk moves forward at constant speed ``v = S / T_stance``::

    x(t) = d + S/2 - v t,   z(t) = -z0,   t in [0, T_stance]

which is the unique cubic meeting the four boundary conditions of Table 3 (positions
``d +- S/2``, velocities -v at both ends). ``d`` is the gait's stance x-offset of the leg's pair
(front or hind; the paper's 0: the foot passes under the hip at mid-stance). The trunk's
acceleration is ``-x''(t) = 0``.

Foot forces: at every stance sample the feet on the ground share the trunk's load by the
minimum-norm distribution (:mod:`scalf_opt.locomotion.forces`, decision 11).
"""

from __future__ import annotations

import numpy as np

from scalf_opt.locomotion.forces import min_norm_foot_forces
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.trot import (
    DIAGONAL_PARTNER,
    stance_start_s,
    support_groups,
    support_masks,
    time_since_touchdown_s,
)


def stance_path(gait: Gait, t_s: np.ndarray, leg: str) -> np.ndarray:
    """Stance foot position, velocity and acceleration in the leg frame, shape (3, 2, n).

    Args:
        gait: The gait.
        t_s: Times since touch-down [s], shape (n,).
        leg: The leg (its pair's stance x-offset applies).
    """
    t = np.asarray(t_s, dtype=float)
    v = gait.speed_m_s
    x = gait.stance_x_offset_m(leg) + 0.5 * gait.step_length_m - v * t
    p = np.vstack([x, np.full_like(t, -gait.stance_height_m)])
    pd = np.vstack([np.full_like(t, -v), np.zeros_like(t)])
    return np.array([p, pd, np.zeros((2, t.size))])


def trunk_acceleration_m_s2(gait: Gait, t_s: np.ndarray) -> np.ndarray:
    """Forward acceleration of the trunk during stance [m/s^2], shape (n,): ``-x''(t)``."""
    return -stance_path(gait, t_s, "RF")[2, 0]  # the same for every leg


def stance_forces(
    gait: Gait, hips_xz_m: dict[str, np.ndarray], trunk_mass_kg: float
) -> dict[str, np.ndarray]:
    """Ground reaction force on each leg's foot over its stance samples, each (2, n) [N].

    Args:
        gait: The gait (its stance grid).
        hips_xz_m: Pitching-hip position (x, z) of every leg relative to the trunk COM [m].
        trunk_mass_kg: Mass the feet carry [kg].
    """
    t = gait.phase_times_s("stance")
    accel = trunk_acceleration_m_s2(gait, t)
    forces = {}
    for leg in hips_xz_m:
        cycle_times = stance_start_s(gait, leg) + t
        standing = support_masks(gait, cycle_times, leg)
        feet = {}  # every leg's stance foot at every sample (used where it stands)
        for other in standing:
            pair = other in (leg, DIAGONAL_PARTNER[leg])
            local = t if pair else time_since_touchdown_s(gait, cycle_times, other)
            feet[other] = stance_path(gait, local, other)[0] + hips_xz_m[other][:, None]
        f_leg = np.zeros((2, t.size))
        # the samples with the same feet on the ground, as one stack (leg first among them)
        for at, on in support_groups(standing):
            stack = np.stack([feet[other][:, at].T for other in on], axis=-1)  # (m, 2, k)
            f = min_norm_foot_forces(stack, trunk_mass_kg, accel[at])
            f_leg[:, at] = f[:, :, 0].T
        forces[leg] = f_leg
    return forces
