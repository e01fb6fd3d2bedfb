"""``analyze_log``: the mechanical energy in a cylinder log (the paper's Table 7)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scalf_opt.api.gaits import command_tuple, read_gait
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.io.provenance import provenance
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.robot import Robot
from scalf_opt.robots.loading import load_robot


@dataclass(frozen=True)
class LogResult:
    """The energy in a cylinder log (:class:`scalf_opt.logs.analysis.LogAnalysis`).

    Attributes:
        robot: The robot whose cylinders the log comes from.
        analysis: Per leg and phase, the energies over complete cycles.
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    analysis: Any
    command: tuple[str, ...] | None = None

    @property
    def average_power_w(self) -> float:
        """The robot's mechanical average power [W]."""
        return float(self.analysis.average_power_w)

    def to_dict(self) -> dict[str, Any]:
        """Plain data: what ``analyze-log --json`` prints."""
        return {"provenance": provenance(self.robot, self.command), **self.analysis.as_dict()}


def analyze_log(
    path: str | Path,
    robot: Robot | None = None,
    gait: Gait | None = None,
    *,
    period_s: float | None = None,
    command: Sequence[str] | None = None,
) -> LogResult:
    """The mechanical energy per leg and phase in a cylinder log (the paper's Table 7).

    Args:
        path: The log (CSV: ``t_s,leg,hip_length_m,knee_length_m,hip_force_n,knee_force_n``
            and an optional ``contact``).
        robot: The robot (default: SCalf), for its cylinders and joint limits.
        gait: Its duty cycle and period, where the log does not say (default: the robot's).
        period_s: The gait period [s], over the log's contacts and the gait.
        command: The command line, recorded in the result's provenance.

    Raises:
        LogError: A bad log (the message names the row and the column), or a robot without
            cylinders.
        ConfigError: A period that is not > 0.
    """
    from scalf_opt.logs.analysis import analyze_log as analyze
    from scalf_opt.logs.log_file import read_log

    if period_s is not None and not period_s > 0:
        raise ConfigError(f"the period must be > 0, got {period_s}", field="period_s")
    robot = robot or load_robot("scalf")
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot))
    analysis = analyze(read_log(path), pipeline, period_s)
    return LogResult(robot, analysis, command_tuple(command))
