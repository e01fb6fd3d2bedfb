"""The periodic C2 cubic spline of the 3-D model: its rows, its fit and its order of accuracy."""

import numpy as np
import pytest

from scalf_opt.locomotion import periodic_spline as spline

PERIOD_S = 0.8
DRIFT = 0.3  # what one period adds to the second coordinate


def signal(t):
    w = 2 * np.pi / PERIOD_S
    values = np.vstack([np.sin(w * t), DRIFT * t / PERIOD_S + np.cos(2 * w * t)])
    rates = np.vstack([w * np.cos(w * t), DRIFT / PERIOD_S - 2 * w * np.sin(2 * w * t)])
    return values, rates


def fitted(n):
    step = PERIOD_S / n
    nodes = np.arange(n) * step
    shift = np.array([[0.0], [DRIFT]])
    values, _ = signal(nodes)
    rates, second = spline.fit(values, step, shift)
    return values, rates, second, step, shift


def test_the_fit_satisfies_the_nlps_continuity_rows():
    values, rates, second, step, shift = fitted(24)
    a, b = spline.continuity_rows(values, rates, second, step, shift)
    assert np.abs(a).max() < 1e-14 and np.abs(b).max() < 1e-12


@pytest.mark.parametrize("fraction", [0.25, 0.5, 0.75])
def test_between_nodes_the_spline_is_its_cubic_and_inner_points_agree(fraction):
    values, rates, second, step, shift = fitted(24)
    at_nodes = spline.evaluate(values, rates, second, step, np.arange(24) * step)
    np.testing.assert_allclose(at_nodes[0], values, atol=1e-15)
    inner = spline.inner_points(values, rates, second, step, shift, fraction)
    read = spline.evaluate(values, rates, second, step, (np.arange(24) + fraction) * step)
    for m, r in zip(inner, read, strict=True):
        np.testing.assert_allclose(m, r, rtol=0, atol=1e-11 * max(1, np.abs(r).max()))


@pytest.mark.parametrize("per_interval", [2, 4, 8, 16])
def test_the_read_points_are_composite_simpson_s_rule(per_interval):
    """On one interval (a node's weight shared by the two intervals it ends) the rule is exact
    for a cubic; summed over the periodic grid the weights add up to the period; four points
    are the nodes, quarter points and midpoints with weights 1/6, 1/3, 1/6, 1/3 (the default)."""
    read = spline.read_points(per_interval)
    assert [f for f, _ in read] == pytest.approx(np.arange(per_interval) / per_interval, abs=0)
    assert sum(w for _, w in read) == pytest.approx(1.0, abs=1e-15)
    h = 0.1
    node_weight = dict(read)[0.0]
    points = [(0.0, node_weight / 2), *read[1:], (1.0, node_weight / 2)]
    for cubic, exact in (
        (lambda t: (t - 0.03) ** 3, ((h - 0.03) ** 4 - 0.03**4) / 4),
        (lambda t: 2.0 + t - t**2, 2 * h + h**2 / 2 - h**3 / 3),
    ):
        rule = sum(w * h * cubic(f * h) for f, w in points)
        assert rule == pytest.approx(exact, rel=1e-13)
    assert spline.READ_POINTS == ((0.0, 1 / 6), (0.25, 1 / 3), (0.5, 1 / 6), (0.75, 1 / 3))


def test_a_denser_reading_integrates_a_kink_closer():
    """What the denser reading is for: ``|sin|`` (three periods in the cycle, its mean ``2 / pi``)
    has kinks between the read points; eight points per interval come several times closer to
    its integral than four (Simpson's rule across a kink converges at second order)."""
    n = 12
    errors = []
    for per_interval in (4, 8):
        read = spline.read_points(per_interval)
        t = np.concatenate([(np.arange(n) + f) / n for f, _ in read])
        w = np.repeat([wt for _, wt in read], n) / n
        errors.append(abs(np.sum(w * np.abs(np.sin(6 * np.pi * t + 0.37))) - 2 / np.pi))
    assert errors[1] < errors[0] / 2.5


@pytest.mark.parametrize("per_interval", [0, 3, -2])
def test_an_odd_or_too_small_reading_is_refused(per_interval):
    with pytest.raises(ValueError, match="even count"):
        spline.read_points(per_interval)


def test_the_spline_converges_at_fourth_order_in_value_and_third_in_rate():
    fine = np.linspace(0, PERIOD_S, 997, endpoint=False)
    exact_values, exact_rates = signal(fine)
    errors = []
    for n in (32, 64):
        values, rates, second, step, _ = fitted(n)
        v, r, _ = spline.evaluate(values, rates, second, step, fine)
        errors.append((np.abs(v - exact_values).max(), np.abs(r - exact_rates).max()))
    assert errors[0][0] / errors[1][0] == pytest.approx(16, rel=0.15)
    assert errors[0][1] / errors[1][1] == pytest.approx(8, rel=0.3)
