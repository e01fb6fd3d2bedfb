"""A saved optimum: what ``scalf-opt optimize --out`` records, and reading it back.

``summary.json`` of ``optimize`` holds, besides the cycle (:func:`~scalf_opt.io.results
.cycle_summary`), an ``optimization`` record per optimized leg (family, method, parameters,
their unit, the energies and checks) and an ``optimization_run`` record (the rate, the rates
tried, the settings). :func:`read_optimum` reads the family and the parameters of every leg back,
so that ``scalf-opt evaluate --swing FILE`` can evaluate the optimum under another rate or
accounting; :func:`check_timing` refuses a gait whose timing differs from the optimum's.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.optimize.driver import SwingOptimization
from scalf_opt.types import LEG_NAMES

TIMING_FIELDS: tuple[str, ...] = (
    "period_s",
    "duty_cycle",
    "step_length_m",
    "clearance_m",
    "stance_height_m",
    "stance_x_offset_front_m",
    "stance_x_offset_hind_m",
)
"""Gait fields an optimum belongs to (its timing and stance): a gait that differs in one of them
is another problem."""

TIMING_RTOL = 1e-9
"""Relative difference allowed between a file's timing field and the gait's (round-off)."""


def optimization_record(run: SwingOptimization) -> dict[str, Any]:
    """The ``optimization_run`` record of ``summary.json``."""
    return {
        "family": run.family.name,
        "method": run.settings.method,
        "starts": run.settings.starts,
        "sample_rate_hz": run.rate_hz,
        "rates_tried_hz": list(run.rates_hz),
        "sampling_tolerance": run.settings.sampling_tolerance,
        "converged_sampling": run.converged_sampling,
        "success": run.success,
        "any_worse_than_reference": any(r.worse_than_reference for r in run.legs.values()),
        "wall_time_s": run.wall_time_s,
    }


@dataclass(frozen=True)
class SavedOptimum:
    """An optimum read from a ``summary.json``.

    Attributes:
        path: The file.
        family: Family name.
        thetas: Parameters per optimized leg (family units).
        gait: The file's gait fields.
        sample_rate_hz: The rate the optimum was found at [Hz].
    """

    path: Path
    family: str
    thetas: dict[str, np.ndarray]
    gait: dict[str, Any]
    sample_rate_hz: float


def _field(path: Path, data: Any, key: str, kind: type | tuple[type, ...], where: str) -> Any:
    if not isinstance(data, dict) or key not in data:
        raise ConfigError(f"{path}: missing field {where}{key}: not an optimum written by optimize")
    value = data[key]
    if not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool):
        raise ConfigError(f"{path}: field {where}{key} has the wrong type ({type(value).__name__})")
    return value


def read_optimum(path: str | Path) -> SavedOptimum:
    """Read the optimum of a ``summary.json`` written by ``scalf-opt optimize --out``.

    Raises:
        ConfigError: The file cannot be read, is not JSON, or is not an optimum (a field is
            missing or mistyped; the message names it).
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the optimum file ({exc.strerror})") from exc
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{path}: not a JSON file (line {exc.lineno}: {exc.msg})") from exc
    records = _field(path, data, "optimization", dict, "")
    if not records:
        raise ConfigError(f"{path}: field optimization is empty: not an optimum")
    gait = _field(path, data, "gait", dict, "")
    run = data.get("optimization_run", {})
    rate = run.get("sample_rate_hz", gait.get("sample_rate_hz")) if isinstance(run, dict) else None
    families = set()
    thetas = {}
    for leg, record in records.items():
        if leg not in LEG_NAMES:
            raise ConfigError(
                f"{path}: field optimization.{leg} names no leg ({', '.join(LEG_NAMES)})"
            )
        where = f"optimization.{leg}."
        families.add(_field(path, record, "family", str, where))
        parameters = _field(path, record, "parameters", dict, where)
        values = list(parameters.values())
        if not all(isinstance(v, int | float) and math.isfinite(v) for v in values):
            raise ConfigError(f"{path}: field {where}parameters holds a value that is not a number")
        if not _field(path, record, "success", bool, where):
            raise ConfigError(f"{path}: field {where}success is false: the file holds no optimum")
        thetas[leg] = np.array(values, dtype=float)
    if len(families) != 1:
        raise ConfigError(f"{path}: field optimization.*.family differs between legs: {families}")
    return SavedOptimum(path, families.pop(), thetas, gait, float(rate or math.nan))


def check_timing(saved: SavedOptimum, gait: Gait) -> None:
    """Refuse a gait whose timing differs from the optimum's.

    Raises:
        ConfigError: A timing field differs (the message names it and both values).
    """
    for name in TIMING_FIELDS:
        if name not in saved.gait and name.startswith("stance_x_offset"):
            theirs = 0.0  # files from before the stance offsets: the foot under the hip
        elif name not in saved.gait:
            raise ConfigError(f"{saved.path}: missing field gait.{name}: not an optimum file")
        else:
            theirs = saved.gait[name]
        ours = getattr(gait, name)
        if not isinstance(theirs, int | float) or not math.isclose(
            float(theirs), float(ours), rel_tol=TIMING_RTOL
        ):
            raise ConfigError(
                f"{saved.path}: the optimum was found for gait field {name} = {theirs!r}, the "
                f"gait has {ours!r}: its timing and stance must match (only the rate and the "
                "accounting may differ)"
            )
