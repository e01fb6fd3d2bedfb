"""Speed of the swing optimization: Ipopt (exact CasADi derivatives) against SciPy.

For the paper family (2 parameters) and richer families (``joint-4``: 10, ``joint-6``: 18), all
methods minimise the same exact swing energy of the RF leg from zero parameters, under the same
constraints, in one run:
  * Ipopt on the smooth NLP (slack pairs, smoothed heat), answer evaluated exactly;
  * scipy.optimize.minimize, Nelder-Mead, on the exact energy plus a penalty on the constraint
    violation (Nelder-Mead has no constraints);
  * scipy.optimize.minimize, SLSQP, exact energy and the constraints as inequalities, gradients
    by finite differences.
Prints wall time, exact energy, feasibility and the ratio of each SciPy time to Ipopt's.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import minimize

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import run_ipopt
from scalf_opt.robots.loading import load_robot

PENALTY_J_PER_UNIT = 1e4  # Nelder-Mead penalty per metre or radian of constraint violation


def margins(problem: SwingProblem, theta: np.ndarray) -> np.ndarray:
    """Every constraint as ``g(theta) >= 0``, from the exact evaluator's samples."""
    _, q, foot, _, *outputs = (np.array(v) for v in problem.exact_function(theta))
    lo, hi = problem.joint_bounds
    parts = [
        (q - lo).ravel(),
        (hi - q).ravel(),
        foot[1, 1:-1] - problem.ground_z_m,
        [foot[1, problem.mid_index] - problem.clearance_z_m],
    ]
    for (b_lo, b_hi), value in zip(problem.output_bounds.values(), outputs, strict=True):
        parts += [(value - b_lo).ravel(), (b_hi - value).ravel()]
    return np.concatenate(parts)


def exact_energy(problem: SwingProblem, theta: np.ndarray) -> float:
    return float(np.array(problem.exact_function(theta)[0]).item())


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def main() -> None:
    families = sys.argv[1:] or ["paper", "joint-4", "joint-6"]
    pipeline = EnergyPipeline(load_robot("scalf"), Gait())
    for name in families:
        compare(SwingProblem(pipeline, "RF", make_family(name)))
        print()


def compare(problem: SwingProblem) -> None:
    """Run and print the three methods on one problem."""
    x0 = np.zeros(problem.n_params)
    problem.evaluate(x0)  # build the compiled exact function once, outside every timing

    ipopt, t_ipopt = timed(lambda: run_ipopt(problem, x0))

    def penalised(theta: np.ndarray) -> float:
        e = problem.evaluate(theta)
        energy = exact_energy(problem, theta)
        return energy + PENALTY_J_PER_UNIT * e.violation

    nm, t_nm = timed(
        lambda: minimize(
            penalised,
            x0,
            method="Nelder-Mead",
            options={"xatol": 1e-4, "fatol": 1e-6, "maxfev": 20000},
        )
    )
    slsqp, t_slsqp = timed(
        lambda: minimize(
            lambda th: exact_energy(problem, th),
            x0,
            method="SLSQP",
            constraints=[{"type": "ineq", "fun": lambda th: margins(problem, th)}],
            options={"ftol": 1e-10, "maxiter": 500},
        )
    )
    rows = [
        ("Ipopt (CasADi, exact derivatives)", ipopt.theta, t_ipopt, ipopt.iterations),
        ("SciPy Nelder-Mead (penalty)", nm.x, t_nm, nm.nfev),
        ("SciPy SLSQP (finite differences)", slsqp.x, t_slsqp, slsqp.nfev),
    ]
    print(
        f"{problem.family.name} family ({problem.n_params} parameters), RF leg, from zero; "
        "energies evaluated exactly"
    )
    print(
        f"{'method':38s} {'time [s]':>9s} {'energy [J]':>11s} {'feasible':>9s} "
        f"{'iter/fev':>9s} {'time / Ipopt':>13s}"
    )
    best_scipy = None
    for name, theta, seconds, count in rows:
        e = problem.evaluate(theta)
        energy = exact_energy(problem, theta)
        feasible = e.reason is None
        ratio = seconds / t_ipopt
        print(
            f"{name:38s} {seconds:9.3f} {energy:11.5f} {feasible!s:>9s} {count:9d} {ratio:12.1f}x"
        )
        if (
            name.startswith("SciPy")
            and feasible
            and (best_scipy is None or seconds < best_scipy[1])
        ):
            best_scipy = (name, seconds, energy)
    ipopt_energy = ipopt.swing_energy_j
    if best_scipy:
        name, seconds, energy = best_scipy
        verdict = "equal or better" if ipopt_energy <= energy + 1e-6 else "WORSE"
        print(
            f"fastest feasible SciPy method: {name}, {seconds / t_ipopt:.1f}x Ipopt's time; "
            f"Ipopt's optimum is {verdict} ({ipopt_energy:.5f} J vs {energy:.5f} J)"
        )


if __name__ == "__main__":
    main()
