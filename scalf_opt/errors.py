"""One exception hierarchy for every user-facing mistake and solver failure.

The CLI turns any :class:`ScalfError` into one line on stderr and exit code 2; everything else is
a bug and keeps its traceback.
"""

from __future__ import annotations


class ScalfError(Exception):
    """Base class of every error scalf-opt raises on purpose."""


class ModelError(ScalfError):
    """A URDF, leg or actuator description is missing, malformed or unphysical."""


class ConfigError(ScalfError):
    """A configuration file (gait, actuator table) cannot be read or has a bad field."""


class GaitError(ScalfError):
    """A gait is impossible: a field is out of its allowed range or leaves the workspace."""


class InfeasibleError(ScalfError):
    """A motion cannot be realised: unreachable foot target, joint limit, foot below ground."""


class SolverError(ScalfError):
    """An optimizer did not converge; carries the solver's status and statistics."""

    def __init__(self, message: str, stats: dict[str, object] | None = None) -> None:
        super().__init__(message)
        self.stats = dict(stats or {})
