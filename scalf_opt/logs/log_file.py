"""The cylinder log: a CSV file of the robot's cylinder sensors, read strictly and written.

Format: a header row, then one row per leg per sample, SI units::

    t_s,leg,hip_length_m,knee_length_m,hip_force_n,knee_force_n[,contact]

``leg`` is RF, LF, RH or LH; ``*_length_m`` the cylinder lengths [m]; ``*_force_n`` the cylinder
forces [N] (the force the cylinder exerts, positive when it pushes its joint the way that
lengthens it: the sign of ``tau / (dl/dtheta)``); ``contact`` (optional) 1 when the foot is on
the ground, else 0. Rows may come in any leg order; each leg's times must increase. Any sample
rate (the robot logs at 80 Hz). A log need not hold every leg.

A bad log is refused with one line that names the file, the row (1 is the header) and the
column: a missing or unknown column, a row with the wrong number of cells, an unknown leg, a
value that is not a finite number (``nan`` included), a contact other than 0 or 1, a time that
does not increase. (The stroke and the log's length are checked where the robot and the gait are
known, :mod:`scalf_opt.logs.analysis`, with the same row-and-column message.)
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scalf_opt.errors import LogError
from scalf_opt.files import read_untrusted_text
from scalf_opt.types import JOINT_ROLES, LEG_NAMES

TIME, LEG, CONTACT = "t_s", "leg", "contact"
LENGTH_COLUMNS: tuple[str, str] = tuple(f"{j}_length_m" for j in JOINT_ROLES)  # type: ignore[assignment]
FORCE_COLUMNS: tuple[str, str] = tuple(f"{j}_force_n" for j in JOINT_ROLES)  # type: ignore[assignment]
REQUIRED_COLUMNS: tuple[str, ...] = (TIME, LEG, *LENGTH_COLUMNS, *FORCE_COLUMNS)
ALL_COLUMNS: tuple[str, ...] = (*REQUIRED_COLUMNS, CONTACT)

MAX_LOG_BYTES = 200 * 1024 * 1024
"""Largest log read [bytes]: about 50 hours of the robot's 80 Hz four-leg log."""


@dataclass(frozen=True)
class LegLog:
    """One leg's samples, in time order.

    Attributes:
        t_s: Sample times, shape (n,) [s].
        length_m: (hip, knee) cylinder lengths, shape (2, n) [m].
        force_n: (hip, knee) cylinder forces, shape (2, n) [N].
        contact: Foot on the ground, shape (n,), or ``None`` without a contact column.
        rows: The file row of each sample (1 is the header), shape (n,).
    """

    t_s: np.ndarray
    length_m: np.ndarray
    force_n: np.ndarray
    contact: np.ndarray | None
    rows: np.ndarray


@dataclass(frozen=True)
class CylinderLog:
    """A whole log.

    Attributes:
        source: The file (for messages).
        legs: Per leg present, its samples, in :data:`~scalf_opt.types.LEG_NAMES` order.
    """

    source: str
    legs: dict[str, LegLog]

    @property
    def has_contact(self) -> bool:
        """Whether the log has the contact column."""
        return any(leg.contact is not None for leg in self.legs.values())


def _number(source: str, row: int, column: str, cell: str) -> float:
    try:
        value = float(cell)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise LogError(f"{source}: row {row}, column {column}: {cell!r} is not a finite number")
    return value


def parse_log(text: str, source: str) -> CylinderLog:
    """Parse and check a log's text (module docstring); ``source`` names it in messages.

    Raises:
        LogError: The first problem found, naming the row and the column.
    """
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header is None or not any(cell.strip() for cell in header):
        raise LogError(f"{source}: row 1: empty file, expected the header {','.join(ALL_COLUMNS)}")
    header = [cell.strip() for cell in header]
    for column in header:
        if column not in ALL_COLUMNS:
            raise LogError(
                f"{source}: row 1, column {column}: not a log column "
                f"(columns: {', '.join(ALL_COLUMNS)})"
            )
    for column in REQUIRED_COLUMNS:
        if column not in header:
            raise LogError(f"{source}: row 1, column {column}: missing from the header")
    if len(set(header)) != len(header):
        raise LogError(f"{source}: row 1: a column appears twice")
    position = {column: header.index(column) for column in header}
    with_contact = CONTACT in position
    samples: dict[str, list[tuple[float, ...]]] = {leg: [] for leg in LEG_NAMES}
    rows: dict[str, list[int]] = {leg: [] for leg in LEG_NAMES}
    for row, cells in enumerate(reader, start=2):
        if not cells or not any(cell.strip() for cell in cells):
            continue
        if len(cells) != len(header):
            raise LogError(f"{source}: row {row}: {len(cells)} cells, the header has {len(header)}")
        leg = cells[position[LEG]].strip()
        if leg not in samples:
            raise LogError(
                f"{source}: row {row}, column {LEG}: {leg!r} is not a leg "
                f"({', '.join(('RF', 'LF', 'RH', 'LH'))})"
            )
        numeric = [TIME, *LENGTH_COLUMNS, *FORCE_COLUMNS]
        values = [_number(source, row, c, cells[position[c]].strip()) for c in numeric]
        if with_contact:
            cell = cells[position[CONTACT]].strip()
            if cell not in ("0", "1"):
                raise LogError(f"{source}: row {row}, column {CONTACT}: {cell!r} is not 0 or 1")
            values.append(float(cell))
        if samples[leg] and values[0] <= samples[leg][-1][0]:
            raise LogError(
                f"{source}: row {row}, column {TIME}: {cells[position[TIME]].strip()} s does "
                f"not increase (the previous {leg} row, row {rows[leg][-1]}, has "
                f"{samples[leg][-1][0]!r} s)"
            )
        samples[leg].append(tuple(values))
        rows[leg].append(row)
    legs = {}
    for leg in LEG_NAMES:
        if not samples[leg]:
            continue
        data = np.array(samples[leg]).T
        legs[leg] = LegLog(
            t_s=data[0],
            length_m=data[1:3],
            force_n=data[3:5],
            contact=data[5].astype(bool) if with_contact else None,
            rows=np.array(rows[leg]),
        )
    if not legs:
        raise LogError(f"{source}: row 2: the log has no samples")
    return CylinderLog(source, legs)


def read_log(path: str | Path) -> CylinderLog:
    """Read and check a log file (module docstring).

    Raises:
        LogError: The file cannot be read, or the first problem in it (row and column).
    """
    path = Path(path)
    text = read_untrusted_text(path, "log", MAX_LOG_BYTES, LogError)
    return parse_log(text, str(path))


def log_csv_text(log: CylinderLog) -> str:
    """A log as CSV text: samples in time order, the legs of one instant in leg order."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    columns = list(ALL_COLUMNS if log.has_contact else REQUIRED_COLUMNS)
    writer.writerow(columns)
    entries = []
    for order, (leg, data) in enumerate(log.legs.items()):
        for k in range(data.t_s.size):
            cells = [repr(float(data.t_s[k])), leg]
            cells += [repr(float(v)) for v in (*data.length_m[:, k], *data.force_n[:, k])]
            if data.contact is not None:
                cells.append(str(int(data.contact[k])))
            entries.append((float(data.t_s[k]), order, cells))
    for _, _, cells in sorted(entries, key=lambda e: (e[0], e[1])):
        writer.writerow(cells)
    return buffer.getvalue()
