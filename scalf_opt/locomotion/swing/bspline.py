r"""Dense cubic B-splines in joint space: the family behind the free-trajectory bound.

Each joint angle is a clamped cubic B-spline over the swing with ``K`` equal spans
(``K + 3`` control points ``c_0 .. c_{K+2}``; knots ``0, 0, 0, 0, 1/K, ..., 1, 1, 1, 1`` in
normalised time ``s = t / T_sw``). It is twice continuously differentiable: joint accelerations,
torques and powers are continuous. The clamped ends give the boundary conditions directly:

.. math::

    y(0) = c_0, \quad y'(0) = \frac{3 K}{T_{sw}} (c_1 - c_0), \qquad
    y(1) = c_{K+2}, \quad y'(1) = \frac{3 K}{T_{sw}} (c_{K+2} - c_{K+1}),

so ``c_0, c_1, c_{K+1}, c_{K+2}`` are fixed by the swing's end conditions (the same as every
family's) and the ``K - 1`` interior control points of each joint are free: ``2 (K - 1)``
parameters per leg, in degrees. Doubling ``K`` inserts a knot in every span, so ``bspline-K`` is
inside ``bspline-2K`` (nested), and the refinement of :mod:`scalf_opt.optimize.bound` can only
lower the optimum. Each sample depends on four control points: the path's basis is sparse, which
the NLP exploits.
"""

from __future__ import annotations

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import PARAMETER_SCALE, AffinePath, SwingFamily
from scalf_opt.model.kinematics import LegKinematics

DEGREE = 3
"""Cubic splines: C2 joint motion."""

MIN_SPANS = 2


def knots(spans: int) -> np.ndarray:
    """Clamped uniform knot vector on [0, 1] with ``spans`` equal spans."""
    inner = np.linspace(0.0, 1.0, spans + 1)
    return np.concatenate([np.zeros(DEGREE), inner, np.ones(DEGREE)])


def design_matrices(spans: int, s: np.ndarray) -> np.ndarray:
    """Values and first two derivatives (in ``s``) of every basis function at ``s``.

    Returns:
        Shape (3, n, spans + 3): ``[d, i, j]`` is the d-th derivative of basis function ``j`` at
        ``s[i]``.
    """
    from scipy.interpolate import BSpline  # imported here: scipy.interpolate is slow to load

    count = spans + DEGREE
    # one spline per basis function (identity coefficients); on [0, 1] the polynomial pieces
    # extend to the closed interval, so s = 1 gets the last span's one-sided limit
    spline = BSpline(knots(spans), np.eye(count), DEGREE, extrapolate=True)
    s = np.clip(np.asarray(s, dtype=float), 0.0, 1.0)
    return np.array([spline(s), spline.derivative(1)(s), spline.derivative(2)(s)])


class BSplineFamily(SwingFamily):
    """Clamped cubic B-splines of the joint angles with ``spans`` equal spans.

    Args:
        spans: Number of spans K (>= 2); the family has ``2 (K - 1)`` parameters.
    """

    space = "joint"

    def __init__(self, spans: int) -> None:
        if spans < MIN_SPANS:
            raise ConfigError(f"B-spline family: spans must be >= {MIN_SPANS}, got {spans}")
        self.spans = spans
        self.name = f"bspline-{spans}"
        free = tuple(("cp", j) for j in range(2, spans + 1))
        self.free_terms = (free, free)

    def shortest_period_s(self, swing_duration_s: float) -> float:
        """Four spans, the support of one basis function: its narrowest bump [s].

        (Alternating control points make a two-span oscillation, but a cubic B-spline damps
        it to a few per cent of theirs; the sampling check refines the rate if it matters.)
        """
        return 4.0 * swing_duration_s / self.spans

    def path(  # noqa: D102
        self, gait: Gait, kin: LegKinematics, t_s: np.ndarray | None = None
    ) -> AffinePath:
        b = self.boundary(gait, kin)
        t = gait.phase_times_s("swing") if t_s is None else np.asarray(t_s, dtype=float)
        k = self.spans
        basis_s = design_matrices(k, t / b.duration_s)
        time_scale = np.array([1.0, 1.0 / b.duration_s, 1.0 / b.duration_s**2])[:, None, None]
        phi = basis_s * time_scale  # d/dt = (1/T_sw) d/ds
        free = np.arange(2, k + 1)
        fixed = np.array([0, 1, k + 1, k + 2])
        scale = PARAMETER_SCALE["joint"]
        base = np.zeros((3, 2, t.size))
        basis = np.zeros((3, 2, t.size, self.n_params))
        for c in range(2):
            step = b.duration_s / (3 * k)
            end_points = np.array(
                [
                    b.start[c],
                    b.start[c] + step * b.start_rate[c],
                    b.end[c] - step * b.end_rate[c],
                    b.end[c],
                ]
            )
            base[:, c] = phi[:, :, fixed] @ end_points
            columns = slice(c * (k - 1), (c + 1) * (k - 1))
            basis[:, c, :, columns] = scale * phi[:, :, free]
        return AffinePath(self.space, t, base, basis)
