"""Energy and its saving against the mid-swing clearance H, on SCalf at the paper's trot.

Under the paper's trunk-only stance loads (``loads = "trunk"`` in the study file), like the
paper.

H from 4 to 16 cm (the paper: 8 cm); every case evaluates the reference swing (whose apex is H)
and optimizes the diagonal pair with Ipopt (the optimum must clear H at mid-swing).

    python studies/clearance_sweep.py [--quick] [--out DIR] [--workers N]

Writes ``clearance.toml``, ``results.csv`` and ``study.png`` in DIR (default
results/clearance_sweep). --quick: three clearances, family joint-3 (the tests run it).
"""

from __future__ import annotations

import sys

from scalf_opt.studies.script import run_study_script
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
loads = "trunk"
[sweep]
"gait.clearance_m" = [{values}]
"""


def main(argv: list[str] | None = None) -> int:
    study, result, _ = run_study_script(
        argv,
        __doc__,
        study_text,
        file_name="clearance.toml",
        default_out="results/clearance_sweep",
        quick_help="three clearances, family joint-3",
    )
    print(results_table(study.name, result))
    return 0 if not result.failed else 3


if __name__ == "__main__":
    sys.exit(main())
