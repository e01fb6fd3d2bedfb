"""Render an HTML page with a headless Chromium: a screenshot and the page's console.

Used by ``scalf-opt view --screenshot`` and by the end-to-end test of the view. Chromium runs
headless with a fresh, throw-away profile, software WebGL (SwiftShader) and every background
network service off, so it renders a local page offline. A copy of the page gets a first script
that marks ``console.error`` messages, so that they can be told apart in Chromium's log from
ordinary messages (uncaught exceptions are logged as ``Uncaught ...`` anyway).
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import signal
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import IO

from scalf_opt.errors import ConfigError
from scalf_opt.files import current_location, scratch_folder, write_with

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
"""Executables tried, in order, unless ``SCALF_OPT_CHROMIUM`` names one."""

CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",  # also as root, in containers
    "--single-process",  # one process: no renderer or zygote helpers that could outlive it
    "--disable-crashpad-for-testing",  # no crash handler daemon outliving the browser
    "--disable-gpu",
    "--enable-unsafe-swiftshader",  # software WebGL, without the deprecation warning
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--host-resolver-rules=MAP * ~NOTFOUND",  # no name resolves: the page must need no network
    "--enable-logging=stderr",
    "--v=0",
)

ERROR_MARK = "[console.error]"

_PROBE = (
    "<script>(function () { var error = console.error.bind(console);"
    " console.error = function () { error.apply(console, ['" + ERROR_MARK + "']"
    ".concat([].slice.call(arguments))); }; })();</script>"
)

_CONSOLE_LINE = re.compile(r":CONSOLE[:(][^\]]*\] \"(?P<message>.*)\", source: ")


@dataclass(frozen=True)
class Rendering:
    """What Chromium made of a page.

    Attributes:
        screenshot: The PNG written.
        console: Every console message, in order.
        errors: The messages that are JavaScript errors (uncaught exceptions, ``console.error``).
        process_group: The process group Chromium ran in (its own; empty once it has exited).
    """

    screenshot: Path
    console: list[str]
    errors: list[str]
    process_group: int


def find_chromium() -> str | None:
    """The Chromium executable: ``$SCALF_OPT_CHROMIUM`` or the first of :data:`CHROMIUM_NAMES`."""
    explicit = os.environ.get("SCALF_OPT_CHROMIUM")
    if explicit:
        return shutil.which(explicit)
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


def render_page(
    page: str | Path,
    screenshot: str | Path,
    size_px: tuple[int, int] = (1000, 560),
    fragment: str = "",
    timeout_s: float = 120.0,
) -> Rendering:
    """Open ``page`` in headless Chromium and write a screenshot of it.

    Args:
        page: The HTML file.
        screenshot: The PNG to write.
        size_px: Window width and height [px].
        fragment: Appended to the page's address after ``#`` (the view: ``t=0.6`` for a still).
        timeout_s: Chromium is stopped (its whole process group) after this long [s].

    Raises:
        ConfigError: No Chromium is installed, it failed or timed out, or wrote no screenshot.
    """
    chromium = find_chromium()
    if chromium is None:
        raise ConfigError(
            "no Chromium found (install the 'chromium' package, or set SCALF_OPT_CHROMIUM)"
        )
    page, screenshot = Path(page), Path(screenshot)
    with scratch_folder("chromium") as tmp:
        probe = Path(tmp) / "page.html"
        text = current_location(page).read_text(encoding="utf-8")
        head = text.find("<head>")
        at = head + len("<head>") if head >= 0 else 0
        probe.write_text(text[:at] + _PROBE + text[at:], encoding="utf-8")
        shot = Path(tmp) / "screenshot.png"
        url = probe.as_uri() + (f"#{fragment}" if fragment else "")
        command = [
            chromium,
            *CHROMIUM_FLAGS,
            f"--user-data-dir={Path(tmp) / 'profile'}",
            f"--window-size={size_px[0]},{size_px[1]}",
            f"--screenshot={shot}",
            url,
        ]
        for _ in range(ATTEMPTS):
            stderr, group, finished = _run(command, timeout_s)
            if finished or _screenshot_written(shot, stderr):
                break
            # a headless single-process Chromium now and then hangs when another runs beside it:
            # it was stopped; another run in a fresh profile is the workaround
            shutil.rmtree(Path(tmp) / "profile", ignore_errors=True)
            shot.unlink(missing_ok=True)
        else:
            raise ConfigError(
                f"{chromium} did not finish within {timeout_s:g} s ({ATTEMPTS} attempts)"
            )
        if not shot.is_file():
            last = stderr.strip().splitlines()[-1:] or ["no output"]
            raise ConfigError(f"{chromium} wrote no screenshot of {page} ({last[0]})")
        data = shot.read_bytes()

        def copy(handle: IO[bytes]) -> None:
            handle.write(data)

        write_with(screenshot, copy)
    console = [m.group("message") for m in map(_CONSOLE_LINE.search, stderr.splitlines()) if m]
    errors = [m for m in console if m.startswith("Uncaught") or m.startswith(ERROR_MARK)]
    return Rendering(screenshot, console, errors, group)


ATTEMPTS = 3
"""Runs of Chromium before a render that times out is an error (a hang is rare: two in a row were
seen once in a loaded test run)."""


def _screenshot_written(shot: Path, stderr: str) -> bool:
    """Whether a Chromium stopped on timeout had written its screenshot (and said so)."""
    return shot.is_file() and shot.stat().st_size > 0 and "written to file" in stderr


def _run(command: list[str], timeout_s: float) -> tuple[str, int, bool]:
    """Run Chromium in its own process group; on timeout or interrupt stop the whole group.

    Returns:
        Chromium's log (stderr), its process group, and whether it finished by itself (``False``:
        stopped after ``timeout_s``; its log is what it wrote until then).
    """
    process = subprocess.Popen(
        command,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        start_new_session=True,  # Chromium's helpers share the group: one signal ends them all
        text=True,
        errors="replace",
    )
    try:
        _, stderr = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        _stop_group(process.pid)
        process.kill()
        _, stderr = process.communicate()  # what it logged until stopped (none of it lost)
        return stderr or "", process.pid, False
    except BaseException:
        _stop(process)
        raise
    return stderr, process.pid, True


def _stop(process: subprocess.Popen[str]) -> None:
    _stop_group(process.pid)
    process.kill()
    process.wait()


def _stop_group(pgid: int) -> None:
    """Kill what is left of the process group Chromium led (helpers it did not reap)."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pgid, signal.SIGKILL)
