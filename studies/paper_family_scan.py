"""Which two free Fourier coefficients make the best 'paper' family? A scan, by Ipopt.

The paper optimizes two coefficients per leg (C1, C2) of a Fourier series whose form was lost.
This study tries every pair of one free term per coordinate, each term one of cos/sin of orders
2-4 (the four end-condition terms a0, a1, b1, b2 are always eliminated), in foot space (x, z) and
joint space (hip, knee), solves each family's NLP for the RF and LH legs, and ranks the pairs by
swing energy against the reference. `scalf_opt.locomotion.swing.fourier.PAPER_FREE_TERMS` is the
winner.

    python studies/paper_family_scan.py [--quick] [--out FILE.csv]

--quick scans joint space with orders 2-3 only (the test suite runs it that way). Pairs whose
z (or knee) term vanishes at mid-swing cannot meet the clearance: Ipopt reports them infeasible.
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

from scalf_opt.cli.console import Console
from scalf_opt.energy.cycle import change_percent
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.files import write_atomic
from scalf_opt.io.results import rows_csv_text
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.fourier import FourierFamily
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import run_ipopt
from scalf_opt.robots.loading import load_robot


def scan(quick: bool) -> list[dict[str, object]]:
    pipeline = EnergyPipeline(load_robot("scalf"), Gait(), loads="trunk")
    reference = pipeline.robot_cycle(make_family("reference"), legs=("RF", "LH"))
    orders = (2, 3) if quick else (2, 3, 4)
    terms = [(kind, k) for k in orders for kind in ("cos", "sin") if (kind, k) != ("sin", 2)]
    rows: list[dict[str, object]] = []
    for space in ("joint",) if quick else ("joint", "foot"):
        for first, second in itertools.product(terms, terms):
            family = FourierFamily(f"{space}-{first}-{second}", space, ((first,), (second,)))
            row: dict[str, object] = {
                "space": space,
                "term_1": "".join(map(str, first)),
                "term_2": "".join(map(str, second)),
            }
            for leg in ("RF", "LH"):
                # an infeasible pair is recognised long before Ipopt's default 3000 iterations
                optimum = run_ipopt(
                    SwingProblem(pipeline, leg, family), ipopt_options={"max_iter": 300}
                )
                ref = reference.legs[leg].swing_energy_j
                change = change_percent(optimum.swing_energy_j, ref) if optimum.success else None
                row[f"{leg}_swing_change_pct"] = change
                row[f"{leg}_status"] = optimum.status
            rows.append(row)
    rows.sort(
        key=lambda r: (
            r["RF_swing_change_pct"] if r["RF_swing_change_pct"] is not None else float("inf")
        )
    )
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="orders 2-3 only")
    parser.add_argument("--out", type=Path, help="write the ranking as CSV")
    args = parser.parse_args(argv)
    rows = scan(args.quick)
    if args.out:
        write_atomic(args.out, rows_csv_text(rows))
    console = Console()  # survives `| head`: the CSV is written first, the table printed after
    console.text("rank  space  C1 term  C2 term   RF swing    LH swing")
    for i, r in enumerate(rows, 1):

        def fmt(x: object) -> str:
            return f"{x:+8.2f} %" if isinstance(x, float) else "  not solved"

        console.text(
            f"{i:4d}  {r['space']:5s}  {r['term_1']:7s}  {r['term_2']:7s}  "
            f"{fmt(r['RF_swing_change_pct'])}  {fmt(r['LH_swing_change_pct'])}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
