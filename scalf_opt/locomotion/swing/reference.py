r"""The paper's reference swing: clamped cubic splines in x and z (decision 12).

Each coordinate is a two-piece C2 cubic spline through lift-off ``y0``, the mid-swing apex ``y1``
at ``T_sw / 2`` and touch-down ``y2``, with end slopes ``m0``, ``m2`` equal to the stance
velocity. With knots ``h = T_sw / 2`` apart, continuity of the second derivative at the apex fixes
its slope (the tridiagonal system of a clamped spline with one unknown):

.. math::

    m_0 + 4 m_1 + m_2 = \frac{3 (y_2 - y_0)}{h},

and each piece is the cubic Hermite interpolant of its end values and slopes. (The tests check it
against SciPy's ``CubicSpline`` with the same clamped end conditions; SciPy is not imported here
because loading ``scipy.interpolate`` would double the command line's start-up time.)
"""

from __future__ import annotations

import numpy as np

from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.boundary import foot_boundary
from scalf_opt.locomotion.swing.family import AffinePath, SwingFamily
from scalf_opt.model.kinematics import LegKinematics


def hermite_piece(
    y0: float, y1: float, m0: float, m1: float, h: float, t: np.ndarray
) -> np.ndarray:
    """Value, first and second derivative (3, n) of the cubic Hermite piece on ``[0, h]``.

    Args:
        y0: Value at ``t = 0``.
        y1: Value at ``t = h``.
        m0: Slope at ``t = 0`` [per s].
        m1: Slope at ``t = h`` [per s].
        h: Length of the piece [s].
        t: Times in ``[0, h]`` [s].
    """
    s = np.asarray(t, dtype=float) / h
    # y(s) = y0 + m0 h s + c2 s^2 + c3 s^3 with y(1) = y1 and y'(1) = m1 h
    c2 = 3 * (y1 - y0) - (2 * m0 + m1) * h
    c3 = -2 * (y1 - y0) + (m0 + m1) * h
    value = y0 + s * (m0 * h + s * (c2 + s * c3))
    rate = (m0 * h + s * (2 * c2 + 3 * c3 * s)) / h
    accel = (2 * c2 + 6 * c3 * s) / h**2
    return np.array([value, rate, accel])


def clamped_spline(
    knots_y: tuple[float, float, float], end_slopes: tuple[float, float], h: float, t: np.ndarray
) -> np.ndarray:
    """Two-piece clamped C2 cubic spline through three equally spaced knots, shape (3, n).

    Args:
        knots_y: Values at ``0``, ``h`` and ``2 h``.
        end_slopes: Slopes at ``0`` and ``2 h`` [per s].
        h: Knot spacing [s].
        t: Times in ``[0, 2 h]`` [s].
    """
    y0, y1, y2 = knots_y
    m0, m2 = end_slopes
    m1 = (3 * (y2 - y0) / h - m0 - m2) / 4
    t = np.asarray(t, dtype=float)
    first = t <= h
    out = np.empty((3, t.size))
    out[:, first] = hermite_piece(y0, y1, m0, m1, h, t[first])
    out[:, ~first] = hermite_piece(y1, y2, m1, m2, h, t[~first] - h)
    return out


class ReferenceSpline(SwingFamily):
    """The paper's reference: clamped cubic splines in x and z (decision 12), no free parameter."""

    name = "reference"
    space = "foot"

    def path(  # noqa: D102
        self, gait: Gait, kin: LegKinematics, t_s: np.ndarray | None = None
    ) -> AffinePath:
        b = foot_boundary(gait, kin.leg.name)
        # decision 12: the apex H above the ground, midway between lift-off and touch-down
        apex = np.array([0.5 * (b.start[0] + b.end[0]), -gait.stance_height_m + gait.clearance_m])
        t = gait.phase_times_s("swing") if t_s is None else np.asarray(t_s, dtype=float)
        base = np.zeros((3, 2, t.size))
        for c in range(2):
            base[:, c] = clamped_spline(
                (b.start[c], apex[c], b.end[c]),
                (b.start_rate[c], b.end_rate[c]),
                0.5 * b.duration_s,
                t,
            )
        return AffinePath("foot", t, base, np.zeros((3, 2, t.size, 0)))
