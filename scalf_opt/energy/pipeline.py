"""The energy pipeline of one robot and gait: every leg's physics, stance and swing, the cycle.

Each leg is computed directly with its own Pinocchio model and its own stance forces; the paper's
symmetry argument (LF repeats RF, RH repeats LH half a cycle later) is then a check, not an input.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np

from scalf_opt.actuators.drive import Drive
from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.cycle import LegCycle, RobotCycle
from scalf_opt.energy.loads import (
    DEFAULT_LOADS,
    StanceDistribution,
    StanceForces,
    StanceLoads,
    Swings,
    stance_distribution,
    stance_loads,
)
from scalf_opt.energy.phase import PhaseResult, PhaseSamples, evaluate_phase
from scalf_opt.energy.physics import LegPhysics
from scalf_opt.energy.robot_physics import RobotPhysics
from scalf_opt.energy.workspace import check_workspace
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.stance import stance_forces, stance_path
from scalf_opt.locomotion.swing.family import AffinePath, SwingFamily
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.locomotion.trot import SYMMETRIC_TWIN, stance_start_s, swing_start_s
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES, Accounting


@dataclass
class GaitCaches:
    """What the pipelines of one gait compute once and share.

    The pipelines derived from one another for the same gait (:meth:`EnergyPipeline.with_loads`,
    :meth:`~EnergyPipeline.with_accounting`, :meth:`~EnergyPipeline.with_gait` with an equal
    gait) hold the same instance: the data half's caches, apart from the robot's physics.

    Attributes:
        distributions: How the stance feet share a wrench, by (gait, loads, leg)
            (:func:`~scalf_opt.energy.loads.stance_distribution`).
    """

    distributions: dict[tuple[Gait, str, str], StanceDistribution] = field(default_factory=dict)


@dataclass(frozen=True)
class EnergyPipeline:
    """Evaluates cycles of one robot for one gait and accounting (the data half of model/data).

    The robot's physics (:class:`~scalf_opt.energy.robot_physics.RobotPhysics`) is built once
    and shared by every pipeline made from this one with :meth:`with_gait` or
    :meth:`with_accounting`; the pipeline itself holds the gait's stance paths and forces.

    Attributes:
        robot: The robot.
        gait: The gait.
        accounting: Power accounting (a name in
            :data:`~scalf_opt.energy.accounting.ACCOUNTINGS`).
        drives: Drives keyed by joint name; ``None`` reads the sidecar beside the URDF, ``{}``
            gives every joint an ideal drive (the drives in use: ``robot_physics.drives``).
        model: The robot's physics to share; ``None`` builds it from ``robot`` and ``drives``.
        loads: What the stance feet carry (a name in
            :data:`~scalf_opt.energy.loads.LOAD_MODELS`): the whole robot's dynamics (default)
            or the trunk's weight only (the paper's).
    """

    robot: Robot
    gait: Gait
    accounting: Accounting = "paper"
    drives: Mapping[str, Drive] | None = None
    model: RobotPhysics | None = field(default=None, repr=False, compare=False)
    loads: str = DEFAULT_LOADS
    caches: GaitCaches = field(default_factory=GaitCaches, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.gait, Gait):  # a user's dict of fields, say: name the remedy
            raise ConfigError(
                f"gait must be a Gait (read_gait(robot=..., **fields) builds one), got "
                f"{type(self.gait).__name__}",
                field="gait",
            )
        power_accounting(self.accounting)
        stance_loads(self.loads)
        self.robot_physics  # noqa: B018 (an invalid actuator file is told here, not on first use)

    @cached_property
    def robot_physics(self) -> RobotPhysics:
        """The robot's physics, shared by every gait and accounting."""
        return self.model or RobotPhysics.build(self.robot, self.drives)

    def __reduce__(self) -> tuple[type[EnergyPipeline], tuple[Any, ...]]:
        """Pickled as its inputs.

        Where it is unpickled (a worker process) the robot's physics is built again, its
        compiled functions loaded from the compile cache.
        """
        drives = dict(self.robot_physics.drives)
        return (EnergyPipeline, (self.robot, self.gait, self.accounting, drives, None, self.loads))

    def _derived(self, **changes: Any) -> EnergyPipeline:
        """``changes`` applied; the robot's physics shared, the caches too if the gait stays."""
        same_gait = changes.get("gait", self.gait) == self.gait
        caches = self.caches if same_gait else GaitCaches()
        return replace(self, model=self.robot_physics, caches=caches, **changes)

    def with_gait(self, gait: Gait) -> EnergyPipeline:
        """The same robot physics and accounting with another gait (or rate)."""
        return self._derived(gait=gait)

    def with_loads(self, loads: str) -> EnergyPipeline:
        """The same robot physics, gait and accounting with another load model."""
        return self._derived(loads=loads)

    @property
    def load_model(self) -> StanceLoads:
        """The load model (:mod:`scalf_opt.energy.loads`)."""
        return stance_loads(self.loads)

    def with_accounting(self, accounting: Accounting) -> EnergyPipeline:
        """The same robot physics and gait with another accounting."""
        return self._derived(accounting=accounting)

    def physics(self, leg: str) -> LegPhysics:
        """The leg's :class:`LegPhysics` (built once per robot)."""
        return self.robot_physics.leg(leg)

    def kinematics(self, leg: str) -> LegKinematics:
        """The leg's kinematics."""
        return self.physics(leg).kin

    # --- stance -------------------------------------------------------------------------------
    @cached_property
    def stance_times_s(self) -> np.ndarray:
        """The stance grid: time since touch-down of each sample, shape (n,) [s]."""
        return self.gait.phase_times_s("stance")

    @cached_property
    def stance_paths(self) -> dict[str, np.ndarray]:
        """Each leg's stance foot samples (3, 2, n) in its leg frame."""
        return {leg: stance_path(self.gait, self.stance_times_s, leg) for leg in LEG_NAMES}

    @cached_property
    def trunk_stance_forces(self) -> dict[str, np.ndarray]:
        """The trunk-only load on each leg's foot over its stance samples, (2, n) [N].

        The paper's sagittal minimum-norm share of the trunk link's weight (decision 11).
        """
        com = self.robot.trunk_com_m
        hips = {}
        for leg in LEG_NAMES:
            hip = self.robot.leg(leg).hip_origin_m - com
            hips[leg] = np.array([hip[0], hip[2]])
        return stance_forces(self.gait, hips, self.robot.trunk_mass_kg)

    def reference_swings(self) -> dict[str, tuple[SwingFamily, np.ndarray]]:
        """Every leg on the reference swing (what a stance is evaluated with by default)."""
        reference = make_family("reference")
        return {leg: (reference, np.zeros(0)) for leg in LEG_NAMES}

    def stance_forces(self, leg: str, swings: Swings | None = None) -> StanceForces:
        """The load on ``leg``'s foot over its stance samples under :attr:`loads`.

        Args:
            leg: The leg.
            swings: Every leg's swing (family, parameters), which the whole-body loads depend
                on; ``None``: every leg on the reference swing.
        """
        chosen = self.reference_swings() if swings is None else swings
        key = (leg, tuple((k, f.name, tuple(np.ravel(t))) for k, (f, t) in sorted(chosen.items())))
        if not self.load_model.couples_legs:
            key = (leg, ())
        if key not in self._stance_force_cache:
            self._stance_force_cache[key] = self.load_model.stance_forces(self, leg, chosen)
        return self._stance_force_cache[key]

    @cached_property
    def _stance_force_cache(self) -> dict[object, StanceForces]:
        return {}

    def stance_distribution(self, leg: str) -> StanceDistribution:
        """How ``leg``'s stance feet share a wrench, per sample (built once per gait)."""
        cache = self.caches.distributions
        key = (self.gait, self.loads, leg)  # the gait too: a copy by replace() shares the caches
        if key not in cache:
            cache[key] = stance_distribution(self, leg)
        return cache[key]

    def stance(self, leg: str, swings: Swings | None = None) -> PhaseResult:
        """Evaluate ``leg``'s stance phase.

        Args:
            leg: The leg.
            swings: Every leg's swing (family, parameters): the whole-body loads depend on
                them; ``None``: every leg on the reference swing.

        Raises:
            GaitError: The stance path leaves the leg's reach or joint limits.
        """
        path = self.stance_paths[leg]
        check_workspace(
            self.kinematics(leg),
            self.gait,
            "foot",
            path,
            "stance",
            ("stance_height_m", "step_length_m"),
        )
        forces = self.stance_forces(leg, swings)
        samples = PhaseSamples(
            phase="stance",
            space="foot",
            path=path,
            grf_n=forces.sagittal_n,
            t_phase_s=self.stance_times_s,
            start_s=stance_start_s(self.gait, leg),
            period_s=self.gait.period_s,
            unbalanced_nm=forces.unbalanced_nm,
            grf_lateral_n=forces.grf_n[1],
        )
        return evaluate_phase(self.physics(leg), samples, self.accounting)

    # --- swing --------------------------------------------------------------------------------
    def swing_path(self, leg: str, family: SwingFamily) -> AffinePath:
        """The family's affine swing path for ``leg``."""
        return family.path(self.gait, self.kinematics(leg))

    def swing(self, leg: str, family: SwingFamily, theta: np.ndarray | None = None) -> PhaseResult:
        """Evaluate ``leg``'s swing for a family member (``theta`` in the family's units).

        Raises:
            GaitError: The reference swing (no parameters) leaves the reach or joint limits: the
                gait's clearance, stance height or step length are impossible.
            InfeasibleError: A family member leaves the reach or joint limits.
        """
        path = self.swing_path(leg, family)
        values = path.values(theta)
        fields = ("clearance_m", "stance_height_m", "step_length_m") if not path.n_params else ()
        check_workspace(self.kinematics(leg), self.gait, path.space, values, "swing", fields)
        samples = PhaseSamples(
            phase="swing",
            space=path.space,
            path=values,
            grf_n=np.zeros((2, path.t_s.size)),
            t_phase_s=path.t_s,
            start_s=swing_start_s(self.gait, leg),
            period_s=self.gait.period_s,
        )
        return evaluate_phase(self.physics(leg), samples, self.accounting)

    # --- cycles -------------------------------------------------------------------------------
    def leg_cycle(
        self,
        leg: str,
        family: SwingFamily,
        theta: np.ndarray | None = None,
        swings: Swings | None = None,
    ) -> LegCycle:
        """One leg's stance and swing.

        Args:
            leg: The leg.
            family: Its swing family.
            theta: Its parameters (``None``: zeros).
            swings: Every leg's swing, for the whole-body stance loads; ``None``: every leg
                swings like this one (its symmetric twin with the same parameters, the other
                pair with the same family at zero parameters, as :meth:`robot_cycle` does
                without ``thetas``).
        """
        theta_arr = np.zeros(family.n_params) if theta is None else np.asarray(theta, float)
        if swings is None:
            swings = self.swings(family, {leg: theta_arr})
        return LegCycle(
            leg,
            self.stance(leg, swings),
            self.swing(leg, family, theta_arr),
            family.name,
            theta_arr,
        )

    def swings(
        self, family: SwingFamily, thetas: Mapping[str, np.ndarray] | None = None
    ) -> dict[str, tuple[SwingFamily, np.ndarray]]:
        """Every leg's swing under :meth:`robot_cycle`'s rule for ``family`` and ``thetas``."""
        reference = make_family("reference")
        out: dict[str, tuple[SwingFamily, np.ndarray]] = {}
        for leg in LEG_NAMES:
            if thetas is None:
                out[leg] = (family, np.zeros(family.n_params))
            elif leg in thetas or SYMMETRIC_TWIN[leg] in thetas:
                theta = thetas[leg] if leg in thetas else thetas[SYMMETRIC_TWIN[leg]]
                out[leg] = (family, np.asarray(theta, dtype=float))
            else:
                out[leg] = (reference, np.zeros(0))
        return out

    def robot_cycle(
        self,
        family: SwingFamily,
        thetas: Mapping[str, np.ndarray] | None = None,
        legs: tuple[str, ...] = LEG_NAMES,
    ) -> RobotCycle:
        """Evaluate every leg in ``legs`` with the same swing family and per-leg parameters.

        The paper's symmetry: a leg without parameters of its own takes its symmetric twin's (LF
        repeats RF, RH repeats LH). When ``thetas`` names some legs, a leg with neither its own
        nor its twin's parameters keeps the reference swing; without ``thetas`` every leg uses
        the family at zero parameters.
        """
        swings = self.swings(family, thetas)
        cycles = {}
        for leg in (name for name in LEG_NAMES if name in legs):
            own, theta = swings[leg]
            cycles[leg] = self.leg_cycle(leg, own, theta, swings)
        return RobotCycle(
            self.gait, self.accounting, cycles, self.robot.total_mass_kg, loads=self.loads
        )
