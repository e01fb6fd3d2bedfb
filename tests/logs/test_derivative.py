"""The log's velocity filter: Savitzky-Golay on the sample times."""

import numpy as np
import pytest
from scipy.signal import savgol_filter

from scalf_opt.logs.derivative import half_window_samples, local_polynomial_derivative


@pytest.mark.parametrize(("half", "degree"), [(2, 2), (3, 3), (5, 3), (4, 4)])
def test_on_a_uniform_grid_it_is_scipys_savitzky_golay(half, degree):
    dt = 1 / 80
    t = 3.0 + np.arange(150) * dt
    y = np.sin(7 * t) + 0.3 * t**3 + np.random.default_rng(1).normal(0, 1e-3, t.size)
    ours = local_polynomial_derivative(t, y, half, degree)
    scipy = savgol_filter(y, 2 * half + 1, degree, deriv=1, delta=dt, mode="interp")
    np.testing.assert_allclose(ours, scipy, rtol=0, atol=1e-10)


def test_a_polynomial_of_the_fits_degree_is_differentiated_exactly_on_any_grid():
    """Time stamps rounded to the millisecond (80 Hz: 12 or 13 ms steps) cost no accuracy."""
    t = np.round(np.arange(100) / 80, 3)
    y = 2.0 - 0.5 * t + 0.7 * t**2 - 0.2 * t**3
    exact = -0.5 + 1.4 * t - 0.6 * t**2
    np.testing.assert_allclose(local_polynomial_derivative(t, y, 3, 3), exact, atol=1e-10)
    stacked = local_polynomial_derivative(t, np.vstack([y, 3 * y]), 3, 3)
    np.testing.assert_allclose(stacked, np.vstack([exact, 3 * exact]), atol=1e-9)


def test_the_window_is_a_time():
    assert half_window_samples(80.0, 0.0375, 3) == 3  # 7 samples at the robot's 80 Hz
    assert half_window_samples(2000.0, 0.0375, 3) == 75
    assert half_window_samples(20.0, 0.0375, 3) == 2  # never fewer than a fit needs


def test_too_few_samples_are_refused():
    with pytest.raises(ValueError, match="fewer than one window"):
        local_polynomial_derivative(np.arange(4.0), np.arange(4.0), 3, 3)
