"""Hydraulic cylinders: stroke over the joint range, moment arm, Stribeck friction, file errors.

The expected numbers are written here from the paper's Table 2, Table 4 and friction table.
"""

import math

import casadi as ca
import numpy as np
import pytest

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.actuators.sidecar import load_sidecar as load_actuators
from scalf_opt.actuators.sidecar import sidecar_path_for
from scalf_opt.actuators.stribeck import StribeckBranch, StribeckFriction, smooth_max
from scalf_opt.errors import ConfigError, ModelError
from scalf_opt.robots.files import shipped_file

ACTUATORS = shipped_file("scalf_actuators.toml")
LEGS = ("RF", "LF", "RH", "LH")
TABLE_4 = {
    "hip_pitch": {"F": (-2.032, 0.047), "H": (-0.047, 2.032)},
    "knee": {"F": (0.491, 2.570), "H": (-2.570, -0.491)},
}
EXTEND = StribeckBranch(220.0, 50.0, 30.0, 0.015)
RETRACT = StribeckBranch(180.0, 50.0, 20.0, 0.007)


@pytest.fixture(scope="module")
def cylinders():
    return load_actuators(ACTUATORS)


def test_the_sidecar_sits_beside_the_urdf():
    assert sidecar_path_for(shipped_file("scalf.urdf")) == ACTUATORS


def test_all_eight_joints(cylinders):
    assert sorted(cylinders) == sorted(f"{leg}_{j}" for leg in LEGS for j in ("hip_pitch", "knee"))


@pytest.mark.parametrize("leg", LEGS)
def test_table_2_values_and_friction(cylinders, leg):
    hip, knee = cylinders[f"{leg}_hip_pitch"], cylinders[f"{leg}_knee"]
    assert (hip.a_m, hip.b_m, hip.stroke_m) == pytest.approx((0.28926, 0.05687, 0.098), abs=1e-15)
    assert (knee.a_m, knee.b_m, knee.stroke_m) == pytest.approx(
        (0.28926, 0.05689, 0.098), abs=1e-15
    )
    assert hip.phi_offset_rad == pytest.approx(math.radians(90 - 5.36 - 54.90), abs=1e-12)
    assert knee.phi_offset_rad == pytest.approx(math.radians(-(8.02 - 2.35)), abs=1e-12)
    front = leg.endswith("F")
    assert (hip.angle_sign, knee.angle_sign) == ((-1, 1) if front else (1, -1))
    for cyl in (hip, knee):
        assert cyl.friction == StribeckFriction(EXTEND, RETRACT)
        assert cyl.joint_name.startswith(leg)


@pytest.mark.parametrize("joint", ["hip_pitch", "knee"])
def test_hind_legs_mirror_the_front(cylinders, joint):
    # decision 7: hind legs use the negated joint angle
    for front, hind in (("RF", "RH"), ("LF", "LH"), ("RF", "LF")):
        mirror = -1 if hind.endswith("H") else 1
        for theta in np.linspace(-2.5, 2.5, 11):
            assert float(cylinders[f"{hind}_{joint}"].length_m(mirror * theta)) == (
                pytest.approx(float(cylinders[f"{front}_{joint}"].length_m(theta)), 1e-15)
            )


@pytest.mark.parametrize("leg", LEGS)
@pytest.mark.parametrize("joint", ["hip_pitch", "knee"])
def test_stroke_over_table_4_range_is_98_mm(cylinders, leg, joint):
    # decision 7: with the law-of-cosines mapping each cylinder sweeps its 98 mm stroke
    cyl = cylinders[f"{leg}_{joint}"]
    lo, hi = TABLE_4[joint][leg[1]]
    lengths = np.array([float(cyl.length_m(t)) for t in np.linspace(lo, hi, 2001)])
    assert abs((lengths.max() - lengths.min()) * 1e3 - 98.0) <= 2.0
    assert np.all(np.diff(lengths) > 0) or np.all(np.diff(lengths) < 0)  # monotonic
    l_min, l_max = cyl.stroke_limits_m(lo, hi)
    assert l_min == pytest.approx(lengths.min(), abs=1e-12)
    assert l_max == pytest.approx(l_min + 0.098, abs=1e-12)
    assert lengths.max() <= l_max + 1e-4  # the whole range fits the stroke (to 0.1 mm)


def test_stroke_limits_refuse_a_non_monotonic_range(cylinders):
    # RF hip: phi = 29.74 deg - theta reaches 0 at theta = 0.519 rad
    with pytest.raises(ModelError, match="RF_hip_pitch"):
        cylinders["RF_hip_pitch"].stroke_limits_m(-1.0, 1.0)


def test_rf_mapping_by_hand(cylinders):
    for joint, a, b, phi_of in (
        ("RF_hip_pitch", 0.28926, 0.05687, lambda t: math.radians(90 - 5.36 - 54.90) - t),
        ("RF_knee", 0.28926, 0.05689, lambda t: t - math.radians(8.02 - 2.35)),
    ):
        for theta in (-0.7, 0.3, 1.2):
            phi = phi_of(theta)
            expected = math.sqrt(a * a + b * b - 2 * a * b * math.cos(phi))
            assert float(cylinders[joint].length_m(theta)) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("joint", ["RF_hip_pitch", "RF_knee", "LH_hip_pitch", "LH_knee"])
def test_moment_arm_is_the_derivative_of_length(cylinders, joint):
    cyl = cylinders[joint]
    # central difference with step h = 1e-6 rad: truncation ~h^2 |l'''| / 6 ~ 1e-14 m/rad,
    # round-off ~ eps * l / h ~ 2e-16 * 0.3 / 1e-6 ~ 1e-10 m/rad; tolerance 1e-9 m/rad
    h = 1e-6
    for theta in np.linspace(-1.5, 1.5, 13):
        fd = (float(cyl.length_m(theta + h)) - float(cyl.length_m(theta - h))) / (2 * h)
        assert float(cyl.moment_arm_m(theta)) == pytest.approx(fd, abs=1e-9)


def test_one_formula_for_floats_and_symbols(cylinders):
    cyl = cylinders["RF_knee"]
    for sym in (ca.SX.sym("x"), ca.MX.sym("x")):
        fun = ca.Function(
            "f",
            [sym],
            [
                cyl.length_m(sym),
                cyl.moment_arm_m(sym),
                cyl.friction.force_n(sym),
                cyl.friction.heat_rate_w(sym),
            ],
        )
        for x in (-0.3, 0.0, 0.02, 1.4):
            got = [float(v) for v in fun(x)]
            want = [
                float(cyl.length_m(x)),
                float(cyl.moment_arm_m(x)),
                float(cyl.friction.force_n(x)),
                float(cyl.friction.heat_rate_w(x)),
            ]
            assert got == pytest.approx(want, rel=1e-14, abs=1e-14)
    # the symbolic derivative agrees with the closed-form moment arm
    theta = ca.SX.sym("theta")
    dldt = ca.Function("d", [theta], [ca.jacobian(cyl.length_m(theta), theta)])
    assert float(dldt(1.0)) == pytest.approx(float(cyl.moment_arm_m(1.0)), rel=1e-14)


VELOCITIES = np.concatenate([-np.logspace(-5, 0, 40), [0.0], np.logspace(-5, 0, 40)])


def test_friction_heat_equals_abs_force_times_velocity(cylinders):
    fr = cylinders["RF_knee"].friction
    for v in VELOCITIES:
        heat = float(fr.heat_rate_w(v))
        assert heat >= 0.0
        assert heat == pytest.approx(abs(float(fr.force_n(v)) * v), rel=1e-12, abs=1e-15)


def test_friction_force_branches(cylinders):
    fr = cylinders["RF_knee"].friction
    # continuity limits: F_f(0+) -> +F_s, F_f(0-) -> -F_s (50 N both ways)
    for v in (1e-7, 1e-9, 1e-12):
        assert float(fr.force_n(v)) == pytest.approx(50.0, abs=1e-2 * v / 1e-7)
        assert float(fr.force_n(-v)) == pytest.approx(-50.0, abs=1e-2 * v / 1e-7)
    assert float(fr.force_n(0.0)) == 0.0
    # far from zero: Coulomb + viscous of each branch
    assert float(fr.force_n(1.0)) == pytest.approx(30 + 20 * math.exp(-1 / 0.015) + 220)
    assert float(fr.force_n(-1.0)) == pytest.approx(-20 - 30 * math.exp(-1 / 0.007) - 180)
    # at the Stribeck velocity of each branch
    assert float(fr.force_n(0.015)) == pytest.approx(30 + 20 / math.e + 220 * 0.015)
    assert float(fr.force_n(-0.007)) == pytest.approx(-20 - 30 / math.e - 180 * 0.007)


def test_smooth_max_converges():
    xs = np.linspace(-0.1, 0.1, 201)
    previous = math.inf
    for eps in (1e-2, 1e-4, 1e-6):
        gaps = [float(smooth_max(x, eps)) - max(x, 0.0) for x in xs]
        assert min(gaps) >= -1e-15  # never below max(x, 0)
        assert max(gaps) <= eps / 2 + 1e-15
        assert max(gaps) < previous
        previous = max(gaps)


def test_smooth_heat_approaches_the_exact_heat(cylinders):
    fr = cylinders["RF_hip_pitch"].friction
    for eps in (1e-3, 1e-5):
        smooth = [
            float(fr.heat_rate_w(v, lambda x, _, e=eps: smooth_max(x, e))) for v in VELOCITIES
        ]
        exact = [float(fr.heat_rate_w(v)) for v in VELOCITIES]
        # |h'| <= F_s + 2 B |v| ~ 500 W/(m/s) on this grid; each max moves by <= eps/2
        assert np.max(np.abs(np.subtract(smooth, exact))) <= 500 * eps


def test_cylinder_is_frozen(cylinders):
    cyl = cylinders["RF_knee"]
    assert isinstance(cyl, HydraulicCylinder)
    with pytest.raises(AttributeError):
        cyl.a_m = 1.0  # type: ignore[misc]


GOOD = """
[friction.extend]
viscous_n_s_per_m = 220.0
static_n = 50.0
coulomb_n = 30.0
stribeck_velocity_m_s = 0.015
[friction.retract]
viscous_n_s_per_m = 180.0
static_n = 50.0
coulomb_n = 20.0
stribeck_velocity_m_s = 0.007
[cylinders.RF_knee]
a_mm = 289.26
b_mm = 56.89
phi_offset_deg = -5.67
angle_sign = 1
stroke_mm = 98.0
"""


def test_good_file_loads(tmp_path):
    path = tmp_path / "act.toml"
    path.write_text(GOOD)
    (cyl,) = load_actuators(path).values()
    assert cyl.joint_name == "RF_knee"
    assert cyl.phi_offset_rad == pytest.approx(math.radians(-5.67))


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("a_mm = 289.26", "", "missing key cylinders.RF_knee.a_mm"),
        ("a_mm = 289.26", "a_mm = -3", "cylinders.RF_knee.a_mm must be a positive number, got -3"),
        ("stroke_mm = 98.0", "stroke_mm = 0", "cylinders.RF_knee.stroke_mm must be a positive"),
        ("b_mm = 56.89", "b_mm = 'x'", "cylinders.RF_knee.b_mm must be a positive number"),
        ("phi_offset_deg = -5.67", "phi_offset_deg = true", "cylinders.RF_knee.phi_offset_deg"),
        ("angle_sign = 1", "angle_sign = 2", r"cylinders.RF_knee.angle_sign must be \+1 or -1"),
        ("angle_sign = 1", "angle_sign = 1.0", r"cylinders.RF_knee.angle_sign must be \+1 or -1"),
        (
            "static_n = 50.0\ncoulomb_n = 30.0",
            "static_n = 'x'\ncoulomb_n = 30.0",
            "friction.extend.static_n must be a positive number",
        ),
        ("coulomb_n = 20.0\n", "", "missing key friction.retract.coulomb_n"),
        (
            "stroke_mm = 98.0",
            "stroke_mm = 98.0\ncolour = 1",
            "unknown key cylinders.RF_knee.colour",
        ),
        ("[friction.retract]", "[friction.retreat]", "unknown key friction.retreat"),
        ("[cylinders.RF_knee]", "[pumps.RF_knee]", "unknown key pumps"),
        ("[friction.extend]", "[friction.extend", "not valid TOML"),
    ],
)
def test_bad_actuator_files_name_file_and_key(tmp_path, old, new, match):
    path = tmp_path / "act.toml"
    assert old in GOOD
    path.write_text(GOOD.replace(old, new, 1))
    with pytest.raises(ConfigError, match=match) as info:
        load_actuators(path)
    message = str(info.value)
    assert "act.toml" in message
    assert "\n" not in message


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (GOOD.split("[cylinders.RF_knee]")[0], r"missing table \[cylinders\]"),
        (
            GOOD.split("[friction.retract]")[0] + "[cylinders.X]\n",
            r"missing table \[friction.retract",
        ),
        ("cylinders = 3\n" + GOOD.split("[cylinders.RF_knee]")[0], "cylinders must be a table"),
    ],
)
def test_bad_actuator_file_structure(tmp_path, text, match):
    path = tmp_path / "act.toml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=match) as info:
        load_actuators(path)
    assert "act.toml" in str(info.value)


def test_missing_actuator_file(tmp_path):
    with pytest.raises(ConfigError, match=r"none\.toml"):
        load_actuators(tmp_path / "none.toml")


def _joint_range(joint):
    leg, role = joint.split("_", 1)
    return TABLE_4[role][leg[1]]


def test_the_inverse_mapping_undoes_the_length_over_the_whole_range(cylinders):
    """Eq. 67: theta(l(theta)) = theta and l(theta(l)) = l, on every cylinder, to round-off."""
    for joint, cylinder in cylinders.items():
        lo, hi = _joint_range(joint)
        theta = np.linspace(lo, hi, 201)
        length = np.array(cylinder.length_m(theta)).ravel()
        back = np.array(cylinder.angle_from_length_rad(length)).ravel()
        np.testing.assert_allclose(back, theta, rtol=0, atol=1e-12)
        l_min, l_max = cylinder.stroke_limits_m(lo, hi)
        lengths = np.linspace(l_min, l_max - 1e-6, 101)
        again = np.array(cylinder.length_m(cylinder.angle_from_length_rad(lengths))).ravel()
        np.testing.assert_allclose(again, lengths, rtol=0, atol=1e-15)


def test_torque_from_force_is_the_virtual_work_of_the_cylinder(cylinders):
    """Eq. 68: tau = F dl/dtheta gives the same power as F v, v the rate of the length."""
    rng = np.random.default_rng(3)
    for joint, cylinder in cylinders.items():
        lo, hi = _joint_range(joint)
        theta = rng.uniform(lo, hi, 20)
        rate = rng.normal(0.0, 2.0, 20)
        force = rng.normal(0.0, 3000.0, 20)
        arm = np.array(cylinder.moment_arm_m(theta)).ravel()
        h = 1e-6
        length_rate = (
            np.array(cylinder.length_m(theta + h * rate)).ravel()
            - np.array(cylinder.length_m(theta - h * rate)).ravel()
        ) / (2 * h)
        np.testing.assert_allclose(force * arm * rate, force * length_rate, rtol=1e-7, atol=1e-6)
