"""Energy and its saving against the mid-swing clearance H, on SCalf at the paper's trot.

H from 4 to 16 cm (the paper: 8 cm); every case evaluates the reference swing (whose apex is H)
and optimizes the diagonal pair with Ipopt (the optimum must clear H at mid-swing).

    python studies/clearance_sweep.py [--quick] [--out DIR] [--workers N]

Writes ``clearance.toml``, ``results.csv`` and ``study.png`` in DIR (default
results/clearance_sweep). --quick: three clearances, family joint-3 (the tests run it).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from scalf_opt.files import write_atomic
from scalf_opt.studies.runner import choose_runner, run_study
from scalf_opt.studies.study_file import read_study
from scalf_opt.studies.table import results_table

FULL = (0.04, 0.06, 0.08, 0.10, 0.12, 0.14, 0.16)
QUICK = (0.04, 0.08, 0.12)


def study_text(quick: bool) -> str:
    values = ", ".join(str(h) for h in (QUICK if quick else FULL))
    return f"""# Written by studies/clearance_sweep.py
[study]
name = "clearance sweep (SCalf)"
robot = "scalf"
family = "{"joint-3" if quick else "joint-6"}"
[sweep]
"gait.clearance_m" = [{values}]
"""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="three clearances, family joint-3")
    parser.add_argument("--out", type=Path, default=Path("results/clearance_sweep"))
    parser.add_argument("--workers", type=int, help="local worker processes (default: per CPU)")
    args = parser.parse_args(argv)
    path = write_atomic(args.out / "clearance.toml", study_text(args.quick))
    study = read_study(path)
    result = run_study(study, args.out, choose_runner(args.workers))
    print(results_table(study.name, result))
    return 0 if not result.failed else 3


if __name__ == "__main__":
    sys.exit(main())
