"""Names from a URDF become identifiers (CasADi functions, files, the page, the terminal) safely."""

import json

from scalf_opt.cli import main
from scalf_opt.cli.console import terminal_safe
from scalf_opt.robots.files import shipped_file
from scalf_opt.types import casadi_name


def test_casadi_names_are_identifiers_whatever_the_parts():
    assert casadi_name("frame", "LH-foot") == "frame_LH_foot"
    assert casadi_name("RF-knée", "power") == "RF_kn_e_power"
    assert casadi_name("1st", "leg") == "f_1st_leg"
    assert casadi_name("jac") == "f_jac" and casadi_name("") == "f"


def test_a_robot_whose_names_hold_dashes_and_accents_is_evaluated(tmp_path, capsys):
    urdf = shipped_file("scalf.urdf").read_text(encoding="utf-8")
    urdf = urdf.replace("RF_knee", "RF-knée").replace("LH_foot", "LH-foot")
    (tmp_path / "robot.urdf").write_text(urdf, encoding="utf-8")
    actuators = shipped_file("scalf_actuators.toml").read_text(encoding="utf-8")
    actuators = actuators.replace("[cylinders.RF_knee]", '[cylinders."RF-knée"]')
    (tmp_path / "robot_actuators.toml").write_text(actuators, encoding="utf-8")
    assert main(["evaluate", "--urdf", str(tmp_path / "robot.urdf"), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["total_energy_per_cycle_j"] > 0


def test_the_terminal_sees_escapes_not_control_characters():
    shown = terminal_safe("run\x1b]0;owned\x07 \x1b[2J\r\u202e\tdone\n")
    assert shown == "run\\x1b]0;owned\\x07 \\x1b[2J\\r\\u202e\tdone\n"
