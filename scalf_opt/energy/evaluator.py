"""The fast cycle evaluator: every phase of several legs in one call of one compiled function.

Input: one flat vector holding, for each leg and phase, the path samples (value, velocity,
acceleration; foot or joint space) and the ground reaction forces. Output: the energy of each
leg, phase and joint. The function is the per-sample physics of
:class:`~scalf_opt.energy.physics.LegPhysics` mapped over the samples and integrated with the
trapezoidal weights, expanded into one SX graph, reduced by common-subexpression elimination,
compiled to native code
(:func:`~scalf_opt.energy.codegen.compile_function`) and called through CasADi's zero-copy buffers.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from scalf_opt.energy.codegen import compile_function
from scalf_opt.energy.physics import trapezoid_weights
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.types import FIRST_PAIR, PHASES, Space

ROWS_PER_SAMPLE = 8  # y (2), yd (2), ydd (2), ground force (2)


class CycleEvaluator:
    """Energies of the stance and swing phases of ``legs`` from their samples, in one call.

    Args:
        pipeline: Robot, gait and accounting.
        legs: Legs to evaluate (default: the diagonal pair RF, LH).
        swing_space: ``foot`` or ``joint``: the space of the swing samples.
        compiled: Compile to native code (else CasADi's virtual machine; same numbers).
    """

    def __init__(
        self,
        pipeline: EnergyPipeline,
        legs: tuple[str, ...] = FIRST_PAIR,
        swing_space: Space = "foot",
        compiled: bool = True,
    ) -> None:
        self.pipeline = pipeline
        self.legs = legs
        self.swing_space = swing_space
        gait = pipeline.gait
        self.t_phase_s = {phase: gait.phase_times_s(phase) for phase in PHASES}
        blocks, energies = [], []
        for leg in legs:
            physics = pipeline.physics(leg)
            for phase in PHASES:
                space: Space = "foot" if phase == "stance" else swing_space
                n = self.t_phase_s[phase].size
                x = ca.SX.sym(f"{leg}_{phase}", ROWS_PER_SAMPLE, n)
                fn = physics.sample_function(space, pipeline.accounting).map(n)
                out = fn(x[0:2, :], x[2:4, :], x[4:6, :], x[6:8, :])
                power = out[physics.output_names.index("power")]
                weights = ca.DM(trapezoid_weights(self.t_phase_s[phase]))
                energies.append(ca.mtimes(power, weights))
                blocks.append(ca.vec(x))
        flat = ca.vertcat(*blocks)
        self.function = ca.Function(
            f"cycle_energy_{'_'.join(legs)}_{swing_space}",
            [flat],
            [ca.cse(ca.vertcat(*energies))],
            ["samples"],
            ["energy"],
        )
        if compiled:
            self.function = compile_function(self.function)
        self._input = np.zeros(flat.numel())
        self._output = np.zeros(2 * len(energies))
        self._buffer, self._eval = self.function.buffer()
        # zero-copy: CasADi reads and writes these arrays' memory directly (the Python binding
        # takes the size from the buffer, unlike the type stubs' signature)
        self._buffer.set_arg(0, memoryview(self._input))  # type: ignore[call-arg, arg-type]
        self._buffer.set_res(0, memoryview(self._output))  # type: ignore[call-arg, arg-type]

    def pack(self, phases: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
        """Flat input from ``{(leg, phase): (samples (3, 2, n), grf (2, n))}``."""
        parts = []
        for leg in self.legs:
            for phase in PHASES:
                samples, grf = phases[(leg, phase)]
                block = np.vstack([samples[0], samples[1], samples[2], grf])
                parts.append(block.ravel(order="F"))
        return np.concatenate(parts)

    def inputs(
        self, family: SwingFamily, thetas: dict[str, np.ndarray] | None = None
    ) -> np.ndarray:
        """Flat input for the pipeline's stance and a swing family's members (default theta = 0)."""
        if family.space != self.swing_space:
            raise ValueError(
                f"family {family.name} is in {family.space} space, not {self.swing_space}"
            )
        pipeline = self.pipeline
        phases = {}
        swings = pipeline.swings(family, thetas)
        for leg in self.legs:
            forces = pipeline.stance_forces(leg, swings).sagittal_n
            phases[(leg, "stance")] = (pipeline.stance_paths[leg], forces)
            path = pipeline.swing_path(leg, family)
            theta = (thetas or {}).get(leg)
            phases[(leg, "swing")] = (path.values(theta), np.zeros((2, path.t_s.size)))
        return self.pack(phases)

    def __call__(self, flat: np.ndarray) -> np.ndarray:
        """Energy [J] per leg, phase (stance, swing) and joint (hip, knee): shape (legs, 2, 2)."""
        np.copyto(self._input, flat)
        self._eval()
        return self._output.reshape(len(self.legs), 2, 2).copy()
