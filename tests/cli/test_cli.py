"""The command line: outputs, file formats, one-line errors with exit code 2."""

import csv
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from scalf_opt.cli import main
from scalf_opt.energy.physics import trapezoid_weights
from scalf_opt.robots.files import shipped_file
from scalf_opt.robots.loading import load_robot

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
    assert code == 0 and "lh_kfe_joint" in out and "valve-controlled supply: 160 bar" in out
    code, out, _ = run(["model", "--robot", "go1"], capsys)
    assert code == 0 and "FR_calf_joint: electric drive: gear 9.495:1" in out


def test_evaluate_writes_summary_and_samples(tmp_path, capsys):
    code, out, _ = run(["evaluate", "--loads", "trunk", "--out", str(tmp_path)], capsys)
    assert code == 0
    assert "671.52 W" in out  # the paper's value is printed beside ours (the paper's loads)
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
    # SCalf's URDF without its actuator file beside it: every joint has an ideal drive
    urdf = tmp_path / "bare.urdf"
    urdf.write_text(shipped_file("scalf.urdf").read_text())
    code, _, _ = run(["evaluate", "--urdf", str(urdf), "--out", str(tmp_path)], capsys)
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


def test_optimize_records_the_optimum_its_checks_and_peaks(tmp_path, capsys):
    code, out, _ = run(["optimize", "--family", "joint-4", "--out", str(tmp_path)], capsys)
    assert code == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    record = summary["optimization"]["RF"]
    assert record["family"] == "joint-4" and record["success"]
    assert record["worse_than_reference"] is False
    assert abs(record["sampling_error"]) <= 0.005
    assert record["swing_energy_j"] == pytest.approx(summary["legs"]["RF"]["swing_energy_j"])
    assert summary["optimization_run"]["sample_rate_hz"] == summary["gait"]["sample_rate_hz"]
    assert summary["peaks"]["RF"]["tau_hip"]["limit"] == 800.0
    assert summary["peaks"]["LH"]["cyl_force_knee"]["exceeds"] is False
    assert summary["limit_violations"] == []
    assert "peaks over the cycle" in out and "limit knee" in out


def write_gait(path, **fields):
    path.write_text("[gait]\n" + "".join(f"{k} = {v!r}\n" for k, v in fields.items()))
    return path


def test_evaluate_swing_re_evaluates_a_saved_optimum(tmp_path, capsys):
    opt, ev = tmp_path / "opt", tmp_path / "ev"
    assert run(["optimize", "--family", "joint-6", "--out", str(opt)], capsys)[0] == 0
    saved = json.loads((opt / "summary.json").read_text())
    rate = saved["gait"]["sample_rate_hz"]
    gait = write_gait(tmp_path / "same.toml", sample_rate_hz=rate)
    code, out, _ = run(
        ["evaluate", "--swing", str(opt / "summary.json"), "--gait", str(gait), "--out", str(ev)],
        capsys,
    )
    assert code == 0 and "saved optimum (joint-6" in out
    again = json.loads((ev / "summary.json").read_text())
    for leg in ("RF", "LH", "LF", "RH"):
        assert again["legs"][leg]["swing_energy_j"] == pytest.approx(
            saved["legs"][leg]["swing_energy_j"], rel=1e-12
        )
    # by default at the optimum's own gait and rate; any rate and any accounting: the paper's
    # 200 Hz (with a note), positive work only
    code, out, _ = run(["evaluate", "--swing", str(opt), "--json"], capsys)
    assert code == 0 and json.loads(out)["gait"]["sample_rate_hz"] == rate
    code, out, _ = run(
        [
            "evaluate",
            "--swing",
            str(opt / "summary.json"),
            "--rate",
            "200",
            "--accounting",
            "positive",
        ],
        capsys,
    )
    assert code == 0 and f"found at {rate:g} Hz" in out


@pytest.mark.parametrize(
    ("field", "value"),
    [("period_s", 0.6), ("stance_height_m", 0.7), ("clearance_m", 0.1), ("duty_cycle", 0.6)],
)
def test_evaluate_swing_refuses_another_timing(tmp_path, capsys, field, value):
    opt = tmp_path / "opt"
    assert run(["optimize", "--family", "paper", "--leg", "RF", "--out", str(opt)], capsys)[0] == 0
    gait = write_gait(tmp_path / "other.toml", **{field: value})
    code, _, err = run(
        ["evaluate", "--swing", str(opt / "summary.json"), "--gait", str(gait)], capsys
    )
    assert code == 2 and err.count("\n") == 1 and f"gait field {field}" in err


def test_evaluate_swing_refuses_what_is_not_an_optimum(tmp_path, capsys):
    assert run(["evaluate", "--out", str(tmp_path)], capsys)[0] == 0
    code, _, err = run(["evaluate", "--swing", str(tmp_path / "summary.json")], capsys)
    assert code == 2 and "missing field optimization" in err and err.count("\n") == 1
    (tmp_path / "bad.json").write_text("{not json")
    code, _, err = run(["evaluate", "--swing", str(tmp_path / "bad.json")], capsys)
    assert code == 2 and "bad.json: not valid JSON" in err
    code, _, err = run(["evaluate", "--swing", str(tmp_path / "none.json")], capsys)
    assert code == 2 and "none.json" in err
    broken = json.loads((tmp_path / "summary.json").read_text())
    broken["optimization"] = {"RF": {"family": "joint-4", "parameters": {}}}
    (tmp_path / "broken.json").write_text(json.dumps(broken))
    code, _, err = run(["evaluate", "--swing", str(tmp_path / "broken.json")], capsys)
    assert code == 2 and "optimization.RF.success" in err


def test_commands_that_read_a_saved_optimum_take_its_catalog_robot(tmp_path, capsys):
    """Without --robot or --urdf, a saved result's robot is the one its provenance names, when
    that is a catalog robot; another name needs --urdf, and a --robot that differs is refused."""
    opt = tmp_path / "go1"
    argv = ["optimize", "--robot", "go1", "--family", "paper", "--leg", "RF", "--loads", "trunk"]
    assert run([*argv, "--out", str(opt), "-q"], capsys)[0] == 0
    saved = json.loads((opt / "summary.json").read_text())
    code, out, _ = run(["evaluate", "--swing", str(opt), "--json"], capsys)
    again = json.loads(out)
    assert code == 0 and again["provenance"]["robot"] == "go1"
    assert again["legs"]["RF"]["swing_energy_j"] == saved["legs"]["RF"]["swing_energy_j"]
    plan = tmp_path / "plan.csv"
    code, out, _ = run(["export", "--from", str(opt), "--rate", "500", "--out", str(plan)], capsys)
    assert code == 0 and "RL_calf_joint" in out and plan.exists()
    code, _, err = run(["evaluate", "--swing", str(opt), "--robot", "scalf"], capsys)
    assert code == 2 and err.count("\n") == 1
    assert "field provenance.robot is 'go1', not 'scalf'" in err
    # a name the catalog does not know (a robot loaded from its URDF): SCalf unless --urdf
    saved["provenance"]["robot"] = "my_dog"
    (tmp_path / "mine.json").write_text(json.dumps(saved))
    code, _, err = run(["evaluate", "--swing", str(tmp_path / "mine.json")], capsys)
    assert code == 2 and err.count("\n") == 1
    assert "field provenance.robot is 'my_dog', not 'scalf': give the same --robot or --urdf" in err


def test_paper_and_optimize_give_the_same_optimum(tmp_path, capsys):
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.locomotion.gait import Gait
    from scalf_opt.robots.loading import load_robot
    from scalf_opt.studies.paper import reproduce

    # the paper's trunk-only loads (its tables' model); the default loads' agreement is
    # tests/api/test_one_solve_path.py's
    gait = write_gait(tmp_path / "trot.toml", period_s=0.4, step_length_m=0.3)
    argv = ["optimize", "--gait", str(gait), "--loads", "trunk", "--out", str(tmp_path)]
    assert run(argv, capsys)[0] == 0
    saved = json.loads((tmp_path / "summary.json").read_text())
    trot = Gait(period_s=0.4, step_length_m=0.3)
    rep = reproduce(EnergyPipeline(load_robot("scalf"), trot, loads="trunk"), beyond=False)
    for leg in ("RF", "LH"):
        ours = rep.runs["ipopt_rich"].legs[leg].best
        assert saved["optimization"][leg]["swing_energy_j"] == ours.swing_energy_j
        assert list(saved["optimization"][leg]["parameters"].values()) == list(
            map(float, ours.theta)
        )


def test_an_optimum_worse_than_the_reference_says_so(tmp_path, capsys):
    # fourier-2 (foot space, two free terms per coordinate) cannot reach the reference on SCalf
    code, out, _ = run(["optimize", "--family", "fourier-2", "--out", str(tmp_path)], capsys)
    assert code == 0
    assert "warning: RF: the fourier-2 optimum" in out and "WORSE than the reference" in out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["optimization"]["RF"]["worse_than_reference"] is True
    assert summary["optimization_run"]["any_worse_than_reference"] is True
    # under whole-body loads a swing is optimized with the stance it loads: the warning says
    # what the whole cycle costs against the reference's (here more too), as summary.json has it
    optimized, reference = (
        summary["total_energy_per_cycle_j"],
        summary["reference_total_energy_per_cycle_j"],
    )
    assert (
        f"the cycle costs {optimized:.3f} J against the reference's {reference:.3f} J "
        f"({100 * (optimized / reference - 1):+.2f} %)"
    ) in out
    assert "the reference crosses" not in out  # SCalf's reference keeps its limits


def test_a_worse_optimum_says_which_limit_the_reference_crosses(capsys):
    """HyQ's reference swings load the stance hips' cylinders a quarter beyond their pull; the
    pattern search's optimum keeps every limit and costs more: the warning names the crossing,
    and the peaks table marks the reference's peak beyond its limit inside its brackets."""
    args = ["optimize", "--robot", "hyq", "--method", "pattern", "--family", "paper"]
    code, out, _ = run(args, capsys)
    assert code == 0 and "WORSE than the reference" in out
    assert (
        "; the reference crosses limits the optimum keeps: LF hip cyl_force by 25 % in stance"
        in (out)
    )
    table = out.split("peaks over the cycle")[1].split("\nlimit ")[0].split("\n", 2)[2]
    assert "*)" in table  # a reference peak beyond its limit, in its brackets
    assert not any(cell.endswith("*") for cell in table.replace(")", ") ").split())  # the optimum's
    _, reference_out, _ = run(["evaluate", "--robot", "hyq"], capsys)
    assert "LF hip: cyl_force = -2773.94 N exceeds" in reference_out and "by 25 %" in reference_out


def test_optimize_starts_and_regenerative_refusal(tmp_path, capsys):
    code, out, _ = run(["optimize", "--family", "joint-3", "--leg", "LH", "--starts", "3"], capsys)
    assert code == 0 and "3 starts, best" in out and "spread" in out
    # SCalf's URDF without its actuator file: ideal drives, which lose nothing
    bare = tmp_path / "bare_scalf.urdf"
    bare.write_text(load_robot("scalf").urdf_path.read_text())
    code, _, err = run(["optimize", "--urdf", str(bare), "--accounting", "regenerative"], capsys)
    assert code == 2 and err.count("\n") == 1 and "nothing to optimize" in err
    code, _, err = run(["optimize", "--starts", "0"], capsys)
    assert code == 2 and "--starts" in err


def test_optimize_free_method_and_free_stance(tmp_path, capsys):
    code, out, _ = run(
        ["optimize", "--family", "free", "--robot", "hyq", "--leg", "RF", "--out", str(tmp_path)],
        capsys,
    )
    assert code == 0 and "RF: free-trajectory bound" in out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["optimization"]["RF"]["family"].startswith("bspline-")
    assert summary["free_bound"]["RF"]["converged"]
    # the saved bound is an optimum like any other
    code, out, _ = run(
        ["evaluate", "--robot", "hyq", "--swing", str(tmp_path / "summary.json")], capsys
    )
    assert code == 0 and "saved optimum (bspline-" in out
    code, out, _ = run(
        [
            *("optimize", "--family", "paper", "--free-stance", "--loads", "trunk"),
            *("--out", str(tmp_path / "fs")),
        ],
        capsys,
    )
    assert code == 0 and "from the stance" in out
    # the stance found and the gait's own, to the same tenth of a millimetre
    assert re.search(r"free stance: z0 = \d\.\d{4} m \(was \d\.\d{4}\)", out)
    summary = json.loads((tmp_path / "fs" / "summary.json").read_text())
    assert summary["gait"]["stance_height_m"] == summary["free_stance"]["stance"]["stance_height_m"]
    assert summary["total_energy_per_cycle_j"] < summary["reference_total_energy_per_cycle_j"]


def test_optimize_bad_arguments(capsys):
    code, _, err = run(["optimize", "--family", "reference"], capsys)
    assert code == 2 and "no free parameter" in err
    code, _, err = run(["optimize", "--family", "bspline-16"], capsys)
    assert code == 2 and "family 'free'" in err
    code, _, err = run(["optimize", "--family", "free", "--starts", "3"], capsys)
    assert code == 2 and err.count("\n") == 1 and "--starts" in err  # not silently ignored
    with pytest.raises(SystemExit) as info:  # the bound is a family, not a solver
        run(["optimize", "--method", "free"], capsys)
    assert info.value.code == 2 and "--method: invalid choice: 'free'" in capsys.readouterr().err
    code, _, err = run(["optimize", "--free-stance", "--leg", "RF"], capsys)
    assert code == 2 and "--free-stance" in err
    with pytest.raises(SystemExit) as info:
        run(["optimize", "--leg", "XX"], capsys)
    assert info.value.code == 2 and "--leg: invalid choice: 'XX'" in capsys.readouterr().err


def test_paper_writes_report_json_and_csv(tmp_path, capsys):
    code, out, _ = run(["paper", "--quick", "--out", str(tmp_path)], capsys)
    assert code == 0
    assert "Table 6" in out and "671.52 W -> 617.68 W" in out and "report.md" in out
    report = (tmp_path / "report.md").read_text()
    assert "Table 5" in report and "-33.76" in report and "671.52 -> 617.68" in report
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


def test_output_into_a_closed_pipe_ends_quietly():
    # the reader goes away before scalf-opt writes (as `| head -2` does with a long output)
    proc = subprocess.Popen(
        [sys.executable, "-m", "scalf_opt.cli", "evaluate"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    proc.stdout.close()
    err = proc.stderr.read()
    proc.wait()
    assert proc.returncode == 0  # the output is dropped, the work done (files written)
    assert "Traceback" not in err and "BrokenPipe" not in err and "Exception" not in err
