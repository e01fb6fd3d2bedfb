"""``analyze_log``: the mechanical energy in a cylinder log (the paper's Table 7)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from scalf_opt.api.gaits import as_robot, command_tuple, read_gait
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.io.provenance import provenance
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.robot import Robot


@dataclass(frozen=True)
class LogResult:
    """The energy in a cylinder log (:class:`scalf_opt.logs.analysis.LogAnalysis`).

    Attributes:
        robot: The robot whose cylinders the log comes from.
        analysis: Per leg and phase, the energies over complete cycles.
        command: The command line that asked for it (``None`` from Python).
        measured: The power series and the velocity's source
            (:class:`scalf_opt.logs.measured.MeasuredAnalysis`).
        plan: The plan the log is compared with (:class:`scalf_opt.logs.measured.PlanComparison`),
            or ``None``.
        joint_log: The log held joints of a robot without cylinders: its mechanical energy is
            ``sum |tau qd|`` and its ``friction_heat_j`` what the drives draw beyond it.
        metered: The cylinders meter their own input power (valve-controlled, HyQ's): their
            ``friction_heat_j`` is what they draw beyond ``sum |F v|``, not a friction heat.
    """

    robot: Robot
    analysis: Any
    command: tuple[str, ...] | None = None
    measured: Any = None
    plan: Any = None
    joint_log: bool = False
    metered: bool = False

    @property
    def report_kind(self) -> str:
        """The words of its report: ``joint``, ``metered cylinder`` or ``cylinder``."""
        if self.joint_log:
            return "joint"
        return "metered cylinder" if self.metered else "cylinder"

    @property
    def average_power_w(self) -> float:
        """The robot's mechanical average power [W]."""
        return float(self.analysis.average_power_w)

    def to_dict(self) -> dict[str, Any]:
        """Plain data: what ``analyze-log --json`` prints."""
        data = {"provenance": provenance(self.robot, self.command), **self.analysis.as_dict()}
        if self.measured is not None:
            data["velocity_source"] = self.measured.velocity_source
            if self.measured.velocity_source == "measured":
                data["filter"] = None  # the log's own velocities: nothing was filtered
        data["log_kind"] = "joint" if self.joint_log else "cylinder"
        # the cylinders draw supply pressure x flow: friction_heat_per_cycle_j is that beyond |F v|
        data["drives_meter_their_power"] = self.metered
        if self.plan is not None:
            data["plan_comparison"] = self.plan.compare(self.analysis)
        return data

    def write_figure(self, path: str | Path) -> Path:
        """Write the measured against the planned power over one cycle (PNG, atomically).

        Raises:
            ConfigError: The result has no plan to compare with.
        """
        from scalf_opt.viz.figures import save_atomic
        from scalf_opt.viz.log_figure import log_plan_figure

        if self.plan is None or self.measured is None:
            raise ConfigError("a figure of the log against the plan needs the plan (--plan DIR)")
        t, power = self.measured.folded_power_w()
        comparison = self.plan.compare(self.analysis)
        legs = comparison["legs"]
        title = (
            f"{self.analysis.source} against the plan {self.plan.source}: "
            f"{comparison['measured_average_power_w']:.1f} W measured, "
            f"{comparison['planned_average_power_w']:.1f} W planned "
            f"({comparison['change_percent']:+.2f} %)"
        )
        figure = log_plan_figure(
            t,
            power,
            self.plan.t_s,
            self.plan.power_w,
            {leg: v["measured_j"] for leg, v in legs.items()},
            {leg: v["planned_j"] for leg, v in legs.items()},
            title,
        )
        return save_atomic(figure, Path(path))


def analyze_log(
    path: str | Path,
    robot: str | Robot | None = None,
    gait: Gait | None = None,
    *,
    period_s: float | None = None,
    command: Sequence[str] | None = None,
    topic: str | None = None,
    joint_names: Mapping[str, str] | None = None,
    signals: str | None = None,
    plan: str | Path | None = None,
) -> LogResult:
    """The mechanical energy per leg and phase in a cylinder log (the paper's Table 7).

    Args:
        path: The log: the cylinder CSV (``t_s,leg,hip_length_m,knee_length_m,hip_force_n,
            knee_force_n`` and an optional ``contact``), the CSV of ``export``, or a ROS 2 bag
            (``.mcap``, ``.db3`` or a bag folder; extra ``ros``).
        robot: The robot (default: SCalf), for its cylinders and joint limits.
        gait: Its duty cycle and period, where the log does not say (default: the robot's).
        period_s: The gait period [s], over the log's contacts and the gait.
        command: The command line, recorded in the result's provenance.
        topic: A bag's topic of ``sensor_msgs/JointState`` messages (joints or cylinders;
            default: the bag's only one).
        joint_names: A bag's joint name -> the URDF joint name (default: the URDF's names).
        signals: ``joints`` or ``cylinders``: what the topic holds (default: by its names).
        plan: A directory with the ``summary.json`` of the optimum the robot ran: its gait is
            the analysis's, and its energies and power are compared with the log's.

    Without contact (a bag) and without ``period_s``, the period is the motion's own
    (:func:`scalf_opt.logs.measured.motion_period_s`); where the log has the cylinder speeds
    (a bag's velocities, the export's speed columns), they are used as measured.

    Raises:
        LogError: A bad log (the message names the row and the column, or the topic and the
            message), or a robot without cylinders.
        ConfigError: A period that is not > 0, a gait given with a plan, a bad plan.
    """
    from scalf_opt.io.ros_bag import is_bag
    from scalf_opt.logs.bag_log import read_any_log
    from scalf_opt.logs.joint_log import JointLog, analyze_joint_log
    from scalf_opt.logs.measured import MeasuredAnalysis, analyze_measured

    if period_s is not None and not period_s > 0:
        raise ConfigError(f"the period must be > 0, got {period_s}", field="period_s")
    if signals is not None and signals not in ("joints", "cylinders"):
        raise ConfigError(f"signals must be joints or cylinders, got {signals!r}", field="signals")
    robot = as_robot(robot)
    comparison = None
    if plan is not None:
        from scalf_opt.io.plan_export import export_plan, plan_rate_hz
        from scalf_opt.io.saved import read_saved_swings
        from scalf_opt.logs.measured import plan_comparison

        if gait is not None:
            raise ConfigError("the gait comes with the plan's summary.json: give one", field="gait")
        saved = read_saved_swings(plan)
        saved.require_all_legs()
        gait = saved.gait
        comparison = plan_comparison(export_plan(robot, saved, plan_rate_hz(gait)))
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot))
    log = read_any_log(path, pipeline, topic, signals, joint_names)  # type: ignore[arg-type]
    if isinstance(log, JointLog):
        analysis, power, source = analyze_joint_log(log, pipeline, period_s)
        measured = MeasuredAnalysis(analysis, source, power)
    elif not is_bag(path) and period_s is None and not log.has_contact:
        period_s = pipeline.gait.period_s  # a CSV without contact: the gait's, as ever
        measured = analyze_measured(log, pipeline, period_s)
        analysis = replace(measured.analysis, period_source="gait")
        measured = replace(measured, analysis=analysis)
    else:
        measured = analyze_measured(log, pipeline, period_s)
    drives = pipeline.robot_physics.drives
    metered = any(not drive.charges_joint_power for drive in drives.values())
    return LogResult(
        robot,
        measured.analysis,
        command_tuple(command),
        measured,
        comparison,
        isinstance(log, JointLog),
        metered and not isinstance(log, JointLog),
    )
