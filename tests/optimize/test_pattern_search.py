"""Hooke-Jeeves pattern search on functions with known minima."""

import itertools
import math

import numpy as np
import pytest

from scalf_opt.optimize.pattern_search import PatternSearchOptions, pattern_search


def quadratic(x):
    return float((x[0] - 3.2) ** 2 + 2 * (x[1] + 1.7) ** 2 + 0.5 * x[0] * x[1]), None


def test_finds_minimum_of_a_quadratic_to_the_precision():
    # exact minimiser of (x-3.2)^2 + 2(y+1.7)^2 + 0.5xy: gradient = 0
    a = np.array([[2.0, 0.5], [0.5, 4.0]])
    b = np.array([2 * 3.2, -4 * 1.7])
    x_star = np.linalg.solve(a, b)
    res = pattern_search(quadratic, np.zeros(2), PatternSearchOptions(precision=1e-6))
    assert res.converged
    np.testing.assert_allclose(res.x, x_star, atol=1e-5)
    assert res.evaluations > res.iterations > 0


def test_paper_settings_stop_at_precision_and_record_history():
    res = pattern_search(quadratic, np.zeros(2))
    assert res.converged
    f0 = quadratic(np.zeros(2))[0]
    assert res.value < f0
    values = [row[-1] for row in res.history]
    assert values[0] == f0
    assert all(b < a for a, b in itertools.pairwise(values))  # strictly improving


def test_rosenbrock_with_pattern_moves():
    def rosen(x):
        return float(100 * (x[1] - x[0] ** 2) ** 2 + (1 - x[0]) ** 2), None

    res = pattern_search(rosen, np.array([-1.2, 1.0]), PatternSearchOptions(precision=1e-7))
    np.testing.assert_allclose(res.x, [1.0, 1.0], atol=1e-3)


def test_infeasible_points_are_worse_and_counted():
    def constrained(x):
        if x[0] < 1.0:
            return math.inf, "x0 below 1"
        return float((x[0] - 0.0) ** 2 + x[1] ** 2), None

    res = pattern_search(constrained, np.array([3.0, 2.0]), PatternSearchOptions(precision=1e-4))
    assert res.x[0] >= 1.0
    assert res.value == pytest.approx(1.0, abs=1e-3)
    assert res.infeasible["x0 below 1"] > 0


def test_never_worse_than_start_even_when_all_neighbours_are_infeasible():
    def spike(x):
        if np.any(x != 0):
            return math.inf, "only the origin is feasible"
        return 5.0, None

    res = pattern_search(spike, np.zeros(2))
    assert res.value == 5.0
    np.testing.assert_array_equal(res.x, [0.0, 0.0])


def test_options_are_validated():
    with pytest.raises(ValueError, match="shrinkage"):
        PatternSearchOptions(shrinkage=1.5)
    with pytest.raises(ValueError, match="precision"):
        PatternSearchOptions(precision=0)
