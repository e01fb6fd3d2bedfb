"""The valve-controlled cylinder: pressure x flow by hand, negative work still costs flow, the
supply never delivers less than the mechanical power inside its force range, bounds, smoothing,
and HyQ's actuator file against its URDF."""

import math

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scalf_opt.actuators.cylinder import FRICTIONLESS, HydraulicCylinder
from scalf_opt.actuators.sidecar import drives_for
from scalf_opt.actuators.stribeck import smooth_max
from scalf_opt.actuators.valve_cylinder import ValveControlledCylinder
from scalf_opt.errors import ModelError

GEOMETRY = HydraulicCylinder("j", 0.3, 0.046, math.radians(80.0), 1, 0.08, FRICTIONLESS)
PRESSURE_PA = 160e5
CYL = ValveControlledCylinder.from_diameters(GEOMETRY, PRESSURE_PA, 0.016, 0.010)
PISTON = math.pi * 0.008**2
ANNULUS = PISTON - math.pi * 0.005**2


def test_areas_and_a_case_by_hand():
    assert CYL.piston_area_m2 == pytest.approx(2.0106192982974676e-4, rel=1e-14)
    assert CYL.annulus_area_m2 == pytest.approx(1.2252211349000193e-4, rel=1e-14)
    for theta, qd in ((0.3, 2.0), (0.3, -2.0), (-0.5, 1.0)):
        v = float(CYL.velocity_m_s(theta, qd))
        flow = PISTON * v if v > 0 else ANNULUS * -v
        assert float(CYL.outputs(theta, qd, 10.0)["flow"]) == pytest.approx(flow, rel=1e-14)
        assert float(CYL.loss_rate(theta, qd, 10.0)) == pytest.approx(PRESSURE_PA * flow, rel=1e-14)
    assert not CYL.charges_joint_power  # pressure x flow is all the joint draws


def test_negative_work_and_no_load_still_cost_flow():
    theta, qd = 0.3, 2.0
    tau = -30.0 * np.sign(float(CYL.moment_arm_m(theta)) * qd)  # the load drives the cylinder
    assert tau * qd < 0
    assert float(CYL.loss_rate(theta, qd, tau)) == pytest.approx(
        float(CYL.loss_rate(theta, qd, -tau)), rel=1e-15
    )
    assert float(CYL.loss_rate(theta, qd, 0.0)) > 0.0


@settings(max_examples=100, deadline=None)
@given(theta=st.floats(-0.87, 1.22), qd=st.floats(-10, 10), share=st.floats(-1, 1))
def test_the_supply_never_delivers_less_than_the_mechanical_power(theta, qd, share):
    # any force the supply can hold (share of its range): p_s Q >= F v = tau qd (the throttle
    # only dissipates)
    lo, hi = CYL.force_limits_n()
    force = share * (hi if share > 0 else -lo)
    tau = force * float(CYL.moment_arm_m(theta))
    supply = float(CYL.loss_rate(theta, qd, tau))
    assert supply >= tau * qd - 1e-9 * (1 + abs(tau * qd))
    assert supply >= 0.0


def test_bounds_are_the_stroke_and_the_supplys_force_range():
    lo, hi = -0.873, 1.222
    bounds = CYL.output_bounds(lo, hi)
    assert bounds["cyl_len"] == GEOMETRY.output_bounds(lo, hi)["cyl_len"]
    assert bounds["cyl_force"] == pytest.approx((-PRESSURE_PA * ANNULUS, PRESSURE_PA * PISTON))


def test_a_rod_as_wide_as_the_bore_is_refused():
    with pytest.raises(ModelError, match="annulus"):
        ValveControlledCylinder.from_diameters(GEOMETRY, PRESSURE_PA, 0.016, 0.016)


def test_smooth_loss_gradient_and_gap():
    theta, qd = ca.SX.sym("theta"), ca.SX.sym("qd")
    loss = CYL.loss_rate(theta, qd, 0.0, lambda x, _: smooth_max(x, 1e-4))
    fn = ca.Function("f", [theta, qd], [loss, ca.gradient(loss, ca.vertcat(theta, qd))])
    h = 1e-6
    for t0, q0 in ((0.2, 1.5), (-0.4, -2.0), (0.5, 0.01)):
        _, grad = fn(t0, q0)
        fd = [
            (float(fn(t0 + h, q0)[0]) - float(fn(t0 - h, q0)[0])) / (2 * h),
            (float(fn(t0, q0 + h)[0]) - float(fn(t0, q0 - h)[0])) / (2 * h),
        ]
        # truncation h^2 |f'''| and round-off eps |f| / h ~ 1e-7 W: 1e-6 relative
        np.testing.assert_allclose(np.array(grad).ravel(), fd, rtol=1e-6, atol=1e-5)
        exact = float(CYL.loss_rate(t0, q0, 0.0))
        # each smooth max is at most eps / 2 (in units of 10 m/s) above: p_s (A_p + A_a) 0.5 mm/s
        bound = PRESSURE_PA * (PISTON + ANNULUS) * 0.5e-3
        assert 0.0 <= float(fn(t0, q0)[0]) - exact <= bound + 1e-9


def test_hyq_file_fits_hyq(hyq):
    drives = drives_for(hyq)
    for name in ("RF", "LH", "LF", "RH"):
        leg = hyq.leg(name)
        for i, joint in enumerate(leg.joint_names):
            cyl = drives[joint]
            assert isinstance(cyl, ValveControlledCylinder)
            lo, hi = leg.lower_limits_rad[i], leg.upper_limits_rad[i]
            grid = np.linspace(lo, hi, 2001)
            lengths = np.array([float(cyl.length_m(x)) for x in grid])
            l_min, l_max = cyl.stroke_limits_m(lo, hi)
            assert lengths.min() >= l_min - 1e-12 and lengths.max() <= l_max  # inside the stroke
            # the file's claim: the largest torque the supply can push, 148 N m, is close to the
            # URDF's 150 N m effort limit
            arm = max(abs(float(cyl.moment_arm_m(x))) for x in grid)
            assert arm * cyl.force_limits_n()[1] == pytest.approx(148.0, abs=1.0)
            assert arm * cyl.force_limits_n()[1] <= leg.effort_limits_nm[i]
