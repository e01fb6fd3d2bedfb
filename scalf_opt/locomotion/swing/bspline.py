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

from typing import TYPE_CHECKING

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import PARAMETER_SCALE, AffinePath, SwingFamily
from scalf_opt.model.kinematics import LegKinematics

if TYPE_CHECKING:
    from scipy.sparse import csr_array

DEGREE = 3
"""Cubic splines: C2 joint motion."""

MIN_SPANS = 2


def knots(spans: int) -> np.ndarray:
    """Clamped uniform knot vector on [0, 1] with ``spans`` equal spans."""
    inner = np.linspace(0.0, 1.0, spans + 1)
    return np.concatenate([np.zeros(DEGREE), inner, np.ones(DEGREE)])


def sparse_design_matrices(spans: int, s: np.ndarray) -> list[csr_array]:
    """Values and first two derivatives (in ``s``) of every basis function at ``s``, sparse.

    The derivative of a spline of degree ``p`` on knots ``t`` is a spline of degree ``p - 1`` on
    ``t[1:-1]`` whose coefficients are the scaled differences ``p (c_i - c_(i-1)) /
    (t_(i+p) - t_i)`` (what SciPy's ``BSpline.derivative`` does): each matrix is SciPy's
    sparse design matrix of the lower degree times those difference matrices.

    Returns:
        Three matrices of shape (n, spans + 3): entry ``[i, j]`` of the d-th is the d-th
        derivative of basis function ``j`` at ``s[i]``.
    """
    from scipy.interpolate import BSpline  # imported here: scipy.interpolate is slow to load
    from scipy.sparse import csr_array, diags_array

    t = knots(spans)
    s = np.clip(np.asarray(s, dtype=float), 0.0, 1.0)
    out = []
    chain = None  # the difference matrices of the derivatives taken so far
    for d in range(3):
        degree = DEGREE - d
        inner = t[d : t.size - d]
        design = BSpline.design_matrix(s, inner, degree)
        out.append(csr_array(design if chain is None else design @ chain))
        count = inner.size - degree - 1  # basis functions of this degree
        rate = degree / (inner[degree + 1 : degree + count] - inner[1:count])
        step = diags_array([-rate, rate], offsets=[0, 1], shape=(count - 1, count))
        chain = step if chain is None else step @ chain
    return out


def design_matrices(spans: int, s: np.ndarray) -> np.ndarray:
    """:func:`sparse_design_matrices` as one dense array of shape (3, n, spans + 3)."""
    return np.array([m.toarray() for m in sparse_design_matrices(spans, s)])


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
        from scipy.sparse import block_diag, csr_array, vstack

        b = self.boundary(gait, kin)
        t = gait.phase_times_s("swing") if t_s is None else np.asarray(t_s, dtype=float)
        k = self.spans
        phi = [
            m * b.duration_s**-d  # d/dt = (1/T_sw) d/ds
            for d, m in enumerate(sparse_design_matrices(k, t / b.duration_s))
        ]
        free = np.arange(2, k + 1)
        fixed = np.array([0, 1, k + 1, k + 2])
        scale = PARAMETER_SCALE["joint"]
        base = np.zeros((3, 2, t.size))
        step = b.duration_s / (3 * k)
        ends = [
            np.array(
                [
                    b.start[c],
                    b.start[c] + step * b.start_rate[c],
                    b.end[c] - step * b.end_rate[c],
                    b.end[c],
                ]
            )
            for c in range(2)
        ]
        for d in range(3):
            for c in range(2):
                base[d, c] = phi[d][:, fixed] @ ends[c]
        # rows (d, c, sample) in C order; the two joints' parameters in two column blocks
        blocks = [block_diag([scale * phi[d][:, free]] * 2, format="csr") for d in range(3)]
        return AffinePath(self.space, t, base, csr_array(vstack(blocks, format="csr")))
