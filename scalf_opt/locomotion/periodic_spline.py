r"""Periodic cubic splines on a uniform grid: the 3-D model's trajectories between their nodes.

A trajectory ``Y(t)`` (rows: coordinates) is known at the nodes ``t_k = k h`` of one period
``T = N h`` together with its first and second derivatives. Between two nodes the second
derivative is linear (constant jerk), so

.. math::

    Y_{k+1} = Y_k + h \dot Y_k + \tfrac{h^2}{6} (2 \ddot Y_k + \ddot Y_{k+1}), \qquad
    \dot Y_{k+1} = \dot Y_k + \tfrac{h}{2} (\ddot Y_k + \ddot Y_{k+1}),

which makes ``Y`` a C2 cubic spline; the NLP imposes exactly these rows (:func:`continuity_rows`)
and the re-evaluation reads the same polynomial between the nodes (:func:`evaluate`). The cycle is
periodic up to a drift: node ``N`` is node ``0`` plus ``shift`` (the stride, on the trunk's x).
"""

from __future__ import annotations

from typing import Any

import numpy as np


def continuity_rows(y: Any, yd: Any, ydd: Any, step_s: float, shift: Any) -> tuple[Any, Any]:
    """The two row blocks that are zero on a periodic C2 cubic spline (CasADi or numpy).

    Args:
        y: Values at the nodes (m, N).
        yd: Rates at the nodes (m, N).
        ydd: Second derivatives at the nodes (m, N).
        step_s: The node interval ``h`` [s].
        shift: What one period adds to ``y`` (m, 1): node ``N`` is ``y[:, 0] + shift``.
    """
    n = y.shape[1]
    order = [*range(1, n), 0]
    y_next = y[:, order] + _last_column(shift, n)
    yd_next, ydd_next = yd[:, order], ydd[:, order]
    h = step_s
    values = y_next - y - h * yd - (h**2 / 6) * (2 * ydd + ydd_next)
    rates = yd_next - yd - (h / 2) * (ydd + ydd_next)
    return values, rates


def _last_column(shift: Any, n: int) -> Any:
    """``shift`` in the last column of an (m, n) block, zeros elsewhere."""
    column = np.zeros((1, n))
    column[0, -1] = 1.0
    return shift * column if isinstance(shift, int | float) else shift @ column


def fit(y: np.ndarray, step_s: float, shift: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rates and second derivatives of the periodic C2 cubic spline through ``y`` (m, N).

    Solves ``M_{k-1} + 4 M_k + M_{k+1} = 6 (Y_{k+1} - 2 Y_k + Y_{k-1}) / h^2`` on the cycle.
    """
    n = y.shape[1]
    h = step_s
    y_next = np.roll(y, -1, axis=1)
    y_next[:, -1] += np.ravel(shift)
    y_prev = np.roll(y, 1, axis=1)
    y_prev[:, 0] -= np.ravel(shift)
    circulant = 4 * np.eye(n) + np.roll(np.eye(n), 1, axis=1) + np.roll(np.eye(n), -1, axis=1)
    ydd = np.linalg.solve(circulant, (6 / h**2) * (y_next - 2 * y + y_prev).T).T
    ydd_next = np.roll(ydd, -1, axis=1)
    yd = (y_next - y) / h - (h / 6) * (2 * ydd + ydd_next)
    return yd, ydd


def evaluate(
    y: np.ndarray,
    yd: np.ndarray,
    ydd: np.ndarray,
    step_s: float,
    t_s: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Values, rates and second derivatives of the spline at times ``t_s`` in ``[0, T)`` (m, n).

    The last interval's polynomial starts at node ``N - 1``: the drift is in its rates already.
    """
    n = y.shape[1]
    k = np.minimum((np.asarray(t_s) / step_s).astype(int), n - 1)
    tau = np.asarray(t_s) - k * step_s
    ydd_next = np.roll(ydd, -1, axis=1)[:, k]
    jerk = (ydd_next - ydd[:, k]) / step_s
    values = y[:, k] + yd[:, k] * tau + ydd[:, k] * tau**2 / 2 + jerk * tau**3 / 6
    rates = yd[:, k] + ydd[:, k] * tau + jerk * tau**2 / 2
    accelerations = ydd[:, k] + jerk * tau
    return values, rates, accelerations


def read_points(per_interval: int) -> tuple[tuple[float, float], ...]:
    """Where a quantity on the periodic grid is read, and its weight: composite Simpson's rule.

    Each interval ``[t_k, t_{k+1}]`` is cut into ``per_interval`` (even, at least 2) equal parts
    and Simpson's rule applied to each pair of them. Each returned pair is a fraction of the
    interval and the weight of the reading there in units of the interval ``h``, the node first
    (its weight counts both intervals it closes: ``2 / (3 m)``; the odd points ``4 / (3 m)``, the
    other inner even points ``2 / (3 m)``); the weights of one interval sum to 1.

    Raises:
        ValueError: ``per_interval`` is odd or below 2.
    """
    if per_interval < 2 or per_interval % 2:
        raise ValueError(f"per_interval = {per_interval}: Simpson's rule needs an even count >= 2")
    m = per_interval
    return tuple((i / m, (4.0 if i % 2 else 2.0) / (3 * m)) for i in range(m))


READS_PER_INTERVAL = 4
"""The read points per interval unless a finer reading is asked for: the nodes, quarter points
and midpoints (composite Simpson's rule on the half intervals)."""

READ_POINTS: tuple[tuple[float, float], ...] = read_points(READS_PER_INTERVAL)
"""The default read points (:func:`read_points` of :data:`READS_PER_INTERVAL`): nodes and
midpoints ``h / 6``, quarter points ``h / 3``."""


def interval_points(y: Any, fraction: float) -> Any:
    """A quantity linear between the nodes, ``fraction`` of the way through each interval (m, N).

    Column ``k`` is at ``t_k + fraction h``; periodic without drift (the contact forces; CasADi
    or numpy).
    """
    n = y.shape[1]
    return (1 - fraction) * y + fraction * y[:, [*range(1, n), 0]]


def interval_means(y: Any) -> Any:
    """Each node's values averaged with the next node's (m, N): :func:`interval_points` at 1/2."""
    return interval_points(y, 0.5)


def inner_points(
    y: Any, yd: Any, ydd: Any, step_s: float, shift: Any, fraction: float
) -> tuple[Any, Any, Any]:
    """Values, rates and second derivatives of the spline ``fraction`` through each interval.

    The cubic Hermite form on ``[t_k, t_{k+1}]`` at ``s = fraction`` (values and rates of both
    nodes; the second derivative linear, as the C2 spline's is), CasADi or numpy; column ``k`` is
    at ``t_k + s h``. At ``s = 1/2``: ``(Y_k + Y_{k+1}) / 2 + h (Yd_k - Yd_{k+1}) / 8`` and
    ``3 (Y_{k+1} - Y_k) / (2 h) - (Yd_k + Yd_{k+1}) / 4``.
    """
    n = y.shape[1]
    order = [*range(1, n), 0]
    y_next = y[:, order] + _last_column(shift, n)
    yd_next, ydd_next = yd[:, order], ydd[:, order]
    h, t = step_s, fraction
    values = (
        (2 * t**3 - 3 * t**2 + 1) * y
        + (t**3 - 2 * t**2 + t) * h * yd
        + (-2 * t**3 + 3 * t**2) * y_next
        + (t**3 - t**2) * h * yd_next
    )
    rates = (
        (6 * t**2 - 6 * t) * (y - y_next) / h
        + (3 * t**2 - 4 * t + 1) * yd
        + (3 * t**2 - 2 * t) * yd_next
    )
    return values, rates, (1 - t) * ydd + t * ydd_next


def midpoints(y: Any, yd: Any, ydd: Any, step_s: float, shift: Any) -> tuple[Any, Any, Any]:
    """The spline halfway through each interval: :func:`inner_points` at 1/2."""
    return inner_points(y, yd, ydd, step_s, shift, 0.5)
