"""Energy and its saving against trotting speed, 0.25 to 1.5 m/s, on SCalf.

Speed is changed through both the gait period and the step length, as animals do: the stride
frequency grows with the square root of the speed, ``T = 0.5 s * sqrt(1 m/s / v)``, and the step
follows, ``S = v * d * T`` (duty ``d = 0.5``): at 1 m/s this is the paper's trot (T = 0.5 s,
S = 0.25 m); at 0.25 m/s T = 1.0 s, S = 0.125 m; at 1.5 m/s T = 0.41 s, S = 0.31 m. Every case
evaluates the reference swing and optimizes the diagonal pair with Ipopt.

    python studies/speed_sweep.py [--quick] [--out DIR] [--workers N]

Writes ``speed.toml`` (the study file; ``scalf-opt study`` reruns it), ``results.csv`` and
``study.png`` (energy per cycle, saving and cost of transport against speed) in DIR (default
results/speed_sweep). --quick: three speeds, family joint-3 (the tests run it).
"""

from __future__ import annotations

import math
import sys

from scalf_opt.studies.script import run_study_script
from scalf_opt.studies.table import results_table

FULL_SPEEDS = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5)
QUICK_SPEEDS = (0.5, 1.0, 1.5)


def period_and_step(speed_m_s: float, duty: float = 0.5) -> tuple[float, float]:
    """``T = 0.5 s sqrt(1 m/s / v)`` and ``S = v d T`` (rounded to 0.1 mm and 0.1 ms)."""
    period = 0.5 * math.sqrt(1.0 / speed_m_s)
    return round(period, 4), round(speed_m_s * duty * period, 4)


def study_text(quick: bool) -> str:
    speeds = QUICK_SPEEDS if quick else FULL_SPEEDS
    pairs = ", ".join(f"[{t}, {s}]" for t, s in map(period_and_step, speeds))
    return f"""# Written by studies/speed_sweep.py: T = 0.5 s sqrt(1 m/s / v), S = v d T
[study]
name = "speed sweep (SCalf)"
robot = "scalf"
family = "{"joint-3" if quick else "joint-6"}"
[sweep]
"gait.period_s + gait.step_length_m" = [{pairs}]
[plot]
x = "speed_m_s"
"""


def main(argv: list[str] | None = None) -> int:
    study, result, _ = run_study_script(
        argv,
        __doc__,
        study_text,
        file_name="speed.toml",
        default_out="results/speed_sweep",
        quick_help="three speeds, family joint-3",
    )
    print(results_table(study.name, result))
    return 0 if not result.failed else 3


if __name__ == "__main__":
    sys.exit(main())
