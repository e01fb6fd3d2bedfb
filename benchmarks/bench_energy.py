"""Speed of one full-cycle energy evaluation of the diagonal pair (RF + LH) at 200 Hz.

Times, in the same run and on the same inputs (the cubic-spline reference):
  * the plain per-sample loop of NumPy and Pinocchio (tests/reference_loop.py), the baseline;
  * scalf-opt's CycleEvaluator in CasADi's virtual machine;
  * scalf-opt's CycleEvaluator compiled to native code (the default).
Prints the best-of-repeats time per cycle and the ratio to the baseline, and checks that all
three give the same energies. Wall-clock figures are machine-dependent; the ratio is the result.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

# isort: off
import scalf_opt  # noqa: E402, F401 (first: it pins OpenBLAS's kernels before numpy loads)

# isort: on
import numpy as np  # noqa: E402

from scalf_opt.energy.evaluator import CycleEvaluator  # noqa: E402
from scalf_opt.energy.pipeline import EnergyPipeline  # noqa: E402
from scalf_opt.locomotion.gait import Gait  # noqa: E402
from scalf_opt.locomotion.swing.registry import make_family  # noqa: E402
from scalf_opt.robots.loading import load_robot  # noqa: E402
from tests.reference_loop import phase_energy  # noqa: E402


def best_time(fn, repeats: int, number: int) -> float:
    """Best over ``repeats`` of the mean time of ``number`` calls [s]."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - start) / number)
    return best


def main() -> None:
    model = EnergyPipeline(load_robot("scalf"), Gait())
    family = make_family("reference")
    legs = ("RF", "LH")
    stance, tau_stance = model.stance_paths["RF"], model.stance_times_s
    swing = {leg: model.swing_path(leg, family) for leg in legs}
    leg_models = {leg: model.physics(leg).leg for leg in legs}

    def loop() -> np.ndarray:
        out = []
        for leg in legs:
            s = stance
            e_st, _ = phase_energy(
                leg_models[leg], s[0], s[1], s[2], model.stance_forces[leg], tau_stance
            )
            w = swing[leg].values()
            e_sw, _ = phase_energy(
                leg_models[leg], w[0], w[1], w[2], np.zeros_like(w[0]), swing[leg].t_s
            )
            out.append([e_st, e_sw])
        return np.array(out)

    start = time.perf_counter()
    compiled = CycleEvaluator(model, legs)
    build_compiled = time.perf_counter() - start
    vm = CycleEvaluator(model, legs, compiled=False)
    x = compiled.inputs(family)

    reference = loop()
    for name, ev in (("virtual machine", vm), ("compiled", compiled)):
        err = np.max(np.abs(ev(x) - reference) / np.abs(reference))
        assert err < 1e-9, f"{name} evaluator disagrees with the loop: {err:.2e}"

    t_loop = best_time(loop, repeats=5, number=5)
    t_vm = best_time(lambda: vm(x), repeats=5, number=500)
    t_compiled = best_time(lambda: compiled(x), repeats=5, number=2000)
    samples = 2 * (tau_stance.size + swing["RF"].t_s.size)
    print(f"one cycle of RF + LH at 200 Hz ({samples} samples), best of 5:")
    print(f"  plain NumPy + Pinocchio loop : {t_loop * 1e6:10.1f} us   (baseline)")
    print(f"  CycleEvaluator, CasADi VM    : {t_vm * 1e6:10.1f} us   {t_loop / t_vm:6.1f}x faster")
    print(
        f"  CycleEvaluator, compiled     : {t_compiled * 1e6:10.1f} us   "
        f"{t_loop / t_compiled:6.1f}x faster"
    )
    print(f"  (building the compiled evaluator took {build_compiled:.1f} s, cached afterwards)")
    print(f"  energies agree with the loop to 1e-9 relative: {reference.sum():.6f} J in total")


if __name__ == "__main__":
    main()
