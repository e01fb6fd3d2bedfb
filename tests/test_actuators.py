"""Hydraulic cylinders: stroke over the joint range, moment arm, Stribeck friction, file errors."""

import math

import numpy as np
import pytest

from scalf_opt.actuators import (
    cylinder_length,
    cylinder_length_rate,
    friction_force,
    friction_heat_rate,
    load_actuators,
    smooth_max,
    stroke_limits_m,
)
from scalf_opt.errors import ConfigError
from scalf_opt.robot import default_urdf_path

ACTUATORS = default_urdf_path().with_name("scalf_actuators.toml")
TABLE_4 = {
    "hip_pitch": {"F": (-2.032, 0.047), "H": (-0.047, 2.032)},
    "knee": {"F": (0.491, 2.570), "H": (-2.570, -0.491)},
}


@pytest.fixture(scope="module")
def cylinders():
    return load_actuators(ACTUATORS)


def test_all_eight_joints(cylinders):
    assert sorted(cylinders) == sorted(
        f"{leg}_{j}" for leg in ("RF", "LF", "RH", "LH") for j in ("hip_pitch", "knee")
    )


@pytest.mark.parametrize("leg", ["RF", "LF", "RH", "LH"])
@pytest.mark.parametrize("joint", ["hip_pitch", "knee"])
def test_stroke_over_table_4_range_is_98_mm(cylinders, leg, joint):
    # decision 7: with the law-of-cosines mapping each cylinder sweeps its 98 mm stroke
    cyl = cylinders[f"{leg}_{joint}"]
    lo, hi = TABLE_4[joint][leg[1]]
    lengths = np.array([float(cylinder_length(cyl, t)) for t in np.linspace(lo, hi, 2001)])
    assert abs((lengths.max() - lengths.min()) * 1e3 - 98.0) <= 2.0
    assert np.all(np.diff(lengths) > 0) or np.all(np.diff(lengths) < 0)  # monotonic
    l_min, l_max = stroke_limits_m(cyl, lo, hi)
    assert l_min == pytest.approx(lengths.min(), abs=1e-12)
    assert l_max == pytest.approx(l_min + 0.098, abs=1e-12)


def test_rf_hip_mapping_by_hand(cylinders):
    # phi = (90 - 5.36 - 54.90) deg - theta; a = 289.26 mm, b = 56.87 mm
    theta = -0.7
    phi = math.radians(90 - 5.36 - 54.90) - theta
    a, b = 0.28926, 0.05687
    expected = math.sqrt(a * a + b * b - 2 * a * b * math.cos(phi))
    assert float(cylinder_length(cylinders["RF_hip_pitch"], theta)) == pytest.approx(
        expected, rel=1e-12
    )


@pytest.mark.parametrize("joint", ["RF_hip_pitch", "RF_knee", "LH_hip_pitch", "LH_knee"])
def test_moment_arm_is_the_derivative_of_length(cylinders, joint):
    cyl = cylinders[joint]
    h = 1e-6  # central difference: truncation ~h^2 |l'''| ~ 1e-13, round-off ~eps l / h ~ 1e-10
    for theta in np.linspace(-1.5, 1.5, 13):
        fd = (float(cylinder_length(cyl, theta + h)) - float(cylinder_length(cyl, theta - h))) / (
            2 * h
        )
        assert float(cylinder_length_rate(cyl, theta)) == pytest.approx(fd, abs=1e-9)


def test_friction_heat_equals_abs_force_times_velocity(cylinders):
    fr = cylinders["RF_knee"].friction
    for v in np.concatenate([-np.logspace(-5, 0, 40), [0.0], np.logspace(-5, 0, 40)]):
        heat = float(friction_heat_rate(fr, v))
        assert heat >= 0.0
        assert heat == pytest.approx(abs(float(friction_force(fr, v)) * v), rel=1e-12, abs=1e-15)


def test_friction_force_branches(cylinders):
    fr = cylinders["RF_knee"].friction
    assert float(friction_force(fr, 1e-9)) == pytest.approx(50.0, abs=1e-5)  # -> F_s from above
    assert float(friction_force(fr, -1e-9)) == pytest.approx(-50.0, abs=1e-5)
    assert float(friction_force(fr, 0.0)) == 0.0
    # far from zero: Coulomb + viscous of each branch
    assert float(friction_force(fr, 1.0)) == pytest.approx(30 + 20 * math.exp(-1 / 0.015) + 220)
    assert float(friction_force(fr, -1.0)) == pytest.approx(-20 - 30 * math.exp(-1 / 0.007) - 180)


def test_smooth_max_converges(cylinders):
    xs = np.linspace(-0.1, 0.1, 201)
    for eps in (1e-2, 1e-4, 1e-6):
        err = max(abs(float(smooth_max(x, eps)) - max(x, 0.0)) for x in xs)
        assert err <= eps / 2 + 1e-15


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


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("a_mm = 289.26", "", "missing key cylinders.RF_knee.a_mm"),
        ("a_mm = 289.26", "a_mm = -3", "cylinders.RF_knee.a_mm must be a positive number"),
        ("angle_sign = 1", "angle_sign = 2", "angle_sign must be \\+1 or -1"),
        (
            "static_n = 50.0\ncoulomb_n = 30.0",
            "static_n = 'x'\ncoulomb_n = 30.0",
            "friction.extend.static_n",
        ),
        (
            "stroke_mm = 98.0",
            "stroke_mm = 98.0\ncolour = 1",
            "unknown key cylinders.RF_knee.colour",
        ),
        ("[friction.extend]", "[friction.extend", "not valid TOML"),
    ],
)
def test_bad_actuator_files_name_file_and_key(tmp_path, old, new, match):
    path = tmp_path / "act.toml"
    path.write_text(GOOD.replace(old, new, 1))
    with pytest.raises(ConfigError, match=match) as info:
        load_actuators(path)
    assert "act.toml" in str(info.value)


def test_missing_actuator_file(tmp_path):
    with pytest.raises(ConfigError, match=r"none\.toml"):
        load_actuators(tmp_path / "none.toml")
