"""A progress bar on long work, drawn on stderr only when stdout is a terminal and not in CI."""

from __future__ import annotations

from types import TracebackType

from scalf_opt.cli.console import progress_enabled


class ProgressBar:
    """A context manager with ``step(label)``, a no-op in pipes, CI or ``--quiet``.

    Args:
        total: Number of steps (``None`` when not known beforehand: a count).
        what: What is being done (the bar's prefix).
        enabled: False to draw nothing whatever the terminal.
    """

    def __init__(self, total: int | None, what: str, enabled: bool = True) -> None:
        self._bar = None
        if enabled and progress_enabled():
            from tqdm import tqdm

            self._bar = tqdm(total=total, desc=what, unit="step", leave=False, dynamic_ncols=True)
        self._started = False

    def step(self, label: str) -> None:
        """Start the next step, ``label`` describing it (the previous one is done)."""
        if self._bar is None:
            return
        if self._started:
            self._bar.update(1)
        self._started = True
        self._bar.set_postfix_str(label, refresh=True)

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        if self._bar is not None:
            if kind is None and self._started:
                self._bar.update(1)
            self._bar.close()
