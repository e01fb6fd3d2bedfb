"""How far is each swing family from the free-trajectory bound? (SCalf, the paper's gait.)

For each family, Ipopt's optimum of the RF and LH legs (``scalf-opt optimize --family F``), then
the free-trajectory bound of each leg (dense B-splines refined until the energy converges,
started from the reference and from every family's optimum), and each optimum's gap to it.
Energies are at ten times each optimization's rate (the converged energies).

    python studies/bound_gaps.py [--quick] [--out FILE.csv]

--quick: the paper family and joint-4 only, and the bound's first two levels (the test suite
runs it that way).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.files import write_atomic
from scalf_opt.io.results import rows_csv_text
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.bound import SPANS, bound_for
from scalf_opt.optimize.driver import optimize_swings
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import FIRST_PAIR

FAMILIES = ("paper", "joint-2", "joint-4", "joint-6", "joint-8", "joint-12")


def gaps(quick: bool) -> tuple[list[dict[str, object]], dict[str, object]]:
    pipeline = EnergyPipeline(load_robot("scalf"), Gait(), loads="trunk")
    families = ("paper", "joint-4") if quick else FAMILIES
    runs = {name: optimize_swings(pipeline, FIRST_PAIR, make_family(name)) for name in families}
    bounds = {
        leg: bound_for(
            pipeline,
            leg,
            [(run.family, run.legs[leg].best.theta) for run in runs.values()],
            spans=SPANS[:2] if quick else SPANS,
        )
        for leg in FIRST_PAIR
    }
    rows: list[dict[str, object]] = []
    for name, run in runs.items():
        row: dict[str, object] = {"family": name, "sample_rate_hz": run.rate_hz}
        for leg in FIRST_PAIR:
            energy = run.legs[leg].check_energy_j
            row[f"{leg}_swing_j"] = energy
            row[f"{leg}_gap_pct"] = bounds[leg].gap_percent(energy)
        rows.append(row)
    bound_row: dict[str, object] = {"family": "free-trajectory bound"}
    for leg in FIRST_PAIR:
        b = bounds[leg]
        bound_row[f"{leg}_swing_j"] = b.check_energy_j
        bound_row[f"{leg}_spans"] = b.spans
        bound_row[f"{leg}_remaining_pct"] = 100 * b.remaining_j / b.check_energy_j
    return rows, bound_row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    rows, bound = gaps(args.quick)
    print("family      rate [Hz]   RF swing [J]   RF gap   LH swing [J]   LH gap")
    for r in rows:
        print(
            f"{r['family']!s:11s} {r['sample_rate_hz']:9g} {r['RF_swing_j']:14.3f} "
            f"{r['RF_gap_pct']:+7.2f} % {r['LH_swing_j']:14.3f} {r['LH_gap_pct']:+7.2f} %"
        )
    print(
        f"bound       {'':9s} {bound['RF_swing_j']:14.3f} ({bound['RF_spans']} spans, "
        f"~{bound['RF_remaining_pct']:.1f} % left) {bound['LH_swing_j']:10.3f} "
        f"({bound['LH_spans']} spans, ~{bound['LH_remaining_pct']:.1f} % left)"
    )
    if args.out is not None:
        write_atomic(args.out, rows_csv_text([*rows, bound]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
