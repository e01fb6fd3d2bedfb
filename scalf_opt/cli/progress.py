"""Progress on long work: a bar on a terminal, a heartbeat line on stderr everywhere else.

On a terminal (and not under CI) a tqdm bar on stderr shows the current step. When the output
is a pipe or a log, a :class:`~scalf_opt.heartbeat.Heartbeat` writes the current step to stderr
at least every 10 s while the work lasts. ``--quiet`` turns both off.
"""

from __future__ import annotations

from types import TracebackType

from scalf_opt.cli.console import progress_enabled
from scalf_opt.heartbeat import HEARTBEAT_S, Heartbeat, listening


class ProgressBar:
    """A context manager with ``step(label)``: a bar on a terminal, heartbeat lines otherwise.

    Args:
        total: Number of steps (``None`` when not known beforehand: a count).
        what: What is being done (the bar's prefix, the heartbeat's subject).
        enabled: False to print nothing at all (``--quiet``).
        heartbeat_s: Seconds between heartbeat lines when there is no terminal.
    """

    def __init__(
        self,
        total: int | None,
        what: str,
        enabled: bool = True,
        heartbeat_s: float = HEARTBEAT_S,
    ) -> None:
        self._bar = None
        self._heartbeat: Heartbeat | None = None
        if enabled and progress_enabled():
            from tqdm import tqdm

            self._bar = tqdm(total=total, desc=what, unit="step", leave=False, dynamic_ncols=True)
        elif enabled:
            self._heartbeat = Heartbeat(what, heartbeat_s)
        self._started = False
        self._label = ""
        self._listening = listening(self._aside)

    def step(self, label: str) -> None:
        """Start the next step, ``label`` describing it (the previous one is done)."""
        self._label = label
        if self._heartbeat is not None:
            self._heartbeat.doing = label
        if self._bar is None:
            return
        if self._started:
            self._bar.update(1)
        self._started = True
        self._bar.set_postfix_str(label, refresh=True)

    def _aside(self, doing: str | None) -> None:
        """Show ``doing`` beside the current step (``None``: the step alone again)."""
        if doing is None:
            text = self._label
        elif self._label:
            text = f"{self._label}: {doing}"
        else:
            text = doing
        if self._heartbeat is not None:
            self._heartbeat.doing = text
        if self._bar is not None:
            self._bar.set_postfix_str(text, refresh=True)

    def __enter__(self) -> ProgressBar:
        if self._heartbeat is not None:
            self._heartbeat.__enter__()
        self._listening.__enter__()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self._listening.__exit__(kind, value, traceback)
        if self._heartbeat is not None:
            self._heartbeat.__exit__(kind, value, traceback)
        if self._bar is not None:
            if kind is None and self._started:
                self._bar.update(1)
            self._bar.close()
