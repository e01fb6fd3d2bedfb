"""MuJoCo's own check that a run still holds numbers, read by both referees after every step.

``mj_step`` checks the state as it goes: positions or velocities NaN or beyond ``1e10``
(MuJoCo's warnings ``BADQPOS``, ``BADQVEL``), the controls likewise (``BADCTRL``), the
accelerations likewise (``BADQACC``). It does not stop there: on a bad state it resets the
simulation (every joint at the model's initial pose, at rest) and carries on, on bad controls it
applies none, and in both cases it only counts a warning in ``data.warning``. A referee that did
not read the counts would measure a robot teleported to its initial pose, or moved by no torque,
as physics. Both referees clear the counts before their first step (:func:`clear_divergence`),
read them after every step (:func:`divergence`) and stop the run at the first: its record ends
before the step MuJoCo flagged, ``diverged_at_s`` says when that step started and
``divergence`` which check failed, in words; the run's verdict is never met.
"""

from __future__ import annotations

import mujoco

DIVERGENCE_WARNINGS: tuple[tuple[mujoco.mjtWarning, str], ...] = (
    (mujoco.mjtWarning.mjWARN_BADQPOS, "bad positions, MuJoCo's BADQPOS"),
    (mujoco.mjtWarning.mjWARN_BADQVEL, "bad velocities, MuJoCo's BADQVEL"),
    (mujoco.mjtWarning.mjWARN_BADCTRL, "torques NaN or huge, MuJoCo's BADCTRL"),
    (mujoco.mjtWarning.mjWARN_BADQACC, "bad accelerations, MuJoCo's BADQACC"),
)
"""The warnings that mean a run diverged, in the order ``mj_step`` checks them, and their words."""


def clear_divergence(data: mujoco.MjData) -> None:
    """Set the counts of :data:`DIVERGENCE_WARNINGS` to zero (before a run's first step)."""
    for warning, _ in DIVERGENCE_WARNINGS:
        data.warning[warning].number = 0


def divergence(data: mujoco.MjData) -> str | None:
    """The words of the first of :data:`DIVERGENCE_WARNINGS` MuJoCo counted, else ``None``."""
    for warning, words in DIVERGENCE_WARNINGS:
        if data.warning[warning].number:
            return words
    return None
