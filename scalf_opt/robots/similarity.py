"""Dynamic similarity to SCalf: a robot's defaults scaled from SCalf's by its leg length.

Two legged machines of different size move alike when their Froude numbers
``Fr = v^2 / (g L)`` are equal (Alexander and Jayes, 1983): lengths then scale with the leg length
``L`` and times with ``sqrt(L / g)``. With ``k = L / L_SCalf``, the length scale against SCalf
(``L`` is the thigh plus shank length, :attr:`~scalf_opt.model.robot.Robot.leg_length_m`), a
robot whose standing posture is unknown stands at ``z0 = 0.75 m * k`` (SCalf's z0 over its leg
length, decision 6), and its default trot (:mod:`scalf_opt.locomotion.scaling`) is SCalf's with
lengths times ``k`` and times times ``sqrt(k)``.
"""

from __future__ import annotations

REFERENCE_LEG_LENGTH_M = 0.45099 + 0.40487
"""SCalf's thigh plus shank length, Table 1 [m] (0.85586 m)."""

REFERENCE_STANCE_HEIGHT_M = 0.75
"""SCalf's nominal stance height, decision 6 [m]."""


def length_scale(leg_length_m: float) -> float:
    """``k = L / L_SCalf``: a robot's leg length over SCalf's."""
    return leg_length_m / REFERENCE_LEG_LENGTH_M


def similar_stance_height_m(leg_length_m: float) -> float:
    """The stance height of a robot shaped like SCalf with legs ``L`` long: ``0.75 m * k`` [m]."""
    return REFERENCE_STANCE_HEIGHT_M * length_scale(leg_length_m)
