"""The log's velocity filter: Savitzky-Golay on the sample times."""

import math

import numpy as np
import pytest
from scipy.signal import savgol_filter

from scalf_opt.logs.derivative import (
    BLOCK_SAMPLES,
    MAX_HALF_WINDOW_SAMPLES,
    half_window_samples,
    local_polynomial_derivative,
)


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


def test_the_window_is_a_time_up_to_a_bound_in_samples():
    assert half_window_samples(80.0, 0.0375, 3) == 3  # 7 samples at the robot's 80 Hz
    assert half_window_samples(320.0, 0.0375, 3) == 12
    assert half_window_samples(2000.0, 0.0375, 3) == MAX_HALF_WINDOW_SAMPLES == 12
    assert half_window_samples(1e6, 0.0375, 3) == 12  # a 1 MHz log: 25 samples, not 75,001
    assert half_window_samples(math.inf, 0.0375, 3) == 12
    assert half_window_samples(20.0, 0.0375, 3) == 2  # never fewer than a fit needs


def test_blocks_give_the_same_derivative_as_one_fit():
    """More samples than a block: the blocks' seams change nothing."""
    rng = np.random.default_rng(2)
    t = np.cumsum(rng.uniform(0.01, 0.015, BLOCK_SAMPLES + 500))
    y = np.vstack([np.sin(3 * t), np.cos(2 * t)])
    whole = local_polynomial_derivative(t, y, 3, 3)
    np.testing.assert_allclose(whole[0], 3 * np.cos(3 * t), atol=1e-3)
    around = slice(BLOCK_SAMPLES - 13, BLOCK_SAMPLES + 13)  # the seam and 3 samples each side
    alone = local_polynomial_derivative(t[around], y[:, around], 3, 3)
    np.testing.assert_allclose(alone[:, 3:-3], whole[:, around][:, 3:-3], rtol=0, atol=1e-12)


def test_too_few_samples_are_refused():
    with pytest.raises(ValueError, match="fewer than one window"):
        local_polynomial_derivative(np.arange(4.0), np.arange(4.0), 3, 3)
