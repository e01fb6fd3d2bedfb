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
