r"""Stance loads: which forces the stance feet carry, from the trunk alone or the whole robot.

Two load models (``--loads``), each one object in :data:`LOAD_MODELS`, so that nothing else in
scalf-opt asks which one it has:

``trunk`` (the paper's, decision 11)
    The stance feet carry the trunk link's weight (and its forward acceleration, zero in the
    plan), shared by the sagittal minimum-norm distribution
    (:func:`~scalf_opt.locomotion.forces.min_norm_foot_forces`). The legs' own weight and
    inertia never reach the other legs: the stance forces do not depend on the swings.

``whole-body``
    The stance feet supply the wrench the whole robot needs for its planned motion: the
    floating-base inverse dynamics' first six rows. The trunk moves at constant velocity
    without rotating, so its frame is inertial (Galilean invariance) and that wrench, in the
    trunk frame about its origin, is a sum of one constant term and one term per leg::

        W = W_static + sum_legs W_leg(q_leg, qd_leg, qdd_leg),

    ``W_static = (m_s g, c_s x m_s g)`` the weight of every body no leg joint moves (trunk,
    hip-roll links at zero roll, ...; mass ``m_s``, centre of mass ``c_s``, ``g`` pointing up)
    and ``W_leg`` the force the trunk supplies to the leg's moving links
    (:meth:`~scalf_opt.energy.physics.LegPhysics.wrench_function`, one CasADi function per leg
    for the numeric evaluator and the NLP alike). The wrench is shared by the stance feet with
    the 3-D minimum-norm distribution (:func:`~scalf_opt.locomotion.forces.contact_maps`:
    no internal force between the feet); what two diagonal feet cannot supply (the moment about
    the line joining them) is reported per sample, not hidden. Each leg's joints then see the
    sagittal part ``(F_x, F_z)`` of its foot force; the lateral part loads only the locked roll
    joint. Each leg's own joint torques ``RNEA_leg - J^T F`` are the leg rows of the floating-
    base RNEA with the foot forces as external forces (the tests check it to 1e-9 on every
    robot).

``whole-body-sagittal``
    The same wrench, shared by the sagittal minimum norm
    (:func:`~scalf_opt.locomotion.forces.sagittal_contact_maps`): the feet supply its forward
    and vertical forces and its pitch moment in full, with no lateral force, and the roll and yaw
    moments that leaves are reported as unbalanced. That is the distribution of a trunk held in
    its sagittal plane, the simulation referee's (:mod:`scalf_opt.sim.inverse`; a test checks the
    two agree): on a diagonal pair it differs from the 3-D one by the moment about the line
    joining the feet, which the 3-D distribution leaves out and this one supplies as pitch.

Under whole-body loads a stance leg's energy depends on the swinging legs' motion: the stance
forces are computed for the swings actually chosen (:meth:`StanceLoads.stance_forces`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Protocol

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.forces import contact_maps, sagittal_contact_maps
from scalf_opt.locomotion.gait import PHASE_EDGE_TOLERANCE_S
from scalf_opt.locomotion.stance import stance_path
from scalf_opt.locomotion.trot import (
    DIAGONAL_PARTNER,
    stance_start_s,
    support_groups,
    support_masks,
    time_since_touchdown_s,
)
from scalf_opt.types import LEG_NAMES, Space

if TYPE_CHECKING:
    from scalf_opt.energy.physics import LegPhysics
    from scalf_opt.locomotion.gait import Gait
    from scalf_opt.locomotion.swing.family import AffinePath, SwingFamily
    from scalf_opt.model.kinematics import LegKinematics
    from scalf_opt.model.robot import Robot

Swings = Mapping[str, tuple["SwingFamily", np.ndarray]]
"""The swing of every leg: its family and parameters (family units)."""


class StanceContext(Protocol):
    """What the load models read of a gait's evaluation.

    The robot and gait, the stance grid, each leg's physics and kinematics, the trunk-only
    loads and the stance distribution.
    :class:`~scalf_opt.energy.pipeline.EnergyPipeline` is one; the load models name this
    protocol, not the pipeline, so that the pipeline's module and theirs do not import each
    other.
    """

    @property
    def robot(self) -> Robot: ...  # noqa: D102

    @property
    def gait(self) -> Gait: ...  # noqa: D102

    @property
    def stance_times_s(self) -> np.ndarray: ...  # noqa: D102

    @property
    def trunk_stance_forces(self) -> dict[str, np.ndarray]: ...  # noqa: D102

    @property
    def load_model(self) -> StanceLoads: ...  # noqa: D102

    def physics(self, leg: str) -> LegPhysics: ...  # noqa: D102

    def kinematics(self, leg: str) -> LegKinematics: ...  # noqa: D102

    def stance_distribution(self, leg: str) -> StanceDistribution: ...  # noqa: D102


@dataclass(frozen=True)
class StanceForces:
    """The forces on one leg's foot over its stance samples.

    Attributes:
        grf_n: Ground reaction force on the foot (F_x, F_y, F_z) in the trunk axes, (3, n) [N].
        unbalanced_nm: Moment the stance feet cannot supply at each sample (trunk axes), (3, n)
            [N m]; zero under trunk loads and whenever three or more feet stand.
    """

    grf_n: np.ndarray
    unbalanced_nm: np.ndarray

    @property
    def sagittal_n(self) -> np.ndarray:
        """``(F_x, F_z)``, (2, n) [N]: what the leg's hip-pitch and knee joints see."""
        return self.grf_n[[0, 2]]


class StanceLoads(ABC):
    """A model of the loads the stance feet carry."""

    name: ClassVar[str]
    description: ClassVar[str]
    couples_legs: ClassVar[bool]
    """Whether a stance leg's forces depend on the other legs' swings."""
    unbalanced: ClassVar[str] = ""
    """What the moment the feet do not supply is, for the reports (empty: always zero)."""

    @abstractmethod
    def stance_forces(self, pipeline: StanceContext, leg: str, swings: Swings) -> StanceForces:
        """Forces on ``leg``'s foot over the pipeline's stance grid, for the given swings."""

    @abstractmethod
    def carried_mass_kg(self, robot: Robot) -> float:
        """The mass whose weight the stance feet carry on average [kg]."""


class TrunkLoads(StanceLoads):
    """The trunk link's weight on the stance feet, sagittal minimum norm (the paper's)."""

    name = "trunk"
    description = "the trunk link's weight only, sagittal minimum norm (the paper's model)"
    couples_legs = False

    def carried_mass_kg(self, robot: Robot) -> float:  # noqa: D102
        return robot.trunk_mass_kg

    def stance_forces(  # noqa: D102
        self, pipeline: StanceContext, leg: str, swings: Swings
    ) -> StanceForces:
        sagittal = pipeline.trunk_stance_forces[leg]
        n = sagittal.shape[1]
        grf = np.vstack([sagittal[0], np.zeros(n), sagittal[1]])
        return StanceForces(grf, np.zeros((3, n)))


class WholeBodyLoads(StanceLoads):
    """The whole robot's inverse dynamics on the stance feet, 3-D minimum norm."""

    name = "whole-body"
    description = "the whole robot's inverse dynamics (trunk and all four legs), 3-D minimum norm"
    couples_legs = True
    unbalanced = "two point feet cannot supply the moment about the line joining them"

    @staticmethod
    def contact_maps(feet_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The maps from the wrench to the feet's forces and to the moment left over."""
        return contact_maps(feet_m)

    def carried_mass_kg(self, robot: Robot) -> float:  # noqa: D102
        return robot.total_mass_kg

    def stance_forces(  # noqa: D102
        self, pipeline: StanceContext, leg: str, swings: Swings
    ) -> StanceForces:
        t = pipeline.stance_times_s
        cycle_times = stance_start_s(pipeline.gait, leg) + t
        wrench = np.tile(static_wrench(pipeline.robot)[:, None], (1, t.size))
        for other in LEG_NAMES:
            standing = other in (leg, DIAGONAL_PARTNER[leg])
            space, path = leg_motion(pipeline, other, cycle_times, swings, standing)
            fn = pipeline.physics(other).wrench_function(space).map(t.size)
            wrench += np.array(fn(path[0], path[1], path[2]))
        share = pipeline.stance_distribution(leg)
        grf = np.einsum("nij,jn->in", share.force[leg], wrench)
        unbalanced = np.einsum("nij,jn->in", share.unbalanced, wrench)
        return StanceForces(grf, unbalanced)


@dataclass(frozen=True)
class StanceDistribution:
    """The linear maps from the required wrench to a stance's foot forces, sample by sample.

    The wrench ``W`` (6: force, then moment about the trunk origin, trunk axes) at stance
    sample ``j`` gives foot force ``force[leg][j] @ W`` (3) on each leg of the diagonal pair
    and the moment the feet cannot supply ``unbalanced[j] @ W`` (3)
    (:func:`~scalf_opt.locomotion.forces.contact_maps`). The maps depend only on where
    the feet stand: computed once per gait and pair.

    Attributes:
        force: Per leg of the pair, shape (n, 3, 6) [1, 1/m].
        unbalanced: Shape (n, 3, 6) [m, 1].
    """

    force: dict[str, np.ndarray]
    unbalanced: np.ndarray


def stance_distribution(pipeline: StanceContext, leg: str) -> StanceDistribution:
    """The distribution maps of ``leg``'s stance samples (see :class:`StanceDistribution`)."""
    cycle_times = stance_start_s(pipeline.gait, leg) + pipeline.stance_times_s
    n = cycle_times.size
    pair = (leg, DIAGONAL_PARTNER[leg])
    force = {s: np.zeros((n, 3, 6)) for s in pair}
    unbalanced = np.zeros((n, 3, 6))
    standing = support_masks(pipeline.gait, cycle_times, leg)
    feet = {other: foot_position_m(pipeline, other, cycle_times) for other in standing}
    model = pipeline.load_model
    assert isinstance(model, WholeBodyLoads), "only the whole-body models share a wrench"
    # the samples with the same feet on the ground, as one stack (the pair first among them)
    for at, on in support_groups(standing):
        stacked = np.stack([feet[o][:, at].T for o in on], axis=-1)
        forces, unbalanced[at] = model.contact_maps(stacked)
        for s in pair:
            k = on.index(s)
            force[s][at] = forces[:, 3 * k : 3 * k + 3]
    return StanceDistribution(force, unbalanced)


class SagittalWholeBodyLoads(WholeBodyLoads):
    """The whole robot's inverse dynamics on the stance feet, sagittal minimum norm."""

    name = "whole-body-sagittal"
    description = (
        "the whole robot's inverse dynamics, sagittal minimum norm (forward and vertical "
        "forces, pitch moment: a planar trunk's, as the simulation referee's)"
    )
    unbalanced = "the roll and yaw moments the sagittal forces leave to the trunk"

    @staticmethod
    def contact_maps(feet_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The maps from the wrench to the feet's forces and to the moment left over."""
        return sagittal_contact_maps(feet_m)


LOAD_MODELS: dict[str, StanceLoads] = {
    m.name: m for m in (WholeBodyLoads(), TrunkLoads(), SagittalWholeBodyLoads())
}
"""Every load model by name (the choices of ``--loads``, in this order)."""

DEFAULT_LOADS = WholeBodyLoads.name
"""The default of every command that evaluates energy, except ``paper``."""

PAPER_LOADS = TrunkLoads.name
"""The paper's model (decision 11): what ``scalf-opt paper`` reproduces Tables 5 and 6 with."""


def stance_loads(name: str) -> StanceLoads:
    """The load model called ``name``.

    Raises:
        ConfigError: No load model has that name; the message lists the choices.
    """
    if name not in LOAD_MODELS:
        raise ConfigError(f"loads = {name!r} is not one of {', '.join(LOAD_MODELS)}", field="loads")
    return LOAD_MODELS[name]


def moving_joints(robot: Robot) -> set[int]:
    """Joints of the whole model that a leg's hip pitch or knee moves (their subtrees)."""
    model = robot.model
    roots = set()
    for leg in LEG_NAMES:
        for joint in robot.leg(leg).joint_names:
            roots.add(int(model.getJointId(joint)))
    moving = set()
    for j in range(1, model.njoints):
        k = j
        while k > 0:
            if k in roots:
                moving.add(j)
                break
            k = int(model.parents[k])
    return moving


def static_wrench(robot: Robot) -> np.ndarray:
    """The wrench that holds up every body no leg joint moves, (6,): ``(m g, c x m g)``.

    Force [N] then moment [N m] about the trunk origin, trunk axes; the other joints (hip
    roll, ...) at their neutral position, as the legs' sagittal models assume.
    """
    import pinocchio as pin  # here: the registry's names load without Pinocchio (command line)

    model = robot.model
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    moving = moving_joints(robot)
    total = pin.Inertia.Zero()
    for j in range(model.njoints):
        if j not in moving:
            total += data.oMi[j].act(model.inertias[j])
    up = -np.array(model.gravity.linear, dtype=float)
    force = total.mass * up
    return np.concatenate([force, np.cross(np.array(total.lever), force)])


def foot_position_m(pipeline: StanceContext, leg: str, cycle_times_s: np.ndarray) -> np.ndarray:
    """Position of ``leg``'s stance foot in the trunk frame at cycle times, (3, n) [m]."""
    model_leg = pipeline.robot.leg(leg)
    times = np.asarray(cycle_times_s, dtype=float)
    local = time_since_touchdown_s(pipeline.gait, times, leg)
    xz = stance_path(pipeline.gait, local, leg)[0]
    lateral = np.full(times.shape, model_leg.foot_lateral_m)
    return model_leg.hip_origin_m[:, None] + np.vstack([xz[0], lateral, xz[1]])


def leg_motion(
    pipeline: StanceContext,
    leg: str,
    cycle_times_s: np.ndarray,
    swings: Swings,
    standing: bool = False,
) -> tuple[Space, np.ndarray]:
    """``leg``'s planned motion at the given cycle times: ``(space, path (3, 2, n))``.

    See :func:`affine_leg_motion`; this is its value at the leg's parameters.
    """
    if leg not in swings:
        raise ConfigError(f"the whole-body loads need leg {leg}'s swing", field="loads")
    family, theta = swings[leg]
    motion = affine_leg_motion(pipeline, leg, cycle_times_s, family, standing)
    return motion.space, motion.values(theta)


def affine_leg_motion(
    pipeline: StanceContext,
    leg: str,
    cycle_times_s: np.ndarray,
    family: SwingFamily,
    standing: bool = False,
) -> AffinePath:
    """``leg``'s planned motion at the given cycle times, affine in its swing's parameters.

    Stance samples are the stance path (fixed); swing samples the family's path at those
    times. ``standing``: the times lie in this leg's own stance, ends included (the stance
    whose samples these are: its leg and diagonal partner). Otherwise a foot exactly at
    touch-down or lift-off (within the phase-edge tolerance) is taken from the swing, its
    value on the side of the edge where the window lies (the other pair lifts off as the
    window begins and touches down as it ends), as
    :func:`~scalf_opt.locomotion.trot.support_masks` does not count it as standing. The space
    is the family's; stance samples of a joint-space family are mapped to joint motion by the
    leg's inverse kinematics.
    """
    from scalf_opt.locomotion.swing.family import AffinePath

    gait = pipeline.gait
    t_stance, t_swing = gait.stance_duration_s, gait.swing_duration_s
    times = np.asarray(cycle_times_s, dtype=float)
    local = time_since_touchdown_s(gait, times, leg)
    tol = PHASE_EDGE_TOLERANCE_S
    in_stance = (local > tol) & (local < t_stance - tol)
    if standing:
        in_stance[:] = True
        local = np.clip(np.where(local > t_stance + tol, local - gait.period_s, local), 0, t_stance)
    swing_t = local - t_stance
    swing_t = np.where(swing_t < -tol, swing_t + gait.period_s, swing_t)
    swing_t = np.clip(np.where(local <= tol, t_swing, swing_t), 0.0, t_swing)  # touch-down: T_sw
    stance = stance_path(gait, local, leg)
    swing = family.path(gait, pipeline.kinematics(leg), swing_t)
    if family.space == "joint" and in_stance.any():
        joints = pipeline.kinematics(leg).functions["motion"].map(local.size)(*stance)
        stance = np.array([np.array(x) for x in joints])
    mask = in_stance[None, None, :]
    return AffinePath(
        swing.space,
        times,
        np.where(mask, stance, swing.base),
        np.where(mask[..., None], 0.0, swing.dense_basis()),
    )
