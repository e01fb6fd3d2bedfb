"""The time derivative of a sampled signal: a local least-squares polynomial (Savitzky-Golay).

At each sample ``t_i`` a polynomial of degree ``p`` is fitted by least squares to the ``2h + 1``
samples around it (the window is shifted inward at both ends of the record, never padded), and
its slope at ``t_i`` is the derivative. On a uniform grid this is exactly the Savitzky-Golay
differentiator (:func:`scipy.signal.savgol_filter` with ``deriv=1, mode="interp"``; the tests
check it to round-off); the fit is written on the actual sample times, so a log whose time stamps
jitter or are rounded (to the millisecond, say) is differentiated correctly too, which SciPy's
filter, built for a uniform step, does not do.

Why this filter and window (a cubic over 75 ms; at the robot's 80 Hz the 7-point cubic
Savitzky-Golay differentiator, weights ``(22, -67, -58, 0, 58, 67, -22) / (252 dt)``):

* noise: 0.1 mm of position noise becomes ``0.1 mm * 0.512 / 12.5 ms = 4.1 mm/s`` of velocity
  noise (a central difference: 5.7 mm/s), against cylinder speeds of 50 to 300 mm/s;
* bandwidth: it differentiates a sinusoid of 4 Hz within 0.2 %, 6 Hz within 1 %, 10 Hz within
  7 % (a 5-point quadratic, the other common choice: 5 %, 12 %, 31 %). A 0.5 s trot's motion sits
  in its first harmonics (2, 4, 6 Hz); on SCalf's logs the quadratic lost 7 to 16 % of the
  mechanical energy, the cubic 1 to 5 % (``studies/simulation_validation.py`` measures it);
* the window is a time, so a faster log is smoothed over the same 75 ms with more samples (less
  noise) rather than differentiated over a shorter, noisier span.
"""

from __future__ import annotations

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

DEFAULT_HALF_WINDOW_S = 0.0375
"""Half-width of the fitted window in time [s]: 75 ms, 7 samples at the robot's 80 Hz."""

DEFAULT_DEGREE = 3
"""Degree of the fitted polynomial."""


def half_window_samples(sample_rate_hz: float, half_window_s: float, degree: int) -> int:
    """Samples on each side of the fit for a window of ``2 half_window_s`` [s].

    At least enough for the degree (``2 h + 1 >= degree + 2``: one sample more than the
    polynomial has coefficients, so that it is a fit and smooths).
    """
    return max(round(half_window_s * sample_rate_hz), (degree + 2) // 2)


def window_starts(n: int, half_window: int) -> np.ndarray:
    """First sample of each sample's window, shape (n,): centred, shifted inward at the ends."""
    width = 2 * half_window + 1
    return np.clip(np.arange(n) - half_window, 0, n - width)


def local_polynomial_derivative(
    t_s: np.ndarray,
    y: np.ndarray,
    half_window: int = 3,
    degree: int = DEFAULT_DEGREE,
) -> np.ndarray:
    """Derivative of ``y`` with respect to ``t_s`` by a local polynomial fit (module docstring).

    Args:
        t_s: Strictly increasing sample times, shape (n,) [s].
        y: Samples, shape (n,) or (m, n) (samples along the last axis).
        half_window: Samples on each side of the fitted window (``2 h + 1 >= degree + 1``).
        degree: Degree of the polynomial (>= 1).

    Returns:
        ``dy/dt`` at every sample, the shape of ``y`` [unit of y per s].

    Raises:
        ValueError: Fewer samples than one window, or a window too small for the degree.
    """
    t = np.asarray(t_s, dtype=float)
    values = np.asarray(y, dtype=float)
    width = 2 * half_window + 1
    if degree < 1 or width < degree + 1:
        raise ValueError(f"a window of {width} samples cannot fit a degree-{degree} polynomial")
    if t.size < width:
        raise ValueError(f"{t.size} samples are fewer than one window ({width})")
    start = window_starts(t.size, half_window)
    index = start[:, None] + np.arange(width)[None, :]  # (n, width)
    dt = t[index] - t[:, None]
    scale = np.abs(dt).max(axis=1, keepdims=True)  # conditions the Vandermonde matrix
    vander = (dt / scale)[..., None] ** np.arange(degree + 1)  # (n, width, degree + 1)
    slope_row = np.linalg.pinv(vander)[:, 1, :] / scale  # (n, width): weights of dy/dt
    if values.ndim == 1:
        return np.einsum("nw,nw->n", slope_row, values[index])
    windows = sliding_window_view(values, width, axis=-1)  # (m, n - width + 1, width)
    return np.einsum("nw,mnw->mn", slope_row, windows[:, start, :])
