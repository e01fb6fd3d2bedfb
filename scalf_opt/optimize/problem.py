"""The swing-optimization problem of one leg, shared by the pattern search and the NLP.

Decision variables: the swing family's free parameters ``theta`` (degrees or centimetres, see
:mod:`scalf_opt.locomotion.swing`). Objective: the leg's swing energy [J] (stance energy does not
depend on the swing). Constraints at every swing sample (decision 14): joint angles inside their
limits, foot at or above the ground, every bounded drive output inside its range (SCalf: the
cylinder inside its stroke), the target inside the leg's reach (foot space), and the foot at
least H above the ground at mid-swing.

The CasADi graph ``theta -> path samples -> per-sample physics`` is built once here. The exact
(non-smooth) energy is a compiled function of ``theta``; the NLP reuses the very same graph with
the smooth friction-heat variant.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cached_property

import casadi as ca
import numpy as np

from scalf_opt.energy.physics import LegPhysics, trapezoid_weights
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.swing.family import AffinePath, SwingFamily
from scalf_opt.types import Expr

FEASIBILITY_TOLERANCE = 1e-9
"""Round-off allowed on every constraint when judging a point feasible [rad, m]."""

HEAT_SMOOTHING_EPS_M_S = 1e-4
"""Velocity scale of the smooth max in the NLP's friction heat [m/s].

It is 70x below the smaller Stribeck velocity (0.007 m/s); the smooth max overestimates
``max(v, 0)`` by at most eps/2, so the heat rate changes by at most ``F_s eps / 2 = 2.5 mW`` per
cylinder: far below the energies compared (the exact energy is what every report prints).
"""


def casadi_name(*parts: str) -> str:
    """A valid CasADi function name from arbitrary parts (letters, digits, single underscores)."""
    name = re.sub(r"[^A-Za-z0-9]+", "_", "_".join(parts)).strip("_")
    return name if name[:1].isalpha() else f"f_{name}"


@dataclass(frozen=True)
class Evaluation:
    """Exact evaluation of one parameter vector.

    Attributes:
        energy_j: Swing energy of both joints [J] (exact, non-smooth); inf if infeasible.
        reason: ``None`` if feasible, else which constraint fails first.
        violation: Sum of every constraint's excess over its bound (metres and radians); zero
            exactly when the point is feasible.
    """

    energy_j: float
    reason: str | None
    violation: float = 0.0


@dataclass
class SwingProblem:
    """One leg's swing optimization over one family.

    Attributes:
        pipeline: The robot's energy pipeline (robot, gait, accounting).
        leg: Leg name.
        family: Swing family.
    """

    pipeline: EnergyPipeline
    leg: str
    family: SwingFamily

    @cached_property
    def path(self) -> AffinePath:
        """The family's affine swing path for this leg."""
        return self.pipeline.swing_path(self.leg, self.family)

    @property
    def physics(self) -> LegPhysics:
        """The leg's physics."""
        return self.pipeline.physics(self.leg)

    @property
    def n_params(self) -> int:
        """Number of free parameters."""
        return self.family.n_params

    @cached_property
    def weights(self) -> np.ndarray:
        """Trapezoidal weights of the swing samples [s]."""
        return trapezoid_weights(self.path.t_s)

    @cached_property
    def joint_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper joint-angle bounds, each (2, 1) [rad]."""
        leg = self.physics.leg
        return leg.lower_limits_rad[:, None], leg.upper_limits_rad[:, None]

    @cached_property
    def output_bounds(self) -> dict[str, tuple[float, float]]:
        """Bounds of drive outputs by output name (``cyl_len_hip``: the stroke) [SI]."""
        leg = self.physics.leg
        lo, hi = leg.lower_limits_rad, leg.upper_limits_rad
        out = {}
        for output in self.physics.drive_outputs:
            bounds = self.physics.drives[output.joint].output_bounds(
                lo[output.joint], hi[output.joint]
            )
            if output.channel.name in bounds:
                out[output.name] = bounds[output.channel.name]
        return out

    @cached_property
    def mid_index(self) -> int:
        """Index of the mid-swing sample (the swing grid has an even number of intervals)."""
        return (self.path.t_s.size - 1) // 2

    @property
    def clearance_z_m(self) -> float:
        """Lowest foot height allowed at mid-swing, in the leg frame [m]: ground + H."""
        return self.ground_z_m + self.pipeline.gait.clearance_m

    @property
    def ground_z_m(self) -> float:
        """Ground height in the leg frame [m]."""
        return -self.pipeline.gait.stance_height_m

    def graph(self, theta: Expr, heat_eps: float | None) -> dict[str, Expr]:
        """Per-sample outputs (2 x n; drive outputs 1 x n) and reach cosines (1 x n) of theta."""
        path = self.path
        n = path.t_s.size
        ys = []
        for d in range(3):
            y = ca.DM(path.base[d])
            if path.n_params:
                rows = [ca.mtimes(ca.DM(path.basis[d, c]), theta).T for c in range(2)]
                y = y + ca.vertcat(*rows)
            ys.append(y)
        physics = self.physics
        fn = physics.sample_function(path.space, self.pipeline.accounting, heat_eps).map(n)
        outs = fn(ys[0], ys[1], ys[2], ca.DM.zeros(2, n))
        result = dict(zip(physics.output_names, outs, strict=True))
        if path.space == "foot":
            result["reach"] = physics.kin.functions["reach"].map(n)(ys[0])
        return result

    @cached_property
    def exact_function(self) -> ca.Function:
        """Compiled ``theta -> (energy, q, foot, reach, bounded drive outputs)``, exact energy."""
        theta = ca.SX.sym("theta", self.n_params)
        g = self.graph(theta, None)
        energy = ca.sum1(ca.mtimes(g["power"], ca.DM(self.weights)))
        reach = g.get("reach", ca.DM.zeros(1, self.path.t_s.size))
        bounded = list(self.output_bounds)
        return ca.Function(
            casadi_name(self.leg, self.family.name, "swing_energy"),
            [theta],
            [energy, g["q"], g["foot"], reach, *(g[name] for name in bounded)],
            ["theta"],
            ["energy", "q", "foot", "reach", *bounded],
        )

    def evaluate(self, theta: np.ndarray) -> Evaluation:
        """Exact swing energy and feasibility of ``theta`` (family units)."""
        energy, q, foot, reach, *outputs = (
            np.array(v) for v in self.exact_function(np.asarray(theta, dtype=float))
        )
        if not np.all(np.isfinite(q)):
            excess = np.abs(reach) - 1.0
            out_of_reach = float(np.sum(excess[excess > 0])) or 1.0  # NaN angles: always > 0
            return Evaluation(float("inf"), "foot target out of reach", out_of_reach)
        lo, hi = self.joint_bounds
        excesses = {
            "joint limit": np.concatenate([(lo - q).ravel(), (q - hi).ravel()]),
            "foot below ground": self.ground_z_m - foot[1],
            "mid-swing clearance": np.array([self.clearance_z_m - foot[1, self.mid_index]]),
        }
        for (name, (b_lo, b_hi)), value in zip(self.output_bounds.items(), outputs, strict=True):
            excesses[f"{name} out of range"] = np.concatenate(
                [(b_lo - value).ravel(), (value - b_hi).ravel()]
            )
        # only what exceeds the tolerance counts, so that feasible <=> violation == 0 exactly
        # (samples that touch a bound, like the feet at lift-off, carry round-off of 1e-16)
        beyond = {
            k: e[e > FEASIBILITY_TOLERANCE] - FEASIBILITY_TOLERANCE for k, e in excesses.items()
        }
        violation = float(sum(np.sum(e) for e in beyond.values()))
        for reason, excess in beyond.items():
            if excess.size:
                return Evaluation(float("inf"), reason, violation)
        return Evaluation(float(energy.item()), None, 0.0)
