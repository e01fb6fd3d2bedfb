"""Speed of the swing optimization: Ipopt against SciPy's SLSQP with finite differences.

For each family (default: the paper family, joint-2, joint-4 and the default joint-6), on the
RF leg of SCalf at the paper's gait and its trunk-only stance loads (the problem of
``scalf-opt paper``), from zero parameters, both methods solve the same problem: the exact swing
energy under every constraint, sampled at the rate ``scalf-opt optimize`` uses for that family
(the rate at which its optimum's energy has converged):

* Ipopt on the NLP (exact derivatives through the compiled per-sample kernel). The NLP is
  built once per problem shape (the first call) and reused, like the compiled evaluator SLSQP
  uses; the build time is printed on its own. Best of three solves.
* ``scipy.optimize.minimize(method="SLSQP")`` on the exact energy, every constraint as an
  inequality, gradients by finite differences (SciPy's default), evaluated through the same
  compiled kernel. One run.

Both answers are evaluated exactly; the table says whether Ipopt's is equal or better. The
ratio is SLSQP's time over Ipopt's, measured in the same run (wall-clock times vary with the
machine's load; ratios are what to compare). The last lines, one per family, are
``FAMILY: Ipopt T s, SLSQP-FD T s, ratio Rx``.

Then the drivers on top of the families, each timed whole (its every solve, sampling check
and level) and stated as a multiple of the last family's Ipopt solve in the same run, with the
CPU time it took (every thread's and worker process's; on a loaded machine the wall-clock time
grows with the load, the CPU time much less):

* ``bound RF``: the free-trajectory bound of the RF leg (``--family free``), its levels, and the
  energy still to gain;
* ``bounds RF + LH``: the bounds of both legs as ``scalf-opt paper`` computes them, in worker
  processes (one per core, :mod:`scalf_opt.workers`), against the RF bound alone (with two free
  cores about the slower leg's time, plus a second or two to start the workers);
* ``free stance``: the stance height and x-offsets optimized with the ``joint-6`` swings of RF
  and LH (``--free-stance``; the two legs' swings on parallel threads, which Ipopt's lock on
  MUMPS runs mostly one after the other), and how many stances it tried.

    python benchmarks/bench_optimize.py [FAMILY ...]
"""

from __future__ import annotations

import os
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

# isort: off
import scalf_opt  # noqa: F401 (first: it pins OpenBLAS's kernels before numpy loads)

# isort: on
import numpy as np
from scipy.optimize import minimize

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.bound import bound_for, bounds_for
from scalf_opt.optimize.driver import optimize_swings
from scalf_opt.optimize.free_stance import optimize_stance
from scalf_opt.optimize.nlp import build_nlp
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import run_ipopt
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import FIRST_PAIR

LEG = "RF"
EQUAL = 1e-6  # J: optima closer than this count as equal


def margins(problem: SwingProblem, theta: np.ndarray) -> np.ndarray:
    """Every constraint as ``g(theta) >= 0`` (the NLP's: bounds where they apply)."""
    c = problem.outputs(theta)["c"].ravel(order="F")[problem.constraint_index]
    lower, upper = (b.ravel(order="F")[problem.constraint_index] for b in problem.constraint_bounds)
    out = np.concatenate([(c - lower)[np.isfinite(lower)], (upper - c)[np.isfinite(upper)]])
    return np.nan_to_num(out, nan=-1.0)


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def cpu_s() -> float:
    """CPU time of this process (every thread) and of its finished worker processes [s]."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def timed_cpu(fn):
    """``fn()``, its wall-clock time and the CPU time over it (:func:`cpu_s`) [s]."""
    cpu = cpu_s()
    out, wall = timed(fn)
    return out, wall, cpu_s() - cpu


def compare(pipeline: EnergyPipeline, name: str) -> tuple[float, float, bool]:
    """Run both methods on one family; print a table; return (Ipopt s, SLSQP s, equal/better)."""
    family = make_family(name)
    rate = optimize_swings(pipeline, (LEG,), family).rate_hz  # the rate optimize would use
    at_rate = pipeline.with_gait(Gait(sample_rate_hz=rate))
    problem = SwingProblem(at_rate, LEG, family)
    x0 = np.zeros(problem.n_params)
    problem.evaluate(x0)  # the compiled kernel, loaded once, outside every timing
    t_build = build_nlp(problem).build_time_s  # when it was built, for this shape
    runs = [timed(lambda: run_ipopt(problem, x0)) for _ in range(3)]
    ipopt, t_ipopt = min(runs, key=lambda r: r[1])
    slsqp, t_slsqp = timed(
        lambda: minimize(
            problem.energy_j,
            x0,
            method="SLSQP",
            constraints=[{"type": "ineq", "fun": lambda th: margins(problem, th)}],
            options={"ftol": 1e-10, "maxiter": 1000},
        )
    )
    slsqp_eval = problem.evaluate(slsqp.x)
    print(
        f"{name} ({problem.n_params} parameters), {LEG} leg at {rate:g} Hz "
        f"({problem.n_samples} swing samples), from zero; NLP built once in {t_build:.3f} s"
    )
    print(f"{'method':34s} {'time [s]':>9s} {'energy [J]':>11s} {'feasible':>9s} {'iter/fev':>9s}")
    print(
        f"{'Ipopt (exact derivatives)':34s} {t_ipopt:9.3f} {ipopt.swing_energy_j:11.5f} "
        f"{ipopt.success!s:>9s} {ipopt.iterations:9d}"
    )
    print(
        f"{'SciPy SLSQP (finite differences)':34s} {t_slsqp:9.3f} "
        f"{problem.energy_j(slsqp.x):11.5f} {slsqp_eval.reason is None!s:>9s} {slsqp.nfev:9d}"
    )
    better = ipopt.success and (
        slsqp_eval.reason is not None or ipopt.swing_energy_j <= slsqp_eval.energy_j + EQUAL
    )
    verdict = "equal or better" if better else "WORSE"
    print(f"Ipopt's optimum is {verdict}; SLSQP-FD takes {t_slsqp / t_ipopt:.1f}x Ipopt's time")
    print()
    return t_ipopt, t_slsqp, better


def main() -> None:
    families = sys.argv[1:] or ["paper", "joint-2", "joint-4", "joint-6"]
    # the paper's problem, as `scalf-opt paper` solves it: the trunk-only stance loads
    pipeline = EnergyPipeline(load_robot("scalf"), Gait(), loads="trunk")
    lines = []
    for name in families:
        t_ipopt, t_slsqp, better = compare(pipeline, name)
        note = "" if better else " (Ipopt's optimum is worse)"
        lines.append(
            f"{name}: Ipopt {t_ipopt:.3f} s, SLSQP-FD {t_slsqp:.3f} s, "
            f"ratio {t_slsqp / t_ipopt:.1f}x{note}"
        )
    bound, t_bound, cpu_bound = timed_cpu(lambda: bound_for(pipeline, LEG))
    levels = ", ".join(f"{lv.spans}: {lv.wall_time_s:.1f} s" for lv in bound.levels)
    lines.append(
        f"bound {LEG}: {t_bound:.1f} s, CPU {cpu_bound:.1f} s ({t_bound / t_ipopt:.0f}x the "
        f"{families[-1]} Ipopt solve; levels {levels}), {bound.status_text()}"
    )
    pair, t_pair, cpu_pair = timed_cpu(lambda: bounds_for(pipeline, FIRST_PAIR))
    lines.append(
        f"bounds {' + '.join(FIRST_PAIR)} in {min(os.cpu_count() or 1, len(FIRST_PAIR))} "
        "processes "
        f"(paper): {t_pair:.1f} s, CPU {cpu_pair:.1f} s ({t_pair / t_bound:.2f}x the {LEG} "
        "bound alone), " + "; ".join(f"{leg} {b.status_text()}" for leg, b in pair.items())
    )
    stance, t_stance, cpu_stance = timed_cpu(
        lambda: optimize_stance(pipeline, make_family("joint-6"))
    )
    lines.append(
        f"free stance: {t_stance:.1f} s, CPU {cpu_stance:.1f} s ({t_stance / t_ipopt:.0f}x the "
        f"{families[-1]} Ipopt "
        f"solve), {stance.evaluations} stances tried, "
        f"{'converged' if stance.success else 'NOT CONVERGED'}"
    )
    print("\n".join(lines))


if __name__ == "__main__":
    main()
