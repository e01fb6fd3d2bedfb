"""Where the optimizers start: the default start, the member closest to a path, more starts.

* The **default start** (the first of ``--starts N``), where the solver says
  (:meth:`~scalf_opt.optimize.solvers.SwingSolver.default_start`): zero parameters, or the
  member closest to the reference swing.
* The **member closest to a path**: the least-squares fit of the family's affine samples to the
  path's value, rate and acceleration, weighted by ``T_sw`` and ``T_sw^2`` so that the three are
  comparable (a dimensionless fit in the family's space: joint angles or foot position). The
  fit is a truncated SVD (:data:`FIT_RCOND`): directions ten thousand times weaker than the
  strongest stay at zero. The Fourier families' modes never reach that (their fit's condition
  number is 1.5e3 on ``joint-12``, from the rates and accelerations of the higher modes): their
  fit is the exact one. A basis of cancelling terms would: ``joint-12``'s coefficients, whose
  plain fit of the reference needed 27,000 degrees, kept below 7 degrees truncated.
* **More starts**: the member closest to the reference (if it was not the first), then that
  member plus deterministic pseudo-random offsets (standard deviation :data:`START_SPREAD`
  parameter units, seeded by the start's number; halved until a foot-space start is inside the
  reach), so that ``--starts N`` gives the same answer on every run and machine.
"""

from __future__ import annotations

import numpy as np

from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solvers import SwingSolver

FIT_RCOND = 1e-4
"""Relative singular-value cutoff of the least-squares fit of a path."""

START_SPREAD = 5.0
"""Standard deviation of the random offsets of extra starts, in parameter units (deg or cm)."""


def closest_member(problem: SwingProblem, path: np.ndarray) -> np.ndarray:
    """The family member whose samples are closest to ``path`` (least squares), family units.

    Args:
        problem: The problem (family, leg, sample grid).
        path: Samples of the path to fit, shape (3, 2, n) in the family's space (value, rate,
            acceleration; SI).
    """
    if problem.n_params == 0:
        return np.zeros(0)
    duration = problem.pipeline.gait.swing_duration_s
    scale = np.array([1.0, duration, duration**2])[:, None, None]
    target = ((path - problem.path.base) * scale).reshape(-1)
    if not problem.path.sparse:
        design = (problem.path.basis * scale[..., None]).reshape(-1, problem.n_params)
        theta, *_ = np.linalg.lstsq(design, target, rcond=FIT_RCOND)
        return theta
    # a sparse basis (B-splines, each parameter with its own short support: well conditioned):
    # the normal equations, a banded system solved sparse
    from scipy.sparse import csc_array, diags_array
    from scipy.sparse.linalg import spsolve

    rows = np.broadcast_to(scale, problem.path.base.shape).reshape(-1)
    design = diags_array(rows) @ problem.path.basis_rows()
    return np.asarray(spsolve(csc_array(design.T @ design), design.T @ target), dtype=float)


def reference_path(problem: SwingProblem) -> np.ndarray:
    """The reference swing's samples in the family's space, shape (3, 2, n)."""
    foot = problem.pipeline.swing_path(problem.leg, make_family("reference")).values()
    if problem.family.space == "foot":
        return foot
    q, qd, qdd = problem.pipeline.kinematics(problem.leg).joint_motion(foot[0], foot[1], foot[2])
    return np.array([q, qd, qdd])


def closest_to_reference(problem: SwingProblem) -> np.ndarray:
    """The member closest to the reference swing (family units)."""
    return closest_member(problem, reference_path(problem))


def default_start(problem: SwingProblem, solver: SwingSolver) -> tuple[str, np.ndarray]:
    """The first start: ``(label, theta)``, where the solver says."""
    if solver.default_start(problem) == "closest to the reference":
        return "closest to the reference", closest_to_reference(problem)
    return "zero", np.zeros(problem.n_params)


def starts(problem: SwingProblem, solver: SwingSolver, count: int) -> list[tuple[str, np.ndarray]]:
    """``count`` deterministic starts ``(label, theta)``; the first is :func:`default_start`."""
    out = [default_start(problem, solver)]
    closest = closest_to_reference(problem) if count > 1 else None
    if closest is not None and out[0][0] != "closest to the reference":
        out.append(("closest to the reference", closest))
    seed = 1
    while len(out) < count:
        assert closest is not None
        rng = np.random.default_rng(seed)
        offset = START_SPREAD * rng.standard_normal(problem.n_params)
        # a foot-space start must be inside the reach (an IK beyond it has no joint angles for
        # Ipopt to start from): halve the offset until it is
        for _ in range(20):
            if np.all(np.isfinite(problem.outputs(closest + offset)["c"])):
                break
            offset = offset / 2
        out.append((f"closest + random offset (seed {seed})", closest + offset))
        seed += 1
    return out[:count]
