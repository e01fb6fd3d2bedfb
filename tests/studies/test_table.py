"""The study's text table."""

from __future__ import annotations

from pathlib import Path

from scalf_opt.studies.runner import StudyRun
from scalf_opt.studies.table import results_table


def _row(case: int, clearance: float, reference: float | None, optimized: float | None) -> dict:
    ok = optimized is not None
    return {
        "case": case,
        "gait.clearance_m": clearance,
        "status": "ok" if ok else "failed",
        "error": "" if ok else "no feasible point",
        "reference_energy_j": reference,
        "optimized_energy_j": optimized,
        "saving_pct": None if not ok else 100.0 * (1.0 - optimized / reference),
    }


def test_energies_are_printed_to_the_millijoule_in_every_row():
    # "%.4g" printed 156 beside 157.9 and 9.77 beside 8.966
    rows = [_row(0, 0.04, 181.9, 156.0), _row(1, 0.06, 9.77, 8.966), _row(2, 0.08, 0.1249, None)]
    columns = ["case", "gait.clearance_m", "status", "error"]
    run = StudyRun(rows, columns, Path("r/results.csv"), Path("r/study.png"), cached=0)
    lines = results_table("sweep", run).splitlines()
    assert lines[1].split()[:4] == ["case", "clearance_m", "reference", "J"]
    assert lines[2].split()[:5] == ["0", "0.04", "181.900", "156.000", "14.24"]
    assert lines[3].split()[:5] == ["1", "0.06", "9.770", "8.966", "8.23"]
    assert lines[4].split() == ["2", "0.08", "0.125", "failed:", "no", "feasible", "point"]
