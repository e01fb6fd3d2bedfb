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
  noise) rather than differentiated over a shorter, noisier span; up to
  :data:`MAX_HALF_WINDOW_SAMPLES` a side (320 Hz): a faster log is fitted over that many samples,
  a shorter time, so that the work and the memory stay linear in the log's length whatever its
  rate (a 1 MHz log would otherwise fit 75,000 samples around each one).

The fits are computed in blocks of :data:`BLOCK_SAMPLES` samples: the memory is bounded, the time
linear in the log's length.
"""

from __future__ import annotations

import numpy as np

DEFAULT_HALF_WINDOW_S = 0.0375
"""Half-width of the fitted window in time [s]: 75 ms, 7 samples at the robot's 80 Hz."""

DEFAULT_DEGREE = 3
"""Degree of the fitted polynomial."""

MAX_HALF_WINDOW_SAMPLES = 12
"""Most samples on each side of the fit (a 25-sample window)."""

BLOCK_SAMPLES = 8192
"""Samples whose fits are computed at once."""


def half_window_samples(sample_rate_hz: float, half_window_s: float, degree: int) -> int:
    """Samples on each side of the fit for a window of ``2 half_window_s`` [s].

    At least enough for the degree (``2 h + 1 >= degree + 2``: one sample more than the
    polynomial has coefficients, so that it is a fit and smooths), at most
    :data:`MAX_HALF_WINDOW_SAMPLES`.
    """
    wanted = half_window_s * sample_rate_hz
    wanted = (
        min(wanted, MAX_HALF_WINDOW_SAMPLES) if np.isfinite(wanted) else MAX_HALF_WINDOW_SAMPLES
    )
    return max(round(wanted), (degree + 2) // 2)


def window_starts(n: int, half_window: int) -> np.ndarray:
    """First sample of each sample's window, shape (n,): centred, shifted inward at the ends."""
    width = 2 * half_window + 1
    return np.clip(np.arange(n) - half_window, 0, n - width)


_PATTERN_RESOLUTION = 2.0**40
"""Windows whose steps, relative to the window's span, agree to 2^-40 (1e-12) share one fit."""


_MIXERS = np.random.default_rng(0).integers(1, 2**62, 2 * MAX_HALF_WINDOW_SAMPLES + 1) | 1
"""Odd multipliers that mix a window's quantised steps into one 64-bit fingerprint."""


def _slope_weights(unit: np.ndarray, degree: int) -> np.ndarray:
    """Weights of the fitted slope at 0 for windows at relative times ``unit`` (k, width).

    Least squares by QR (V = QR): the slope's weights are e1' R^-1 Q', i.e. Q x with R' x = e1
    (as accurate as the pseudo-inverse, four times faster).
    """
    vander = unit[..., None] ** np.arange(degree + 1)  # (k, width, degree + 1)
    q, r = np.linalg.qr(vander)
    e1 = np.zeros((q.shape[0], degree + 1, 1))
    e1[:, 1, 0] = 1.0
    x = np.linalg.solve(np.swapaxes(r, 1, 2), e1)[..., 0]
    return np.einsum("nwj,nj->nw", q, x)


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
    out = np.empty(values.shape, dtype=float)
    for first in range(0, t.size, BLOCK_SAMPLES):
        block = slice(first, min(first + BLOCK_SAMPLES, t.size))
        index = start[block, None] + np.arange(width)[None, :]  # (b, width)
        dt = t[index] - t[block, None]
        scale = np.abs(dt).max(axis=1, keepdims=True)  # conditions the Vandermonde matrix
        unit = dt / scale  # in [-1, 1]
        # a log's windows repeat a few patterns of steps (a steady rate): fit each pattern once
        key = np.round(unit * _PATTERN_RESOLUTION).astype(np.int64)
        with np.errstate(over="ignore"):
            fingerprint = (key * np.resize(_MIXERS, width)).sum(axis=1)  # wraps around: a hash
        _, first_of, which = np.unique(fingerprint, return_index=True, return_inverse=True)
        if width <= _MIXERS.size and (key[first_of][which] == key).all():  # no collision
            slope_row = _slope_weights(unit[first_of], degree)[which] / scale
        else:
            slope_row = _slope_weights(unit, degree) / scale
        if values.ndim == 1:
            out[block] = np.einsum("nw,nw->n", slope_row, values[index])
        else:
            out[:, block] = np.einsum("nw,mnw->mn", slope_row, values[:, index])
    return out
