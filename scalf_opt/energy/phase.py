"""One phase of one leg evaluated numerically: every sample's physics and the phase's energy."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from scalf_opt.energy.physics import LegPhysics, trapezoid_weights
from scalf_opt.types import Accounting, Phase, Space


@dataclass(frozen=True)
class PhaseSamples:
    """The input of one phase: its path samples, foot forces and timing.

    Attributes:
        phase: ``stance`` or ``swing``.
        space: What ``path`` holds: foot positions or joint angles.
        path: Value, first and second time derivative of the path, shape (3, 2, n) [SI].
        grf_n: Ground reaction force on the foot, shape (2, n) [N] (zero in swing).
        t_phase_s: Time since the phase began, shape (n,) [s].
        start_s: Cycle time at which the phase begins [s].
        period_s: Gait period, to wrap cycle times into [0, T] [s].
        unbalanced_nm: Moment the stance feet cannot supply (trunk axes), (3, n) [N m];
            ``None``: zero (:mod:`scalf_opt.energy.loads`).
        grf_lateral_n: The foot force's lateral part F_y, (n,) [N] (loads only the roll joint);
            ``None``: zero.
    """

    phase: Phase
    space: Space
    path: np.ndarray
    grf_n: np.ndarray
    t_phase_s: np.ndarray
    start_s: float
    period_s: float
    unbalanced_nm: np.ndarray | None = None
    grf_lateral_n: np.ndarray | None = None

    @property
    def cycle_times_s(self) -> np.ndarray:
        """Cycle time of each sample [s]; a phase ending at the cycle's end stays at T, not 0."""
        t = np.mod(self.start_s + self.t_phase_s, self.period_s)
        if t.size > 1 and t[-1] < t[-2]:
            t[-1] += self.period_s
        return t


@dataclass(frozen=True)
class PhaseResult:
    """Every sample of one phase of one leg (numeric), plus its energy per joint.

    Array shapes: (2, n) with rows (hip, knee), or (x, z) for ``foot`` and ``grf``; drive outputs
    (``cyl_len_hip``, ...) are (n,).

    Attributes:
        leg: Leg name.
        phase: ``stance`` or ``swing``.
        t_s: Cycle time of each sample [s], shape (n,).
        t_phase_s: Time since the phase began [s], shape (n,).
        values: Arrays by output name (:attr:`LegPhysics.output_names`) plus ``grf`` [SI].
        energy_j: Energy per joint over the phase [J], shape (2,).
        loss_j: The drives' loss part of ``energy_j`` (SCalf: friction heat) [J], shape (2,).
        drive_columns: Drive output name -> column name with unit (``cyl_len_hip`` ->
            ``cyl_len_hip_m``), in column order.
        unbalanced_nm: Moment the stance feet cannot supply at each sample (trunk axes),
            shape (3, n) [N m] (zero in swing, under trunk loads, and with three or more feet).
        grf_lateral_n: Lateral foot force F_y, shape (n,) [N].
    """

    leg: str
    phase: Phase
    t_s: np.ndarray
    t_phase_s: np.ndarray
    values: dict[str, np.ndarray]
    energy_j: np.ndarray
    loss_j: np.ndarray
    drive_columns: dict[str, str]
    unbalanced_nm: np.ndarray = field(default_factory=lambda: np.zeros((3, 0)))
    grf_lateral_n: np.ndarray = field(default_factory=lambda: np.zeros(0))


def evaluate_phase(
    physics: LegPhysics, samples: PhaseSamples, accounting: Accounting = "paper"
) -> PhaseResult:
    """Evaluate one phase numerically through the leg's compiled per-sample function."""
    n = samples.t_phase_s.size
    fn = physics.sample_function(samples.space, accounting).map(n)
    path = samples.path
    out = fn(path[0], path[1], path[2], samples.grf_n)
    values = {
        name: np.array(v) if v.shape[0] > 1 else np.array(v).ravel()
        for name, v in zip(physics.output_names, out, strict=True)
    }
    values["grf"] = np.asarray(samples.grf_n, dtype=float)
    w = trapezoid_weights(samples.t_phase_s)
    return PhaseResult(
        leg=physics.leg.name,
        phase=samples.phase,
        t_s=samples.cycle_times_s,
        t_phase_s=np.asarray(samples.t_phase_s, dtype=float),
        values=values,
        energy_j=values["power"] @ w,
        loss_j=values["p_loss"] @ w,
        drive_columns={o.name: o.column for o in physics.drive_outputs},
        unbalanced_nm=(
            np.zeros((3, n)) if samples.unbalanced_nm is None else samples.unbalanced_nm
        ),
        grf_lateral_n=np.zeros(n) if samples.grf_lateral_n is None else samples.grf_lateral_n,
    )
