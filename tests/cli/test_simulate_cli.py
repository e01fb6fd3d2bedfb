"""``scalf-opt simulate`` and ``scalf-opt analyze-log`` as a user runs them."""

import json

import pytest

from scalf_opt.cli import main
from scalf_opt.types import LEG_NAMES


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


SHARED_RUN = pytest.mark.xdist_group("cli_runs")
"""The tests that read the `simulated` run (tests/cli/conftest.py), test_cli_help.py's too."""


@SHARED_RUN
def test_simulate_writes_the_result_the_figure_and_a_log(simulated, capsys):
    simulated, _ = simulated
    data = json.loads((simulated / "simulation.json").read_text())
    for key in ("trunk_height_fluctuation_m", "trunk_pitch_peak_rad", "forward_speed_m_s"):
        assert isinstance(data[key], float)
    for key in ("foot_slip_m", "stance_force_peak_n", "stance_force_mean_n"):
        assert set(data[key]) == set(LEG_NAMES)
    for leg in LEG_NAMES:
        energy = data["joint_energy_per_cycle_j"][leg]
        # the referee ensemble's median, and its spread
        assert set(energy) == {
            "simulated",
            "model",
            "relative_difference",
            "relative_difference_spread",
        }
        assert energy["relative_difference"] == pytest.approx(
            energy["simulated"] / energy["model"] - 1, rel=1e-12
        )
    assert data["provenance"]["robot"] == "scalf"
    assert data["provenance"]["command"].startswith("scalf-opt simulate --cycles 3")
    assert data["cycles"] == 3 and data["cycles_averaged"] == 2
    # derived from SCalf's leg length: 30 Hz (settings.py), and said so
    assert data["settings"]["servo_bandwidth_hz"] == pytest.approx(30.0, rel=1e-3)
    assert "sqrt(g / L)" in data["settings_derivation"]["servo_bandwidth_hz"]
    assert data["model_repairs"] == []
    assert set(data["servo_work_per_cycle_j"]) == set(LEG_NAMES)
    assert data["trajectory"]["RF"]["swing_family"] == "reference"
    assert "reference" not in data  # the reference is not simulated twice
    png = (simulated / "simulation.png").read_bytes()
    assert png.startswith(b"\x89PNG")
    header = (simulated / "log.csv").read_text().splitlines()[0]
    assert header == "t_s,leg,hip_length_m,knee_length_m,hip_force_n,knee_force_n,contact"
    capsys.readouterr()


def test_simulate_prints_the_table(tmp_path, capsys):
    code, out, err = run(["simulate", "--cycles", "2", "--out", str(tmp_path)], capsys)
    assert code == 0 and err == ""
    assert "trunk height fluctuation" in out and "goal <= 4 mm: met" in out
    for leg in LEG_NAMES:
        assert f"\n{leg} " in out
    assert out.rstrip().endswith("report.txt")
    # a summary: the details (the plan followed exactly, the servo, contacts) are in the file
    assert "the plan followed exactly (MuJoCo" not in out and f"{tmp_path}/report.txt" in out
    report = (tmp_path / "report.txt").read_text()
    assert "the plan followed exactly (MuJoCo" in report and "trunk height fluctuation" in report
    assert len(out.splitlines()) <= 22


@SHARED_RUN
def test_analyze_log_reads_the_simulated_log(simulated, capsys):
    simulated, _ = simulated
    code, out, _ = run(["analyze-log", str(simulated / "log.csv")], capsys)
    assert code == 0
    assert "80.0 Hz" in out and "phases from the contact column" in out
    assert "average power of the robot (4 legs)" in out
    code, out, _ = run(["analyze-log", str(simulated / "log.csv"), "--json"], capsys)
    data = json.loads(out)
    assert data["provenance"]["robot"] == "scalf"
    assert set(data["mechanical_energy_per_cycle_j"]) == set(LEG_NAMES)
    assert data["average_power_w"] == pytest.approx(
        sum(data["mechanical_energy_per_cycle_j"].values()) / data["period_s"]
    )
    assert data["filter"]["samples"] == 7


def test_simulate_an_optimum_beside_the_reference(tmp_path, capsys):
    opt = tmp_path / "opt"
    assert main(["optimize", "--family", "paper", "--out", str(opt)]) == 0
    capsys.readouterr()
    code, out, _ = run(
        ["simulate", "--from", str(opt), "--cycles", "2", "--out", str(tmp_path)], capsys
    )
    assert code == 0
    assert "saving over the reference" in out
    data = json.loads((tmp_path / "simulation.json").read_text())
    assert data["trajectory"]["RF"]["swing_family"] == "paper"
    saving = data["saving_vs_reference"]
    assert saving["model_percent"] < 0 and saving["simulated_percent"] < 0
    assert data["reference"]["trajectory"]["LH"]["swing_family"] == "reference"
    assert data["loads"] == "whole-body"


def test_a_saved_optimum_is_simulated_and_exported_under_the_loads_it_was_planned_with(
    tmp_path, capsys
):
    """A trunk-only optimum keeps its loads: the model's side of the simulation, its energy and
    the exported plan are the saved ones, unless ``--loads`` says otherwise."""
    opt = tmp_path / "opt"
    argv = ["optimize", "--family", "paper", "--loads", "trunk", "--json", "--out", str(opt)]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    # the nominal referee alone: what is checked is the model's side, which the ensemble's
    # perturbed referees share (test_simulate_prints_the_table and tests/sim run the ensemble)
    sim = ["simulate", "--from", str(opt), "--cycles", "2", "--ensemble", "off"]
    assert main([*sim, "--out", str(tmp_path / "saved"), "-q"]) == 0
    data = json.loads((tmp_path / "saved" / "simulation.json").read_text())
    assert data["loads"] == "trunk"
    model = data["total_energy_per_cycle_j"]["model"]
    assert model == pytest.approx(summary["total_energy_per_cycle_j"], rel=1e-9)
    assert main([*sim, "--loads", "whole-body", "--out", str(tmp_path / "wb"), "-q"]) == 0
    data = json.loads((tmp_path / "wb" / "simulation.json").read_text())
    assert data["loads"] == "whole-body"
    assert data["total_energy_per_cycle_j"]["model"] > 1.05 * model  # the legs' loads added
    # the exported plan carries the saved loads: read back it is the saved plan, and the same
    # swings saved as whole-body export a plan that also carries the legs' loads
    whole = tmp_path / "whole"
    whole.mkdir()
    saved = json.loads((opt / "summary.json").read_text())
    (whole / "summary.json").write_text(json.dumps({**saved, "loads": "whole-body"}))
    planned = {}
    for folder in (opt, whole):
        plan = tmp_path / f"{folder.name}.csv"
        export = ["export", "--from", str(folder), "--rate", "1000", "--cycles", "4"]
        assert main([*export, "--out", str(plan), "-q"]) == 0
        assert main(["analyze-log", str(plan), "--plan", str(folder), "--json"]) == 0
        comparison = json.loads(capsys.readouterr().out)["plan_comparison"]
        assert abs(comparison["change_percent"]) < 0.01
        planned[folder.name] = comparison["planned_average_power_w"]
    assert planned["whole"] > 1.05 * planned["opt"]


def test_simulate_another_robot(tmp_path, capsys):
    code, out, _ = run(
        ["simulate", "--robot", "solo12", "--cycles", "2", "--out", str(tmp_path)], capsys
    )
    assert code == 0 and "simulation of solo12" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--cycles", "1"], "--cycles: cycles must be an integer in 2..200"),
        (["--from", "nowhere"], "nowhere/summary.json: not found"),
        (["--from", "nowhere", "--gait", "g.toml"], "with --from DIR the gait is DIR's"),
        (["--from", "nowhere", "--period", "0.6"], "with --from DIR the gait is DIR's"),
        (["--robot", "solo12", "--log", "x.csv"], "has no hydraulic cylinder"),
        (["--servo-bandwidth", "0"], "servo_bandwidth_hz = 0.0 must be > 0"),
    ],
)
def test_simulate_refuses_bad_input_and_writes_nothing(tmp_path, capsys, argv, message):
    out = tmp_path / "out"
    code, _, err = run(["simulate", "--out", str(out), *argv], capsys)
    assert code == 2
    assert err.startswith("scalf-opt: error: ") and err.count("\n") == 1
    assert message in err
    assert not out.exists()


def test_a_closed_pipe_ends_the_command_without_a_traceback():
    """``scalf-opt ... | head``: the reader goes away before the command prints."""
    import subprocess
    import sys

    process = subprocess.Popen(
        [sys.executable, "-m", "scalf_opt", "evaluate"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    process.stdout.close()  # before the command has computed anything
    _, err = process.communicate(timeout=120)
    assert b"Traceback" not in err and b"Error" not in err
    assert process.returncode == 0
