"""``evaluate``: the energy of the reference swing, or of a saved optimum, on every leg."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scalf_opt.api.gaits import as_robot, command_tuple, read_gait
from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.energy.peaks import CycleViolation, Peak, cycle_peaks, cycle_violations
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.energy.swings import planned_cycle
from scalf_opt.files import write_atomic
from scalf_opt.io.provenance import provenance
from scalf_opt.io.results import checked_summary, samples_csv_text, write_results_json
from scalf_opt.io.saved import SavedSwings, read_saved_swings
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.types import Accounting


@dataclass(frozen=True)
class EvaluationResult:
    """The energy of one swing trajectory on every leg over a gait cycle.

    Attributes:
        robot: The robot.
        pipeline: Robot, gait and accounting it was evaluated with.
        cycle: Per leg and phase: samples, energies; robot totals.
        swing: The saved optimum evaluated (``None``: the reference swing).
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    pipeline: EnergyPipeline
    cycle: RobotCycle
    swing: SavedSwings | None = None
    command: tuple[str, ...] | None = None

    @property
    def energy_j(self) -> float:
        """Energy of all legs per cycle [J]."""
        return self.cycle.energy_j

    @property
    def average_power_w(self) -> float:
        """Average total leg power [W]."""
        return self.cycle.average_power_w

    @property
    def cost_of_transport(self) -> float:
        """Dimensionless cost of transport."""
        return self.cycle.cost_of_transport

    @property
    def peaks(self) -> list[Peak]:
        """Peak torque, speed, drive outputs and power per leg and joint."""
        return cycle_peaks(self.cycle, self._physics())

    @property
    def violations(self) -> list[CycleViolation]:
        """Every limit a sample exceeds (none for a trajectory the optimizers found)."""
        return cycle_violations(self.cycle, self._physics())

    def _physics(self) -> dict[str, Any]:
        return {leg: self.pipeline.physics(leg) for leg in self.cycle.legs}

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``summary.json``."""
        data = {
            "provenance": provenance(self.robot, self.command),
            **checked_summary(self.cycle, self.pipeline),
        }
        if self.swing is not None:
            data["swing_file"] = str(self.swing.source)
        return data

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``summary.json`` and ``samples.csv`` into ``out_dir`` (atomically)."""
        out = Path(out_dir)
        return [
            *write_results_json(out / "summary.json", self.to_dict()),
            write_atomic(out / "samples.csv", samples_csv_text(self.cycle)),
        ]


def evaluate(
    robot: str | Robot,
    gait: Gait | None = None,
    *,
    accounting: Accounting = "paper",
    swing: str | Path | None = None,
    command: Sequence[str] | None = None,
    loads: str | None = None,
) -> EvaluationResult:
    """Energy of the reference swing, or of a saved optimum, on every leg.

    Args:
        robot: The robot (:func:`load_robot`).
        gait: The gait (default: the robot's default trot; with ``swing``, the optimum's).
        accounting: ``paper`` (``|tau qd|`` + drive losses), ``positive`` or ``regenerative``.
        swing: A ``summary.json`` written by ``optimize`` (or its folder): its swings are
            evaluated instead of the reference, under any rate and accounting; the gait's timing
            and stance must be the file's.
        command: The command line, recorded in the result's provenance.
        loads: The stance load model (a name in :data:`~scalf_opt.energy.loads.LOAD_MODELS`);
            ``None``: the saved optimum's, else ``whole-body``.

    Raises:
        ConfigError: The file is not an optimum of this robot, or the timing differs.
    """
    robot = as_robot(robot)
    saved = None
    if swing is not None:
        saved = read_saved_swings(swing)
        saved.require_optimum()
        saved.check_robot(robot)
        gait = gait or saved.gait
        saved.check_timing(gait)
    if loads is None:
        loads = saved.loads if saved is not None else DEFAULT_LOADS
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot), accounting, loads=loads)
    if saved is None:
        cycle = pipeline.robot_cycle(make_family("reference"))
    else:
        cycle = planned_cycle(pipeline, saved.require_all_legs())
    return EvaluationResult(robot, pipeline, cycle, saved, command_tuple(command))
