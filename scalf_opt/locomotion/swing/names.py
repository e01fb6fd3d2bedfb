"""Swing family names: ``reference``, ``paper``, ``fourier-N`` (foot space), ``joint-N``."""

from __future__ import annotations

import re

MIN_ORDER = 2
MAX_ORDER = 12
"""Orders N a Fourier family may have."""

DEFAULT_FAMILY = "joint-6"
"""The family optimized by default: half-range Fourier series of order 6 in joint space."""

FREE_FAMILY = "free"
"""Not a family but the free-trajectory bound: dense B-splines refined until the energy
converges (:mod:`scalf_opt.optimize.bound`)."""

BSPLINE_PATTERN = re.compile(r"bspline-(\d+)")
"""The free-trajectory bound's family names: ``bspline-K``, K spans per joint angle."""


def parse_bspline_name(name: str) -> int | None:
    """The number of spans of a ``bspline-K`` name (the free method's family), else ``None``."""
    match = BSPLINE_PATTERN.fullmatch(name)
    return int(match.group(1)) if match else None
