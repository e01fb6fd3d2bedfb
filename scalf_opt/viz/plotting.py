"""What every figure shares: the style, the cycle's time axis, and deterministic files.

A figure is written as PNG or SVG (by the file's suffix), atomically and byte-for-byte
deterministically: no date or software version in the metadata, SVG element ids salted with a
fixed string instead of a random one, the fonts matplotlib ships (DejaVu).
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any

import matplotlib

matplotlib.use("Agg")  # files only: no display needed

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from scalf_opt.energy.cycle import LegCycle
from scalf_opt.errors import ConfigError
from scalf_opt.files import write_with

FORMATS = ("png", "svg")
"""File formats a figure can be written in."""

PNG_DPI = 120
"""PNG resolution: an 8-inch-wide figure is 960 px, legible at a README's width."""

STYLE: dict[Any, Any] = {
    "font.family": "DejaVu Sans",
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "svg.hashsalt": "scalf-opt",  # element ids from a fixed salt: the same SVG bytes every run
    "svg.fonttype": "path",  # text as paths: no dependence on the reader's fonts
}

DASHES = ("-", "--", "-.", ":")
"""Line styles that tell trajectories apart where colours tell something else apart."""

SWING_SHADE = "#e6e6e6"
"""Background of the swing phase in plots over the cycle."""


@contextmanager
def style() -> Iterator[None]:
    """Matplotlib's settings for scalf-opt's figures (restored afterwards)."""
    with plt.rc_context():
        plt.rcParams.update(STYLE)
        yield


def fitted_title(text: str, width_in: float, fontsize_pt: float) -> str:
    """``text`` wrapped into lines that fit ``width_in`` inches at ``fontsize_pt`` points.

    A title that names a user's files, a study or a gait to six digits runs past the figure's
    edge otherwise, and the saved file cuts it off. A character is taken as 0.65 em wide, a
    little more than the average of the sans-serif font, so that a line never overflows.
    """
    return textwrap.fill(text, max(20, int(width_in * 72.0 / (0.65 * fontsize_pt))))


def save_figure(fig: Figure, path: str | Path) -> Path:
    """Write ``fig`` to ``path`` (``.png`` or ``.svg``) atomically and deterministically.

    Raises:
        ConfigError: Another suffix.
    """
    path = Path(path)
    kind = path.suffix.lower().lstrip(".")
    if kind not in FORMATS:
        raise ConfigError(f"{path}: a figure is written as {' or '.join(FORMATS)}")
    metadata: dict[str, Any] = (
        {"Software": None} if kind == "png" else {"Date": None, "Creator": None}
    )

    def write(handle: IO[bytes]) -> None:
        with style():
            fig.savefig(handle, format=kind, dpi=PNG_DPI, metadata=metadata)

    return write_with(path, write)


def save_in_formats(
    fig: Figure,
    directory: Path,
    name: str,
    formats: Sequence[str],
    on_written: Callable[[Path], None] | None = None,
) -> list[Path]:
    """Write ``fig`` as ``directory/name.<kind>`` for each format in turn, then close it.

    Laid out once: the other formats keep the first's layout (and save faster).
    """
    written = []
    try:
        for kind in formats:
            path = save_figure(fig, directory / f"{name}.{kind}")
            fig.set_layout_engine("none")
            written.append(path)
            if on_written is not None:
                on_written(path)
    finally:
        close(fig)
    return written


def close(fig: Figure) -> None:
    """Release a figure's memory (pyplot keeps every figure until closed)."""
    plt.close(fig)


def cycle_samples(leg: LegCycle, name: str) -> tuple[np.ndarray, np.ndarray]:
    """A leg's output ``name`` over one cycle in cycle time: ``(t [s], values (rows, n))``.

    Stance and swing samples are joined in time order; the phase boundary, which both phases
    sample, appears once per phase, and a NaN column between the phases keeps a line from
    joining them where a quantity jumps (torque at touch-down). A phase that runs over the end of
    the cycle (LF's and RH's stance when the duty cycle is above 0.5) wraps to its start: a NaN
    column there too, so that no line runs back across the cycle.
    """
    parts = sorted((leg.stance, leg.swing), key=lambda p: float(p.t_s[0]))
    times, values = [], []
    for phase in parts:
        v = np.atleast_2d(phase.values[name])
        wraps = np.flatnonzero(np.diff(phase.t_s) < 0.0) + 1
        times += [np.insert(phase.t_s, wraps, np.nan), np.array([np.nan])]
        values += [np.insert(v, wraps, np.nan, axis=1), np.full((v.shape[0], 1), np.nan)]
    return np.concatenate(times[:-1]), np.concatenate(values[:-1], axis=1)


def shade_swing(ax: Axes, leg: LegCycle, label: bool = True) -> None:
    """Shade ``leg``'s swing phase on an axis over cycle time."""
    t = leg.swing.t_s
    ax.axvspan(float(t[0]), float(t[-1]), color=SWING_SHADE, zorder=0, lw=0)
    if label:
        ax.text(
            float(t[0] + t[-1]) / 2.0,
            0.98,
            "swing",
            transform=ax.get_xaxis_transform(),
            ha="center",
            va="top",
            fontsize=7,
            color="#666666",
        )


FALL_COLOR = "tab:red"
"""The line at the instant a simulated robot fell."""

DIVERGENCE_COLOR = "tab:purple"
"""The line at the instant MuJoCo's integration diverged."""


def run_stops(
    fell_at_s: float | None, diverged_at_s: float | None, divergence: str | None
) -> list[tuple[float, str, str]]:
    """A simulated run's stops: ``(time [s], colour, words)`` for a fall and a divergence.

    Args:
        fell_at_s: When the robot fell [s], or ``None``.
        diverged_at_s: When the step in which MuJoCo's integration diverged started [s], or
            ``None``.
        divergence: Which of MuJoCo's checks failed then, in words (``bad accelerations,
            MuJoCo's BADQACC``; ``None``: unknown).
    """
    stops = []
    if fell_at_s is not None:
        stops.append((float(fell_at_s), FALL_COLOR, f"fell at {fell_at_s:.3f} s"))
    if diverged_at_s is not None:
        words = f"MuJoCo diverged at {diverged_at_s:.3f} s"
        if divergence:
            words += f":\n{divergence}"
        stops.append((float(diverged_at_s), DIVERGENCE_COLOR, words))
    return stops


def mark_stops(axes: Sequence[Axes], stops: Sequence[tuple[float, str, str]]) -> None:
    """Mark each of a run's :func:`run_stops` on every panel, its words on the first panel.

    Call it once the time axis has its final limits: the words go on the line's emptier side
    (left of a line in the right half of the axis), halfway up the panel (a second stop's a
    quarter up, so that the two never overlap).
    """
    if len(axes) == 0:
        return
    x0, x1 = axes[0].get_xlim()
    for i, (at, color, words) in enumerate(stops):
        for ax in axes:
            ax.axvline(at, color=color, lw=1.2)
        right_half = at > 0.5 * (x0 + x1)
        axes[0].annotate(
            words,
            (at, 0.5 if i == 0 else 0.25),
            xycoords=axes[0].get_xaxis_transform(),
            xytext=(-5.0 if right_half else 5.0, 0.0),
            textcoords="offset points",
            ha="right" if right_half else "left",
            va="center",
            fontsize=8,
            color=color,
            bbox={"facecolor": "white", "edgecolor": color, "alpha": 0.85, "pad": 2.0},
        )
