"""Swing family names: ``reference``, ``paper``, ``fourier-N`` (foot space), ``joint-N``."""

from __future__ import annotations

import re
from collections.abc import Iterable

from scalf_opt.errors import ConfigError, did_you_mean
from scalf_opt.types import Space

MIN_ORDER = 2
MAX_ORDER = 12
"""Orders N a Fourier family may have."""

DEFAULT_FAMILY = "joint-6"
"""The family optimized by default: half-range Fourier series of order 6 in joint space."""

FREE_FAMILY = "free"
"""Not a family but the free-trajectory bound: dense B-splines refined until the energy
converges (:mod:`scalf_opt.optimize.bound`)."""

_FAMILY_PATTERN = re.compile(r"^(fourier|joint)-(\d+)$")
_BSPLINE_PATTERN = re.compile(r"^bspline-(\d+)$")


def parse_bspline_name(name: str) -> int | None:
    """The number of spans of a ``bspline-K`` name (the free method's family), else ``None``."""
    match = _BSPLINE_PATTERN.match(name)
    return int(match.group(1)) if match else None


def parse_fourier_name(name: str, also: Iterable[str] = ()) -> tuple[Space, int]:
    """``(space, order)`` of a ``fourier-N`` or ``joint-N`` name.

    ``also``: other names the caller accepts (``free``), suggested for a near miss too.

    Raises:
        ConfigError: Not such a name, or an order outside 2..12.
    """
    match = _FAMILY_PATTERN.match(name)
    if not match:
        also = tuple(also)
        known = [
            "reference",
            "paper",
            *(
                f"{kind}-{n}"
                for kind in ("joint", "fourier")
                for n in range(MIN_ORDER, MAX_ORDER + 1)
            ),
            *also,
        ]
        raise ConfigError(
            f"unknown family {name!r}: use reference, paper, fourier-N (foot space) or "
            f"joint-N (joint space) with N in {MIN_ORDER}..{MAX_ORDER}"
            f"{''.join(f', or {other}' for other in also)}{did_you_mean(str(name), known)}",
            field="family",
        )
    order = int(match.group(2))
    if not MIN_ORDER <= order <= MAX_ORDER:
        raise ConfigError(
            f"family {name!r}: order N must be in {MIN_ORDER}..{MAX_ORDER}, got {order}",
            field="family",
        )
    return ("foot" if match.group(1) == "fourier" else "joint"), order
