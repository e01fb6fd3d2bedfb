"""Every study runs headless (quick mode) and its conclusion holds."""

import importlib.util
from pathlib import Path

from scalf_opt.locomotion.swing.fourier import PAPER_FREE_TERMS

STUDIES = Path(__file__).resolve().parents[2] / "studies"


def load(name):
    spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


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


def test_paper_reproduction_study(tmp_path, capsys):
    assert load("paper_reproduction").main(["--out", str(tmp_path)]) == 0
    assert (tmp_path / "report.md").exists()
    capsys.readouterr()


def test_simulation_validation_study(tmp_path, capsys):
    """Quick mode: 2 cycles, 5 seeds; the reference keeps the paper's 4 mm and the 10 % goal."""
    assert load("simulation_validation").main(["--quick", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "| reference |" in out and "optimum (joint-6)" in out
    import json

    data = json.loads((tmp_path / "validation.json").read_text())
    reference, optimum = data["results"]
    assert reference["height_fluctuation_mm"] <= 4.0
    assert abs(reference["largest_leg_difference_pct"]) <= 10.0
    assert optimum["saving_model_pct"] < 0 and optimum["saving_sim_pct"] < 0
    for name in ("reference", "optimum"):
        assert (tmp_path / name / "simulation.png").read_bytes().startswith(b"\x89PNG")
