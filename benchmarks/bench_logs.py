"""Log analysis is linear in the log's length: a 3-hour 80 Hz log against a 10-minute one.

Both logs are SCalf's reference trot as its sensors would record it (80 Hz, four legs, the
contact column; lengths to 0.01 mm, forces to 0.1 N, times to 0.1 ms, as a logger writes them),
written to a file and analysed from the file by ``scalf_opt.api.analyze_log`` (read, checked,
filtered, integrated per cycle), as ``scalf-opt analyze-log`` does. Prints the best-of-repeats
time of each and the ratio of the times beside the ratio of the lengths (18): linear analysis
gives a time ratio near 18, a quadratic one near 324. Wall-clock figures are machine-dependent;
the ratio is the result. Also checks that both logs give the same mean power (to 1e-4: the
cycles at the ends differ).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

# isort: off
import scalf_opt  # noqa: E402, F401 (first: it pins OpenBLAS's kernels before numpy loads)

# isort: on
import numpy as np  # noqa: E402

from scalf_opt.api import analyze_log  # noqa: E402
from scalf_opt.energy.pipeline import EnergyPipeline  # noqa: E402
from scalf_opt.locomotion.gait import Gait  # noqa: E402
from scalf_opt.logs.log_file import ALL_COLUMNS  # noqa: E402
from scalf_opt.logs.model_log import model_log  # noqa: E402
from scalf_opt.robots.loading import load_robot  # noqa: E402
from scalf_opt.sim.plan import REFERENCE_SWINGS  # noqa: E402

RATE_HZ = 80.0
BASELINE_S = 600.0
LONG_S = 3 * 3600.0


def log_text(pipeline: EnergyPipeline, duration_s: float) -> str:
    """The reference trot's noiseless cylinder log over ``duration_s``, as a logger writes it."""
    cycles = round(duration_s / pipeline.gait.period_s)
    log, _ = model_log(pipeline, REFERENCE_SWINGS, RATE_HZ, cycles=cycles)
    rows = []
    for order, (leg, data) in enumerate(log.legs.items()):
        assert data.contact is not None
        table = np.column_stack([data.t_s, data.length_m.T, data.force_n.T, data.contact])
        rows += [(t, order, leg, row) for t, row in zip(data.t_s, table, strict=True)]
    rows.sort(key=lambda r: (r[0], r[1]))
    lines = [",".join(ALL_COLUMNS)]
    lines += [
        f"{r[0]:.4f},{leg},{r[1]:.5f},{r[2]:.5f},{r[3]:.1f},{r[4]:.1f},{int(r[5])}"
        for _, _, leg, r in rows
    ]
    return "\n".join(lines) + "\n"


def best_time(fn, repeats: int) -> tuple[float, object]:
    """Best time of ``repeats`` calls [s], and the last result."""
    best, result = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return best, result


def main() -> None:
    robot = load_robot("scalf")
    gait = Gait()
    pipeline = EnergyPipeline(robot, gait)
    with tempfile.TemporaryDirectory() as tmp:
        times, energies, sizes = {}, {}, {}
        for name, duration_s, repeats in (("10 min", BASELINE_S, 3), ("3 h", LONG_S, 1)):
            path = Path(tmp) / f"{name.replace(' ', '')}.csv"
            path.write_text(log_text(pipeline, duration_s), encoding="utf-8")
            sizes[name] = path.stat().st_size
            seconds, result = best_time(lambda p=path: analyze_log(p, robot, gait), repeats)
            times[name] = seconds
            energies[name] = result.analysis.average_power_w  # type: ignore[union-attr]
            path.unlink()
    ratio = times["3 h"] / times["10 min"]
    print(f"log analysis at {RATE_HZ:g} Hz, four legs, from the file (best of repeats):")
    for name in times:
        print(
            f"  {name:>6}: {sizes[name] / 1e6:7.1f} MB  {times[name]:7.2f} s  "
            f"mean power {energies[name]:.3f} W"
        )
    print(
        f"  ratio 3 h / 10 min: {ratio:.1f} (lengths: {LONG_S / BASELINE_S:.0f}; "
        f"quadratic: {(LONG_S / BASELINE_S) ** 2:.0f})"
    )
    same = abs(energies["3 h"] / energies["10 min"] - 1) < 1e-4
    print(f"  same mean power per cycle: {'yes' if same else 'NO'}")
    if not same:
        sys.exit(1)


if __name__ == "__main__":
    main()
