"""Find a quadruped's legs in its kinematic tree, whatever the URDF calls them.

A *chain* is the path of movable joints from the base (the URDF root, Pinocchio's universe of the
fixed-base model) to a joint without children. A chain is a *leg* when at least two of its joints
rotate about axes parallel to the trunk's y axis at the zero configuration (the hip pitch and the
knee: the last two such joints of the chain) and a foot frame hangs from its last joint. The
foot is the frame attached to the last joint farthest from that joint's axis (frames named like a
foot, ``*foot*`` in any case, first; a body before a fixed joint at the same place). The joint
before the hip pitch, if any, is the hip roll.

A quadruped has exactly four legs, one per quadrant: front or hind by the sign of the hip-pitch
axis's x coordinate, left or right by the sign of its y (trunk frame: x forward, y left). Anything
else is an error that lists what was found, so the user can write a legs file
(:func:`~scalf_opt.model.naming.read_leg_map`) instead.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from scalf_opt.errors import ModelError
from scalf_opt.model.naming import LegJoints, LegMap, legs_file_for

PARALLEL_TOLERANCE = 1e-9
"""Largest |x| or |z| component a unit joint axis may have and still count as parallel to y."""


@dataclass(frozen=True)
class Chain:
    """A path of movable joints from the base to a joint without children.

    Attributes:
        joints: Joint names, base first.
        pitch_like: Names of the joints whose axis is parallel to the trunk's y axis.
        foot: The foot frame hanging from the last joint, if any.
        tip_m: Position of the foot (or of the last joint) at q = 0, trunk frame [m].
        hip_m: Position of the hip-pitch joint (the first pitch-like joint of the last two), or
            of the first joint, at q = 0, trunk frame [m].
    """

    joints: tuple[str, ...]
    pitch_like: tuple[str, ...]
    foot: str | None
    tip_m: np.ndarray
    hip_m: np.ndarray

    @property
    def is_leg(self) -> bool:
        """Two pitch-like joints and a foot."""
        return len(self.pitch_like) >= 2 and self.foot is not None

    def describe(self) -> str:
        """One line: the joints and the foot."""
        x, y, z = self.tip_m
        foot = f"foot {self.foot}" if self.foot else "no foot frame"
        about_y = len(self.pitch_like)
        return (
            f"{' -> '.join(self.joints)} ({about_y} joint{'' if about_y == 1 else 's'} about y, "
            f"{foot} at x={x:+.3f} y={y:+.3f} z={z:+.3f} m)"
        )


def _axes_and_origins(model: pin.Model) -> tuple[np.ndarray, np.ndarray, pin.Data]:
    data = model.createData()
    q0 = pin.neutral(model)
    pin.forwardKinematics(model, data, q0)
    pin.updateFramePlacements(model, data)
    jac = pin.computeJointJacobians(model, data, q0)
    axes = np.zeros((model.njoints, 3))
    origins = np.zeros((model.njoints, 3))
    for j in range(1, model.njoints):
        origins[j] = data.oMi[j].translation
        if model.joints[j].nv == 1:
            axes[j] = jac[3:, model.joints[j].idx_v]  # zero for a prismatic joint
    return axes, origins, data


def _foot_frame(model: pin.Model, data: pin.Data, joint: int) -> str | None:
    """The frame hanging from ``joint`` farthest from it; foot-named frames and bodies first."""
    best: tuple[bool, float, bool, int] | None = None
    name = None
    for i, frame in enumerate(model.frames):
        if frame.parentJoint != joint or frame.type not in (
            pin.BODY,
            pin.FIXED_JOINT,
            pin.OP_FRAME,
        ):
            continue
        distance = float(np.linalg.norm(frame.placement.translation))
        key = ("foot" in frame.name.lower(), round(distance, 9), frame.type == pin.BODY, -i)
        if distance > 0.0 and (best is None or key > best):
            best, name = key, frame.name
    return name


def chains(model: pin.Model) -> list[Chain]:
    """Every chain of movable joints from the base to a childless joint, in joint order."""
    axes, origins, data = _axes_and_origins(model)
    children: dict[int, list[int]] = {j: [] for j in range(model.njoints)}
    for j in range(1, model.njoints):
        children[model.parents[j]].append(j)
    out = []
    for leaf in (j for j in range(1, model.njoints) if not children[j]):
        path = []
        j = leaf
        while j != 0:
            path.append(j)
            j = model.parents[j]
        path.reverse()
        pitch = [
            j
            for j in path
            if abs(axes[j][0]) < PARALLEL_TOLERANCE
            and abs(axes[j][2]) < PARALLEL_TOLERANCE
            and abs(axes[j][1]) > 0.5
        ]
        foot = _foot_frame(model, data, leaf)
        tip = np.array(data.oMf[model.getFrameId(foot)].translation) if foot else origins[leaf]
        hip = origins[pitch[-2]] if len(pitch) >= 2 else origins[path[0]]
        out.append(
            Chain(
                tuple(model.names[j] for j in path),
                tuple(model.names[j] for j in pitch),
                foot,
                tip,
                hip,
            )
        )
    return out


def discover_legs(model: pin.Model, source: str) -> LegMap:
    """The four legs of a quadruped, found in its kinematic tree.

    Raises:
        ModelError: Not exactly four chains look like legs, or two share a quadrant; the message
            lists every chain found and says how to name the legs instead.
    """
    found = chains(model)
    legs = [c for c in found if c.is_leg]
    hint = (
        f"; name the legs in {legs_file_for(Path(source)).name} beside the URDF ([legs.RF] "
        "pitch = ..., knee = ..., foot = ..., and the same for LH, LF, RH)"
    )
    listing = "; ".join(c.describe() for c in found) or "none"
    if len(legs) != 4:
        raise ModelError(
            f"{source}: found {len(legs)} legs (chains from the base with two joints about y and "
            f"a foot frame) where a quadruped has 4; chains: {listing}{hint}"
        )
    out: dict[str, LegJoints] = {}
    for chain in legs:
        x, y = chain.hip_m[0], chain.hip_m[1]
        if x == 0.0 or y == 0.0:
            raise ModelError(
                f"{source}: the hip of {chain.describe()} is on the trunk's "
                f"{'y-z' if x == 0.0 else 'x-z'} plane: front/hind or left/right is ambiguous{hint}"
            )
        leg = ("L" if y > 0 else "R") + ("F" if x > 0 else "H")
        if leg in out:
            raise ModelError(
                f"{source}: two legs have their hip in the {leg} quadrant; chains: {listing}{hint}"
            )
        pitch, knee = chain.pitch_like[-2], chain.pitch_like[-1]
        index = chain.joints.index(pitch)
        roll = chain.joints[index - 1] if index > 0 else None
        assert chain.foot is not None  # is_leg
        out[leg] = LegJoints(roll, pitch, knee, chain.foot)
    return LegMap("discovered", out)
