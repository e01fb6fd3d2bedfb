"""A 3-D whole-body plan replayed in the world over a few cycles: what ``view --from DIR`` shows.

World frame: the plan's own (x forward, y left, z up, the ground at z = 0), shifted along y by the
walk's lateral offset. At walk time ``t`` the trunk and every joint are the plan's periodic cubic
spline at ``t mod T`` (:meth:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan.states_at`), the
trunk's x one stride further per cycle walked: the trunk's world pose is its position and
``R = R_z(yaw) R_y(pitch) R_x(roll)``, every joint of the URDF (abduction included) is the plan's.
Every foot position is Pinocchio's forward kinematics of those same poses, so the drawn foot paths
are where the animated feet go. A leg's power along its path is the sum of its joints' charged
power (the plan's accounting, drive losses included) from the plan's own dynamics at each sample
(:meth:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan.node_outputs` of the plan read densely, as
``export`` reads it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pinocchio as pin

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.io.whole_body_dense import dense_plan, samples_per_interval
from scalf_opt.io.whole_body_export import SavedCycle, saved_plan, summary_number
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES, Accounting
from scalf_opt.viz.colors import trajectory_color
from scalf_opt.viz.scene import (
    LegendEntry,
    Scene,
    SceneOptions,
    compose_scene,
    lateral_spacing_m,
    robot_looks,
)
from scalf_opt.viz.visuals import Visual
from scalf_opt.viz.walk import FootPath

PATH_RATE_HZ = 500.0
"""Samples per second of the drawn foot paths, about (a whole number per node interval, so that
every touch-down and lift-off is a sample) [Hz]."""

POWER_NOTE = "all its joints, losses included"
"""What a leg's power sums in the 3-D view, in the legend's words."""


@dataclass(frozen=True)
class WholeBodyWalk:
    """A 3-D whole-body plan walked ``n_cycles`` times (a :class:`~scalf_opt.viz.walk.Walker`).

    Attributes:
        plan: The plan walked.
        accounting: The power accounting its energies were charged with.
        n_cycles: Number of cycles.
        lateral_offset_m: Added to the plan's world y [m] (to set robots side by side).
        path_rate_hz: About how many foot-path samples per second [Hz].
    """

    plan: WholeBodyPlan
    accounting: Accounting
    n_cycles: int = 3
    lateral_offset_m: float = 0.0
    path_rate_hz: float = PATH_RATE_HZ

    @property
    def robot(self) -> Robot:
        """The robot of the plan's 3-D model."""
        return self.plan.physics.robot

    @property
    def duration_s(self) -> float:
        """Length of the walk [s]."""
        return self.n_cycles * self.plan.schedule.period_s

    @property
    def x_range_m(self) -> tuple[float, float]:
        """The trunk's world x at the walk's start and end [m] (one stride further per cycle)."""
        start = float(self.plan.x[0, 0])
        return start, start + self.n_cycles * self.plan.stride_m

    @cached_property
    def trunk_height_m(self) -> float:
        """The trunk frame's mean height over the plan's nodes [m]."""
        return float(np.mean(self.plan.x[2]))

    @property
    def stance_height_m(self) -> float:
        """The pitching hips' mean height above the ground, the trunk level [m]."""
        hips = [self.robot.leg(leg).hip_origin_m[2] for leg in LEG_NAMES]
        return self.trunk_height_m + float(np.mean(hips))

    def coordinates(self, t_s: np.ndarray) -> np.ndarray:
        """The plan's coordinates ``X`` at walk times ``t_s``, world frame, shape (nx, n).

        The spline at ``t mod T``; each cycle begun adds one stride to the trunk's x; the lateral
        offset is added to its y [m, rad].
        """
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        period = self.plan.schedule.period_s
        cycles = np.floor(t / period)
        x = self.plan.states_at(np.clip(t - cycles * period, 0.0, None))[0]
        x[0] = x[0] + cycles * self.plan.stride_m
        x[1] = x[1] + self.lateral_offset_m
        return x

    def trunk_pose(self, t_s: np.ndarray) -> np.ndarray:
        """World from trunk frame at walk times ``t_s``, shape (n, 4, 4) [m].

        Rotation ``R = R_z(yaw) R_y(pitch) R_x(roll)`` of the plan's roll, pitch and yaw.
        """
        x = self.coordinates(t_s)
        out = np.tile(np.eye(4), (x.shape[1], 1, 1))
        for k in range(x.shape[1]):
            out[k, :3, :3] = pin.rpy.rpyToMatrix(x[3, k], x[4, k], x[5, k])
        out[:, :3, 3] = x[:3].T
        return out

    @cached_property
    def _joint_index(self) -> np.ndarray:
        """Where each of the plan's joints sits in ``robot.model``'s configuration."""
        model = self.robot.model
        return np.array(
            [model.joints[model.getJointId(name)].idx_q for name in self.plan.physics.joint_names]
        )

    def configurations(self, t_s: np.ndarray) -> np.ndarray:
        """``robot.model``'s configuration at walk times ``t_s``: every joint the plan's (n, nq)."""
        x = self.coordinates(t_s)
        q = np.tile(pin.neutral(self.robot.model), (x.shape[1], 1))
        q[:, self._joint_index] = x[6:].T
        return q

    def feet_m(self, t_s: np.ndarray) -> np.ndarray:
        """The feet's world positions at walk times ``t_s`` (n, 4, 3) [m].

        Legs in :data:`~scalf_opt.types.LEG_NAMES` order; Pinocchio's forward kinematics of the
        animated poses (:meth:`trunk_pose`, :meth:`configurations`).
        """
        model = self.robot.model
        data = model.createData()
        frames = [model.getFrameId(self.robot.leg(leg).foot_frame) for leg in LEG_NAMES]
        q, trunk = self.configurations(t_s), self.trunk_pose(t_s)
        out = np.empty((q.shape[0], len(frames), 3))
        for k in range(q.shape[0]):
            pin.framesForwardKinematics(model, data, q[k])
            for i, frame in enumerate(frames):
                out[k, i] = trunk[k, :3, :3] @ data.oMf[frame].translation + trunk[k, :3, 3]
        return out

    def foot_paths(self) -> dict[str, FootPath]:
        """Every leg's foot over the walk, a whole number of samples per node interval.

        The walk's last instant closes each path. Power: the sum of the leg's joints' charged
        power [W]; swing: the schedule's swing nodes and the touch-down and lift-off that end them.
        """
        plan = self.plan
        per = samples_per_interval(plan, self.path_rate_hz)
        dense = dense_plan(plan, per)
        n = dense.schedule.intervals
        charged = dense.node_outputs(self.accounting)["charged"]
        legs = np.asarray(plan.physics.joint_legs)
        stance = dense.schedule.stance
        swing = ~stance | np.roll(~stance, 1, axis=1) | np.roll(~stance, -1, axis=1)
        index = np.arange(self.n_cycles * n + 1) % n  # each sample's node in the dense cycle
        times = np.arange(self.n_cycles * n + 1) * dense.schedule.step_s
        feet = self.feet_m(times)
        return {
            leg: FootPath(
                t_s=times,
                position_m=feet[:, i],
                power_w=charged[legs == i].sum(axis=0)[index],
                swing=swing[i, index],
            )
            for i, leg in enumerate(LEG_NAMES)
        }


@dataclass(frozen=True)
class ShownPlan:
    """A 3-D plan to show, and what its run reported about it.

    Attributes:
        label: What the legend calls it.
        plan: The plan.
        accounting: The power accounting it was charged with.
        energy_j: Energy per cycle as its run reported it [J] (``summary.json``; NaN if not).
        cost_of_transport: Its cost of transport as reported (NaN if not).
        leg_energy_j: Each leg's energy per cycle as reported [J] (empty if not).
        headline: Its folder, robot, period, speed and energy in one line (empty if not saved).
    """

    label: str
    plan: WholeBodyPlan
    accounting: Accounting
    energy_j: float
    cost_of_transport: float
    leg_energy_j: dict[str, float]
    headline: str = ""

    @classmethod
    def of(cls, saved: SavedCycle, physics: WholeBodyPhysics) -> ShownPlan:
        """A saved cycle's plan and the numbers its ``summary.json`` reports (none recomputed).

        The plan is :func:`~scalf_opt.io.whole_body_export.saved_plan`'s.

        Raises:
            ConfigError: What :func:`~scalf_opt.io.whole_body_export.saved_plan` raises.
        """
        summary = saved.summary
        legs = summary.get("leg_energy_per_cycle_j")
        return cls(
            label=saved.directory.name or str(saved.directory),
            plan=saved_plan(saved, physics),
            accounting=summary.get("accounting", "paper"),
            energy_j=summary_number(summary.get("energy_per_cycle_j")),
            cost_of_transport=summary_number(summary.get("cost_of_transport")),
            leg_energy_j=(
                {leg: summary_number(legs.get(leg)) for leg in LEG_NAMES if leg in legs}
                if isinstance(legs, dict)
                else {}
            ),
            headline=saved.headline,
        )

    @property
    def words(self) -> str:
        """The plan's period, duty, speed and accounting in a few words."""
        schedule = self.plan.schedule
        return (
            f"3-D plan: T = {schedule.period_s:.4g} s, duty {schedule.duty_cycle:.4g}, "
            f"{self.plan.speed_m_s:.3g} m/s, accounting '{self.accounting}', "
            f"{schedule.intervals} nodes"
        )


def build_plan_scene(
    shown: Sequence[ShownPlan],
    options: SceneOptions | None = None,
    loaded: tuple[list[Visual], list[str]] | None = None,
) -> Scene:
    """The scene of 3-D plans, side by side, each walked ``options.n_cycles`` times.

    ``loaded``: the first plan's robot's :func:`~scalf_opt.viz.visuals.load_visuals`, when loaded
    already.

    Raises:
        ModelError: A robot's visual geometry cannot be loaded.
        ConfigError: No plan, or bad options.
    """
    from scalf_opt.errors import ConfigError

    opts = options or SceneOptions()
    if not shown:
        raise ConfigError("nothing to show: give at least one 3-D plan")
    robots = [s.plan.physics.robot for s in shown]
    visuals, skipped = robot_looks(robots[0], robots, loaded)
    spacing = max(lateral_spacing_m(robot) for robot in robots)
    walks = [
        WholeBodyWalk(s.plan, s.accounting, opts.n_cycles, lateral_offset_m=i * spacing)
        for i, s in enumerate(shown)
    ]
    legend = [
        LegendEntry(
            label=s.label,
            color=trajectory_color(i),
            energy_j=s.energy_j,
            average_power_w=s.energy_j / s.plan.schedule.period_s,
            leg_energy_j=s.leg_energy_j,
            lateral_offset_m=walk.lateral_offset_m,
            energy_model=s.words,
            leg_energy_kind="per leg",
        )
        for i, (s, walk) in enumerate(zip(shown, walks, strict=True))
    ]
    first = shown[0].plan
    names = " beside ".join(dict.fromkeys(robot.name for robot in robots))
    title = (
        f"{names}: 3-D whole-body trot T = {first.schedule.period_s:.4g} s, duty "
        f"{first.schedule.duty_cycle:.4g}, stride {first.stride_m:.4g} m, "
        f"{first.speed_m_s:.3g} m/s"
        if len(shown) == 1
        else f"{names}: {len(shown)} 3-D whole-body trots"
    )
    return compose_scene(walks, visuals, legend, title, opts, skipped, POWER_NOTE)
