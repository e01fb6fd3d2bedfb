"""One exception hierarchy for every user-facing mistake.

The CLI turns any :class:`ScalfError` into one line on stderr and exit code 2; anything else is a
bug: one line and exit code 1 (``--debug`` shows the traceback). An optimizer that does not
converge is not an exception: its result says so (``SwingOptimum.success``, with the solver's
status and statistics) and the CLI exits 3.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable


class ScalfError(Exception):
    """Base class of every error scalf-opt raises on purpose.

    Args:
        message: One line that names the file or field at fault.
        field: The field (e.g. a gait field ``period_s``) the error is about, when there is one;
            the command line maps it to the option that sets it.
    """

    def __init__(self, message: str, *, field: str | None = None) -> None:
        super().__init__(message)
        self.field = field


class ModelError(ScalfError):
    """A URDF, leg or actuator description is missing, malformed or unphysical."""


class ConfigError(ScalfError):
    """A configuration file (gait, actuator table) cannot be read or has a bad field."""


class GaitError(ScalfError):
    """A gait is impossible: a field is out of its allowed range or leaves the workspace."""


class InfeasibleError(ScalfError):
    """A motion cannot be realised: unreachable foot target, joint limit, foot below ground."""


class LogError(ScalfError):
    """A measurement log (cylinder lengths and forces) cannot be read or is invalid."""


AS_CLOSE = 0.06
"""Candidates whose similarity to a mistyped word (difflib's ratio, 0 to 1) is within this of the
closest one's are suggested beside it: ``--shank-scale`` is 0.84 from ``--shank-mass-scale`` and
0.79 from ``--shank-length-scale``, and either may be meant."""


def close_matches(word: str, candidates: Iterable[str]) -> list[str]:
    """The candidates closest to a mistyped ``word``, closest first.

    The closest one and any about as close (:data:`AS_CLOSE`); else the candidates that begin
    with ``word`` (three letters at least: ``duty`` for ``duty_cycle``, which difflib finds only
    0.57 similar); none when nothing is close (difflib's similarity of 0.6).
    """
    unique = list(dict.fromkeys(candidates))
    close = difflib.get_close_matches(word, unique, n=3)
    if not close:
        return [c for c in unique if len(word) >= 3 and c.startswith(word)][:3]
    best = difflib.SequenceMatcher(None, word, close[0]).ratio()
    return [c for c in close if difflib.SequenceMatcher(None, word, c).ratio() >= best - AS_CLOSE]


def suggestion(close: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` (``'x' or 'y'``) for the given matches, ``""`` for none."""
    close = list(close)
    return f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""


def did_you_mean(word: str, candidates: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` for the candidates closest to a mistyped ``word``, else ``""``.

    ``'x' or 'y'`` when another candidate is about as close (:data:`AS_CLOSE`), closest first.
    """
    return suggestion(close_matches(word, candidates))
