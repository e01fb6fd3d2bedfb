"""A URDF loaded into Pinocchio once: the whole robot, fixed at its trunk, with named legs.

Frames (the trunk frame, which is Pinocchio's world for the fixed-base model): x forward, y left,
z up, origin at the URDF root link.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from scalf_opt.errors import ModelError
from scalf_opt.files import captured_native_output
from scalf_opt.model.discovery import discover_legs
from scalf_opt.model.inertia import inertia_problems
from scalf_opt.model.leg import Leg
from scalf_opt.model.naming import LegNames, legs_file_for, read_leg_map
from scalf_opt.model.urdf_file import read_srdf_text, read_urdf_text
from scalf_opt.types import LEG_NAMES


def check_bodies(model: pin.Model, path: Path) -> None:
    """Every body Pinocchio built (fixed-joint children merged in) has a physical inertia.

    The check (:func:`~scalf_opt.model.inertia.inertia_problems`) is on Pinocchio's bodies, not
    on the URDF's links: many published URDFs carry massless marker links with degenerate
    inertias (HyQ's feet, ANYmal's camera frames) that vanish in the merged body.

    Raises:
        ModelError: A body's inertia is not physical; the message names the body's joint.
    """
    problems = inertia_problems(model)
    if problems:
        raise ModelError(f"{path}: the body of {problems[0]}")


def parse_urdf(path: Path) -> pin.Model:
    """Pinocchio's fixed-base model of a URDF file, read as untrusted input.

    Raises:
        ModelError: The file is missing, unsafe or unphysical (:func:`read_urdf_text`,
            :func:`check_bodies`), or is not a URDF Pinocchio reads.
    """
    text = read_urdf_text(path)
    try:
        with captured_native_output() as printed:  # urdfdom prints its errors on stderr
            model = pin.buildModelFromXML(text)
    except (RuntimeError, ValueError) as exc:
        raise ModelError(f"{path}: not a valid URDF ({_first_line(exc, printed)})") from exc
    check_bodies(model, path)
    _rename_links_named_like_joints(model)
    return model


def _first_line(exc: BaseException, printed: list[str]) -> str:
    """The native library's own message: its exception's first line, else what it printed."""
    for text in (str(exc), *printed):
        if text.strip():
            return text.strip().splitlines()[0][:300]
    return type(exc).__name__


def reference_configuration(model: pin.Model, srdf_path: Path, state: str) -> np.ndarray:
    """The configuration of group state ``state`` in an SRDF, read as untrusted input.

    Raises:
        ModelError: The SRDF is not a regular, bounded, well-formed file (see
            :func:`~scalf_opt.model.urdf_file.read_srdf_text`), Pinocchio refuses it, it has no
            such state, or a value is not finite.
    """
    text = read_srdf_text(srdf_path)
    try:
        with captured_native_output() as printed:
            pin.loadReferenceConfigurationsFromXML(model, text, False)
    except (RuntimeError, ValueError) as exc:
        raise ModelError(f"{srdf_path}: not a valid SRDF ({_first_line(exc, printed)})") from exc
    if state not in model.referenceConfigurations:
        raise ModelError(f"{srdf_path}: no group state {state!r}")
    reference = np.array(model.referenceConfigurations[state], dtype=float)
    if not np.isfinite(reference).all():
        raise ModelError(f"{srdf_path}: group state {state!r} has a value that is not finite")
    return reference


def _rename_links_named_like_joints(model: pin.Model) -> None:
    """Rename the frame of a link that shares its name with a joint to ``<name>_link``.

    ANYmal's drive housings are links named like their joints; Pinocchio's reduced models look
    frames up by name and refuse duplicates.
    """
    joints = {f.name for f in model.frames if f.type == pin.JOINT}
    taken = {f.name for f in model.frames}
    for i, frame in enumerate(model.frames):
        if frame.type == pin.BODY and frame.name in joints:
            name = f"{frame.name}_link"
            while name in taken:
                name += "_"
            taken.add(name)
            frame.name = name
            model.frames[i] = frame


@dataclass(frozen=True)
class Robot:
    """A whole robot as Pinocchio sees it (fixed base at the trunk), with named legs.

    Attributes:
        model: Pinocchio model of the whole robot, root = trunk, gravity (0, 0, -9.81) m/s^2.
        urdf_path: The URDF it was built from.
        naming: How its legs' joints and feet are named.
        name: Robot name for reports (the catalog's name, or the URDF file's stem).
        nominal_stance_height_m: Pitching hip above the ground in the robot's nominal standing
            posture [m], when known (the catalog's value, or :attr:`standing_height_m`); the
            default gait uses it.
        reference_q: The robot's standing configuration (nq), when known (an SRDF's
            ``standing`` state); it fixes each leg's IK branch.
        actuator_path: The robot's actuator file, when it is not the one beside the URDF
            (``None``: ``<urdf stem>_actuators.toml`` beside it, if there is one).
        parent: The robot this one is a variant of (``scalf-opt variant``), whose default
            trot it walks, so that a variant differs from its parent only by its geometry.
    """

    model: pin.Model
    urdf_path: Path
    naming: LegNames
    name: str
    nominal_stance_height_m: float | None = None
    reference_q: np.ndarray | None = None
    actuator_path: Path | None = None
    parent: Robot | None = None

    @classmethod
    def from_urdf(
        cls,
        urdf_path: str | Path,
        legs: LegNames | None = None,
        name: str | None = None,
        nominal_stance_height_m: float | None = None,
        srdf: tuple[Path, str] | None = None,
        actuator_path: Path | None = None,
    ) -> Robot:
        """Parse a URDF with Pinocchio (once) and name its legs.

        Args:
            urdf_path: The URDF.
            legs: How the legs are named; ``None``: the legs file beside the URDF
                (``<name>_legs.toml``) if there is one, else the legs found in the kinematic tree
                (:func:`~scalf_opt.model.discovery.discover_legs`).
            name: Robot name (default: the file's stem).
            nominal_stance_height_m: See the attribute.
            srdf: ``(SRDF path, state name)`` of the standing configuration, if any.
            actuator_path: See the attribute.

        Raises:
            ModelError: The file is missing, is not a URDF Pinocchio reads, or its legs cannot
                be found.
            ConfigError: The legs file is invalid.
        """
        path = Path(urdf_path)
        model = parse_urdf(path)
        if legs is None:
            legs_file = legs_file_for(path)
            legs = (
                read_leg_map(legs_file) if legs_file.exists() else discover_legs(model, str(path))
            )
        reference = None
        if srdf is not None:
            reference = reference_configuration(model, *srdf)
        return cls(
            model, path, legs, name or path.stem, nominal_stance_height_m, reference, actuator_path
        )

    @property
    def total_mass_kg(self) -> float:
        """Mass of the whole robot [kg]."""
        return float(sum(inertia.mass for inertia in self.model.inertias))

    @property
    def trunk_com_m(self) -> np.ndarray:
        """Centre of mass of the root link (the trunk) in the trunk frame, shape (3,) [m]."""
        # Pinocchio attaches the root link's inertia of a fixed-base model to the universe joint.
        return np.array(self.model.inertias[0].lever, dtype=float)

    @property
    def trunk_mass_kg(self) -> float:
        """Mass of the root link (the trunk) [kg]: what the stance legs carry (decision 11)."""
        return float(self.model.inertias[0].mass)

    @property
    def standing_height_m(self) -> float | None:
        """Hip height of the reference posture [m]; ``None`` without a reference posture.

        The mean over the legs of the pitching hip's height above the foot at
        :attr:`reference_q`, with the roll joints at zero (the sagittal leg).
        """
        if self.reference_q is None:
            return None
        heights = []
        for leg in (self.leg(n) for n in LEG_NAMES):
            model = leg.model
            data = model.createData()
            pin.framesForwardKinematics(model, data, leg.reference_posture_rad)
            heights.append(leg.hip_origin_m[2] - data.oMf[leg.foot_frame_id].translation[2])
        return float(np.mean(heights))

    @property
    def leg_length_m(self) -> float:
        """Thigh plus shank length, the mean over the four legs [m]."""
        legs = [self.leg(n) for n in LEG_NAMES]
        return float(np.mean([leg.thigh_length_m + leg.shank_length_m for leg in legs]))

    def leg(self, name: str) -> Leg:
        """The sagittal two-joint view of leg ``name`` (RF, LH, LF or RH), built once."""
        if name not in self._legs:
            self._legs[name] = Leg.from_robot_model(
                self.model, name, self.naming.names(name), self.urdf_path, self.reference_q
            )
        return self._legs[name]

    @cached_property
    def _legs(self) -> dict[str, Leg]:
        return {}

    def __getstate__(self) -> dict[str, Any]:
        """Pickled without the legs built so far.

        They hold CasADi expressions; a worker process builds them again on first use.
        """
        state = dict(self.__dict__)
        state.pop("_legs", None)
        return state
