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
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scalf_opt.errors import LogError
from scalf_opt.files import number_text, read_untrusted_text
from scalf_opt.types import JOINT_ROLES, LEG_NAMES

TIME, LEG, CONTACT = "t_s", "leg", "contact"
LENGTH_COLUMNS: tuple[str, str] = tuple(f"{j}_length_m" for j in JOINT_ROLES)  # type: ignore[assignment]
FORCE_COLUMNS: tuple[str, str] = tuple(f"{j}_force_n" for j in JOINT_ROLES)  # type: ignore[assignment]
REQUIRED_COLUMNS: tuple[str, ...] = (TIME, LEG, *LENGTH_COLUMNS, *FORCE_COLUMNS)
ALL_COLUMNS: tuple[str, ...] = (*REQUIRED_COLUMNS, CONTACT)

MAX_LOG_BYTES = 200 * 1024 * 1024
"""Largest log read [bytes]: about 4 hours of the robot's 80 Hz four-leg log (40-byte rows)."""

MIN_STEP_S = 1e-5
"""Smallest time step between two samples of one leg [s] (100 kHz; the robot logs at 80 Hz): a
repeated or denormal time stamp is refused, not divided by."""

MAX_FORCE_N = 1e7
"""Largest magnitude of a cylinder force [N] (SCalf's cylinders: 4 kN): a larger one is a unit or
sensor error, and would overflow the energy."""

MAX_TIME_S = 1e7
"""Largest magnitude of a time stamp [s] (116 days): beyond it a double's spacing nears the
smallest step."""


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


def finite_number(source: str, row: int, column: str, cell: str) -> float:
    """A CSV cell as a finite number.

    Raises:
        LogError: Not a number, or NaN or infinite (the message names the row and column).
    """
    try:
        value = float(cell)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise LogError(f"{source}: row {row}, column {column}: {cell!r} is not a finite number")
    return value


def _header(text: str, source: str) -> tuple[list[str], int]:
    """The checked header and where the body starts in ``text``."""
    end = text.find("\n")
    end = len(text) if end < 0 else end
    first = text[:end]
    header = next(csv.reader([first], quoting=csv.QUOTE_NONE), None)
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
    return header, end + 1


def check_times(
    source: str,
    leg: str,
    t_s: np.ndarray,
    rows: np.ndarray,
    place: str = "row",
    column: str = TIME,
) -> None:
    """Check a series' times: within :data:`MAX_TIME_S`, increasing by :data:`MIN_STEP_S` or more.

    A repeated or denormal step is refused, not divided by. ``place`` names what ``rows``
    count: ``row`` (a CSV's, with its time ``column``) or ``message`` (a bag topic's); ``leg`` the
    leg whose samples these are (``""``: every leg's).

    Raises:
        LogError: The first time beyond the bound or too close to the one before, named.
    """
    where = f"row {{}}, column {column}" if place == "row" else f"{place} {{}}"
    big = np.flatnonzero(np.abs(t_s) > MAX_TIME_S)
    if big.size:
        k = int(big[0])
        raise LogError(
            f"{source}: {where.format(rows[k])}: {float(t_s[k])!r} s is beyond the "
            f"{MAX_TIME_S:g} s a log's clock may read"
        )
    steps = np.diff(t_s)
    bad = np.flatnonzero(~(steps >= MIN_STEP_S))
    if bad.size:
        k = int(bad[0]) + 1
        what = (
            "does not increase"
            if not steps[k - 1] > 0
            else (
                f"is {steps[k - 1]:.3g} s after the previous one, closer than the {MIN_STEP_S:g} s "
                f"({1 / MIN_STEP_S:g} Hz) a log may be sampled at"
            )
        )
        previous = f"{leg} {place}" if leg else place
        raise LogError(
            f"{source}: {where.format(rows[k])}: {float(t_s[k])!r} s {what} (the previous "
            f"{previous}, {place} {rows[k - 1]}, has {float(t_s[k - 1])!r} s)"
        )


def _legs(
    source: str,
    t_s: np.ndarray,
    legs: np.ndarray,
    values: np.ndarray,
    contact: np.ndarray | None,
    rows: np.ndarray,
) -> CylinderLog:
    """The log from its columns: ``values`` (n, 4) are the lengths then the forces."""
    big = np.abs(values[:, 2:4]) > MAX_FORCE_N
    if big.any():
        k, j = (int(i) for i in np.argwhere(big)[0])
        raise LogError(
            f"{source}: row {rows[k]}, column {FORCE_COLUMNS[j]}: {float(values[k, 2 + j])!r} N "
            f"is beyond the {MAX_FORCE_N:g} N a cylinder's force sensor may read"
        )
    out = {}
    for leg in LEG_NAMES:
        mine = np.flatnonzero(legs == leg)
        if not mine.size:
            continue
        check_times(source, leg, t_s[mine], rows[mine])
        out[leg] = LegLog(
            t_s=t_s[mine],
            length_m=values[mine, 0:2].T.copy(),
            force_n=values[mine, 2:4].T.copy(),
            contact=contact[mine] if contact is not None else None,
            rows=rows[mine],
        )
    if not out:
        raise LogError(f"{source}: row 2: the log has no samples")
    return CylinderLog(source, out)


_BLANK_LINE = re.compile(r"\n[ \t\r]*\n|\n[ \t\r]+\Z")
_TEXT_WIDTH = 16


def _parse_fast(text: str, body: int, header: list[str], source: str) -> CylinderLog | None:
    """The log by NumPy's C reader, when every row is well-formed.

    ``None`` when one may not be: the strict row-by-row parser then finds and names the first
    problem.
    """
    if _BLANK_LINE.search(text, max(body - 1, 0)) or '"' in text or not text[body:].strip():
        return None
    numeric = [TIME, *LENGTH_COLUMNS, *FORCE_COLUMNS]
    dtype = [(c, float) if c in numeric else (c, f"U{_TEXT_WIDTH}") for c in header]
    try:
        data = np.loadtxt(
            io.StringIO(text[body:]), delimiter=",", dtype=dtype, comments=None, ndmin=1
        )
    except (ValueError, IndexError):
        return None
    if data.size == 0:
        return None
    columns = np.column_stack([data[c] for c in numeric])
    if not np.isfinite(columns).all():
        return None
    legs = data[LEG]
    if not np.isin(legs, LEG_NAMES).all():  # spaces around a leg's name: a rare log
        if (np.char.str_len(legs) >= _TEXT_WIDTH).any():
            return None
        legs = np.char.strip(legs)
        if not np.isin(legs, LEG_NAMES).all():
            return None
    contact = None
    if CONTACT in header:
        cells = data[CONTACT]
        if not np.isin(cells, ("0", "1")).all():
            if (np.char.str_len(cells) >= _TEXT_WIDTH).any():
                return None
            cells = np.char.strip(cells)
            if not np.isin(cells, ("0", "1")).all():
                return None
        contact = cells == "1"
    rows = np.arange(2, data.size + 2)
    return _legs(source, columns[:, 0], legs, columns[:, 1:], contact, rows)


def parse_log(text: str, source: str) -> CylinderLog:
    """Parse and check a log's text (module docstring); ``source`` names it in messages.

    Linear in the log's length: NumPy's reader takes a well-formed log at once; a log it cannot
    take is read row by row, which names the first problem.

    Raises:
        LogError: The first problem found, naming the row and the column.
    """
    header, body = _header(text, source)
    fast = _parse_fast(text, body, header, source)
    if fast is not None:
        return fast
    position = {column: header.index(column) for column in header}
    with_contact = CONTACT in position
    numeric = [TIME, *LENGTH_COLUMNS, *FORCE_COLUMNS]
    samples: list[list[float]] = []
    legs: list[str] = []
    rows: list[int] = []
    lines = io.StringIO(text[body:])
    reader = csv.reader(lines, quoting=csv.QUOTE_NONE, strict=True)
    try:
        for row, cells in enumerate(reader, start=2):
            if not cells or not any(cell.strip() for cell in cells):
                continue
            if len(cells) != len(header):
                raise LogError(
                    f"{source}: row {row}: {len(cells)} cells, the header has {len(header)}"
                )
            leg = cells[position[LEG]].strip()
            if leg not in LEG_NAMES:
                raise LogError(
                    f"{source}: row {row}, column {LEG}: {leg!r} is not a leg "
                    f"({', '.join(LEG_NAMES)})"
                )
            values = [finite_number(source, row, c, cells[position[c]].strip()) for c in numeric]
            if with_contact:
                cell = cells[position[CONTACT]].strip()
                if cell not in ("0", "1"):
                    raise LogError(f"{source}: row {row}, column {CONTACT}: {cell!r} is not 0 or 1")
                values.append(float(cell))
            samples.append(values)
            legs.append(leg)
            rows.append(row)
    except csv.Error as exc:
        raise LogError(f"{source}: row {reader.line_num + 1}: not CSV ({exc})") from None
    if not samples:
        raise LogError(f"{source}: row 2: the log has no samples")
    data = np.array(samples)
    contact = data[:, 5].astype(bool) if with_contact else None
    return _legs(source, data[:, 0], np.array(legs), data[:, 1:5], contact, np.array(rows))


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
            cells = [number_text(data.t_s[k]), leg]
            cells += [number_text(v) for v in (*data.length_m[:, k], *data.force_n[:, k])]
            if data.contact is not None:
                cells.append(str(int(data.contact[k])))
            entries.append((float(data.t_s[k]), order, cells))
    for _, _, cells in sorted(entries, key=lambda e: (e[0], e[1])):
        writer.writerow(cells)
    return buffer.getvalue()
