"""The command line: outputs, file formats, one-line errors with exit code 2."""

import csv
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from scalf_opt.cli import main
from scalf_opt.energy.physics import trapezoid_weights

SCALF_COLUMNS = [
    "leg",
    "phase",
    "t_s",
    "q_hip_rad",
    "q_knee_rad",
    "qd_hip_rad_s",
    "qd_knee_rad_s",
    "qdd_hip_rad_s2",
    "qdd_knee_rad_s2",
    "foot_x_m",
    "foot_z_m",
    "grf_x_n",
    "grf_z_n",
    "tau_hip_nm",
    "tau_knee_nm",
    "cyl_len_hip_m",
    "cyl_len_knee_m",
    "cyl_vel_hip_m_s",
    "cyl_vel_knee_m_s",
    "cyl_force_hip_n",
    "cyl_force_knee_n",
    "friction_hip_n",
    "friction_knee_n",
    "power_hip_w",
    "power_knee_w",
]


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_model_prints_the_leg(capsys):
    code, out, _ = run(["model"], capsys)
    assert code == 0
    assert "thigh" in out and "0.45099" in out and "sweep 98.0 mm" in out
    assert "standing posture" in out


def test_model_of_other_robots(capsys):
    code, out, _ = run(["model", "--robot", "hyq", "--leg", "LH"], capsys)
    assert code == 0 and "lh_kfe_joint" in out and "ideal drive" in out


def test_evaluate_writes_summary_and_samples(tmp_path, capsys):
    code, out, _ = run(["evaluate", "--out", str(tmp_path)], capsys)
    assert code == 0
    assert "671.52 W" in out  # the paper's value is printed beside ours
    summary = json.loads((tmp_path / "summary.json").read_text())
    with (tmp_path / "samples.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0].keys()) == SCALF_COLUMNS
    assert len(rows) == 4 * (51 + 51)
    assert {r["leg"] for r in rows} == {"RF", "LF", "RH", "LH"}
    assert {r["phase"] for r in rows} == {"stance", "swing"}
    for leg in ("RF", "LH"):
        for phase in ("stance", "swing"):
            sel = [r for r in rows if r["leg"] == leg and r["phase"] == phase]
            t = np.array([float(r["t_s"]) for r in sel])
            power = np.array([[float(r["power_hip_w"]), float(r["power_knee_w"])] for r in sel])
            tau = t - t[0]
            energy = (power.T @ trapezoid_weights(tau)).sum()
            key = f"{phase}_energy_j"
            assert energy == pytest.approx(summary["legs"][leg][key], rel=1e-12)
    swing = [r for r in rows if r["phase"] == "swing"]
    assert all(float(r["grf_x_n"]) == 0.0 and float(r["grf_z_n"]) == 0.0 for r in swing)
    assert summary["average_total_power_w"] == pytest.approx(
        summary["total_energy_per_cycle_j"] / 0.5
    )


def test_ideal_drives_have_no_cylinder_columns(tmp_path, capsys):
    code, _, _ = run(["evaluate", "--robot", "hyq", "--out", str(tmp_path)], capsys)
    assert code == 0
    header = (tmp_path / "samples.csv").read_text().splitlines()[0].split(",")
    assert header == [c for c in SCALF_COLUMNS if not c.startswith(("cyl_", "friction_"))]
    assert "nan" not in (tmp_path / "samples.csv").read_text()


def test_bad_gait_file_is_one_line_and_keeps_previous_output(tmp_path, capsys):
    (tmp_path / "summary.json").write_text("previous")
    gait = tmp_path / "gait.toml"
    gait.write_text("[gait]\nduty_cycle = 1.5\n")
    code, _, err = run(["evaluate", "--gait", str(gait), "--out", str(tmp_path)], capsys)
    assert code == 2
    assert err.count("\n") == 1 and "duty_cycle" in err and "gait.toml" in err
    assert (tmp_path / "summary.json").read_text() == "previous"
    assert not (tmp_path / "samples.csv").exists()


def test_unreachable_gait_is_refused(tmp_path, capsys):
    gait = tmp_path / "tall.toml"
    gait.write_text("[gait]\nstance_height_m = 0.95\n")
    code, _, err = run(["evaluate", "--gait", str(gait)], capsys)
    assert code == 2 and "reach" in err and err.count("\n") == 1


def test_missing_urdf(tmp_path, capsys):
    code, _, err = run(["model", "--urdf", str(tmp_path / "none.urdf")], capsys)
    assert code == 2 and "none.urdf" in err and "Traceback" not in err


def test_console_script_has_no_traceback(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "scalf_opt.cli", "evaluate", "--gait", str(tmp_path / "x.toml")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 2
    assert proc.stderr.startswith("scalf-opt: error:") and "Traceback" not in proc.stderr


def test_optimize_writes_the_optimized_cycle(tmp_path, capsys):
    code, out, _ = run(
        ["optimize", "--family", "paper", "--method", "pattern", "--out", str(tmp_path)], capsys
    )
    assert code == 0 and "RF: paper by pattern: solved" in out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert set(summary["optimization"]) == {"RF", "LH"}
    assert summary["total_energy_per_cycle_j"] < summary["reference_total_energy_per_cycle_j"]
    with (tmp_path / "samples.csv").open() as handle:
        assert len(list(csv.DictReader(handle))) == 4 * (51 + 51)


def test_optimize_bad_arguments(capsys):
    code, _, err = run(["optimize", "--family", "reference"], capsys)
    assert code == 2 and "no free parameter" in err
    with pytest.raises(SystemExit) as info:
        run(["optimize", "--leg", "XX"], capsys)
    assert info.value.code == 2 and "--leg: invalid choice: 'XX'" in capsys.readouterr().err


def test_paper_writes_report_json_and_csv(tmp_path, capsys):
    code, out, _ = run(["paper", "--no-bound", "--out", str(tmp_path)], capsys)
    assert code == 0
    assert "Table 5" in out and "-33.76" in out and "671.52 -> 617.68" in out
    for name in ("report.md", "paper.json", "table5.csv", "table6.csv"):
        assert (tmp_path / name).stat().st_size > 0
    for name in ("pattern_search.png", "swing_paths.png"):
        assert (tmp_path / name).read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
        assert f"]({name})" in (tmp_path / "report.md").read_text()
    # outputs are as readable as any new file (mkstemp alone would make them owner-only)
    umask = os.umask(0)
    os.umask(umask)
    assert (tmp_path / "report.md").stat().st_mode & 0o777 == 0o666 & ~umask
    data = json.loads((tmp_path / "paper.json").read_text())
    assert data["all_solved"]
    for leg in ("RF", "LH"):
        assert abs(data["validation"][leg]["gap_at_fine_precision_pct"]) < 0.1
