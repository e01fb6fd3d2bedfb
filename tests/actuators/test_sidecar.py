"""The actuator file: drive per joint (cylinder, valve-controlled supply, electric, ideal), its
errors, and the sources every shipped number carries."""

import pytest

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.actuators.drive import Drive, IdealDrive
from scalf_opt.actuators.electric import ElectricDrive
from scalf_opt.actuators.sidecar import drives_for, leg_drives, read_sidecar, robot_sidecar_path
from scalf_opt.actuators.valve_cylinder import ValveControlledCylinder
from scalf_opt.errors import ConfigError
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.robots.files import robot_files_dir
from scalf_opt.robots.loading import load_robot

CYLINDER = """
[cylinders.A]
a_mm = 300.0
b_mm = 46.0
phi_offset_deg = 80.0
angle_sign = 1
stroke_mm = 80.0
"""
FRICTION = """
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
"""
SUPPLY = """
[supplies.pump]
joints = ["A"]
pressure_bar = 160.0
bore_mm = 16.0
rod_mm = 10.0
"""
ELECTRIC = """
[electric.motor]
joints = ["B", "C"]
gear_ratio = 9.0
torque_constant_nm_per_a = 0.025
winding_resistance_ohm = 0.3
"""


def read(tmp_path, text):
    path = tmp_path / "x_actuators.toml"
    path.write_text(text)
    return read_sidecar(path)


def test_one_file_mixes_every_drive(tmp_path):
    sidecar = read(tmp_path, CYLINDER + SUPPLY + ELECTRIC)
    assert isinstance(sidecar.drives["A"], ValveControlledCylinder)
    assert isinstance(sidecar.drives["B"], ElectricDrive)
    assert sidecar.drives["C"].regenerative is False  # type: ignore[attr-defined]
    assert sidecar.drives["A"].friction.force_n(0.3) == 0.0  # type: ignore[attr-defined]
    assert sidecar.sources == {}  # a file without [sources] still reads
    hip, knee = leg_drives(sidecar.drives, ("B", "Z"))
    assert isinstance(hip, ElectricDrive) and type(knee) is IdealDrive


def test_a_cylinder_without_supply_is_the_papers_and_needs_friction(tmp_path):
    drives = read(tmp_path, FRICTION + CYLINDER).drives
    assert type(drives["A"]) is HydraulicCylinder
    with pytest.raises(ConfigError, match=r"missing table \[friction\] \(cylinder A"):
        read(tmp_path, CYLINDER)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (
            CYLINDER + SUPPLY.replace('["A"]', '["Q"]'),
            r"supplies.pump.joints names Q, which has no",
        ),
        (CYLINDER + SUPPLY + SUPPLY.replace("pump", "other"), "already fed by another supply"),
        (CYLINDER + SUPPLY.replace("rod_mm = 10.0", "rod_mm = 16.0"), "rod_mm must be below"),
        (CYLINDER + SUPPLY + ELECTRIC.replace('"B"', '"A"'), "A has a cylinder and an electric"),
        (ELECTRIC + ELECTRIC.replace("motor", "m2"), "B, already driven by another motor"),
        (ELECTRIC.replace("gear_ratio = 9.0", "gear_ratio = 0"), "electric.motor.gear_ratio must"),
        (ELECTRIC.replace("winding_resistance_ohm = 0.3", ""), "missing key electric.motor.wind"),
        (ELECTRIC + "regenerative = 1\n", "regenerative must be true or false"),
        (ELECTRIC + "kv = 3\n", "unknown key electric.motor.kv"),
        (ELECTRIC.replace('["B", "C"]', "[]"), "joints must be a non-empty list"),
        (ELECTRIC + "[sources]\n", "electric.motor.gear_ratio has no entry in"),
        (ELECTRIC + '[sources]\n"electric" = "x"\n"electric.motr" = "y"\n', "'electric.motr'"),
        ("[sources]\n", "the file names no drive"),
    ],
)
def test_errors_name_the_file_and_the_key(tmp_path, text, match):
    with pytest.raises(ConfigError, match=match) as info:
        read(tmp_path, text)
    assert "x_actuators.toml" in str(info.value) and "\n" not in str(info.value)


def test_sources_cover_by_table_and_by_pattern_the_most_specific_wins(tmp_path):
    sources = read(
        tmp_path,
        ELECTRIC
        + '[sources]\n"electric" = "datasheet"\n'
        + '"electric.*.winding_resistance_ohm" = "estimate: guessed"\n',
    )
    assert sources.sources == {
        "electric.motor.gear_ratio": "datasheet",
        "electric.motor.torque_constant_nm_per_a": "datasheet",
        "electric.motor.winding_resistance_ohm": "estimate: guessed",
    }
    assert sources.estimates() == ["electric.motor.winding_resistance_ohm"]


@pytest.mark.parametrize("name", list(CATALOG))
def test_every_robot_drives_its_legs_and_cites_every_number(name):
    robot = load_robot(name)
    path = robot_sidecar_path(robot)
    assert path is not None and path.parent == robot_files_dir()
    sidecar = read_sidecar(path)
    assert sidecar.sources, f"{path} has no [sources]"  # every parameter covered: read checks it
    drives: dict[str, Drive] = drives_for(robot)
    for leg in ("RF", "LH", "LF", "RH"):
        for joint in robot.leg(leg).joint_names:
            assert joint in drives and not isinstance(drives[joint], IdealDrive)
    kinds = {type(d) for d in drives.values()}
    expected = {
        "scalf": HydraulicCylinder,
        "hyq": ValveControlledCylinder,
    }.get(name, ElectricDrive)
    assert kinds == {expected}
