"""Every study runs headless (quick mode) and its conclusion holds."""

import importlib.util
from pathlib import Path

import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.fourier import PAPER_FREE_TERMS
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.robots.loading import load_robot

STUDIES = Path(__file__).resolve().parents[2] / "studies"


def load(name):
    spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow  # a study end to end: about 15 s alone
def test_paper_family_is_the_scan_winner(tmp_path, capsys):
    study = load("paper_family_scan")
    rows = study.scan(quick=True)
    best = rows[0]
    chosen = ["".join(map(str, terms[0])) for terms in PAPER_FREE_TERMS]
    assert best["space"] == "joint"
    assert [best["term_1"], best["term_2"]] == chosen
    assert best["RF_swing_change_pct"] < 0 and best["LH_swing_change_pct"] < 0
    assert study.main(["--quick", "--out", str(tmp_path / "scan.csv")]) == 0
    assert (tmp_path / "scan.csv").read_text().startswith("space,term_1,term_2")
    capsys.readouterr()


@pytest.mark.slow  # the whole paper: about 40 s alone, minutes beside the other tests
def test_paper_reproduction_study(tmp_path, capsys):
    """The whole `scalf-opt paper` (the suite's one run of it beyond --quick): the tables, the
    validation, the bound and the free stance, every one converged, and the whole-body line."""
    import json

    assert load("paper_reproduction").main(["--out", str(tmp_path)]) == 0
    report = (tmp_path / "report.md").read_text()
    for heading in (
        "## Table 5",
        "## Table 6",
        "## Validation: pattern search against the NLP optimum",
        "## Beyond the paper: the free-trajectory bound",
        "## Beyond the paper: the stance as a free variable",
    ):
        assert heading in report
    assert "NOT CONVERGED" not in report and "whole-body loads" in report
    saved = json.loads((tmp_path / "paper.json").read_text())
    assert saved["all_solved"] and saved["status"] == "converged" and saved["free_stance"]
    capsys.readouterr()


@pytest.mark.slow  # a study end to end: about 45 s alone
def test_simulation_validation_study(tmp_path, capsys):
    """Quick mode: 2 cycles, 5 seeds; the reference keeps the paper's 4 mm, and the simulation
    spends what the plan needs (MuJoCo's inverse dynamics of the plan) within 3 % on the
    reference. The whole-body optimum's hind swing is not followed as well (measured +9.3 % in
    this quick run, +9.2 % over 10 cycles: docs/simulation-referee.md, a goal not met); the test
    holds it below 12 % so that a worse referee or a harder optimum fails here."""
    assert load("simulation_validation").main(["--quick", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "| reference |" in out and "optimum (joint-6)" in out
    import json

    data = json.loads((tmp_path / "validation.json").read_text())
    reference, optimum = data["results"]
    assert reference["height_fluctuation_mm"] <= 4.0
    assert abs(reference["sim_vs_plan_pct"]) <= 3.0 and abs(optimum["sim_vs_plan_pct"]) <= 12.0
    assert optimum["saving_model_pct"] < 0 and optimum["saving_sim_pct"] < 0
    for name in ("reference", "optimum"):
        assert (tmp_path / name / "simulation.png").read_bytes().startswith(b"\x89PNG")


def rows_of(path):
    import csv

    with path.open() as handle:
        return list(csv.DictReader(handle))


def test_speed_sweep(tmp_path, capsys):
    assert load("speed_sweep").main(["--quick", "--workers", "1", "--out", str(tmp_path)]) == 0
    rows = rows_of(tmp_path / "results.csv")
    speeds = [float(r["speed_m_s"]) for r in rows]
    assert speeds == pytest.approx([0.5, 1.0, 1.5], abs=1e-3)  # T and S rounded to 0.1 ms, mm
    energies = [float(r["reference_energy_j"]) for r in rows]
    assert energies == sorted(energies)  # faster costs more per cycle here
    assert all(float(r["saving_pct"]) > 0 for r in rows)
    assert (tmp_path / "study.png").stat().st_size > 10_000
    capsys.readouterr()


def test_clearance_sweep(tmp_path, capsys):
    assert load("clearance_sweep").main(["--quick", "--workers", "1", "--out", str(tmp_path)]) == 0
    rows = rows_of(tmp_path / "results.csv")
    reference = [float(r["reference_energy_j"]) for r in rows]
    assert reference == sorted(reference)  # lifting the foot higher costs more
    assert float(rows[1]["reference_energy_j"]) == pytest.approx(282.259, abs=1e-3)  # H = 8 cm
    capsys.readouterr()


@pytest.mark.slow  # a study end to end: about 10 s alone
def test_leg_ratio(tmp_path, capsys):
    study = load("leg_ratio")
    assert study.main(["--quick", "--workers", "1", "--out", str(tmp_path)]) == 0
    rows = rows_of(tmp_path / "results.csv")
    ratios = [float(r["thigh_to_shank"]) for r in rows]
    assert ratios == pytest.approx(list(study.QUICK), rel=1e-12)
    assert all(
        float(r["thigh_length_m"]) + float(r["shank_length_m"]) == pytest.approx(0.85586)
        for r in rows
    )
    # SCalf's own ratio is a variant with scales 1 up to round-off: SCalf's energy
    scalf = EnergyPipeline(load_robot("scalf"), Gait()).robot_cycle(make_family("reference"))
    assert float(rows[1]["reference_energy_j"]) == pytest.approx(scalf.energy_j, rel=1e-9)
    capsys.readouterr()


def test_paper_power_height(tmp_path, capsys):
    study = load("paper_power_height")
    assert study.main(["--quick", "--out", str(tmp_path)]) == 0
    rows = rows_of(tmp_path / "result.csv")
    root = float(rows[0]["stance_height_m"])
    assert 0.5 < root < 0.6
    assert study.reference_power_w(root) == pytest.approx(671.52, abs=1e-3)
    assert float(rows[1]["reference_power_w"]) == pytest.approx(564.52, abs=0.01)  # z0 = 0.75 m
    out = capsys.readouterr().out
    assert "671.52 W (the paper, Table 6) at z0 = 0.54" in out


@pytest.mark.slow  # a study end to end on six robots: about 25 s alone
def test_cross_robot(tmp_path, capsys):
    assert load("cross_robot").main(["--quick", "--workers", "1", "--out", str(tmp_path)]) == 0
    rows = rows_of(tmp_path / "results.csv")
    assert [r["robot"] for r in rows] == ["scalf", "hyq", "solo12", "anymal_c", "go1", "a1"]
    assert all(r["status"] == "ok" and float(r["saving_pct"]) > 0 for r in rows)
    table = (tmp_path / "table.md").read_text()
    assert table.count("\n") == 8 and "valve-controlled" in table
    capsys.readouterr()


def test_bound_gaps_study(tmp_path, capsys):
    import csv

    assert load("bound_gaps").main(["--quick", "--out", str(tmp_path / "gaps.csv")]) == 0
    with (tmp_path / "gaps.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert [r["family"] for r in rows] == ["paper", "joint-4", "free-trajectory bound"]
    # every family's optimum lies above the bound, the richer one closer
    for row in rows[:2]:
        assert float(row["RF_gap_pct"]) > 0 and float(row["LH_gap_pct"]) > 0
    assert float(rows[1]["RF_gap_pct"]) < float(rows[0]["RF_gap_pct"])
    assert "bound" in capsys.readouterr().out


@pytest.mark.slow  # an optimization and two 3-cycle simulations of Solo12: about 15 s
def test_whole_robot_validation_study(tmp_path, capsys):
    """Quick mode on one robot under the referee's distribution: the tables, the model is the
    plan's inverse dynamics, and the referee spends what the plan needs."""
    import json

    study = load("whole_robot_validation")
    argv = ["--quick", "--robots", "solo12", "--loads", "whole-body-sagittal"]
    assert study.main([*argv, "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "| solo12 | reference | RF |" in out and "| solo12 | optimum |" in out
    written = json.loads((tmp_path / "whole_robot_validation.json").read_text())
    assert written["loads"] == "whole-body-sagittal"
    (result,) = written["results"]
    for row in result["trajectories"].values():
        # the planar referee shares the loads as this model does (measured +0.1 %; +4.9 % on
        # the reference with the default 3-D distribution)
        assert abs(row["model_vs_plan_pct"]) < 0.5
        # the simulation follows the plan: its energy is the plan's inverse dynamics' (measured
        # +1.0 and +1.1 %), its trunk level (0.03 mm) and on time
        assert abs(row["simulated_vs_plan_pct"]) < 3.0
        assert row["trunk_height_fluctuation_over_stance_height_pct"] < 1.0
        assert row["speed_m_s"] == pytest.approx(row["planned_speed_m_s"], rel=1e-3)
    assert (tmp_path / "solo12" / "simulation" / "simulation.png").exists()
